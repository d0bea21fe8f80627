"""A compiled one-pass check of large state arrays (numba, loaded only for large inputs)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def all_valid(P: np.ndarray, landing: bool) -> bool:
    """True when every value is finite and, for landings, every ydot is negative.

    One pass over memory instead of NumPy's several temporaries; on a failure the
    caller re-checks with NumPy to name the row and column.
    """
    for i in range(P.shape[0]):
        x, y, w = P[i, 0], P[i, 1], P[i, 2]
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(w)):
            return False
        if landing and not y < 0.0:
            return False
    return True
