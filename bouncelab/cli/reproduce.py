"""``bouncelab reproduce``: the paper's whole analysis for one or more campaigns, written to a folder.

For every campaign (the embedded surrogates "A" and "B", or data files):

* Table 3 layout: the rigid family and the piecewise-affine law fitted to all bounces by
  bouncelab's global search, beside the paper's published values for the paper's campaigns
  A and B (and only for them) (plus, beyond the paper,
  the tangential-restitution law and the paper's own two-stage procedure for Rigid), with the
  number of free parameters and, beside the training errors, the held-out errors of 5-fold
  cross-validation grouped by launcher setting (:func:`bouncelab.compare`'s ``heldout``; not for
  the laws of :data:`NOT_CROSS_VALIDATED`, whose fits take seconds to minutes);
* Table 2 layout: the piecewise-affine law on the paper's split (one bounce per launcher
  setting held out), by the paper's SVM procedure and by bouncelab's delta-optimal plane;
* beyond the paper: an assessment of each law of :data:`ASSESSED` (:func:`bouncelab.assess`:
  held-out errors, and per parameter a bootstrap interval, the spread of independent global
  fits, a profile and a verdict on its identifiability; the laws not assessed are named with the
  reason), the cross-validated delta of every law, and bootstrap intervals of the rigid family's
  parameters (resampling whole launcher settings, the assessment's own bootstrap);
* the analyses: repeatability per setting, tangential-velocity counts, prediction-interval widths;
* the fitted laws as JSON, every table as markdown and CSV, the figures as PNG;
* one ``index.html`` showing it all.

A step that cannot run on the data (too few bounces for a law, one slip/roll class for the
SVM, no launcher setting with repeats, a fit that would leave the law's bounds, a figure that
cannot be drawn) is skipped with its reason, in the report and in :attr:`Report.skipped`; the
rest is written (the command line then exits with 5). Only the typed errors of
:data:`bouncelab.fitting.comparison.SKIPPABLE` become skips; anything else is a bug and stops the run.

The report is built in a hidden folder beside ``out`` and swapped in only when every file is
written, so a failed run (a bad file, a full disk, an interrupt, SIGTERM) leaves the previous
report as it was; a hidden folder that a killed run left is removed by the next run
(:func:`remove_stale_staging`). File names never come from the data: a
campaign is named by the command line (``A``, ``B``, a ``--label``, or the file's stem), cleaned
to letters, digits, ``_`` and ``-``. ``out`` must be new, empty, or a previous report whose
files are all bouncelab's (listed in its ``.bouncelab-report.json``); any other folder is
refused before any work, so files a user keeps there are never deleted.
"""

from __future__ import annotations

import contextlib
import json
import numbers
import os
import re
import shutil
import signal
import stat
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.cli.report import assessment_markdown, frame_markdown, index_html, table2_markdown
from bouncelab.core.atomic import atomic_write_text
from bouncelab.core.errors import DataError, FitError, Hint, OutputError
from bouncelab.data.campaign import synthetic_warning

__all__ = ["BOOTSTRAP_RESAMPLES", "MANIFEST", "OutputError", "Report", "campaign_file_name", "default_laws",
           "remove_stale_staging", "reproduce"]

#: The file in a report folder that lists every file bouncelab wrote there (relative paths).
MANIFEST = ".bouncelab-report.json"


def check_output_file(path: str, flag: str, example: str, suffix: str | None = None) -> None:
    """Refuse, before a possibly long job, an output file path that cannot be written (OutputError naming
    ``flag``): a folder, a missing parent folder, or (when ``suffix`` is given) another file type."""
    p = Path(path).expanduser()
    if p.is_dir():
        raise OutputError(f"{flag} {path!r} is a folder; give a file name such as {example}", path=path,
                          reason="a folder")
    if suffix is not None and p.suffix.lower() != suffix:
        raise OutputError(f"{flag} {path!r}: give the file a {suffix} suffix, e.g. {example}", path=path,
                          reason=f"not a {suffix} file")
    if not p.parent.is_dir():
        raise OutputError(f"{flag} {path!r}: the folder {str(p.parent)!r} does not exist", path=path,
                          reason="no such folder")

#: Resamples of the parameter bootstrap in the report (3 to 4 s per campaign here; the refits run one after another).
BOOTSTRAP_RESAMPLES = 100


@dataclass
class Report:
    """What :func:`reproduce` wrote.

    ``skipped`` lists the steps that could not run on the data, as ``(campaign, step, reason)``
    (too few bounces for a law, one slip/roll class only, no repeated launcher setting, a figure
    that cannot be drawn...); the rest of the report is written all the same. ``complete`` is
    True when nothing was skipped. Steps left out on purpose (``figures=False``, ``bootstrap=0``,
    laws not asked for) are not skips.
    """

    out: Path
    index: Path
    files: list[Path] = field(default_factory=list)
    sections: dict[str, dict[str, Any]] = field(default_factory=dict)
    elapsed: float = 0.0
    #: Units of the figures (``{"velocity": ..., "spin": ...}``); None for the scaled units.
    figure_units: dict[str, str] | None = None
    skipped: list[tuple[str, str, str]] = field(default_factory=list)

    @property
    def complete(self) -> bool:
        """Whether every step ran (nothing in :attr:`skipped`)."""
        return not self.skipped


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
        self.status = "done"

    def __enter__(self) -> _Step:
        self.t = time.perf_counter()
        if self.p.enabled:
            print(f"[{self.p.step:>2}/{self.p.total}] {self.message} ...", end="", file=sys.stderr, flush=True)
        return self

    def __exit__(self, exc_type, *exc: Any) -> None:
        if self.p.enabled:
            if exc_type is None:
                status = self.status
            elif issubclass(exc_type, KeyboardInterrupt | _Terminated):
                status = "interrupted"
            else:
                status = "FAILED"
            print(f" {status} ({time.perf_counter() - self.t:.1f} s)", file=sys.stderr, flush=True)


