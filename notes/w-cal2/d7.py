import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
from brute import loglik_brute
data, post, x0 = build(3, True)
mode = np.load("/tmp/cal2/mode_3_True.npy"); post.fix_landing(mode)
m0 = mode.copy(); m0[4:6] = 0
m1 = m0.copy(); m1[6:9] = 1e-3
for name, x in [("mode s=0 (disc_omega 8.9)", m0), ("mode s=0 disc=0", m1)]:
    print(name, "hermite", round(post.log_likelihood(x), 2), "brute(G model)", round(loglik_brute(post, x, "model"), 2))
