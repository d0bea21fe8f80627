"""Figures of the ground phase: a surface fitted to launch-monitor shots, predicted against observed roll-out."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError
from bouncelab.plots._common import scatter_alpha, single_axes

__all__ = ["plot_roll_fit"]


def plot_roll_fit(result: Any, *, ax: Any = None, heldout: bool | None = None, title: str | None = None) -> Any:
    """Predicted against observed roll-out (total - carry, m) of a :func:`~bouncelab.ground.fit_surface` result.

    One point per shot, coloured by club when the shots name clubs, with the line of perfect
    prediction; the legend gives each club's median absolute error. The held-out predictions
    (each shot predicted by the fold that did not see it) are drawn when the fit had folds,
    the fitted surface's in-sample predictions otherwise.

    Parameters
    ----------
    result
        A :class:`~bouncelab.ground.fit.SurfaceFit`.
    ax
        Axes to draw into (a new figure if None).
    heldout
        True for the held-out predictions (refused when the fit had no folds), False for the
        in-sample ones; None (default): held out when there are any.
    title
        The axes' title (default: the law and which predictions are drawn).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from bouncelab.ground.fit import SurfaceFit

    if not isinstance(result, SurfaceFit):
        raise ParameterError(f"plot_roll_fit takes the result of bouncelab.ground.fit_surface; got "
                             f"{type(result).__name__}", parameter="result")
    has_heldout = len(result.heldout) > 0
    if heldout is None:
        heldout = has_heldout
    if heldout and not has_heldout:
        raise ParameterError("this fit has no held-out predictions (folds=0); pass heldout=False", parameter="heldout")
    if heldout:
        t = result.heldout
        observed, predicted = t["observed_roll"].to_numpy(), t["predicted_roll"].to_numpy()
        club = t["club"].to_numpy() if "club" in t else None
        what = f"held out ({len(result.folds)} folds over {result.groups}s)"
    else:
        t = result.fitted_predictions
        observed, predicted = t["observed_roll"].to_numpy(), t["predicted_roll"].to_numpy()
        club = t["club"].to_numpy() if "club" in t else None
        what = "fitted shots (in-sample)"
    fig, ax = single_axes(ax, figsize=(5.6, 5.0))
    alpha = scatter_alpha(len(observed))
    groups = sorted(set(club)) if club is not None else [None]
    for g in groups:
        m = np.ones(len(observed), dtype=bool) if g is None else club == g
        err = float(np.median(np.abs(predicted[m] - observed[m])))
        name = "all shots" if g is None else str(g)
        ax.scatter(observed[m], predicted[m], s=9, alpha=alpha, lw=0,
                   label=f"{name} ({int(m.sum())}): median |error| {err:.2g} m")
    lo = float(min(observed.min(), predicted.min()))
    hi = float(max(observed.max(), predicted.max()))
    pad = 0.03 * (hi - lo if hi > lo else 1.0)
    ax.plot([lo - pad, hi + pad], [lo - pad, hi + pad], color="0.3", lw=1.0, ls="--", label="predicted = observed")
    ax.set_xlim(lo - pad, hi + pad)
    ax.set_ylim(lo - pad, hi + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("observed roll-out, total - carry (m)")
    ax.set_ylabel("predicted roll-out (m)")
    ax.set_title(f"{result.law} surface: {what}" if title is None else title, fontsize="medium")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")
    return fig
