"""The paper's measurement procedure over many tracked bounces at once (:func:`measure_frames`).

:func:`bouncelab.analysis.measurement.measure_bounce` measures one bounce in
about 25 ms (contact detection about 10 ms), too slow for calibrating a
simulator on thousands of campaigns. :func:`measure_frames` computes the
same estimators for all bounces of a :class:`~bouncelab.simulation.camera.Frames`
together, with the same formulas and defaults:

* contact by :func:`~bouncelab.analysis.measurement.detect_contact`
  (``contact_model="flat"``: three-piece least-squares segmentation of the
  height of the lowest visible point, BIC against one quadratic, both kinks
  5 standard errors clear of 0, touch-down and lift-off where the flight
  quadratics meet the contact line);
* velocities by :func:`~bouncelab.analysis.measurement.estimate_velocity`
  (``method="differences"``, ``interval="prediction"``: the paper's line fit
  of finite differences and its 95 % prediction interval at the detected
  instant);
* spins by :func:`~bouncelab.analysis.measurement.estimate_spin` (mean and
  Student-t CI of the mean);

with ``guard = 1`` frame left out next to each contact instant, as
:func:`~bouncelab.analysis.measurement.measure_bounce` does. The library's own
functions remain the reference: ``tests/test_simulation.py`` checks that both
give the same contact frames and the same states and intervals (to rounding)
on simulated clips. Bounces whose contact is not detected, or with too few
frames on a side, are flagged in ``ok`` instead of raising.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from bouncelab.simulation.camera import Frames

__all__ = ["FrameMeasurement", "measure_frames"]

_KINK_SIGMAS = 5.0  # as bouncelab.analysis.measurement.contact


@dataclass(frozen=True)
class FrameMeasurement:
    """Measured states of many bounces (rows), as :func:`~bouncelab.analysis.measurement.measure_bounce` gives one.

    ``landing``, ``liftoff``, ``landing_pi``, ``liftoff_pi`` are (n, 3) in scaled
    units (NaN where ``ok`` is False); ``touchdown_index``, ``liftoff_index``
    (first and last contact frame) and ``touchdown_time``, ``liftoff_time`` (s)
    are (n,); ``ok`` (n,) is False where the contact was not detected or a
    side had fewer than ``min_frames`` frames.
    """

    landing: np.ndarray
    liftoff: np.ndarray
    landing_pi: np.ndarray
    liftoff_pi: np.ndarray
    touchdown_index: np.ndarray
    liftoff_index: np.ndarray
    touchdown_time: np.ndarray
    liftoff_time: np.ndarray
    ok: np.ndarray


def measure_frames(
    frames: Frames,
    *,
    level: float = 0.95,
    guard: int = 1,
    min_flight: int = 4,
    min_contact: int = 2,
    min_frames: int = 5,
    chunk: int = 64,
) -> FrameMeasurement:
    """Detect contact and estimate landing and lift-off states with their intervals, for every bounce.

    Parameters
    ----------
    frames
        Tracks from :meth:`~bouncelab.simulation.camera.Camera.film`.
    level
        Coverage level of all intervals.
    guard, min_frames
        As :func:`~bouncelab.analysis.measurement.measure_bounce`.
    min_flight, min_contact
        As :func:`~bouncelab.analysis.measurement.detect_contact`.
    chunk
        Bounces segmented at once (memory: about ``chunk * N^2 * 40`` bytes for N frames).
    """
    t = np.asarray(frames.t, dtype=float)
    n, N = frames.x.shape
    dt = float(t[-1] - t[0]) / (N - 1)
    i_idx = np.empty(n, dtype=np.int64)
    j_idx = np.empty(n, dtype=np.int64)
    t_down = np.empty(n)
    t_up = np.empty(n)
    ok = np.empty(n, dtype=bool)
    for start in range(0, n, chunk):
        sl = slice(start, min(start + chunk, n))
        i_idx[sl], j_idx[sl], t_down[sl], t_up[sl], ok[sl] = _detect(
            t, dt, frames.lowest[sl], min_flight, min_contact
        )
    stop_b = np.maximum(i_idx - guard, 0)
    start_a = np.minimum(j_idx + 1 + guard, N)
    ok &= (stop_b >= min_frames) & (N - start_a >= min_frames)
    zeros = np.zeros(n, dtype=np.int64)
    full = np.full(n, N, dtype=np.int64)
    landing, landing_pi = _side(frames, t, dt, zeros, stop_b, t_down, level)
    liftoff, liftoff_pi = _side(frames, t, dt, start_a, full, t_up, level)
    for arr in (landing, landing_pi, liftoff, liftoff_pi):
        arr[~ok] = np.nan
    return FrameMeasurement(landing, liftoff, landing_pi, liftoff_pi, i_idx, j_idx, t_down, t_up, ok)


def _side(frames: Frames, t, dt, start, stop, t_eval, level) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (paper's differences, PI) and spin (mean, CI) on frames ``start .. stop-1`` of each row."""
    n, N = frames.x.shape
    cols = np.arange(N)
    # Differences d_k = (x_{k+1} - x_k)/dt at tau_k = t_{k+1}, for k = start .. stop-2.
    k = cols[:-1][None, :]
    w = ((k >= start[:, None]) & (k <= stop[:, None] - 2)).astype(float)
    m = w.sum(axis=1)
    tau = t[1:][None, :]
    with np.errstate(invalid="ignore", divide="ignore"):
        tau_bar = (w * tau).sum(axis=1) / m
        tcen = (tau - tau_bar[:, None]) * w
        sxx = (tcen * tcen).sum(axis=1)
        q = stats.t.ppf(0.5 + level / 2.0, np.maximum(m - 2, 1))
        lever = 1.0 / m + (t_eval - tau_bar) ** 2 / sxx
        out = np.empty((n, 3))
        half = np.empty((n, 3))
        for c, pos in enumerate((frames.x, frames.y)):
            d = np.diff(pos, axis=1) / dt
            slope = (tcen * d).sum(axis=1) / sxx
            mean_d = (w * d).sum(axis=1) / m
            resid = (d - (mean_d[:, None] + slope[:, None] * (tau - tau_bar[:, None]))) * w
            s2 = (resid * resid).sum(axis=1) / (m - 2)
            out[:, c] = mean_d + slope * (t_eval - tau_bar)
            half[:, c] = q * np.sqrt(np.maximum(s2 * (lever + 1.0), 0.0))
        # Spin: mean of the samples of frames start .. stop-1, Student-t CI of the mean.
        ws = ((cols[None, :] >= start[:, None]) & (cols[None, :] < stop[:, None])).astype(float)
        ns = ws.sum(axis=1)
        mean_w = (ws * frames.spin).sum(axis=1) / ns
        dev = (frames.spin - mean_w[:, None]) * ws
        std = np.sqrt((dev * dev).sum(axis=1) / (ns - 1))
        out[:, 2] = mean_w
        half[:, 2] = stats.t.ppf(0.5 + level / 2.0, np.maximum(ns - 1, 1)) * std / np.sqrt(ns)
    return out, half


