"""Input checks and unit conversions at the edges of the ground phase (scaled units inside)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core import checks
from bouncelab.core.errors import DataError, ParameterError
from bouncelab.core.units import (
    BALL_RADIUS_M,
    SPEED_UNITS,
    SPIN_UNITS,
    ball_radius,
    spin_from_scaled,
    spin_to_scaled,
    unit_pair,
    velocity_from_scaled,
    velocity_to_scaled,
)
from bouncelab.core.validation import STATE_LIMIT, real_array

if TYPE_CHECKING:
    from bouncelab.laws import BounceModel

__all__ = ["Units", "as_vectors", "unit_normals", "within_limit"]

_AXES = ("x", "y", "z")

class Units:
    """The caller's units: None (scaled: radii, radii/s, rad/s) or ``{"velocity": ..., "spin": ...}``.

    Lengths are in ball radii with velocities in radii/s, in metres with any other velocity unit.
    """

    def __init__(self, units: Any, radius_m: Any = None) -> None:
        self.radius_m = BALL_RADIUS_M if radius_m is None else ball_radius(radius_m)
        pair = unit_pair(units)
        if pair is None:
            self.velocity = self.spin = None
            return
        velocity, spin = pair
        self.velocity = None if velocity == "radius/s" else velocity
        self.spin = None if spin == "rad/s" else spin

    @property
    def scaled(self) -> bool:
        """True when lengths are in ball radii (velocities in radii/s); metres otherwise."""
        return self.velocity is None

    @property
    def length(self) -> str:
        return "radius" if self.scaled else "m"

    def velocity_in(self, v: np.ndarray) -> np.ndarray:
        return v if self.velocity is None else velocity_to_scaled(v, self.velocity, radius_m=self.radius_m)

    def velocity_out(self, v: np.ndarray) -> np.ndarray:
        return v if self.velocity is None else velocity_from_scaled(v, self.velocity, radius_m=self.radius_m)

    def spin_in(self, w: np.ndarray) -> np.ndarray:
        return w if self.spin is None else spin_to_scaled(w, self.spin)

    def spin_out(self, w: np.ndarray) -> np.ndarray:
        return w if self.spin is None else spin_from_scaled(w, self.spin)

    def length_out(self, x: np.ndarray) -> np.ndarray:
        """Ball radii to the caller's lengths (metres with physical units)."""
        return x if self.scaled else x * self.radius_m

    def in_place_out(self, pos: np.ndarray, vel: np.ndarray, spin: np.ndarray) -> None:
        """Scaled lengths, velocities and spins to the caller's units, overwriting the arrays (large paths).

        The same arithmetic as :func:`velocity_from_scaled` (times ``R / factor``) and
        :func:`spin_from_scaled` (divided by the factor), so the same bits.
        """
        if not self.scaled:
            pos *= self.radius_m
            vel *= self.radius_m / SPEED_UNITS[self.velocity]
        if self.spin is not None:
            spin /= SPIN_UNITS[self.spin]

    @property
    def velocity_unit(self) -> str:
        return self.velocity or "radius/s"

    @property
    def spin_unit(self) -> str:
        return self.spin or "rad/s"


def as_vectors(value: Any, name: str) -> tuple[np.ndarray, tuple[int, ...]]:
    """``value`` as a new finite float (n, 3) array and its leading shape (``()`` for one vector).

    Raises
    ------
    DataError
        Not real numbers, not of shape (3,) or (n, 3), no rows, or NaN/infinite (naming row and column).
    """
    if np.ma.isMaskedArray(value) and np.ma.getmaskarray(value).any():
        raise DataError(f"{name} has masked (missing) values; remove or fill them first", option=name)
    arr = np.array(real_array(np.ma.getdata(value), name, "x, y, z"))  # a copy: never the caller's array
    if arr.ndim not in (1, 2) or arr.shape[-1] != 3:
        raise DataError(f"{name} must have shape (3,) or (n, 3) (x, y, z components); got shape {arr.shape}",
                        option=name)
    lead = arr.shape[:-1]
    arr = arr.reshape(-1, 3)
    if len(arr) == 0:
        raise DataError(f"{name} has no rows: give at least one (3,) vector", option=name)
    bad = ~np.isfinite(arr)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise DataError(f"{name} is not finite at row {row + 1}, component {_AXES[col]}: {arr[row, col]!r}",
                        column=f"{name}_{_AXES[col]}", row=int(row) + 1)
    return arr, lead


