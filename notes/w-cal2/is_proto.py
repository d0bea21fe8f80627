"""Prototype: the setting level integrated by importance sampling over each setting's draw (nodes fixed per setting,
built once by adaptive importance sampling at a given point), bounce-level scales zero. Compared with brute force."""
import sys, time; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__))); sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__import__("os").path.abspath(__file__)), "..", "..", "tests"))
from setup import *
from scipy.special import logsumexp
from scipy.stats import qmc, multivariate_t
from bouncelab.laws import predict_per_bounce
import test_calibrate as T

def log_lambda(post, a, b, Z, tau):
    """log prod_i N(y_i; f(p_i, theta(z)), D_i) for z in Z (K, V) of setting rows a:b -> (K,)"""
    K = len(Z)
    th = np.column_stack([post.transforms["r"].inverse(Z[:, 0]), post.transforms["mu"].inverse(Z[:, 1])])
    k = b - a
    f = predict_per_bounce(post.law, np.repeat(post.p0[a:b], K, axis=0), np.tile(th, (k, 1))).reshape(k, K, 3)
    d = [c[a:b].copy() for c in post._land_cov]
    for c in range(3):
        d[c] = d[c] + post.liftoff_var[a:b, c] + tau[c]**2 + post.jitter[c]
    det, quad = H._det_quad([c[:, None] for c in d], post.y[a:b, None, :] - f)
    return (-0.5 * (np.log(det) + quad + 3 * math.log(2 * math.pi))).sum(0)

DIAG = {}
def build_nodes(post, xhat, K=64, M=1024, rounds=5, seed=0):
    m = np.array([post.transforms["r"].forward(xhat[0]), post.transforms["mu"].forward(xhat[1])])
    sd = np.hypot(xhat[2:4], xhat[4:6])
    tau = xhat[6:9]
    starts = [*post._starts, post.n]
    nodes = []
    for g, (a, b) in enumerate(zip(starts[:-1], starts[1:])):
        mean, cov, df = m, np.diag(sd**2), 1e6
        for rd in range(rounds + 1):
            n = K if rd == rounds else M
            dist = multivariate_t(mean, cov, df=df)
            # t draws from uniform via normal quantiles and a chi2 per point: use plain rng for simplicity
            rng = np.random.default_rng([seed, g, rd])
            Z = dist.rvs(size=n, random_state=rng)
            logq = dist.logpdf(Z)
            if rd == rounds:
                nodes.append((Z, logq))
                break
            lw = log_lambda(post, a, b, Z, tau) - 0.5 * (((Z - m) / sd)**2).sum(1) - logq
            w = np.exp(lw - lw.max()); w /= w.sum()
            ess = 1.0 / (w @ w)
            DIAG.setdefault(g, []).append(round(float(ess), 1))
            if ess < 20:  # too few points in the mass: keep the centre, shrink towards the best points gently
                top = np.argsort(lw)[-20:]
                mean = Z[top[-1]]
                cov = np.cov(Z[top], rowvar=False) + 1e-8 * np.eye(2)
            else:
                mean = w @ Z
                cov = ((Z - mean) * w[:, None]).T @ (Z - mean) + 1e-8 * np.eye(2)
                cov = cov * 2.0
            df = 4.0
    return nodes

def loglik_is(post, x, nodes):
    m = np.array([post.transforms["r"].forward(x[0]), post.transforms["mu"].forward(x[1])])
    sd = np.hypot(x[2:4], x[4:6])
    starts = [*post._starts, post.n]
    out = []
    for g, (a, b) in enumerate(zip(starts[:-1], starts[1:])):
        Z, logq = nodes[g]
        lp = -0.5 * (((Z - m) / sd)**2).sum(1) - np.log(sd).sum() - math.log(2 * math.pi)
        out.append(logsumexp(lp - logq + log_lambda(post, a, b, Z, x[6:9])) - math.log(len(Z)))
    return np.array(out)

if __name__ == "__main__":
    data, post, x0 = build(3, True)
    mode = np.load("/tmp/cal2/mode_3_True.npy"); post.fix_landing(mode)
    truth = np.r_[R_MED, MU_MED, S_R, S_MU, 0, 0, 1e-3, 1e-3, 1e-3]
    hm = mode.copy(); hm[4:6] = 0
    _, brute_truth = T._setting_loglikes(post, truth)
    _, brute_mode = T._setting_loglikes(post, hm)
    for K in (32, 64, 128, 256):
        t = time.time()
        nodes = build_nodes(post, mode, K=K)
        tb = time.time() - t
        t = time.time()
        it = loglik_is(post, truth, nodes); im = loglik_is(post, hm, nodes)
        print(f"K={K} build {tb:.1f}s eval {time.time()-t:.2f}s; truth: IS-brute sum {it.sum()-brute_truth.sum():+.2f} max|per setting| {np.abs(it-brute_truth).max():.2f};"
              f" worst {np.argsort(-np.abs(it-brute_truth))[:3]} ess {[DIAG[g] for g in np.argsort(-np.abs(it-brute_truth))[:3]]}"
              f" mode: sum {im.sum()-brute_mode.sum():+.2f} max {np.abs(im-brute_mode).max():.2f}; IS truth-mode {it.sum()-im.sum():+.2f} brute {brute_truth.sum()-brute_mode.sum():+.2f}")
