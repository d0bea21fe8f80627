"""``bouncelab.fit``: fit a bounce law to bounces, by the law's own or the generic fitting method."""

from __future__ import annotations

import inspect
import time
from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import checks
from bouncelab.core.errors import Code, FitError, Hint, ParameterError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, check_scaled
from bouncelab.data.campaign import synthetic_warning
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.objective import (
    bounce_weights,
    mean_one,
    objective_label,
    objective_weighting,
    objective_weights,
    sample_weights,
)
from bouncelab.fitting.problem import (
    DEFAULT_ALGORITHM,
    Problem,
    default_maxeval,
    resolve_bounds,
    resolve_fixed,
)
from bouncelab.fitting.result import FitResult
from bouncelab.laws import FitOutcome, law_class, law_name, registered_laws
from bouncelab.laws.base import BounceModel
from bouncelab.laws.protocol import DEFAULT_LOCAL_ALGORITHM
from bouncelab.laws.provenance import Provenance
from bouncelab.metrics import error_terms

__all__ = ["DEFAULT_ALGORITHM", "DEFAULT_LOCAL_ALGORITHM", "default_maxeval", "fit", "law_instance", "resolve_bounds"]

#: Largest seed accepted (NLopt and NumPy take it as an unsigned 64-bit number).
SEED_MAX = checks.SEED_MAX


