r"""CompliantImpact: a rigid ball on a linear spring-dashpot with a tangential spring and a Coulomb slider.

Stronge's lumped-parameter compliant impact (W. J. Stronge, *Impact Mechanics*,
Cambridge University Press, 2000, ch. 8; R. Cross, *Grip-slip behavior of a
bouncing ball*, Am. J. Phys. 70 (2002) 1093; the paper's reference
biber_analysis). It is the simplest contact law in which a ball that grips the
surface can leave with its contact-point velocity reversed, and in which the
friction force reverses during contact.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter
from bouncelab.laws.rigid import MU

__all__ = ["R_MIN", "CompliantImpact", "contact_time", "restitution_of_damping"]

ZETA_MAX = 0.999
#: Smallest restitution of a spring-dashpot that leaves when its force vanishes (damping ratio 0.999).
R_MIN = 0.1357


def _lift_off(z: float) -> tuple[float, float, float]:
    """(omega_d, t_c, r) of the normal spring-dashpot with damping ratio z (omega_n = 1), closed form."""
    wd = math.sqrt(1.0 - z * z)
    tc = (math.pi - math.atan2(2.0 * z * wd, 1.0 - 2.0 * z * z)) / wd
    r = -math.exp(-z * tc) * (math.cos(wd * tc) - (z / wd) * math.sin(wd * tc))
    return wd, tc, r


def restitution_of_damping(zeta: float) -> float:
    """Normal restitution of the spring-dashpot with damping ratio ``zeta`` (lift-off where N = 0)."""
    return _lift_off(zeta)[2]


def _damping_of_restitution(r: float) -> float:
    """Damping ratio giving restitution r (bisection to machine precision; r decreases with zeta)."""
    if r >= 1.0:
        return 0.0
    lo, hi = 0.0, ZETA_MAX
    for _ in range(200):
        m = 0.5 * (lo + hi)
        if m <= lo or m >= hi:
            break
        if _lift_off(m)[2] > r:
            lo = m
        else:
            hi = m
    return 0.5 * (lo + hi)


def contact_time(r: float) -> float:
    """Contact duration in units of 1/omega_n (pi for r = 1, 2 at critical damping)."""
    return _lift_off(_damping_of_restitution(r))[1]


class CompliantImpact(CompiledLaw):
    r"""Compliant impact: normal spring-dashpot, tangential spring in series with a Coulomb slider.

    The ball (mass m, radius R, :math:`I = \tfrac25 m R^2`) lands on a surface
    with normal penetration :math:`\delta` (radii, :math:`\dot\delta_0 = -\dot y_0 = v_0`).
    Forces per unit mass, time in units of :math:`1/\omega_n`:

    .. math::

        \ddot\delta = -N,\qquad N = \delta + 2\zeta\dot\delta
        \quad\text{(Kelvin-Voigt), lift-off at } N = 0,

    in closed form, :math:`\delta = \tfrac{v_0}{\omega_d} e^{-\zeta t}\sin\omega_d t`,
    :math:`\omega_d = \sqrt{1-\zeta^2}`; lift-off (the surface cannot pull) at
    :math:`\omega_d t_c = \pi - \operatorname{atan2}(2\zeta\omega_d, 1-2\zeta^2)`, with
    restitution :math:`r = -\dot\delta(t_c)/v_0`. The parameter is ``r``; the damping
    ratio :math:`\zeta` is found from it by bisection (to machine precision).

    Tangentially a spring of stiffness :math:`k_t` (displacement u) in series with a
    Coulomb slider sits at the contact point, :math:`F = -k_t u`, :math:`|F| \le \mu N`.
    With :math:`v_P = \dot x + \omega` (so :math:`\dot v_P = \tfrac72 F`) and
    :math:`\kappa = \sqrt{\tfrac72 k_t}/\omega_n` the ratio of the stuck contact
    point's tangential frequency to the normal one:

    * **stick** (:math:`\dot u = v_P`, :math:`k_t|u| < \mu N`): harmonic,
      :math:`u(\tau) = u_1\cos\kappa\tau + \tfrac{v_1}{\kappa}\sin\kappa\tau` (closed form);
      it ends where :math:`\mu N - k_t |u|` turns negative;
    * **slip** in direction :math:`\sigma = \operatorname{sign} u` (:math:`F = -\sigma\mu N`,
      :math:`u = \sigma\mu N/k_t`): the tangential impulse is :math:`-\sigma\mu` times the
      normal impulse, :math:`\int N\,dt = \dot\delta(t_1) - \dot\delta(t)` (closed form);
      it ends where the slider's velocity :math:`\sigma v_P - \mu\dot N/k_t` turns negative.

    Every contact starts stuck (the spring loads from u = 0). The switching times
    are the only numerical part: each is bracketed by scanning the closed-form
    switching function on a grid of 32 points per contact time or per tangential
    period (whichever is shorter) and refined by bisection to the last bit of
    time (``ROOT_ITER`` = 60 halvings). A switch is missed only if the function dips
    below zero and back within one grid step (a graze; tested against
    ``scipy.integrate.solve_ivp`` to 1e-6 relative in ``tests/test_compliant.py``).

    Regimes: ``slip`` (the contact point slips throughout once the spring has
    loaded), ``grip`` (it sticks during contact and leaves with :math:`v_P` of the
    landing's sign or zero), ``reversed`` (it leaves slipping the other way:
    Cross's grip-slip, the paper's Fig. 7).

    **Limits.** :math:`\kappa\to\infty` (rigid tangential contact) gives
    :class:`~bouncelab.Rigid` with the same r and :math:`\mu` (slipping bounces get
    exactly :math:`\mu` times the normal impulse; gripping ones stop and stay stopped);
    the deviation falls like :math:`1/\kappa`. :math:`\mu\to\infty` (no slider) gives
    Walton's :class:`~bouncelab.TangentialRestitution` for gripping bounces with
    :math:`e_t = -\cos(\kappa t_c)` when that lies in [0, 1]; for finite :math:`\mu`,
    Walton's law is the algebraic approximation of this one. :math:`\mu = 0`:
    frictionless, :math:`\dot x` and :math:`\omega` unchanged. :math:`\dot y_F = -r\dot y_0`
    always. The law is homogeneous of degree one in :math:`(\dot x_0, \dot y_0, \omega_0)`
    (linear elements, rate-independent friction): it has no velocity scale.

    Parameters
    ----------
    r : float, optional
        Normal restitution, dimensionless, in [0.1357, 1] (a dashpot that cannot pull
        gives no less: critical damping leaves with :math:`e^{-2} \approx 0.1353`; ``R_MIN`` is the
        restitution at damping ratio 0.999).
    mu : float, optional
        Coulomb friction, dimensionless, >= 0.
    kappa : float, optional
        Tangential-to-normal frequency ratio :math:`\sqrt{7 k_t / (2 k_n)}`, dimensionless,
        in [0.05, 100] (searched in [0.3, 6]; an elastic sphere on an elastic half-space
        has about 1.6 to 1.8).

    Examples
    --------
    A gripping landing leaves with its contact-point velocity reversed:

    >>> law = CompliantImpact(r=0.5, mu=0.8, kappa=1.2)
    >>> out = law.predict([[300.0, -800.0, 0.0]])
    >>> bool(out[0, 0] + out[0, 2] < 0), str(law.regime([300.0, -800.0, 0.0]))
    (True, 'reversed')
    """

    r = Parameter(bounds=(R_MIN, 1.0), physical=(R_MIN, 1.0), unit="1", doc="normal restitution of the spring-dashpot")
    mu = MU
    kappa = Parameter(bounds=(0.3, 6.0), physical=(0.05, 100.0), unit="1",
                      doc="tangential-to-normal frequency ratio sqrt(7 k_t / (2 k_n))")
    regimes = ("slip", "grip", "reversed")
    lift_plane = "slip"  # an isotropic tangential spring and slider: the 3-D contact is the 2-D one along the slip

    @property
    def kernel(self):  # type: ignore[override]  # loaded on first use: importing a law does not import numba
        from bouncelab.laws._contact_kernels import compliant_kernel

        return compliant_kernel

    def _kernel_args(self, *, r: Any, mu: Any, kappa: Any) -> tuple:
        """The kernel also takes the damping ratio, damped frequency and contact time of ``r``: found by
        bisection, so once per law, not once per call (a law is immutable). ``r`` may be an array (a value
        per bounce)."""
        if np.ndim(r):
            z = np.array([_damping_of_restitution(float(x)) for x in np.ravel(r)]).reshape(np.shape(r))
            wd, tc = np.sqrt(1.0 - z * z), np.array([_lift_off(float(x))[1] for x in np.ravel(z)]).reshape(z.shape)
            return r, mu, kappa, z, wd, tc
        z = _damping_of_restitution(float(r))
        wd, tc, _ = _lift_off(z)
        return r, mu, kappa, z, wd, tc

    def _summary_lines(self) -> list[str]:
        if not self.is_fitted:
            return []
        z = _damping_of_restitution(self.r)
        _, tc, _ = _lift_off(z)
        et = -math.cos(self.kappa * tc)
        return [f"damping ratio zeta = {z:.4g}; contact time = {tc:.4g}/omega_n; "
                f"stuck contact point turns through kappa t_c = {self.kappa * tc:.4g} rad "
                f"(Walton's e_t in the mu -> inf limit: {et:.3g})"]