class _Terminated(BaseException):
    """SIGTERM arrived during a run (raised by the handler :func:`_sigterm_raises` installs)."""


@contextlib.contextmanager
def _sigterm_raises() -> Iterator[None]:
    """During the block, SIGTERM (what ``timeout``, batch schedulers and systemd send) raises
    :class:`_Terminated`, so the cleanup that runs for Ctrl-C (an exception) runs for it too; after the
    cleanup the signal is delivered again under the previous handler (by default the process ends
    of it, as it would have without bouncelab). Only in the main thread of a POSIX process, and only
    when SIGTERM is not ignored; the previous handler is restored on the way out."""
    if (os.name != "posix" or threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) in (signal.SIG_IGN, None)):
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second SIGTERM does not cut the cleanup short
        raise _Terminated

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    except _Terminated:
        signal.signal(signal.SIGTERM, previous)
        os.kill(os.getpid(), signal.SIGTERM)  # the cleanup is done: now what SIGTERM would have done
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)


#: Names of the folders a run makes beside ``--out`` (``tempfile.mkdtemp``: the prefix and 8 characters).
_STAGING = re.compile(r"\.(?P<name>.+)\.(?:new|old)-[a-z0-9_]{8}")
#: What a report (and a staging folder) holds at its top level; anything else means it is not ours.
_REPORT_ENTRIES = frozenset({"index.html", MANIFEST, "tables", "laws", "figures"})


def _lock(folder: Path) -> int | None:
    """An exclusive lock on ``folder`` (held by the returned descriptor until it is closed, or the process
    ends): a later run sees the folder is in use. None where folders cannot be locked."""
    try:
        import fcntl

        fd = os.open(folder, os.O_RDONLY)
    except (ImportError, OSError):
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return None
    return fd


def _unlock(fd: int | None) -> None:
    if fd is not None:
        with contextlib.suppress(OSError):
            os.close(fd)


def _only_report_files(folder: Path) -> bool:
    """Whether ``folder`` holds nothing but what a report run writes (its top-level entries, and in them
    files, the atomic writes' temporary files included): a folder holding anything else is not removed."""
    try:
        for entry in folder.iterdir():
            if entry.is_symlink() or entry.name not in _REPORT_ENTRIES:
                temporary = entry.name.startswith((".index.html.", f".{MANIFEST}.")) and entry.name.endswith(".tmp")
                if not temporary:  # (the atomic writes' temporary files are ours too)
                    return False
            if entry.is_dir() and not entry.is_symlink():
                if any(p.is_symlink() or p.is_dir() for p in entry.iterdir()):
                    return False
    except OSError:
        return False
    return True


def remove_stale_staging(out: Path, before: float) -> list[Path]:
    """Remove the staging (``.NAME.new-XXXXXXXX``) and old-report (``.NAME.old-XXXXXXXX``) folders that an
    earlier run of ``reproduce`` into ``out`` left beside it when it was killed (SIGKILL, a power cut...).

    Only folders matching bouncelab's own pattern for this ``out``, owned by this user, last changed before
    ``before`` (the start of this run), not locked by a running ``reproduce`` (each run holds a lock on its
    folders) and holding nothing but report files are removed; anything else is left alone. Returns the
    folders removed.
    """
    removed: list[Path] = []
    try:
        candidates = list(out.parent.iterdir())
    except OSError:
        return removed
    for folder in candidates:
        m = _STAGING.fullmatch(folder.name)
        if m is None or m["name"] != out.name:
            continue
        try:
            st = folder.lstat()
        except OSError:
            continue
        if (not stat.S_ISDIR(st.st_mode) or st.st_uid != os.geteuid() or st.st_mtime >= before
                or not _only_report_files(folder)):
            continue
        fd = _lock(folder)
        if fd is None:  # in use by a running report (or not lockable here): leave it
            continue
        try:
            shutil.rmtree(folder)
            removed.append(folder)
        except OSError:
            pass
        finally:
            _unlock(fd)
    return removed


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
        raise OutputError(f"--out {str(out)!r} exists and is not a folder", path=out, reason="not a folder")
    parent = out.parent
    if not parent.is_dir():
        raise OutputError(f"cannot write the report to {str(out)!r}: the folder {str(parent)!r} does not exist",
                          path=out, reason="no such folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write the report to {str(out)!r}: the folder {str(parent)!r} is not writable",
                          path=out, reason="not writable")
    if not out.exists():
        return
    cwd = Path.cwd()
    if cwd == out or out in cwd.parents:
        raise OutputError(f"--out {str(out)!r} holds the current folder; the report replaces --out as a whole, "
                          "so give a folder below it (e.g. --out report)", path=out, reason="holds the current folder")
    if not os.access(out, os.W_OK | os.X_OK):
        raise OutputError(f"cannot replace {str(out)!r}: the folder is not writable", path=out, reason="not writable")
    # Files and links (a link to a folder counts as the user's: it is never walked into).
    present = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_symlink() or not p.is_dir()}
    if not present:
        return
    ours = _previous_report_files(out)
    if ours is None:
        raise OutputError(f"--out {str(out)!r} is a non-empty folder that is not a bouncelab report; "
                          "give a new or empty folder (a previous report there is replaced as a whole)", path=out,
                          reason="not a bouncelab report")
    foreign = sorted(present - ours)
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise OutputError(f"--out {str(out)!r} holds files that are not part of its previous report ({shown}); "
                          "move them or give another folder (the report is replaced as a whole)", path=out,
                          reason="holds files that are not the report's")


