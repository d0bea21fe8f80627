"""The fitting problem handed to a law's fitting method, and the generic global method.

:func:`bouncelab.fit` validates the data and options once and builds a
:class:`Problem` (the :class:`~bouncelab.laws.FitProblem` protocol): the
bounces, the search box, the held parameters, and the services a method needs
(the objective through the law's one hook, NLopt's search, and the generic
``"global"`` method, which a law's own method may reuse).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from bouncelab.core import checks
from bouncelab.core.errors import Code, FitError, Hint, ParameterError
from bouncelab.core.validation import inverse_norms
from bouncelab.fitting.search import SearchOutcome, global_search
from bouncelab.fitting.vector import ParameterVector
from bouncelab.laws.base import BounceModel
from bouncelab.laws.protocol import DEFAULT_LOCAL_ALGORITHM, FitOutcome
from bouncelab.laws.registry import law_name

__all__ = ["DEFAULT_ALGORITHM", "Problem", "default_maxeval", "resolve_bounds", "resolve_fixed"]

#: Default global algorithm of the parameter search, chosen by measurement (``benchmarks/bench_algorithms.py``):
#: on 200 random fitting problems (4 laws, 20 to 700 bounces) every global algorithm did well with a
#: Nelder-Mead polish (MLSL 0 misses of the best known minimum, DIRECT_L and CRS2_LM 1, all at 20 bounces)
#: and worse with SBPLX (6-13) or BOBYQA (10-17); DIRECT_L needs no random numbers.
DEFAULT_ALGORITHM = "DIRECT_L"


def default_maxeval(n_free: int, n_bounces: int) -> int:
    """Global-stage budget: 100 evaluations per free parameter, more for small data.

    An evaluation costs time in proportion to the number of bounces, while small
    data sets have the more rugged delta landscapes; below 300 bounces the budget
    grows as 300 / n (at most tenfold), keeping the time per fit roughly constant.
    """
    return int(100 * n_free * min(10.0, max(1.0, 300.0 / max(n_bounces, 1))))


def resolve_bounds(cls: type[BounceModel], bounds: Mapping[str, Any] | None) -> dict[str, tuple[Any, Any]]:
    """The search box: the law's default bounds updated by ``bounds``, validated.

    For an array parameter ``low`` and ``high`` are numbers (every element) or
    arrays of its shape; the result holds flat arrays for array parameters.

    Raises
    ------
    ParameterError
        Unknown parameter name, non-finite or reversed bounds, or bounds outside
        the parameter's physical range (e.g. r above 1).
    """
    specs = {s.name: s for s in cls.parameter_specs}
    if bounds is not None and not isinstance(bounds, Mapping):
        raise ParameterError(f"bounds must be a mapping name -> (low, high); got {type(bounds).__name__}",
                             law=law_name(cls), parameter="bounds", value=bounds)
    box: dict[str, tuple[Any, Any]] = {}
    for name, spec in specs.items():
        lo, hi = spec.bound_arrays()
        box[name] = (float(lo[0]), float(hi[0])) if spec.is_scalar else (lo, hi)
    for name, value in (bounds or {}).items():
        if name not in specs:
            raise ParameterError(f"{law_name(cls)} has no parameter {name!r}; its parameters are {list(specs)}",
                                 law=law_name(cls), parameter=name)
        spec = specs[name]
        if isinstance(value, str | bytes):
            raise ParameterError(f"bounds of {name!r} must be a (low, high) pair of numbers; got {value!r}",
                                 law=law_name(cls), parameter=name, value=value)
        try:
            lo, hi = spec.replace(bounds=tuple(value)).bound_arrays()
        except (ParameterError, TypeError, ValueError):
            raise ParameterError(f"bounds of {name!r} must be a (low, high) pair of numbers; got {value!r}",
                                 law=law_name(cls), parameter=name, value=value) from None
        plo, phi = spec.physical_arrays()
        if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
            raise ParameterError(f"bounds of {name!r} must be finite; got ({value[0]}, {value[1]})",
                                 law=law_name(cls), parameter=name, value=value)
        if (lo > hi).any():
            raise ParameterError(f"bounds of {name!r} are reversed: low {value[0]} > high {value[1]}",
                                 law=law_name(cls), parameter=name, value=value)
        if (lo < plo).any() or (hi > phi).any():
            raise ParameterError(
                f"bounds of {name!r} = ({value[0]}, {value[1]}) leave its physical range [{plo.min():g}, "
                f"{phi.max():g}] ({spec.description})", law=law_name(cls), parameter=name, value=value
            )
        box[name] = (float(lo[0]), float(hi[0])) if spec.is_scalar else (lo, hi)
    return box


def resolve_fixed(law: BounceModel, fixed: Any, free: Any) -> dict[str, Any]:
    """Parameters held in a fit, name -> value.

    ``fixed`` is a mapping name -> value, or names held at the law's own values;
    parameters declared ``vary=False`` are held too unless named in ``free``.
    """
    specs = {s.name: s for s in law.parameter_specs}
    name_of = law_name(law)

    def names(arg: Any, what: str) -> list[str]:
        if arg is None:
            return []
        if isinstance(arg, str):
            arg = [arg]
        try:
            out = list(arg)
        except TypeError:
            raise FitError(f"{what} must be parameter names or a mapping name -> value; got {arg!r}", law=name_of,
                           option=what) from None
        unknown = [n for n in out if n not in specs]
        if unknown:
            raise ParameterError(f"{name_of} has no parameter(s) {unknown}; its parameters are {list(specs)}",
                                 law=name_of, parameter=unknown[0])
        return out

    held: dict[str, Any] = {}
    freed = set(names(free, "free"))
    explicit = names(list(fixed) if isinstance(fixed, Mapping) else fixed, "fixed")
    both = freed & set(explicit)
    if both:
        raise FitError(f"parameter(s) {sorted(both)} are both fixed and free", law=name_of, option="free")
    for spec in law.parameter_specs:
        if not spec.vary and spec.name not in freed:
            held[spec.name] = None
    for name in explicit:
        held[name] = specs[name].check(fixed[name], name_of) if isinstance(fixed, Mapping) else None
    for name, value in held.items():
        if value is None:
            own = getattr(law, name)
            if own is None:
                raise FitError(f"{name_of} parameter {name!r} is held in this fit but has no value (give one in the "
                               "law or here)", law=name_of, option="fixed",
                               hints=[Hint("fixed", {name: Code("value")})])
            held[name] = own
    return held


class Problem:
    """What a law's fitting method receives (implements :class:`bouncelab.laws.FitProblem`)."""

    def __init__(self, law: BounceModel, landing: np.ndarray, liftoff: np.ndarray, *, setting: Any,
                 weights: np.ndarray, seed: int, box: dict[str, tuple[Any, Any]], fixed: dict[str, Any],
                 test: tuple[np.ndarray, np.ndarray] | None, bounce_weights: np.ndarray | None = None,
                 sample_weight: np.ndarray | None = None) -> None:
        self.law = law
        self.landing = landing
        self.liftoff = liftoff
        # Each bounce's weight in the objective: 1 / ||p0|| (delta), or 1 / h from prediction intervals,
        # times the user's sample weight (mean 1, so the objective stays a weighted mean).
        self.inv_norm = inverse_norms(landing) if bounce_weights is None else bounce_weights
        if sample_weight is not None:
            self.inv_norm = np.ascontiguousarray(self.inv_norm * sample_weight)
        self.sample_weight = sample_weight
        self.setting = setting
        self.n = len(landing)
        self.weights = np.asarray(weights, dtype=np.float64)
        self.seed = seed
        self.box = box
        self.fixed = fixed
        self.test = test

    # ------------------------------------------------------------------ services
    def value(self, law: BounceModel) -> float:
        """The objective (the weighted mean error, delta by default) of ``law`` on the bounces fitted."""
        vec = ParameterVector(law)
        return float(self.objective(law)(vec.of(law)))

    def objective(self, law: BounceModel) -> Callable[[np.ndarray], float]:
        """The objective as a function of the law's flat parameter vector (:class:`ParameterVector`), for
        the fitting machinery: a fitting method asks for :meth:`value` or :meth:`run_global` instead."""
        error_sums = law._error_function(self.landing, self.liftoff, self.inv_norm)
        vector = ParameterVector(law)
        # With scalar parameters only, the flat vector already is the values in declaration order: no
        # conversion in the search's inner loop (thousands of calls).
        sums = error_sums if vector.scalar else (lambda theta: error_sums(vector.values(theta)))
        w = self.weights / self.n
        if w[1] == w[2] == w[3] == 0.0:
            w0 = float(w[0])
            return lambda theta: w0 * sums(theta)[0]
        w0, w1, w2, w3 = (float(v) for v in w)

        def f(theta: np.ndarray) -> float:
            s = sums(theta)
            return w0 * s[0] + w1 * s[1] + w2 * s[2] + w3 * s[3]

        return f

    def search(self, f: Callable[[np.ndarray], float], x0: np.ndarray, **options: Any) -> SearchOutcome:
        """NLopt global search and local polish of ``f`` over ``[0, 1]^d`` (see :func:`global_search`)."""
        options.setdefault("seed", self.seed)
        return global_search(f, x0, **options)

    def run_global(self, law: BounceModel, *, algorithm: str | None = None,
                   local_algorithm: str | None = DEFAULT_LOCAL_ALGORITHM, maxeval: int | None = None,
                   hold: Mapping[str, Any] | None = None,
                   criterion: Callable[..., float] | None = None) -> FitOutcome:
        """The generic method: NLopt global search then a polish over the free parameters of ``law``.

        ``hold`` holds further parameters (name -> value) in this call only;
        ``criterion`` replaces the objective in the search: a function of the law's parameters by
        keyword, ``criterion(r=..., mu=...) -> float``; diagnostics and the reported value use the objective.
        """
        space = _Space(law, self.box, {**(hold or {}), **self.fixed})  # the caller's fixed values win
        if self.n <= space.d:
            raise FitError(
                f"{self.n} bounce(s) are too few to fit {space.d} parameter(s) of {law_name(law)}; "
                f"need at least {space.d + 1}", law=law_name(law)
            )
        if maxeval is not None:  # (NLopt counts evaluations in a C int)
            try:
                maxeval = checks.count(maxeval, "maxeval", 1, maximum=2**31 - 1, error=FitError)
            except FitError as exc:
                raise FitError(exc.message, law=law_name(law), option="maxeval") from None
        obj = self.objective(law)
        f = space.unit_function(obj)
        if criterion is None:
            g = f
        else:
            named = space.vector.named
            g = space.unit_function(lambda theta: float(criterion(**named(theta))))
        if space.d == 0:
            outcome = SearchOutcome(x=np.empty(0), fun=float(f(np.empty(0))), global_stop="all parameters fixed")
        else:
            outcome = self.search(
                g, space.unit(space.start), algorithm=algorithm or DEFAULT_ALGORITHM, local_algorithm=local_algorithm,
                maxeval=maxeval if maxeval is not None else default_maxeval(space.d, self.n),
            )
        theta = space.theta(outcome.x)
        fitted = space.vector.law(law, theta)
        at_bounds, flat = space.diagnose(f, outcome.x)
        notes = _notes(at_bounds, flat, space)
        stop = outcome.global_stop + (f"; polish: {outcome.local_stop}" if outcome.local_stop else "")
        algo = (f"{outcome.algorithms[0]} + {outcome.algorithms[1] or 'no polish'}" if space.d
                else "none (all parameters held)")
        return FitOutcome(model=fitted, objective_value=float(f(outcome.x)), algorithm=algo,
                          n_global=outcome.n_global, n_local=outcome.n_local, stop_reason=stop,
                          at_bounds=at_bounds, insensitive=flat, notes=notes)


