"""What the camera-file readers share: their error (:class:`CameraFileError`) and the frames missing from a
clip's times (:func:`frame_gaps`)."""

from __future__ import annotations

import numpy as np

from bouncelab.analysis.measurement.input_checks import frame_periods
from bouncelab.core.errors import DataError

__all__ = ["CameraFileError", "frame_gaps"]


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
