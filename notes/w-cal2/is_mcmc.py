"""End to end with the proposed setting-level integral: emcee on (r, mu, sigma_r, sigma_mu, tau x3) with the bounce-level
scales held at zero, the setting level integrated by importance sampling over each setting's draw (nodes from
is_proto.build_nodes at the Hermite mode, f precomputed there); then the Posterior's default intervals on the fresh
campaign, the population medians and the new-spot scales."""
import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from is_proto import *
import pandas as pd, emcee
from test_calibrate import LOGIT
from bouncelab.fitting.hierarchical import Posterior
seed, iv = int(sys.argv[1]), sys.argv[2] == "1"
K = 128
data, post, x0 = build(seed, iv)
mode = H._mode(post, x0); post.fix_landing(mode); mode = H._mode(post, mode)
land = post._land_cov if post._land_cov is not None else [np.zeros(post.n)] * 6
lv = post.liftoff_var if post.liftoff_var is not None else np.zeros((post.n, 3))
if post._land_cov is None: post._land_cov = land
if post.liftoff_var is None: post.liftoff_var = lv
nodes = build_nodes(post, mode, K=K)
starts = [*post._starts, post.n]
G = len(starts) - 1
Z = np.stack([z for z, _ in nodes]); LQ = np.stack([q for _, q in nodes])  # (G, K, 2), (G, K)
gidx = np.repeat(np.arange(G), np.diff(starts))
th = np.stack([post.transforms["r"].inverse(Z[..., 0]), post.transforms["mu"].inverse(Z[..., 1])], -1)  # (G,K,2)
F = predict_per_bounce(post.law, np.repeat(post.p0, K, axis=0), th[gidx].reshape(-1, 2)).reshape(post.n, K, 3)
R = post.y[:, None, :] - F  # (n, K, 3)
box = post.box
def logpost(X):
    X = np.atleast_2d(X); out = np.full(len(X), -np.inf)
    ok = (X[:, 0] > 0) & (X[:, 0] < 1) & (X[:, 1] > 0) & (X[:, 1] <= box["mu"][1]) & (X[:, 2:] > 0).all(1)
    for w in np.flatnonzero(ok):
        x = X[w]
        m = np.array([post.transforms["r"].forward(x[0]), post.transforms["mu"].forward(x[1])]); sd = x[2:4]; tau = x[4:7]
        c = [land[j] + (lv[:, j] + tau[j] ** 2 + post.jitter[j] if j < 3 else 0) for j in range(6)]
        det, quad = H._det_quad([cc[:, None] for cc in c], R)
        ll = np.add.reduceat(-0.5 * (np.log(det) + quad + 3 * math.log(2 * math.pi)), post._starts, axis=0)  # (G, K)
        lp = -0.5 * (((Z - m) / sd) ** 2).sum(-1) - np.log(sd).sum() - math.log(2 * math.pi) - LQ
        t = ll + lp; top = t.max(1)
        lik = (top + np.log(np.exp(t - top[:, None]).sum(1)) - math.log(K)).sum()
        prior = -0.5 * (sd ** 2).sum() - 0.5 * ((tau / post.tau_prior) ** 2).sum()
        out[w] = lik + prior
    return out
start = np.r_[mode[:4], np.maximum(mode[6:9], 0.5)]
nw = 20
rng = np.random.default_rng(0)
p0 = start * (1 + 0.01 * rng.standard_normal((nw, 7)))
t0 = time.time()
sampler = emcee.EnsembleSampler(nw, 7, logpost, vectorize=True, moves=[(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)])
sampler.run_mcmc(p0, 2500)
chain = sampler.get_chain(discard=1000, thin=10, flat=True)
tau_ac = sampler.get_autocorr_time(discard=1000, quiet=True)
print(f"seed {seed} intervals {iv}: {time.time()-t0:.0f} s, autocorr {np.round(tau_ac, 0)}, acceptance {sampler.acceptance_fraction.mean():.2f}")
name = "discrepancy" if iv else "noise"
cols = ["r", "mu", "setting_scale_r", "setting_scale_mu", f"{name}_xdot", f"{name}_ydot", f"{name}_omega"]
S = pd.DataFrame(chain, columns=cols); S.insert(4, "scale_r", 1e-9); S.insert(5, "scale_mu", 1e-9)
S = S[["r", "mu", "setting_scale_r", "setting_scale_mu", "scale_r", "scale_mu", *cols[4:]]]
P = Posterior(law=bl.Rigid(r=0.5, mu=0.4), free=["r", "mu"], vary=["r", "mu"], transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)},
              samples=S, diagnostics={"autocorr": [1.0] * 9, "rhat": [1.0] * 9}, residual=name, with_tau=True,
              measurement={"landing_sd": SD_LAND.tolist() if iv else None, "liftoff_sd": SD_LIFT.tolist() if iv else None},
              n_bounces=600, levels=["setting", "bounce"])
med = S.median()
q = S[["setting_scale_r", "setting_scale_mu"]].quantile([0.025, 0.5, 0.975])
print(f"  medians: r {med['r']:.4f} ({100*(med['r']/0.5-1):+.1f} %), mu {med['mu']:.4f} ({100*(med['mu']/0.4-1):+.1f} %); {name} {np.round(med[cols[4:]].to_numpy(), 2)}")
print(f"  new-spot scale r {q.iloc[1,0]:.3f} [{q.iloc[0,0]:.3f}, {q.iloc[2,0]:.3f}], mu {q.iloc[1,1]:.3f} [{q.iloc[0,1]:.3f}, {q.iloc[2,1]:.3f}]")
fresh = spot_campaign(200, 6, seed=seed + 1000, intervals=iv)
lo, hi = P.interval(fresh.landing.values)
inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
by = pd.DataFrame(inside).groupby(fresh.setting.values).mean().mean().to_numpy()
print(f"  coverage {inside.mean(0).round(3)}, by setting {by.round(3)}")
