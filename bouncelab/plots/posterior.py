"""Figures of a hierarchical calibration (:func:`bouncelab.calibrate`): the posterior and the predicted spread.

=====================  ==============================================================
:func:`plot_corner`    corner plot: each sampled number's histogram and every pair's scatter
:func:`plot_spread`    predicted against observed spread of each launcher setting's repeats
=====================  ==============================================================

matplotlib only; both return a :class:`matplotlib.figure.Figure`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from bouncelab.core.errors import DataError, ParameterError
from bouncelab.core.units import COMPONENTS
from bouncelab.data.inputs import campaign_arrays
from bouncelab.plots import _common as c

__all__ = ["plot_corner", "plot_spread"]


def _check_posterior(posterior: Any) -> None:
    from bouncelab.fitting.hierarchical import Posterior

    if not isinstance(posterior, Posterior):
        raise ParameterError(f"posterior must be a bouncelab Posterior (from bouncelab.calibrate); got "
                             f"{type(posterior).__name__}", parameter="posterior")


def plot_corner(posterior: Any, *, columns: list[str] | None = None, bins: int = 30, fig: Any = None,
                title: str | None = None) -> Any:
    """Corner plot of the posterior samples: histograms on the diagonal, pairs below it.

    Parameters
    ----------
    posterior
        A :class:`~bouncelab.fitting.hierarchical.Posterior`.
    columns
        Which sampled numbers to show (default all: population values, scales, discrepancy).
    bins
        Histogram bins.
    fig
        An empty figure to draw into (default: a new one).

    Raises
    ------
    ParameterError
        Not a posterior, or an unknown column name.
    """
    _check_posterior(posterior)
    samples: pd.DataFrame = posterior.samples
    cols = list(samples.columns) if columns is None else list(columns)
    unknown = [x for x in cols if x not in samples.columns]
    if unknown or not cols:
        raise ParameterError(f"columns must name sampled numbers {list(samples.columns)}; got {columns!r}",
                             parameter="columns")
    k = len(cols)
    size = max(4.0, 1.9 * k)
    fig, axes = c.new_figure(fig, nrows=k, ncols=k, figsize=(size, size))
    med = samples[cols].median()
    for i, yi in enumerate(cols):
        for j, xj in enumerate(cols):
            ax = axes[i, j]
            if j > i:
                ax.set_visible(False)
                continue
            if i == j:
                ax.hist(samples[xj], bins=bins, color="tab:blue", alpha=0.75, gid=f"hist-{xj}")
                ax.axvline(med[xj], color="k", lw=0.8)
                ax.set_yticks([])
                ax.set_title(f"{xj} = {med[xj]:.4g}", fontsize="small")
            else:
                ax.plot(samples[xj], samples[yi], ",", color="tab:blue", alpha=0.4, gid=f"pair-{xj}-{yi}")
            if i == k - 1:
                ax.set_xlabel(xj, fontsize="small")
            else:
                ax.set_xticklabels([])
            if j == 0 and i > 0:
                ax.set_ylabel(yi, fontsize="small")
            elif j > 0:
                ax.set_yticklabels([])
            ax.tick_params(labelsize="x-small")
    from bouncelab.laws import law_name

    if title is None:
        state = "" if posterior.converged else " (NOT converged)"
        title = f"Posterior of {law_name(posterior.law)}, {len(samples)} samples{state}"
    return c.finish(fig, {"data_kind": posterior.data_kind}, title)


def spread_table(posterior: Any, data: Any, *, n: int = 400, seed: int = 0) -> pd.DataFrame:
    """Per launcher setting with two or more repeats: the observed and the predicted standard deviation
    of each lift-off component over the setting's repeats (columns ``observed_<c>``, ``predicted_<c>``, and ``n``).

    The prediction pools :meth:`~bouncelab.fitting.hierarchical.Posterior.predict`'s draws of measured
    lift-offs (each bounce's own measurement errors from the data's intervals where the posterior separates
    them) over the setting's measured landings, the repeats of a setting on one spot (``spots=``: they share
    its setting-level draw, as the repeats do), so it includes the landings' own scatter as the repeats do.
    """
    _check_posterior(posterior)
    p0, pf, setting = campaign_arrays(data)
    if setting is None:
        raise DataError("plot_spread needs the launcher setting of each bounce (a 'setting' coordinate)",
                        column="setting")
    draws = posterior.predict(p0, n, measurement_sd=posterior.measurement_sd_of(data), spots=setting, seed=seed)
    rows = {}
    labels = np.asarray(setting)
    for s in pd.unique(labels):
        idx = np.flatnonzero(labels == s)
        if len(idx) < 2:
            continue
        obs = pf[idx].std(axis=0, ddof=1)
        # the spread of the repeats within each draw (one spot per draw), as the observed one, averaged as variances
        pred = np.sqrt(draws[:, idx, :].var(axis=1, ddof=1).mean(axis=0))
        rows[s] = {"n": len(idx), **{f"observed_{k}": v for k, v in zip(COMPONENTS, obs, strict=True)},
                   **{f"predicted_{k}": v for k, v in zip(COMPONENTS, pred, strict=True)}}
    if not rows:
        raise DataError("no launcher setting has two or more bounces: there is no spread of repeats to compare",
                        column="setting")
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.name = "setting"
    return table


def plot_spread(posterior: Any, data: Any, *, n: int = 400, seed: int = 0, fig: Any = None,
                title: str | None = None) -> Any:
    """Predicted against observed standard deviation of the lift-offs of each launcher setting's repeats.

    One panel per component; a point per setting (see :func:`spread_table`), the diagonal where
    they agree. Points above it: the posterior predicts more spread than the repeats show.

    Raises
    ------
    DataError
        Data without launcher settings, or no setting with two or more repeats.
    """
    table = spread_table(posterior, data, n=n, seed=seed)
    fig, axes = c.new_figure(fig, nrows=1, ncols=3, figsize=(13.0, 4.4))
    for k, comp in enumerate(COMPONENTS):
        ax = axes[0, k]
        x, y = table[f"observed_{comp}"], table[f"predicted_{comp}"]
        ax.scatter(x, y, s=14, color="tab:blue", alpha=0.8, gid="settings")
        top = float(max(x.max(), y.max())) * 1.05
        ax.plot([0, top], [0, top], color="0.4", lw=0.8, ls="--")
        ax.set_xlim(0, top)
        ax.set_ylim(0, top)
        unit = c.FigureUnits().unit(comp)
        ax.set_xlabel(f"observed sd of {c.symbol(comp)}$_F$ over repeats [{unit}]")
        ax.set_ylabel(f"predicted sd [{unit}]")
        ratio = float(np.median(y / np.where(x > 0, x, np.nan)))
        ax.set_title(f"{c.symbol(comp)}: median predicted/observed {ratio:.2f}")
        ax.grid(True, alpha=0.3)
    attrs = dict(getattr(data, "attrs", {}))
    if title is None:
        title = f"{c.campaign_name(attrs)}: spread of the repeats of {len(table)} launcher settings"
    return c.finish(fig, attrs, title)
