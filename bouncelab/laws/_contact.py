"""What the contact laws share: the restitution of vertical landings, and its line in fit reports."""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core.errors import DataError

__all__ = ["check_speeds", "restitution_line", "vertical_restitution"]


def check_speeds(values: Any, name: str, *, positive: bool) -> np.ndarray:
    """``values`` as a 1-d float array of finite speeds (radii/s), or a DataError naming ``name``."""
    arr = np.atleast_1d(np.asarray(values))
    if arr.dtype.kind not in "iuf":
        raise DataError(f"{name} must be numbers of radii/s; got values of type {arr.dtype}", option=name)
    arr = arr.astype(float).reshape(-1)
    bad = ~np.isfinite(arr) | ((arr <= 0) if positive else False)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        need = "a positive, finite" if positive else "a finite"
        raise DataError(f"{name} must be {need} number of radii/s; element {i} is {arr[i]}", option=name)
    return arr


def vertical_restitution(law: Any, speed: Any) -> np.ndarray:
    """Normal restitution |ydotF / ydot0| of ``law`` for vertical, spinless landings at ``speed`` radii/s.

    Raises
    ------
    DataError
        A speed that is not a positive, finite number (element named).
    """
    s = check_speeds(speed, "speed", positive=True)
    land = np.column_stack([np.zeros_like(s), -s, np.zeros_like(s)])
    return law.predict(land, plausible=None)[:, 1] / s  # the law's maths at any speed asked


def restitution_line(law: Any) -> str:
    """The fit report's line on a contact law's restitution at 200 / 500 / 900 radii/s."""
    r = vertical_restitution(law, [200.0, 500.0, 900.0])
    return f"restitution of vertical landings at 200 / 500 / 900 radii/s: {r[0]:.3f} / {r[1]:.3f} / {r[2]:.3f}"
