"""Figures of the reference paper for any campaign (needs the ``plot`` extra: ``pip install bouncelab[plot]``).

>>> import bouncelab as bl
>>> from bouncelab.plots import plot_tangential, save_figure
>>> fig = plot_tangential(bl.load_campaign("A"))          # doctest: +SKIP
>>> save_figure(fig, "fig7_campaign_A.png")                 # doctest: +SKIP

Every function returns a :class:`matplotlib.figure.Figure` and never calls ``plt.show()``.
matplotlib itself is imported only when a figure is drawn.
"""

from bouncelab.plots.figures import (
    plot_landing_space,
    plot_pi_widths,
    plot_predictions,
    plot_repeatability,
    plot_slices,
    plot_tangential,
    save_figure,
)

__all__ = [
    "plot_landing_space",
    "plot_pi_widths",
    "plot_predictions",
    "plot_repeatability",
    "plot_slices",
    "plot_tangential",
    "save_figure",
]