def within_limit(scaled: np.ndarray, name: str, given: np.ndarray, unit: str) -> np.ndarray:
    """``scaled`` (velocities or spins in scaled units) if every component is within
    :data:`~bouncelab.core.validation.STATE_LIMIT`, else a DataError naming the row and component.

    No ball moves or spins that fast (1e8 radii/s is 2135 km/s); the arithmetic of a run would
    overflow long before a double does (squares of 1e154 are infinite). ``given`` holds the
    caller's values in ``unit``, for the message.
    """
    bad = ~(np.abs(scaled) <= STATE_LIMIT)  # also infinite after a unit conversion
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise DataError(f"{name} row {row + 1}, component {_AXES[col]}: {given[row, col]:.6g} {unit} is beyond "
                        f"{STATE_LIMIT:g} in scaled units (radii/s, rad/s); no ball moves or spins that fast - is it "
                        f"in another unit?", column=f"{name}_{_AXES[col]}", row=int(row) + 1, option=name)
    return scaled


def unit_normals(normal: Any, *, upward: bool) -> tuple[np.ndarray, tuple[int, ...]]:
    """Ground normals as unit (n, 3) vectors (any non-zero length is normalised).

    Each row is first divided by its largest component (in magnitude), then by its length:
    a normal of any magnitude, tiny or huge, normalises as its multiple of order 1 does
    (``[1e-160, 0, 1e-160]`` exactly as ``[1, 0, 1]``), where squaring it would underflow or
    overflow. With ``upward`` the normal must have a positive z component (gravity pushes the
    ball into that ground); a DataError names the row otherwise.
    """
    n, lead = as_vectors(normal, "normal")
    big = np.abs(n).max(axis=1)
    if (big == 0).any():
        row = int(np.flatnonzero(big == 0)[0])
        raise DataError(f"normal row {row + 1} is the zero vector; give the ground's normal, e.g. (0, 0, 1)",
                        column="normal", row=row + 1, option="normal")
    n = n / big[:, None]
    n = n / np.sqrt(n[:, 0] * n[:, 0] + n[:, 1] * n[:, 1] + n[:, 2] * n[:, 2])[:, None]
    if upward and (n[:, 2] <= 0).any():
        row = int(np.flatnonzero(n[:, 2] <= 0)[0])
        raise DataError(f"normal row {row + 1} = {normal_text(n[row])} does not point up (z <= 0): gravity "
                        f"(0, 0, -g) would not press the ball onto that ground; z is up", column="normal",
                        row=row + 1)
    return n, lead


def normal_text(n: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in n) + ")"


def broadcast_rows(name_arrays: list[tuple[str, np.ndarray]]) -> int:
    """The common number of rows of (n, 3) arrays where single rows broadcast; DataError otherwise."""
    sizes = {len(a) for _, a in name_arrays if len(a) != 1}
    if len(sizes) > 1:
        text = ", ".join(f"{name} {len(a)}" for name, a in name_arrays)
        first = next(len(a) for _, a in name_arrays if len(a) != 1)
        raise DataError(f"the rows do not match: {text} (one row is repeated for every shot)",
                        option=next(name for name, a in name_arrays if len(a) not in (1, first)))
    return sizes.pop() if sizes else 1


def positive(value: Any, name: str, *, allow_zero: bool = False, error: type = ParameterError) -> float:
    """A finite number > 0 (or >= 0), or a typed error naming it (:func:`bouncelab.core.checks.positive`)."""
    return checks.positive(value, name, allow_zero=allow_zero, error=error)


def check_law(law: Any) -> BounceModel:
    """``law`` if it is a bounce law with all its parameters, else a ParameterError."""
    from bouncelab.laws import BounceModel, law_name

    if not isinstance(law, BounceModel):
        raise ParameterError(f"law must be a bouncelab bounce law (e.g. bl.Rigid(r=0.5, mu=0.4)); got "
                             f"{type(law).__name__}", parameter="law")
    from bouncelab.core.errors import NotFittedError

    try:
        law._fitted_values()
    except NotFittedError as exc:  # the law's own error, told as about the argument ``law``
        raise NotFittedError(f"{law_name(law)} has no value for {list(exc.missing)}: fit it or give the values",
                             law=law_name(law), missing=exc.missing, parameter="law") from None
    return law


def retention(value: Any) -> float:
    """A pivot retention: the fraction in [0, 1] of the spin about the normal that a bounce keeps."""
    x = positive(value, "pivot_retention", allow_zero=True)
    if x > 1:
        raise ParameterError(f"pivot_retention is the fraction of the spin about the normal kept by a bounce, in "
                             f"[0, 1]; got {value!r}", parameter="pivot_retention", value=value)
    return x
