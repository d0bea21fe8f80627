"""The landing guard's compiled one-pass check of large landing arrays (numba, loaded only for large inputs)."""

from __future__ import annotations

import numpy as np

from bouncelab.core._jit import jit


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
