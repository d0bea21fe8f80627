import sys, time; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from setup import *
data, post, x0 = build(3, True)
mode = np.load("/tmp/cal2/mode_3_True.npy"); post.fix_landing(mode)
rng = np.random.default_rng(0)
X = mode + 0.01 * np.abs(rng.standard_normal((12, 9))) * np.r_[1, 1, 1, 1, 1, 1, 10, 10, 10]
post.batch(X)
for nodes in (7, 3):
    p = post.with_nodes(nodes); p.batch(X)
    t = time.perf_counter(); [p.batch(X) for _ in range(20)]; print(f"current, {nodes} nodes: {(time.perf_counter()-t)/20*1e3:.1f} ms per batch of 12 walkers")
# node path cost with precomputed f, J (no law calls): (w, n, K)
w, n, K, V = 12, 600, 64, 2
f = rng.standard_normal((n, K, 3)); J = rng.standard_normal((n, K, 3, V)); y = rng.standard_normal((n, 3))
D = [rng.random(n) + 1 for _ in range(3)]; starts = post._starts
Z = rng.standard_normal((100, K, V)); logq = rng.standard_normal((100, K))
def node_ll(s, tau, m, sig):
    s2 = s[:, None, None, :] ** 2  # (w,1,1,V)
    c = []
    for (a, b) in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)):
        v = (J[None, :, :, a, :] * J[None, :, :, b, :] * s2).sum(-1)
        if a == b: v = v + (D[a][None, :, None] + tau[:, a, None, None] ** 2)
        c.append(v)
    r = y[None, :, None, :] - f[None]
    det, quad = H._det_quad(c, r)
    ll = -0.5 * (np.log(det) + quad)
    per = np.add.reduceat(ll, starts, axis=1)  # (w, G, K)
    lp = -0.5 * (((Z[None] - m[:, None, None, :]) / sig[:, None, None, :]) ** 2).sum(-1) - logq[None]
    tot = per + lp
    top = tot.max(-1, keepdims=True)
    return (top[..., 0] + np.log(np.exp(tot - top).sum(-1))).sum(-1)
args = (np.full((w, V), 0.01), np.full((w, 3), 1.0), np.zeros((w, V)), np.full((w, V), 0.3))
node_ll(*args)
t = time.perf_counter(); [node_ll(*args) for _ in range(20)]; print(f"node path, K={K}, f and J precomputed: {(time.perf_counter()-t)/20*1e3:.1f} ms per batch of 12 walkers")
