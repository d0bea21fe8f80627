"""Penner's inclined-surface variants of the rigid bounce."""

from __future__ import annotations

import math

import numpy as np

from bouncelab.data import published as _published
from bouncelab.data.validation import as_states
from bouncelab.laws import _ids
from bouncelab.laws._compiled import _CompiledLaw, kernels
from bouncelab.laws.base import Parameter
from bouncelab.laws.rigid import MU_SPEC, R_SPEC

__all__ = ["K_P_MAX", "PennerFixed", "PennerVarying"]

#: Upper search bound of Penner's k_p in s/radius. At k_p = 1e-3 a landing at 1000 radii/s
#: (21 m/s) sees the surface tilted by its own landing angle, far beyond any published fit
#: (1.5e-4 and 3.0e-4); beta is capped at 90 degrees in any case.
K_P_MAX = 1.0e-3

_PENNER_DOC = r"""

    The rigid bounce of :class:`~bouncelab.Rigid` is applied on a surface
    rotated by :math:`\beta` against the direction of travel (the ball climbs
    out of the depression it makes). With :math:`c = \cos\beta`, :math:`s = \sin\beta`
    and a ball moving in +x, the landing velocity in the rotated frame is

    .. math::

        v_t = c\,\dot x_0 + s\,\dot y_0, \qquad v_n = -s\,\dot x_0 + c\,\dot y_0,

    restitution and friction act on :math:`(v_t, v_n, \omega_0)` exactly as in
    eq. (rigid_bounce), and the lift-off velocity is rotated back:
    :math:`\dot x_F = c\,v_{tF} - s\,v_{nF}`, :math:`\dot y_F = s\,v_{tF} + c\,v_{nF}`.
    A ball moving in -x is the mirror image (:math:`\dot x \to -\dot x`,
    :math:`\omega \to -\omega`); :math:`\dot x_0 = 0` counts as +x. Regimes are
    those of the rigid bounce in the rotated frame, named in the lab frame
    ("slip_forward" means the contact point slides towards +x).
"""


class PennerFixed(_CompiledLaw):
    __doc__ = (
        "Rigid bounce on a surface tilted by a fixed angle ``beta_deg`` (Penner, fixed beta)."
        + _PENNER_DOC
        + r"""
    Parameters
    ----------
    r : float, optional
        Restitution in the rotated frame, dimensionless, in [0, 1].
    mu : float, optional
        Friction coefficient, dimensionless, >= 0 (search bounds [0, 1.5]).
    beta_deg : float, optional
        Tilt of the effective surface in degrees, in [0, 90) (search bounds [0, 45]).

    Examples
    --------
    With ``beta_deg=0`` the law is the rigid bounce:

    >>> from bouncelab import Rigid
    >>> p0 = [[1000.0, -800.0, 300.0]]
    >>> bool((PennerFixed(r=0.5, mu=0.4, beta_deg=0.0).predict(p0) == Rigid(r=0.5, mu=0.4).predict(p0)).all())
    True
    """
    )

    parameter_specs = (
        R_SPEC,
        MU_SPEC,
        Parameter("beta_deg", (0.0, 45.0), (0.0, 89.999), "deg", "tilt of the effective surface"),
    )
    _law_id = _ids.PENNER_FIXED

    def __init__(self, r: float | None = None, mu: float | None = None, beta_deg: float | None = None) -> None:
        self.r = r
        self.mu = mu
        self.beta_deg = beta_deg
        super().__init__()

    _kernel_scale = (1.0, 1.0, math.pi / 180.0)  # the kernel takes beta in radians

    @classmethod
    def published(cls, campaign: str) -> PennerFixed:
        """Table 3: campaign "A" (r=0.420, mu=0.852, beta=12.9 deg) or "B" (0.147, 0.998, 18.4 deg)."""
        return cls(**_published.rigid_family_parameters(campaign, "PennerFixed"))


class PennerVarying(_CompiledLaw):
    __doc__ = (
        r"""Rigid bounce on a surface tilted by Penner's angle :math:`\beta = k_p\, s\, \phi`.

    Eq. (penner_angle): :math:`s = \sqrt{\dot x_0^2 + \dot y_0^2}` is the landing
    speed in radii/s and :math:`\phi = \arctan(-\dot y_0 / |\dot x_0|)` the landing
    angle; with :math:`\phi` in radians :math:`\beta` is in radians (the relation is the
    same in degrees). :math:`\beta` is capped at 90 degrees (a vertical surface)."""
        + _PENNER_DOC
        + r"""
    Parameters
    ----------
    r : float, optional
        Restitution in the rotated frame, dimensionless, in [0, 1].
    mu : float, optional
        Friction coefficient, dimensionless, >= 0 (search bounds [0, 1.5]).
    k_p : float, optional
        Turf constant in s/radius (1 / scaled speed), >= 0 (search bounds
        [0, :data:`K_P_MAX`] = [0, 1e-3]).
    """
    )

    parameter_specs = (
        R_SPEC,
        MU_SPEC,
        Parameter("k_p", (0.0, K_P_MAX), (0.0, float("inf")), "s/radius", "Penner's angle per unit speed and angle"),
    )
    _law_id = _ids.PENNER_VARYING

    def __init__(self, r: float | None = None, mu: float | None = None, k_p: float | None = None) -> None:
        self.r = r
        self.mu = mu
        self.k_p = k_p
        super().__init__()

    def beta_deg(self, landing) -> np.ndarray:
        """Penner's angle beta (degrees) for each landing, as the law uses it (capped at 90 degrees)."""
        theta = self._theta()
        p, wrap = as_states(landing, "landing", landing=True)
        sphi = kernels().speeds_times_angles(p)
        return wrap(np.degrees(np.minimum(theta[2] * sphi, np.pi / 2)))

    @classmethod
    def published(cls, campaign: str) -> PennerVarying:
        """Table 3: campaign "A" (r=0.448, mu=0.969, k_p=1.543e-4) or "B" (0.222, 0.999, 2.973e-4)."""
        return cls(**_published.rigid_family_parameters(campaign, "PennerVarying"))
