"""Compiled objective of the plane search: delta of the piecewise-affine law whose maps are
least-squares fits on each side of a trial plane (one pass to fit, one to score)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

INFEASIBLE = 1.0e3  # objective of a plane leaving a side with too few bounces (delta is ~0.1)


@njit(cache=True)
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


@njit(cache=True)
def side_maps(Z, PF, side):
    """Least-squares affine maps [z, 1] -> p_F on side 0 and side 1; returns (B0, B1, n0, n1, ok)."""
    XtX = np.zeros((2, 4, 4))
    XtY = np.zeros((2, 4, 3))
    counts = np.zeros(2, dtype=np.int64)
    x = np.empty(4)
    for i in range(Z.shape[0]):
        s = side[i]
        counts[s] += 1
        x[0] = Z[i, 0]
        x[1] = Z[i, 1]
        x[2] = Z[i, 2]
        x[3] = 1.0
        for a in range(4):
            for b in range(a, 4):
                XtX[s, a, b] += x[a] * x[b]
            for k in range(3):
                XtY[s, a, k] += x[a] * PF[i, k]
    for s in range(2):
        for a in range(4):
            for b in range(a):
                XtX[s, a, b] = XtX[s, b, a]
    B0, ok0 = _solve4(XtX[0], XtY[0])
    B1, ok1 = _solve4(XtX[1], XtY[1])
    return B0, B1, counts[0], counts[1], ok0 and ok1


@njit(cache=True)
def plane_delta(Z, PF, inv_norm, u0, u1, u2, t, min_side):
    """delta of the least-squares piecewise-affine law split by the plane u . z = t (standardised z)."""
    n = Z.shape[0]
    side = np.empty(n, dtype=np.int64)
    for i in range(n):
        side[i] = 1 if u0 * Z[i, 0] + u1 * Z[i, 1] + u2 * Z[i, 2] >= t else 0
    B0, B1, n0, n1, ok = side_maps(Z, PF, side)
    short = max(min_side - n0, 0) + max(min_side - n1, 0)
    if short > 0 or not ok:
        return INFEASIBLE + short
    total = 0.0
    for i in range(n):
        B = B1 if side[i] == 1 else B0
        e2 = 0.0
        for k in range(3):
            pred = B[0, k] * Z[i, 0] + B[1, k] * Z[i, 1] + B[2, k] * Z[i, 2] + B[3, k]
            e = PF[i, k] - pred
            e2 += e * e
        total += math.sqrt(e2) * inv_norm[i]
    return total / n
