r"""``bouncelab.assess``: what a fitted law is worth on these data, and which of its parameters the data determine.

One call answers two questions a fit alone does not:

* **How well does the law predict bounces it has not seen?** Held-out delta and Delta q by
  grouped k-fold cross-validation over launcher settings (every repeat of a setting in the
  same fold; over single bounces when the data have no settings), beside the training
  figures and the number of free parameters.
* **Which parameters mean something?** Per parameter (element names for arrays): the
  estimate, a bootstrap interval resampling whole launcher settings, the spread of
  independent global fits from random starts, a *profile* of the objective along the
  parameter (the parameter held at each point of a grid over its search box, every other
  parameter refitted), whether it sits on a bound, and a verdict with the parameters it is
  entangled with.

Verdicts
--------
The profile is judged against the noise of the data, defined by a paired test: at a
profile point :math:`\theta_j` each bounce's objective term changes by
:math:`\Delta_i = t_i(\theta_j) - t_i(\hat\theta)` (for the default objective
:math:`t_i = \lVert p_{F,i} - \hat p_{F,i}\rVert / \lVert p_{0,i}\rVert`, so the mean of
:math:`t_i` is delta). The increase :math:`\bar\Delta` is *within the noise* when

.. math::

    \bar\Delta \le z_{\text{level}}\, \mathrm{se}(\bar\Delta) + \text{tol}\cdot\bar t(\hat\theta),

with :math:`\mathrm{se}` clustered by launcher setting (repeats of a setting are not
independent; by bounce without settings), :math:`z_{\text{level}}` the one-sided normal
quantile (1.645 at ``level=0.95``) and ``tol`` (default 1e-3) absorbing the optimiser's own
accuracy. The *profile interval* is the connected range of values around the estimate
within the noise (ends interpolated between grid points); it is *closed* on a side when
the profile leaves the noise before the box's bound on that side, or when the estimate
sits on that bound.

``"not identifiable"``
    A flat direction: the profile stays within the noise over the whole box; or the
    parameter takes part (|component| >= 0.2) in a near-null direction of the residuals'
    Jacobian at the estimate (singular value below ``null_tol`` times the largest, columns
    scaled to unit norm; a column of zeros counts) or the fit found the objective
    insensitive to it, and its profile interval is open on a side. Such a parameter can
    be traded against the ones named in ``correlated`` without changing the fit.
``"weakly identifiable"``
    Not a flat direction, but the data do not bound it: its profile interval is open on a
    side (the data cannot exclude values up to that bound of the box), or another part of
    the box away from the estimate is within the noise too (a second minimum).
``"identifiable"``
    The profile interval is closed on both sides.

``correlated`` names the parameters whose bootstrap estimates correlate with this one's
by at least ``correlation`` in absolute value (default 0.9) and those sharing a near-null
Jacobian direction with it.

Cost
----
A full fit, ``k`` fold fits, ``n_bootstrap`` bootstrap refits, ``starts`` global fits and
``profile_points + 2 local_points`` fits per free number. The defaults (5, 100, 4, 11 + 2 x 3) take a few seconds
for a law of the rigid family on a campaign of 700 bounces; every count is a keyword.
The refits run on ``executor`` (any :class:`concurrent.futures.Executor`, a dask ``Client``: see
:func:`~bouncelab.fitting.tasks.map_tasks`) with exactly the serial results.

The bootstrap's percentile interval at ``level`` needs at least one resample in each tail:
``n_bootstrap`` below :math:`2 / (1 - \text{level})` (40 at the default 95 %) gives an interval
that is just the range of a few refits, which can exclude the estimate itself; :func:`assess`
then warns (:class:`SmallBootstrapWarning`) and says so in its notes.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core import checks
from bouncelab.core.errors import BouncelabWarning, FitError
from bouncelab.data.campaign import make_campaign, synthetic_warning
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.fitter import (
    SEED_MAX,
    check_count,
    check_fraction,
    check_seed,
    fit,
    law_instance,
    refuse_sample_weight,
)
from bouncelab.fitting.objective import bounce_weights, objective_weighting, objective_weights
from bouncelab.fitting.problem import resolve_fixed
from bouncelab.fitting.result import FitResult, _indent
from bouncelab.fitting.splits import CrossValidation, cross_validate
from bouncelab.fitting.tasks import map_tasks, resolve_executor
from bouncelab.fitting.uncertainty import Bootstrap, bootstrap
from bouncelab.fitting.vector import ParameterVector
from bouncelab.laws.base import BounceModel
from bouncelab.laws.registry import law_name
from bouncelab.metrics import ERROR_COLUMNS, error_terms

__all__ = ["START_ALGORITHMS", "VERDICTS", "Assessment", "HeldOut", "SmallBootstrapWarning", "assess",
           "held_out_errors", "min_bootstrap"]

#: The verdicts of :func:`assess`, from best to worst (see the module documentation).
VERDICTS = ("identifiable", "weakly identifiable", "not identifiable")

#: Global algorithms of the independent starts, used in turn.
START_ALGORITHMS = ("DIRECT_L", "CRS2_LM", "MLSL")

#: Options of :func:`bouncelab.fit` itself (everything else in ``**fit_kwargs`` is an option of the method).
_FIT_KEYS = ("objective", "bounds", "fixed", "free", "plausible")

#: A parameter takes part in a near-null Jacobian direction when its component there is at least this.
_NULL_PART = 0.2


class SmallBootstrapWarning(BouncelabWarning):
    """Too few bootstrap resamples for the level of the interval reported (see :func:`min_bootstrap`)."""


def min_bootstrap(level: float) -> int:
    """The fewest resamples whose percentile interval at ``level`` has a resample in each tail: ``2 / (1 - level)``
    rounded up (40 at 95 %). Fewer make the interval the range of a few refits, which can exclude the estimate."""
    return int(np.ceil(2.0 / (1.0 - level) - 1e-9))


@dataclass
class Assessment:
    """Result of :func:`assess`.

    Attributes
    ----------
    law
        Name of the law.
    fit
        The fit to all the data (:class:`~bouncelab.FitResult`); ``fit.model`` is the fitted law.
    scores
        Rows ``"training"`` and ``"held-out"``: ``n`` (bounces), delta and the three Delta q
        (fractions), and ``delta_sd``, the standard deviation of the held-out delta over the folds.
    parameters
        One row per number of the law (element names for arrays), see :meth:`to_frame`.
    profiles
        One row per profile point: ``parameter``, ``value``, the objective ``change`` from the
        estimate, its noise ``threshold``, ``within_noise``, and ``delta`` there.
    starts
        One row per independent global start: ``algorithm``, ``seed``, ``delta`` and the parameters found.
    correlation
        Correlation matrix of the bootstrap estimates of the free numbers (empty without a bootstrap).
    null_directions
        Near-null directions of the residuals' Jacobian at the estimate: each a mapping with the
        singular value ratio (``"ratio"``) and the parameters taking part (``"parts"``: name -> component).
    cross_validation, bootstrap
        The underlying :class:`~bouncelab.fitting.CrossValidation` and :class:`~bouncelab.fitting.Bootstrap`
        (the latter None with ``n_bootstrap=0``).
    split
        ``"setting"`` (folds and resamples of launcher settings) or ``"bounce"``.
    options
        The counts and thresholds used (k, n_bootstrap, starts, profile_points, level, tol, ...).
    notes
        Anything a reader should know (synthetic data, a profile point that fits better than the estimate ...).
    """

    law: str
    fit: FitResult
    scores: pd.DataFrame
    parameters: pd.DataFrame
    profiles: pd.DataFrame
    starts: pd.DataFrame
    correlation: pd.DataFrame
    null_directions: list[dict[str, Any]]
    cross_validation: CrossValidation
    bootstrap: Bootstrap | None
    split: str
    options: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    # ------------------------------------------------------------------ numbers
    @property
    def model(self) -> BounceModel:
        """The law fitted to all the data."""
        return self.fit.model

    @property
    def n_free(self) -> int:
        """Number of free (fitted) numbers of the law (:attr:`FitResult.n_free`)."""
        return self.fit.n_free

    @property
    def verdicts(self) -> dict[str, str]:
        """Parameter (element) name -> verdict, for the free numbers."""
        free = self.parameters[self.parameters["verdict"] != "fixed"]
        return dict(zip(free.index, free["verdict"], strict=True))

    def summary(self) -> dict[str, Any]:
        """One flat row for tables of several laws: free parameters, training and held-out errors, verdict counts."""
        train, test = self.scores.loc["training"], self.scores.loc["held-out"]
        row: dict[str, Any] = {"law": self.law, "n_free": self.n_free}
        for col in ERROR_COLUMNS:
            row[f"train_{col}"] = float(train[col])
        for col in ERROR_COLUMNS:
            row[f"heldout_{col}"] = float(test[col])
        row["heldout_delta_sd"] = float(test["delta_sd"])
        counts = pd.Series(list(self.verdicts.values()), dtype=object).value_counts()
        for v in VERDICTS:
            row[f"n_{v.replace(' ', '_')}"] = int(counts.get(v, 0))
        return row

    def to_frame(self) -> pd.DataFrame:
        """The per-parameter table (a copy), with the scores and options in ``attrs``.

        Columns: ``estimate``; ``low``, ``high`` (search box); ``ci_low``, ``ci_high`` (bootstrap
        percentile interval at ``level``); ``starts_spread`` (max - min over the global starts);
        ``profile_low``, ``profile_high`` (the profile interval within the noise);
        ``profile_max_change`` (largest objective increase along the profile); ``at_bound``
        (``"lower"``, ``"upper"`` or ``""``); ``verdict``; ``correlated`` (names, comma-separated).
        Held parameters have the verdict ``"fixed"``.
        """
        table = self.parameters.copy()
        table.attrs.update(law=self.law, split=self.split, summary=self.summary(), **self.options)
        return table

    # ------------------------------------------------------------------ text
    def _score_line(self) -> str:
        s = self.summary()
        folds = self.options["k"]
        return (f"delta training {s['train_delta']:.4f}, held-out {s['heldout_delta']:.4f} "
                f"+- {s['heldout_delta_sd']:.4f} ({folds} folds by {self.split})")

    def report(self) -> str:
        """A readable account: errors, the parameter table, what each verdict rests on, notes."""
        o = self.options
        n = int(self.scores.loc["training", "n"])
        groups = f"{o['n_groups']} launcher settings" if self.split == "setting" else "no launcher settings"
        lines = [f"[[Assessment]] {self.law} on {n} bounces ({groups}), {self.n_free} free parameter(s)",
                 f"    held out: {o['k']} folds by {self.split}; bootstrap: {o['n_bootstrap']} resamples by "
                 f"{self.split}; {o['starts']} global starts; profiles of {o['profile_points']} points over the box "
                 f"+ {o['local_points']} on each side of the estimate; level {o['level']:g}"]
        lines.append("[[Errors]] (fractions; the paper prints them as %)")
        table = self.scores.copy()
        table["n"] = table["n"].astype(int)
        lines.append(_indent(table.to_string(float_format=lambda v: f"{v:.4f}", na_rep="")))
        lines.append("[[Parameters]]")
        cols = ["estimate", "ci_low", "ci_high", "starts_spread", "profile_low", "profile_high", "at_bound",
                "verdict", "correlated"]
        shown = self.parameters[cols].copy()
        lines.append(_indent(shown.to_string(float_format=lambda v: f"{v:.4g}", na_rep="")))
        why = self._reasons()
        if why:
            lines.append("[[Verdicts]]")
            lines.extend(f"    - {name}: {text}" for name, text in why.items())
        if self.notes:
            lines.append("[[Notes]]")
            lines.extend(f"    - {note}" for note in self.notes)
        return "\n".join(lines)

    def _reasons(self) -> dict[str, str]:
        out = {}
        for name, row in self.parameters.iterrows():
            if row["verdict"] == "fixed":
                continue
            out[str(name)] = f"{row['verdict']} ({row['reason']})"
        return out

    def __str__(self) -> str:
        return self.report()

    def __repr__(self) -> str:
        counts = ", ".join(f"{k}: {v}" for k, v in self.verdicts.items())
        return f"Assessment({self.law}: {self._score_line()}; {counts})"

    def to_markdown(self) -> str:
        """A short Markdown summary: one line of errors and a table of estimates, intervals and verdicts."""
        pct = f"{100 * self.options['level']:g} %"
        lines = [f"**{self.law}**: {self.n_free} free parameter(s); {self._score_line()}", "",
                 f"| parameter | estimate | {pct} bootstrap interval | spread over starts | profile within noise "
                 "| verdict | correlated with |",
                 "|---|---|---|---|---|---|---|"]
        lines += [f"| {name} | " + " | ".join(cells) + " |" for name, cells in self.table_rows()]
        return "\n".join(lines)

    def table_rows(self) -> list[tuple[str, list[str]]]:
        """Each parameter's cells in the Markdown tables (here and in ``bouncelab reproduce``'s report): estimate
        (and the bound it sits on), bootstrap interval, spread over starts, profile within the noise, verdict,
        correlated parameters."""
        def num(v: Any) -> str:
            return "" if v is None or (isinstance(v, float) and np.isnan(v)) else f"{v:.4g}"

        rows = []
        for name, r in self.parameters.iterrows():
            if r["verdict"] == "fixed":
                rows.append((str(name), [num(r["estimate"]), "", "", "", "fixed", ""]))
                continue
            ci = "" if np.isnan(r["ci_low"]) else f"{r['ci_low']:.4g} to {r['ci_high']:.4g}"
            bound = f" (at {r['at_bound']} bound)" if r["at_bound"] else ""
            rows.append((str(name), [num(r["estimate"]) + bound, ci, num(r["starts_spread"]),
                                     f"{r['profile_low']:.4g} to {r['profile_high']:.4g}", r["verdict"],
                                     r["correlated"]]))
        return rows

    def _repr_html_(self) -> str:
        from bouncelab.fitting._display import assessment_html  # the notebook view

        return assessment_html(self)


# ------------------------------------------------------------------------------ the function
def assess(
    model: Any,
    data: Any,
    *,
    k: int = 5,
    n_bootstrap: int = 100,
    starts: int = 4,
    profile_points: int = 11,
    local_points: int = 3,
    level: float = 0.95,
    seed: int = 0,
    method: str | None = None,
    executor: Any = None,
    client: Any = None,
    correlation: float = 0.9,
    null_tol: float = 1e-3,
    tol: float = 1e-3,
    **fit_kwargs: Any,
) -> Assessment:
    """Held-out errors and the identifiability of each parameter of a law on these data.

    See the module documentation (:mod:`bouncelab.fitting.assessment`) for the definitions of
    the noise, the profile interval and the verdicts.

    Parameters
    ----------
    model
        A law class, instance or name, as for :func:`bouncelab.fit` (an instance's values
        start the fits).
    data
        A campaign Dataset (with a ``setting`` coordinate for folds and resamples by launcher
        setting; without one, single bounces are folded and resampled) or a
        ``(landing, liftoff)`` pair.
    k
        Folds of the cross-validation (at most the number of settings, or bounces).
    n_bootstrap
        Bootstrap resamples (0 skips the bootstrap: no intervals, no correlations; fewer than
        :func:`min_bootstrap` at ``level``, 40 at 95 %, warn).
    starts
        Independent global fits from random start points in the search box, by the
        algorithms of :data:`START_ALGORITHMS` in turn, each with its own seed (0 skips them).
    profile_points
        Points of each profile, spread evenly over the parameter's search box (geometrically
        when the box is positive and spans two decades or more); the estimate is added.
    local_points
        Further profile points on each side of the estimate, at 1, 2, 4 ... bootstrap standard
        errors from it (1 % of the box without a bootstrap): they place the ends of the profile
        interval where a coarse grid over the box could not.
    level
        Level of the bootstrap intervals and of the one-sided noise test of the profiles.
    seed
        Seed of everything random (folds, resamples, starts, fits).
    method
        Fitting method of the full fit, the folds and the bootstrap (default: the law's).
        The starts and the profiles use the generic ``"global"`` method, which can hold any
        parameter; options of ``method`` in ``fit_kwargs`` reach them only when it is ``"global"``.
    executor
        Where to run the refits: any :class:`concurrent.futures.Executor` (a ``ThreadPoolExecutor``,
        loky's reusable executor, dask's ``client.get_executor()``), a dask ``Client``, or None
        (serially); see :func:`~bouncelab.fitting.tasks.map_tasks`. The result is the same.
    client
        Deprecated alias of ``executor`` (a :class:`DeprecationWarning`); it will be removed.
    correlation
        Bootstrap correlation (absolute) from which two parameters are named correlated.
    null_tol
        A Jacobian direction is near-null when its singular value is below ``null_tol`` times the largest.
    tol
        Objective changes below ``tol`` times the objective at the estimate are within the noise.
    **fit_kwargs
        Passed to :func:`bouncelab.fit` (``objective``, ``bounds``, ``fixed``, ``free``, method options).

    Returns
    -------
    Assessment
        ``print(result)`` gives a report; ``result.parameters`` the per-parameter table;
        ``result.scores`` training and held-out errors; ``result.to_markdown()`` a short table.

    Raises
    ------
    FitError
        Bad counts or thresholds, ``sample_weight`` (folds and resamples could not carry it),
        too few settings or bounces for ``k`` folds, anything :func:`bouncelab.fit` refuses.

    Warns
    -----
    SmallBootstrapWarning
        ``n_bootstrap`` too few for intervals at ``level`` (fewer than :func:`min_bootstrap`).

    Examples
    --------
    >>> import bouncelab as bl
    >>> result = bl.assess(bl.Rigid, bl.load_campaign("B"))  # doctest: +SKIP
    >>> result.parameters["verdict"]                           # doctest: +SKIP
    """
    executor = resolve_executor(executor, client, "assess")
    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "assess")
    seed = check_seed(seed)
    k = check_count(k, "k", minimum=2)
    n_bootstrap = check_count(n_bootstrap, "n_bootstrap", minimum=0)
    if n_bootstrap == 1:
        raise FitError("n_bootstrap must be 0 (no bootstrap) or at least 2 resamples; got 1", option="n_bootstrap")
    starts = check_count(starts, "starts", minimum=0)
    profile_points = check_count(profile_points, "profile_points", minimum=3)
    local_points = check_count(local_points, "local_points", minimum=0)
    level = check_fraction(level, "level")
    small_bootstrap = None
    if 0 < n_bootstrap < min_bootstrap(level):
        small_bootstrap = (f"{n_bootstrap} bootstrap resamples are too few for {100 * level:g} % intervals (at least "
                           f"{min_bootstrap(level)} put a resample in each tail): the intervals are the range of a few "
                           "refits and can exclude the estimate; use n_bootstrap >= "
                           f"{min_bootstrap(level)}, or a lower level")
        warnings.warn(f"assess: {small_bootstrap}", SmallBootstrapWarning, stacklevel=2)
    correlation = check_fraction(correlation, "correlation")
    null_tol = checks.positive(null_tol, "null_tol", error=FitError)
    tol = checks.positive(tol, "tol", allow_zero=True, error=FitError)
    if not law.parameter_specs:
        raise FitError(f"assess needs a law with parameters; {law_name(law)} has none", law=law_name(law))

    p0, pf, _ = campaign_arrays(data)
    n = len(p0)
    cv_data, groups, split = _fold_groups(data)
    n_groups = len(pd.unique(groups))
    if k > n_groups:
        raise FitError(f"k = {k} folds need at least {k} launcher settings (or bounces); the data have {n_groups}",
                       option="k")

    fit_level = {key: fit_kwargs[key] for key in _FIT_KEYS if key in fit_kwargs}
    method_options = {key: v for key, v in fit_kwargs.items() if key not in _FIT_KEYS}
    objective = fit_level.get("objective", "delta")
    weights = objective_weights(objective)
    with_pis = objective_weighting(objective) == "pi"

    # 1. the full fit (it checks the data, the options and the bounds once)
    full = fit(law, data, method=method, seed=seed, **fit_kwargs)
    estimate_law = full.model
    later = {**fit_kwargs, "plausible": None}  # the data were checked by the full fit
    later_level = {**fit_level, "plausible": None}

    # 2. held-out errors by grouped folds
    held_out = _held_out(law, cv_data, k=k, seed=seed, executor=executor, split=split, method=method, **later)
    cv = held_out.cross_validation
    # 3. the bootstrap
    boot = None
    if n_bootstrap:
        boot = bootstrap(law, cv_data if with_pis else (p0, pf, groups), n=n_bootstrap, by="setting", level=level,
                         seed=seed, executor=executor, method=method, **later)

    # 4. starts and profiles, one batch of tasks
    box = full.bounds
    held = resolve_fixed(law, fit_level.get("fixed"), fit_level.get("free"))
    elements = _elements(estimate_law, box, held)
    free = [e for e in elements if e.free]
    global_options = method_options if (method or type(law).default_fit_method) == "global" else {}
    fit_data = data if with_pis else (p0, pf)
    tasks: list[tuple] = []
    start_rows: list[dict[str, Any]] = []
    for j in range(starts):
        algorithm = START_ALGORITHMS[j % len(START_ALGORITHMS)]
        start_seed = (seed + 1 + j) % (SEED_MAX + 1)
        start = _random_start(estimate_law, elements, np.random.default_rng([seed, j]))
        options = {**global_options, "algorithm": algorithm}
        tasks.append((start, fit_data, start_seed, {**later_level, **options}))
        start_rows.append({"start": j + 1, "algorithm": algorithm, "seed": start_seed})
    scale = {} if boot is None else boot.samples[[e.name for e in free]].std(ddof=1).to_dict()
    grids = {e.name: _grid(e, profile_points, local_points, scale.get(e.name, 0.0)) for e in free}
    profile_keys: list[tuple[str, float]] = []
    for e in free:
        for value in grids[e.name]:
            start, kwargs = _held_at(estimate_law, e, float(value), held, box, later_level)
            tasks.append((start, fit_data, seed, {**global_options, **kwargs}))
            profile_keys.append((e.name, float(value)))
    thetas = map_tasks(_fit_task, tasks, executor)

    # per-bounce objective terms, and the noise test of a change from the estimate
    inv = bounce_weights(data, p0) if with_pis else None
    vec = ParameterVector(estimate_law)
    theta_hat = vec.of(estimate_law)

    def terms(theta: np.ndarray) -> np.ndarray:
        return error_terms(p0, pf, vec.predict(estimate_law, p0, theta), inv) @ weights

    def deltas(theta: np.ndarray) -> np.ndarray:
        return error_terms(p0, pf, vec.predict(estimate_law, p0, theta))[:, 0]

    t_hat = terms(theta_hat)
    codes = pd.factorize(groups)[0]
    floor = tol * float(t_hat.mean())
    z = _normal_quantile(level)

    starts_table = pd.DataFrame(start_rows)
    start_thetas = thetas[:starts]
    if starts:
        starts_table["delta"] = [float(deltas(t).mean()) for t in start_thetas]
        flat = [dict(zip(_flat_names(law), t, strict=True)) for t in start_thetas]
        starts_table = pd.concat([starts_table, pd.DataFrame(flat)], axis=1)
    notes: list[str] = []
    profile_rows = []
    for (name, value), theta in zip(profile_keys, thetas[starts:], strict=True):
        change, se = _paired_change(terms(theta) - t_hat, codes)
        profile_rows.append({"parameter": name, "value": value, "change": change, "threshold": z * se + floor,
                             "delta": float(deltas(theta).mean()), "estimate": False})
    est_delta = float(deltas(theta_hat).mean())
    for e in free:
        profile_rows.append({"parameter": e.name, "value": e.estimate, "change": 0.0, "threshold": floor,
                             "delta": est_delta, "estimate": True})
    profiles = pd.DataFrame(profile_rows, columns=["parameter", "value", "change", "threshold", "delta", "estimate"])
    profiles["within_noise"] = profiles["change"] <= profiles["threshold"]
    profiles = profiles.sort_values(["parameter", "value", "estimate"], kind="stable")
    order = {e.name: i for i, e in enumerate(free)}
    profiles = profiles.sort_values("parameter", key=lambda s: s.map(order), kind="stable").reset_index(drop=True)
    better = profiles[(profiles["change"] < -profiles["threshold"]) & ~profiles["estimate"]]
    if len(better):
        first = better.iloc[int(np.argmin(better["change"].to_numpy()))]
        notes.append(f"the profile of {first['parameter']} at {first['value']:.4g} fits better than the estimate "
                     f"(objective lower by {-first['change']:.3g}): the full fit missed the best minimum, so the "
                     "profile intervals are measured from a point that is not the best")

    # 5. the Jacobian of the residuals at the estimate
    nulls = _null_directions(estimate_law, p0, pf, free, theta_hat, null_tol)
    in_null: dict[str, set[str]] = {}
    for d in nulls:
        for a in d["parts"]:
            in_null.setdefault(a, set()).update(b for b in d["parts"] if b != a)

    # 6. bootstrap correlations
    names_free = [e.name for e in free]
    corr = pd.DataFrame()
    if boot is not None and len(names_free) > 1:
        samples = boot.samples[names_free].to_numpy(dtype=float)
        sd = samples.std(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            c = np.corrcoef(samples, rowvar=False)
        c[:, sd == 0] = np.nan
        c[sd == 0, :] = np.nan
        corr = pd.DataFrame(c, index=names_free, columns=names_free)
    summary = boot.summary() if boot is not None else None

    rows = {}
    for e in elements:
        row: dict[str, Any] = {"estimate": e.estimate, "low": e.low, "high": e.high}
        if not e.free:
            rows[e.name] = {**row, "ci_low": np.nan, "ci_high": np.nan, "starts_spread": np.nan,
                            "profile_low": np.nan, "profile_high": np.nan, "profile_max_change": np.nan,
                            "at_bound": "", "verdict": "fixed", "correlated": "", "reason": "held in the fit"}
            continue
        prof = profiles[profiles["parameter"] == e.name]
        judged = _judge(e, prof, in_null, full.insensitive)
        partners = set(in_null.get(e.name, set()))
        if not corr.empty:
            col = corr[e.name].drop(e.name)
            partners.update(col.index[np.abs(col.to_numpy()) >= correlation])
        row.update(
            ci_low=np.nan if summary is None else float(summary.loc[e.name, "ci_low"]),
            ci_high=np.nan if summary is None else float(summary.loc[e.name, "ci_high"]),
            starts_spread=float(np.ptp(starts_table[e.name].to_numpy())) if starts else np.nan,
            **judged,
            correlated=", ".join(n_ for n_ in names_free if n_ in partners),
        )
        rows[e.name] = row
    parameters = pd.DataFrame.from_dict(rows, orient="index")
    parameters.index.name = "parameter"

    train = error_terms(p0, pf, vec.predict(estimate_law, p0, theta_hat)).mean(axis=0)
    test = held_out.scores
    scores = pd.DataFrame(
        [[n, *train, np.nan], [test["n"], *(test[c] for c in ERROR_COLUMNS), test["delta_sd"]]],
        index=pd.Index(["training", "held-out"], name="data"), columns=["n", *ERROR_COLUMNS, "delta_sd"])
    scores["n"] = scores["n"].astype(int)
    if small_bootstrap is not None:
        notes.insert(0, small_bootstrap)
    note = synthetic_warning(data)
    if note is not None:
        notes.insert(0, note)
    options = {"k": k, "n_bootstrap": n_bootstrap, "starts": starts, "profile_points": profile_points,
               "local_points": local_points,
               "level": level, "seed": seed, "correlation": correlation, "null_tol": null_tol, "tol": tol,
               "n_groups": n_groups, "method": full.method, "objective": full.objective}
    return Assessment(law=law_name(law), fit=full, scores=scores, parameters=parameters, profiles=profiles,
                      starts=starts_table, correlation=corr, null_directions=nulls, cross_validation=cv,
                      bootstrap=boot, split=split, options=options, notes=notes)


# ------------------------------------------------------------------------------ held-out errors
@dataclass
class HeldOut:
    """Held-out errors of a law by grouped k-fold cross-validation (:func:`held_out_errors`).

    Attributes
    ----------
    cross_validation
        The folds (:class:`~bouncelab.fitting.CrossValidation`).
    scores
        ``n`` (bounces, each held out once), delta and the three Delta q over all of them (the folds'
        figures weighted by their bounces) and ``delta_sd``, the standard deviation of delta over the folds.
    split
        ``"setting"`` (folds of whole launcher settings) or ``"bounce"`` (the data have no settings).
    k
        Number of folds.
    """

    cross_validation: CrossValidation
    scores: dict[str, float]
    split: str
    k: int


def held_out_errors(model: Any, data: Any, *, k: int = 5, seed: int = 0, executor: Any = None,
                    **fit_kwargs: Any) -> HeldOut:
    """Held-out delta and Delta q of a law: grouped k-fold cross-validation by launcher setting, by bounce
    without settings.

    The one implementation behind :func:`assess`'s held-out row and :func:`bouncelab.compare`'s held-out
    columns: every repeat of a launcher setting falls in the same fold
    (:func:`~bouncelab.fitting.cross_validate`), so each bounce is predicted by a fit that saw none of
    its setting; without a ``setting`` coordinate (or for a ``(landing, liftoff)`` pair) each bounce is
    its own group.

    Parameters
    ----------
    model
        A law class, instance or name.
    data
        A campaign Dataset or a ``(landing, liftoff)`` pair.
    k
        Number of folds, between 2 and the number of settings (or bounces).
    seed, executor, **fit_kwargs
        As for :func:`~bouncelab.fitting.cross_validate`.

    Raises
    ------
    FitError
        ``k`` is not an integer between 2 and the number of settings (or bounces), or a fold cannot be fitted.
    """
    grouped, _, split = _fold_groups(data)
    return _held_out(model, grouped, k=k, seed=seed, executor=executor, split=split, **fit_kwargs)


def _held_out(model: Any, grouped: Any, *, k: int, seed: int, executor: Any, split: str,
              **fit_kwargs: Any) -> HeldOut:
    """:func:`held_out_errors` on data that carry their groups as ``setting`` (see :func:`_fold_groups`)."""
    cv = cross_validate(model, grouped, k=k, seed=seed, executor=executor, **fit_kwargs)
    folds = cv.folds
    weights = folds["n_test"].to_numpy(dtype=float)
    scores: dict[str, float] = {"n": int(weights.sum())}
    for col in ERROR_COLUMNS:
        scores[col] = float(np.average(folds[f"test_{col}"], weights=weights))
    scores["delta_sd"] = cv.delta_std
    return HeldOut(cross_validation=cv, scores=scores, split=split, k=len(folds))


# ------------------------------------------------------------------------------ pieces
@dataclass
class _Element:
    """One number of a law's parameter vector: its name, place, box and estimate."""

    name: str
    param: str
    index: int  # position within the parameter (0 for a scalar)
    scalar: bool
    low: float
    high: float
    estimate: float
    free: bool


def _elements(law: BounceModel, box: dict[str, tuple[Any, Any]], held: Mapping[str, Any]) -> list[_Element]:
    out = []
    for spec in law.parameter_specs:
        lo, hi = (np.broadcast_to(np.asarray(b, dtype=float), (spec.size,)) for b in box[spec.name])
        value = getattr(law, spec.name)
        flat = np.ravel(np.asarray(value if value is not None else np.full(spec.size, np.nan), dtype=float))
        for i, name in enumerate(spec.element_names()):
            free = spec.name not in held and hi[i] > lo[i]
            out.append(_Element(name, spec.name, i, spec.is_scalar, float(lo[i]), float(hi[i]), float(flat[i]), free))
    return out


def _flat_names(law: BounceModel) -> list[str]:
    return [name for spec in law.parameter_specs for name in spec.element_names()]


def _grid(e: _Element, m: int, local: int, scale: float) -> np.ndarray:
    """``m`` points over the box, and ``local`` on each side of the estimate at 1, 2, 4 ... times ``scale``
    (the bootstrap standard error, else 1 % of the box), inside the box."""
    if e.low > 0 and e.high / e.low >= 100:
        box = np.geomspace(e.low, e.high, m)
    else:
        box = np.linspace(e.low, e.high, m)
    width = e.high - e.low
    step = scale if np.isfinite(scale) and scale > 1e-9 * width else 0.01 * width
    offsets = step * 2.0 ** np.arange(local)
    near = np.r_[e.estimate - offsets, e.estimate + offsets]
    near = near[(near > e.low) & (near < e.high)]
    return np.unique(np.r_[box, near])


def _random_start(law: BounceModel, elements: Sequence[_Element], rng: np.random.Generator) -> BounceModel:
    """The fitted law with every free number drawn uniformly from its box (held numbers kept)."""
    values: dict[str, Any] = {}
    for spec in law.parameter_specs:
        flat = np.ravel(np.asarray(getattr(law, spec.name), dtype=float)).copy()
        for e in elements:
            if e.param == spec.name and e.free:
                flat[e.index] = rng.uniform(e.low, e.high)
        values[spec.name] = float(flat[0]) if spec.is_scalar else flat.reshape(spec.shape)
    return law.replace(**values)


def _held_at(law: BounceModel, e: _Element, value: float, held: Mapping[str, Any], box: dict[str, tuple[Any, Any]],
             base: Mapping[str, Any]) -> tuple[BounceModel, dict[str, Any]]:
    """The start and the fit options of a profile point: ``e`` held at ``value``, the rest free as in the full fit.

    A scalar is held with ``fixed=``; an element of an array parameter by a search box of zero width for it.
    """
    kwargs = {k: v for k, v in base.items() if k not in ("fixed", "free", "bounds")}
    given = base.get("free") or []
    free = [f for f in ([given] if isinstance(given, str) else given) if f != e.param]
    if e.scalar:
        kwargs["fixed"] = {**held, e.param: value}
        if base.get("bounds"):
            kwargs["bounds"] = {k: v for k, v in base["bounds"].items() if k != e.param}
        start = law.replace(**{e.param: value})
    else:
        arr = np.ravel(np.asarray(getattr(law, e.param), dtype=float)).copy()
        arr[e.index] = value
        lo, hi = (np.array(b, dtype=float) for b in box[e.param])
        lo[e.index] = hi[e.index] = value
        kwargs["fixed"] = dict(held)
        kwargs["bounds"] = {**(base.get("bounds") or {}), e.param: (lo, hi)}
        shape = next(s.shape for s in law.parameter_specs if s.name == e.param)
        start = law.replace(**{e.param: arr.reshape(shape)})
    if free:
        kwargs["free"] = free
    return start, kwargs


def _fit_task(task: tuple) -> np.ndarray:
    """One start or profile fit (module level, so that executors can pickle it): the fitted parameter vector."""
    law, data, seed, kwargs = task
    fitted = fit(law, data, method="global", seed=seed, **kwargs).model
    return ParameterVector(fitted).of(fitted)


def _fold_groups(data: Any) -> tuple[Any, np.ndarray, str]:
    """The data as a campaign whose ``setting`` is each bounce's fold group, the groups, and the split:
    ``"setting"`` (the data's launcher settings) or ``"bounce"`` (no settings: each bounce its own group)."""
    p0, pf, setting = campaign_arrays(data)
    if setting is not None:
        return data, np.asarray(setting), "setting"
    groups = np.arange(len(p0))
    if isinstance(data, xr.Dataset):
        return data.assign_coords(setting=("bounce", groups)), groups, "bounce"
    return make_campaign(p0, pf, setting=groups, plausible=None), groups, "bounce"


def _paired_change(diff: np.ndarray, codes: np.ndarray) -> tuple[float, float]:
    """Mean of the per-bounce changes and its standard error, clustered by group."""
    n = len(diff)
    mean = float(diff.mean())
    sums = np.bincount(codes, weights=diff)
    sizes = np.bincount(codes)
    g = len(sums)
    if g < 2:
        return mean, float("inf")
    resid = sums - sizes * mean
    se = float(np.sqrt(g / (g - 1) * (resid @ resid)) / n)
    return mean, se


def _normal_quantile(level: float) -> float:
    from scipy.stats import norm

    return float(norm.ppf(level))


def _null_directions(law: BounceModel, p0: np.ndarray, pf: np.ndarray, free: Sequence[_Element],
                     theta: np.ndarray, null_tol: float) -> list[dict[str, Any]]:
    """Near-null directions of the Jacobian of the residuals (pF - P) / ||p0|| w.r.t. the free numbers."""
    if not free:
        return []
    inv = 1.0 / np.linalg.norm(p0, axis=1)
    vec = ParameterVector(law)
    where = {name: i for i, name in enumerate(_flat_names(law))}
    cols = []
    for e in free:
        i = where[e.name]
        h = 1e-5 * (e.high - e.low)
        up, down = min(theta[i] + h, e.high), max(theta[i] - h, e.low)
        tu, td = theta.copy(), theta.copy()
        tu[i], td[i] = up, down
        d = (vec.predict(law, p0, tu) - vec.predict(law, p0, td)) / (up - down)
        cols.append((d * inv[:, None]).ravel())
    jac = np.column_stack(cols)
    norms = np.linalg.norm(jac, axis=0)
    out: list[dict[str, Any]] = []
    zero = norms <= 1e-12 * max(float(norms.max()), 1e-300)
    for j in np.flatnonzero(zero):
        out.append({"ratio": 0.0, "parts": {free[j].name: 1.0}})
    live = np.flatnonzero(~zero)
    if len(live) >= 2:
        _, s, vt = np.linalg.svd(jac[:, live] / norms[live], full_matrices=False)
        for sv, v in zip(s, vt, strict=True):
            ratio = float(sv / s[0])
            if ratio < null_tol:
                parts = {free[live[j]].name: float(v[j]) for j in range(len(live)) if abs(v[j]) >= _NULL_PART}
                out.append({"ratio": ratio, "parts": parts})
    return out


def _judge(e: _Element, prof: pd.DataFrame, in_null: Mapping[str, set[str]],
           insensitive: Mapping[str, Any]) -> dict[str, Any]:
    """Profile interval, bound and verdict of one free number (see the module documentation)."""
    values = prof["value"].to_numpy(dtype=float)
    excess = (prof["change"] - prof["threshold"]).to_numpy(dtype=float)  # <= 0: within the noise
    i0 = int(np.flatnonzero(prof["estimate"].to_numpy())[0])
    width = e.high - e.low
    on_low = e.estimate - e.low <= 1e-6 * width
    on_high = e.high - e.estimate <= 1e-6 * width
    at_bound = "lower" if on_low else "upper" if on_high else ""

    def walk(step: int) -> tuple[float, bool, int]:
        j = i0
        while 0 <= j + step < len(values):
            nxt = j + step
            if excess[nxt] > 0:  # left the noise between j and nxt: interpolate the crossing
                a, b = excess[j], excess[nxt]
                frac = 0.0 if b == a else (0.0 - a) / (b - a)
                return float(values[j] + frac * (values[nxt] - values[j])), True, j
            j = nxt
        return float(values[j]), False, j

    lo_end, lo_closed, lo_j = walk(-1)
    hi_end, hi_closed, hi_j = walk(+1)
    lo_closed = lo_closed or on_low
    hi_closed = hi_closed or on_high
    outside = np.r_[excess[:lo_j], excess[hi_j + 1:]]
    second = bool((outside <= 0).any())
    flat = bool((excess <= 0).all())
    null = e.name in in_null or e.name in insensitive
    closed = lo_closed and hi_closed
    if flat:
        verdict, reason = "not identifiable", "the profile stays within the noise over the whole search box"
    elif null and not closed:
        partners = sorted(in_null.get(e.name, set()))
        with_ = f" with {', '.join(partners)}" if partners else ""
        verdict = "not identifiable"
        reason = (f"a near-null direction of the residuals' Jacobian{with_}, and the profile stays within the noise "
                  f"up to the {'lower' if not lo_closed else 'upper'} bound")
    elif not closed:
        verdict = "weakly identifiable"
        reason = f"the profile stays within the noise up to the {'lower' if not lo_closed else 'upper'} bound"
    elif second:
        verdict, reason = "weakly identifiable", "another part of the search box is within the noise too"
    else:
        verdict = "identifiable"
        reason = "the profile leaves the noise on both sides" + (f" (the estimate sits on the {at_bound} bound)"
                                                                 if at_bound else "")
        if null:
            reason += "; the residuals' Jacobian is singular at the estimate (a kink, such as a regime boundary)"
    return {"profile_low": lo_end, "profile_high": hi_end,
            "profile_max_change": float(prof["change"].max()), "at_bound": at_bound, "verdict": verdict,
            "reason": reason}

