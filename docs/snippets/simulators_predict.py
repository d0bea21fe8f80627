import numpy as np
import pandas as pd

import bouncelab as bl

law = bl.PennerFixed.published("A")
si = {"velocity": "m/s", "spin": "rpm"}

# One call, physical units in and out: [vx, vy, spin] in m/s and rpm (vy < 0: the ball comes down).
print(law.predict([[22.7, -17.3, 2094.0]], units=si).round(2))

# Polar: [speed, angle, spin]; the landing angle is positive below the horizontal,
# the lift-off angle positive above it, both from the direction of travel.
landings = np.array([[28.5, 37.3, 2094.0],    # the paper's typical driver landing
                     [15.0, 60.0, 6000.0],    # a steep wedge shot with heavy backspin
                     [30.0, 20.0, -1000.0]])  # a low runner with topspin
out = law.predict(landings, units=si, form="polar")
print(pd.DataFrame(out, columns=["speed m/s", "angle deg", "spin rpm"]).round(2))

# Other units, a DataFrame with named columns, or Cartesian lift-offs from polar landings.
df = pd.DataFrame({"speed": [63.8], "angle": [37.3], "spin": [2094.0]}, index=["driver"])
print(law.predict(df, units={"velocity": "mph", "spin": "rpm"}, form="polar").round(2))
print(law.predict(landings[:1], units=si, form=("polar", "cartesian")).round(2))

# Non-physical lift-offs are flagged in the same call (ydotF <= 0, or more energy than the landing);
# a law with the paper's published values also warns (NonphysicalLiftoffWarning) when it predicts them.
steep = np.array([[5.0, 80.0, 10000.0], [28.5, 37.3, 2094.0]])  # a near-vertical landing with heavy backspin
out, flags = bl.PennerFixed.published("B").predict(steep, units=si, form="polar", return_flags=True)
print(flags)
print("into the ground:", flags.into_ground, " lift-offs:", out.round(1).tolist())

# Regimes: int8 codes into law.regimes (1 byte per landing) for large inputs.
codes = law.regime(landings, units=si, form="polar", codes=True)
print(codes, [law.regimes[c] for c in codes])
