import numpy as np

import bouncelab as bl
from bouncelab.core import units
from bouncelab.core.plausibility import PLAUSIBLE_RANGES

# Campaign A's bounces as a lab sheet would hold them: m/s and rpm.
a = bl.load_campaign("A", surrogate="published")
landing = units.from_scaled(a.landing.values, velocity="m/s", spin="rpm")
liftoff = units.from_scaled(a.liftoff.values, velocity="m/s", spin="rpm")
np.set_printoptions(suppress=True)
print(np.round(landing[:2], 1))

try:
    bl.make_campaign(landing, liftoff)                      # m/s and rpm taken as radii/s and rad/s
except bl.DataError as exc:
    print("DataError:", exc)

# Spins in rpm beside velocities already scaled: the spin column is named, and the bounce.
rpm_spins = a.landing.values * [1, 1, 60 / (2 * np.pi)]
try:
    bl.fit(bl.Rigid, (rpm_spins, a.liftoff.values))         # bare arrays get the same guard
except bl.DataError as exc:
    print("DataError:", exc)

# Converted, they are a campaign; numbers beyond the ranges on purpose need wider ranges.
ds = bl.make_campaign(units.to_scaled(landing, velocity="m/s", spin="rpm"),
                      units.to_scaled(liftoff, velocity="m/s", spin="rpm"))
print(dict(ds.sizes))
fast = bl.make_campaign(a.landing.values * [1, 1, 1.5], a.liftoff.values,
                        plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
print(f"widened: spins up to {np.abs(fast.landing.values[:, 2]).max() * 60 / (2 * np.pi):.0f} rpm accepted")