class _Space:
    """Map between a law's flat parameter vector and the unit box of its free numbers."""

    def __init__(self, law: BounceModel, box: dict[str, tuple[Any, Any]], held: Mapping[str, Any]) -> None:
        self.vector = ParameterVector(law)
        names, lo, hi, start, free = [], [], [], [], []
        for spec in self.vector.specs:
            blo, bhi = (np.broadcast_to(np.asarray(b, dtype=np.float64), (spec.size,)) for b in box[spec.name])
            enames = spec.element_names()
            if spec.name in held:
                value = np.ravel(np.asarray(held[spec.name], dtype=np.float64))
                names += enames
                lo.append(value)
                hi.append(value)
                start.append(value)
                free.append(np.zeros(spec.size, bool))
                continue
            own = getattr(law, spec.name)
            s = np.where(bhi > blo, 0.5 * (blo + bhi), blo)
            if own is not None:
                v = np.ravel(np.asarray(own, dtype=np.float64))
                outside = (v < blo) | (v > bhi)
                if outside.any():
                    i = int(np.argmax(outside))
                    raise ParameterError(
                        f"start value {enames[i]}={v[i]} lies outside the bounds [{blo[i]}, {bhi[i]}]",
                        law=law_name(law), parameter=enames[i], value=float(v[i])
                    )
                s = np.where(bhi > blo, v, blo)
            names += enames
            lo.append(blo)
            hi.append(bhi)
            start.append(s)
            free.append(bhi > blo)
        self.names = names
        self.lo = np.concatenate(lo) if lo else np.empty(0)
        self.hi = np.concatenate(hi) if hi else np.empty(0)
        self.start = np.ascontiguousarray(np.concatenate(start)) if start else np.empty(0)
        self.free = np.concatenate(free) if free else np.empty(0, bool)
        self.idx = np.flatnonzero(self.free)
        self.d = len(self.idx)
        self._lo_f = self.lo[self.free]
        self._span_f = (self.hi - self.lo)[self.free]

    def theta(self, u: np.ndarray) -> np.ndarray:
        t = self.start.copy()
        t[self.idx] = self._lo_f + u * self._span_f
        return t

    def unit(self, theta: np.ndarray) -> np.ndarray:
        return ((theta - self.lo) / np.where(self.free, self.hi - self.lo, 1.0))[self.free]

    def unit_function(self, obj: Callable[[np.ndarray], float]) -> Callable[[np.ndarray], float]:
        """``obj`` of the unit-box point of the free numbers (the search's objective)."""
        lo, span = self._lo_f, self._span_f
        if self.d == len(self.start):  # every number free: theta is an affine image of u
            return lambda u: obj(lo + u * span)
        base, idx = self.start, self.idx

        def f(u: np.ndarray) -> float:
            t = base.copy()
            t[idx] = lo + u * span
            return obj(t)

        return f

    def diagnose(self, f: Callable[[np.ndarray], float], x: np.ndarray):
        """Numbers on a bound, and the range over which each flat number leaves the objective unchanged.

        A number is flat when moving it by 1 % of its box width either way changes the objective by
        less than 1e-9 of its value; its range is then found by bisection in each direction.
        """
        at, flat = {}, {}
        f0 = f(x)
        tol = 1e-9 * max(abs(f0), 1e-12)

        def same(i: int, value: float) -> bool:
            y = x.copy()
            y[i] = value
            return abs(f(y) - f0) <= tol

        if self.d > 12:  # a many-dimensional generic search: skip the per-number probing (costly)
            return at, flat
        for i, k in enumerate(self.idx):
            name = self.names[k]
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
            lo, span = self.lo[k], self.hi[k] - self.lo[k]
            flat[name] = (float(lo + ends[0] * span), float(lo + ends[1] * span))
        return at, flat


def _notes(at_bounds: dict[str, str], flat: dict[str, tuple[float, float]], space: _Space) -> list[str]:
    notes = []
    where = {n: i for i, n in enumerate(space.names)}
    for name, side in at_bounds.items():
        if name in flat:
            continue
        k = where[name]
        bound = space.lo[k] if side == "lower" else space.hi[k]
        notes.append(
            f"{name} ended on its {side} bound ({bound:g}); the best value may lie outside the search box - widen "
            f"it with bounds={{'{name}': (low, high)}} if that is physical"
        )
    for name, (lo, hi) in flat.items():
        notes.append(
            f"the objective is the same for every {name} in [{lo:.6g}, {hi:.6g}]: the data do not determine "
            f"{name} within that range, and the reported value is one point of it"
        )
    return notes
