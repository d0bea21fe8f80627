"""``bouncelab.fit``: fit a bounce law to bounces."""

from __future__ import annotations

import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.data.campaign import campaign_arrays
from bouncelab.errors import FitError, ParameterError
from bouncelab.fitting import piecewise as pw
from bouncelab.fitting.objective import ErrorMeasure, objective_label, objective_weights
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.search import SearchOutcome, global_search
from bouncelab.laws.base import BounceModel
from bouncelab.laws.piecewise import PiecewiseAffine
from bouncelab.laws.rigid import Rigid
from bouncelab.metrics import error_table, error_terms

__all__ = ["DEFAULT_ALGORITHM", "DEFAULT_LOCAL_ALGORITHM", "fit", "resolve_bounds"]

#: Default global algorithm of the parameter search, chosen by measurement (``benchmarks/bench_algorithms.py``):
#: on 200 random fitting problems (4 laws, 20 to 700 bounces) every global algorithm did well with a
#: Nelder-Mead polish (MLSL 0 misses of the best known minimum, DIRECT_L and CRS2_LM 1, all at 20 bounces)
#: and worse with SBPLX (6-13) or BOBYQA (10-17); DIRECT_L needs no random numbers.
DEFAULT_ALGORITHM = "DIRECT_L"
#: Default local polish (delta has kinks at regime changes, where BOBYQA's quadratic models stall).
DEFAULT_LOCAL_ALGORITHM = "NELDERMEAD"
#: Default global algorithm of the piecewise law's plane search.
DEFAULT_PLANE_ALGORITHM = "CRS2_LM"

_METHODS = {None, "global", "structured", "svm", "plane"}


def default_maxeval(n_free: int, n_bounces: int) -> int:
    """Global-stage budget: 100 evaluations per free parameter, more for small data.

    An evaluation costs time in proportion to the number of bounces, while small
    data sets have the more rugged delta landscapes; below 300 bounces the budget
    grows as 300 / n (at most tenfold), keeping the time per fit roughly constant.
    """
    return int(100 * n_free * min(10.0, max(1.0, 300.0 / max(n_bounces, 1))))


def resolve_bounds(
    cls: type[BounceModel], bounds: Mapping[str, tuple[float, float]] | None
) -> dict[str, tuple[float, float]]:
    """The search box: the law's default bounds updated by ``bounds``, validated.

    Raises
    ------
    ParameterError
        Unknown parameter name, non-finite or reversed bounds, or bounds outside
        the parameter's physical range (e.g. r above 1).
    """
    specs = {s.name: s for s in cls.parameter_specs}
    box = {name: tuple(map(float, s.bounds)) for name, s in specs.items()}
    for name, value in (bounds or {}).items():
        if name not in specs:
            raise ParameterError(f"{cls.__name__} has no parameter {name!r}; its parameters are {list(specs)}")
        try:
            lo, hi = (float(v) for v in value)
        except (TypeError, ValueError):
            raise ParameterError(f"bounds of {name!r} must be a (low, high) pair of numbers; got {value!r}") from None
        plo, phi = specs[name].physical
        if not (np.isfinite(lo) and np.isfinite(hi)):
            raise ParameterError(f"bounds of {name!r} must be finite; got ({lo}, {hi})")
        if lo > hi:
            raise ParameterError(f"bounds of {name!r} are reversed: low {lo} > high {hi}")
        if lo < plo or hi > phi:
            raise ParameterError(
                f"bounds of {name!r} = ({lo}, {hi}) leave its physical range [{plo}, {phi}] "
                f"({specs[name].description})"
            )
        box[name] = (lo, hi)
    return box


