"""Writing files safely: only over a regular file or a new name, never over an input, all at once or not at all.

Every file bouncelab writes goes through :func:`atomic_path` (or the helpers built on it):

* the target must be a **regular file or a new name**: a character or block device (``/dev/null``), a
  FIFO, a socket or a folder is refused, so that a write never replaces ``/dev/null`` with a regular file
  (as root it could) nor a pipe another program reads;
* the target must not be **an input** of the running command (:func:`protect_inputs`: the same file, also
  through a symlink or a hard link), so ``bouncelab export LAW.json -o link-to-LAW.json`` cannot overwrite
  the law it reads;
* the file is written to a temporary file in the target's folder, then renamed over it, so that a failed
  write (disk full, a file-size limit, an interrupt, SIGTERM) leaves the previous file intact and never a
  half-written one, and **no temporary file outlives a signal**: during the write SIGTERM raises an
  exception (:func:`sigterm_raises`), the temporary file is removed, then the signal is delivered again
  (the process ends of it, as it would have).

The new file gets the old file's permission bits (or, for a new file, the usual ``0o666`` minus the umask,
not ``mkstemp``'s ``0o600``), and a symlink is kept: the file it points to is replaced, not the link. Every
refusal and every failure is an :class:`~bouncelab.core.errors.OutputError` naming the path, with the
reason; nothing is written then.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import signal
import stat
import tempfile
import threading
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from bouncelab.core.errors import OutputError

__all__ = ["atomic_path", "atomic_write_bytes", "atomic_write_text", "protect_inputs", "sigterm_raises",
           "write_output"]

_KINDS = (
    (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
    (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"),
)

#: The inputs of the running command that no write may replace: (device, inode) -> the name given.
_INPUTS: contextvars.ContextVar[tuple[tuple[tuple[int, int], str], ...]] = contextvars.ContextVar(
    "bouncelab_inputs", default=())


class _Terminated(BaseException):
    """SIGTERM arrived during a write or a run (raised by the handler :func:`sigterm_raises` installs)."""


#: The SIGTERM the handler raised, kept so that code which sees the exception only as something else (NLopt turns
#: an exception in its glue into ForcedStop) can raise it again (:func:`pending_termination`).
_RAISED: list[_Terminated] = []


def pending_termination() -> BaseException | None:
    """The exception SIGTERM raised inside the running :func:`sigterm_raises` block, if it did (else None)."""
    return _RAISED[-1] if _RAISED else None


@contextlib.contextmanager
def sigterm_raises() -> Iterator[None]:
    """During the block, SIGTERM (what ``timeout``, batch schedulers and systemd send) raises an exception,
    so the cleanup that runs for Ctrl-C (an exception) runs for it too; after the cleanup the signal is
    delivered again under the previous handler (by default the process ends of it, as it would have without
    bouncelab). Only in the main thread of a POSIX process, and only when SIGTERM is not ignored; the
    previous handler is restored on the way out. Blocks may nest."""
    if (os.name != "posix" or threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) in (signal.SIG_IGN, None)):
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second SIGTERM does not cut the cleanup short
        _RAISED.append(_Terminated())
        raise _RAISED[-1]

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    except _Terminated:
        signal.signal(signal.SIGTERM, previous)
        os.kill(os.getpid(), signal.SIGTERM)  # the cleanup is done: now what SIGTERM would have done
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
        _RAISED.clear()


@contextlib.contextmanager
def protect_inputs(paths: Iterable[str | os.PathLike[str]]) -> Iterator[None]:
    """During the block, no write through :func:`atomic_path` may replace one of ``paths`` (the files a
    command reads), whatever name it is given: the same file through a symlink or a hard link is refused
    too. Names that are not existing files (an embedded campaign's ``"A"``) are ignored."""
    known = dict(_INPUTS.get())
    for p in paths:
        try:
            st = os.stat(Path(p).expanduser())
        except (OSError, TypeError, ValueError):
            continue
        if stat.S_ISREG(st.st_mode):
            known[(st.st_dev, st.st_ino)] = os.fspath(p)
    token = _INPUTS.set(tuple(known.items()))
    try:
        yield
    finally:
        _INPUTS.reset(token)


def _umask() -> int:
    # os.umask can only be read by setting it; set it back at once.
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _final_target(path: Path) -> Path:
    """The file a write to ``path`` should replace: the end of a chain of symlinks, else ``path``."""
    if path.is_symlink():
        return Path(os.path.realpath(path))
    return path


def _refusal(shown: str, what: str, reason: str, said: str, errno: int | None = None) -> OutputError:
    return OutputError(f"cannot write {what} to {shown!r}: {said}; nothing was written (a file already there is "
                       "unchanged)", path=shown, reason=reason, errno=errno)


def _check_target(target: Path, shown: str, what: str) -> int | None:
    """The permission bits of the regular file at ``target`` (None for a new name), or an OutputError: a
    device, FIFO, socket or folder, or an input of the running command."""
    try:
        st = os.stat(target)
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise _refusal(shown, what, exc.strerror or str(exc), exc.strerror or str(exc), exc.errno) from None
    if not stat.S_ISREG(st.st_mode):
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        follows = f" ({str(target)!r})" if os.fspath(target) != shown else ""
        raise _refusal(shown, what, kind, f"it is {kind}{follows}, not a regular file; bouncelab writes only "
                       "regular files (a new name, or a file it replaces)")
    source = dict(_INPUTS.get()).get((st.st_dev, st.st_ino))
    if source is not None:
        same = "" if os.path.abspath(source) == os.path.abspath(shown) else f" {source!r}"
        raise _refusal(shown, what, "the output is an input", f"it is the input file{same} (the same file"
                       f"{', through a link' if same else ''}): writing it would destroy what is read; give "
                       "another output file")
    return stat.S_IMODE(st.st_mode)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], what: str = "the file") -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on a clean exit it replaces ``path`` in one rename.

    Write the whole file to the yielded path inside the ``with`` block. If the block raises (or SIGTERM
    arrives), the temporary file is removed and ``path`` is untouched. ``what`` names the file in errors
    (``"the law"``).

    Raises
    ------
    OutputError
        Before anything is written: the folder of ``path`` does not exist; ``path`` is a folder, a device
        (``/dev/null``), a FIFO or a socket, also through a symlink; it is an input of the running command
        (:func:`protect_inputs`). After: the write failed (an ``OSError`` of the block or of the rename,
        e.g. a full disk), the previous file kept. An ``OutputError`` is an ``OSError``.
    """
    try:
        shown = os.fspath(path)
        target = _final_target(Path(path).expanduser())
        os.fsencode(target)  # (a NUL or a lone surrogate: no file can have the name)
        if "\0" in shown:
            raise ValueError("embedded null byte")
    except (TypeError, ValueError) as exc:
        raise OutputError(f"cannot write {what} to {path!r}: no file can have this name ({exc})",
                          path=str(path), reason="not a file name") from None
    parent = target.parent
    if not parent.is_dir():
        raise _refusal(shown, what, "no such folder", f"the folder {os.fspath(parent)!r} does not exist")
    mode = _check_target(target, shown, what)
    if mode is None:
        mode = 0o666 & ~_umask()
    with sigterm_raises():
        try:
            fd, tmp_name = tempfile.mkstemp(dir=parent, prefix=f".{target.name}.", suffix=".tmp")
        except OSError as exc:
            raise _refusal(shown, what, exc.strerror or str(exc), exc.strerror or str(exc), exc.errno) from None
        os.close(fd)
        tmp = Path(tmp_name)
        try:
            yield tmp
            os.chmod(tmp, mode)
            _check_target(target, shown, what)  # (it may have become a FIFO or a link to a device meanwhile)
            os.replace(tmp, target)
        except BaseException as exc:
            tmp.unlink(missing_ok=True)
            if isinstance(exc, OSError) and not isinstance(exc, OutputError):
                reason = exc.strerror or str(exc)
                raise _refusal(shown, what, reason, reason, exc.errno) from exc
            raise


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes, what: str = "the file") -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_path`); returns ``path``."""
    with atomic_path(path, what) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
    return Path(path)


def atomic_write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8",
                      what: str = "the file") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_path`); returns ``path``.

    Text that cannot be encoded (a lone surrogate such as ``"\\ud800"``) is an OutputError, before anything
    is written."""
    try:
        data = text.encode(encoding)
    except UnicodeEncodeError as exc:
        raise _refusal(os.fspath(path), what, "text that cannot be encoded",
                       f"the text holds {text[exc.start:exc.end]!r} at position {exc.start}, which {encoding} "
                       "cannot encode (a lone surrogate)") from None
    return atomic_write_bytes(path, data, what)


def write_output(path: str | os.PathLike[str], text: str, what: str) -> Path:
    """:func:`atomic_write_text`, its failure an :class:`~bouncelab.core.errors.OutputError` naming ``what``
    (e.g. ``"the law"``) and the path, with the reason; nothing is written then."""
    return atomic_write_text(path, text, what=what)
