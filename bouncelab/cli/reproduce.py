"""``bouncelab reproduce``: the paper's whole analysis for one or more campaigns, written to a folder.

For every campaign (the embedded surrogates "A" and "B", or data files):

* Table 3 layout: the rigid family and the piecewise-affine law fitted to all bounces by
  bouncelab's global search, beside the paper's published values for the paper's campaigns
  A and B (and only for them) (plus, beyond the paper,
  the tangential-restitution law and the paper's own two-stage procedure for Rigid);
* Table 2 layout: the piecewise-affine law on the paper's split (one bounce per launcher
  setting held out), by the paper's SVM procedure and by bouncelab's delta-optimal plane;
* beyond the paper: 5-fold cross-validated delta of every law, grouped by launcher setting, and
  bootstrap intervals of the rigid family's parameters (resampling whole launcher settings);
* the analyses: repeatability per setting, tangential-velocity counts, prediction-interval widths;
* the fitted laws as JSON, every table as markdown and CSV, the figures as PNG;
* one ``index.html`` showing it all.

The report is complete or not there at all: it is built in a hidden folder beside ``out`` and
swapped in only when every file is written, so a failed run (a bad file, a full disk, an
interrupt) leaves the previous report as it was. File names never come from the data: a
campaign is named by the command line (``A``, ``B``, a ``--label``, or the file's stem), cleaned
to letters, digits, ``_`` and ``-``. ``out`` must be new, empty, or a previous report whose
files are all bouncelab's (listed in its ``.bouncelab-report.json``); any other folder is
refused before any work, so files a user keeps there are never deleted.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import stat
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.atomic import atomic_write_text
from bouncelab.cli.report import frame_markdown, index_html, table2_markdown
from bouncelab.data.campaign import synthetic_warning
from bouncelab.errors import DataError, FitError, OutputError

__all__ = ["BOOTSTRAP_RESAMPLES", "MANIFEST", "OutputError", "Report", "campaign_file_name", "reproduce"]

#: The file in a report folder that lists every file bouncelab wrote there (relative paths).
MANIFEST = ".bouncelab-report.json"


def check_output_file(path: str, flag: str, example: str, suffix: str | None = None) -> None:
    """Refuse, before a possibly long job, an output file path that cannot be written (OutputError naming
    ``flag``): a folder, a missing parent folder, or (when ``suffix`` is given) another file type."""
    p = Path(path).expanduser()
    if p.is_dir():
        raise OutputError(f"{flag} {path!r} is a folder; give a file name such as {example}")
    if suffix is not None and p.suffix.lower() != suffix:
        raise OutputError(f"{flag} {path!r}: give the file a {suffix} suffix, e.g. {example}")
    if not p.parent.is_dir():
        raise OutputError(f"{flag} {path!r}: the folder {str(p.parent)!r} does not exist")

#: Resamples of the parameter bootstrap in the report (3 to 4 s per campaign here; the refits run one after another).
BOOTSTRAP_RESAMPLES = 100


@dataclass
class Report:
    """What :func:`reproduce` wrote."""

    out: Path
    index: Path
    files: list[Path] = field(default_factory=list)
    sections: dict[str, dict[str, Any]] = field(default_factory=dict)
    elapsed: float = 0.0
    #: Units of the figures (``{"velocity": ..., "spin": ...}``); None for the scaled units.
    figure_units: dict[str, str] | None = None


class _Progress:
    """A one-line-per-step progress display on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled, self.step = total, enabled, 0
        self.start = time.perf_counter()

    def __call__(self, message: str) -> _Step:
        self.step += 1
        return _Step(self, message)


class _Step:
    def __init__(self, progress: _Progress, message: str) -> None:
        self.p, self.message = progress, message

    def __enter__(self) -> _Step:
        self.t = time.perf_counter()
        if self.p.enabled:
            print(f"[{self.p.step:>2}/{self.p.total}] {self.message} ...", end="", file=sys.stderr, flush=True)
        return self

    def __exit__(self, exc_type, *exc: Any) -> None:
        if self.p.enabled:
            status = "done" if exc_type is None else "FAILED"
            print(f" {status} ({time.perf_counter() - self.t:.1f} s)", file=sys.stderr, flush=True)


def _write_table(df: pd.DataFrame, md: str, stem: Path, files: list[Path]) -> None:
    stem.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(stem.with_suffix(".csv"), df.to_csv())
    atomic_write_text(stem.with_suffix(".md"), md)
    files += [stem.with_suffix(".csv"), stem.with_suffix(".md")]


