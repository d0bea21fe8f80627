import sys; sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__))); sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__import__("os").path.abspath(__file__)), "..", "..", "tests"))
from setup import *
import pandas as pd
from test_calibrate import LOGIT
from bouncelab.fitting.hierarchical import Posterior
samples = pd.DataFrame({"r": [0.5], "mu": [0.4], "setting_scale_r": [0.25], "setting_scale_mu": [0.3], "scale_r": [1e-9], "scale_mu": [1e-9],
                        "noise_xdot": [6.46], "noise_ydot": [5.43], "noise_omega": [23.16]})
post = Posterior(law=bl.Rigid(r=0.5, mu=0.4), free=["r", "mu"], vary=["r", "mu"], transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)},
                 samples=samples, diagnostics={"autocorr": [1.0]*9, "rhat": [1.0]*9}, residual="noise", with_tau=True,
                 measurement={"landing_sd": None, "liftoff_sd": None}, n_bounces=1, levels=["setting", "bounce"])
d = post.predict([[800.0, -500.0, -800.0]], n=200000)  # v_P = 0: rolls for every mu, lift-off independent of r in x, omega
print("roll-certain landing: draw sd", d[:, 0].std(0).round(2), "(noise 6.46, ydot adds r spread, 23.16)")
