r"""CraterContact: a ball on the wall of its own crater, with velocity-weakening friction and ploughing."""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError
from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter

__all__ = ["CRATER_FADE_XDOT", "CraterContact"]

#: Default of the ``fade_xdot`` option (radii/s): the crater wall's tilt fades to zero below this xdot0.
CRATER_FADE_XDOT = 50.0


class _class_or_instance:
    """A method that receives the class when called on it and the instance when called on one."""

    def __init__(self, func: Any) -> None:
        self.func = func
        self.__doc__ = func.__doc__

    def __get__(self, obj: Any, cls: type) -> Any:
        return functools.partial(self.func, cls if obj is None else obj)


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

    parameter_specs = (
        Parameter("r0", (0.0, 1.0), (0.0, 1.0), "1", "restitution of a slow impact"),
        Parameter("v_r", (50.0, 20000.0), (1e-3, 1e9), "radius/s", "normal speed at which the restitution halves"),
        Parameter("mu_k", (0.0, 1.0), (0.0, 10.0), "1", "friction of a fast slip"),
        Parameter("mu_s", (0.0, 2.0), (0.0, 10.0), "1", "friction at zero slip"),
        Parameter("v_s", (5.0, 1000.0), (1e-3, 1e7), "radius/s", "slip speed over which friction weakens"),
        Parameter("lam", (0.0, 1.0), (0.0, 20.0), "1",
                  "ploughing (with kappa 0 a spinless ball keeps exp(-lam (1+r)) of v_t)"),
        Parameter("kappa", (0.0, 1.0), (0.0, 1.0), "radius", "depth below the centre of the ploughing force"),
        Parameter("e_t", (0.0, 1.0), (0.0, 1.0), "1", "tangential restitution of a gripped contact"),
        Parameter("beta0", (0.0, 30.0), (0.0, 60.0), "deg", "tilt of the crater wall at a slow landing"),
        Parameter("beta_n", (0.0, 30.0), (0.0, 100.0), "deg per 1000 radius/s", "tilt growth with |ydot0|"),
        Parameter("beta_t", (0.0, 30.0), (0.0, 100.0), "deg per 1000 radius/s", "tilt growth with |xdot0|"),
    )
    regimes = ("slip", "grip", "reversed")

    def __init__(self, r0: float | None = None, v_r: float | None = None, mu_k: float | None = None,
                 mu_s: float | None = None, v_s: float | None = None, lam: float | None = None,
                 kappa: float | None = None, e_t: float | None = None, beta0: float | None = None,
                 beta_n: float | None = None, beta_t: float | None = None,
                 fade_xdot: float = CRATER_FADE_XDOT) -> None:
        self.r0 = r0
        self.v_r = v_r
        self.mu_k = mu_k
        self.mu_s = mu_s
        self.v_s = v_s
        self.lam = lam
        self.kappa = kappa
        self.e_t = e_t
        self.beta0 = beta0
        self.beta_n = beta_n
        self.beta_t = beta_t
        self.fade_xdot = fade_xdot
        super().__init__()

    def _validate_parameters(self) -> None:
        super()._validate_parameters()
        value = self.fade_xdot
        if isinstance(value, (bool, str, bytes)) or not isinstance(value, (int, float, np.number)):
            raise ParameterError(f"CraterContact option 'fade_xdot' must be a number of radii/s; got {value!r}")
        fade = float(value)
        if not (np.isfinite(fade) and fade > 0):
            raise ParameterError(f"CraterContact option 'fade_xdot' must be a positive number of radii/s; "
                                 f"got {self.fade_xdot!r}")
        object.__setattr__(self, "fade_xdot", fade)

    @property
    def kernel(self):  # type: ignore[override]  # loaded on first use: importing a law does not import numba
        return _kernels().crater_kernel

    def _kernel_theta(self, theta: np.ndarray) -> np.ndarray:
        return np.append(theta, self.fade_xdot)

    @_class_or_instance
    def predict_varying(owner: Any, landing: Any, params: Any, *, codes: bool = False,
                        fade_xdot: float | None = None) -> Any:
        """Lift-off of ``n`` landings with a parameter vector per landing (spot-to-spot variation).

        ``params`` is an ``(n, 11)`` array in the order of ``parameter_specs`` (a single row
        broadcasts) or a mapping (dict, DataFrame) naming the eleven parameters; each row gives
        what ``CraterContact(**row).predict(landing_row)`` gives. The option ``fade_xdot`` is the
        argument's, else the instance's when called on one (``law.predict_varying``), else the
        default :data:`CRATER_FADE_XDOT`.
        """
        from bouncelab.laws._contact import predict_per_bounce

        if fade_xdot is None:
            fade_xdot = owner.fade_xdot if isinstance(owner, CraterContact) else CRATER_FADE_XDOT
        # an instance carries the option; its parameter values are placeholders, never used
        law = CraterContact(**{s.name: 0.5 * sum(s.bounds) for s in CraterContact.parameter_specs},
                            fade_xdot=fade_xdot)
        return predict_per_bounce(law, landing, params, codes=codes, kernel=_kernels().crater_kernel)

    def friction(self, slip_speed: Any) -> np.ndarray:
        """Friction coefficient mu(v) = mu_k + (mu_s - mu_k) exp(-|v| / v_s) at slip speeds ``v`` (radii/s)."""
        theta = self._theta()  # NotFittedError if a parameter has no value
        mu_k, mu_s, v_s = (float(theta[i]) for i in (2, 3, 4))
        from bouncelab.laws._contact import check_speeds

        v = np.abs(check_speeds(slip_speed, "slip_speed", positive=False))
        return mu_k + (mu_s - mu_k) * np.exp(-v / v_s)

    def _summary_lines(self) -> list[str]:
        if not self.is_fitted:
            return []
        from bouncelab.laws._contact import restitution_line

        mu = self.friction([0.0, 100.0, 500.0])
        return [restitution_line(self),
                f"friction at slip speeds 0 / 100 / 500 radii/s: {mu[0]:.3f} / {mu[1]:.3f} / {mu[2]:.3f}"]

    def restitution(self, speed: Any) -> np.ndarray:
        """Normal restitution |ydotF / ydot0| of vertical landings at ``speed`` radii/s (no spin, no tilt)."""
        from bouncelab.laws._contact import vertical_restitution

        return vertical_restitution(self, speed)