def fit(
    model: BounceModel | type[BounceModel],
    data: Any,
    *,
    objective: str | Mapping[str, float] = "delta",
    method: str | None = None,
    seed: int = 0,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    algorithm: str | None = None,
    local_algorithm: str | None = DEFAULT_LOCAL_ALGORITHM,
    maxeval: int | None = None,
    test: Any = None,
    svm_C: float = 1.0,
    svm_plane: str = "support_vectors",
    min_side: int = pw.MIN_SIDE,
    mu_objective: str = "delta",
) -> FitResult:
    """Fit a bounce law to bounces by minimising the paper's error measure.

    Parameters
    ----------
    model
        A :class:`~bouncelab.BounceModel` instance (its parameters, if set, are the
        start of the search) or a law class.
    data
        A campaign Dataset or a ``(landing, liftoff)`` pair of (n, 3) arrays in
        scaled units.
    objective
        ``"delta"`` (eq. error, default), ``"xdot"``, ``"ydot"`` or ``"omega"`` (one
        Delta q of eq. error_individual), or a mapping of weights such as
        ``{"delta": 1, "omega": 0.5}``.
    method
        ``None``/``"global"``: NLopt global search then local polish (any law
        with scalar parameters). ``"structured"``: the paper's two-stage
        procedure for :class:`~bouncelab.Rigid` (r by least squares on ydot,
        then mu with r fixed). For :class:`~bouncelab.PiecewiseAffine`:
        ``None``/``"plane"`` searches the plane minimising delta, ``"svm"`` is
        the paper's SVM procedure.
    seed
        Seed of NLopt's random generator: same seed and data give the same result.
    bounds
        Search box per parameter, name -> (low, high), overriding the law's
        defaults (r in [0, 1], mu in [0, 1.5], beta_deg in [0, 45], k_p in
        [0, 1e-3], e_t in [0, 1]); low == high holds a parameter fixed.
    algorithm, local_algorithm
        NLopt global algorithm (CRS2_LM, ISRES, ESCH, DIRECT_L, MLSL; default
        DIRECT_L, or CRS2_LM for the plane search) and local polish (BOBYQA,
        SBPLX, NELDERMEAD; default NELDERMEAD; None skips it).
    maxeval
        Evaluations of the global stage (default :func:`default_maxeval`: 100 per
        free parameter, up to ten times more below 300 bounces; 3000 for the
        plane search).
    test
        Held-out bounces (a Dataset or pair) on which to report the errors too.
    svm_C
        Regularisation of the SVM (methods "svm" and, for its start, "plane").
    svm_plane
        Method "svm": ``"support_vectors"`` (least-squares plane through the
        support vectors, the paper's words) or ``"hyperplane"`` (the SVM's own
        decision boundary); see :func:`bouncelab.fitting.piecewise.fit_svm`.
    min_side
        Fewest bounces allowed on each side of the piecewise law's plane.
    mu_objective
        Structured method only: choose mu minimising ``"delta"`` (default) or
        the ``"lstsq"`` sum of squared xdot and omega residuals (the paper's
        text allows both readings).

    Returns
    -------
    FitResult
        With the fitted law in ``result.model``; ``print(result)`` gives a report.

    Raises
    ------
    DataError
        Bad data (NaN, a landing with ydot >= 0, shapes...).
    FitError
        Too few bounces, a class too small for its affine map, an unknown
        method, objective or algorithm.
    ParameterError
        Bounds outside the law's physical range, or a start outside the bounds.
    """
    start_time = time.perf_counter()
    law = _as_model(model)
    p0, pf, _ = campaign_arrays(data)
    tst = None if test is None else campaign_arrays(test, name="test")[:2]
    if method not in _METHODS:
        raise FitError(f"unknown method {method!r}; use one of {sorted(m for m in _METHODS if m)}")
    weights = objective_weights(objective)

    if isinstance(law, PiecewiseAffine):
        if method not in (None, "plane", "svm"):
            raise FitError(f"PiecewiseAffine is fitted with method 'plane' (default) or 'svm'; got {method!r}")
        if not np.array_equal(weights, objective_weights("delta")):
            raise FitError("the piecewise-affine fit minimises delta; other objectives are not offered for it")
        if len(p0) < 2 * min_side:
            raise FitError(f"{len(p0)} bounces are too few for a piecewise-affine law (need {2 * min_side})")
        return _fit_piecewise(law, p0, pf, tst, method or "plane", seed, algorithm, local_algorithm, maxeval,
                              svm_C, svm_plane, min_side, start_time)
    if method in ("svm", "plane"):
        raise FitError(f"method {method!r} is for PiecewiseAffine, not {type(law).__name__}")
    if method == "structured" and type(law) is not Rigid:
        raise FitError(f"the structured procedure is the paper's for Rigid; {type(law).__name__} uses 'global'")
    if not law.parameter_specs:
        raise FitError(f"{type(law).__name__} declares no parameter_specs, so there is nothing to search")
    box = resolve_bounds(type(law), bounds)
    n_free = sum(hi > lo for lo, hi in box.values())
    if len(p0) <= n_free:
        raise FitError(
            f"{len(p0)} bounce(s) are too few to fit {n_free} parameter(s) of {type(law).__name__}; "
            f"need at least {n_free + 1}"
        )
    if method == "structured":
        return _fit_structured(law, p0, pf, tst, box, weights, seed, mu_objective, start_time)
    return _fit_global(law, p0, pf, tst, box, weights, seed, algorithm or DEFAULT_ALGORITHM, local_algorithm,
                       maxeval, start_time)


