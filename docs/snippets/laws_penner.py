import numpy as np

import bouncelab as bl

law = bl.PennerFixed(r=0.42, mu=0.852, beta_deg=12.9)
p0 = np.array([[1000.0, -800.0, 300.0]])
mirror = p0 * [-1.0, 1.0, -1.0]                 # the same bounce travelling in -x
print(law.predict(p0).round(2), law.regime(p0))
print(law.predict(mirror).round(2), law.regime(mirror))

varying = bl.PennerVarying.published("A")       # beta = k_p s phi
landings = bl.units.landing_from_speed_angle_spin([10.0, 20.0, 40.0], [20.0, 40.0, 60.0], 0.0)
print(varying.beta_deg(landings).round(2))      # degrees

# The jump at xdot0 = 0 (published fixed-beta law of B) and the continuous variant, which fades the
# tilt linearly to zero below |xdot0| = fade_xdot (radii/s) and leaves the law unchanged above it.
law_b = bl.PennerFixed.published("B")
near_vertical = np.array([[1.0, -1000.0, 0.0], [-1.0, -1000.0, 0.0], [60.0, -1000.0, 0.0]])
print(law_b.predict(near_vertical)[:, 0].round(2))
print(law_b.replace(fade_xdot=50.0).predict(near_vertical)[:, 0].round(2))
