"""Compiled one-pass scans of large state arrays (numba; loaded only for large inputs).

On a failure the callers (:mod:`bouncelab.core.validation`, :mod:`bouncelab.core.plausibility`) find and
name the rows with NumPy; these only say whether to look.
"""

from __future__ import annotations

import numpy as np

from bouncelab.core._jit import jit


@jit(nogil=True, fastmath={"nsz", "reassoc"})
def all_valid(P: np.ndarray, landing: bool, limit: float, start: int, stop: int) -> bool:
    """True when, in rows [start, stop), every value is finite and at most ``limit`` in magnitude and,
    for landings, every ydot is negative.

    One branch-free pass over memory (``abs(v) <= limit`` is false for NaN and inf too); on a
    failure the caller re-checks with NumPy to name the row and column.
    """
    ok = True
    for i in range(start, stop):
        x, y, w = P[i, 0], P[i, 1], P[i, 2]
        good = (abs(x) <= limit) & (abs(y) <= limit) & (abs(w) <= limit)
        if landing:
            good = good & (y < 0.0)
        ok = ok & good
    return ok


@jit(nogil=True)
def scan_landings(P: np.ndarray, min_s2: float, max_s2: float, max_w: float, tan_a: float, limit: float,
                  start: int, stop: int) -> tuple[bool, bool]:
    """Whether some valid landing in rows ``[start, stop)`` breaks a limit of
    :func:`bouncelab.core.plausibility.landing_faults` (too slow, too fast, spinning too fast, too flat), and
    whether some row is not a valid landing (not finite, beyond ``limit``, ``ydot >= 0``).

    One pass over memory; on a fault the caller finds the rows with NumPy. Rows that are not valid
    landings are left to the value check, which names them. No fastmath: the comparisons must see NaN
    as NaN (``abs(v) <= limit`` is false for NaN and inf).
    """
    faulty = False
    invalid = False
    for i in range(start, stop):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        if not (abs(x) <= limit and abs(y) <= limit and abs(w) <= limit and y < 0.0):
            invalid = True
            continue
        s2 = x * x + y * y
        if s2 < min_s2 or s2 > max_s2 or abs(w) > max_w or -y < abs(x) * tan_a:
            faulty = True
    return faulty, invalid
