"""Reading a whole file safely: only regular files, of a bounded size, without hanging on a FIFO.

Every file bouncelab reads that a person names (a campaign, a law, a surface, a posterior, a camera
clip) is checked by :func:`check_regular_file` or read by :func:`read_regular_file`: a FIFO would hang
a read, ``/dev/zero`` would never end, and a file of many gigabytes is not a bounce campaign. Every
refusal is a :class:`~bouncelab.core.errors.DataError` naming the file (a missing file a
:class:`~bouncelab.core.errors.MissingFileError`, also a ``FileNotFoundError``). (Writing goes through
:mod:`bouncelab.core.atomic`.)
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from bouncelab.core.errors import DataError, MissingFileError

__all__ = ["MAX_FILE_BYTES", "check_regular_file", "read_head", "read_regular_file", "read_regular_text"]

#: Largest file bouncelab reads, in bytes (1 GiB: some ten million bounces as CSV).
MAX_FILE_BYTES = 1 << 30

_KINDS = (
    (stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"),
)


def check_regular_file(path: Path, file: str, max_bytes: int = MAX_FILE_BYTES) -> os.stat_result:
    """The file's status, or a DataError naming ``file`` for anything but a regular file of at most ``max_bytes``."""
    try:
        st = path.stat()  # follows symlinks: a link to /dev/zero is a device
    except (OSError, ValueError) as exc:
        raise _unreadable(exc, file) from None
    _refuse_irregular(st, file, max_bytes)
    return st


def read_regular_file(path: Path, file: str, max_bytes: int = MAX_FILE_BYTES) -> bytes:
    """The whole file, read without blocking on a FIFO that replaced it since a check (DataError naming ``file``)."""
    fd = _open_nonblocking(path, file)
    try:
        with os.fdopen(fd, "rb") as fh:
            st = os.fstat(fh.fileno())
            _refuse_irregular(st, file, max_bytes)
            # read what the file holds (a read of max_bytes would reserve a GiB), then anything it grew by
            data = fh.read(min(st.st_size, max_bytes) + 1)
            if len(data) > st.st_size:
                data += fh.read(max_bytes + 1 - len(data))
    except OSError as exc:  # (a DataError is not an OSError: it passes through)
        raise _unreadable(exc, file) from None
    if len(data) > max_bytes:
        raise DataError(f"the file is larger than the {max_bytes / 2**30:g} GiB bouncelab reads", file=file)
    return data


def read_head(path: Path, file: str, nbytes: int) -> bytes:
    """At most the first ``nbytes`` bytes of the regular file ``path`` (a header; a longer file is not refused,
    its rest not read), or a DataError naming ``file``: missing, a FIFO, a device, a folder."""
    fd = _open_nonblocking(path, file)
    try:
        with os.fdopen(fd, "rb") as fh:
            _refuse_irregular(os.fstat(fh.fileno()), file)
            return fh.read(nbytes)
    except OSError as exc:
        raise _unreadable(exc, file) from None


def read_regular_text(path: Path, file: str, max_bytes: int = MAX_FILE_BYTES) -> str:
    """:func:`read_regular_file` decoded as UTF-8 (a byte-order mark dropped); text that is not UTF-8 a DataError
    naming ``file`` and the byte."""
    data = read_regular_file(path, file, max_bytes)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DataError(f"the file is not UTF-8 text (byte {exc.start}: {data[exc.start:exc.start + 1]!r})",
                        file=file) from None


def _open_nonblocking(path: Path, file: str) -> int:
    """A read-only descriptor of ``path`` that does not block on a FIFO, or the DataError naming ``file``."""
    try:
        return os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as exc:  # (ValueError: a NUL or a lone surrogate in the name)
        raise _unreadable(exc, file) from None


def _refuse_irregular(st: os.stat_result, file: str, max_bytes: int | None = None) -> None:
    """A DataError naming ``file`` and what it is unless ``st`` is a regular file of at most ``max_bytes``
    (None: any size)."""
    if not stat.S_ISREG(st.st_mode):
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "some other kind of file")
        raise DataError(f"it is {kind}, not a regular file; bouncelab reads data only from regular files",
                        file=file)
    if max_bytes is not None and st.st_size > max_bytes:
        raise DataError(f"the file is {st.st_size / 2**30:.1f} GiB, more than the {max_bytes / 2**30:g} GiB "
                        "bouncelab reads (bouncelab.core.files.MAX_FILE_BYTES)", file=file)


def _unreadable(exc: OSError | ValueError, file: str) -> DataError:
    """The DataError of a file that cannot be opened: missing (a MissingFileError), a permission, a name no
    file can have, ..."""
    if isinstance(exc, ValueError):  # a NUL byte, or a character the file system cannot encode
        return DataError(f"no file can have this name ({exc})", file=file)
    if isinstance(exc, FileNotFoundError):
        return MissingFileError("no such file", file=file)
    if isinstance(exc, PermissionError):
        return DataError("permission denied: the file cannot be read", file=file)
    if isinstance(exc, IsADirectoryError):
        return DataError("it is a folder, not a regular file; bouncelab reads data only from regular files", file=file)
    if isinstance(exc, NotADirectoryError):
        return MissingFileError("no such file (a part of its path is not a folder)", file=file)
    return DataError(f"the file cannot be read ({exc.strerror or exc})", file=file)