def _as_model(model: Any) -> BounceModel:
    if isinstance(model, type) and issubclass(model, BounceModel):
        return model()
    if isinstance(model, BounceModel):
        return model
    raise FitError(f"model must be a BounceModel instance or class; got {type(model).__name__}")


# ------------------------------------------------------------------------- rigid family: global
class _Box:
    """Map between a law's parameter vector and the unit box of its free parameters."""

    def __init__(self, law: BounceModel, box: dict[str, tuple[float, float]]) -> None:
        names = [s.name for s in law.parameter_specs]
        self.names = names
        self.lo = np.array([box[n][0] for n in names])
        self.hi = np.array([box[n][1] for n in names])
        self.free = self.hi > self.lo
        start = np.where(self.free, 0.5 * (self.lo + self.hi), self.lo)
        given = law.parameters
        for i, n in enumerate(names):
            if given[n] is None:
                continue
            if not self.lo[i] <= given[n] <= self.hi[i]:
                raise ParameterError(
                    f"start value {n}={given[n]} lies outside the bounds [{self.lo[i]}, {self.hi[i]}]"
                )
            if self.free[i]:
                start[i] = given[n]
        self.start = start
        self._idx = np.flatnonzero(self.free)
        self._lo_free = self.lo[self.free]
        self._span_free = (self.hi - self.lo)[self.free]

    def theta(self, u: np.ndarray) -> np.ndarray:
        t = self.start.copy()
        t[self._idx] = self._lo_free + u * self._span_free
        return t

    def unit(self, theta: np.ndarray) -> np.ndarray:
        return ((theta - self.lo) / np.where(self.free, self.hi - self.lo, 1.0))[self.free]


def _fit_global(law, p0, pf, tst, box, weights, seed, algorithm, local_algorithm, maxeval, start_time):
    b = _Box(law, box)
    measure = ErrorMeasure(law, p0, pf)
    f = measure.unit_function(b.start, b.lo, b.hi - b.lo, b.free.astype(np.float64), weights)

    d = int(b.free.sum())
    if d == 0:
        outcome = SearchOutcome(x=np.empty(0), fun=f(np.empty(0)), global_stop="all parameters fixed")
    else:
        outcome = global_search(
            f, b.unit(b.start), algorithm=algorithm, local_algorithm=local_algorithm, seed=seed,
            maxeval=maxeval if maxeval is not None else default_maxeval(d, len(p0)),
        )
    theta = b.theta(outcome.x)
    fitted = law.replace(**dict(zip(b.names, (float(v) for v in theta), strict=True)))
    at_bounds, flat = _diagnose(f, outcome.x, b)
    notes = _notes(fitted, at_bounds, flat, box)
    return _result(
        fitted, "global", weights, float(f(outcome.x)), p0, pf, tst, box, at_bounds, flat, outcome,
        f"{outcome.algorithms[0]} + {outcome.algorithms[1] or 'no polish'}", seed, notes, start_time,
    )


