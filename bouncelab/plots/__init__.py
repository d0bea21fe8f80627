"""Figures of the reference paper for any campaign (needs the ``plot`` extra: ``pip install bouncelab[plot]``).

>>> import bouncelab as bl
>>> from bouncelab.plots import plot_tangential, save_figure
>>> fig = plot_tangential(bl.load_campaign("A"))          # doctest: +SKIP
>>> save_figure(fig, "fig7_campaign_A.png")                 # doctest: +SKIP

==========================  =========================================================
:func:`plot_landing_space`  Fig. 3: landing conditions in 3-D by slip/roll, with the plane
:func:`plot_pi_widths`      Fig. 6: histograms of the prediction-interval widths
:func:`plot_tangential`     Fig. 7: contact-point velocity at landing vs lift-off
:func:`plot_predictions`    Fig. 8: predicted vs observed lift-off, one row per law
:func:`plot_repeatability`  Fig. 9: mean landing vs mean lift-off per setting, 95 % CIs
:func:`plot_slices`         Fig. 10: all nine landing/lift-off component slices
:func:`plot_lever_arm`      where the horizontal impulse acts: Δω/Δẋ of data and laws
:func:`plot_roll_fit`       a surface fitted to launch-monitor shots: predicted vs observed roll-out
:func:`save_figure`         write a figure to a file
:func:`figure_units`        the units a ``units=`` argument names
==========================  =========================================================

Every function returns a :class:`matplotlib.figure.Figure` and never calls ``plt.show()``.
matplotlib is imported on first use; on a machine without a display the non-interactive
Agg backend is used unless a backend was chosen. Figures made from synthetic surrogate
data carry a visible "synthetic surrogate data" note.

Every figure of states takes ``units=``: None or ``"scaled"`` (the paper's radii/s and
rad/s, the default), a preset (``"si"``: m/s and rad/s; ``"lab"``: m/s and rpm;
``"imperial"``: mph and rpm) or a mapping such as ``{"velocity": "m/s", "spin": "rpm"}``
(optionally with ``"radius_m"``, the ball radius, default 0.02135). Only the plotted values
and the labels are converted; errors such as Delta q stay those of the scaled data.
(``plot_pi_widths`` has no ``units``: its axes are ratios without a unit.)
"""

from bouncelab.plots._common import UNIT_PRESETS, FigureUnits, figure_units, save_figure
from bouncelab.plots.comparison import plot_predictions, plot_repeatability
from bouncelab.plots.figures import plot_pi_widths, plot_slices, plot_tangential
from bouncelab.plots.ground import plot_roll_fit
from bouncelab.plots.impulse import plot_lever_arm
from bouncelab.plots.landing import plot_landing_space

__all__ = [
    "UNIT_PRESETS",
    "FigureUnits",
    "figure_units",
    "plot_landing_space",
    "plot_lever_arm",
    "plot_pi_widths",
    "plot_predictions",
    "plot_repeatability",
    "plot_roll_fit",
    "plot_slices",
    "plot_tangential",
    "save_figure",
]
