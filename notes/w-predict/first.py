import sys
sys.path.insert(0, sys.argv[1])
import numpy as np, bouncelab as bl
assert bl.__file__.startswith(sys.argv[1])
bl.Rigid(r=0.5, mu=0.4).predict(np.array([[1000.0, -800.0, 300.0]]))
