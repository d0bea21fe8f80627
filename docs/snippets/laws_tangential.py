import numpy as np

import bouncelab as bl

p0 = np.array([[500.0, -800.0, -300.0]])        # a landing that grips (v_P = 200 radii/s)
for e_t in (0.0, 0.3, 1.0):
    law = bl.TangentialRestitution(r=0.5, mu=0.4, e_t=e_t)
    pf = law.predict(p0)
    print(f"e_t = {e_t}: lift-off {pf.round(2)}, v_P at lift-off {float(pf[0, 0] + pf[0, 2]):.2f}, "
          f"regime {law.regime(p0)[0]}")
# The friction cap binds, yet the contact point stopped and reversed: by the paper's rule it rolled.
law = bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.5)
pf = law.predict([1000.0, -800.0, 400.0])
print(f"v_P {1400.0:.0f} -> {pf[0] + pf[2]:.0f}: regime {law.regime([1000.0, -800.0, 400.0])}")
print(np.array_equal(bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.0).predict(p0), bl.Rigid(r=0.5, mu=0.4).predict(p0)))
res = bl.fit(bl.TangentialRestitution, bl.load_campaign("A", surrogate="published"))
print(res.model, res.at_bounds)
print(res.notes[0])
