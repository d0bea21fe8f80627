""":func:`reproduce`: the paper's whole analysis of one or more campaigns, as a :class:`~bouncelab.report.Report`.

For every campaign (the embedded surrogates "A" and "B", or data files) the steps of
:mod:`bouncelab.report.steps` run in turn (Table 3, Table 2, cross-validation and assessment, lever
arm, bootstrap, repeatability, tangential velocities, prediction intervals, the reload check) and
then the figures (:mod:`bouncelab.report.figures`); what the report holds is kept in memory and,
given ``out``, written to a folder (:mod:`bouncelab.report.folder`: a new folder, or a previous
report replaced only once the new one is complete).
"""

from __future__ import annotations

import numbers
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import xarray as xr

from bouncelab.core.errors import DataError, FitError, Hint
from bouncelab.report import folder, steps
from bouncelab.report.model import Report, Section

__all__ = ["reproduce"]


class _Progress:
    """A one-line-per-step progress display on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled, self.step = total, enabled, 0

    def __call__(self, message: str) -> _Step:
        self.step += 1
        return _Step(self, message)


class _Step:
    def __init__(self, progress: _Progress, message: str) -> None:
        self.p, self.message = progress, message
        self.status = "done"

    def __enter__(self) -> _Step:
        self.t = time.perf_counter()
        if self.p.enabled:
            print(f"[{self.p.step:>2}/{self.p.total}] {self.message} ...", end="", file=sys.stderr, flush=True)
        return self

    def __exit__(self, exc_type: Any, *exc: Any) -> None:
        if self.p.enabled:
            if exc_type is None:
                status = self.status
            elif issubclass(exc_type, KeyboardInterrupt | folder._Terminated):
                status = "interrupted"
            else:
                status = "FAILED"
            print(f" {status} ({time.perf_counter() - self.t:.1f} s)", file=sys.stderr, flush=True)


def _resolve_laws(law_set: Sequence[Any] | None, laws: Sequence[Any]) -> list[Any]:
    """The report's laws as instances, each once (the first of two with the same name is kept); unknown
    names fail here, before any work."""
    from bouncelab.fitting.comparison import law_instance
    from bouncelab.laws import law_name

    chosen = list(steps.default_laws() if law_set is None else law_set) + list(laws)
    if not chosen:
        raise FitError("no laws to fit: give at least one law", option="law_set",
                       hints=[Hint("law_set", ["Rigid", "PennerFixed"])])
    out: dict[str, Any] = {}
    for law in chosen:
        model = law_instance(law)
        out.setdefault(law_name(model), model)
    return list(out.values())


def _names(sources: Sequence[str], campaigns: Sequence[str], labels: Mapping[str, str]) -> list[str]:
    """One file-safe name per source: the command line's (the campaign, the label or the file's stem), never
    the data's own "campaign" attribute, which is shown in the report but does not steer where files go."""
    names: list[str] = []
    for src in sources:
        base = steps.campaign_file_name(labels.get(src, src if src in campaigns else Path(str(src)).stem))
        name, i = base, 2
        while name in names:
            name, i = f"{base}_{i}", i + 1
        names.append(name)
    return names


def _campaign(name: str, source: str, ds: xr.Dataset, *, seed: int, laws: Sequence[Any], bootstrap: int,
              figures: bool, units: Any, step: _Progress) -> Section:
    """One campaign's analysis: every step of :data:`~bouncelab.report.steps.STAGES`, then the figures."""
    from bouncelab.laws import law_name

    section, ds = steps.start(name, source, ds)
    section.law_names = [law_name(m) for m in laws]
    run = steps.Run(section, ds, seed, list(laws), bootstrap, units)
    for label, functions in steps.STAGES:
        with step(f"{name}: {label}") as st:
            st.status = steps.statuses([f(run) for f in functions])
    if figures:
        from bouncelab.report.figures import draw_figures

        with step(f"{name}: figures") as st:
            st.status = draw_figures(run) or "done"
    else:
        run.leave_out("Figures (Figs. 3 and 6-10, lever arm)", "figures=False (--no-figures)")
    steps.caveats(run)
    return section


