"""A new law in NumPy: the rigid bounce with a restitution that falls with impact speed."""

import numpy as np

import bouncelab as bl


class SpeedRestitution(bl.BounceModel):
    r"""Rigid bounce whose restitution falls with the normal impact speed: r = r0 / (1 + |ydot0| / v_c).

    Friction as in eq. (rigid_bounce): with k = mu (1 + r), the tangential impulse is
    J = clip(-2/7 v_P, -k |ydot0|, k |ydot0|).
    """

    r0 = bl.Parameter(bounds=(0, 1), physical=(0, 1), unit="1", doc="restitution of a slow impact")
    v_c = bl.Parameter(bounds=(10, 5000), physical=(1e-6, 1e9), unit="radius/s", doc="normal speed at which r halves")
    mu = bl.Parameter(bounds=(0, 1.5), physical=(0, np.inf), unit="1", doc="Coulomb friction coefficient")
    regimes = ("slip_forward", "roll", "slip_backward")

    def _predict(self, p, r0, v_c, mu):
        r = r0 / (1.0 + np.abs(p[:, 1]) / v_c)
        cap = mu * (1.0 + r) * np.abs(p[:, 1])
        j = np.clip(-(p[:, 0] + p[:, 2]) / 3.5, -cap, cap)
        return np.column_stack([p[:, 0] + j, -r * p[:, 1], p[:, 2] + 2.5 * j])

    def _regime(self, p, r0, v_c, mu):
        r = r0 / (1.0 + np.abs(p[:, 1]) / v_c)
        cap, j_stop = mu * (1.0 + r) * np.abs(p[:, 1]), -(p[:, 0] + p[:, 2]) / 3.5
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
