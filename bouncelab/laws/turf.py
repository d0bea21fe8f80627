r"""TurfContact: a ball pressing into an elasto-plastic, rate-dependent turf bed, integrated through the contact."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from bouncelab.core import _parallel
from bouncelab.laws._contact import restitution_line, vertical_restitution
from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter
from bouncelab.laws.rigid import MU

__all__ = ["DEFAULT_LOG10_K", "TURF_STEPS", "TurfContact"]

#: Default normal stiffness (log10): a 10 m/s landing compresses the turf by 0.3 radii (6 mm) for 1.3 ms.
DEFAULT_LOG10_K = 6.8
#: Parts the fitter's error sums are cut into (shared by the threads; fixed, so sums do not depend on them).
FIT_PARTS = 8
#: RK4 steps per estimated elastic contact time used by ``predict`` (see the accuracy note of TurfContact).
TURF_STEPS = 64


def _kernel():
    from bouncelab.laws._contact_kernels import turf_kernel

    return turf_kernel


class TurfContact(CompiledLaw):
    r"""A rigid ball pressing into an elasto-plastic turf bed with a bristle spring and Coulomb friction.

    Lengths in ball radii, forces per unit ball mass, :math:`I = \tfrac25 m R^2`.
    The ball's lowest point penetrates the undisturbed turf by :math:`\delta`
    (:math:`\dot\delta_0 = -\dot y_0`); the turf under it has a plastic crater
    of depth :math:`d`, so its elastic compression is :math:`e = \delta - d`.

    **Normal pressure** (a bed of turf columns under a sphere, small contact
    arc; Hunt-Crossley damping on the indentation rate), acting radially over
    the contact arc and hence through the ball's centre:

    .. math::

        N = \max\!\big(0,\; k\, e^{3/2} (1 + c\,\dot\delta)\big),\qquad \ddot\delta = -N .

    **Plasticity.** The elastic force cannot exceed the yield force
    :math:`k e_y^{3/2}`: while the ball moves down with :math:`e = e_y` the crater
    deepens, :math:`\dot d = \dot\delta` (perfectly plastic); it stops deepening when
    the ball turns back. Faster landings dig deeper craters and lose more energy, and
    damping grows with speed: restitution falls with impact speed.

    **Ploughing.** The columns in front of a ball moving sideways are compressed at
    the rate :math:`\lambda\dot x\phi` at arc angle :math:`\phi`; integrating the damped
    radial pressure over the arc (the front wall of the crater, of height
    :math:`\delta`, capped at the ball's equator) gives a horizontal force through the
    centre, so no torque:

    .. math::

        F_p = -\tfrac25\, \lambda\, c\, k\, \min(\delta, 1)^{5/2}\, \dot x \qquad (\text{while } N > 0).

    **Tangential compliance.** A bristle spring :math:`k_t` (displacement u) in series
    with a Coulomb slider at the contact point: stuck, :math:`\dot u = v_P = \dot x + \omega`
    and :math:`F_b = -k_t u` while :math:`k_t |u| < \mu N`; slipping in direction
    :math:`\sigma`, :math:`F_b = -\sigma\mu N` and :math:`u = \sigma\mu N / k_t`, until the
    slider's velocity :math:`\sigma v_P - \mu \dot N / k_t` reaches zero. Then

    .. math::

        \ddot x = F_b + F_p,\qquad \dot\omega = \tfrac52 F_b .

    Lift-off when the turf stops pushing (:math:`e = 0` or :math:`1 + c\dot\delta = 0`).
    Gravity (about 460 radii/s², i.e. under 1 radius/s over a contact) is neglected.

    **Integration.** Classical RK4 with a fixed step, :data:`TURF_STEPS` = 64 steps per
    Hertzian contact time :math:`2.943\,e_{max}/v_0`, :math:`e_{max} = (5 v_0^2/4k)^{2/5}`,
    at least 24 per period of the stuck contact point :math:`2\pi/\sqrt{3.5 k_t}`, and short
    enough for stability (step times the damping rates of the normal motion and the
    ploughing below 1.5);
    every mode switch (yield, unloading, stick to slip, slip to stick, lift-off) is an
    event located inside its step by Illinois false position on the RK4 step size
    (to 1e-11 of a step), and the integration restarts from it in the new mode.
    **Accuracy** (measured against 2048 steps over 3000 random landings and parameter
    sets of the default search box, ``tests/test_turf.py``): lift-off within
    7e-5 of the landing speed ‖p₀‖ at worst, 1e-5 for 99 %; halving the step
    changes it by less than 1e-4 ‖p₀‖. ``bouncelab.laws._contact_kernels.turf_integrate``
    takes the number of steps for tighter work.

    **What bounce data can identify.** The law has an exact scaling symmetry: for any
    :math:`\lambda > 0`, :math:`(k, e_y, k_t, \lambda_p) \to (k\lambda^{-5/2}, \lambda e_y,
    k_t\lambda^{-2}, \lambda_p/\lambda)` with the same c and μ scales depths by λ and times by
    λ and leaves every lift-off velocity unchanged (as long as the crater wall stays below the
    equator, δ < 1). Landing and lift-off velocities therefore cannot fix the stiffness: only the
    invariant combinations (e.g. the yield speed :math:`\sqrt{k e_y^{5/2}}`, :math:`k_t e_y^2`,
    :math:`\lambda_p e_y`). ``log10_k`` is declared ``vary=False`` and held at
    :data:`DEFAULT_LOG10_K` = 6.8 in fits (the other five are then identifiable, tested by
    parameter recovery); free it (``fit(..., free=["log10_k"])``) only with data that see
    contact times or depths.

    Regimes: ``slip`` (the contact point slips throughout), ``grip`` (it sticks
    during contact and leaves with :math:`v_P` of the landing's sign or zero),
    ``reversed`` (it leaves slipping the other way).

    Limits: ``lam = 0`` puts all horizontal impulse at the contact point (lever arm
    Δω/Δẋ = 2.5 as for the rigid laws); large ``log10_kt`` with ``c = 0`` and large
    ``e_y`` gives a Hertzian elastic bounce with Coulomb friction (restitution 1).

    Parameters
    ----------
    log10_k : float, default 6.8
        Normal stiffness, log10 of k in radius^-1/2 s^-2 (per unit mass); at 6.8 a 10 m/s
        landing compresses the turf by 0.3 radii (6 mm) for 1.3 ms. Held in fits (see above).
    c : float
        Hunt-Crossley damping, ms/radius, [0, 5] (restitution about 1 - c v0 at low speed).
    e_y : float
        Yield compression, radii, [0.05, 2]: the yield force is k e_y^1.5.
    mu : float
        Coulomb friction, dimensionless, [0, 1.5].
    log10_kt : float
        Bristle stiffness, log10 of k_t in s^-2 (per unit mass), searched in [4.5, 9]: the stuck
        contact point oscillates at sqrt(3.5 k_t) rad/s (1870 rad/s at 6; stiffer bristles cost
        more steps, as each period gets at least 24).
    lam : float
        Ploughing: horizontal-to-vertical damping ratio of the turf bed, dimensionless, [0, 20].

    Notes
    -----
    For spot-to-spot variation (a different parameter vector per bounce) use
    :meth:`predict_varying`.

    Examples
    --------
    >>> law = TurfContact(log10_k=6.8, c=1.0, e_y=0.3, mu=0.6, log10_kt=6.0, lam=3.0)
    >>> law.predict([[300.0, -800.0, 0.0]]).round(1)
    array([[  65.5,  419.6, -345. ]])
    """

    log10_k = Parameter(bounds=(5.0, 8.0), physical=(3.0, 10.0), unit="log10(radius^-1/2 s^-2)", vary=False,
                        default=DEFAULT_LOG10_K,
                        doc="normal stiffness k of N = k e^1.5 (per unit mass); sets the scale, held in fits")
    c = Parameter(bounds=(0.0, 5.0), physical=(0.0, 100.0), unit="ms/radius",
                  doc="Hunt-Crossley damping of the indentation rate")
    e_y = Parameter(bounds=(0.05, 2.0), physical=(0.01, 10.0), unit="radius",
                    doc="yield compression (yield force k e_y^1.5)")
    mu = MU
    log10_kt = Parameter(bounds=(4.5, 9.0), physical=(2.0, 11.0), unit="log10(s^-2)",
                         doc="bristle (tangential) stiffness k_t per unit mass")
    lam = Parameter(bounds=(0.0, 20.0), physical=(0.0, 1000.0), unit="1",
                    doc="ploughing: horizontal-to-vertical damping ratio")
    regimes = ("slip", "grip", "reversed")

    @property
    def kernel(self):  # type: ignore[override]  # loaded on first use: importing a law does not import numba
        return _kernel()

    def _error_function(self, landing: np.ndarray, liftoff: np.ndarray,
                        inv_norm: np.ndarray) -> Callable[[Sequence[float]], Any]:
        """The fitter's error sums, shared between threads already for campaign-sized data.

        Each bounce costs microseconds here (against nanoseconds for the algebraic laws), so
        a fit of a few hundred bounces is worth splitting: always into the same
        :data:`FIT_PARTS` parts, whose sums are added in order, so the value does not depend
        on the number of threads.
        """
        n = len(landing)
        if n >= _parallel.PARALLEL_MIN or n < 2 * FIT_PARTS:
            return super()._error_function(landing, liftoff, inv_norm)
        sums = self._loops().error_sums
        cuts = [(k * n) // FIT_PARTS for k in range(FIT_PARTS + 1)]

        def f(values: Sequence[float]) -> tuple[float, ...]:
            args = (landing, liftoff, inv_norm, tuple(values))
            if _parallel.num_threads() == 1 or getattr(_parallel._local, "in_pool", False):
                parts = [sums(*args, cuts[k], cuts[k + 1]) for k in range(FIT_PARTS)]
            else:
                parts = [None] * FIT_PARTS
                _parallel._share(sums, args, cuts, parts)
            return tuple(math.fsum(p[j] for p in parts) for j in range(4))

        return f

    def restitution(self, speed: Any) -> np.ndarray:
        """Normal restitution |ydotF / ydot0| of vertical landings at ``speed`` radii/s (no spin)."""
        return vertical_restitution(self, speed)

    def _summary_lines(self) -> list[str]:
        if not self.is_fitted:
            return []
        return [restitution_line(self)]