def reproduce(
    campaigns: Sequence[str] | None = None,
    data: Sequence[str | Path] = (),
    out: str | Path | None = "report",
    *,
    seed: int = 0,
    figures: bool = True,
    progress: bool = True,
    load: Callable[[str], xr.Dataset] | None = None,
    labels: Mapping[str, str] | None = None,
    figure_units: Any = None,
    laws: Sequence[Any] = (),
    surrogate: str | None = None,
    law_set: Sequence[Any] | None = None,
    bootstrap: int | None = None,
    units: Mapping[str, str] | None = None,
    missing: str = "drop",
) -> Report:
    """Run the paper's analysis for each campaign; return the :class:`~bouncelab.report.Report` and, given
    ``out``, write it to that folder.

    A step that cannot run on the data (too few bounces for a law, one slip/roll class only for
    the SVM, no launcher setting with repeats, a figure that cannot be drawn) is skipped: its
    reason is written in the report (the page and the markdown of its section) and listed in
    :attr:`Report.skipped`, and the rest of the report is made (:attr:`Report.complete` is then
    False). Only the errors that mean "not on these data" (FitError, DataError, ParameterError)
    become skips; anything else still stops the run, leaving the previous report as it was. What is
    not made by choice or for want of an optional input (Fig. 6 and the prediction-interval table
    without interval columns, ``figures=False``, ``bootstrap=0``, laws not asked for) is listed in
    :attr:`Report.left_out`, with the reason; the report then stays complete.

    Parameters
    ----------
    campaigns
        Embedded campaigns ("A", "B"); None (default): both, unless ``data`` is given (as the command line).
    data
        Paths of bounce-data files (see :func:`bouncelab.load_campaign`).
    out
        Output folder: new, empty, or a previous report (replaced as a whole, only once the new
        one is complete). A folder holding anything else is refused with :class:`OutputError`.
        Staging folders that an earlier, killed run left beside it (``.NAME.new-*``, ``.NAME.old-*``)
        are removed (see :func:`bouncelab.report.folder.remove_stale_staging`). None: nothing is
        written; the report is kept in memory (its figures as PNG bytes).
    seed
        Seed of the held-out split and of every fit.
    figures
        Draw the figures (needs matplotlib, the ``plot`` extra).
    progress
        Show a progress display on stderr.
    load
        How to load a source (default :func:`bouncelab.load_campaign`, with ``units`` and ``missing``
        for the data files).
    labels
        A name for some ``data`` files (path -> name), used in the file names and headings;
        other files are named by their stem. Names are cleaned to letters, digits, ``_`` and ``-``.
    figure_units
        Units of the figures' axes: None (scaled: radii/s, rad/s), a preset ("si", "lab",
        "imperial") or a mapping such as ``{"velocity": "m/s", "spin": "rpm"}`` (see
        :func:`bouncelab.plots.figure_units`). Tables stay in scaled units.
    laws
        Further laws (classes, instances or registered names, e.g. your own) fitted, compared and
        cross-validated beside those of ``law_set`` (the command line's ``--law``).
    surrogate
        Which synthetic surrogate the embedded campaigns are (``"turf"`` or ``"published"``; None,
        the default, is :data:`bouncelab.simulation.surrogate.DEFAULT_SURROGATE`, see
        :func:`bouncelab.load_campaign`); the report's notes name it. Ignored when ``load`` is given.
    law_set
        The laws of the report (names in any case, classes or instances; the command line's
        ``--laws``); None, the default, is :func:`~bouncelab.report.steps.default_laws` (the paper's
        four and :data:`~bouncelab.report.steps.BEYOND_PAPER_LAWS`). Table 2 needs PiecewiseAffine
        among them, the bootstrap one of :data:`~bouncelab.report.steps.BOOTSTRAPPED`, the assessment
        one of :data:`~bouncelab.report.steps.ASSESSED`; without them those steps are left out (not
        skips). The laws not assessed are named in the report with the reason.
    bootstrap
        Resamples of the parameter bootstrap, which is the assessment's (default
        :data:`~bouncelab.report.steps.BOOTSTRAP_RESAMPLES`); 0 leaves it out (the assessment then
        has no bootstrap intervals or correlations).
    units
        Units of the data files' columns whose header gives none, e.g. ``{"velocity": "m/s",
        "spin": "rpm"}`` (as :func:`bouncelab.load_campaign` takes them). Ignored when ``load`` is given.
    missing
        Rows of a data file with an empty or NA cell: ``"drop"`` (default: left out, and the report
        names them by row number, as does a :class:`~bouncelab.core.errors.DroppedRowsWarning`) or
        ``"raise"`` (a DataError naming the cell). Ignored when ``load`` is given.

    Returns
    -------
    Report
        Its tables, figures, fitted laws, the inputs read, what was skipped or left out and why.

    Raises
    ------
    OutputError
        ``out`` is not a new, empty or previous-report folder, or a file cannot be written;
        the previous report is then left as it was.
    DataError
        A source cannot be loaded.
    FitError
        An unknown law, no laws, or a bad ``bootstrap``.

    Examples
    --------
    >>> import bouncelab as bl
    >>> report = bl.reproduce(["A"], out="report", laws=["CraterContact"])  # doctest: +SKIP
    >>> report.complete, report.sections["A"].tables["table3"].frame  # doctest: +SKIP
    """
    from bouncelab.data.io import load_campaign
    from bouncelab.data.io.load import EMBEDDED_SURROGATES
    from bouncelab.fitting.fitter import check_seed
    from bouncelab.laws import law_name

    chosen = _resolve_laws(law_set, laws)  # unknown names fail here, before any work
    seed = check_seed(seed)
    resamples = steps.BOOTSTRAP_RESAMPLES if bootstrap is None else bootstrap
    # one resample has no spread: assess (whose bootstrap the report shows) takes 0 or at least 2
    if (isinstance(resamples, bool) or not isinstance(resamples, numbers.Integral) or resamples < 0
            or resamples == 1):
        raise FitError(f"bootstrap must be 0 (leaves it out) or a whole number of resamples >= 2; got {bootstrap!r}",
                       option="bootstrap")
    resamples = int(resamples)
    if missing not in ("drop", "raise"):
        raise DataError(f"missing must be 'drop' or 'raise'; got {missing!r}", option="missing")
    campaigns = list(("A", "B") if campaigns is None and not data else campaigns or ())
    sources = [*campaigns, *(str(d) for d in data)]
    if not sources:
        raise DataError("nothing to reproduce: give campaigns (A, B) or data files", option="campaigns")
    labels = {str(k): str(v) for k, v in (labels or {}).items()}  # (paths as given, str or Path)
    names = _names(sources, campaigns, labels)
    plot_units = None
    if figures:
        from bouncelab.plots._common import figure_units as resolve_units
        from bouncelab.plots._common import pyplot

        pyplot()  # fail early, before any work, if matplotlib is missing
        plot_units = resolve_units(figure_units)  # and on bad units
    if load is None:
        if surrogate is not None and surrogate not in EMBEDDED_SURROGATES:  # before any work
            raise DataError(f"surrogate must be one of {', '.join(map(repr, EMBEDDED_SURROGATES))}; got {surrogate!r}",
                            option="surrogate")

        def load(src: str) -> xr.Dataset:
            if src in campaigns:
                return load_campaign(src, surrogate=surrogate)
            return load_campaign(src, units=units, missing=missing)
    start = time.perf_counter()
    started = time.time()
    if out is not None:
        out = folder.resolve_out(out)
        folder.check_out(out)
    step = _Progress(len(sources) * (len(steps.STAGES) + 1 + figures) + (out is not None), progress)
    loaded = []
    for src, name in zip(sources, names, strict=True):
        with step(f"loading {src}"):
            loaded.append((name, src, load(src)))
    report = Report(out=out, seed=seed, laws=tuple(law_name(m) for m in chosen), bootstrap=resamples)
    if plot_units is not None and (plot_units.velocity, plot_units.spin) != ("radius/s", "rad/s"):
        report.figure_units = {"velocity": plot_units.velocity, "spin": plot_units.spin}

    def analyse() -> None:
        for name, src, ds in loaded:
            report.sections[name] = _campaign(name, src, ds, seed=seed, laws=chosen, bootstrap=resamples,
                                              figures=figures, units=plot_units, step=step)
        report.elapsed = time.perf_counter() - start

    if out is None:
        analyse()
        return report
    for stale in folder.remove_stale_staging(out, started):
        if progress:
            print(f"removed {str(stale)!r}, left by an earlier run that was killed", file=sys.stderr)
    with folder.staged(out) as staging:
        analyse()
        with step("writing the report (tables, laws, figures, index.html)"):
            folder.write_report(report, staging)
    return report
