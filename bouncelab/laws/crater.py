r"""CraterContact: a ball on the wall of its own crater, with velocity-weakening friction and ploughing."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.laws._contact import check_speeds, restitution_line, vertical_restitution
from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Option, Parameter, fade_speed

__all__ = ["CRATER_FADE_XDOT", "CraterContact"]

#: Default of the ``fade_xdot`` option (radii/s): the crater wall's tilt fades to zero below this xdot0.
CRATER_FADE_XDOT = 50.0



def _kernels():
    from bouncelab.laws import _contact_kernels

    return _contact_kernels


class CraterContact(CompiledLaw):
    r"""A rigid ball bouncing off the front wall of the crater it digs, with ploughing and turf friction.

    Scaled units (radii, radii/s, rad/s), the ball a uniform sphere (:math:`I = \tfrac25 mR^2`),
    forces per unit mass. Built from what the paper's data show (its Fig. 7 and eqs. disjointA/B)
    and the physics of turf; every piece dissipates energy.

    **Crater wall.** The ball meets the turf on a wall tilted by :math:`\beta` against its
    direction of travel, steeper for deeper (faster-sinking) and faster-moving landings
    (:math:`\beta` in degrees, speeds in radii/s, capped at 60°):

    .. math::

        \beta = \Big(\beta_0 + \beta_n \frac{|\dot y_0|}{1000} + \beta_t \frac{|\dot x_0|}{1000}\Big)
                \min\!\Big(\frac{|\dot x_0|}{x_f}, 1\Big)

    where the fade :math:`x_f` (option ``fade_xdot``, default 50 radii/s) makes the law continuous
    at :math:`\dot x_0 = 0`. In the wall's frame the landing is :math:`v_t = \cos\beta\,|\dot x_0| +
    \sin\beta\,\dot y_0`, :math:`v_n = -\sin\beta\,|\dot x_0| + \cos\beta\,\dot y_0 < 0`.

    **Normal restitution** falls with the normal speed (plastic turf): :math:`r = r_0 / (1 +
    |v_n| / v_r)`, so the contact's normal impulse per unit mass is :math:`P = (1 + r)|v_n|`.

    **Tangential motion**, integrated over the normal impulse :math:`p \in [0, P]` (friction and
    ploughing both scale with the normal force, so :math:`p` is their clock):

    .. math::

        \frac{dv_t}{dp} = g + f, \qquad \frac{d\omega}{dp} = \tfrac52 (f + \kappa g), \qquad
        g = -\frac{\lambda}{|v_n|}\,(v_t + \kappa\omega)

    * :math:`g`, **ploughing**: the turf in front of the ball resists the motion of the part of
      the ball it touches, a dashpot acting :math:`\kappa` radii below the centre (κ = 0: through
      the centre, no torque; κ = 1: at the contact point). Its power :math:`-\tfrac{\lambda}{|v_n|}
      (v_t + \kappa\omega)^2` is never positive. With κ = 0 a frictionless, spinless ball keeps
      :math:`e^{-\lambda(1+r)}` of :math:`v_t`.
    * :math:`f`, **turf friction**, velocity weakening: while the contact point slips with
      :math:`v_P = v_t + \omega`, :math:`f = -\operatorname{sign}(v_P)\,\mu(|v_P|)`,
      :math:`\mu(v) = \mu_k + (\mu_s - \mu_k)\,e^{-v / v_s}`. With :math:`\mu_s > \mu_k`, a ball
      that slips fast feels little friction and keeps slipping, one that slows down grips harder:
      the transition between "slips throughout" and "grips" is sharp, as in the paper's Fig. 7.
    * **Stick.** When :math:`v_P` reaches zero, friction holds it there against the ploughing
      torque if it needs at most :math:`\mu_s` (per unit normal force); otherwise the contact
      point slips back.

    **Bristle recoil.** A contact that stuck leaves with :math:`v_P = -e_t\, v_{P0}\,(1 - p^*/P)`
    (the rolling speed :math:`(5 v_t - 2\omega)/7` unchanged), :math:`p^*` the normal impulse at
    which it stuck: Walton's tangential restitution for a ball that grips from the start, none for
    one that grips only as it leaves (so the law stays continuous). The recoil is capped so that
    the bounce never returns more energy than the contact dissipated.

    Lift-off: :math:`v_{nF} = r|v_n|`, rotated back to the lab frame; a ball moving in -x is the
    mirror image.

    **Integration.** Classical RK4 in :math:`p`, :data:`~bouncelab.laws._contact_kernels.CRATER_STEPS`
    = 48 steps over :math:`P`, shortened near :math:`v_P = 0` so that a step changes :math:`v_P` by at
    most a quarter of :math:`|v_P| + v_s` (friction varies on the scale :math:`v_s` there) and stays
    stable where friction balances ploughing (steady sliding); the instant the contact point stops
    is located inside its step by Illinois false position (to 1e-12 of a step), and a contact that
    slips back from a stop is followed to its next stop. **Accuracy** (measured against 1536 steps
    over 100 000 random landings and parameter sets of the search box; tested on 300): lift-off
    within about 1e-4 of the landing speed ‖p₀‖ at worst (7e-5 in that sample, up to 1.05e-4 in
    others over the whole allowed ranges), 1.4e-6 for 99 %, the same regime every time;
    doubling the steps divides the typical error by about 16 (fourth order). It agrees with an
    independent ``solve_ivp`` implementation (``benchmarks/contact_reference.py``).

    Regimes, what happened during contact: ``slip`` (slips throughout in one direction), ``grip``
    (the contact point stuck; it leaves with :math:`v_P` reversed by the recoil if
    :math:`e_t > 0`), ``reversed`` (it slipped back without ever sticking).

    **Limit.** With heavy backspin on a steep wall the ball can slide back down it and leave with
    :math:`\dot y_F \le 0` (into the ground; the law has no second contact):
    ``predict(..., return_flags=True)`` marks such lift-offs.

    Limits: ``beta0 = beta_n = beta_t = 0``, ``lam = 0``, ``e_t = 0``, ``mu_s = mu_k`` and
    ``v_r`` large give the rigid bounce of :class:`~bouncelab.Rigid` with ``r = r0``, ``mu = mu_k``;
    adding the tilt gives :class:`~bouncelab.PennerFixed`.

    Parameters
    ----------
    r0 : float
        Restitution of a slow impact, dimensionless, [0, 1].
    v_r : float
        Normal speed at which the restitution halves, radii/s (search [50, 20000]).
    mu_k : float
        Friction of a fast slip, dimensionless (search [0, 1]).
    mu_s : float
        Friction at zero slip, dimensionless (search [0, 2]); above ``mu_k``: velocity weakening.
    v_s : float
        Slip speed over which friction weakens, radii/s (search [5, 1000]).
    lam : float
        Ploughing, dimensionless (search [0, 1]).
    kappa : float
        Depth below the centre at which the ploughing force acts, radii, [0, 1].
    e_t : float
        Tangential restitution (bristle recoil) of a gripped contact, dimensionless, [0, 1].
    beta0 : float
        Tilt of the crater wall at a slow landing, degrees (search [0, 30]).
    beta_n, beta_t : float
        Growth of the tilt per 1000 radii/s of normal (``|ydot0|``) and horizontal (``|xdot0|``)
        landing speed, degrees (search [0, 30]).
    fade_xdot : float, optional
        Option, not a parameter: the tilt fades linearly to zero below this ``|xdot0|`` (radii/s;
        default 50). Must be positive.

    Examples
    --------
    >>> law = CraterContact(r0=0.6, v_r=2000.0, mu_k=0.15, mu_s=1.0, v_s=150.0, lam=0.25,
    ...                     kappa=0.1, e_t=0.2, beta0=5.0, beta_n=0.0, beta_t=0.0)
    >>> law.predict([[1000.0, -800.0, 0.0], [1000.0, -800.0, 900.0]]).round(1)
    array([[ 463. ,  409.8, -552.6],
           [ 439.4,  407.7,  362.7]])
    >>> law.regime([[1000.0, -800.0, 0.0], [1000.0, -800.0, 900.0]]).tolist()
    ['grip', 'slip']
    """

    r0 = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="restitution of a slow impact")
    v_r = Parameter(bounds=(50.0, 20000.0), physical=(1e-3, 1e9), unit="radius/s",
                    doc="normal speed at which the restitution halves")
    mu_k = Parameter(bounds=(0.0, 1.0), physical=(0.0, 10.0), unit="1", doc="friction of a fast slip")
    mu_s = Parameter(bounds=(0.0, 2.0), physical=(0.0, 10.0), unit="1", doc="friction at zero slip")
    v_s = Parameter(bounds=(5.0, 1000.0), physical=(1e-3, 1e7), unit="radius/s",
                    doc="slip speed over which friction weakens")
    lam = Parameter(bounds=(0.0, 1.0), physical=(0.0, 20.0), unit="1",
                    doc="ploughing (with kappa 0 a spinless ball keeps exp(-lam (1+r)) of v_t)")
    kappa = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="radius",
                      doc="depth below the centre of the ploughing force")
    e_t = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="tangential restitution of a gripped contact")
    beta0 = Parameter(bounds=(0.0, 30.0), physical=(0.0, 60.0), unit="deg",
                      doc="tilt of the crater wall at a slow landing")
    beta_n = Parameter(bounds=(0.0, 30.0), physical=(0.0, 100.0), unit="deg per 1000 radius/s",
                       doc="tilt growth with |ydot0|")
    beta_t = Parameter(bounds=(0.0, 30.0), physical=(0.0, 100.0), unit="deg per 1000 radius/s",
                       doc="tilt growth with |xdot0|")
    fade_xdot = Option(default=CRATER_FADE_XDOT, check=fade_speed,
                       doc="radii/s below which the crater wall's tilt fades linearly to zero (positive)")
    regimes = ("slip", "grip", "reversed")

    @property
    def kernel(self):  # type: ignore[override]  # loaded on first use: importing a law does not import numba
        return _kernels().crater_kernel

    def _kernel_args(self, **parameters: Any) -> tuple:
        return (*parameters.values(), self.fade_xdot)

    def friction(self, slip_speed: Any) -> np.ndarray:
        """Friction coefficient mu(v) = mu_k + (mu_s - mu_k) exp(-|v| / v_s) at slip speeds ``v`` (radii/s)."""
        values = self._fitted_values()  # NotFittedError if a parameter has no value
        mu_k, mu_s, v_s = values["mu_k"], values["mu_s"], values["v_s"]
        v = np.abs(check_speeds(slip_speed, "slip_speed", positive=False))
        return mu_k + (mu_s - mu_k) * np.exp(-v / v_s)

    def _summary_lines(self) -> list[str]:
        if not self.is_fitted:
            return []
        mu = self.friction([0.0, 100.0, 500.0])
        return [restitution_line(self),
                f"friction at slip speeds 0 / 100 / 500 radii/s: {mu[0]:.3f} / {mu[1]:.3f} / {mu[2]:.3f}"]

    def restitution(self, speed: Any) -> np.ndarray:
        """Normal restitution |ydotF / ydot0| of vertical landings at ``speed`` radii/s (no spin, no tilt)."""
        return vertical_restitution(self, speed)
