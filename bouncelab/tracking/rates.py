"""A clip's frame rate: where it may come from, the range a camera's can have, and the check every source goes
through (:func:`check_fps`, :class:`FrameRateError`). Below the readers (``frames``) and the tracker, which both
judge frame rates."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from bouncelab.analysis.measurement import FRAME_RATE_RANGE
from bouncelab.core import checks
from bouncelab.core.errors import DataError, Hint

__all__ = ["FPS_AGREEMENT", "FPS_RANGE", "FPS_SOURCES", "FrameRateError", "agree", "check_fps"]

#: Frame rates a clip may have, frames/s: from 1 (slower is not video) to 10^7 (the fastest framing cameras
#: record some 10^7 frames/s; a golf ball then moves a few micrometres a frame). Beyond them the frame rate is
#: a mistake (a unit, a typo, a damaged file), and the velocities would be as wrong. The measurement's own
#: range (:data:`bouncelab.analysis.measurement.FRAME_RATE_RANGE`).
FPS_RANGE = FRAME_RATE_RANGE

#: Where a clip's frame rate can come from (:attr:`FrameRateError.source`): the ``fps`` given to the function
#: (``--fps`` on the command line), the manifest's ``fps`` column, the file name (through the pattern's ``fps``
#: group) or the clip file itself (the ``fps`` entry of a rendered ``.npz``).
FPS_SOURCES = ("argument", "manifest", "file name", "clip file")

#: Largest relative difference between a frame rate given for a camera file and the rate of the times it
#: records (0.1 %): more is another rate (a typing mistake, the playback rate, a decimated recording), and
#: the file's times are not silently overruled.
FPS_AGREEMENT = 1e-3


class FrameRateError(DataError):
    """A clip's frame rate is missing, not a number, outside :data:`FPS_RANGE`, or disagrees with the rate or
    times the clip file records.

    Attributes
    ----------
    fps
        The value as given (``None`` if missing).
    source
        Where it came from, one of :data:`FPS_SOURCES` (``"argument"``: the
        ``fps`` passed in, ``--fps`` on the command line).
    """

    def __init__(self, message: str, *, fps: Any = None, source: str = "argument", file: str | None = None,
                 hints: Iterable[Hint] = (), **where: Any) -> None:
        super().__init__(message, file=file, hints=hints, **where)
        self.fps = fps
        self.source = source


_SOURCE_TEXT = {"argument": "fps", "manifest": "the manifest's fps", "file name": "the fps in the file name",
                "clip file": "the fps stored in the clip file"}


def check_fps(fps, label: str, source: str = "argument") -> float:
    """The frame rate as a float within :data:`FPS_RANGE`, or a :class:`FrameRateError` naming the clip, the
    value and where it came from (``source``, one of :data:`FPS_SOURCES`)."""
    if source not in FPS_SOURCES:
        raise ValueError(f"source must be one of {FPS_SOURCES}; got {source!r}")
    what = _SOURCE_TEXT[source]
    if fps is None:
        raise FrameRateError("the frame rate is missing", fps=None, source=source, file=label,
                             hints=[Hint("fps", None, "the camera's recording rate, e.g. 5000"),
                                    Hint("manifest", None, "with an fps column")])
    given = fps
    why = ""
    if isinstance(fps, str) and source in ("manifest", "file name"):  # a manifest's cell, a file name's digits
        try:
            fps = float(fps)
        except ValueError:
            why = "text that is not a number"
    else:  # an argument or a file's entry: a real number (not True, "5000" or 5000j: core.checks' rule)
        fps, why = checks.as_float(fps)
    if why:
        raise FrameRateError(f"{what} is not a number of frames per second: {checks.shown(given)} ({why})",
                             fps=given, source=source, file=label) from None
    lo, hi = FPS_RANGE
    if not np.isfinite(fps):
        raise FrameRateError(f"{what} must be a finite number of frames per second; got {given!r}", fps=given,
                             source=source, file=label)
    if not fps > 0:
        raise FrameRateError(f"{what} must be a positive number of frames per second; got {given!r}", fps=given,
                             source=source, file=label)
    if not lo <= fps <= hi:
        raise FrameRateError(f"{what} {fps:g} frames/s is not a camera's frame rate (bouncelab takes "
                             f"{lo:g} to {hi:g} frames/s, bouncelab.tracking.FPS_RANGE): a unit or typing mistake?",
                             fps=given, source=source, file=label)
    return fps


def agree(fps, own: float, fps_source: str, label: str, records: str) -> None:
    """A FrameRateError where a given ``fps`` disagrees with the rate ``own`` (checked) the file records by more than
    :data:`FPS_AGREEMENT`; ``records`` says what the file records and what to do."""
    if fps is not None and abs(float(fps) / own - 1.0) > FPS_AGREEMENT:
        raise FrameRateError(f"{_SOURCE_TEXT[fps_source]} {float(fps):g} frames/s disagrees with {records}",
                             fps=fps, source=fps_source, file=label)
