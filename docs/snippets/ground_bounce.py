import numpy as np

import bouncelab as bl
from bouncelab.ground import bounce

law = bl.PennerVarying.published("A")
si = {"velocity": "m/s", "spin": "rpm"}

# The paper's typical driver landing, in 3-D: +x, z up; backspin for travel in +x is a NEGATIVE y spin.
speed, angle, backspin = 93.6 * 0.3048, np.radians(37.3), 34.9 * 60.0
v = [speed * np.cos(angle), 0.0, -speed * np.sin(angle)]
w = [0.0, -backspin, 0.0]
v3, w3 = bounce(law, v, w, units=si)
print("3-D lift-off:", v3.round(3), w3.round(1))
# ... is the 2-D law's lift-off [xdot, ydot, omega] -> (xdot, 0, ydot), spin (0, -omega, 0):
print("2-D lift-off:", law.predict([[v[0], v[2], backspin]], units=si).round(3))

# With 800 rpm of sidespin (a spin about z) and heading 30 degrees to the left of x:
rot = np.array([[np.cos(np.pi / 6), -np.sin(np.pi / 6), 0.0], [np.sin(np.pi / 6), np.cos(np.pi / 6), 0.0],
                [0.0, 0.0, 1.0]])
v3, w3 = bounce(law, rot @ v, rot @ w + [0.0, 0.0, 800.0], units=si)
print("heading 30 deg, sidespin:", v3.round(3), w3.round(1))
# A surface's pivot friction can take some of the spin about the normal away (1 keeps it):
print("half the sidespin kept:", bounce(law, rot @ v, rot @ w + [0.0, 0.0, 800.0], units=si,
                                        pivot_retention=0.5)[1].round(1))

# Penner's laws in 3-D are the rigid bounce on the ground tilted towards the incoming ball, in the plane of its
# travel: continuous in the spin. A straight shot along x whose contact point does not slip, spins 2e-6 rad/s
# apart (taking the frame along the slip, the tilt turned with a rounding error: 590 radii/s apart for PennerFixed).
for p_law in (bl.PennerFixed.published("B"), bl.PennerVarying.published("B")):
    a = bounce(p_law, [1000.0, 0.0, -800.0], [1e-6, 1000.0, 0.0])[0]
    b = bounce(p_law, [1000.0, 0.0, -800.0], [-1e-6, 1000.0, 0.0])[0]
    print(f"{type(p_law).__name__}: lift-offs {np.abs(a - b).max():.1e} radii/s apart")

# On a 5-degree slope rising towards +x (normal tilted back, towards -x), the same landing:
n = [-np.sin(np.radians(5.0)), 0.0, np.cos(np.radians(5.0))]
v3, w3 = bounce(law, v, w, normal=n, units=si)
print("uphill slope:", v3.round(3), w3.round(1), " lift-off angle to the slope:",
      round(float(np.degrees(np.arcsin(v3 @ n / np.linalg.norm(v3)))), 2), "deg")

# Many landings at once, with the law's own flags (into the ground, energy gain):
rng = np.random.default_rng(0)
vs = rng.uniform([5, -5, -30], [35, 5, -3], (100_000, 3))
ws = rng.uniform([-500, -9000, -1000], [500, 3000, 1000], (100_000, 3))
vf, wf, flags = bounce(bl.PennerVarying.published("B"), vs, ws, units=si, return_flags=True)
print(vf.shape, flags)
