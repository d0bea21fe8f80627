"""Penner's inclined-surface variants of the rigid bounce."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from bouncelab.core import published as _published
from bouncelab.core.validation import as_states
from bouncelab.laws.compiled import PARALLEL_MIN, CompiledLaw, run_chunked
from bouncelab.laws.parameters import Option, Parameter, fade_speed
from bouncelab.laws.rigid import MU, R

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

    **The law jumps at** :math:`\dot x_0 = 0`. The tilt always opposes the
    direction of travel, so it flips as :math:`\dot x_0` changes sign, while
    :math:`\beta` stays finite there (PennerVarying's :math:`\beta` is even largest
    at a vertical impact, where :math:`\phi = 90°`). With the published fixed-β law
    of campaign B, landings (±1, −1000, 0) lift off with :math:`\dot x_F = \mp 257`
    radii/s: two almost identical landings leave in opposite directions at
    5.5 m/s. This is the published behaviour and the default. The option
    ``fade_xdot`` (radii/s) gives a continuous variant: the tilt is multiplied by
    :math:`\min(|\dot x_0| / \text{fade\_xdot}, 1)`, so it fades linearly to zero as
    :math:`\dot x_0 \to 0` and is unchanged for :math:`|\dot x_0| \ge` ``fade_xdot``;
    the law is then continuous at :math:`\dot x_0 = 0` (it is the rigid bounce there).

    **In 3-D** (:func:`bouncelab.ground.bounce`, :func:`bouncelab.ground.run`) the law is
    what it describes: the 3-D rigid bounce with Coulomb friction along the contact point's
    slip, on the ground tilted by :math:`\beta` towards the incoming ball in the vertical plane
    of its velocity along the ground (``kernel_3d``, with :math:`\dot x_0` that velocity's
    size). It is continuous wherever that rigid bounce is, in the spin everywhere; an
    in-plane landing gives this 2-D law's lift-off bit for bit; and, as in 2-D, it jumps
    where the direction of travel does (a landing with no velocity along the ground) unless
    the tilt fades (``fade_xdot``).
"""


def _kernels():
    from bouncelab.laws import _kernels

    return _kernels



class _Penner(CompiledLaw):
    """What the two Penner laws share: the tilted-surface kernel, the fade option, a fast objective."""

    r = R
    mu = MU
    regimes = ("slip_forward", "roll", "slip_backward")
    _varying = False

    def _kernel_args(self, *, r: float, mu: float, **angle: float) -> tuple:
        (value,) = angle.values()  # beta_deg or k_p
        return r, mu, value, self.fade_xdot or 0.0

    def _scalars(self, values: Mapping[str, Any]) -> tuple[float, float, float, bool, float]:
        r, mu, angle, fade = self._args(values)
        return r, mu, angle * (1.0 if self._varying else _kernels().DEG), self._varying, fade

    # Dedicated loops (same scalar functions as the kernel): a fixed tilt's sine and cosine are
    # computed once per call, not once per bounce.
    def _row_loops(self, values: Mapping[str, Any]) -> tuple[Callable, Callable, tuple]:
        k = _kernels()
        return k.penner_predict_rows, k.penner_regime_rows, self._scalars(values)

    def _error_function(self, landing: np.ndarray, liftoff: np.ndarray,
                        inv_norm: np.ndarray) -> Callable[[Sequence[Any]], Any]:
        # Each landing's tilt factor (the fade, times s * phi for PennerVarying) is fixed for a
        # fit: computed once here, so an evaluation costs one pass without trigonometric inverses.
        k = _kernels()
        factor = k.penner_tilt_factors(landing, self._varying, self.fade_xdot or 0.0)
        sums, n = k.penner_error_sums, len(landing)
        scale = 1.0 if self._varying else k.DEG
        if n < PARALLEL_MIN:
            def f(values: Sequence[Any]) -> tuple[float, float, float, float]:
                r, mu, angle = values
                return sums(landing, liftoff, inv_norm, factor, r, mu, angle * scale, 0, n)
            return f

        def f_chunked(values: Sequence[Any]) -> tuple[float, float, float, float]:
            r, mu, angle = values
            parts = run_chunked(sums, n, landing, liftoff, inv_norm, factor, r, mu, angle * scale)
            return tuple(math.fsum(p[i] for p in parts) for i in range(4))

        return f_chunked


