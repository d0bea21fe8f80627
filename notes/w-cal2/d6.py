import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__))); sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__import__("os").path.abspath(__file__)), "..", "..", "tests"))
from setup import *
import pandas as pd
from test_calibrate import LOGIT
from bouncelab.fitting.hierarchical import Posterior
def post_at(r, mu, sr, smu, disc):
    samples = pd.DataFrame({"r": [r], "mu": [mu], "setting_scale_r": [sr], "setting_scale_mu": [smu], "scale_r": [1e-9], "scale_mu": [1e-9],
                            "discrepancy_xdot": [disc[0]], "discrepancy_ydot": [disc[1]], "discrepancy_omega": [disc[2]]})
    return Posterior(law=bl.Rigid(r=r, mu=mu), free=["r", "mu"], vary=["r", "mu"], transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)},
                     samples=samples, diagnostics={"autocorr": [1.0]*9, "rhat": [1.0]*9}, residual="discrepancy", with_tau=True,
                     measurement={"landing_sd": SD_LAND.tolist(), "liftoff_sd": SD_LIFT.tolist()}, n_bounces=1, levels=["setting", "bounce"])
for seed, rows in [(3, [("hermite mode", (0.506, 0.3621, 0.2609, 0.2478, (0, 0.0384, 8.875))), ("hermite MLE tau=0", (0.5010, 0.3426, 0.2639, 0.2725, (0,0,0))),
                        ("exact MLE tau=0", (0.5078, 0.3871, 0.2540, 0.2938, (0, 0, 0))), ("truth", (0.5, 0.4, 0.25, 0.3, (0,0,0)))]),
                   (1, [("exact MLE tau=0", (0.4964, 0.4026, 0.2458, 0.3663, (0,0,0))), ("truth", (0.5, 0.4, 0.25, 0.3, (0,0,0)))])]:
    fresh = spot_campaign(200, 6, seed=seed + 1000, intervals=True)
    for name, a in rows:
        lo, hi = post_at(*a).interval(fresh.landing.values, n=4000)
        inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
        print(seed, name, a, inside.mean(0).round(3))