def fit(
    model: BounceModel | type[BounceModel] | str,
    data: Any,
    *,
    method: str | None = None,
    objective: str | Mapping[str, float] = "delta",
    seed: int = 0,
    bounds: Mapping[str, Any] | None = None,
    fixed: Any = None,
    free: Any = None,
    test: Any = None,
    plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
    sample_weight: Any = None,
    **method_options: Any,
) -> FitResult:
    """Fit a bounce law to bounces by minimising the paper's error measure.

    Parameters
    ----------
    model
        A law instance (its parameters, if set, are the start of the search), a law class,
        or a registered law name in any case (``"Rigid"``, ``"turfcontact"``, ``"module:Class"``).
    data
        A campaign Dataset or a ``(landing, liftoff)`` pair of (n, 3) arrays in
        scaled units.
    method
        A fitting method of the law (``type(law).fit_methods()``): ``"global"``
        for every law (NLopt global search then a local polish), plus the law's own,
        e.g. ``"structured"`` for :class:`~bouncelab.Rigid` and ``"plane"`` /
        ``"svm"`` for :class:`~bouncelab.PiecewiseAffine`. Default: the law's
        ``default_fit_method``.
    objective
        ``"delta"`` (eq. error, default), ``"xdot"``, ``"ydot"`` or ``"omega"`` (one
        Delta q of eq. error_individual), or a mapping of weights such as
        ``{"delta": 1, "omega": 0.5}``. ``"delta_pi"`` (or ``"weighting": "pi"`` in a
        mapping) weights each bounce by its prediction intervals instead of its
        landing speed (:mod:`bouncelab.fitting.objective`); the data must carry them.
    seed
        Seed for anything random (a non-negative integer): same seed and data give the same result.
    bounds
        Search box per parameter, name -> (low, high), overriding the law's
        defaults (for arrays, numbers or arrays of the parameter's shape); low ==
        high holds a parameter at that value.
    fixed
        Parameters held in the fit: names (held at the law's own values) or a
        mapping name -> value. Parameters declared ``vary=False`` are held too.
    free
        Names of parameters declared ``vary=False`` to fit all the same.
    test
        Held-out bounces (a Dataset or pair), on which the errors and the law's
        diagnostics are reported too. They must not be among the fitted bounces.
    plausible
        The unit guard of bare arrays (a campaign Dataset was checked when it was made or
        loaded): ``(landing, liftoff)`` values that only a unit mistake makes (m/s or rpm given
        as radii/s or rad/s) are refused as by :func:`~bouncelab.data.campaign.make_campaign`.
        Default :data:`~bouncelab.core.plausibility.PLAUSIBLE_RANGES`; widen them on purpose
        (``PLAUSIBLE_RANGES.widened(max_spin=...)``) or pass ``None`` to check nothing.
    sample_weight
        One non-negative weight per bounce; only their ratios matter (they are scaled to mean 1).
        Each bounce's term of the objective is multiplied by it, and so is its row in any other
        stage of the method (the least squares of r and mu in Rigid's ``"structured"``; the
        affine maps, the SVM and its standardisation in PiecewiseAffine's ``"plane"`` and
        ``"svm"``; an SVM's ``C`` applies to a bounce of average weight). A bounce of weight 0 is
        left out, as if not given. Default None: all bounces alike, as in the paper. The reported
        ``delta`` and ``Delta q`` stay the paper's unweighted means over the fitted bounces;
        ``objective_value`` is weighted.
    **method_options
        Options of the method, its keyword-only arguments, e.g. ``algorithm``,
        ``local_algorithm``, ``maxeval`` (``"global"``), ``mu_objective``
        (``"structured"``), ``svm_C``, ``svm_plane``, ``min_side`` (piecewise).

    Returns
    -------
    FitResult
        With the fitted law in ``result.model``; ``print(result)`` gives a report. The law carries
        what it was fitted to (``result.model.provenance``: the campaign, synthetic or measured,
        the generator of synthetic bounces, the landing ranges fitted), which its law file keeps.

    Raises
    ------
    DataError
        Bad data (NaN, a landing with ydot >= 0, shapes...), a bad ``sample_weight`` (row
        named), bare arrays implausible in scaled units (naming the column, the unit they look like and how to convert).
    FitError
        Too few bounces, an unknown method or option, a bad objective, seed or
        algorithm, held-out bounces that were fitted too.
    ParameterError
        Bounds outside the law's physical range, a start outside the bounds, an
        unknown parameter name.
    LawDefinitionError
        The law is written wrongly (no ``_predict``, or one returning anything but an (n, 3)
        array), naming the class, the method and the shape.
    """
    start_time = time.perf_counter()
    law = law_instance(model)
    seed = check_seed(seed)
    p0, pf, setting = campaign_arrays(data)
    tst = None if test is None else campaign_arrays(test, name="test")[:2]
    for given, states in ((data, (p0, pf)), (test, tst)):
        if given is not None and not isinstance(given, xr.Dataset):
            check_scaled(*states, ranges=plausible)
    if tst is not None:
        _check_held_out(p0, pf, *tst)
    weights = objective_weights(objective)
    weighting = objective_weighting(objective)
    per_bounce = bounce_weights(data, p0) if weighting == "pi" else None
    user_weights = sample_weights(sample_weight, len(p0))
    dropped = 0
    if user_weights is not None:
        keep = user_weights > 0  # a weight of zero leaves the bounce out, as if it were not given
        dropped = int((~keep).sum())
        if dropped:
            p0, pf, user_weights = p0[keep], pf[keep], user_weights[keep]
            setting = None if setting is None else setting[keep]
            per_bounce = None if per_bounce is None else per_bounce[keep]
        user_weights = mean_one(user_weights)
    name, func = _method(law, method)
    _check_options(law, name, func, method_options)
    if not law.parameter_specs:
        raise FitError(f"{law_name(law)} declares no parameter_specs, so there is nothing to fit", law=law_name(law))
    box = resolve_bounds(type(law), bounds)
    held = resolve_fixed(law, fixed, free)
    problem = Problem(law, p0, pf, setting=setting, weights=weights, seed=seed, box=box, fixed=held, test=tst,
                      bounce_weights=per_bounce, sample_weight=user_weights)
    outcome = func(law, problem, **method_options)
    if not isinstance(outcome, FitOutcome) or type(outcome.model) is not type(law):
        raise FitError(f"fitting method {name!r} of {law_name(law)} returned {type(outcome).__name__}, "
                       f"not a FitOutcome holding a {type(law).__name__}", law=law_name(law), option="method")
    _check_contract(outcome.model, name, box, held, explicit_bounds=set(bounds or {}))
    label = objective_label(weights, weighting) + ("" if user_weights is None else ", sample-weighted")
    # what the law was fitted to travels with it (law.provenance, law files), beside its value
    outcome.model = outcome.model._with_provenance(
        Provenance.of_fit(data, problem.landing, method=name, objective=label, seed=seed))
    result = _result(outcome, name, label, problem, box, held, seed, start_time)
    if dropped:
        result.notes.append(f"{dropped} bounce(s) with sample_weight 0 left out: {problem.n} fitted")
    note = synthetic_warning(data)  # a report read on its own must not pass for a fit to measurements
    if note is not None:
        result.notes.append(note)
    return result


