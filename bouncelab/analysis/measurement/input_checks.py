"""Checks of the inputs shared by the estimators: 1-D finite arrays, equally spaced frame
times, coverage levels and integer options.
"""

from __future__ import annotations

import numpy as np

from bouncelab.core import checks
from bouncelab.core.errors import DataError

#: Largest relative deviation of a frame interval from the mean interval that is
#: accepted as timing jitter (timestamps rounded to 1 us at 7000 fps deviate by 0.35 %).
JITTER_RTOL = 0.01

#: Frame rates a tracked bounce may have, frames/s: from 1 (slower is not video) to 10^7 (the fastest framing
#: cameras; a golf ball then moves micrometres a frame). Frame times whose interval is outside
#: 1/10^7 s to 1 s are a unit or typing mistake (times in microseconds, a frame rate of 1e300), and beyond
#: them the estimators' arithmetic would overflow or divide by zero.
FRAME_RATE_RANGE = (1.0, 1.0e7)


def _as_1d(value, name: str) -> np.ndarray:
    arr = checks.real_array(value, name, "one value per frame", error=DataError)
    if arr.ndim != 1:
        raise DataError(f"{name} must be 1-D (one value per frame); got shape {arr.shape}", column=name, option=name)
    return arr


def _check_finite(arr: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        k = int(np.argmax(bad))
        raise DataError(f"{name} is NaN or infinite at frame {k} ({int(bad.sum())} bad value(s))", column=name)


def _frame_interval(t: np.ndarray, *, jitter_rtol: float = JITTER_RTOL, missing_frames: bool = False) -> float:
    """The constant frame interval ``dt`` of times ``t``; DataError if they are not equally spaced.

    With ``missing_frames``, an interval may span a whole number of frame periods (frames a camera dropped,
    whose times the file records): ``dt`` is then the period, each interval within ``jitter_rtol`` of a
    multiple of it."""
    checks.positive(jitter_rtol, "jitter_rtol", allow_zero=True, error=DataError)
    _check_finite(t, "t")
    if t.size < 2:
        raise DataError(f"need at least 2 frame times; got {t.size}", column="t")
    steps = np.diff(t)
    if not (steps > 0).all():
        k = int(np.argmax(steps <= 0))
        raise DataError(f"frame times must increase; t[{k + 1}] <= t[{k}]", column="t")
    periods = frame_periods(steps) if missing_frames else None
    if periods is not None:
        dt = float(t[-1] - t[0]) / float(periods.sum())
        steps = steps / periods
    else:
        dt = float(t[-1] - t[0]) / (t.size - 1)
    lo, hi = FRAME_RATE_RANGE
    if not 1.0 / hi <= dt <= 1.0 / lo:
        raise DataError(
            f"the frame interval is {dt:.6g} s ({1.0 / dt if dt > 0 else float('inf'):.6g} frames/s): frame times "
            f"must be in seconds, from a camera of {lo:g} to {hi:g} frames/s "
            "(bouncelab.analysis.measurement.FRAME_RATE_RANGE)", column="t")
    dev = np.abs(steps - dt) / dt
    if dev.max() > jitter_rtol:
        k = int(np.argmax(dev))
        if periods is not None:
            raise DataError(
                f"frame times are not on one frame period: the interval after frame {k} is "
                f"{steps[k] * periods[k]:.6g} s, {dev[k]:.1%} off {int(periods[k])} period(s) of {dt:.6g} s "
                f"(tolerance {jitter_rtol:.1%})", column="t")
        raise DataError(
            f"frame times are not equally spaced: the interval after frame {k} is {steps[k]:.6g} s "
            f"against a mean of {dt:.6g} s ({dev[k]:.1%} off; tolerance {jitter_rtol:.1%}). The "
            "paper's method assumes a constant frame interval: were frames dropped?",
            column="t",
        )
    return dt


def frame_periods(steps: np.ndarray) -> np.ndarray:
    """Whole frame periods each interval ``steps`` spans (1 where no frame is missing), taking the period
    as the median interval (most frames are not dropped)."""
    base = float(np.median(steps))
    return np.maximum(np.rint(steps / base), 1.0) if base > 0 else np.ones_like(steps)


def _check_level(level: float) -> float:
    return checks.fraction(level, "level", error=DataError)


def _check_int_at_least(name: str, value, low: int) -> None:
    """DataError unless ``value`` is an integer (not a bool) of at least ``low``."""
    checks.count(value, name, low, error=DataError)
