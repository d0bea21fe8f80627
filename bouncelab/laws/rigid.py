"""Rigid bounce with restitution and Coulomb friction."""

from __future__ import annotations

from bouncelab.data import published as _published
from bouncelab.laws import _ids
from bouncelab.laws._compiled import _CompiledLaw
from bouncelab.laws.base import Parameter

__all__ = ["Rigid"]

R_SPEC = Parameter("r", (0.0, 1.0), (0.0, 1.0), "1", "normal coefficient of restitution |ydotF / ydot0|")
MU_SPEC = Parameter("mu", (0.0, 1.5), (0.0, float("inf")), "1", "Coulomb friction coefficient")


class Rigid(_CompiledLaw):
    r"""Instantaneous rigid bounce with restitution ``r`` and Coulomb friction ``mu``.

    Eq. (rigid_bounce) of the paper. With :math:`k = \mu (1 + r)` and the
    contact-point velocity :math:`v_P = \dot x_0 + \omega_0`:

    .. math::

        \dot y_F = -r \dot y_0 \quad \text{always, and}

        \text{slip forward } (v_P > \tfrac72 k |\dot y_0|):\;
            \dot x_F = \dot x_0 + k \dot y_0,\; \omega_F = \omega_0 + \tfrac52 k \dot y_0

        \text{roll } (|v_P| \le \tfrac72 k |\dot y_0|):\;
            \dot x_F = \tfrac57 \dot x_0 - \tfrac27 \omega_0,\;
            \omega_F = -\tfrac57 \dot x_0 + \tfrac27 \omega_0 \;(v_{P,F} = 0)

        \text{slip backward } (v_P < -\tfrac72 k |\dot y_0|):\;
            \dot x_F = \dot x_0 - k \dot y_0,\; \omega_F = \omega_0 - \tfrac52 k \dot y_0

    The law is continuous across the regime boundaries and, for
    ``0 <= r <= 1``, never gains kinetic energy.

    Parameters
    ----------
    r : float, optional
        Coefficient of restitution, dimensionless, in [0, 1] (search bounds [0, 1]).
    mu : float, optional
        Coefficient of friction, dimensionless, >= 0 (search bounds [0, 1.5]).

    Notes
    -----
    States are in scaled units: velocities in ball radii per second, spin in rad/s.

    Examples
    --------
    >>> Rigid(r=0.5, mu=0.4).predict([[1000.0, -800.0, 300.0]]).round(3)
    array([[ 628.571,  400.   , -628.571]])
    """

    parameter_specs = (R_SPEC, MU_SPEC)
    _law_id = _ids.RIGID

    def __init__(self, r: float | None = None, mu: float | None = None) -> None:
        self.r = r
        self.mu = mu
        super().__init__()

    @classmethod
    def published(cls, campaign: str) -> Rigid:
        """Table 3 of the paper: campaign "A" (r=0.544, mu=0.997) or "B" (r=0.260, mu=0.998)."""
        return cls(**_published.rigid_family_parameters(campaign, "Rigid"))
