import sys, math, time, os
os.makedirs('/tmp/cal2', exist_ok=True)  # the scripts keep the modes they find here
import numpy as np
sys.path.insert(0, __import__("os").path.join(__import__("os").path.dirname(__import__("os").path.abspath(__file__)), "..", "..", "tests"))
import bouncelab as bl
from bouncelab.fitting import hierarchical as H
from bouncelab.fitting.fitter import fit
from bouncelab.data.campaign import interval_sds
from bouncelab.data.inputs import campaign_arrays
from test_calibrate import spot_campaign, R_MED, MU_MED, S_R, S_MU, SD_LAND, SD_LIFT

def build(seed, intervals, nodes=7):
    data = spot_campaign(100, 6, seed=seed, intervals=intervals)
    p0, pf, setting = campaign_arrays(data)
    point = fit(bl.Rigid, data, seed=0)
    fitted = point.model
    free = ["r", "mu"]
    landing_sd, liftoff_sd = interval_sds(data, len(p0))
    with_tau = True
    tau_prior = np.maximum(pf.std(axis=0), 1e-6)
    post = H._LogPosterior(fitted, p0, pf, free=free, vary=free, box=point.bounds, landing_sd=landing_sd,
                           liftoff_sd=liftoff_sd, with_tau=with_tau, tau_prior=tau_prior, approximation="hermite",
                           nodes=nodes, groups=setting)
    resid = pf - fitted._evaluate(p0)
    x0 = np.r_[[getattr(fitted, n) for n in free], np.full(post._n_scales, 0.1),
               np.maximum(0.5 * resid.std(axis=0), 1e-3 * tau_prior)]
    return data, post, x0
