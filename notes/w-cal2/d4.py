import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__))); sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__import__("os").path.abspath(__file__)), "..", "..", "tests"))
from setup import *
import pandas as pd
from test_calibrate import LOGIT
from bouncelab.fitting.hierarchical import Posterior
fresh = spot_campaign(200, 6, seed=1001, intervals=False)
def post_at(r, mu, sr, smu, noise):
    samples = pd.DataFrame({"r": [r], "mu": [mu], "setting_scale_r": [sr], "setting_scale_mu": [smu], "scale_r": [1e-9], "scale_mu": [1e-9],
                            "noise_xdot": [noise[0]], "noise_ydot": [noise[1]], "noise_omega": [noise[2]]})
    return Posterior(law=bl.Rigid(r=r, mu=mu), free=["r", "mu"], vary=["r", "mu"], transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)},
                     samples=samples, diagnostics={"autocorr": [1.0]*9, "rhat": [1.0]*9}, residual="noise", with_tau=True,
                     measurement={"landing_sd": None, "liftoff_sd": None}, n_bounces=1, levels=["setting", "bounce"])
roll = bl.Rigid(r=0.5, mu=0.4).regime(fresh.landing.values) == "roll"
for args in [(0.4973, 0.3957, 0.2454, 0.3755, (6.46, 5.43, 23.16)), (0.5, 0.4, 0.25, 0.3, (6.46, 5.43, 23.16)),
             (0.5, 0.4, 0.25, 0.34, (6.46, 5.43, 23.16)), (0.4973, 0.3957, 0.2454, 0.3755, (6.46, 5.43, 20.65))]:
    lo, hi = post_at(*args).interval(fresh.landing.values, n=4000)
    inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
    print(args, "all", inside.mean(0).round(3), "roll-at-median", inside[roll].mean(0).round(3), "slip", inside[~roll].mean(0).round(3))
