"""Refusing values that can only come from a unit mistake (limits in scaled units)."""

from __future__ import annotations

import math

import numpy as np

from bouncelab.data.io.column_units import _ROLE_KINDS
from bouncelab.data.io.synonyms import _STATES
from bouncelab.data.io.table import _Column, _err, _Table
from bouncelab.data.units import BALL_RADIUS_M, COMPONENTS
from bouncelab.errors import DataError

# Plausibility limits that catch a wrong unit (scaled units).
_MIN_MEDIAN_LANDING_YDOT = 20.0  # radii/s: 0.43 m/s
_MAX_VELOCITY = 10_000.0  # radii/s: 213 m/s
_MAX_SPIN = 5_000.0  # rad/s: 48 000 rpm


def _check_plausible(
    table: _Table,
    cols: dict[str, _Column],
    scaled: dict[str, np.ndarray],
    parsed: dict[str, np.ndarray],
    unit_of: dict[str, tuple[str, str]],
) -> None:
    """Refuse numbers that can only come from a unit mistake."""
    median = float(np.median(np.abs(scaled["landing.ydot"])))
    if unit_of["landing.ydot"][1] == "assumed" and median < _MIN_MEDIAN_LANDING_YDOT:
        raise DataError(
            f"the column has no velocity unit (in units= or the file), so radii/s are assumed, "
            f"but the median landing |ydot| is "
            f"{median:.3g} radii/s (below {_MIN_MEDIAN_LANDING_YDOT:g} radii/s = "
            f"{_MIN_MEDIAN_LANDING_YDOT * BALL_RADIUS_M:.2f} m/s, which no golf landing is): "
            "the velocities look like physical units; pass units={'velocity': 'm/s'} "
            "(or the unit they are in)", file=table.file, column=cols["landing.ydot"].name,
        )
    for role in (f"{s}.{c}" for s in _STATES for c in COMPONENTS):
        kind = _ROLE_KINDS[role.split(".")[1]]
        limit = _MAX_VELOCITY if kind == "velocity" else _MAX_SPIN
        big = np.abs(scaled[role]) > limit
        if not big.any():
            continue
        i = int(np.argmax(big))
        unit, origin = unit_of[role]
        said = f"{'assumed' if origin == 'assumed' else 'declared'} {unit}"
        if kind == "velocity":
            msg = (f"{float(parsed[role][i])!r} ({said}) is {scaled[role][i]:.4g} radii/s, faster than "
                   f"{_MAX_VELOCITY:g} radii/s ({_MAX_VELOCITY * BALL_RADIUS_M:.0f} m/s), "
                   "which no golf ball reaches: the velocity unit is wrong "
                   "(pass units={'velocity': ...})")
        else:
            msg = (f"{float(parsed[role][i])!r} ({said}) is {scaled[role][i]:.4g} rad/s, beyond "
                   f"{_MAX_SPIN:g} rad/s ({_MAX_SPIN * 60 / (2 * math.pi):.0f} rpm), which no golf "
                   "ball reaches: the spin unit is wrong"
                   + (" (rpm read as rad/s? pass units={'spin': 'rpm'})" if origin == "assumed"
                      else " (pass units={'spin': ...})"))
        raise _err(table, msg, cols[role].name, i)