def _swap_in(staging: Path, out: Path) -> None:
    """Put the finished ``staging`` folder at ``out``, the previous report (if any) going away only after."""
    mode = stat.S_IMODE(out.stat().st_mode) if out.exists() else 0o777 & ~_umask()
    os.chmod(staging, mode)
    if not out.exists():
        os.rename(staging, out)
        return
    lock = _lock(out)  # the lock follows the folder: while it is '.NAME.old-...', no other run removes it
    try:
        old = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.old-"))
        os.rmdir(old)
        os.rename(out, old)
        try:
            os.rename(staging, out)
        except BaseException:
            os.rename(old, out)
            raise
        shutil.rmtree(old, ignore_errors=True)
    finally:
        _unlock(lock)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


#: Laws fitted beside the paper's in every report: Walton's tangential restitution and the physics-based laws.
BEYOND_PAPER_LAWS = ("TangentialRestitution", "CompliantImpact", "TurfContact")
#: Laws left out of the report's cross-validation because each fit takes seconds (they integrate every bounce).
NOT_CROSS_VALIDATED = frozenset({"TurfContact", "CraterContact"})
#: Why (the report says so beside Table 3's held-out rows).
NOT_CROSS_VALIDATED_REASON = ("left out to keep the report quick: each fit integrates every bounce through the contact "
                              "and takes seconds to minutes; bouncelab.compare(data, [law]) gives them")
#: The laws whose parameters the report bootstraps (the paper's rigid family).
BOOTSTRAPPED = ("Rigid", "PennerVarying", "PennerFixed")
#: The laws the report assesses (:func:`bouncelab.assess`): the rigid family, whose fits take milliseconds.
ASSESSED = ("Rigid", "PennerVarying", "PennerFixed", "TangentialRestitution")

def _assess_defaults() -> dict[str, int]:
    from inspect import signature

    from bouncelab.fitting.assessment import assess

    params = signature(assess).parameters
    return {name: params[name].default for name in ("k", "starts", "profile_points", "local_points")}


#: The assessment's counts in the report: :func:`bouncelab.assess`'s defaults (its bootstrap resamples are the
#: report's ``bootstrap``, and its folds at most the launcher settings); about 1 to 3 s per law on 693 bounces.
ASSESS_OPTIONS = _assess_defaults()
#: Why a law is not assessed in the report, by law (others: :data:`NOT_ASSESSED_OTHER`).
NOT_ASSESSED = {
    "PiecewiseAffine": "28 numbers in array parameters: an assessment profiles each with about 17 refits by the "
                       "generic global search, hundreds in all, and its plane search has no held parameters",
    "CompliantImpact": "each fit integrates every bounce through the contact (one to a few seconds); an assessment "
                       "refits it about 160 times",
    "TurfContact": "each fit integrates every bounce through the contact (seconds to a minute); an assessment refits "
                   "it some 200 times",
    "CraterContact": "each fit integrates every bounce through the contact (half a minute to a minute or more); an "
                     "assessment refits it some 300 times (docs/physics_laws.md gives one, with reduced counts)",
}
NOT_ASSESSED_OTHER = "not one of the rigid family assessed in the report; an assessment refits a law some 150 times"


def default_laws() -> tuple[str, ...]:
    """The laws of a report unless chosen: the paper's four and :data:`BEYOND_PAPER_LAWS`."""
    from bouncelab.fitting.comparison import PAPER_LAWS

    return (*PAPER_LAWS, *BEYOND_PAPER_LAWS)


def _steps_per_campaign(figures: bool) -> int:
    return 9 + (1 if figures else 0)  # load, 8 analysis steps, figures


