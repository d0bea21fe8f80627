"""Split the Hermite-vs-brute gap over all 100 settings of seed 3 (truth): moments (Hermite 7 vs a normal with Monte
Carlo moments of the two-level model, 100 000 draws) and shape (that normal vs the brute force)."""
import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
from brute import loglik_brute, rigid
from scipy.stats import multivariate_normal
import test_calibrate as T
data, post, x0 = build(3, True)
mode = np.load("/tmp/cal2/mode_3_True.npy"); post.fix_landing(mode)
truth = np.r_[R_MED, MU_MED, S_R, S_MU, 0, 0, 1e-3, 1e-3, 1e-3]
h7, br = T._setting_loglikes(post, truth)
starts = [*post._starts, post.n]
rng = np.random.default_rng(0)
n = 100000
v = rng.standard_normal((n, 2)); R = 1 / (1 + np.exp(-(S_R * v[:, 0]))); M = 0.4 * np.exp(S_MU * v[:, 1])
lc = post._land_cov
mc = []
for g in range(100):
    a, b = starts[g], starts[g + 1]; k = b - a
    F = np.stack([rigid(post.p0[i], R, M)[0] for i in range(a, b)], 1).reshape(n, -1)
    D = np.zeros((3 * k, 3 * k))
    for i in range(k):
        xx, yy, ww, xy, xw, yw = (c[a + i] for c in lc)
        D[3*i:3*i+3, 3*i:3*i+3] = np.array([[xx, xy, xw], [xy, yy, yw], [xw, yw, ww]]) + np.diag(post.liftoff_var[a + i] + 1e-6 + post.jitter)
    mc.append(multivariate_normal(F.mean(0), np.cov(F, rowvar=False) + D).logpdf(post.y[a:b].ravel()))
mc = np.array(mc)
print(f"sum: hermite7 {h7.sum():.1f}, normal with MC moments {mc.sum():.1f}, brute {br.sum():.1f}")
print(f"moments part (hermite7 - MC normal) {h7.sum()-mc.sum():.1f}; shape part (MC normal - brute) {mc.sum()-br.sum():.1f}")
