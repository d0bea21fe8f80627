"""The report's folder: refused before any work when it could not be replaced safely, built beside it,
swapped in only when complete.

The report is built in a hidden folder beside ``out`` (``.NAME.new-XXXXXXXX``) and swapped in only when
every file is written, so a failed run (a bad file, a full disk, an interrupt, SIGTERM) leaves the
previous report as it was; a hidden folder that a killed run left is removed by the next run
(:func:`remove_stale_staging`). ``out`` must be new, empty, or a previous report whose files are all
bouncelab's (listed in its ``.bouncelab-report.json``); any other folder is refused before any work, so
files a user keeps there are never deleted. Every file is written atomically
(:mod:`bouncelab.core.atomic`).
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from bouncelab.core.atomic import _Terminated, atomic_write_bytes, atomic_write_text  # noqa: F401 (named here by report.pipeline)
from bouncelab.core.atomic import sigterm_raises as _sigterm_raises
from bouncelab.core.errors import OutputError
from bouncelab.core.files import read_regular_file, read_regular_text
from bouncelab.report.model import Report

__all__ = ["MANIFEST", "check_out", "remove_stale_staging", "staged", "write_report"]

#: The file in a report folder that lists every file bouncelab wrote there (relative paths).
MANIFEST = ".bouncelab-report.json"


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



def _previous_report_files(out: Path) -> set[str] | None:
    """Relative paths of the files a previous report in ``out`` consists of; None if it is not one."""
    manifest = out / MANIFEST
    if manifest.is_file():
        try:
            listed = json.loads(read_regular_text(manifest, str(manifest)))["files"]
        except (ValueError, KeyError, TypeError, OSError):  # (a FIFO or a device: a DataError, a ValueError)
            return None
        return {str(f) for f in listed} | {MANIFEST}
    index = out / "index.html"
    if index.is_file():  # an older report, from before the manifest: its index lists its files
        try:
            text = read_regular_file(index, str(index)).decode("utf-8", errors="replace")
        except (OSError, ValueError):  # (a FIFO or a device: a DataError, a ValueError)
            return None
        if "<title>bouncelab report</title>" in text:
            import html

            return {html.unescape(f) for f in re.findall(r"<li><a href='([^']*)'>", text)} | {"index.html"}
    return None


def check_out(out: Path) -> None:
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




def resolve_out(out: str | os.PathLike[str]) -> Path:
    """``out`` as the absolute folder the swap replaces: a symlinked ``out`` is followed (the link is kept), and
    "." and ".." are resolved (the swap renames the folder itself); the root folder is refused."""
    path = Path(out).expanduser()
    if path.is_symlink():
        path = Path(os.path.realpath(path))  # replace the folder the link points to, keep the link
    path = Path(os.path.abspath(path))
    if path.parent == path:
        raise OutputError(f"--out {str(path)!r} is the root folder; give a folder for the report", path=path,
                          reason="the root folder")
    return path


def _remove(staging: Path | None) -> None:
    if staging is not None:
        shutil.rmtree(staging, ignore_errors=True)


@contextlib.contextmanager
def staged(out: Path) -> Iterator[Path]:
    """A new hidden folder beside ``out`` to build the report in, locked while the block runs and swapped in
    for ``out`` when it ends cleanly; removed if it does not (an error, Ctrl-C, SIGTERM), the previous report
    left as it was. An OSError becomes an :class:`OutputError` naming the path."""
    with _sigterm_raises():
        staging = lock = None
        try:
            staging = Path(tempfile.mkdtemp(dir=out.parent, prefix=f".{out.name}.new-"))
            lock = _lock(staging)  # in use: a run starting meanwhile does not take it for a stale one
            yield staging
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


def _write_table(frame: Any, markdown: str | None, base: Path) -> None:
    """A table's CSV (when it has numbers) and markdown (when it is shown), each written atomically."""
    if frame is not None:
        atomic_write_text(base.with_suffix(".csv"), frame.to_csv())
    if markdown is not None:
        atomic_write_text(base.with_suffix(".md"), markdown)


def write_report(report: Report, folder: Path) -> list[str]:
    """Write every table, fitted law and figure of ``report``, its ``index.html`` and its manifest into the
    (new, empty) ``folder``; returns the files written, relative to it."""
    from bouncelab.report.page import report_html

    written: list[str] = []
    for name, sec in report.sections.items():
        for sub in ("tables", "laws", "figures"):
            if any(f.startswith(f"{sub}/") for f in sec.files()):
                (folder / sub).mkdir(exist_ok=True)
        for table in sec.tables.values():
            _write_table(table.frame, table.markdown, folder / "tables" / f"{name}_{table.stem}")
        for law in sec.laws.values():
            law.model.to_json(folder / law.files(name)[0])
        for figure in sec.figures.values():
            if figure.png is not None:
                atomic_write_bytes(folder / figure.files(name)[0], figure.png)
        written += sec.files()
    written.append("index.html")
    report.files = [report.out / f for f in written] if report.out is not None else []
    atomic_write_text(folder / "index.html", report_html(report, inline=False, standalone=True))
    atomic_write_text(folder / MANIFEST, json.dumps({"written_by": "bouncelab reproduce", "files": sorted(written)},
                                                    indent=1) + "\n")
    return written