def _resolve_laws(law_set: Sequence[Any] | None, laws: Sequence[Any]) -> list[Any]:
    """The report's laws as instances, each once (the first of two with the same name is kept); unknown
    names fail here, before any work."""
    from bouncelab.fitting.comparison import law_instance
    from bouncelab.laws import law_name

    chosen = list(default_laws() if law_set is None else law_set) + list(laws)
    if not chosen:
        raise FitError("no laws to fit: give at least one law", option="law_set",
                       hints=[Hint("law_set", ["Rigid", "PennerFixed"])])
    out: dict[str, Any] = {}
    for law in chosen:
        model = law_instance(law)
        out.setdefault(law_name(model), model)
    return list(out.values())


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
    law_set: Sequence[Any] | None = None,
    bootstrap: int | None = None,
) -> Report:
    """Run the paper's analysis for each campaign and write the report folder.

    A step that cannot run on the data (too few bounces for a law, one slip/roll class only for
    the SVM, no launcher setting with repeats, a figure that cannot be drawn) is skipped: its
    reason is written in the report (index.html and the markdown of its section) and listed in
    :attr:`Report.skipped`, and the rest of the report is written (:attr:`Report.complete` is then
    False). Only the errors that mean "not on these data" (FitError, DataError, ParameterError)
    become skips; anything else still stops the run, leaving the previous report as it was.

    Parameters
    ----------
    campaigns
        Embedded campaigns ("A", "B").
    data
        Paths of bounce-data files (see :func:`bouncelab.load_campaign`).
    out
        Output folder: new, empty, or a previous report (replaced as a whole, only once the new
        one is complete). A folder holding anything else is refused with :class:`OutputError`.
        Staging folders that an earlier, killed run left beside it (``.NAME.new-*``, ``.NAME.old-*``)
        are removed (see :func:`remove_stale_staging`).
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
        cross-validated beside those of ``law_set`` (the command line's ``--law``).
    surrogate
        Which synthetic surrogate the embedded campaigns are (``"turf"`` or ``"published"``; None,
        the default, is :data:`bouncelab.simulation.surrogate.DEFAULT_SURROGATE`, see
        :func:`bouncelab.load_campaign`); the report's notes name it. Ignored when ``load`` is given.
    law_set
        The laws of the report (names in any case, classes or instances; the command line's
        ``--laws``); None, the default, is :func:`default_laws` (the paper's four and
        :data:`BEYOND_PAPER_LAWS`). Table 2 needs PiecewiseAffine among them, the bootstrap one of
        :data:`BOOTSTRAPPED`, the assessment one of :data:`ASSESSED`; without them those steps are
        left out (not skips). The laws not assessed are named in the report with the reason.
    bootstrap
        Resamples of the parameter bootstrap, which is the assessment's (default
        :data:`BOOTSTRAP_RESAMPLES`); 0 leaves it out (the assessment then has no bootstrap
        intervals or correlations).

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
    FitError
        An unknown law, no laws, or a bad ``bootstrap``.
    """
    from bouncelab.data.io import load_campaign
    from bouncelab.data.io.load import EMBEDDED_SURROGATES

    chosen = _resolve_laws(law_set, laws)  # unknown names fail here, before any work
    resamples = BOOTSTRAP_RESAMPLES if bootstrap is None else bootstrap
    # one resample has no spread: assess (whose bootstrap the report shows) takes 0 or at least 2
    if (isinstance(resamples, bool) or not isinstance(resamples, numbers.Integral) or resamples < 0
            or resamples == 1):
        raise FitError(f"bootstrap must be 0 (leaves it out) or a whole number of resamples >= 2; got {bootstrap!r}",
                       option="bootstrap")
    resamples = int(resamples)
    sources = [*campaigns, *data]
    if not sources:
        raise DataError("nothing to reproduce: give campaigns (A, B) or data files", option="campaigns")
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
            raise DataError(f"surrogate must be one of {', '.join(map(repr, EMBEDDED_SURROGATES))}; got {surrogate!r}",
                            option="surrogate")

        def load(src: str) -> xr.Dataset:
            return load_campaign(src, surrogate=surrogate) if src in campaigns else load_campaign(src)
    start = time.perf_counter()
    started = time.time()
    out = Path(out).expanduser()
    if out.is_symlink():
        out = Path(os.path.realpath(out))  # replace the folder the link points to, keep the link
    out = Path(os.path.abspath(out))  # "." and ".." resolved: the swap renames the folder itself
    if out.parent == out:
        raise OutputError(f"--out {str(out)!r} is the root folder; give a folder for the report", path=out,
                          reason="the root folder")
    _check_out(out)
    step = _Progress(len(sources) * _steps_per_campaign(figures) + 1, progress)  # + index.html
    loaded = []
    for src, name in zip(sources, names, strict=True):
        with step(f"loading {src}"):
            loaded.append((name, load(src)))
    for stale in remove_stale_staging(out, started):
        if progress:
            print(f"removed {str(stale)!r}, left by an earlier run that was killed", file=sys.stderr)
    with _sigterm_raises():
        staging = lock = None
        try:
            staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.new-"))
            lock = _lock(staging)  # in use: a run starting meanwhile does not take it for a stale one
            report = _build(loaded, staging, seed, figures, step, start, units, chosen, resamples)
            _swap_in(staging, out)
        except OSError as exc:
            _remove(staging)
            where = f" ({exc.filename})" if exc.filename else ""
            if staging is None:
                raise OutputError(f"cannot write the report beside {str(out)!r}: {exc.strerror or exc}", path=out,
                                  reason=exc.strerror, errno=exc.errno) from None
            raise OutputError(f"cannot write the report to {str(out)!r}{where}: {exc.strerror or exc}; "
                              "the previous report, if any, is unchanged", path=exc.filename or out,
                              reason=exc.strerror, errno=exc.errno) from None
        except BaseException:
            _remove(staging)
            raise
        finally:
            _unlock(lock)
    return _moved(report, staging, out)


