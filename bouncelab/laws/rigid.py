"""Rigid bounce with restitution and Coulomb friction."""

from __future__ import annotations

import numpy as np

from bouncelab.core import published as _published
from bouncelab.core.errors import FitError
from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter
from bouncelab.laws.protocol import FitOutcome, FitProblem, fit_method
from bouncelab.laws.registry import law_name

__all__ = ["MU", "R", "Rigid"]

#: The rigid family's restitution and friction (Rigid, Penner's laws, TangentialRestitution share them).
R = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="normal coefficient of restitution |ydotF / ydot0|")
MU = Parameter(bounds=(0.0, 1.5), physical=(0.0, float("inf")), unit="1", doc="Coulomb friction coefficient")


def _rigid_kernel():
    from bouncelab.laws._kernels import rigid_kernel

    return rigid_kernel


class Rigid(CompiledLaw):
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
    Fitting methods: ``"global"`` (default) and the paper's ``"structured"``
    procedure (:meth:`_fit_structured`).

    Examples
    --------
    >>> Rigid(r=0.5, mu=0.4).predict([[1000.0, -800.0, 300.0]]).round(3)
    array([[ 628.571,  400.   , -628.571]])
    """

    r = R
    mu = MU
    regimes = ("slip_forward", "roll", "slip_backward")

    @property
    def kernel(self):  # type: ignore[override]  # loaded on first use: importing a law does not import numba
        return _rigid_kernel()

    @property
    def kernel_3d(self):  # type: ignore[override]  # the exact 3-D rigid bounce (bouncelab.ground)
        from bouncelab.laws._kernels import rigid_kernel_3d

        return rigid_kernel_3d

    @classmethod
    def published(cls, campaign: str) -> Rigid:
        """Table 3 of the paper: campaign "A" (r=0.544, mu=0.997) or "B" (r=0.260, mu=0.998)."""
        return cls(**_published.rigid_family_parameters(campaign, "Rigid"))

    @fit_method("structured")
    def _fit_structured(self, problem: FitProblem, *, mu_objective: str = "delta") -> FitOutcome:
        """The paper's two-stage procedure: r by least squares on ``ydotF = -r ydot0``, then mu with r fixed.

        Options: ``mu_objective`` chooses mu minimising ``"delta"`` (default) or the
        ``"lstsq"`` sum of squared xdot and omega residuals (the paper's text allows both).
        """
        if mu_objective not in ("delta", "lstsq"):
            raise FitError(f"mu_objective must be 'delta' or 'lstsq'; got {mu_objective!r}", law=law_name(self),
                           option="mu_objective")
        p0, pf = problem.landing, problem.liftoff
        r_lo, r_hi = problem.box["r"]
        r = problem.fixed.get("r")
        w = np.ones(len(p0)) if problem.sample_weight is None else problem.sample_weight
        if r is None:  # least squares on ydotF = -r ydot0 (weighted by the sample weights, if any)
            r = float(np.clip(-((w * pf[:, 1]) @ p0[:, 1]) / ((w * p0[:, 1]) @ p0[:, 1]), r_lo, r_hi))
        start = self.replace(r=r, mu=None)

        def lstsq(**values: float) -> float:
            res = (pf - start._evaluate(p0, values))[:, [0, 2]]
            return float((res * res).sum(axis=1) @ w)

        outcome = problem.run_global(start, hold={"r": r}, algorithm="DIRECT_L", maxeval=200,
                                     criterion=None if mu_objective == "delta" else lstsq)
        at_bounds = dict(outcome.at_bounds)
        if r in (r_lo, r_hi) and r_lo < r_hi:
            at_bounds["r"] = "lower" if r == r_lo else "upper"
        notes = [f"r = {r:.6g} from least squares on ydot; mu chosen with r fixed, minimising {mu_objective}",
                 *outcome.notes]
        return FitOutcome(
            model=outcome.model, objective_value=outcome.objective_value,
            algorithm=f"least squares + {outcome.algorithm.split(' ')[0]}", n_global=outcome.n_global,
            n_local=outcome.n_local, stop_reason=outcome.stop_reason, at_bounds=at_bounds,
            insensitive=outcome.insensitive, notes=notes,
        )
