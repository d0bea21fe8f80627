"""The report's figures, one function per figure (the paper's Figs. 3 and 6-10, and the lever arm).

Each takes the campaign's :class:`~bouncelab.report.steps.Run` and returns the matplotlib figure
(and, for Fig. 3, its caption, which says what it shows); it raises one of the typed errors of
:data:`bouncelab.fitting.comparison.SKIPPABLE` when it cannot be drawn on these data, and returns
None when it is not made for want of an optional input (Fig. 6 without interval columns).
:func:`draw_figures` draws them all into the campaign's section as PNG bytes.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from typing import Any

from bouncelab.core.errors import DataError
from bouncelab.report.model import Figure
from bouncelab.report.steps import NO_INTERVALS, Run, _first_line

__all__ = ["FIGURES", "draw_figures", "fig3", "fig6", "fig7", "fig8", "fig9", "fig10", "lever_arm_figure"]

#: The resolution of the report's PNGs (bouncelab.plots.save_figure's).
DPI = 150


def fig3(run: Run) -> tuple[Any, str]:
    """Fig. 3: the landing conditions by slip/roll class, with the delta-optimal plane and the SVM's support
    vectors where they can be had; the caption says what is and is not shown."""
    import numpy as np

    from bouncelab.fitting.comparison import SKIPPABLE
    from bouncelab.laws.plane_fitting import fit_svm
    from bouncelab.plots import plot_landing_space

    ds, cmp, names = run.data, run.section.comparison, run.names
    try:
        svm = fit_svm(np.ascontiguousarray(ds.landing.values), np.ascontiguousarray(ds.liftoff.values))
    except SKIPPABLE:  # too few bounces of a class for the SVM: Fig. 3 without support vectors (Table 2 says why)
        svm = None
    fitted = {} if cmp is None else cmp.results
    plane_law = fitted["PiecewiseAffine"].model if "PiecewiseAffine" in fitted else None
    shown = ["the delta-optimal plane" if plane_law is not None else "", "SVM support vectors" if svm else ""]
    absent = [] if plane_law is not None else [
        "no plane: " + ("PiecewiseAffine is not among the laws" if "PiecewiseAffine" not in names
                        else "PiecewiseAffine could not be fitted, see Table 3")]
    if svm is None:
        absent.append("no support vectors: the paper's SVM cannot run on these data")
    caption = ("Fig. 3: landing conditions, slip/roll classes" + "".join(f", {x}" for x in shown if x)
               + (f" ({'; '.join(absent)})" if absent else ""))
    return plot_landing_space(ds, plane_law, support=svm, units=run.units), caption


def fig6(run: Run) -> Any:
    """Fig. 6: the widths of the prediction intervals (None: the data have none)."""
    from bouncelab.plots import plot_pi_widths

    return plot_pi_widths(run.data) if "landing_pi" in run.data.data_vars else None


def fig7(run: Run) -> Any:
    """Fig. 7: the tangential velocity at landing and lift-off."""
    from bouncelab.plots import plot_tangential

    return plot_tangential(run.data, units=run.units)


def fig8(run: Run) -> Any:
    """Fig. 8: predicted against observed lift-off, the paper's laws fitted without the ringed held-out bounces
    (the split of Table 2)."""
    import bouncelab.plots as plots
    from bouncelab.fitting import fit
    from bouncelab.fitting.comparison import PAPER_LAWS
    from bouncelab.laws import law_name

    if run.train is None:
        raise DataError(f"the paper's split cannot be made: {run.split_error}")
    laws = {}
    for model in run.laws:
        key = law_name(model)
        if key in PAPER_LAWS[:-1]:
            laws[key] = fit(model, run.train, test=run.test, seed=run.seed)
    if "bouncelab's delta-optimal plane" in run.section.piecewise:
        laws[PAPER_LAWS[-1]] = run.section.piecewise["bouncelab's delta-optimal plane"]
    if not laws:
        raise DataError("none of the paper's laws was fitted on the split")
    return plots.plot_predictions(run.data, laws, test=run.test, units=run.units)


def fig9(run: Run) -> Any:
    """Fig. 9: the repeatability of each launcher setting."""
    from bouncelab.plots import plot_repeatability

    if run.section.repeatability is None:
        raise DataError(run.repeatability_error or "no repeatability")
    return plot_repeatability(run.section.repeatability, units=run.units)


def fig10(run: Run) -> Any:
    """Fig. 10: every landing/lift-off slice."""
    from bouncelab.plots import plot_slices

    return plot_slices(run.data, units=run.units)


def lever_arm_figure(run: Run) -> Any:
    """Beyond the paper: the lever arm of the horizontal impulse, data and every fitted law."""
    from bouncelab.plots import plot_lever_arm

    cmp = run.section.comparison
    return plot_lever_arm(run.data, [] if cmp is None else [res.model for res in cmp.results.values()])


#: The figures in the report's order: (file stem, short name, caption, the function that draws it).
FIGURES: tuple[tuple[str, str, str, Callable[[Run], Any]], ...] = (
    ("fig3_landing_space", "Fig. 3", "Fig. 3: landing conditions, slip/roll classes", fig3),
    ("fig6_pi_widths", "Fig. 6", "Fig. 6: prediction-interval widths", fig6),
    ("fig7_tangential", "Fig. 7", "Fig. 7: tangential velocity at landing and lift-off", fig7),
    ("fig8_predictions", "Fig. 8",
     "Fig. 8: predicted vs observed lift-off, laws fitted without the ringed held-out bounces", fig8),
    ("fig9_repeatability", "Fig. 9", "Fig. 9: repeatability of each launcher setting", fig9),
    ("fig10_slices", "Fig. 10", "Fig. 10: all landing/lift-off slices", fig10),
    ("lever_arm", "lever-arm figure",
     "Beyond the paper: lever arm of the horizontal impulse, data and every fitted law", lever_arm_figure),
)


def png(fig: Any) -> bytes:
    """``fig`` as PNG bytes, as :func:`bouncelab.plots.save_figure` writes it."""
    buffer = io.BytesIO()
    fig.savefig(buffer, dpi=DPI, format="png")
    return buffer.getvalue()


def draw_figures(run: Run) -> str | None:
    """Draw every figure of :data:`FIGURES` into the section; a figure that cannot be drawn on these data is a
    skip (its reason on the page where it would be), Fig. 6 without interval columns is left out."""
    from bouncelab.fitting.comparison import SKIPPABLE
    from bouncelab.plots._common import pyplot

    plt = pyplot()
    figures = run.section.figures
    for stem, label, caption, draw in FIGURES:
        before = set(plt.get_fignums())
        try:
            drawn = draw(run)
        except SKIPPABLE as exc:
            for number in set(plt.get_fignums()) - before:  # only the figure this draw had begun
                plt.close(number)
            figures[stem] = Figure(caption, stem, label, reason=_first_line(exc))
            run.skip(label, _first_line(exc))
            continue
        if drawn is None:
            run.leave_out(caption, NO_INTERVALS)
            continue
        fig, caption = drawn if isinstance(drawn, tuple) else (drawn, caption)
        try:
            figures[stem] = Figure(caption, stem, label, png(fig))
        finally:
            plt.close(fig)
    not_drawn = sum(f.png is None for f in figures.values())
    if not_drawn:
        return f"done, {not_drawn} not drawn" if len(figures) > not_drawn else "skipped"
    return None