#: Penner's laws' option (declared on each law after its angle, as the constructor takes it).
_FADE = dict(default=None, check=functools.partial(fade_speed, optional=True),
             doc="radii/s over which the tilt fades to zero as xdot0 -> 0 (None: the published law)")


class PennerFixed(_Penner):
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
    fade_xdot : float, optional
        Option, not a parameter: the scale in radii/s over which the tilt fades to
        zero as xdot0 -> 0 (None, the default, is the published law).

    Examples
    --------
    With ``beta_deg=0`` the law is the rigid bounce:

    >>> from bouncelab import Rigid
    >>> p0 = [[1000.0, -800.0, 300.0]]
    >>> bool((PennerFixed(r=0.5, mu=0.4, beta_deg=0.0).predict(p0) == Rigid(r=0.5, mu=0.4).predict(p0)).all())
    True

    The jump at xdot0 = 0 and the continuous variant:

    >>> law = PennerFixed.published("B")
    >>> law.predict([[1.0, -1000.0, 0.0], [-1.0, -1000.0, 0.0]])[:, 0].round(0)
    array([-257.,  257.])
    >>> law.replace(fade_xdot=50.0).predict([[1.0, -1000.0, 0.0], [-1.0, -1000.0, 0.0]])[:, 0].round(1)
    array([-5.4,  5.4])
    """
    )

    beta_deg = Parameter(bounds=(0.0, 45.0), physical=(0.0, 89.999), unit="deg", doc="tilt of the effective surface")
    fade_xdot = Option(**_FADE)

    @property
    def kernel(self):  # type: ignore[override]
        return _kernels().penner_fixed_kernel

    @property
    def kernel_3d(self):  # type: ignore[override]
        return _kernels().penner_fixed_kernel_3d

    @classmethod
    def published(cls, campaign: str) -> PennerFixed:
        """Table 3: campaign "A" (r=0.420, mu=0.852, beta=12.9 deg) or "B" (0.147, 0.998, 18.4 deg)."""
        return cls(**_published.rigid_family_parameters(campaign, "PennerFixed"))


class PennerVarying(_Penner):
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
    fade_xdot : float, optional
        Option, not a parameter: the scale in radii/s over which the tilt fades to
        zero as xdot0 -> 0 (None, the default, is the published law).
    """
    )

    k_p = Parameter(bounds=(0.0, K_P_MAX), physical=(0.0, float("inf")), unit="s/radius",
                    doc="Penner's angle per unit speed and angle")
    fade_xdot = Option(**_FADE)
    _varying = True

    @property
    def kernel(self):  # type: ignore[override]
        return _kernels().penner_varying_kernel

    @property
    def kernel_3d(self):  # type: ignore[override]
        return _kernels().penner_varying_kernel_3d

    def beta_deg(self, landing) -> np.ndarray:
        """Penner's angle beta (degrees) for each landing, as the law uses it (capped at 90 degrees, faded)."""
        k_p = self._fitted_values()["k_p"]
        p, wrap = as_states(landing, "landing", landing=True)
        factor = _kernels().penner_tilt_factors(p, True, self.fade_xdot or 0.0)
        return wrap(np.degrees(np.minimum(k_p * factor, np.pi / 2)))

    @classmethod
    def published(cls, campaign: str) -> PennerVarying:
        """Table 3: campaign "A" (r=0.448, mu=0.969, k_p=1.543e-4) or "B" (0.222, 0.999, 2.973e-4)."""
        return cls(**_published.rigid_family_parameters(campaign, "PennerVarying"))