def _remove(staging: Path | None) -> None:
    if staging is not None:
        shutil.rmtree(staging, ignore_errors=True)


def _build(loaded: list[tuple[str, xr.Dataset]], out: Path, seed: int, figures: bool, step: _Progress,
           start: float, units: Any, laws: Sequence[Any], bootstrap: int) -> Report:
    """Write the whole report into the (new, empty) folder ``out``."""
    report = Report(out=out, index=out / "index.html")
    if units is not None and (units.velocity, units.spin) != ("radius/s", "rad/s"):
        report.figure_units = {"velocity": units.velocity, "spin": units.spin}
    for name, ds in loaded:
        section = _campaign(name, ds, out, seed, figures, step, report.files, units, laws=laws, bootstrap=bootstrap)
        report.sections[name] = section
        report.skipped += [(name, what, why) for what, why in section.get("skipped", [])]
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
                  sections=report.sections, elapsed=report.elapsed, figure_units=report.figure_units,
                  skipped=list(report.skipped))


def _first_line(exc: BaseException) -> str:
    return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__


def _campaign(name: str, ds: xr.Dataset, out: Path, seed: int, figures: bool, step: _Progress,
              files: list[Path], units: Any, *, laws: Sequence[Any], bootstrap: int) -> dict[str, Any]:
    from bouncelab.analysis.contact_velocity import tangential_summary
    from bouncelab.analysis.repeats import repeatability, repeatability_summary
    from bouncelab.core import published
    from bouncelab.data.settings import infer_settings
    from bouncelab.fitting import compare, fit, split_by_setting
    from bouncelab.fitting.assessment import assess
    from bouncelab.fitting.comparison import SKIPPABLE, generating_law, generator_note
    from bouncelab.laws import PiecewiseAffine, Rigid, law_name

    camp = str(ds.attrs.get("campaign", "")).upper()
    synthetic = ds.attrs.get("data_kind") == "synthetic surrogate"
    generator = generating_law(ds)
    section: dict[str, Any] = {"notes": [], "tables": {}, "figures": {}, "laws": {}, "skipped": [],
                               "figures_skipped": {}, "synthetic": synthetic, "generator": generator,
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
    compared = list(laws) if laws else _resolve_laws(None, ())
    names = [law_name(m) for m in compared]
    section["law_names"] = names

    def skip(what: str, reason: str) -> None:
        section["skipped"].append((what, reason))

    def add(key: str, df: pd.DataFrame, stem: str, title: str, *, percent: bool = False,
            shown: pd.DataFrame | None = None, missing: str = "nan", note: str = "", marked: bool = False) -> None:
        """Write a table as CSV and markdown and show it in the report under ``key``; ``marked``: the table's
        rows are laws, and the one that generated synthetic data is marked."""
        frame = df if shown is None else shown
        mark = generator if marked and generator is not None else None
        md = f"### {title}\n\n" + frame_markdown(frame, percent=percent, missing=missing, mark=mark)
        md += f"\n{note}\n" if note else ""
        if marked and (footnote := generator_note(generator, [str(i) for i in frame.index])) is not None:
            md += f"\n> {footnote}\n"
        _write_table(df, md, tables / f"{name}_{stem}", files)
        section["tables"][key] = md

    def add_markdown(key: str, stem: str, md: str) -> None:
        """A section without numbers (its steps were skipped): the markdown that says why, and no CSV."""
        tables.mkdir(parents=True, exist_ok=True)
        atomic_write_text(tables / f"{name}_{stem}.md", md)
        files.append(tables / f"{name}_{stem}.md")
        section["tables"][key] = md

    def skipped_table(key: str, stem: str, title: str, reason: str) -> str:
        """A section that could not be computed; returns the progress display's status."""
        add_markdown(key, stem, f"### {title}\n\nSkipped: {reason}\n")
        skip(key, reason)
        return f"skipped: {reason}"

    cmp = None
    key3 = "Table 3: laws fitted to all bounces"
    with step(f"{name}: fitting the paper's laws to all bounces (Table 3)") as st:
        try:
            cmp = compare(ds, compared, seed=seed, errors="skip",
                          heldout=[n for n in names if n not in NOT_CROSS_VALIDATED])
        except SKIPPABLE as exc:
            st.status = skipped_table(key3, "table3", f"Laws fitted to campaign {name}", _first_line(exc))
        if cmp is not None:
            for law, why in cmp.skipped.items():
                skip(f"Table 3: {law}", why)
            for law, why in list(cmp.heldout_skipped.items()):
                if law in NOT_CROSS_VALIDATED:
                    cmp.heldout_skipped[law] = NOT_CROSS_VALIDATED_REASON
                else:  # the folds could not be fitted (or one launcher setting only): a step that did not run
                    skip(f"cross-validation: {law}", why)
            md = cmp.to_markdown()
            if "Rigid" in cmp.results:
                try:
                    structured = fit(Rigid, ds, method="structured", seed=seed)
                    md += ("\n### The paper's two-stage procedure for Rigid (r by least squares on ydot, then mu)\n\n"
                           f"r = {structured.model.r:.4g}, mu = {structured.model.mu:.4g}, "
                           f"delta = {100 * structured.delta:.3g} % (global search: delta = "
                           f"{100 * cmp.results['Rigid'].delta:.3g} %)\n")
                except SKIPPABLE as exc:
                    md += f"\n### The paper's two-stage procedure for Rigid\n\nSkipped: {_first_line(exc)}\n"
                    skip("Table 3: the paper's two-stage procedure for Rigid", _first_line(exc))
            if cmp.skipped:
                st.status = f"done, {len(cmp.skipped)} law(s) skipped"
            _write_table(cmp.side_by_side(), md, tables / f"{name}_table3", files)
            section["tables"][key3] = md
            laws_dir = out / "laws"
            laws_dir.mkdir(exist_ok=True)
            for key, res in cmp.results.items():
                path = laws_dir / f"{name}_{campaign_file_name(key)}.json"  # a user law's key holds ':'
                res.model.to_json(path)
                files.append(path)
                section["laws"][key] = path
            section["comparison"] = cmp

    pw: dict[str, Any] = {}
    train = test = None
    split_error = None
    key2 = "Table 2: piecewise-affine law, held-out bounces"
    with step(f"{name}: piecewise-affine law on the paper's split, SVM and delta plane (Table 2)") as st:
        try:
            train, test = split_by_setting(ds, seed)
        except SKIPPABLE as exc:
            split_error = _first_line(exc)
        if "PiecewiseAffine" not in names:
            st.status = "left out (PiecewiseAffine is not among the laws)"
            section["notes"].append("Table 2 is left out: PiecewiseAffine is not among the laws asked for.")
        elif split_error is not None:
            st.status = skipped_table(key2, "table2", f"Piecewise-affine law, campaign {name}, on the paper's split",
                                      f"the paper's split cannot be made: {split_error}")
        else:
            for method, label in (("svm", "paper's SVM plane"), ("plane", "bouncelab's delta-optimal plane")):
                try:
                    pw[label] = fit(PiecewiseAffine, train, test=test, method=method, seed=seed)
                except SKIPPABLE as exc:
                    # e.g. the SVM needs enough bounces of both classes; the rest of the report is written
                    skip(f"Table 2: {label}", f"cannot run on the {train.sizes['bounce']} training bounces of the "
                                              f"split: {_first_line(exc)}")
            if not pw:
                st.status = "skipped"
                md = (f"### Piecewise-affine law, campaign {name}, on the paper's split\n\n"
                      + "".join(f"Skipped ({w.split(': ', 1)[1]}): {r}\n\n" for w, r in section["skipped"]
                                if w.startswith("Table 2: ")))
                add_markdown(key2, "table2", md)
            else:
                if len(pw) < 2:
                    st.status = "done, one plane skipped"
                rows = []
                for label, res in pw.items():
                    for data_name in ("train", "test"):
                        t = res.errors.loc[data_name]
                        diags = res.diagnostics if data_name == "train" else res.test_diagnostics
                        for subset in t.index:
                            rows.append({"method": label, "data": data_name, "subset": subset,
                                         **t.loc[subset].to_dict(),
                                         **{k: (v if subset == "all" else np.nan) for k, v in diags.items()}})
                t2 = pd.DataFrame(rows).set_index(["method", "data", "subset"])
                md = table2_markdown(name, pw, ds)
                for what, why in section["skipped"]:
                    if what.startswith("Table 2: "):
                        md += f"\n> {what.split(': ', 1)[1]}: skipped, {why}\n"
                _write_table(t2, md, tables / f"{name}_table2", files)
                section["tables"][key2] = md
                section["piecewise"] = pw
                for label, res in pw.items():
                    key = "svm" if "SVM" in label else "plane"
                    path = out / "laws" / f"{name}_PiecewiseAffine_{key}_train.json"
                    path.parent.mkdir(exist_ok=True)
                    res.model.to_json(path)
                    files.append(path)

    keycv = "Cross-validation (beyond the paper)"
    keyassess = "Assessment of each law (beyond the paper)"
    assessments: dict[str, Any] = {}
    k = min(ASSESS_OPTIONS["k"], len(np.unique(ds.setting.values)))
    with step(f"{name}: held-out errors and assessment of each law (beyond the paper)") as st:
        # The cross-validated delta of every law, from Table 3's comparison (no refits).
        held = {} if cmp is None else cmp.heldout
        if held:
            cvt = pd.DataFrame({law: {"fitted_delta": cmp.results[law].delta, "heldout_delta": h.scores["delta"],
                                      "heldout_delta_sd": h.scores["delta_sd"]} for law, h in held.items()}).T
            cvt.index.name = "law"
            first = next(iter(held.values()))
            notes = [f"{law}: no held-out delta, {why}." for law, why in cmp.heldout_skipped.items()]
            add(keycv, cvt, "crossvalidation",
                f"Cross-validated delta, campaign {name} ({first.k} folds grouped by launcher setting; fitted_delta "
                "on all bounces)", percent=True, note="\n\n".join(notes), marked=True)
        # The assessment of each affordable law.
        targets = [m for m in compared if law_name(m) in ASSESSED]
        failed: dict[str, str] = {}
        for model in targets:
            try:
                assessments[law_name(model)] = assess(model, ds, seed=seed, n_bootstrap=bootstrap,
                                                      **{**ASSESS_OPTIONS, "k": k})
            except SKIPPABLE as exc:
                failed[law_name(model)] = _first_line(exc)
                skip(f"assessment: {law_name(model)}", _first_line(exc))
        not_assessed = {n: NOT_ASSESSED.get(n, NOT_ASSESSED_OTHER) for n in names if n not in ASSESSED}
        if assessments or failed:
            options = {**ASSESS_OPTIONS, "k": k, "n_bootstrap": bootstrap}
            md = assessment_markdown(name, assessments, options, not_assessed=not_assessed, failed=failed,
                                     generator=generator)
            if assessments:
                frame = pd.concat({law: a.to_frame() for law, a in assessments.items()}, names=["law", "parameter"])
                _write_table(frame, md, tables / f"{name}_assessment", files)
                section["tables"][keyassess] = md
            else:
                add_markdown(keyassess, "assessment", md)
            section["assessments"] = assessments
            section["not_assessed"] = not_assessed
            if failed:
                st.status = f"done, {len(failed)} law(s) skipped" if assessments else "skipped"
        else:
            st.status = f"left out (none of {', '.join(ASSESSED)} is among the laws)"
            section["notes"].append(f"The assessment of each law is left out: none of {', '.join(ASSESSED)} is among "
                                    "the laws (bouncelab.assess(law, data) assesses any law).")

    with step(f"{name}: where the horizontal impulse acts (lever arm, beyond the paper)"):
        from bouncelab.analysis.impulse import lever_arm_summary

        fitted = [] if cmp is None else [res.model for res in cmp.results.values()]
        lever = lever_arm_summary(ds, fitted)
        add("Impulse lever arm (beyond the paper)", lever, "lever_arm",
            f"Lever arm of the horizontal impulse, d(omega)/d(xdot) per bounce, campaign {name}: data and each law "
            "fitted to all bounces, on the same landings",
            note="A law whose whole horizontal impulse acts at the contact point gives 2.5; the centre fraction "
                 "1 - median/2.5 estimates the share passing through the ball's centre (ploughing)"
                 + (f" of the law that generated these synthetic bounces ({generator}), not of any turf"
                    if synthetic and generator else " in these bounces" if synthetic else "")
                 + ". Bounces whose xdot changes by less than 2 % of the landing speed have no lever arm (n_defined).",
            marked=True)

    keyboot = "Parameter uncertainty (beyond the paper)"
    with step(f"{name}: parameter uncertainty, bootstrap over launcher settings (beyond the paper)") as st:
        # The assessment's own bootstrap (the same resamples of whole launcher settings): no refits here.
        frames = {}
        targets = [law_name(m) for m in compared if law_name(m) in BOOTSTRAPPED]
        failed = {}
        for law in targets if bootstrap > 0 else []:
            if law in assessments and assessments[law].bootstrap is not None:
                frames[law] = assessments[law].bootstrap.summary()
            else:  # its assessment was skipped (see there)
                failed[law] = "its assessment could not run on these data"
        if frames:
            boot_table = pd.concat(frames, names=["law", "parameter"])
            add(keyboot, boot_table, "bootstrap",
                f"Parameter uncertainty, campaign {name}: {bootstrap} bootstrap resamples of whole "
                "launcher settings (95 % percentile intervals)", shown=boot_table.reset_index().set_index("law"),
                note="\n\n".join(f"{law}: skipped, {why}" for law, why in failed.items()), marked=True)
            if failed:
                st.status = f"done, {len(failed)} law(s) skipped"
        elif failed:
            st.status = "skipped"
            md = (f"### Parameter uncertainty, campaign {name}\n\n"
                  + "\n\n".join(f"{law}: skipped, {why}" for law, why in failed.items()) + "\n")
            add_markdown(keyboot, "bootstrap", md)
        else:
            why = ("bootstrap resamples set to 0" if bootstrap == 0 else
                   f"none of {', '.join(BOOTSTRAPPED)} is among the laws")
            st.status = f"left out ({why})"
            section["notes"].append(f"The parameter bootstrap is left out: {why}.")

    rep = None
    rep_error = None
    keyrep = "Repeatability"
    with step(f"{name}: repeatability per launcher setting") as st:
        counts = np.unique(ds.setting.values, return_counts=True)[1]
        if not (counts >= 2).any():
            rep_error = (f"no launcher setting has two or more bounces ({len(counts)} settings, one bounce each), "
                         "so no repeat can be compared")
        else:
            try:
                rep = repeatability(ds)
                summ = repeatability_summary(rep)
            except SKIPPABLE as exc:
                rep, rep_error = None, _first_line(exc)
        if rep_error is not None:
            st.status = skipped_table(keyrep, "repeatability_summary", f"Repeatability, campaign {name}", rep_error)
        else:
            rep_df = rep.to_dataframe()
            tables.mkdir(parents=True, exist_ok=True)
            rep_df.to_csv(tables / f"{name}_repeatability.csv")
            files.append(tables / f"{name}_repeatability.csv")
            add(keyrep, summ, "repeatability_summary",
                f"Repeatability, campaign {name}: 95 % CI half-widths of the mean per setting", missing="–",
                note="Medians over the settings. The row 'all' pools the three components for the ratio and the "
                     "fraction of settings whose lift-off interval is wider; it has no median half-width, as the "
                     "components' units differ.")
            section["repeatability"] = rep

    with step(f"{name}: tangential velocities and prediction intervals") as st:
        try:
            tang = tangential_summary(ds)
            add("Tangential velocities", tang, "tangential", f"Tangential velocity v_P = xdot + omega, campaign {name}")
        except SKIPPABLE as exc:
            st.status = skipped_table("Tangential velocities", "tangential", f"Tangential velocity, campaign {name}",
                                      _first_line(exc))
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
        import warnings

        from bouncelab.core.errors import SyntheticDataWarning
        from bouncelab.laws import load_law

        for key, path in section["laws"].items():
            with warnings.catch_warnings():  # the report says once that the data are synthetic
                warnings.simplefilter("ignore", SyntheticDataWarning)
                again = load_law(path)
            if again != cmp.results[key].model:
                raise RuntimeError(f"{path} does not reload to the fitted law")

    if figures:
        with step(f"{name}: figures") as st:
            context = {"cmp": cmp, "pw": pw, "train": train, "test": test, "split_error": split_error,
                       "rep": rep, "rep_error": rep_error, "names": names, "compared": compared, "seed": seed}
            made, not_drawn = _figures(name, ds, context, out / "figures", files, units)
            section["figures"] = made
            section["figures_skipped"] = not_drawn
            for label, why in not_drawn.values():
                skip(label, why)
            if not_drawn:
                st.status = f"done, {len(not_drawn)} not drawn" if made else "skipped"
    return section


def _figures(name: str, ds: xr.Dataset, context: dict[str, Any], folder: Path, files: list[Path],
             units: Any = None) -> tuple[dict[str, Path], dict[str, tuple[str, str]]]:
    """Draw the figures; returns (caption -> file) of those drawn and (caption -> (short name, reason)) of
    those that cannot be drawn on these data."""
    from bouncelab.fitting import fit
    from bouncelab.fitting.comparison import PAPER_LAWS, SKIPPABLE
    from bouncelab.laws import law_name
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
    cmp, names = context["cmp"], context["names"]
    p0, pf = ds.landing.values, ds.liftoff.values
    try:
        svm = fit_svm(np.ascontiguousarray(p0), np.ascontiguousarray(pf))
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
    fig3 = ("Fig. 3: landing conditions, slip/roll classes" + "".join(f", {x}" for x in shown if x)
            + (f" ({'; '.join(absent)})" if absent else ""))

    def held_out_laws() -> dict[str, Any]:
        """Fig. 8's laws, fitted without the held-out bounces it rings (the split of Table 2)."""
        if context["train"] is None:
            raise DataError(f"the paper's split cannot be made: {context['split_error']}")
        laws = {}
        for model in context["compared"]:
            key = law_name(model)
            if key in PAPER_LAWS[:-1]:
                laws[key] = fit(model, context["train"], test=context["test"], seed=context["seed"])
        if "bouncelab's delta-optimal plane" in context["pw"]:
            laws[PAPER_LAWS[-1]] = context["pw"]["bouncelab's delta-optimal plane"]
        if not laws:
            raise DataError("none of the paper's laws was fitted on the split")
        return laws

    def repeatability_figure():
        if context["rep"] is None:
            raise DataError(context["rep_error"])
        return plot_repeatability(context["rep"], units=units)

    figs = {
        fig3: ("fig3_landing_space", "Fig. 3",
               lambda: plot_landing_space(ds, plane_law, support=svm, units=units)),
        "Fig. 6: prediction-interval widths": ("fig6_pi_widths", "Fig. 6", lambda: plot_pi_widths(ds)),
        "Fig. 7: tangential velocity at landing and lift-off":
            ("fig7_tangential", "Fig. 7", lambda: plot_tangential(ds, units=units)),
        "Fig. 8: predicted vs observed lift-off, laws fitted without the ringed held-out bounces":
            ("fig8_predictions", "Fig. 8",
             lambda: plot_predictions(ds, held_out_laws(), test=context["test"], units=units)),
        "Fig. 9: repeatability of each launcher setting": ("fig9_repeatability", "Fig. 9", repeatability_figure),
        "Fig. 10: all landing/lift-off slices": ("fig10_slices", "Fig. 10", lambda: plot_slices(ds, units=units)),
        "Beyond the paper: lever arm of the horizontal impulse, data and every fitted law":
            ("lever_arm", "lever-arm figure", lambda: plot_lever_arm(ds, [res.model for res in fitted.values()])),
    }
    made: dict[str, Path] = {}
    not_drawn: dict[str, tuple[str, str]] = {}
    for caption, (stem, label, draw) in figs.items():
        if stem == "fig6_pi_widths" and "landing_pi" not in ds.data_vars:
            continue
        before = set(plt.get_fignums())
        try:
            fig = draw()
        except SKIPPABLE as exc:
            not_drawn[caption] = (label, _first_line(exc))
            for number in set(plt.get_fignums()) - before:  # only the figure this draw had begun
                plt.close(number)
            continue
        path = save_figure(fig, folder / f"{name}_{stem}.png")
        plt.close(fig)
        files.append(path)
        made[caption] = path
    return made, not_drawn
