"""Writing files atomically: a temporary file in the target's folder, then a rename.

Every file bouncelab writes goes through :func:`atomic_path` (or the two helpers
built on it), so that a failed write (disk full, a file-size limit, an
interrupt) leaves the previous file intact and never a half-written one. The
new file gets the old file's permission bits (or, for a new file, the usual
``0o666`` minus the umask, not ``mkstemp``'s ``0o600``), and a symlink is kept:
the file it points to is replaced, not the link.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_write_bytes", "atomic_write_text", "write_output"]


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


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on a clean exit it replaces ``path`` in one rename.

    Write the whole file to the yielded path inside the ``with`` block. If the
    block raises, the temporary file is removed and ``path`` is untouched.

    Raises
    ------
    FileNotFoundError
        The folder of ``path`` does not exist.
    IsADirectoryError
        ``path`` is a directory.
    """
    target = _final_target(Path(path).expanduser())
    parent = target.parent
    if not parent.is_dir():
        raise FileNotFoundError(f"cannot write {os.fspath(path)!r}: the folder {os.fspath(parent)!r} does not exist")
    if target.is_dir():
        raise IsADirectoryError(f"cannot write {os.fspath(path)!r}: it is a directory")
    try:
        mode = stat.S_IMODE(target.stat().st_mode)
    except FileNotFoundError:
        mode = 0o666 & ~_umask()
    fd, tmp_name = tempfile.mkstemp(dir=parent, prefix=f".{target.name}.", suffix=".tmp")
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        yield tmp
        os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see :func:`atomic_path`); returns ``path``."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
    return Path(path)


def atomic_write_text(path: str | os.PathLike[str], text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically (see :func:`atomic_path`); returns ``path``."""
    return atomic_write_bytes(path, text.encode(encoding))


def write_output(path: str | os.PathLike[str], text: str, what: str) -> Path:
    """:func:`atomic_write_text`, its failure an :class:`~bouncelab.core.errors.OutputError` naming ``what``
    (e.g. ``"the law"``) and the path, with the operating system's reason; nothing is written then."""
    from bouncelab.core.errors import OutputError

    try:
        return atomic_write_text(path, text)
    except OSError as exc:
        if exc.strerror:
            said, reason = f"cannot write {what} to {str(path)!r}: {exc.strerror}", exc.strerror
        else:  # atomic_path's own checks say it in full
            said = f"{what}: {exc}"
            reason = {FileNotFoundError: "no such folder", IsADirectoryError: "a folder"}.get(type(exc), str(exc))
        raise OutputError(f"{said}; nothing was written (a file already there is unchanged)", path=str(path),
                          reason=reason, errno=getattr(exc, "errno", None)) from None
