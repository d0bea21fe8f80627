import sys
sys.path.insert(0, sys.argv[1])
sys.argv = ["bouncelab", sys.argv[2]]
from bouncelab.cli.main import main
try:
    main()
except SystemExit:
    pass