_UNSAFE = re.compile(r"[^A-Za-z0-9_-]+")


def campaign_file_name(text: str) -> str:
    """``text`` made safe as the start of a file name: runs of anything but letters, digits, ``_``
    and ``-`` become one ``_`` (so no ``/``, ``..`` or leading dot survives); "campaign" if nothing is left.

    >>> campaign_file_name("../../x"), campaign_file_name("turf B (2024)"), campaign_file_name("/")
    ('x', 'turf_B_2024', 'campaign')
    """
    return _UNSAFE.sub("_", str(text)).strip("_") or "campaign"


def _previous_report_files(out: Path) -> set[str] | None:
    """Relative paths of the files a previous report in ``out`` consists of; None if it is not one."""
    manifest = out / MANIFEST
    if manifest.is_file():
        try:
            listed = json.loads(manifest.read_text())["files"]
        except (ValueError, KeyError, TypeError, OSError):
            return None
        return {str(f) for f in listed} | {MANIFEST}
    index = out / "index.html"
    if index.is_file():  # an older report, from before the manifest: its index lists its files
        try:
            text = index.read_text(errors="replace")
        except OSError:
            return None
        if "<title>bouncelab report</title>" in text:
            import html

            return {html.unescape(f) for f in re.findall(r"<li><a href='([^']*)'>", text)} | {"index.html"}
    return None


def _check_out(out: Path) -> None:
    """Refuse, before any work, an ``out`` that the swap at the end could not replace safely."""
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {str(out)!r} exists and is not a folder")
    parent = out.parent
    if not parent.is_dir():
        raise OutputError(f"cannot write the report to {str(out)!r}: the folder {str(parent)!r} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write the report to {str(out)!r}: the folder {str(parent)!r} is not writable")
    if not out.exists():
        return
    cwd = Path.cwd()
    if cwd == out or out in cwd.parents:
        raise OutputError(f"--out {str(out)!r} holds the current folder; the report replaces --out as a whole, "
                          "so give a folder below it (e.g. --out report)")
    if not os.access(out, os.W_OK | os.X_OK):
        raise OutputError(f"cannot replace {str(out)!r}: the folder is not writable")
    # Files and links (a link to a folder counts as the user's: it is never walked into).
    present = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_symlink() or not p.is_dir()}
    if not present:
        return
    ours = _previous_report_files(out)
    if ours is None:
        raise OutputError(f"--out {str(out)!r} is a non-empty folder that is not a bouncelab report; "
                          "give a new or empty folder (a previous report there is replaced as a whole)")
    foreign = sorted(present - ours)
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise OutputError(f"--out {str(out)!r} holds files that are not part of its previous report ({shown}); "
                          "move them or give another folder (the report is replaced as a whole)")