def check_seed(seed: Any) -> int:
    """``seed`` as an int in [0, 2**63), or FitError (:func:`bouncelab.core.checks.seed`)."""
    return checks.seed(seed, "seed", error=FitError)


def check_count(value: Any, name: str, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int of at least ``minimum`` (and at most ``maximum``: a count option such as ``k`` or
    ``walkers``), or FitError (:func:`bouncelab.core.checks.count`)."""
    return checks.count(value, name, minimum, maximum=maximum, error=FitError)


def check_fraction(value: Any, name: str) -> float:
    """``value`` as a float in (0, 1) (a level or a share), or FitError (:func:`bouncelab.core.checks.fraction`)."""
    return checks.fraction(value, name, error=FitError)


def refuse_sample_weight(fit_kwargs: Mapping[str, Any], where: str,
                         why: str = "it splits or resamples the bounces and the weights would not follow them") -> None:
    """FitError if ``sample_weight`` is among the fit options of a function that cannot honour it."""
    if "sample_weight" in fit_kwargs:
        raise FitError(f"{where} takes no sample_weight: {why}; fit with bouncelab.fit(..., sample_weight=...), "
                       "or use bouncelab.BounceRegressor with scikit-learn's cross-validation, which splits the "
                       "weights with the bounces", option="sample_weight")


def law_instance(law: Any) -> BounceModel:
    """A law to fit from a registered name (any case: "turfcontact" is TurfContact), a class or an instance.

    A class is instantiated with its defaults; an instance is used as given.

    Raises
    ------
    FitError
        An unknown name (listing the known ones) or anything that is not a bounce law.
    """
    if isinstance(law, str):
        try:
            return law_class(law, case_sensitive=False)()
        except ParameterError as exc:
            raise FitError(exc.message, law=law, option="model", hints=exc.hints) from None
    if isinstance(law, type) and issubclass(law, BounceModel):
        return law()
    if isinstance(law, BounceModel):
        return law
    raise FitError(f"a law must be a law name, a BounceModel class or instance; got {law!r}", option="model")


def _method(law: BounceModel, method: str | None):
    methods = type(law).fit_methods()
    name = type(law).default_fit_method if method is None else method
    if not isinstance(name, str) or name not in methods:
        others = sorted({law_name(c) for c in registered_laws().values() if isinstance(name, str)
                         and name in c.fit_methods()})
        hint = f"; {name!r} is a method of {', '.join(others)}" if others else ""
        raise FitError(f"unknown method {name!r} for {law_name(law)}: its methods are {list(methods)}{hint}",
                       law=law_name(law), option="method")
    return name, methods[name]


def _check_options(law: BounceModel, name: str, func: Any, options: dict[str, Any]) -> None:
    params = inspect.signature(func).parameters
    allowed = [p for p, v in params.items() if v.kind is inspect.Parameter.KEYWORD_ONLY]
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        raise FitError(f"method {name!r} of {law_name(law)} has no option(s) {unknown}; its options are {allowed}",
                       law=law_name(law), option=unknown[0])


def _check_contract(fitted: BounceModel, method: str, box: dict, held: dict, *, explicit_bounds: set[str]) -> None:
    """A method must honour what the caller asked: held parameters keep their values, and every free
    parameter lies inside the search box (the law's default bounds, or the ``bounds`` given). A method
    that cannot honour them (a closed form, least squares, a plane search whose result has no bounds of
    its own) fails here, naming the parameter, instead of returning a law outside its own bounds."""
    who = f"fitting method {method!r} of {law_name(fitted)}"
    law = law_name(fitted)
    use_global = Hint("method", "global", "which searches within the bounds")
    for name, value in held.items():
        got = getattr(fitted, name)
        if got is None or not np.array_equal(np.asarray(got, dtype=float), np.asarray(value, dtype=float)):
            raise FitError(f"{who} does not hold parameter {name!r}: it was fixed at {value!r} but the method "
                           f"returned {got!r}; this method cannot hold it", law=law, option="fixed", hints=[use_global])
    specs = {p.name: p for p in fitted.parameter_specs}
    for name in [n for n in box if n not in held]:
        lo, hi = box[name]
        value = getattr(fitted, name)
        if value is None:
            raise FitError(f"{who} returned no value for parameter {name!r}", law=law, option="method")
        got = np.ravel(np.asarray(value, dtype=float))
        lo_a, hi_a = np.broadcast_to(lo, got.shape), np.broadcast_to(hi, got.shape)
        tol = 1e-9 * np.maximum(1.0, np.abs(got))
        bad = ~np.isfinite(got) | (got < lo_a - tol) | (got > hi_a + tol)
        if not bad.any():
            continue
        i = int(np.argmax(bad))
        element = specs[name].element_names()[i] if name in specs and specs[name].size == got.size else name
        where = "" if element == name else f" ({element} = {got[i]:.6g}, outside {lo_a[i]:g}..{hi_a[i]:g})"
        if name in explicit_bounds:
            raise FitError(f"{who} returned {name} = {value!r}{where}, outside the bounds {_bound_text(lo)}.."
                           f"{_bound_text(hi)} given; this method does not search within bounds", law=law,
                           option="bounds", hints=[use_global])
        raise FitError(f"{who} returned {name} = {_value_text(value)}{where}, outside the law's search box "
                       f"{_bound_text(lo)}..{_bound_text(hi)}; the data do not determine {name} within it by this "
                       "method", law=law, option="bounds",
                       hints=[Hint("bounds", {name: Code("(low, high)")}, "a wider box, within the physical range"),
                              use_global])


def _bound_text(bound: Any) -> str:
    b = np.ravel(np.asarray(bound, dtype=float))
    return f"{b[0]:g}" if np.all(b == b[0]) else np.array2string(b, precision=4, separator=", ")


def _value_text(value: Any) -> str:
    if np.ndim(value) == 0:
        return f"{float(value):.6g}"
    return np.array2string(np.asarray(value, dtype=float), precision=4, separator=", ",
                           max_line_width=200).replace("\n", "")


def _check_held_out(p0: np.ndarray, pf: np.ndarray, t0: np.ndarray, tf: np.ndarray) -> None:
    """Held out must mean held out: refuse test bounces that are also among the fitted ones."""
    fitted = np.ascontiguousarray(np.column_stack([p0, pf])).view(np.dtype((np.void, 48))).ravel()
    tested = np.ascontiguousarray(np.column_stack([t0, tf])).view(np.dtype((np.void, 48))).ravel()
    both = np.isin(tested, fitted)
    if both.any():
        raise FitError(f"{int(both.sum())} of the {len(t0)} held-out bounces are also among the fitted bounces "
                       f"(first: test row {int(np.argmax(both)) + 1}); held-out bounces must not be fitted",
                       option="test")


def _result(outcome: FitOutcome, method: str, label: str, problem: Problem, box: dict, held: dict,
            seed: int, start_time: float) -> FitResult:
    fitted = outcome.model
    def overall(landing: np.ndarray, liftoff: np.ndarray, inv: np.ndarray | None = None) -> np.ndarray:
        return error_terms(landing, liftoff, fitted._evaluate(landing), inv).mean(axis=0)

    train = overall(problem.landing, problem.liftoff)
    tst = problem.test
    test = None if tst is None else overall(*tst)
    return FitResult(
        model=fitted,
        method=method,
        objective=label,
        objective_value=float(outcome.objective_value),
        delta=float(train[0]),
        delta_q=train[1:],
        data={"train": (problem.landing, problem.liftoff), **({} if tst is None else {"test": tst})},
        n_train=problem.n,
        test_delta=None if test is None else float(test[0]),
        test_delta_q=None if test is None else test[1:],
        n_test=0 if tst is None else len(tst[0]),
        bounds=dict(box),
        fixed=dict(held),
        at_bounds=dict(outcome.at_bounds),
        insensitive=dict(outcome.insensitive),
        diagnostics=fitted._diagnostics(problem.landing, problem.liftoff),
        test_diagnostics={} if tst is None else fitted._diagnostics(*tst),
        stderr=dict(outcome.stderr),
        n_evaluations=outcome.n_global + outcome.n_local,
        n_global=outcome.n_global,
        n_local=outcome.n_local,
        elapsed=time.perf_counter() - start_time,
        stop_reason=outcome.stop_reason,
        algorithm=outcome.algorithm,
        seed=seed,
        notes=list(outcome.notes),
        extras=dict(outcome.extras),
    )
