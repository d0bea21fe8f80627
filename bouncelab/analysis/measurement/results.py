"""The results of the estimators: velocity and spin estimates with their intervals, contact detections."""

from __future__ import annotations

from dataclasses import dataclass


class _Interval:
    """``lower`` and ``upper`` ends of an estimate ``value +- half_width``."""

    value: float
    half_width: float

    @property
    def lower(self) -> float:
        """Lower end of the interval."""
        return self.value - self.half_width

    @property
    def upper(self) -> float:
        """Upper end of the interval."""
        return self.value + self.half_width


@dataclass(frozen=True)
class VelocityEstimate(_Interval):
    """A velocity estimated at one time, with the half-width of its interval.

    Attributes
    ----------
    value
        Estimated velocity at ``t_eval``, radii/s.
    half_width
        Half-width of the ``level`` interval (``interval`` kind), radii/s.
    slope
        Fitted acceleration ``dv/dt``, radii/s^2.
    n
        Number of points in the regression (differences or positions).
    level, interval, method
        The options it was computed with.
    """

    value: float
    half_width: float
    slope: float
    n: int
    level: float
    interval: str
    method: str


@dataclass(frozen=True)
class SpinEstimate(_Interval):
    """Mean of spin samples with the half-width of the Student-t CI of the mean.

    Attributes
    ----------
    value
        Mean spin, rad/s.
    half_width
        Half-width of the ``level`` CI of the mean, rad/s.
    std
        Sample standard deviation of the spin samples, rad/s.
    n
        Number of samples.
    level
        Confidence level.
    """

    value: float
    half_width: float
    std: float
    n: int
    level: float


@dataclass(frozen=True)
class ContactDetection:
    """Touch-down and lift-off found in a track.

    Attributes
    ----------
    touchdown_index
        Index of the first frame in contact (the first frame after touch-down).
    liftoff_index
        Index of the last frame in contact (the last frame before lift-off).
    touchdown_time, liftoff_time
        Estimated instants, s, between frames ``touchdown_index - 1`` and
        ``touchdown_index`` (``liftoff_index`` and ``liftoff_index + 1``).
    """

    touchdown_index: int
    liftoff_index: int
    touchdown_time: float
    liftoff_time: float