def _diagnose(f, x: np.ndarray, b: _Box) -> tuple[dict[str, str], dict[str, tuple[float, float]]]:
    """Parameters on a bound, and the range over which each flat parameter leaves the objective unchanged.

    A parameter is flat when moving it by 1 % of its box width either way changes the objective by
    less than 1e-9 of its value; its range is then found by bisection in each direction.
    """
    free_idx = np.flatnonzero(b.free)
    at, flat = {}, {}
    f0 = f(x)
    tol = 1e-9 * max(abs(f0), 1e-12)

    def same(i: int, value: float) -> bool:
        y = x.copy()
        y[i] = value
        return abs(f(y) - f0) <= tol

    for i, k in enumerate(free_idx):
        name = b.names[k]
        if x[i] <= 1e-6:
            at[name] = "lower"
        elif x[i] >= 1 - 1e-6:
            at[name] = "upper"
        steps = [v for v in (x[i] - 0.01, x[i] + 0.01) if 0.0 <= v <= 1.0]
        if not steps or not all(same(i, v) for v in steps):
            continue
        ends = []
        for end in (0.0, 1.0):
            if same(i, end):
                ends.append(end)
                continue
            inside, outside = x[i], end
            for _ in range(30):
                mid = 0.5 * (inside + outside)
                inside, outside = (mid, outside) if same(i, mid) else (inside, mid)
            ends.append(inside)
        lo, span = b.lo[k], b.hi[k] - b.lo[k]
        flat[name] = (float(lo + ends[0] * span), float(lo + ends[1] * span))
    return at, flat


def _notes(fitted: BounceModel, at_bounds: dict[str, str], flat: dict[str, tuple[float, float]], box) -> list[str]:
    notes = []
    for name, side in at_bounds.items():
        if name in flat:
            continue
        lo, hi = box[name]
        notes.append(
            f"{name} ended on its {side} bound ({lo if side == 'lower' else hi:g}); the best value may lie "
            f"outside the search box - widen it with bounds={{'{name}': (low, high)}} if that is physical"
        )
    for name, (lo, hi) in flat.items():
        why = ""
        if name == "mu":
            why = " (friction this high makes every bounce grip, so any larger mu predicts the same)"
        notes.append(
            f"the objective is the same for every {name} in [{lo:.6g}, {hi:.6g}]{why}: the data do not determine "
            f"{name} within that range, and the reported value is one point of it"
        )
    return notes


# ---------------------------------------------------------------------- rigid: paper's procedure
def _fit_structured(law, p0, pf, tst, box, weights, seed, mu_objective, start_time):
    if mu_objective not in ("delta", "lstsq"):
        raise FitError(f"mu_objective must be 'delta' or 'lstsq'; got {mu_objective!r}")
    r_lo, r_hi = box["r"]
    mu_lo, mu_hi = box["mu"]
    # Step 1: ydotF = -r ydot0 by least squares.
    r = float(np.clip(-(pf[:, 1] @ p0[:, 1]) / (p0[:, 1] @ p0[:, 1]), r_lo, r_hi))
    # Step 2: mu with r fixed, minimising delta (or the squared xdot and omega residuals).
    measure = ErrorMeasure(law, p0, pf)
    b = _Box(law.replace(r=r, mu=None), {**box, "r": (r, r)})
    by_delta = measure.unit_function(b.start, b.lo, b.hi - b.lo, b.free.astype(np.float64), weights)

    def f(u: np.ndarray) -> float:
        if mu_objective == "delta":
            return by_delta(u)
        res = (pf - law._predict(p0, b.theta(u)))[:, [0, 2]]
        return float((res * res).sum())

    if mu_hi > mu_lo:
        outcome = global_search(f, np.array([0.5]), algorithm=DEFAULT_ALGORITHM, local_algorithm="NELDERMEAD",
                                seed=seed, maxeval=200)
    else:
        outcome = SearchOutcome(x=np.empty(0), fun=f(np.empty(0)), global_stop="mu fixed")
    fitted = law.replace(**dict(zip(b.names, b.theta(outcome.x).tolist(), strict=True)))
    at_bounds, flat = _diagnose(by_delta, outcome.x, b)
    if r in (r_lo, r_hi) and r_lo < r_hi:
        at_bounds["r"] = "lower" if r == r_lo else "upper"
    notes = [f"r = {r:.6g} from least squares on ydot; mu chosen with r fixed, minimising {mu_objective}"]
    notes += _notes(fitted, at_bounds, flat, box)
    value = float(by_delta(outcome.x))
    return _result(fitted, "structured", weights, value, p0, pf, tst, box, at_bounds, flat, outcome,
                   f"least squares + {outcome.algorithms[0] or 'none'}", seed, notes, start_time)


