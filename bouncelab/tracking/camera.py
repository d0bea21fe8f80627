"""What the camera-file readers share: their error (:class:`CameraFileError`) and the frames missing from a
clip's times (:func:`frame_gaps`)."""

from __future__ import annotations

import mmap
import os
import sys
from pathlib import Path

import numpy as np

from bouncelab.analysis.measurement.input_checks import frame_periods
from bouncelab.core.errors import DataError
from bouncelab.core.files import check_regular_file

__all__ = ["CameraFileError", "MappedFile", "frame_gaps"]


class CameraFileError(DataError):
    """A camera file (``.cine``, ``.mraw`` and its ``.cihx``/``.cih``) that cannot be read as its format says.

    Attributes
    ----------
    file
        The file at fault (the header or the frames' file).
    format
        ``"cine"``, ``"mraw"``, ``"cihx"`` or ``"cih"``.
    field
        The header field at fault (``"ImageCount"``, ``"biCompression"``, ``"Record Rate(fps)"``...), if one is.
    frame
        The frame (0-based, in the file) at fault, if one is.
    """

    def __init__(self, message: str, *, file: str, format: str, field: str | None = None,
                 frame: int | None = None) -> None:
        super().__init__(message, file=file)
        self.format = format
        self.field = field
        self.frame = frame


def frame_gaps(times) -> list[tuple[int, int]]:
    """``(k, missing)`` for each interval of ``times`` that spans more than one frame period (the median
    interval): ``missing`` frames were not recorded between frame ``k`` and frame ``k + 1``."""
    t = np.asarray(times, dtype=float)
    if t.size < 3:
        return []
    steps = np.diff(t)
    if not (np.isfinite(steps).all() and (steps > 0).all()):
        return []
    periods = frame_periods(steps).astype(np.int64)
    return [(int(k), int(periods[k] - 1)) for k in np.flatnonzero(periods > 1)]


class MappedFile:
    """A camera file mapped into memory once (``mmap``), read a frame at a time.

    :meth:`view` gives a frame's bytes without a copy; :meth:`release` tells the kernel the process
    is done with them (``MADV_DONTNEED``), so the pages read leave the process's resident memory and
    reading a file larger than the memory budget takes one frame's worth of it, not the file's. Each
    read checks the file's size first: a file cut short while it is read is an error, not a crash.
    """

    def __init__(self, path, label: str, format: str) -> None:
        self.path, self.label, self.format = path, label, format
        self._fh = None
        self._mm: mmap.mmap | None = None
        self._size: int | None = None

    def _open(self) -> mmap.mmap:
        if self._mm is None:
            check_regular_file(Path(self.path), self.label, max_bytes=sys.maxsize)  # a FIFO would hang the open
            self._fh = open(self.path, "rb")
            size = os.fstat(self._fh.fileno()).st_size
            if size == 0:
                raise CameraFileError("the file is empty", file=self.label, format=self.format)
            self._mm = mmap.mmap(self._fh.fileno(), 0, access=mmap.ACCESS_READ)
        return self._mm

    def view(self, start: int, nbytes: int, frame: int, *, recheck: bool = True) -> np.ndarray:
        """The ``nbytes`` bytes from ``start`` as a uint8 array (a view of the map: copy what you keep).
        ``recheck=False`` skips asking the file's size again (for a second read of the same frame)."""
        mm = self._open()
        size = os.fstat(self._fh.fileno()).st_size if recheck or self._size is None else self._size
        self._size = size
        if start < 0 or start + nbytes > min(size, len(mm)):
            raise CameraFileError(f"the file ends inside frame {frame}: its bytes would end at {start + nbytes:,}, "
                                  f"the file holds {size:,} (truncated)", file=self.label, format=self.format,
                                  frame=frame)
        return np.frombuffer(mm, dtype=np.uint8, count=nbytes, offset=start)

    def release(self, start: int, nbytes: int) -> None:
        """Drop the pages of ``start .. start + nbytes`` from the process's resident memory."""
        if self._mm is None or not hasattr(mmap, "MADV_DONTNEED"):
            return
        page = mmap.PAGESIZE
        lo = start // page * page
        hi = min(-(-(start + nbytes) // page) * page, len(self._mm))
        if hi > lo:
            self._mm.madvise(mmap.MADV_DONTNEED, lo, hi - lo)

    def close(self) -> None:
        if self._mm is not None:
            try:
                self._mm.close()
            except BufferError:  # a view still held by the caller: the map closes when it goes
                pass
            self._mm = None
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    def __del__(self) -> None:
        self.close()

    def __getstate__(self) -> dict:  # a clip sent to another process maps the file there
        return {"path": self.path, "label": self.label, "format": self.format}

    def __setstate__(self, state: dict) -> None:
        self.__init__(state["path"], state["label"], state["format"])
