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

    The dashed line marks 2.5, where every law whose horizontal impulse acts at the
    contact point sits; values below it mean part of the impulse passes through the
    ball's centre. Values outside ``limits`` are gathered in the end bins.

    Parameters
    ----------
    data
        A campaign Dataset or ``(landing, liftoff)`` pair.
    laws
        Fitted laws (or objects with a ``model`` attribute, e.g. FitResult).
    ax
        Axes to draw into (a new figure if None).

    Returns
    -------
    matplotlib.figure.Figure
    """
    p0, pf, attrs = campaign_data(data)
    fig, ax = single_axes(ax, figsize=(7.0, 4.2))
    edges = np.linspace(limits[0], limits[1], bins + 1)
    sources = [("data", pf)]
    for law in laws:
        model = getattr(law, "model", law)
        sources.append((type(model).__name__, np.asarray(model.predict(p0, plausible=None))))  # checked data
    for i, (name, liftoff) in enumerate(sources):
        _, _, lever = _lever(p0, liftoff, min_fraction)
        lever = np.clip(lever[np.isfinite(lever)], limits[0], limits[1])
        med = float(np.median(lever)) if lever.size else float("nan")
        ax.hist(lever, bins=edges, histtype="stepfilled" if i == 0 else "step", alpha=0.35 if i == 0 else 1.0,
                linewidth=1.0 if i == 0 else 1.6, label=f"{name} (median {med:.2f})",
                color="0.5" if i == 0 else None)
    ax.axvline(CONTACT_POINT_LEVER_ARM, color="k", linestyle="--", linewidth=1.0)
    ax.text(CONTACT_POINT_LEVER_ARM, ax.get_ylim()[1] * 0.97, " impulse at the contact point", va="top",
            fontsize="small")
    ax.set_xlabel(r"lever arm $\Delta\omega / \Delta\dot{x}$ [per radius]")
    ax.set_ylabel("bounces")
    ax.legend(fontsize="small", loc="upper left")
    return finish(fig, attrs, f"{campaign_name(attrs)}: where the horizontal impulse acts",
                  ax=ax if ax is not None and fig is not ax.figure else None)
