import numpy as np

import bouncelab as bl
from bouncelab.plots import save_figure
from bouncelab.plots.posterior import plot_spread

# A campaign made here, with known answers: 100 launcher settings x 6 repeats; the repeats of a setting land on one
# spot, where the Rigid law's r is logit-normal (median 0.5, scale 0.25 from spot to spot) and mu log-normal
# (median 0.4, scale 0.3); landings and lift-offs are measured with known normal errors, stated as 95 % intervals.
rng = np.random.default_rng(1)
sd_land, sd_lift = np.array([4.0, 4.0, 15.0]), np.array([5.0, 5.0, 20.0])


def campaign(n_settings, repeats=6):
    base = np.column_stack([rng.uniform(300, 1200, n_settings), rng.uniform(-700, -200, n_settings),
                            rng.uniform(-300, 600, n_settings)])
    true_landing = np.repeat(base, repeats, axis=0) + rng.normal(0, [15, 15, 30], (n_settings * repeats, 3))
    n = len(true_landing)
    r = np.repeat(1 / (1 + np.exp(-(0.25 * rng.standard_normal(n_settings)))), repeats)  # logit(0.5) = 0
    mu = np.repeat(0.4 * np.exp(0.3 * rng.standard_normal(n_settings)), repeats)
    liftoff = bl.laws.predict_per_bounce(bl.Rigid, true_landing, np.column_stack([r, mu]))
    return bl.make_campaign(true_landing + sd_land * rng.standard_normal((n, 3)),
                            liftoff + sd_lift * rng.standard_normal((n, 3)),
                            setting=np.repeat(np.arange(n_settings) + 1000 * rng.integers(1000), repeats),
                            landing_pi=np.tile(1.96 * sd_land, (n, 1)), liftoff_pi=np.tile(1.96 * sd_lift, (n, 1)))


data = campaign(100)
post = bl.calibrate(bl.Rigid, data, vary=["r", "mu"], seed=0)
print(post.summary().round(4))
print(post.scales().round(3))
print(post.diagnostics["reason"], f"({post.diagnostics['elapsed_s']:.0f} s)")
fresh = campaign(200)  # new settings: new spots
print("fresh measured bounces on new spots inside their default 95 % predictive intervals:")
print(post.check(fresh).round(3))
save_figure(plot_spread(post, fresh), "calibrate_spread_known.png", dpi=80)