def _swap_in(staging: Path, out: Path) -> None:
    """Put the finished ``staging`` folder at ``out``, the previous report (if any) going away only after."""
    mode = stat.S_IMODE(out.stat().st_mode) if out.exists() else 0o777 & ~_umask()
    os.chmod(staging, mode)
    if not out.exists():
        os.rename(staging, out)
        return
    old = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.old-"))
    os.rmdir(old)
    os.rename(out, old)
    try:
        os.rename(staging, out)
    except BaseException:
        os.rename(old, out)
        raise
    shutil.rmtree(old, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Laws fitted beside the paper's in every report: Walton's tangential restitution and the physics-based laws.
BEYOND_PAPER_LAWS = ("TangentialRestitution", "CompliantImpact", "TurfContact")
#: Laws left out of the report's cross-validation because each fit takes seconds (they integrate every bounce).
NOT_CROSS_VALIDATED = frozenset({"TurfContact", "CraterContact"})


def _steps_per_campaign(figures: bool) -> int:
    return 9 + (1 if figures else 0)  # load, 8 analysis steps, figures


def reproduce(
    campaigns: list[str] | tuple[str, ...] = ("A", "B"),
    data: list[str] | tuple[str, ...] = (),
    out: str | Path = "report",
    *,
    seed: int = 0,
    figures: bool = True,
    progress: bool = True,
    load: Callable[[str], xr.Dataset] | None = None,
    labels: dict[str, str] | None = None,
    figure_units: Any = None,
    laws: Sequence[Any] = (),
    surrogate: str | None = None,
) -> Report:
    """Run the paper's analysis for each campaign and write the report folder.

    Parameters
    ----------
    campaigns
        Embedded campaigns ("A", "B").
    data
        Paths of bounce-data files (see :func:`bouncelab.load_campaign`).
    out
        Output folder: new, empty, or a previous report (replaced as a whole, only once the new
        one is complete). A folder holding anything else is refused with :class:`OutputError`.
    seed
        Seed of the held-out split and of every fit.
    figures
        Draw the figures (needs matplotlib, the ``plot`` extra).
    progress
        Show a progress display on stderr.
    load
        How to load a source (default :func:`bouncelab.load_campaign`).
    labels
        A name for some ``data`` files (path -> name), used in the file names and headings;
        other files are named by their stem. Names are cleaned by :func:`campaign_file_name`.
    figure_units
        Units of the figures' axes: None (scaled: radii/s, rad/s), a preset ("si", "lab",
        "imperial") or a mapping such as ``{"velocity": "m/s", "spin": "rpm"}`` (see
        :func:`bouncelab.plots.figure_units`). Tables stay in scaled units.
    laws
        Further laws (classes, instances or registered names, e.g. your own) fitted, compared and
        cross-validated beside the paper's laws and the tangential-restitution law.
    surrogate
        Which synthetic surrogate the embedded campaigns are (``"turf"`` or ``"published"``; None,
        the default, is :data:`bouncelab.data.surrogate.DEFAULT_SURROGATE`, see
        :func:`bouncelab.load_campaign`); the report's notes name it. Ignored when ``load`` is given.

    Returns
    -------
    Report

    Raises
    ------
    OutputError
        ``out`` is not a new, empty or previous-report folder, or a file cannot be written;
        the previous report is then left as it was.
    DataError
        A source cannot be loaded.
    """
    from bouncelab.data.io import load_campaign
    from bouncelab.data.io.load import EMBEDDED_SURROGATES
    from bouncelab.fitting.comparison import law_instance

    extra = [law_instance(law) for law in laws]  # unknown names fail here, before any work
    sources = [*campaigns, *data]
    if not sources:
        raise DataError("nothing to reproduce: give campaigns (A, B) or data files")
    labels = dict(labels or {})
    names: list[str] = []
    for src in sources:
        # The name comes from the command line, never from the data: the data's own "campaign"
        # attribute is shown in the report but does not steer where files are written.
        base = campaign_file_name(labels.get(src, src if src in campaigns else Path(str(src)).stem))
        name, i = base, 2
        while name in names:
            name, i = f"{base}_{i}", i + 1
        names.append(name)
    units = None
    if figures:
        from bouncelab.plots._common import figure_units as resolve_units
        from bouncelab.plots._common import pyplot

        pyplot()  # fail early, before any work, if matplotlib is missing
        units = resolve_units(figure_units)  # and on bad units
    if load is None:
        if surrogate is not None and surrogate not in EMBEDDED_SURROGATES:  # before any work
            raise DataError(f"surrogate must be one of {', '.join(map(repr, EMBEDDED_SURROGATES))}; got {surrogate!r}")

        def load(src: str) -> xr.Dataset:
            return load_campaign(src, surrogate=surrogate) if src in campaigns else load_campaign(src)
    start = time.perf_counter()
    out = Path(out).expanduser()
    if out.is_symlink():
        out = Path(os.path.realpath(out))  # replace the folder the link points to, keep the link
    out = Path(os.path.abspath(out))  # "." and ".." resolved: the swap renames the folder itself
    if out.parent == out:
        raise OutputError(f"--out {str(out)!r} is the root folder; give a folder for the report")
    _check_out(out)
    step = _Progress(len(sources) * _steps_per_campaign(figures) + 1, progress)  # + index.html
    loaded = []
    for src, name in zip(sources, names, strict=True):
        with step(f"loading {src}"):
            loaded.append((name, load(src)))
    try:
        staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.new-"))
    except OSError as exc:
        raise OutputError(f"cannot write the report beside {str(out)!r}: {exc.strerror or exc}") from None
    try:
        report = _build(loaded, staging, seed, figures, step, start, units, extra)
        _swap_in(staging, out)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        where = f" ({exc.filename})" if exc.filename else ""
        raise OutputError(f"cannot write the report to {str(out)!r}{where}: {exc.strerror or exc}; "
                          "the previous report, if any, is unchanged") from None
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return _moved(report, staging, out)


def _build(loaded: list[tuple[str, xr.Dataset]], out: Path, seed: int, figures: bool, step: _Progress,
           start: float, units: Any = None, extra: Sequence[Any] = ()) -> Report:
    """Write the whole report into the (new, empty) folder ``out``."""
    report = Report(out=out, index=out / "index.html")
    if units is not None and (units.velocity, units.spin) != ("radius/s", "rad/s"):
        report.figure_units = {"velocity": units.velocity, "spin": units.spin}
    for name, ds in loaded:
        report.sections[name] = _campaign(name, ds, out, seed, figures, step, report.files, units, extra=extra)
    with step("writing index.html"):
        report.elapsed = time.perf_counter() - start
        report.files.append(report.index)
        atomic_write_text(report.index, index_html(report))
        listed = sorted(p.relative_to(out).as_posix() for p in report.files)
        atomic_write_text(out / MANIFEST, json.dumps({"written_by": "bouncelab reproduce", "files": listed},
                                                     indent=1) + "\n")
    return report


def _moved(report: Report, staging: Path, out: Path) -> Report:
    """The report's paths, from the staging folder to ``out``."""

    def move(p: Path) -> Path:
        return out / p.relative_to(staging)

    for sec in report.sections.values():
        sec["laws"] = {k: move(p) for k, p in sec["laws"].items()}
        sec["figures"] = {k: move(p) for k, p in sec["figures"].items()}
    return Report(out=out, index=out / "index.html", files=[move(p) for p in report.files],
                  sections=report.sections, elapsed=report.elapsed, figure_units=report.figure_units)


def _campaign(name: str, ds: xr.Dataset, out: Path, seed: int, figures: bool, step: _Progress,
              files: list[Path], units: Any = None, *, extra: Sequence[Any] = ()) -> dict[str, Any]:
    from bouncelab.analysis.contact_velocity import tangential_summary
    from bouncelab.analysis.repeats import repeatability, repeatability_summary
    from bouncelab.data import published
    from bouncelab.data.settings import infer_settings
    from bouncelab.fitting import bootstrap, compare, cross_validate, fit, split_by_setting
    from bouncelab.fitting.comparison import PAPER_LAWS
    from bouncelab.laws import PiecewiseAffine, Rigid, law_name, registered_laws

    camp = str(ds.attrs.get("campaign", "")).upper()
    section: dict[str, Any] = {"notes": [], "tables": {}, "figures": {}, "laws": {},
                               "paper_campaign": camp if camp in published.CAMPAIGNS else None}
    if (note := synthetic_warning(ds)) is not None:
        section["notes"].append(note)
    if "setting" not in ds.coords:
        labels = infer_settings(ds)
        ds = ds.assign_coords(setting=("bounce", labels))
        section["notes"].append(
            f"The data record no launcher settings; {len(np.unique(labels))} settings were inferred by clustering "
            "the landing conditions (bouncelab.infer_settings)."
        )
    tables = out / "tables"
    compared = [registered_laws()[law] for law in [*PAPER_LAWS, *BEYOND_PAPER_LAWS]] + list(extra)

    def add(key: str, df: pd.DataFrame, stem: str, title: str, *, percent: bool = False,
            shown: pd.DataFrame | None = None, missing: str = "nan", note: str = "") -> None:
        """Write a table as CSV and markdown and show it in the report under ``key``."""
        md = f"### {title}\n\n" + frame_markdown(df if shown is None else shown, percent=percent, missing=missing)
        md += f"\n{note}\n" if note else ""
        _write_table(df, md, tables / f"{name}_{stem}", files)
        section["tables"][key] = md

    with step(f"{name}: fitting the paper's laws to all bounces (Table 3)"):
        cmp = compare(ds, [*compared], seed=seed)
        structured = fit(Rigid, ds, method="structured", seed=seed)
        md = cmp.to_markdown()
        md += ("\n### The paper's two-stage procedure for Rigid (r by least squares on ydot, then mu)\n\n"
               f"r = {structured.model.r:.4g}, mu = {structured.model.mu:.4g}, delta = {100 * structured.delta:.3g} % "
               f"(global search: delta = {100 * cmp.results['Rigid'].delta:.3g} %)\n")
        _write_table(cmp.side_by_side(), md, tables / f"{name}_table3", files)
        section["tables"]["Table 3: laws fitted to all bounces"] = md
        laws_dir = out / "laws"
        laws_dir.mkdir(exist_ok=True)
        for key, res in cmp.results.items():
            path = laws_dir / f"{name}_{campaign_file_name(key)}.json"  # a user law's key holds ':'
            res.model.to_json(path)
            files.append(path)
            section["laws"][key] = path
        section["comparison"] = cmp

    with step(f"{name}: piecewise-affine law on the paper's split, SVM and delta plane (Table 2)"):
        train, test = split_by_setting(ds, seed)
        pw = {}
        for method, label in (("svm", "paper's SVM plane"), ("plane", "bouncelab's delta-optimal plane")):
            try:
                pw[label] = fit(PiecewiseAffine, train, test=test, method=method, seed=seed)
            except FitError as exc:
                if method != "svm":
                    raise
                # the SVM needs enough bounces of both classes; a small campaign still gets the rest of the report
                section["notes"].append(f"Table 2 shows no SVM plane: the paper's SVM procedure cannot run on the "
                                        f"{train.sizes['bounce']} training bounces of the split ({exc}).")
        rows = []
        for label, res in pw.items():
            for data_name in ("train", "test"):
                t = res.errors.loc[data_name]
                diags = res.diagnostics if data_name == "train" else res.test_diagnostics
                for subset in t.index:
                    rows.append({"method": label, "data": data_name, "subset": subset, **t.loc[subset].to_dict(),
                                 **{k: (v if subset == "all" else np.nan) for k, v in diags.items()}})
        t2 = pd.DataFrame(rows).set_index(["method", "data", "subset"])
        md = table2_markdown(name, pw, ds)
        _write_table(t2, md, tables / f"{name}_table2", files)
        section["tables"]["Table 2: piecewise-affine law, held-out bounces"] = md
        section["piecewise"] = pw
        for label, res in pw.items():
            key = "svm" if "SVM" in label else "plane"
            path = out / "laws" / f"{name}_PiecewiseAffine_{key}_train.json"
            res.model.to_json(path)
            files.append(path)

    with step(f"{name}: 5-fold cross-validation by launcher setting (beyond the paper)"):
        rows = {}
        for model in compared:
            if law_name(model) in NOT_CROSS_VALIDATED:
                continue
            cv = cross_validate(model, ds, k=min(5, len(np.unique(ds.setting.values))), seed=seed)
            rows[law_name(model)] = {"cv_delta": cv.delta, "cv_delta_std": cv.delta_std,
                         "fitted_delta": float(cv.folds["train_delta"].mean())}
        cvt = pd.DataFrame(rows).T
        cvt.index.name = "law"
        skipped = [law_name(m) for m in compared if law_name(m) in NOT_CROSS_VALIDATED]
        add("Cross-validation (beyond the paper)", cvt, "crossvalidation",
            f"Cross-validated delta, campaign {name} (5 folds grouped by launcher setting)", percent=True,
            note=(f"Not cross-validated here, to keep the report quick: {', '.join(skipped)} (each fit integrates "
                  "every bounce through the contact); run bouncelab.cross_validate for them." if skipped else ""))

    with step(f"{name}: where the horizontal impulse acts (lever arm, beyond the paper)"):
        from bouncelab.analysis.impulse import lever_arm_summary

        lever = lever_arm_summary(ds, [res.model for res in cmp.results.values()])
        add("Impulse lever arm (beyond the paper)", lever, "lever_arm",
            f"Lever arm of the horizontal impulse, d(omega)/d(xdot) per bounce, campaign {name}: data and each law "
            "fitted to all bounces, on the same landings",
            note="A law whose whole horizontal impulse acts at the contact point gives 2.5; the centre fraction "
                 "1 - median/2.5 estimates the share passing through the ball's centre (ploughing). Bounces whose "
                 "xdot changes by less than 2 % of the landing speed have no lever arm (n_defined).")

    with step(f"{name}: parameter uncertainty, bootstrap over launcher settings (beyond the paper)"):
        frames = {}
        for law in ("Rigid", "PennerVarying", "PennerFixed"):
            boot = bootstrap(registered_laws()[law], ds, n=BOOTSTRAP_RESAMPLES, seed=seed)
            frames[law] = boot.summary()
        boot_table = pd.concat(frames, names=["law", "parameter"])
        add("Parameter uncertainty (beyond the paper)", boot_table, "bootstrap",
            f"Parameter uncertainty, campaign {name}: {BOOTSTRAP_RESAMPLES} bootstrap resamples of whole "
            "launcher settings (95 % percentile intervals)", shown=boot_table.reset_index().set_index("law"))

    with step(f"{name}: repeatability per launcher setting"):
        rep = repeatability(ds)
        summ = repeatability_summary(rep)
        rep_df = rep.to_dataframe()
        rep_df.to_csv(tables / f"{name}_repeatability.csv")
        files.append(tables / f"{name}_repeatability.csv")
        add("Repeatability", summ, "repeatability_summary",
            f"Repeatability, campaign {name}: 95 % CI half-widths of the mean per setting", missing="–",
            note="Medians over the settings. The row 'all' pools the three components for the ratio and the "
                 "fraction of settings whose lift-off interval is wider; it has no median half-width, as the "
                 "components' units differ.")
        section["repeatability"] = rep

    with step(f"{name}: tangential velocities and prediction intervals"):
        tang = tangential_summary(ds)
        add("Tangential velocities", tang, "tangential", f"Tangential velocity v_P = xdot + omega, campaign {name}")
        if "landing_pi" in ds.data_vars:
            widths = {}
            for state in ("landing", "liftoff"):
                w = 2 * ds[f"{state}_pi"] / np.abs(ds[state]).mean("bounce")
                widths[state] = w.median("bounce").to_pandas()
            pit = pd.DataFrame(widths)
            pit.index.name = "component"
            add("Prediction intervals", pit, "prediction_intervals",
                f"Median 95 % prediction-interval width / campaign mean |q|, campaign {name}", percent=True)

    with step(f"{name}: checking the fitted laws reload"):
        from bouncelab.laws import load_law

        for law_name, path in section["laws"].items():
            again = load_law(path)
            if again != cmp.results[law_name].model:
                raise RuntimeError(f"{path} does not reload to the fitted law")

    if figures:
        with step(f"{name}: figures"):
            # Fig. 8 rings held-out bounces, so its laws are fitted without them (the split of Table 2).
            held_out = {law: fit(registered_laws()[law], train, test=test, seed=seed) for law in PAPER_LAWS[:-1]}
            held_out[PAPER_LAWS[-1]] = pw["bouncelab's delta-optimal plane"]
            section["figures"] = _figures(name, ds, cmp, held_out, test, rep, out / "figures", files, units)
    return section


def _figures(name, ds, cmp, held_out, test, rep, folder: Path, files: list[Path], units: Any = None
             ) -> dict[str, Path]:
    from bouncelab.laws.plane_fitting import fit_svm
    from bouncelab.plots import (
        plot_landing_space,
        plot_lever_arm,
        plot_pi_widths,
        plot_predictions,
        plot_repeatability,
        plot_slices,
        plot_tangential,
        save_figure,
    )
    from bouncelab.plots._common import pyplot

    plt = pyplot()
    folder.mkdir(parents=True, exist_ok=True)
    p0, pf = ds.landing.values, ds.liftoff.values
    try:
        svm = fit_svm(np.ascontiguousarray(p0), np.ascontiguousarray(pf))
    except FitError:  # too few bounces of a class for the SVM: Fig. 3 without support vectors (noted in Table 2)
        svm = None
    plane_law = cmp.results["PiecewiseAffine"].model
    figs = {
        "Fig. 3: landing conditions, slip/roll classes, the delta-optimal plane and SVM support vectors":
            ("fig3_landing_space", lambda: plot_landing_space(ds, plane_law, support=svm, units=units)),
        "Fig. 6: prediction-interval widths": ("fig6_pi_widths", lambda: plot_pi_widths(ds)),
        "Fig. 7: tangential velocity at landing and lift-off":
            ("fig7_tangential", lambda: plot_tangential(ds, units=units)),
        "Fig. 8: predicted vs observed lift-off, laws fitted without the ringed held-out bounces":
            ("fig8_predictions", lambda: plot_predictions(ds, held_out, test=test, units=units)),
        "Fig. 9: repeatability of each launcher setting":
            ("fig9_repeatability", lambda: plot_repeatability(rep, units=units)),
        "Fig. 10: all landing/lift-off slices": ("fig10_slices", lambda: plot_slices(ds, units=units)),
        "Beyond the paper: lever arm of the horizontal impulse, data and every fitted law":
            ("lever_arm", lambda: plot_lever_arm(ds, [res.model for res in cmp.results.values()])),
    }
    made = {}
    for caption, (stem, draw) in figs.items():
        if stem == "fig6_pi_widths" and "landing_pi" not in ds.data_vars:
            continue
        fig = draw()
        path = save_figure(fig, folder / f"{name}_{stem}.png")
        plt.close(fig)
        files.append(path)
        made[caption] = path
    return made
