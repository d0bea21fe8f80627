import numpy as np

import bouncelab as bl
from bouncelab.ground import preset, run

green = preset("green-medium")  # Stimpmeter 9 ft, the published PennerVarying law of campaign B
print(green)
si = {"velocity": "m/s", "spin": "rpm"}

# A 2 % slope falling towards +y (the normal leans towards +y). Three approach shots land at the
# origin heading +x (across the slope) and one ball is putted straight up the slope, rolling.
theta = np.arctan(0.02)
n = np.array([0.0, np.sin(theta), np.cos(theta)])
def landing(speed, angle_deg, backspin_rpm):
    a = np.radians(angle_deg)
    return [speed * np.cos(a), 0.0, -speed * np.sin(a)], [0.0, -backspin_rpm, 0.0]
shots = [landing(15.0, 50.0, 8000.0), landing(12.0, 40.0, 3000.0), landing(8.0, 30.0, 2000.0)]
up = np.array([0.0, -np.cos(theta), np.sin(theta)])  # along the plane, uphill
putt_v = 2.0 * up
putt_w = np.cross(n, putt_v) / 0.02135 * 60 / (2 * np.pi)  # rolling: n x omega = -v (rpm)
v = np.array([s[0] for s in shots] + [putt_v])
w = np.array([s[1] for s in shots] + [putt_w])
r = run(v, w, green, normal=n, units=si, rate=50.0)
print(r)
cols = ["bounces", "bounce_carry", "roll", "total_run", "lateral", "skid_time", "time_to_rest"]
print(r.totals[cols].round(3))
print("rest positions (m):", r.rest_position.round(3).tolist())

# The path: an xarray Dataset (shot, time, axis), with its events.
ds = r.path
print(ds[["position", "phase", "event_time", "event_kind"]])
print("shot 0 at t = 0.5 s:", ds["position"].sel(shot=0, time=0.5).values.round(3),
      "phase", ["flight", "skid", "roll", "rest"][int(ds["phase"].sel(shot=0, time=0.5))])

# The USGA's slope check: Stimpmeter balls up and down the fall line of the 2 % slope.
down = -up
runs = []
for d in (up, down):
    vv = 1.83 * d
    ww = np.cross(n, vv) / 0.02135 * 60 / (2 * np.pi)
    runs.append(float(np.linalg.norm(run(vv, ww, green, normal=n, units=si).rest_position)))
s_up, s_down = runs
print(f"S_up {s_up:.4f} m, S_down {s_down:.4f} m, 2 S_up S_down / (S_up + S_down) = "
      f"{2 * s_up * s_down / (s_up + s_down):.6f} m; flat reading {green.stimp_m:.6f} m "
      f"(/cos(theta) = {green.stimp_m / np.cos(theta):.6f} m)")

# Too steep for this green: refused, with the steepest slope a ball can rest on.
try:
    run(v[:1], w[:1], green, normal=[0.0, np.sin(0.1), np.cos(0.1)], units=si)
except bl.DataError as err:
    print("DataError:", err)