# ---------------------------------------------------------------------------- piecewise affine
def _fit_piecewise(law, p0, pf, tst, method, seed, algorithm, local_algorithm, maxeval, svm_C, svm_plane, min_side,
                   start_time):
    if method == "svm":
        res = pw.fit_svm(p0, pf, C=svm_C, min_side=min_side, plane=svm_plane)
        outcome = SearchOutcome(x=np.empty(0), fun=np.nan, global_stop="SVM converged")
        algo = f"SVC(kernel='linear', C={svm_C:g}) + least squares"
        notes = [f"plane through {len(res.svm_support)} support vectors by least squares (the paper's procedure)"
                 if svm_plane == "support_vectors" else
                 f"plane = the SVM's decision boundary ({len(res.svm_support)} support vectors)"]
    else:
        res = pw.fit_plane_search(
            p0, pf, seed=seed, algorithm=algorithm or DEFAULT_PLANE_ALGORITHM,
            local_algorithm=local_algorithm, maxeval=maxeval or 3000, svm_C=svm_C, min_side=min_side,
        )
        outcome = res.search
        algo = f"{outcome.algorithms[0]} + {outcome.algorithms[1] or 'no polish'} over the plane; least squares maps"
        notes = [
            "plane chosen to minimise delta of the whole law (maps by least squares on each side); "
            "delta is piecewise constant in the plane, so the search is global but heuristic"
        ]
    fitted = res.model
    measure_delta = float(error_table(p0, pf, fitted.predict(p0)).loc["all", "delta"])
    result = _result(fitted, method, objective_weights("delta"), measure_delta, p0, pf, tst, {}, {}, {}, outcome,
                     algo, seed, notes, start_time)
    result.mismatched = pw.mismatched_fraction(fitted, p0, pf)
    if tst is not None:
        result.test_mismatched = pw.mismatched_fraction(fitted, *tst)
    return result


# --------------------------------------------------------------------------------- assembling
def _result(fitted, method, weights, value, p0, pf, tst, box, at_bounds, flat, outcome, algo, seed, notes,
            start_time) -> FitResult:
    def overall(landing: np.ndarray, liftoff: np.ndarray) -> np.ndarray:
        return error_terms(landing, liftoff, fitted.predict(landing)).mean(axis=0)

    train = overall(p0, pf)
    test = None if tst is None else overall(*tst)
    stop = outcome.global_stop + (f"; polish: {outcome.local_stop}" if outcome.local_stop else "")
    return FitResult(
        model=fitted,
        method=method,
        objective=objective_label(weights),
        objective_value=value,
        delta=float(train[0]),
        delta_q=train[1:],
        data={"train": (p0, pf), **({} if tst is None else {"test": tst})},
        n_train=len(p0),
        test_delta=None if test is None else float(test[0]),
        test_delta_q=None if test is None else test[1:],
        n_test=0 if tst is None else len(tst[0]),
        bounds=dict(box),
        at_bounds=at_bounds,
        insensitive=flat,
        n_evaluations=outcome.n_global + outcome.n_local,
        n_global=outcome.n_global,
        n_local=outcome.n_local,
        elapsed=time.perf_counter() - start_time,
        stop_reason=stop,
        algorithm=algo,
        seed=seed,
        notes=notes,
    )
