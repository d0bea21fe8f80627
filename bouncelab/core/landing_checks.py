"""The two comparisons that judge a landing, each written once: a valid state, and the unit guard's limits.

Plain functions of ``x, y, w`` (``[xdot0, ydot0, omega0]`` in scaled units) and their limits, which work
alike on floats, element-wise on NumPy arrays and compiled into numba loops, so that every path that checks
a landing (NumPy's, the compiled scans of :mod:`bouncelab.core._scans`, the laws' prediction loops, one
landing of ``predict_one``) makes the same comparison. :mod:`bouncelab.core.validation` and
:mod:`bouncelab.core.plausibility` say what they mean and name what fails.
"""

from __future__ import annotations

from typing import Any

__all__ = ["FAST", "FLAT", "INVALID", "SLOW", "SPIN", "STATE_LIMIT", "is_landing", "landing_fault"]

#: Largest magnitude accepted for a state component, in scaled units (1e8 radii/s is 2135 km/s for the
#: default ball; 1e8 rad/s is 10^9 rpm): beyond it no bounce is physical, and arithmetic could overflow.
STATE_LIMIT = 1.0e8

#: The bits of :func:`landing_fault`, one per limit (the order of
#: :class:`~bouncelab.core.plausibility.LandingFaults`), and the bit a scan adds for a row that is not a
#: valid landing at all (:func:`is_landing`).
SLOW, FAST, SPIN, FLAT, INVALID = 1, 2, 4, 8, 16


def is_landing(x: Any, y: Any, w: Any, limit: float = STATE_LIMIT) -> Any:
    """Whether ``[x, y, w]`` is a landing the laws may see: finite, each within ``limit`` in magnitude, ``y < 0``.

    ``abs(v) <= limit`` is false for NaN and infinities. Loops compiled with fast-math assumptions about
    NaN compare the values' bits instead (:func:`bouncelab.laws._kernels.valid_bits`).
    """
    return (abs(x) <= limit) & (abs(y) <= limit) & (abs(w) <= limit) & (y < 0.0)


def landing_fault(x: Any, y: Any, w: Any, min_s2: float, max_s2: float, max_w: float, tan_a: float) -> Any:
    """The per-landing limits a valid landing ``[x, y, w]`` breaks, as bits (0: none).

    :data:`SLOW` (squared speed ``x^2 + y^2`` below ``min_s2``), :data:`FAST` (above ``max_s2``),
    :data:`SPIN` (``|w|`` above ``max_w``), :data:`FLAT` (``-y < |x| tan_a``: an angle of incidence
    below the smallest); the limits are :func:`bouncelab.core.plausibility.landing_limits`.
    """
    s2 = x * x + y * y
    return (s2 < min_s2) * SLOW | (s2 > max_s2) * FAST | (abs(w) > max_w) * SPIN | (-y < abs(x) * tan_a) * FLAT
