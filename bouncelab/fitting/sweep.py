"""Parameter sweeps: a law's errors, or its fit of the other parameters, at every point of a grid."""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd

from bouncelab.core.errors import FitError
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.fitter import check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.tasks import map_tasks
from bouncelab.laws import law_name
from bouncelab.laws.base import BounceModel
from bouncelab.metrics import ERROR_COLUMNS, error_terms

__all__ = ["sweep"]

#: A sweep is cut into at most this many tasks (each a batch of points), so that executors are not swamped.
MAX_TASKS = 256


def sweep(model: Any, data: Any, grid: Mapping[str, Sequence[Any]] | Sequence[Mapping[str, Any]], *,
          executor: Any = None, seed: int = 0, **fit_kwargs: Any) -> pd.DataFrame:
    """A law's errors at every point of a grid of parameter (and option) values.

    At a point that sets every parameter of the law, the law is evaluated: its
    delta and Delta q on ``data``. At a point that sets only some, the others are
    fitted with those held (a profile): ``bouncelab.fit(law, data, fixed=point)``.
    Options (constructor keywords that are not parameters, such as PennerFixed's
    ``fade_xdot``) may be swept too.

    Parameters
    ----------
    model
        A law class, instance or name (its options, and its values as starts of the fits).
    data
        A campaign Dataset or a ``(landing, liftoff)`` pair.
    grid
        Name -> values (every combination, the first name varying slowest) or a
        sequence of points, each a mapping name -> value.
    executor
        Where to run the points: any :class:`concurrent.futures.Executor` or a dask ``Client`` (see
        :func:`bouncelab.fitting.tasks.map_tasks`); the result does not depend on it.
    seed
        Seed of every fit.
    **fit_kwargs
        Passed to :func:`bouncelab.fit` at points that fit (``objective``, ``method``, ...).

    Returns
    -------
    pandas.DataFrame
        One row per point, in grid order: the point's values, every parameter of the
        law (fitted or held, by element name for arrays), ``delta``, ``delta_xdot``,
        ``delta_ydot``, ``delta_omega`` on ``data`` and, where fitted, ``objective_value``.

    Raises
    ------
    FitError
        An empty grid, a name that is neither a parameter nor an option of the law.
    ParameterError
        A value outside a parameter's physical range.

    Examples
    --------
    >>> import bouncelab as bl
    >>> table = bl.sweep(bl.Rigid, bl.load_campaign("A"), {"mu": [0.2, 0.4]})  # fits r at each mu
    >>> list(table.columns)[:3]
    ['mu', 'r', 'delta']
    """
    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "sweep", "its table reports the paper's unweighted errors at each point")
    seed = check_seed(seed)
    points = _points(grid)
    params = {s.name for s in law.parameter_specs}
    options = set(law.option_names())
    for point in points:
        unknown = sorted(set(point) - params - options)
        if unknown:
            raise FitError(f"{law_name(law)} has no parameter or option {unknown}; parameters {sorted(params)}, "
                           f"options {sorted(options)}", law=law_name(law), option="grid")
    # Validate every point before any work (a bad value fails here, not on a worker).
    for point in points:
        _law_at(law, point, params)
    p0, _, _ = campaign_arrays(data)  # validates the data once, before any task
    size = max(1, math.ceil(len(points) / MAX_TASKS))
    batches = [points[i:i + size] for i in range(0, len(points), size)]
    rows = [row for batch in map_tasks(_sweep_task, [(law, b, data, seed, fit_kwargs) for b in batches], executor)
            for row in batch]
    table = pd.DataFrame(rows)
    table.attrs.update(law=law_name(law), n_bounces=len(p0))
    return table


def _points(grid: Any) -> list[dict[str, Any]]:
    if isinstance(grid, Mapping):
        if not grid:
            raise FitError("the grid is empty; give name -> values", option="grid")
        names = list(grid)
        values = []
        for name in names:
            v = grid[name]
            v = [v] if isinstance(v, str) or np.ndim(v) == 0 else list(v)
            if not v:
                raise FitError(f"the grid gives no values for {name!r}", option="grid")
            values.append(v)
        return [dict(zip(names, combo, strict=True)) for combo in itertools.product(*values)]
    if isinstance(grid, Sequence) and not isinstance(grid, str) and grid and all(isinstance(p, Mapping) for p in grid):
        return [dict(p) for p in grid]
    raise FitError(f"grid must be a mapping name -> values or a non-empty sequence of points; got {grid!r}",
                   option="grid")


def _law_at(law: BounceModel, point: Mapping[str, Any], params: set[str]) -> tuple[BounceModel, dict[str, Any]]:
    """The law with the point's options (and held parameters as values), and the held parameters."""
    held = {k: v for k, v in point.items() if k in params}
    opts = {k: v for k, v in point.items() if k not in params}
    return law.replace(**opts, **held), held


def _sweep_task(task: tuple) -> list[dict[str, Any]]:
    """One batch of sweep points (a module-level function, so executors can pickle it)."""
    law, points, data, seed, fit_kwargs = task
    params = {s.name for s in law.parameter_specs}
    p0, pf, _ = campaign_arrays(data)
    rows = []
    for point in points:
        at, held = _law_at(law, point, params)
        row: dict[str, Any] = {k: v for k, v in point.items()}
        if set(held) == params:
            terms = error_terms(p0, pf, at.predict(p0, plausible=None)).mean(axis=0)  # the data fitted
            fitted = at
            extra: dict[str, Any] = {}
        else:
            res = fit(at, data, fixed=held, seed=seed, **fit_kwargs)
            fitted = res.model
            terms = np.array([res.delta, *res.delta_q])
            extra = {"objective_value": res.objective_value}
        row.update({k: v for k, v in fitted.flat_parameters().items() if k not in row})
        row.update(dict(zip(ERROR_COLUMNS, (float(t) for t in terms), strict=True)))
        row.update(extra)
        rows.append(row)
    return rows
