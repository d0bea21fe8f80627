import warnings

import numpy as np

import bouncelab as bl
from bouncelab.ground import PRESET_NAMES, Surface, preset, run

for name in PRESET_NAMES:
    s = preset(name)
    print(f"{name:<13} {type(s.law).__name__}{tuple(round(x, 6) for x in s.law.flat_parameters().values())}  "
          f"stimp {s.stimp_m:.3f} m ({s.stimp_ft:.2f} ft), rolling deceleration {s.rolling_deceleration:.3f} m/s^2, "
          f"sliding friction {s.sliding_friction}, steepest slope to rest {s.max_slope_deg():.2f} deg")
print(preset("turf-B").description)

# Your own surface, saved and read back as JSON (the law inside as its own JSON description):
mine = Surface(name="my fairway", law=bl.CompliantImpact(r=0.45, mu=0.5, kappa=1.4), sliding_friction=0.45,
               stimp_ft=5.5, pivot_retention=0.8, description="a guess, for illustration")
mine.to_json("fairway.json")
print(bl.ground.load_surface("fairway.json"))
print(open("fairway.json").read()[:220], "...")

# Why the turf presets use the paper's PennerVarying laws: the driver landing on turf A with each published law.
si = {"velocity": "m/s", "spin": "rpm"}
a = np.radians(37.3)
v, w = [28.53 * np.cos(a), 0.0, -28.53 * np.sin(a)], [0.0, -2094.0, 0.0]
cols = ["bounces", "bounce_carry", "roll", "total_run"]
for law in (bl.PennerVarying.published("A"), bl.PennerFixed.published("A"), bl.Rigid.published("A")):
    t = run(v, w, preset("turf-A").replace(law=law), units=si).totals
    print(f"{type(law).__name__:<14}", t[cols].round(2).to_dict("records")[0])

# The published piecewise-affine law lifts a ball off even when it barely lands (its ydotF offsets are
# 23.7 to 90.4 radii/s, 0.5 to 1.9 m/s): it never settles, and the run stops it at max_bounces.
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    t = run(v, w, preset("turf-A").replace(law=bl.PiecewiseAffine.published("A")), units=si).totals
print(t[["bounces", "bounce_limit"]].to_dict("records")[0], "|", caught[0].category.__name__)
