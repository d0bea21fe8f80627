"""The impulse diagnostic: distribution of the lever arm Δω/Δẋ for the data and for laws."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from bouncelab.analysis.impulse import CONTACT_POINT_LEVER_ARM, MIN_DXDOT_FRACTION, _lever
from bouncelab.plots._common import campaign_data, campaign_name, finish, single_axes

__all__ = ["plot_lever_arm"]


def plot_lever_arm(data: Any, laws: Iterable[Any] = (), *, ax: Any = None, limits: tuple[float, float] = (-2.0, 6.0),
                   bins: int = 72, min_fraction: float = MIN_DXDOT_FRACTION) -> Any:
    """Histograms of the per-bounce lever arm Δω/Δẋ of the data and of each law on the same landings.

    The dashed line (in the legend) marks 2.5, where every law whose horizontal impulse acts at the
    contact point sits; values below it mean part of the impulse passes through the
    ball's centre. Values outside ``limits`` are gathered in the end bins, which are then
    hatched and labelled: the legend gives, per source, how many values lie below and above
    the axis range (so a spike at an edge is not read as a value there). The medians in the
    legend are of all defined values, not of the clipped ones.

    Parameters
    ----------
    data
        A campaign Dataset or ``(landing, liftoff)`` pair.
    laws
        Fitted laws (or objects with a ``model`` attribute, e.g. FitResult).
    ax
        Axes to draw into (a new figure if None).
    limits
        The axis range; values beyond it are counted in the end bins.
    bins
        Number of bins over ``limits``.
    min_fraction
        As in :func:`~bouncelab.analysis.impulse.impulse_lever_arm`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.patches import Patch

    p0, pf, attrs = campaign_data(data)
    fig, ax = single_axes(ax, figsize=(7.0, 4.2))
    lo, hi = float(limits[0]), float(limits[1])
    edges = np.linspace(lo, hi, bins + 1)
    sources = [("data", pf)]
    for law in laws:
        model = getattr(law, "model", law)
        sources.append((type(model).__name__, np.asarray(model.predict(p0, plausible=None))))
    clipped = {"below": 0, "above": 0}
    for i, (name, liftoff) in enumerate(sources):
        _, _, lever = _lever(p0, liftoff, min_fraction)
        lever = lever[np.isfinite(lever)]
        med = float(np.median(lever)) if lever.size else float("nan")
        below, above = int((lever < lo).sum()), int((lever > hi).sum())
        clipped["below"] += below
        clipped["above"] += above
        beyond = [f"{k} below {lo:g}" for k in (below,) if k] + [f"{k} above {hi:g}" for k in (above,) if k]
        label = f"{name} (median {med:.2f}" + (f"; in the end bins: {', '.join(beyond)}" if beyond else "") + ")"
        ax.hist(np.clip(lever, lo, hi), bins=edges, histtype="stepfilled" if i == 0 else "step",
                alpha=0.35 if i == 0 else 1.0, linewidth=1.0 if i == 0 else 1.6, label=label,
                color="0.5" if i == 0 else None)
    # in the legend rather than written beside the line, where the legend would cover it
    ax.axvline(CONTACT_POINT_LEVER_ARM, color="k", linestyle="--", linewidth=1.0,
               label=f"{CONTACT_POINT_LEVER_ARM:g}: impulse at the contact point")
    handles, _ = ax.get_legend_handles_labels()
    # The end bins also hold every value beyond the axis: hatch them, so their height is not read as a
    # peak at exactly lo or hi.
    for side, (a, b) in (("below", edges[:2]), ("above", edges[-2:])):
        if clipped[side]:
            ax.axvspan(a, b, facecolor="none", edgecolor="0.35", hatch="////", linewidth=0.0, zorder=0,
                       gid=f"clipped-{side}")
    if clipped["below"] or clipped["above"]:
        handles.append(Patch(facecolor="none", edgecolor="0.35", hatch="////",
                             label=f"end bins: also every value beyond [{lo:g}, {hi:g}] (counts above)"))
    ax.set_xlabel(r"lever arm $\Delta\omega / \Delta\dot{x}$ [per radius]")
    ax.set_ylabel("bounces")
    ax.legend(handles=handles, fontsize="small", loc="upper left")
    return finish(fig, attrs, f"{campaign_name(attrs)}: where the horizontal impulse acts",
                  ax=ax if ax is not None and fig is not ax.figure else None)
