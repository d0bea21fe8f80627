import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
from brute import loglik_brute, rigid
from scipy.stats import multivariate_normal
seed, iv = 3, True
data, post, x0 = build(seed, iv)
mode = np.load(f"/tmp/cal2/mode_{seed}_{iv}.npy")
post.fix_landing(mode)
truth = np.r_[R_MED, MU_MED, S_R, S_MU, 0, 0, 1e-3, 1e-3, 1e-3]
_, bper = loglik_brute(post, truth, "model", return_per=True)
starts = list(post._starts) + [post.n]
rows = []
for nodes in (7, 21):
    p2 = post.with_nodes(nodes)
    per = []
    for g in range(100):
        a, b = starts[g], starts[g+1]
        sub = H._LogPosterior(post.law, post.p0[a:b], post.y[a:b], free=["r","mu"], vary=["r","mu"], box=post.box,
              landing_sd=post.landing_sd[a:b], liftoff_sd=np.sqrt(post.liftoff_var[a:b]), with_tau=True, tau_prior=post.tau_prior,
              nodes=nodes, groups=np.zeros(b-a))
        sub.fix_landing(mode)
        per.append(sub.log_likelihood(truth))
    rows.append(np.array(per))
h7, h21 = rows
# regime mix per setting at truth draws: fraction of (v draw) for which repeats slip
reg_mix = []
rng = np.random.default_rng(0)
v = rng.standard_normal((4000, 2))
R = LOGIT_inv = 1/(1+np.exp(-(0 + S_R*v[:,0]))); M = 0.4*np.exp(S_MU*v[:,1])
for g in range(100):
    a, b = starts[g], starts[g+1]
    regs = np.array([rigid(post.p0[i], R, M)[1] for i in range(a, b)])
    reg_mix.append(np.mean(regs != 0))
reg_mix = np.array(reg_mix)
d7, d21 = h7 - bper, h21 - bper
print("sum: hermite7 %.1f hermite21 %.1f brute %.1f" % (h7.sum(), h21.sum(), bper.sum()))
for lo, hi in [(0, 0.02), (0.02, 0.98), (0.98, 1.01)]:
    m = (reg_mix >= lo) & (reg_mix < hi)
    print(f"settings with P(slip at truth) in [{lo},{hi}): n={m.sum()}, hermite7-brute sum {d7[m].sum():.1f}, hermite21-brute {d21[m].sum():.1f}")
# normal likelihood with Monte Carlo moments for the 5 worst settings
worst = np.argsort(d7)[:5]
lc = post._land_cov
for g in worst:
    a, b = starts[g], starts[g+1]; k = b - a
    n = 200000
    v = rng.standard_normal((n, 2))
    R = 1/(1+np.exp(-(S_R*v[:,0]))); M = 0.4*np.exp(S_MU*v[:,1])
    F = np.stack([rigid(post.p0[i], R, M)[0] for i in range(a, b)], 1).reshape(n, -1)  # (n, 3k)
    D = np.zeros((3*k, 3*k))
    for i in range(k):
        xx, yy, ww, xy, xw, yw = (c[a+i] for c in lc)
        D[3*i:3*i+3, 3*i:3*i+3] = np.array([[xx, xy, xw], [xy, yy, yw], [xw, yw, ww]]) + np.diag(post.liftoff_var[a+i] + 1e-6)
    mc = multivariate_normal(F.mean(0), np.cov(F, rowvar=False) + D).logpdf(post.y[a:b].ravel())
    print(f"setting {g}: P(slip) {reg_mix[g]:.2f}; hermite7 {h7[g]:.1f} hermite21 {h21[g]:.1f} normal(MC moments) {mc:.1f} brute {bper[g]:.1f}")
