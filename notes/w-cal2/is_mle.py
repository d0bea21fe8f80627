"""MLE of the two-level model (bounce-level scales 0) with the setting level integrated by adaptive importance sampling
(is_proto.py), for a no-interval campaign: population medians, setting scales, noise; coverage of fresh bounces there."""
import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from is_proto import *
import is_proto
import pandas as pd
from scipy.optimize import minimize
from test_calibrate import LOGIT
from bouncelab.fitting.hierarchical import Posterior
seed, iv = int(sys.argv[1]), sys.argv[2] == "1"
data, post, x0 = build(seed, iv)
mode = H._mode(post, x0); post.fix_landing(mode); mode = H._mode(post, mode)
if post._land_cov is None:
    post._land_cov = [np.zeros(post.n)] * 6
if post.liftoff_var is None:
    post.liftoff_var = np.zeros((post.n, 3))
print("hermite mode", np.round(mode, 4))
nodes = build_nodes(post, mode, K=128)
def neg(th):
    x = np.r_[LOGIT.inverse(th[0]), math.exp(th[1]), math.exp(th[2]), math.exp(th[3]), 0, 0, np.exp(th[4:7])]
    return -loglik_is(post, x, nodes).sum()
th0 = np.r_[LOGIT.forward(mode[0]), math.log(mode[1]), np.log(mode[2:4]), np.log(np.maximum(mode[6:9], 1e-2))]
res = minimize(neg, th0, method="Nelder-Mead", options={"maxiter": 3000, "xatol": 1e-4, "fatol": 1e-3, "adaptive": True})
th = res.x
x = np.r_[LOGIT.inverse(th[0]), math.exp(th[1]), math.exp(th[2]), math.exp(th[3]), np.exp(th[4:7])]
print(f"IS MLE seed {seed} intervals {iv}: r {x[0]:.4f} mu {x[1]:.4f} ({100*(x[1]/0.4-1):+.1f} %) sigma_r {x[2]:.4f} sigma_mu {x[3]:.4f} tau {np.round(x[4:7], 2)}; -ll {res.fun:.2f} nfev {res.nfev}")
name = "discrepancy" if iv else "noise"
samples = pd.DataFrame({"r": [x[0]], "mu": [x[1]], "setting_scale_r": [x[2]], "setting_scale_mu": [x[3]], "scale_r": [1e-9], "scale_mu": [1e-9],
                        f"{name}_xdot": [x[4]], f"{name}_ydot": [x[5]], f"{name}_omega": [x[6]]})
P = Posterior(law=bl.Rigid(r=x[0], mu=x[1]), free=["r", "mu"], vary=["r", "mu"], transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)},
              samples=samples, diagnostics={"autocorr": [1.0]*9, "rhat": [1.0]*9}, residual=name, with_tau=True,
              measurement={"landing_sd": SD_LAND.tolist() if iv else None, "liftoff_sd": SD_LIFT.tolist() if iv else None}, n_bounces=1, levels=["setting", "bounce"])
fresh = spot_campaign(200, 6, seed=seed + 1000, intervals=iv)
lo, hi = P.interval(fresh.landing.values, n=4000)
inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
print("coverage at the IS MLE", inside.mean(0).round(3))
