"""Beyond the paper: parameter uncertainty by the bootstrap, resampling whole launcher settings.

The paper reports each fitted parameter as a single number. Refitting on
resampled campaigns shows how far the data pin each one down. Repeats of one
launcher setting are not independent (they share the setting's landing
conditions), so by default whole settings are resampled with replacement (a
cluster bootstrap); with ``by="bounce"`` single bounces are. Array parameters
are resampled number by number (element names such as ``A1[0,2]``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core.errors import FitError, Hint
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.fitter import check_count, check_fraction, check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.objective import objective_weighting
from bouncelab.fitting.tasks import map_tasks
from bouncelab.laws import law_name

__all__ = ["Bootstrap", "bootstrap"]

#: The most resamples :func:`bootstrap` takes (each is a fit).
MAX_RESAMPLES = 1_000_000


@dataclass
class Bootstrap:
    """Result of :func:`bootstrap`.

    Attributes
    ----------
    estimate
        Parameters fitted to the full data (every number, by element name for arrays).
    samples
        One row per resample: the refitted parameters and their delta.
    level
        Confidence level of :meth:`summary`'s percentile intervals.
    by
        What was resampled: ``"setting"`` or ``"bounce"``.
    law
        Name of the law.
    """

    estimate: dict[str, float]
    samples: pd.DataFrame
    level: float
    by: str
    law: str

    def summary(self) -> pd.DataFrame:
        """Per parameter: full-data estimate, bootstrap mean and standard error, percentile interval."""
        lo, hi = 100 * (1 - self.level) / 2, 100 * (1 + self.level) / 2
        rows = {}
        for name, value in self.estimate.items():
            s = self.samples[name].to_numpy(dtype=float)
            rows[name] = {"estimate": value, "mean": s.mean(), "std_error": s.std(ddof=1),
                          "ci_low": np.percentile(s, lo), "ci_high": np.percentile(s, hi)}
        table = pd.DataFrame(rows).T
        table.index.name = "parameter"
        table.attrs.update(level=self.level, by=self.by, n_resamples=len(self.samples))
        return table

    def __repr__(self) -> str:
        parts = ", ".join(f"{k}={v:.4g}+-{self.samples[k].std(ddof=1):.2g}" for k, v in self.estimate.items())
        return f"Bootstrap({self.law}: {parts}; {len(self.samples)} resamples by {self.by})"


def bootstrap(
    model: Any,
    data: Any,
    *,
    n: int = 200,
    by: str = "setting",
    level: float = 0.95,
    seed: int = 0,
    executor: Any = None,
    **fit_kwargs: Any,
) -> Bootstrap:
    """Bootstrap distribution of a law's fitted parameters.

    Parameters
    ----------
    model
        A law class, instance or name (as for :func:`bouncelab.fit`).
    data
        A campaign Dataset (with a ``setting`` coordinate for ``by="setting"``) or a
        ``(landing, liftoff)`` pair (``by="bounce"`` only).
    n
        Number of resamples.
    by
        ``"setting"`` (resample whole launcher settings, the default) or ``"bounce"``.
    level
        Confidence level of the percentile intervals in :meth:`Bootstrap.summary`.
    seed
        Seed of the resampling; every refit uses the same fit seed.
    executor
        Where to run the refits: any :class:`concurrent.futures.Executor` or a dask ``Client`` (see
        :func:`bouncelab.fitting.tasks.map_tasks`); the resamples are drawn first, so the result
        does not depend on it.
    **fit_kwargs
        Passed to :func:`bouncelab.fit` (objective, bounds, method ...).

    Examples
    --------
    >>> import bouncelab as bl
    >>> bl.bootstrap(bl.Rigid, bl.load_campaign("A"), n=50).summary()  # doctest: +SKIP
    """
    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "bootstrap")
    seed = check_seed(seed)
    if not law.parameter_specs:
        raise FitError(f"bootstrap needs a law with parameters; {law_name(law)} has none", law=law_name(law))
    if by not in ("setting", "bounce"):
        raise FitError(f"by must be 'setting' or 'bounce'; got {by!r}", option="by")
    n = check_count(n, "n", 2, MAX_RESAMPLES)
    level = check_fraction(level, "level")
    p0, pf, setting = campaign_arrays(data)
    if by == "setting" and setting is None:
        raise FitError("by='setting' needs the launcher setting of each bounce; the data have none (add one with "
                       "bouncelab.infer_settings)", option="by", hints=[Hint("by", "bounce")])
    # Prediction-interval weighted objectives read the intervals from the Dataset: resample it whole then.
    with_pis = objective_weighting(fit_kwargs.get("objective", "delta")) == "pi"
    # The unit guard checks bare data once, in the full fit; resamples are cut from checked data.
    plausible = fit_kwargs.pop("plausible", PLAUSIBLE_RANGES)
    full = fit(law, data if with_pis else (p0, pf), seed=seed,
               plausible=None if isinstance(data, xr.Dataset) else plausible, **fit_kwargs)
    fit_kwargs["plausible"] = None
    estimate = dict(full.model.flat_parameters())
    rng = np.random.default_rng(seed)
    if by == "bounce":
        draws = [rng.integers(0, len(p0), len(p0)) for _ in range(int(n))]
    else:
        labels = np.asarray(setting)
        groups = [np.flatnonzero(labels == s) for s in pd.unique(labels)]
        draws = [np.concatenate([groups[i] for i in rng.integers(0, len(groups), len(groups))]) for _ in range(int(n))]
    tasks = [(law, data.isel(bounce=idx) if with_pis else (p0[idx], pf[idx]), seed, fit_kwargs) for idx in draws]
    rows = map_tasks(_refit, tasks, executor)
    return Bootstrap(estimate=estimate, samples=pd.DataFrame(rows), level=level, by=by, law=law_name(law))


def _refit(task: tuple) -> dict[str, float]:
    """One bootstrap refit (a module-level function, so executors can pickle it)."""
    law, sample, seed, fit_kwargs = task
    res = fit(law, sample, seed=seed, **fit_kwargs)
    return {**res.model.flat_parameters(), "delta": res.delta}
