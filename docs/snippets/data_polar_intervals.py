from pathlib import Path

import numpy as np

import bouncelab as bl
from bouncelab.core.units import polar_halfwidths_to_cartesian

# A polar landing with 95 % half-widths of its speed, angle and spin (a marker such as _pi after the name),
# and a Cartesian lift-off without intervals.
Path("monitor_pi.csv").write_text(
    "speed_in (m/s),angle_in (deg),spin_in (rpm),speed_in_pi (m/s),angle_in_pi (deg),spin_in_pi (rpm),"
    "vx_out (m/s),vy_out (m/s),spin_out (rpm)\n"
    "25.0,40.0,3000,0.5,1.0,100,11.3,4.1,1500\n"
    "18.0,55.0,-1200,0.3,0.5,80,9.5,3.3,600\n"
)
ds = bl.load_campaign("monitor_pi.csv")
print(ds.attrs["interval_form"])
print(ds.landing_pi.values.round(2))                       # xdot, ydot (radii/s), omega (rad/s)
same = polar_halfwidths_to_cartesian([[25.0, 40.0, 3000], [18.0, 55.0, -1200]], [[0.5, 1.0, 100], [0.3, 0.5, 80]])
print(np.allclose(ds.landing_pi.values, same))

# Half-widths for only some of a polar state's columns are refused, with the columns= to pass.
text = Path("monitor_pi.csv").read_text().replace(",spin_in_pi (rpm)", ",spin_in_note")
Path("no_spin_pi.csv").write_text(text)
try:
    bl.load_campaign("no_spin_pi.csv")
except bl.DataError as exc:
    print(exc)
