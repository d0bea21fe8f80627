"""The piecewise-affine landing-to-lift-off map of the paper (eqs. disjointA/B).

The law is here; the procedures that find its plane (the paper's SVM and
bouncelab's search for the delta-optimal plane) are in
:mod:`bouncelab.laws.plane_fitting`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from bouncelab.core import published as _published
from bouncelab.core.errors import FitError, Hint, NotFittedError, ParameterError
from bouncelab.core.units import COMPONENTS
from bouncelab.laws import plane_fitting as pf_
from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter
from bouncelab.laws.protocol import FitOutcome, FitProblem, fit_method
from bouncelab.laws.registry import law_name

__all__ = ["PAPER_FORM_MIN", "PiecewiseAffine"]

#: The paper's form ``a xdot0 + b ydot0 + omega0 = c`` is printed only when the unit normal's
#: omega component is at least this large (so |a|, |b| <= 1000); otherwise only the unit form.
PAPER_FORM_MIN = 1e-3

_INF = float("inf")

#: The advice of a piecewise-affine fit asked for what only the generic search does.
_GLOBAL = Hint("method", "global", "the generic search, which holds any parameter and takes any objective")


def _kernels():
    from bouncelab.laws import _kernels  # (compiled: imports numba on first use, not with the law)

    return _kernels


class PiecewiseAffine(CompiledLaw):
    r"""Two affine maps either side of a plane in landing space.

    Eq. (piecewise_fit) with the split of eqs. (disjointA/B):

    .. math::

        \mathbf p_F = \begin{cases}
            A_1 \mathbf p_0 + \mathbf b_1 & \text{if } \mathbf n \cdot \mathbf p_0 < c
                \quad(\text{side 1, "roll"})\\
            A_2 \mathbf p_0 + \mathbf b_2 & \text{if } \mathbf n \cdot \mathbf p_0 \ge c
                \quad(\text{side 2, "slip"})
        \end{cases}

    with :math:`\mathbf p = [\dot x, \dot y, \omega]`. The paper prints the plane as
    :math:`a \dot x_0 + b \dot y_0 + \omega_0 = c`, i.e. :math:`\mathbf n = (a, b, 1)`.
    By convention side 1 holds the bounces that roll and side 2 those that slip
    throughout (the fitters orient the plane so); the law itself is just two maps.

    Parameters
    ----------
    normal : array_like (3,), optional
        Plane normal :math:`\mathbf n`: the coefficients of xdot0, ydot0 and omega0. Any
        non-zero scale gives the same plane, so the numbers have no unit of their own; in
        the paper's form (omega coefficient 1) a and b are in rad/radius. Fitted planes are
        stored with their largest coefficient +-1 (inside the search box).
    offset : float, optional
        Plane offset :math:`c` (rad/s in the paper's form; in general the unit of the
        component whose coefficient is 1).
    A1, A2 : array_like (3, 3), optional
        Linear parts, dimensionless (rows: xdotF, ydotF, omegaF; columns: xdot0, ydot0, omega0).
    b1, b2 : array_like (3,), optional
        Offsets in radii/s, radii/s, rad/s.

    Notes
    -----
    All six are parameters like any other (arrays), so a fit can hold some of
    them: ``bouncelab.fit(law, data, fixed=["normal", "offset"])`` refits the two
    maps with the plane of ``law``. Fitting methods: ``"plane"`` (default, the
    delta-optimal plane) and ``"svm"`` (the paper's procedure), see
    :mod:`bouncelab.laws.plane_fitting`; the generic ``"global"`` search also
    works but is slow in 28 dimensions.

    Examples
    --------
    >>> law = PiecewiseAffine.published("A")
    >>> law.plane_equation()
    '0.891·xdot0 + 0.763·ydot0 + omega0 = 600'
    >>> law.regime([[1000.0, -800.0, 600.0], [1000.0, -800.0, 0.0]])
    array(['slip', 'roll'], dtype='<U4')
    """

    # The plane n . p0 = offset has no scale of its own, so n and offset have no fixed unit (a fitted plane is
    # stored with its largest coefficient +-1; in the paper's form, omega coefficient 1, a and b are in
    # rad/radius and the offset in rad/s): reports print the plane as an equation, not these two numbers.
    normal = Parameter(bounds=(-1.0, 1.0), physical=(-_INF, _INF), shape=(3,), unit="",
                       doc="coefficients of xdot0, ydot0, omega0 in the plane n . p0 = offset splitting landing space "
                           "(any non-zero scale, so no unit of their own: see plane_equation())")
    offset = Parameter(bounds=(-3000.0, 3000.0), physical=(-_INF, _INF), unit="",
                       doc="right-hand side of the plane n . p0 = offset (rad/s when n's omega coefficient is 1, the "
                           "paper's form)")
    A1 = Parameter(bounds=(-3.0, 3.0), physical=(-1e6, 1e6), shape=(3, 3), unit="1",
                   doc="linear map on side 1 (roll), rows xdotF ydotF omegaF")
    b1 = Parameter(bounds=(-1000.0, 1000.0), physical=(-1e12, 1e12), shape=(3,), unit="radius/s, radius/s, rad/s",
                   doc="offset of the map on side 1")
    A2 = Parameter(bounds=(-3.0, 3.0), physical=(-1e6, 1e6), shape=(3, 3), unit="1", doc="linear map on side 2 (slip)")
    b2 = Parameter(bounds=(-1000.0, 1000.0), physical=(-1e12, 1e12), shape=(3,), unit="radius/s, radius/s, rad/s",
                   doc="offset of the map on side 2")
    regimes = ("roll", "slip")
    default_fit_method = "plane"

    def _check(self) -> None:
        if self.normal is not None and not np.any(self.normal):
            raise ParameterError("PiecewiseAffine plane normal must not be zero", law="PiecewiseAffine",
                                 parameter="normal", value=self.normal)

    @property
    def kernel(self):  # type: ignore[override]
        return _kernels().piecewise_kernel

    def _row_loops(self, values: Mapping[str, Any]) -> tuple[Callable, Callable, tuple]:
        # the kernel's arithmetic inlined into loops of its own (see bouncelab.laws._kernels)
        k = _kernels()
        return k.piecewise_predict_rows, k.piecewise_regime_rows, self._args(values)

    # ------------------------------------------------------------------ the plane
    def plane_unit_form(self) -> tuple[np.ndarray, float]:
        """The plane as ``(u, d)`` with ``u`` the unit normal: ``u . p0 = d`` (always finite)."""
        self._require_plane()
        norm = float(np.linalg.norm(self.normal))
        return self.normal / norm, float(self.offset) / norm

    def has_paper_form(self) -> bool:
        """Whether the plane can be printed as ``a xdot0 + b ydot0 + omega0 = c`` (see :data:`PAPER_FORM_MIN`)."""
        u, _ = self.plane_unit_form()
        return abs(u[2]) >= PAPER_FORM_MIN

    def printed_plane(self) -> tuple[float, float, float]:
        """The plane as the paper prints it, ``(a, b, c)`` in ``a xdot0 + b ydot0 + omega0 = c``.

        Raises
        ------
        ParameterError
            If the plane is (nearly) parallel to the omega axis, so that form does not exist
            (unit normal's omega component below :data:`PAPER_FORM_MIN`); use :meth:`plane_unit_form`.
        """
        if not self.has_paper_form():
            raise ParameterError("the plane is (nearly) parallel to the omega axis; it has no 'omega0 = ...' form "
                                 "(use plane_unit_form())", law=law_name(self), parameter="normal", value=self.normal)
        a, b, _ = self.normal / self.normal[2]
        c = self.offset / self.normal[2]
        return float(a), float(b), float(c)

    def plane_equation(self, digits: int = 3) -> str:
        """The plane as text: the paper's form where it exists, else the unit-normal form (always finite)."""
        if self.has_paper_form():
            a, b, c = self.printed_plane()
            side = "" if self.normal[2] > 0 else " (sides swapped: omega coefficient was negative)"
            text = f"{a:.{digits}g}·xdot0 + {b:.{digits}g}·ydot0 + omega0 = {c:.{digits}g}{side}"
            return text.replace("+ -", "- ")
        return self.plane_unit_equation(digits)

    def plane_unit_equation(self, digits: int = 3) -> str:
        """The plane as ``u · p0 = d`` with the unit normal ``u``, e.g. ``'0.567·xdot0 + ... = 382'``."""
        u, d = self.plane_unit_form()
        # a zero coefficient (a plane parallel to that axis) is left out, not printed as "+ 0·omega0"
        terms = " + ".join(f"{v:.{digits}g}·{c}0" for v, c in zip(u, COMPONENTS, strict=True) if v != 0)
        terms = terms.replace("+ -", "- ")
        return f"{terms} = {d:.{digits}g}"

    def _require_plane(self) -> None:
        if self.normal is None or self.offset is None:
            missing = [k for k in ("normal", "offset") if getattr(self, k) is None]
            raise NotFittedError("PiecewiseAffine has no plane yet; give normal and offset or fit the law",
                                 law=law_name(self), missing=missing)

    # ------------------------------------------------------------------ reports
    def _summary_lines(self) -> list[str]:
        if self.normal is None or self.offset is None:
            return []
        lines = [f"plane (unit normal): {self.plane_unit_equation(4)}  (xdot0, ydot0 in radii/s, omega0 in rad/s)"]
        if self.has_paper_form():
            lines.append(f"plane (paper's form): {self.plane_equation(4)}  (each term in rad/s)")
        for side, name, (A, b) in ((1, "roll", (self.A1, self.b1)), (2, "slip", (self.A2, self.b2))):
            if A is not None and b is not None:
                lines.append(f"side {side} ({name}): A{side} = {np.array2string(A, precision=3)}".replace("\n", ""))
                lines.append(f"{'':>16}b{side} = {np.array2string(b, precision=3)}")
        return lines

    def _diagnostics(self, landing: np.ndarray, liftoff: np.ndarray) -> dict[str, float]:
        """``mismatched``: fraction of bounces whose measured slip/roll class differs from their side (Table 2)."""
        if not self.is_fitted:
            return {}
        return {"mismatched": pf_._mismatched(self, landing, liftoff)}

    # ------------------------------------------------------------------ fitting
    def _plane_problem_checks(self, problem: FitProblem, min_side: int) -> tuple[np.ndarray, float] | None:
        """Common checks of the plane and svm methods; returns the plane held fixed, if any."""
        law = law_name(self)
        if not np.array_equal(problem.weights, [1.0, 0.0, 0.0, 0.0]):
            raise FitError("the piecewise-affine fit minimises delta; other objectives are not offered for it",
                           law=law, option="objective", hints=[_GLOBAL])
        try:
            min_side = int(min_side)
        except (TypeError, ValueError):
            raise FitError(f"min_side must be an integer of at least 4; got {min_side!r}", law=law,
                           option="min_side") from None
        if min_side < 4:
            raise FitError(f"min_side must be an integer of at least 4; got {min_side!r}", law=law, option="min_side")
        if problem.n < 2 * min_side:
            raise FitError(f"{problem.n} bounces are too few for a piecewise-affine law (need {2 * min_side})",
                           law=law)
        held = set(problem.fixed)
        if held - {"normal", "offset"}:
            raise FitError(f"the plane and svm methods can hold only the plane (normal, offset), not "
                           f"{sorted(held - {'normal', 'offset'})}", law=law, option="fixed", hints=[_GLOBAL])
        if held and held != {"normal", "offset"}:
            raise FitError("hold both 'normal' and 'offset' (the plane) or neither", law=law, option="fixed",
                           hints=[Hint("fixed", ["normal", "offset"])])
        if held:
            return np.asarray(problem.fixed["normal"], dtype=np.float64), float(problem.fixed["offset"])
        return None

    def _outcome(self, problem: FitProblem, model: PiecewiseAffine, algorithm: str, notes: list[str],
                 n_global: int = 0, n_local: int = 0, stop: str = "", extras: dict | None = None) -> FitOutcome:
        value = problem.value(model)
        return FitOutcome(model=model, objective_value=value, algorithm=algorithm, n_global=n_global,
                          n_local=n_local, stop_reason=stop, notes=notes, extras=extras or {})

    @fit_method("plane")
    def _fit_plane(self, problem: FitProblem, *, algorithm: str = "CRS2_LM",
                   local_algorithm: str | None = "NELDERMEAD", maxeval: int = 3000, svm_C: float = 1.0,
                   min_side: int = pf_.MIN_SIDE, max_search_bounces: int = 20_000) -> FitOutcome:
        """The plane minimising delta of the whole law (maps by least squares on each side).

        Started from the plane of the law given, if it has one, else from the SVM's
        hyperplane (trained on at most 5000 bounces). Options: ``algorithm`` and
        ``local_algorithm`` (NLopt, default CRS2_LM + NELDERMEAD), ``maxeval`` (global
        budget, 3000), ``svm_C`` (of the start), ``min_side`` (fewest bounces per side,
        8), ``max_search_bounces`` (above this many bounces the global stage runs on a
        random subsample of this size and only the polish on all bounces).
        """
        p0, pf = problem.landing, problem.liftoff
        held = self._plane_problem_checks(problem, min_side)
        min_side = int(min_side)
        slip = pf_._slip_codes(p0, pf).astype(bool)
        if held is not None:
            normal, offset = held
            model = PiecewiseAffine(**pf_.least_squares_maps(p0, pf, normal, offset, min_side=min_side,
                                                             sample_weight=problem.sample_weight))
            return self._outcome(problem, model, "least squares maps (plane held)",
                                 ["plane held fixed; both maps by least squares"])
        try:
            max_search_bounces = int(max_search_bounces)
        except (TypeError, ValueError):
            max_search_bounces = -1
        if max_search_bounces < 100:
            raise FitError(f"max_search_bounces must be an integer of at least 100; got {max_search_bounces!r}",
                           law=law_name(self), option="max_search_bounces")
        notes = ["plane chosen to minimise delta of the whole law (maps by least squares on each side); "
                 "delta is piecewise constant in the plane, so the search is global but heuristic"]
        if self.normal is not None and self.offset is not None:
            start = (np.asarray(self.normal), float(self.offset))
            notes.append("search started from the plane of the law given")
        else:
            try:
                svm = pf_.fit_svm(p0, pf, C=svm_C, min_side=min_side, plane="hyperplane", max_bounces=5000,
                                  seed=problem.seed, sample_weight=problem.sample_weight)
                start = (svm.normal, svm.offset)
            except FitError as exc:
                if exc.option == "svm_C":
                    raise
                start = None
        found = pf_.search_plane(p0, pf, problem.inv_norm, problem.search, start=start, seed=problem.seed,
                                 algorithm=algorithm, local_algorithm=local_algorithm, maxeval=int(maxeval),
                                 min_side=min_side, max_search_bounces=max_search_bounces,
                                 sample_weight=problem.sample_weight)
        normal, offset = pf_.orient_slip_side(p0, slip, found.normal, found.offset)
        model = PiecewiseAffine(**pf_.least_squares_maps(p0, pf, normal, offset, min_side=min_side,
                                                         sample_weight=problem.sample_weight))
        first, last = found.outcomes[0], found.outcomes[-1]
        stop = "; ".join(o.global_stop + (f"; polish: {o.local_stop}" if o.local_stop else "") for o in found.outcomes)
        algo = (f"{first.algorithms[0]} + {first.algorithms[1] or 'no polish'} over the plane; "
                "least squares maps")
        return self._outcome(problem, model, algo, notes + found.notes,
                             n_global=sum(o.n_global for o in found.outcomes),
                             n_local=sum(o.n_local for o in found.outcomes), stop=stop,
                             extras={"search": last})

    @fit_method("svm")
    def _fit_svm(self, problem: FitProblem, *, svm_C: float = 1.0, svm_plane: str = "hyperplane",
                 svm_scaling: str = "standardize", min_side: int = pf_.MIN_SIDE,
                 max_svm_bounces: int = 20_000) -> FitOutcome:
        """The paper's procedure: a linear SVM on the measured slip/roll labels, its plane, least-squares maps.

        Options: ``svm_C`` (box constraint, 1), ``svm_plane`` (``"hyperplane"`` default,
        ``"support_vectors"``, ``"margin_support_vectors"``), ``svm_scaling``
        (``"standardize"`` default, ``"none"`` as MATLAB's fitcsvm), ``min_side`` (8),
        ``max_svm_bounces`` (train on a random subsample above this many bounces; an
        SVM's cost grows faster than the number of bounces). See
        :mod:`bouncelab.laws.plane_fitting` for the readings and the evidence.
        """
        p0, pf = problem.landing, problem.liftoff
        held = self._plane_problem_checks(problem, min_side)
        if held is not None:
            raise FitError("method 'svm' finds the plane; it cannot hold it", law=law_name(self), option="fixed",
                           hints=[Hint("method", "plane", "with fixed=['normal', 'offset']")])
        res = pf_.fit_svm(p0, pf, C=svm_C, min_side=int(min_side), plane=svm_plane, scaling=svm_scaling,
                          max_bounces=int(max_svm_bounces), seed=problem.seed, sample_weight=problem.sample_weight)
        algo = f"SVC(kernel='linear', C={res.svm_C:g}) + least squares"
        stop = "SVM converged" if res.converged else "SVM iteration limit"
        return self._outcome(problem, PiecewiseAffine(**res.parameters), algo, res.notes, stop=stop,
                             extras={"svm_support": res.svm_support, "margin_support": res.margin_support})

    @classmethod
    def published(cls, campaign: str) -> PiecewiseAffine:
        """Eq. (disjointA) for campaign "A" or eq. (disjointB) for "B"."""
        return cls(**_published.piecewise_parameters(campaign))
