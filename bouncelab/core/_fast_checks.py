"""A compiled one-pass check of large state arrays (numba, loaded only for large inputs)."""

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
