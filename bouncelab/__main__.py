"""``python -m bouncelab``: the same as the ``bouncelab`` command."""

import sys

from bouncelab.cli.main import main

sys.exit(main())
