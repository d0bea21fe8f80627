"""Figs. 8 and 9 of the paper: predicted vs observed lift-off per law, and repeatability per setting."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core.errors import DataError, ParameterError
from bouncelab.core.slip_roll import classify_slip_roll
from bouncelab.core.units import COMPONENTS
from bouncelab.data.inputs import campaign_arrays
from bouncelab.laws.base import BounceModel
from bouncelab.metrics import delta_q
from bouncelab.plots import _common as c

__all__ = ["plot_predictions", "plot_repeatability"]


def plot_predictions(
    data: Any, laws: Any, test: Any = None, *, fig: Any = None, title: str | None = None, units: Any = None
):
    """Fig. 8: predicted against observed lift-off, one row per law, columns xdot, ydot, omega.

    Parameters
    ----------
    data
        A campaign Dataset (or ``(landing, liftoff)`` pair): the bounces to show.
    laws
        One fitted law, a list of them (rows named by class), or a mapping
        name -> law. A fit result (``bouncelab.fit(...)``) may stand for its ``.model``.
    test
        Optional held-out bounces to ring in black: a Dataset of bounces (matched
        to ``data`` by their values; any not in ``data`` are added to the plot) or
        a boolean mask over the bounces of ``data``. Each panel's Delta q is then
        also given on these bounces. When a law is given as a fit result, its fitted
        bounces must not include them (DataError otherwise).
    units
        Units of the axes (see :func:`bouncelab.plots.figure_units`); default scaled.
        Delta q is computed in scaled units, as in the paper, whatever the axes show.

    Raises
    ------
    TypeError
        A law is not a bounce law.
    NotFittedError
        A law has no parameters yet.
    DataError
        Bad data or test mask.

    Notes
    -----
    Markers follow the measured class: roll = triangles, slip = circles. The solid
    line is prediction = observation. Each panel is annotated with the law's
    Delta q for that component (eq. error_individual) on the bounces shown.
    """
    p0, pf, attrs = c.campaign_data(data)
    named = _named_laws(laws)
    p0, pf, is_test = _with_test(p0, pf, test)
    _check_held_out(laws, p0, pf, is_test)
    preds = {name: np.asarray(law.predict(p0, plausible=None), dtype=float)  # campaign data: checked on loading
             for name, law in named.items()}
    fu = c.figure_units(units)
    classes = classify_slip_roll(p0, pf)
    shown_pf = fu.convert(pf)
    shown = {name: fu.convert(pred) for name, pred in preds.items()}
    nrows = len(named)
    fig, axes = c.new_figure(fig, nrows=nrows, ncols=3, figsize=(12.0, 3.7 * nrows + 0.6))
    alpha = c.scatter_alpha(len(p0))
    lims = []
    for k in range(3):
        vals = np.concatenate([shown_pf[:, k], *[p[:, k] for p in shown.values()]])
        lo, hi = float(vals.min()), float(vals.max())
        pad = 0.04 * (hi - lo if hi > lo else 1.0)
        lims.append((lo - pad, hi + pad))
    for r, (name, pred) in enumerate(preds.items()):
        dq = delta_q(p0, pf, pred)
        dq_test = delta_q(p0[is_test], pf[is_test], pred[is_test]) if is_test is not None and is_test.any() else None
        pf_s, pred_s = shown_pf, shown[name]
        for k, comp in enumerate(COMPONENTS):
            ax = axes[r, k]
            for cls, style in c.CLASS_STYLE.items():
                m = classes == cls
                ax.scatter(pf_s[m, k], pred_s[m, k], marker=style["marker"], color=style["color"], s=20,
                           alpha=alpha, linewidths=0, label=f"{style['label']} ({int(m.sum())})", gid=f"class-{cls}")
            if is_test is not None:
                ax.scatter(pf_s[is_test, k], pred_s[is_test, k], marker="o", s=48, facecolors="none",
                           edgecolors="black", linewidths=0.8, label=f"test ({int(is_test.sum())})", gid="test")
            lo, hi = lims[k]
            ax.plot([lo, hi], [lo, hi], color="black", linewidth=1.0, label="prediction = observation")
            ax.set_xlim(lo, hi)
            ax.set_ylim(lo, hi)
            ax.set_aspect("equal", adjustable="box")
            ax.grid(True, alpha=0.3)
            ax.set_xlabel(c.label(comp, "liftoff", prefix="observed ", fu=fu))
            ax.set_ylabel(c.label(comp, "liftoff", prefix="predicted ", fu=fu))
            ax.set_title(f"{name}: {c.label(comp, 'liftoff', units=False)}", fontsize="medium")
            dsym = rf"$\Delta${c.symbol(comp)}"
            text = f"{dsym} = {dq[k]:.1%}"
            if dq_test is not None:
                text = f"{dsym} all: {dq[k]:.1%}\n{dsym} test: {dq_test[k]:.1%}"
            ax.text(0.04, 0.96, text, transform=ax.transAxes, ha="left", va="top", fontsize="small",
                    bbox={"boxstyle": "round", "facecolor": "white", "alpha": 0.85, "edgecolor": "0.7"},
                    gid="delta-q")
    from matplotlib.lines import Line2D

    handles = c.class_handles({k: int((classes == k).sum()) for k in c.CLASS_STYLE})
    if is_test is not None:
        handles.append(Line2D([], [], marker="o", markersize=8, markerfacecolor="none", markeredgecolor="black",
                              linestyle="none", label=f"test bounces ({int(is_test.sum())})"))
    handles.append(Line2D([], [], color="black", linewidth=1.0, label="prediction = observation"))
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize="medium")
    if title is None:
        title = f"{c.campaign_name(attrs)}: predicted against observed lift-off"
    return c.finish(fig, attrs, title)


def _named_laws(laws: Any) -> dict[str, BounceModel]:
    if isinstance(laws, Mapping):
        items = [(str(k), v) for k, v in laws.items()]
    elif isinstance(laws, list | tuple):
        items = [(None, v) for v in laws]
    else:
        items = [(None, laws)]
    if not items:
        raise ParameterError("laws is empty: give at least one fitted bounce law", parameter="laws")
    out: dict[str, BounceModel] = {}
    for name, law in items:
        model = getattr(law, "model", law)
        if not isinstance(model, BounceModel):
            raise TypeError(
                f"laws must be bounce laws (e.g. bouncelab.Rigid(...)) or fit results; got {type(law).__name__}"
            )
        model._fitted_values()  # NotFittedError with the law's own message
        key = name or type(model).__name__
        base, i = key, 2
        while key in out:
            key, i = f"{base} ({i})", i + 1
        out[key] = model
    return out


def _check_held_out(laws: Any, p0: np.ndarray, pf: np.ndarray, is_test: np.ndarray | None) -> None:
    """Held out must mean held out: a fit result whose fitted bounces include a ringed one is refused."""
    if is_test is None or not is_test.any():
        return
    results = laws.values() if isinstance(laws, Mapping) else laws if isinstance(laws, list | tuple) else [laws]
    ringed = {np.concatenate([a, b]).tobytes() for a, b in zip(p0[is_test], pf[is_test], strict=True)}
    for res in results:
        train = getattr(res, "data", {}).get("train") if isinstance(getattr(res, "data", None), dict) else None
        if train is None:
            continue
        fitted = sum(np.concatenate([a, b]).tobytes() in ringed for a, b in zip(*train, strict=True))
        if fitted:
            raise DataError(f"{fitted} of the bounces ringed as held out were fitted by {res.model!r}; "
                            "fit the law without them (bouncelab.split_by_setting) to show held-out bounces",
                            option="test")


def _with_test(p0: np.ndarray, pf: np.ndarray, test: Any):
    """Bounces to plot and the mask of held-out ones (test bounces absent from ``data`` are appended)."""
    if test is None:
        return p0, pf, None
    if isinstance(test, xr.Dataset) or (isinstance(test, tuple) and len(test) in (2, 3)):
        t0, tf, _ = campaign_arrays(test, name="test")
        index = {np.concatenate([a, b]).tobytes(): i for i, (a, b) in enumerate(zip(p0, pf, strict=True))}
        mask = np.zeros(len(p0), dtype=bool)
        extra = []
        for j, (a, b) in enumerate(zip(t0, tf, strict=True)):
            i = index.get(np.concatenate([a, b]).tobytes())
            if i is None:
                extra.append(j)
            else:
                mask[i] = True
        if extra:
            p0, pf = np.vstack([p0, t0[extra]]), np.vstack([pf, tf[extra]])
            mask = np.concatenate([mask, np.ones(len(extra), dtype=bool)])
        return p0, pf, mask
    m = np.asarray(test)
    if m.dtype != bool or m.shape != (len(p0),):
        raise DataError(
            f"test must be a Dataset of held-out bounces or a boolean mask with one entry per bounce ({len(p0)}); "
            f"got {type(test).__name__} of dtype {m.dtype} and shape {m.shape}", option="test")
    return p0, pf, m


_REP_VARS = ("mean", "ci_low", "ci_high")


def plot_repeatability(rep: Any, *, level: float = 0.95, fig: Any = None, title: str | None = None,
                       units: Any = None):
    """Fig. 9: per component, the mean landing (x) against mean lift-off (y) of each launcher setting.

    Horizontal and vertical error bars are the 95 % confidence intervals of the two means.

    Parameters
    ----------
    rep
        The output of ``bouncelab.analysis.repeats.repeatability``: a Dataset with
        dimensions (setting, state, component), state = ["landing", "liftoff"], and
        variables ``mean``, ``ci_low``, ``ci_high`` (or ``half_width``) and ``n``.
        A campaign Dataset with a ``setting`` coordinate is accepted too and
        summarised with that function at ``level``.
    units
        Units of the axes (see :func:`bouncelab.plots.figure_units`); default scaled.

    Raises
    ------
    DataError
        ``rep`` lacks the variables or dimensions above.
    """
    if isinstance(rep, xr.Dataset) and "landing" in rep.data_vars and "mean" not in rep.data_vars:
        campaign = rep
        try:
            from bouncelab.analysis.repeats import repeatability
        except ImportError as exc:
            raise ImportError(
                "summarising a campaign needs bouncelab.analysis.repeats, which could not be imported; "
                "pass the Dataset returned by repeatability(data) instead"
            ) from exc
        rep = repeatability(campaign, level=level)
        rep.attrs = {**campaign.attrs, **rep.attrs}
    mean, lo_err, hi_err = _rep_arrays(rep)
    fu = c.figure_units(units)
    mean, lo_err, hi_err = fu.convert(mean), fu.convert(lo_err), fu.convert(hi_err)  # factors > 0: bars stay
    attrs = dict(rep.attrs)
    fig, axes = c.new_figure(fig, nrows=1, ncols=3, figsize=(13.0, 4.6))
    n_set = mean.shape[0]
    for k, comp in enumerate(COMPONENTS):
        ax = axes[0, k]
        x, y = mean[:, 0, k], mean[:, 1, k]
        ax.errorbar(
            x, y, xerr=np.stack([lo_err[:, 0, k], hi_err[:, 0, k]]), yerr=np.stack([lo_err[:, 1, k], hi_err[:, 1, k]]),
            fmt="o", markersize=4, color="tab:blue", markerfacecolor="none", ecolor="0.45", elinewidth=0.8,
            capsize=1.5, gid="settings",
        )
        if k == 0:
            ax.legend(["setting mean with CI bars"], loc="best", fontsize="small")
        ax.set_xlabel(c.label(comp, "landing", prefix="mean ", fu=fu))
        ax.set_ylabel(c.label(comp, "liftoff", prefix="mean ", fu=fu))
        ax.set_title(c.symbol(comp) + (" (horizontal velocity)", " (vertical velocity)", " (spin)")[k])
        ax.grid(True, alpha=0.3)
    if title is None:
        pct = _level_text(attrs, level)
        title = f"{c.campaign_name(attrs)}: mean landing vs lift-off of {n_set} launcher settings, {pct} CIs"
    return c.finish(fig, attrs, title)


def _level_text(attrs: dict, level: float) -> str:
    lv = attrs.get("level", level)
    try:
        return f"{float(lv):.0%}"
    except (TypeError, ValueError):
        return "95%"


def _rep_arrays(rep: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(setting, 2, 3) means and lower/upper error-bar lengths, states ordered landing, lift-off."""
    if not isinstance(rep, xr.Dataset):
        raise DataError(f"rep must be the Dataset returned by repeatability(data); got {type(rep).__name__}",
                        option="rep")
    dims = {"setting", "state", "component"}
    need = [v for v in ("mean",) if v not in rep.data_vars]
    has_ci = all(v in rep.data_vars for v in _REP_VARS[1:])
    if not has_ci and "half_width" not in rep.data_vars:
        need.append("ci_low/ci_high or half_width")
    if need or not dims <= set(rep.dims):
        raise DataError(
            "rep must be a repeatability Dataset with dims (setting, state, component) and variables "
            f"'mean', 'ci_low', 'ci_high' (or 'half_width'); missing {need or sorted(dims - set(rep.dims))}",
            option="rep")
    try:
        sel = {"state": ["landing", "liftoff"], "component": list(COMPONENTS)}
        order = ("setting", "state", "component")
        mean = rep["mean"].sel(sel).transpose(*order).values.astype(float)
        if has_ci:
            lo = mean - rep["ci_low"].sel(sel).transpose(*order).values
            hi = rep["ci_high"].sel(sel).transpose(*order).values - mean
        else:
            lo = hi = np.abs(rep["half_width"].sel(sel).transpose(*order).values.astype(float))
    except KeyError as exc:
        raise DataError(
            "rep needs state coordinates 'landing', 'liftoff' and component coordinates 'xdot', 'ydot', 'omega'",
            option="rep") from exc
    if mean.shape[0] == 0:
        raise DataError("rep has no settings; there is nothing to plot", option="rep")
    return mean, np.clip(lo, 0.0, None), np.clip(hi, 0.0, None)
