"""Beyond the paper: the rigid bounce with tangential restitution."""

from __future__ import annotations

from bouncelab.laws import _ids
from bouncelab.laws._compiled import _CompiledLaw
from bouncelab.laws.base import Parameter
from bouncelab.laws.rigid import MU_SPEC, R_SPEC

__all__ = ["TangentialRestitution"]


class TangentialRestitution(_CompiledLaw):
    r"""Rigid bounce whose gripping balls leave with reversed contact-point velocity.

    The paper finds that balls which enter rolling do not lift off rolling but
    slipping the other way (its Fig. 7), which no law of the paper can do. This
    law (a rigid ball with tangential compliance in the spirit of Cross's
    tangential coefficient of restitution) adds one parameter :math:`e_t`: a
    ball that grips leaves with :math:`v_{P,F} = -e_t v_{P,0}` instead of
    :math:`v_{P,F} = 0`. With :math:`k = \mu (1 + r)`:

    .. math::

        \dot y_F = -r \dot y_0;\quad
        \text{slip if } |v_P| > \frac{7 k |\dot y_0|}{2 (1 + e_t)}
        \text{ (as in eq. rigid_bounce); otherwise}\;
        J = -\frac{2 (1 + e_t)}{7} v_P,\;
        \dot x_F = \dot x_0 + J,\; \omega_F = \omega_0 + \tfrac52 J.

    :math:`e_t = 0` is exactly :class:`~bouncelab.Rigid`. The law is continuous,
    mirror symmetric and, for ``r <= 1`` and ``e_t <= 1``, never gains energy.

    Parameters
    ----------
    r : float, optional
        Normal restitution, dimensionless, in [0, 1].
    mu : float, optional
        Friction coefficient, dimensionless, >= 0 (search bounds [0, 1.5]).
    e_t : float, optional
        Tangential restitution of the contact point, dimensionless, in [0, 1].
    """

    parameter_specs = (
        R_SPEC,
        MU_SPEC,
        Parameter("e_t", (0.0, 1.0), (0.0, 1.0), "1", "tangential restitution of the contact point"),
    )
    _law_id = _ids.TANGENTIAL

    def __init__(self, r: float | None = None, mu: float | None = None, e_t: float | None = None) -> None:
        self.r = r
        self.mu = mu
        self.e_t = e_t
        super().__init__()
