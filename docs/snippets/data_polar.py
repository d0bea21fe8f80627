import warnings
from pathlib import Path

import numpy as np

import bouncelab as bl
from bouncelab.core.errors import DroppedRowsWarning
from bouncelab.core.units import state_from_polar

# A launch-monitor export: a title line, then speed, angle and spin of the landing and the lift-off.
Path("monitor.csv").write_text(
    "Bounce test 2026-03-14, turf B\n"
    "speed_in (m/s),angle_in (deg),spin_in (rpm),speed_out (m/s),angle_out (deg),spin_out (rpm)\n"
    "25.0,40.0,3000,12.0,20.0,1500\n"
    "24.6,39.5,3050,11.8,NA,1480\n"
    "18.0,55.0,-1200,9.8,105.0,600\n"
)
with warnings.catch_warnings(record=True) as caught:
    ds = bl.load_campaign("monitor.csv", missing="drop")
print(caught[0].category.__name__, caught[0].message)
print(ds.sizes["bounce"], ds.attrs["dropped_rows"], ds.attrs["source_units"], "|", ds.attrs["source_form"])
print(ds.landing.values.round(1))                          # radii/s, rad/s
print(ds.liftoff.values.round(1))
same = state_from_polar([[25.0, 40.0, 3000], [18.0, 55.0, -1200]], kind="landing")
print(np.allclose(ds.landing.values, same))

warnings.simplefilter("ignore", DroppedRowsWarning)  # seen once is enough

# Names no synonym knows: say which column is which (a list is xdot, ydot, omega; a mapping is polar).
named = bl.load_campaign("monitor.csv", missing="drop", columns={
    "landing": {"speed": "speed_in", "angle": "angle_in", "spin": "spin_in"},
    "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"},
})
print(named.landing.equals(ds.landing))

# A landing angle measured the other way round is refused, with the convention.
Path("upside.csv").write_text(
    "inbound speed [m/s],landing angle [deg],inbound spin [rpm],outbound speed [m/s],launch angle [deg],"
    "outbound spin [rpm]\n25.0,-40.0,3000,12.0,20.0,1500\n"
)
try:
    bl.load_campaign("upside.csv")
except bl.DataError as exc:
    print(exc)
