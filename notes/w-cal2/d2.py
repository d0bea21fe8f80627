import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
from brute import loglik_brute, rigid
# check rigid against the law
p = np.array([[900., -450, 100], [300, -600, -200], [1200, -300, 500]])
print(np.abs(rigid(p, 0.5, 0.4)[0] - bl.Rigid(r=0.5, mu=0.4).predict(p)).max())
seed, iv = 3, True
data, post, x0 = build(seed, iv)
mode = np.load(f"/tmp/cal2/mode_{seed}_{iv}.npy")
post.fix_landing(mode)
m0 = mode.copy(); m0[4:6] = 0
truth = np.r_[R_MED, MU_MED, S_R, S_MU, 0, 0, 1e-3, 1e-3, 1e-3]
t = time.time()
for name, x in [("mode(s=0)", m0), ("truth", truth)]:
    h = post.log_likelihood(x)
    b1 = loglik_brute(post, x, "model")
    b2 = loglik_brute(post, x, "exact")
    print(name, "hermite", round(h, 2), "brute(G model)", round(b1, 2), "brute(G exact)", round(b2, 2), time.time()-t)
b1 = loglik_brute(post, truth, "model", nmu=7000, nr=161)
print("finer grid truth", b1)