def _prefix_quadratic(z: np.ndarray, h: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Least-squares quadratics through the first k points of every row, k = 0..N.

    Returns ``sse`` (b, N+1; inf for k < 4), ``beta`` (b, N+1, 3; coefficients of
    1, z, z^2) and the moment matrices ``mat`` (N+1, 3, 3).
    """
    b, N = h.shape
    powers = np.stack([z**p for p in range(5)], axis=1)
    mom = np.concatenate([np.zeros((1, 5)), np.cumsum(powers, axis=0)])
    mat = np.stack([mom[:, p : p + 3] for p in range(3)], axis=1)
    rhs = np.concatenate([np.zeros((b, 1, 3)), np.cumsum(powers[None, :, :3] * h[:, :, None], axis=1)], axis=1)
    hh = np.concatenate([np.zeros((b, 1)), np.cumsum(h * h, axis=1)], axis=1)
    sse = np.full((b, N + 1), np.inf)
    beta = np.full((b, N + 1, 3), np.nan)
    if N >= 4:
        beta[:, 4:] = np.linalg.solve(mat[None, 4:], rhs[:, 4:, :, None])[..., 0]
        sse[:, 4:] = np.maximum(hh[:, 4:] - np.einsum("bkj,bkj->bk", rhs[:, 4:], beta[:, 4:]), 0.0)
    return sse, beta, mat


def _detect(t, dt, lowest, min_flight, min_contact):
    """Vectorised :func:`~bouncelab.analysis.measurement.detect_contact` (flat contact model)."""
    b, N = lowest.shape
    z = (t - t.mean()) / dt
    hc = lowest - lowest.mean(axis=1, keepdims=True)
    sse_b, beta_b, mat_b = _prefix_quadratic(z, hc)  # [k]: frames 0..k-1
    sse_r, beta_r, mat_r = _prefix_quadratic(z[::-1], hc[:, ::-1])
    sse_a = sse_r[:, ::-1]  # [k]: frames k..N-1
    beta_a = beta_r[:, ::-1]
    mat_a = mat_r[::-1]

    ch = np.concatenate([np.zeros((b, 1)), np.cumsum(hc, axis=1)], axis=1)
    chh = np.concatenate([np.zeros((b, 1)), np.cumsum(hc * hc, axis=1)], axis=1)
    ii = np.arange(min_flight, N - min_flight - min_contact + 1)
    jj = np.arange(N)
    A, B = ii[:, None], jj[None, :] + 1
    admissible = (jj[None, :] - ii[:, None] + 1 >= min_contact) & (N - 1 - jj[None, :] >= min_flight)
    m = np.where(admissible, B - A, 1).astype(float)
    sh = ch[:, B] - ch[:, A]
    vh = (chh[:, B] - chh[:, A]) - sh * sh / m
    total = sse_b[:, ii][:, :, None] + np.maximum(vh, 0.0) + sse_a[:, np.minimum(jj + 1, N)][:, None, :]
    total = np.where(admissible[None], total, np.inf).reshape(b, -1)
    best = np.argmin(total, axis=1)
    sse3 = total[np.arange(b), best]
    i = ii[best // N]
    j = best % N
    rows = np.arange(b)

    floor = 1e-300 + 1e-24 * (hc * hc).sum(axis=1)
    sse1 = sse_b[:, N]
    bic3 = N * np.log(np.maximum(sse3, floor) / N) + 9 * np.log(N)
    bic1 = N * np.log(np.maximum(sse1, floor) / N) + 3 * np.log(N)
    ok = np.isfinite(sse3) & (bic3 < bic1)

    level_c = (ch[rows, j + 1] - ch[rows, i]) / (j + 1 - i)  # the contact line (flat)
    pb = beta_b[rows, i]  # quadratic on frames 0..i-1
    pa = beta_a[rows, j + 1]  # quadratic on frames j+1..N-1
    z0 = _meeting(pb, level_c, z[i - 1], z[i])
    zf = _meeting(pa, level_c, z[j], z[j + 1])
    slope_b, se_b = _slope(pb, sse_b[rows, i], mat_b[i], i, z0)
    slope_a, se_a = _slope(pa, sse_a[rows, j + 1], mat_a[j + 1], N - j - 1, zf)
    ok &= (slope_b < -_KINK_SIGMAS * se_b) & (slope_a > _KINK_SIGMAS * se_a)
    t_mid = t.mean()
    return i, j, t_mid + z0 * dt, t_mid + zf * dt, ok


def _meeting(p: np.ndarray, c: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Where p0 + p1 z + p2 z^2 = c in [lo, hi] (the root nearest the middle), else the middle."""
    a2, a1, a0 = p[:, 2], p[:, 1], p[:, 0] - c
    mid = 0.5 * (lo + hi)
    tol = 1e-9 * np.maximum(1.0, np.abs(hi - lo))
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = a1 * a1 - 4.0 * a2 * a0
        sq = np.sqrt(np.where(disc >= 0, disc, np.nan))
        qq = -0.5 * (a1 + np.where(a1 >= 0, sq, -sq))
        quad = a2 != 0
        r1 = np.where(quad, qq / a2, -a0 / a1)
        r2 = np.where(quad, a0 / qq, np.nan)
    roots = np.stack([r1, r2], axis=1)
    inside = np.isfinite(roots) & (roots >= (lo - tol)[:, None]) & (roots <= (hi + tol)[:, None])
    dist = np.where(inside, np.abs(roots - mid[:, None]), np.inf)
    k = np.argmin(dist, axis=1)
    pick = roots[np.arange(len(k)), k]
    found = inside.any(axis=1)
    return np.where(found, np.clip(np.where(found, pick, mid), lo, hi), mid)


def _slope(p, sse, mat, count, z_at) -> tuple[np.ndarray, np.ndarray]:
    """Derivative at ``z_at`` of each least-squares quadratic and its standard error."""
    g = np.stack([np.zeros_like(z_at), np.ones_like(z_at), 2.0 * z_at], axis=1)
    slope = np.einsum("bj,bj->b", g, p)
    inv = np.linalg.inv(mat)
    s2 = sse / np.maximum(count - 3, 1)
    var = s2 * np.einsum("bi,bij,bj->b", g, inv, g)
    return slope, np.sqrt(np.maximum(var, 0.0))
