"""Figs. 6, 7 and 10 of the paper: prediction-interval widths, contact-point velocities and all
landing/lift-off slices (Fig. 3 is in :mod:`bouncelab.plots.landing`, Figs. 8 and 9 in
:mod:`bouncelab.plots.comparison`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core.errors import DataError, ParameterError
from bouncelab.core.slip_roll import classify_slip_roll
from bouncelab.core.units import COMPONENTS
from bouncelab.plots import _common as c

__all__ = ["plot_pi_widths", "plot_slices", "plot_tangential"]


def plot_pi_widths(data: Any, *, bins: int = 30, fig: Any = None, title: str | None = None):
    """Fig. 6: histograms of the 95 % prediction-interval widths, rescaled by the campaign mean.

    The width of a PI is twice its half-width (``landing_pi``/``liftoff_pi``). It is
    divided by the mean ``|q|`` of that quantity over the campaign, separately for
    landing and lift-off, so 1 on the horizontal axis is the average measured value.
    One panel per component; landing in green, lift-off in red.

    Raises
    ------
    DataError
        ``data`` is not a campaign Dataset with ``landing_pi`` and ``liftoff_pi``.
    """
    p0, pf, attrs = c.campaign_data(data)
    missing = [k for k in ("landing_pi", "liftoff_pi") if k not in getattr(data, "data_vars", {})]
    if missing:
        raise DataError(
            f"the PI-width histograms need the prediction-interval half-widths {missing} in the campaign "
            "Dataset; this one has none (see bouncelab.analysis.measurement to estimate them from tracked frames)",
            column=missing[0]
        )
    fig, axes = c.new_figure(fig, nrows=1, ncols=3, figsize=(12.0, 4.0))
    states = {"landing": (p0, data["landing_pi"]), "liftoff": (pf, data["liftoff_pi"])}
    for k, (comp, ax) in enumerate(zip(COMPONENTS, axes[0], strict=True)):
        widths = {}
        for state, (values, pi) in states.items():
            mean_abs = float(np.abs(values[:, k]).mean())
            hw = pi.transpose("bounce", "component").values[:, k]
            widths[state] = 2.0 * hw / mean_abs if mean_abs > 0 else np.full_like(hw, np.nan)
        finite = np.concatenate([w[np.isfinite(w)] for w in widths.values()])
        top = _hist_top(finite)
        edges = np.linspace(0.0, top, bins + 1)
        clipped = 0
        for state, w in widths.items():
            w = w[np.isfinite(w)]
            clipped += int((w > top).sum())
            sym = c.label(comp, state, units=False)
            ax.hist(
                np.minimum(w, top), bins=edges, color=c.STATE_COLOR[state], alpha=0.5, edgecolor="white",
                linewidth=0.4, label=f"{'landing' if state == 'landing' else 'lift-off'} {sym}", gid=f"hist-{state}",
            )
        ax.set_xlabel(f"PI width / mean $|{c._SYMBOL[comp]}|$  [-]")
        ax.set_ylabel("number of bounces")
        ax.set_title(c.symbol(comp) + (" (horizontal velocity)", " (vertical velocity)", " (spin)")[k])
        ax.set_xlim(0.0, top)
        ax.legend(fontsize="small")
        if clipped:
            ax.annotate(f"{clipped} wider than {top:.2g}\nin last bin", (0.98, 0.70), xycoords="axes fraction",
                        ha="right", va="top", fontsize="x-small")
    if title is None:
        title = f"{c.campaign_name(attrs)}: widths of the 95 % prediction intervals, rescaled by the mean |q|"
    return c.finish(fig, attrs, title)


def _hist_top(w: np.ndarray) -> float:
    """Upper edge of the histogram: the largest width, unless a few outliers would squash the rest."""
    if w.size == 0:
        return 1.0
    top, q = float(w.max()), float(np.quantile(w, 0.99))
    if q > 0 and top > 3.0 * q:
        top = 1.5 * q
    return top * 1.02 if top > 0 else 1.0


def plot_tangential(
    data: Any, near_zero: float | None = None, *, ax: Any = None, title: str | None = None, units: Any = None
):
    """Fig. 7: contact-point velocity ``v_P = xdot + omega`` at landing (x) vs at lift-off (y).

    Bounces are marked by measured class (roll triangles, slip circles); the dashed
    line is zero lift-off tangential velocity.

    Parameters
    ----------
    near_zero
        Optional tolerance, in the figure's velocity unit: ``|v_P| <= near_zero`` counts
        as zero for the slip/roll classification (``classify_slip_roll(tol=...)``), a grey
        band shows it around the zero lift-off line, and the number of bounces lifting off
        within it (i.e. in near-pure rolling) is reported.
    units
        Units of the axes: None or "scaled" (radii/s), a preset ("si", "lab", "imperial")
        or a mapping such as ``{"velocity": "m/s"}`` (see
        :func:`bouncelab.plots.figure_units`). ``v_P = xdot + omega`` in radii/s times the
        ball radius is the contact point's speed, shown in the velocity unit.
    """
    p0, pf, attrs = c.campaign_data(data)
    fu = c.figure_units(units)
    vunit = fu.unit("velocity")
    tol = 0.0
    if near_zero is not None:
        try:
            tol = float(near_zero)
        except (TypeError, ValueError):
            raise ParameterError(f"near_zero must be a number of {vunit}; got {near_zero!r}",
                                 parameter="near_zero") from None
        if not (np.isfinite(tol) and tol >= 0):
            raise ParameterError(f"near_zero must be a non-negative number of {vunit}; got {near_zero!r}",
                                 parameter="near_zero")
    own = ax is None
    fig, ax = c.single_axes(ax, figsize=(7.0, 6.0))
    k = fu.velocity_factor()  # v_P in radii/s -> the figure's velocity unit
    v0, vf = k * (p0[:, 0] + p0[:, 2]), k * (pf[:, 0] + pf[:, 2])
    classes = classify_slip_roll(p0, pf, tol=tol / k)
    alpha = c.scatter_alpha(len(p0))
    for name, style in c.CLASS_STYLE.items():
        m = classes == name
        ax.scatter(v0[m], vf[m], marker=style["marker"], color=style["color"], s=18, alpha=alpha,
                   label=f"{style['label']} ({int(m.sum())})", gid=f"class-{name}")
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = c.class_handles({k: int((classes == k).sum()) for k in c.CLASS_STYLE})
    ax.axhline(0.0, color="black", linestyle="--", linewidth=1.2, gid="zero-liftoff")
    handles.append(Line2D([], [], color="black", linestyle="--", linewidth=1.2,
                          label=r"$v_{P,F} = 0$ (lift-off rolling)"))
    ax.axvline(0.0, color="0.6", linestyle=":", linewidth=0.8)
    if near_zero is not None:
        n_zero = int((np.abs(vf) <= tol).sum())
        ax.axhspan(-tol, tol, color="0.5", alpha=0.3, linewidth=0, gid="near-zero")
        handles.append(Patch(color="0.5", alpha=0.3,
                             label=rf"$|v_{{P,F}}| \leq {tol:g}$: {n_zero} bounce{'s' * (n_zero != 1)}"))
    sym0, symf = (r"\dot{x}_0 + \omega_0", r"\dot{x}_F + \omega_F") if fu.velocity == "radius/s" else \
        (r"\dot{x}_0 + R\omega_0", r"\dot{x}_F + R\omega_F")
    ax.set_xlabel(rf"$v_{{P,0}} = {sym0}$ at landing [{vunit}]")
    ax.set_ylabel(rf"$v_{{P,F}} = {symf}$ at lift-off [{vunit}]")
    ax.grid(True, alpha=0.3)
    ax.legend(handles=handles, fontsize="small", loc="best", framealpha=0.9)
    if title is None:
        title = f"{c.campaign_name(attrs)}: tangential velocity of the contact point"
    return c.finish(fig, attrs, title, ax=None if own else ax)


def plot_slices(data: Any, *, fig: Any = None, title: str | None = None, by_class: bool = True,
                units: Any = None):
    """Fig. 10: every landing component (columns) against every lift-off component (rows).

    Parameters
    ----------
    by_class
        Colour and mark the bounces by measured slip/roll class (default); plain
        points otherwise.
    units
        Units of the axes (see :func:`bouncelab.plots.figure_units`); default scaled.
    """
    p0, pf, attrs = c.campaign_data(data)
    fu = c.figure_units(units)
    fig, axes = c.new_figure(fig, nrows=3, ncols=3, figsize=(11.0, 10.0), sharex="col", sharey="row")
    classes = classify_slip_roll(p0, pf) if by_class else np.full(len(p0), "all")
    groups = c.CLASS_STYLE if by_class else {"all": {"marker": "o", "color": "tab:blue", "label": "bounces"}}
    alpha = c.scatter_alpha(len(p0))
    x0, xf = fu.convert(p0), fu.convert(pf)
    for i, out in enumerate(COMPONENTS):
        for j, inp in enumerate(COMPONENTS):
            ax = axes[i, j]
            for name, style in groups.items():
                m = classes == name
                ax.scatter(x0[m, j], xf[m, i], marker=style["marker"], color=style["color"], s=10, alpha=alpha,
                           linewidths=0, label=f"{style['label']} ({int(m.sum())})", gid=f"class-{name}")
            ax.grid(True, alpha=0.3)
            if i == 2:
                ax.set_xlabel(c.label(inp, "landing", fu=fu))
            if j == 0:
                ax.set_ylabel(c.label(out, "liftoff", fu=fu))
    if by_class:
        counts = {k: int((classes == k).sum()) for k in c.CLASS_STYLE}
        fig.legend(handles=c.class_handles(counts), loc="outside lower center", ncols=2, fontsize="medium")
    if title is None:
        title = f"{c.campaign_name(attrs)}: lift-off (rows) against landing (columns), all {len(p0)} bounces"
    return c.finish(fig, attrs, title)
