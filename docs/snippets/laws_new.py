"""A new law in NumPy: the rigid bounce with a restitution that falls with impact speed."""

import numpy as np

import bouncelab as bl
from bouncelab.laws import BounceModel, Parameter


class SpeedRestitution(BounceModel):
    r"""Rigid bounce whose restitution falls with the normal impact speed: r = r0 / (1 + |ydot0| / v_c).

    Friction as in eq. (rigid_bounce): with k = mu (1 + r), the tangential impulse is
    J = clip(-2/7 v_P, -k |ydot0|, k |ydot0|).
    """

    parameter_specs = (
        Parameter("r0", (0.0, 1.0), (0.0, 1.0), "1", "restitution of a slow impact"),
        Parameter("v_c", (10.0, 5000.0), (1e-6, 1e9), "radius/s", "normal speed at which r halves"),
        Parameter("mu", (0.0, 1.5), (0.0, np.inf), "1", "Coulomb friction coefficient"),
    )
    regimes = ("slip_forward", "roll", "slip_backward")

    def __init__(self, r0=None, v_c=None, mu=None):
        self.r0 = r0
        self.v_c = v_c
        self.mu = mu
        super().__init__()

    def _impulse(self, p, theta):
        r0, v_c, mu = theta
        r = r0 / (1.0 + np.abs(p[:, 1]) / v_c)
        cap = mu * (1.0 + r) * np.abs(p[:, 1])
        j_stop = -(p[:, 0] + p[:, 2]) / 3.5
        return r, cap, j_stop

    def _predict(self, p, theta):
        r, cap, j_stop = self._impulse(p, theta)
        j = np.clip(j_stop, -cap, cap)
        return np.column_stack([p[:, 0] + j, -r * p[:, 1], p[:, 2] + 2.5 * j])

    def _regime(self, p, theta):
        _, cap, j_stop = self._impulse(p, theta)
        return np.where(j_stop < -cap, 0, np.where(j_stop > cap, 2, 1)).astype(np.int8)


if __name__ == "__main__":
    law = SpeedRestitution(r0=0.6, v_c=2000.0, mu=0.3)
    print(law.predict([[1000.0, -800.0, 300.0]]).round(2), law.regime([[1000.0, -800.0, 300.0]]))
    ds = bl.load_campaign("B", surrogate="published")
    res = bl.fit(SpeedRestitution, ds)                       # the generic global search works for any law
    print(res)
    print(bl.compare(ds, ["Rigid", SpeedRestitution]).table.round(4).to_string())
    print(res.model.to_json())                               # named by the script's module: laws_new:SpeedRestitution
    print(bl.BounceModel.from_dict(res.model.to_dict()) == res.model)
