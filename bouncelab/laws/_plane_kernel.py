"""Compiled objective of the piecewise law's plane search: delta of the law whose two affine maps are
least-squares fits on each side of a trial plane (one pass to fit the maps, one to score them).

Landings are standardised (``z``); a trial plane is ``u . z = t``. Small problems run one fused
compiled call; from :data:`~bouncelab.laws.compiled.PARALLEL_MIN` bounces both passes run over
fixed chunks on the thread pool and the partial sums are added in chunk order, so the value does
not depend on the number of threads.
"""

from __future__ import annotations

import math

import numpy as np

from bouncelab.core._jit import jit
from bouncelab.laws.compiled import PARALLEL_MIN, run_chunked

INFEASIBLE = 1.0e3  # objective of a plane leaving a side with too few bounces (delta is ~0.1)


@jit(nogil=True)
def _solve4(A, B):
    """Solve the 4x4 system A X = B (B is 4x3) by Gaussian elimination with partial pivoting.

    Returns (X, ok); ok is False when A is numerically singular.
    """
    M = A.copy()
    R = B.copy()
    scale = 0.0
    for i in range(4):
        scale = max(scale, abs(M[i, i]))
    for col in range(4):
        piv = col
        for row in range(col + 1, 4):
            if abs(M[row, col]) > abs(M[piv, col]):
                piv = row
        if abs(M[piv, col]) <= 1e-12 * scale:
            return R, False
        if piv != col:
            for k in range(4):
                M[col, k], M[piv, k] = M[piv, k], M[col, k]
            for k in range(3):
                R[col, k], R[piv, k] = R[piv, k], R[col, k]
        for row in range(col + 1, 4):
            f = M[row, col] / M[col, col]
            for k in range(col, 4):
                M[row, k] -= f * M[col, k]
            for k in range(3):
                R[row, k] -= f * R[col, k]
    for col in range(3, -1, -1):
        for k in range(3):
            acc = R[col, k]
            for j in range(col + 1, 4):
                acc -= M[col, j] * R[j, k]
            R[col, k] = acc / M[col, col]
    return R, True


@jit(nogil=True)
def side_moments(Z, PF, W, u0, u1, u2, t, start, stop):
    """Weighted normal equations [z 1]^T W [z 1] and [z 1]^T W p_F of each side over rows [start, stop)."""
    XtX = np.zeros((2, 4, 4))
    XtY = np.zeros((2, 4, 3))
    counts = np.zeros(2, dtype=np.int64)
    x = np.empty(4)
    for i in range(start, stop):
        s = 1 if u0 * Z[i, 0] + u1 * Z[i, 1] + u2 * Z[i, 2] >= t else 0
        counts[s] += 1
        x[0] = Z[i, 0]
        x[1] = Z[i, 1]
        x[2] = Z[i, 2]
        x[3] = 1.0
        w = W[i]
        for a in range(4):
            for b in range(a, 4):
                XtX[s, a, b] += w * x[a] * x[b]
            for k in range(3):
                XtY[s, a, k] += w * x[a] * PF[i, k]
    return XtX, XtY, counts


@jit(nogil=True)
def _maps(XtX, XtY):
    for s in range(2):
        for a in range(4):
            for b in range(a):
                XtX[s, a, b] = XtX[s, b, a]
    B0, ok0 = _solve4(XtX[0], XtY[0])
    B1, ok1 = _solve4(XtX[1], XtY[1])
    return B0, B1, ok0 and ok1


@jit(nogil=True)
def score(Z, PF, inv_norm, u0, u1, u2, t, B0, B1, start, stop):
    """Sum over rows [start, stop) of ||p_F - prediction|| / ||p_0|| for the maps B0 (side 0), B1 (side 1)."""
    total = 0.0
    for i in range(start, stop):
        B = B1 if u0 * Z[i, 0] + u1 * Z[i, 1] + u2 * Z[i, 2] >= t else B0
        e2 = 0.0
        for k in range(3):
            pred = B[0, k] * Z[i, 0] + B[1, k] * Z[i, 1] + B[2, k] * Z[i, 2] + B[3, k]
            e = PF[i, k] - pred
            e2 += e * e
        total += math.sqrt(e2) * inv_norm[i]
    return total


@jit(nogil=True)
def _plane_delta_serial(Z, PF, W, inv_norm, u0, u1, u2, t, min_side):
    n = Z.shape[0]
    XtX, XtY, counts = side_moments(Z, PF, W, u0, u1, u2, t, 0, n)
    short = max(min_side - counts[0], 0) + max(min_side - counts[1], 0)
    if short > 0:
        return INFEASIBLE + short
    B0, B1, ok = _maps(XtX, XtY)
    if not ok:
        return INFEASIBLE
    return score(Z, PF, inv_norm, u0, u1, u2, t, B0, B1, 0, n) / n


def plane_delta(Z: np.ndarray, PF: np.ndarray, W: np.ndarray, inv_norm: np.ndarray, u: np.ndarray, t: float,
                min_side: int) -> float:
    """delta of the least-squares piecewise-affine law split by the plane u . z = t (standardised z).

    ``W`` weighs each bounce in the least squares of the maps (ones: the paper's unweighted fit),
    ``inv_norm`` its error in delta.
    """
    n = Z.shape[0]
    u0, u1, u2 = float(u[0]), float(u[1]), float(u[2])
    if n < PARALLEL_MIN:
        return _plane_delta_serial(Z, PF, W, inv_norm, u0, u1, u2, t, min_side)
    parts = run_chunked(side_moments, n, Z, PF, W, u0, u1, u2, t)
    XtX = np.sum([p[0] for p in parts], axis=0)
    XtY = np.sum([p[1] for p in parts], axis=0)
    counts = np.sum([p[2] for p in parts], axis=0)
    short = max(min_side - int(counts[0]), 0) + max(min_side - int(counts[1]), 0)
    if short > 0:
        return INFEASIBLE + short
    B0, B1, ok = _maps(XtX, XtY)
    if not ok:
        return INFEASIBLE
    return math.fsum(run_chunked(score, n, Z, PF, inv_norm, u0, u1, u2, t, B0, B1)) / n
