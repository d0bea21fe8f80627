import numpy as np
import xarray as xr

import bouncelab as bl
from bouncelab.ground import Surface, fit_surface, predict_shots, run
from bouncelab.plots import plot_roll_fit, save_figure

# SYNTHETIC shots, written as load_shots returns a launch monitor's export: 800 driver-like shots
# (landing 27.6 m/s at 37.7 deg, 2,440 rpm at launch: the medians of the export in issue 33) whose
# totals come from a hidden surface, plus 2 m of noise. They stand in for your own export.
rng = np.random.default_rng(1)
n = 800
var = {"landing_speed": (rng.normal(27.6, 2.0, n), "m/s"), "landing_angle": (rng.normal(37.7, 3.0, n), "deg"),
       "spin": (rng.normal(2440.0, 500.0, n), "rpm"), "spin_axis": (rng.normal(0.0, 8.0, n), "deg"),
       "launch_angle": (rng.normal(12.0, 2.0, n), "deg"),
       "carry": (rng.normal(230.0, 20.0, n), "m"), "side": (rng.normal(0.0, 15.0, n), "m"),
       "flight_time": (rng.normal(6.5, 0.4, n), "s")}
shots = xr.Dataset({k: ("shot", v, {"units": u}) for k, (v, u) in var.items()}, coords={"shot": np.arange(n)},
                   attrs={"spin_at": "launch"})
shots["club"] = ("shot", np.where(rng.random(n) < 0.5, "Driver", "3 Wood"))
hidden = Surface("hidden", bl.PennerFixed(r=0.3, mu=0.6, beta_deg=19.0), sliding_friction=0.35, stimp_m=1.2)
rest = predict_shots(shots, hidden, spin_decay=0.04, heading_gain=1.5)
shots["total"] = ("shot", rest["total"].to_numpy() + rng.normal(0.0, 2.0, n), {"units": "m"})
shots["side_total"] = ("shot", rest["side_total"].to_numpy(), {"units": "m"})

# What a preset would make of these landings (its law is the paper's fit to bounces on a teeing area):
print(f"median roll-out: shots {float(np.median(shots.total - shots.carry)):.1f} m, on turf-B "
      f"{predict_shots(shots, 'turf-B', spin_decay=0.04).roll.median():.1f} m")

result = fit_surface(shots, law="PennerFixed", seed=0)  # 5 folds held out, then the final fit on all shots
print(result)

# The fitted surface is a surface like the presets: JSON, ground.run, export.
result.surface.to_json("my_fairway.json")
print(bl.ground.load_surface("my_fairway.json"))
a, spin = np.radians(37.7), 2440.0 * np.exp(-result.params["spin_decay"].value * 6.5)  # landing spin (rpm)
r = run([27.6 * np.cos(a), 0.0, -27.6 * np.sin(a)], [0.0, -spin, 0.0], result.surface,
        units={"velocity": "m/s", "spin": "rpm"})
print(r.totals[["bounces", "bounce_carry", "roll", "total_run"]].round(2).to_dict("records")[0])
save_figure(plot_roll_fit(result, title="synthetic shots: held out, 5 folds"), "ground_roll_fit.png", dpi=80)
