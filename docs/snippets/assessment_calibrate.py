import time

import bouncelab as bl
from bouncelab.plots import save_figure
from bouncelab.plots.posterior import plot_corner, plot_spread

# SYNTHETIC data: the default 'turf' surrogate of campaign B, simulated with the CraterContact law
# (whose own parameters vary from spot to spot); Rigid did not generate it.
data = bl.load_campaign("B")
start = time.perf_counter()
post = bl.calibrate(bl.Rigid, data, vary=["r", "mu"], seed=0)
print(f"calibrate: {time.perf_counter() - start:.1f} s on {data.sizes['bounce']} bounces")
print(post)
print()
print("population law:", post.population)
landing = data.landing.values[:2]
print("landings:", landing.round(1).tolist())
print("draws:", post.predict(landing, n=1000).shape)
lower, upper = post.interval(landing, level=0.95)
print("95 % interval of the lift-off, lower:", lower.round(1).tolist())
print("                                upper:", upper.round(1).tolist())
print()
print("share of B's bounces inside their default 95 % predictive intervals (measured bounces on new spots):")
print(post.check(data).round(3))
post.to_json("rigid_B_posterior.json")
print("saved and loaded:", repr(bl.load_posterior("rigid_B_posterior.json")))
save_figure(plot_corner(post, columns=["r", "mu", "setting_scale_r", "setting_scale_mu", "scale_r", "scale_mu"]),
            "calibrate_corner.png", dpi=80)
save_figure(plot_spread(post, data), "calibrate_spread.png", dpi=80)
