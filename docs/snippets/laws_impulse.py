import numpy as np

import bouncelab as bl

r, mu = 0.5, 0.4
law = bl.Rigid(r=r, mu=mu)
landing = np.array([[1500.0, -300.0, 600.0],    # v_P = 2100 > 3.5 mu (1 + r) |ydot0| = 630: slips forward
                    [500.0, -800.0, -300.0],    # |v_P| = 200 < 1680: grips (rolls)
                    [200.0, -300.0, -900.0]])   # v_P = -700 < -630: slips backward
x0, y0, w0 = landing.T
j_grip = -(x0 + w0) / 3.5                       # impulse that stops the contact point
cap = mu * (1 + r) * np.abs(y0)                 # Coulomb: |J| <= mu (1 + r) |ydot0|
j = np.clip(j_grip, -cap, cap)
by_hand = np.column_stack([x0 + j, -r * y0, w0 + 2.5 * j])
print(law.regime(landing))
print(by_hand.round(3))
print(np.allclose(by_hand, law.predict(landing)))
print("v_P at lift-off:", (by_hand[:, 0] + by_hand[:, 2] + 0.0).round(3))
