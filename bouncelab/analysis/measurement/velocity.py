"""Velocity at touch-down or lift-off from tracked positions: the paper's fit of finite
differences, or a quadratic fit of the positions (:func:`estimate_velocity`).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from scipy import stats

from bouncelab.analysis.measurement.input_checks import (
    JITTER_RTOL,
    _as_1d,
    _check_finite,
    _check_level,
    _frame_interval,
    frame_periods,
)
from bouncelab.analysis.measurement.results import VelocityEstimate
from bouncelab.core import checks
from bouncelab.core.errors import DataError

IntervalKind = Literal["prediction", "confidence"]
VelocityMethod = Literal["differences", "positions"]
_INTERVALS = ("prediction", "confidence")
_METHODS = ("differences", "positions")


def _check_velocity_options(level: float, interval: str, method: str) -> float:
    """The checked ``level``; DataError for an unknown ``interval`` or ``method``."""
    level = _check_level(level)
    if interval not in _INTERVALS:
        raise DataError(f"interval must be one of {_INTERVALS}; got {interval!r}", option="interval")
    if method not in _METHODS:
        raise DataError(f"method must be one of {_METHODS}; got {method!r}", option="method")
    return level


def estimate_velocity(
    t,
    pos,
    t_eval: float,
    *,
    level: float = 0.95,
    interval: IntervalKind = "prediction",
    method: VelocityMethod = "differences",
    jitter_rtol: float = JITTER_RTOL,
    missing_frames: bool = False,
) -> VelocityEstimate:
    """Velocity at ``t_eval`` from tracked positions, with its interval (paper's method by default).

    Parameters
    ----------
    t
        Frame times, s: strictly increasing, equally spaced (``dt``) up to
        ``jitter_rtol``.
    pos
        Tracked coordinate at each frame (``x`` or ``y``), radii.
    t_eval
        Time at which to evaluate the velocity (touch-down or lift-off), s.
    level
        Coverage level of the interval, in (0, 1).
    interval
        ``"prediction"`` (default, the paper's PI) or ``"confidence"``.
    method
        ``"differences"`` (default, the paper) or ``"positions"`` (a quadratic
        fit of the positions, whose CI is calibrated; see Notes).
    jitter_rtol
        Largest accepted relative deviation of a frame interval from the mean.
    missing_frames
        Accept intervals of a whole number of frame periods (frames a camera
        dropped, at the times its file records). A difference across ``k``
        periods is divided by its own interval and assigned half a frame
        after its mid-time, as every other difference is.

    Returns
    -------
    VelocityEstimate
        ``value`` (radii/s), ``half_width``, ``slope`` (radii/s^2) and ``n``.

    Notes
    -----
    **Differences (the paper).** With ``dt = (t_N - t_1)/(N - 1)`` the
    ``n = N - 1`` finite differences

    .. math:: d_i = \\frac{x_{i+1} - x_i}{\\Delta t}, \\qquad \\tau_i = t_{i+1},

    are fitted with ``v(t) = m t + c`` minimising
    ``sum_i (d_i - v(tau_i))^2``. With ``s^2 = RSS/(n - 2)``,
    ``S = sum (tau_i - mean tau)^2`` and ``q`` the ``(1 + level)/2`` quantile of
    Student's t with ``n - 2`` degrees of freedom, the half-widths at
    ``t_e = t_eval`` are

    .. math::

        h_{CI} = q\\, s \\sqrt{\\tfrac1n + \\tfrac{(t_e - \\bar\\tau)^2}{S}}, \\qquad
        h_{PI} = q\\, s \\sqrt{1 + \\tfrac1n + \\tfrac{(t_e - \\bar\\tau)^2}{S}}.

    The PI is that of one new difference observed at ``t_e`` (MATLAB's
    ``predint`` default, the paper's tool); the CI is that of the line.
    A difference quotient equals the velocity at the mid-frame time, so the
    paper's assignment to ``t_{i+1}`` lags by half a frame: a bias of
    ``a dt / 2`` for an acceleration ``a`` (0.05 radii/s for gravity at
    5 kfps, negligible).

    **Positions.** Ordinary least squares of the ``N`` positions on
    ``a + b u + c u^2`` with ``u = t - t_e`` gives ``v(t_e) = b`` (slope
    ``2c``); ``h_CI = q s_b`` with ``N - 3`` degrees of freedom. Its
    ``"prediction"`` interval is, as in the paper, that of one new difference
    at ``t_e``: ``q sqrt(s_b^2 + 2 s^2/dt^2)``. Position errors are
    independent, so this CI is exact for a quadratic path (it is the
    generalised-least-squares fit of the differences with their true,
    correlated covariance) and nearly so in flight with drag.

    **Coverage** of the true velocity at the nominal 95 %, measured by
    :func:`~bouncelab.analysis.measurement.interval_coverage` (2000 bounces at
    the default noise: 0.003 radii, 5000 fps, 40 frames a side): paper PI
    100 % and paper CI 100 % (both
    conservative, the CI by a factor of ~4 in width, because consecutive
    differences have errors correlated -1/2); positions CI 95 % (calibrated).

    Raises
    ------
    DataError
        Mismatched lengths, fewer than 4 frames, NaN or infinite values,
        non-increasing or unequally spaced times, a frame interval outside
        :data:`~bouncelab.analysis.measurement.FRAME_RATE_RANGE` (times not in
        seconds), values whose fit overflows, bad options.

    Examples
    --------
    >>> t = np.arange(10) / 5000.0
    >>> est = estimate_velocity(t, 3.0 + 800.0 * t - 229.7 * t**2, t[-1], method="positions")
    >>> round(est.value, 6), round(est.slope, 6)  # 800 - 2 * 229.7 * t[-1], -2 * 229.7
    (799.17308, -459.4)
    """
    level = _check_velocity_options(level, interval, method)
    tt = _as_1d(t, "t")
    xx = _as_1d(pos, "pos")
    if tt.size != xx.size:
        raise DataError(f"t and pos must have the same length; got {tt.size} and {xx.size}", column="pos", option="pos")
    if tt.size < 4:
        raise DataError(f"need at least 4 frames to estimate a velocity with an interval; got {tt.size}", column="t")
    _check_finite(xx, "pos")
    dt = _frame_interval(tt, jitter_rtol=jitter_rtol, missing_frames=missing_frames)
    t_e, why = checks.as_float(t_eval)
    if why:
        raise DataError(f"t_eval must be a time in s; got {checks.shown(t_eval)} ({why})", option="t_eval")
    if not np.isfinite(t_e):
        raise DataError(f"t_eval must be finite; got {t_eval!r}", option="t_eval")

    try:
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # inf and NaN are refused below
            value, slope, var, n, dof = _fit(tt, xx, dt, t_e, interval, method)
    except (OverflowError, ZeroDivisionError, np.linalg.LinAlgError):
        value = slope = var = float("nan")
        dof = tt.size - (2 if method == "differences" else 3)
    if not (np.isfinite(value) and np.isfinite(slope) and np.isfinite(var)):
        # values so large (or times so far from t_eval) that the arithmetic overflows: no estimate, not inf/NaN
        raise DataError(f"the velocity at t_eval = {t_e:g} s cannot be computed in floating point (positions up "
                        f"to {float(np.abs(xx).max()):.3g}, times {tt[0]:.6g} to {tt[-1]:.6g} s)", column="pos")
    q = float(stats.t.ppf(0.5 + level / 2.0, dof))
    return VelocityEstimate(
        value=float(value),
        half_width=q * float(np.sqrt(max(var, 0.0))),
        slope=float(slope),
        n=int(n),
        level=level,
        interval=interval,
        method=method,
    )


def _fit(tt: np.ndarray, xx: np.ndarray, dt: float, t_e: float, interval: str, method: str):
    """(value, slope, variance, n, degrees of freedom) of the velocity fit (see :func:`estimate_velocity`)."""
    if method == "differences":
        steps = np.diff(tt)
        if (frame_periods(steps) > 1).any():  # dropped frames: each difference over its own interval
            d = np.diff(xx) / steps
            tau = tt[1:] - 0.5 * (steps - dt)  # half a frame after its mid-time, as the others
        else:
            d = np.diff(xx) / dt
            tau = tt[1:]
        n = d.size
        tau_bar = tau.mean()
        tc = tau - tau_bar
        sxx = float(tc @ tc)
        slope = float(tc @ d) / sxx
        mean_d = float(d.mean())
        resid = d - (mean_d + slope * tc)
        dof = n - 2
        s2 = float(resid @ resid) / dof
        lever = 1.0 / n + (t_e - tau_bar) ** 2 / sxx
        value = mean_d + slope * (t_e - tau_bar)
        var = s2 * (lever + (1.0 if interval == "prediction" else 0.0))
    else:
        n = xx.size
        u = (tt - t_e) / dt  # in frames, for conditioning
        design = np.stack([np.ones(n), u, u**2], axis=1)
        coef, *_ = np.linalg.lstsq(design, xx, rcond=None)
        resid = xx - design @ coef
        dof = n - 3
        s2 = float(resid @ resid) / dof
        cov = s2 * np.linalg.inv(design.T @ design)
        value = float(coef[1]) / dt
        slope = 2.0 * float(coef[2]) / dt**2
        var = cov[1, 1] / dt**2 + (2.0 * s2 / dt**2 if interval == "prediction" else 0.0)
    return value, slope, var, n, dof
