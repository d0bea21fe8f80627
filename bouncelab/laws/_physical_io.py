"""The edges of ``predict(..., units=, form=)``: physical landings in, physical lift-offs out.

The law itself only ever sees scaled Cartesian states; these helpers convert at
the edge with :mod:`bouncelab.data.units` and give the result back in the
caller's kind (an array of the same leading shape, or a DataFrame with the
same index and named columns).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from bouncelab.data.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, landing_angle_error, scaled_units_error
from bouncelab.data.units import (
    BALL_RADIUS_M,
    COMPONENTS,
    POLAR_COMPONENTS,
    _form_pair,
    _unit_pair,
    ball_radius,
    physical_to_scaled,
    scaled_to_physical,
)
from bouncelab.data.validation import check_downward
from bouncelab.errors import DataError

__all__ = ["PhysicalIO", "is_lazy"]


def is_lazy(x: Any) -> bool:
    """True for a DataArray backed by a dask array (predicted lazily, chunk by chunk)."""
    return isinstance(x, xr.DataArray) and x.chunks is not None


class PhysicalIO:
    """Conversion of one ``predict`` call's landings and lift-offs (None when all is scaled Cartesian)."""

    def __init__(self, units: Any, form: Any, radius_m: float | None,
                 plausible: PlausibleRanges | None = PLAUSIBLE_RANGES) -> None:
        _unit_pair(units)  # validate early, before any work
        if plausible is not None and not isinstance(plausible, PlausibleRanges):
            raise DataError(f"plausible must be a bouncelab.data.plausibility.PlausibleRanges or None; "
                            f"got {plausible!r}")
        self.units = units
        self.plausible = plausible
        self.form_in, self.form_out = _form_pair(form)
        self.radius_m = BALL_RADIUS_M if radius_m is None else ball_radius(radius_m)  # metres, not mm
        self.index = None
        self.lead: tuple[int, ...] = ()

    @staticmethod
    def needed(units: Any, form: Any) -> bool:
        """Whether the landings need converting (anything but scaled Cartesian states); validates ``units``."""
        return not (_unit_pair(units) is None and isinstance(form, str) and form == "cartesian")

    def landing(self, landing: Any) -> np.ndarray:
        """The landings as a scaled Cartesian (..., 3) float array."""
        import pandas as pd

        if isinstance(landing, xr.DataArray):
            raise DataError("units= and form= take arrays or DataFrames; a DataArray states its own units: give it "
                            "in scaled units (see bouncelab.data.units) or pass its .values")
        names = COMPONENTS if self.form_in == "cartesian" else POLAR_COMPONENTS
        if isinstance(landing, pd.DataFrame):
            self.index = landing.index
            cols = [str(c) for c in landing.columns]
            if not isinstance(landing.columns, pd.RangeIndex):
                order = _order(cols, names)
                if order is None:
                    raise DataError(f"landing DataFrame columns must be named {list(names)} for form "
                                    f"{self.form_in!r} (any order; a suffix 0 is allowed); got {cols}")
                landing = landing.iloc[:, order]
            landing = landing.to_numpy()
        if np.ma.isMaskedArray(landing) and np.ma.getmaskarray(landing).any():
            raise DataError("landing has masked (missing) values; remove or fill them first")
        arr = np.asarray(np.ma.getdata(landing))
        if arr.dtype.kind not in "iuf" or arr.ndim == 0 or arr.shape[-1] != 3:
            raise DataError(f"landing must be a real (..., 3) array of {list(names)}; got "
                            f"{arr.dtype} values of shape {arr.shape}")
        self.lead = arr.shape[:-1]
        if self.form_in == "cartesian":  # named here, in the units given, before the conversion rescales it
            check_downward(arr.reshape(-1, 3)[:, 1], unit=(_unit_pair(self.units) or ("radii/s",))[0])
        scaled = physical_to_scaled(arr, units=self.units, form=self.form_in, kind="landing", radius_m=self.radius_m)
        self._check_plausible(arr.reshape(-1, 3).astype(float), scaled.reshape(-1, 3))
        return scaled

    def _check_plausible(self, raw: np.ndarray, scaled: np.ndarray) -> None:
        """Refuse landings that only a wrong unit (or radians for degrees) makes, as the file loader does.

        Units are declared here, so only the upper limits apply (as for a file with declared units).
        """
        ranges = self.plausible
        if ranges is None or not np.isfinite(scaled).all():  # NaN/inf: the validation names them next
            return
        widen = "pass plausible=PLAUSIBLE_RANGES.widened({limit}=...) or plausible=None"
        columns = ("xdot0", "ydot0", "omega0")
        if self.form_in == "polar":
            angle = landing_angle_error(raw[:, 1], ranges)
            if angle is not None:
                raise DataError(f"{angle[1]}; if it is right, {widen.format(limit='min_landing_angle')}",
                                column="angle", row=angle[0] + 1)
            # Check the speed as given, not its components (120 m/s at 45 degrees is 85 m/s in each).
            scaled = np.column_stack([np.hypot(scaled[:, 0], scaled[:, 1]), np.zeros(len(scaled)), scaled[:, 2]])
            columns = ("speed", "speed", "spin")
        pair = _unit_pair(self.units) or ("radius/s", "rad/s")
        given = {"velocity": pair[0], "spin": pair[1]}
        error = scaled_units_error(
            scaled, None, radius_m=self.radius_m, ranges=ranges, units=given, lower=False, landing_columns=columns,
            declare=lambda likely: f"pass units={given | {k: u[0] for k, u in likely.items()}}",
            widen=lambda limit: widen.format(limit=limit))
        if error is not None:
            raise error

    def liftoff(self, out: np.ndarray) -> Any:
        """Scaled (n, 3) lift-offs in the caller's units, form and kind."""
        import pandas as pd

        res = scaled_to_physical(out, units=self.units, form=self.form_out, kind="liftoff", radius_m=self.radius_m)
        if self.index is not None:
            names = COMPONENTS if self.form_out == "cartesian" else POLAR_COMPONENTS
            return pd.DataFrame(res, index=self.index, columns=list(names))
        return res.reshape((*self.lead, 3))

    def per_bounce(self, values: np.ndarray) -> np.ndarray:
        """A (n,) result with the landings' leading shape."""
        return values.reshape(self.lead) if self.index is None else values


def _order(labels: list[str], names: tuple[str, ...]) -> list[int] | None:
    for suffix in ("", "0", "_0"):
        want = [n + suffix for n in names]
        if all(labels.count(w) == 1 for w in want):
            return [labels.index(w) for w in want]
    return None
