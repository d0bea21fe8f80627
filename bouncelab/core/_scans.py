"""Compiled one-pass scans of large state arrays (numba; loaded only for large inputs).

Their comparisons are not written here: they are those of :mod:`bouncelab.core.landing_checks`, compiled.
On a failure the callers (:mod:`bouncelab.core.validation`, :mod:`bouncelab.core.plausibility`) find and
name the rows with NumPy; these only say whether to look.
"""

from __future__ import annotations

import numpy as np

from bouncelab.core._jit import jit
from bouncelab.core.landing_checks import INVALID, is_landing, landing_fault

#: The two comparisons, inlined into compiled loops.
is_landing_ = jit(inline="always")(is_landing)
landing_fault_ = jit(inline="always")(landing_fault)


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
        if landing:
            ok = ok & is_landing_(x, y, w, limit)
        else:
            ok = ok & (abs(x) <= limit) & (abs(y) <= limit) & (abs(w) <= limit)
    return ok


@jit(nogil=True)
def scan_landings(P: np.ndarray, min_s2: float, max_s2: float, max_w: float, tan_a: float, limit: float,
                  start: int, stop: int) -> int:
    """The unit guard's verdict on rows ``[start, stop)``: the faults of
    :func:`~bouncelab.core.landing_checks.landing_fault` of the valid landings, or'ed, with
    :data:`~bouncelab.core.landing_checks.INVALID` if some row is not a valid landing (left to the value
    check, which names it). 0: every landing is valid and plausible.

    One pass over memory; on a fault the caller finds the rows with NumPy. No fastmath: the
    comparisons must see NaN as NaN.
    """
    status = 0
    for i in range(start, stop):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        if is_landing_(x, y, w, limit):
            status |= landing_fault_(x, y, w, min_s2, max_s2, max_w, tan_a)
        else:
            status |= INVALID
    return status
