"""The edge of a law's public methods: one call's landings, taken once, and its results in the caller's kind.

:class:`Landings` is what :meth:`~bouncelab.BounceModel.predict` and :meth:`~bouncelab.BounceModel.regime`
make of their arguments before the law's maths runs: the landings as a scaled Cartesian ``(n, 3)`` float64
array (converted at the edge from physical units and polar forms with :mod:`bouncelab.core.units`; their
shape and type checked), the unit guard's limits, and the way back to the caller's kind (an array of the
same leading shape, a DataFrame with the same index and named columns, a DataArray). The values are
checked in the law's own pass (its hooks return the guard's verdict); :meth:`Landings.refuse` words a
failed verdict. Lazy (dask) DataArrays are predicted chunk by chunk, each chunk through the same path.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np

from bouncelab.core.errors import Code, DataError, Hint
from bouncelab.core.landing_checks import INVALID
from bouncelab.core.plausibility import PlausibleRanges, guard_limits, landing_error
from bouncelab.core.units import (
    BALL_RADIUS_M,
    COMPONENT_UNITS,
    COMPONENTS,
    POLAR_COMPONENTS,
    _form_pair,
    ball_radius,
    physical_to_scaled,
    scaled_to_physical,
    unit_pair,
)
from bouncelab.core.validation import as_states, check_downward, check_values, is_dataarray

__all__ = ["Landings", "PhysicalIO", "is_lazy"]


def check_plausible_argument(plausible: Any) -> PlausibleRanges | None:
    """``plausible=`` as given, if it is a :class:`PlausibleRanges` or None (DataError otherwise)."""
    if plausible is not None and not isinstance(plausible, PlausibleRanges):
        raise DataError(f"plausible must be a bouncelab.core.plausibility.PlausibleRanges or None; got {plausible!r}",
                        option="plausible")
    return plausible


def io_option(units: Any, form: Any) -> str:
    """Which of ``units=`` and ``form=`` asks for a conversion (``"units"`` when both do)."""
    return "units" if unit_pair(units) is not None else "form"


def radius_of(radius_m: Any) -> float:
    """The ball radius in metres of ``radius_m=`` (default 21.35 mm; DataError for what is not metres)."""
    return BALL_RADIUS_M if radius_m is None else ball_radius(radius_m)


class Landings:
    """One call's landings, taken once: ``p``, the scaled Cartesian (n, 3) float64 array the law sees, and
    ``limits``, the unit guard's (:func:`~bouncelab.core.plausibility.guard_limits`).

    Parameters are those of :meth:`~bouncelab.BounceModel.predict`; ``form`` may be a pair (landing form,
    result form). Shapes, types, units and forms are checked here; the values, and the guard, by the law's
    pass over them, whose verdict goes to :meth:`refuse`.
    """

    def __init__(self, landing: Any, units: Any, form: Any, radius_m: Any, plausible: Any) -> None:
        self.plausible = check_plausible_argument(plausible)
        self.io = PhysicalIO(units, form, radius_m) if PhysicalIO.needed(units, form) else None
        given = landing if self.io is None else self.io.landing(landing)
        self.p, self._wrap = as_states(given, "landing", landing=True, defer_check=True)
        if self.plausible is None:
            self.radius_m = None
        else:
            self.radius_m = radius_of(radius_m) if self.io is None else self.io.radius_m
        self.limits = guard_limits(self.plausible, self.radius_m)
        # a DataFrame's own row labels, for the guard's messages
        self.labels = landing.index if self.io is None and hasattr(landing, "columns") else None

    def refuse(self, status: int) -> None:
        """Raise the error of a failed verdict (``status`` of the law's pass, not 0): a value no landing has
        first (:func:`~bouncelab.core.validation.check_values`, naming the row and column), then a landing
        outside the guard's limits (:func:`~bouncelab.core.plausibility.landing_error`, in the units and
        form the caller gave)."""
        if status & INVALID:
            check_values(self.p, "landing", landing=True)
        if self.plausible is None or not status & ~INVALID:
            return
        pair = None if self.io is None else unit_pair(self.io.units)
        units = {"velocity": "radius/s", "spin": "rad/s"} if pair is None else {"velocity": pair[0], "spin": pair[1]}
        error = landing_error(self.p, radius_m=self.radius_m, ranges=self.plausible, units=units,
                              form="cartesian" if self.io is None else self.io.form_in,
                              row_labels=self.labels if self.io is None else self.io.index)
        if error is not None:
            raise error

    def liftoff(self, out: np.ndarray) -> Any:
        """Scaled (n, 3) lift-offs in the caller's kind (and units and form)."""
        return self._wrap(out) if self.io is None else self.io.liftoff(out)

    def per_bounce(self, values: np.ndarray) -> Any:
        """An (n,) result with the landings' leading shape (or index)."""
        return self._wrap(values) if self.io is None else self.io.per_bounce(values)


def is_lazy(x: Any) -> bool:
    """True for a DataArray backed by a dask array (predicted lazily, chunk by chunk)."""
    return is_dataarray(x) and x.chunks is not None


def _lazy_input(da: Any) -> Any:
    if "component" not in da.dims or da.sizes["component"] != 3:
        raise DataError(f"landing DataArray needs a 'component' dimension of size 3; its sizes are "
                        f"{dict(da.sizes)}", option="landing")
    if "component" in da.coords:
        labels = [str(v) for v in da["component"].values]
        if sorted(labels) != sorted(COMPONENTS):
            raise DataError(f"landing component labels must be {list(COMPONENTS)}; got {labels}", option="landing")
        da = da.sel(component=list(COMPONENTS))
    return da.chunk({"component": -1})


def lazy_predict(law: Any, da: Any, plausible: PlausibleRanges | None, radius_m: float | None) -> Any:
    """``predict`` of a dask-backed DataArray: one task per chunk, nothing computed yet (guarded per chunk)."""
    import xarray as xr

    out = xr.apply_ufunc(lambda block: law.predict(block, plausible=plausible, radius_m=radius_m),
                         _lazy_input(da), input_core_dims=[["component"]], output_core_dims=[["component"]],
                         dask="parallelized", output_dtypes=[np.float64])
    return out.assign_coords(component=list(COMPONENTS), unit=("component", list(COMPONENT_UNITS)))


def lazy_regime(law: Any, da: Any, codes: bool, plausible: PlausibleRanges | None, radius_m: float | None) -> Any:
    """``regime`` of a dask-backed DataArray, lazily (codes or names)."""
    import xarray as xr

    names = np.asarray(law.regimes)
    dtype = np.int8 if codes else names.dtype

    def block_codes(block: np.ndarray) -> np.ndarray:
        return law.regime(block, codes=True, plausible=plausible, radius_m=radius_m)

    return xr.apply_ufunc(lambda block: block_codes(block) if codes else names[block_codes(block)],
                          _lazy_input(da), input_core_dims=[["component"]], dask="parallelized",
                          output_dtypes=[dtype])


class PhysicalIO:
    """Conversion of one call's landings and lift-offs (used when they are not scaled Cartesian states)."""

    def __init__(self, units: Any, form: Any, radius_m: float | None) -> None:
        unit_pair(units)  # validate early, before any work
        self.units = units
        self.form_in, self.form_out = _form_pair(form)
        self.radius_m = radius_of(radius_m)
        self.index = None
        self.lead: tuple[int, ...] = ()

    @staticmethod
    def needed(units: Any, form: Any) -> bool:
        """Whether the landings need converting (anything but scaled Cartesian states); validates ``units``."""
        return not (unit_pair(units) is None and isinstance(form, str) and form == "cartesian")

    def landing(self, landing: Any) -> np.ndarray:
        """The landings as a scaled Cartesian (..., 3) float array."""
        if is_dataarray(landing):
            raise DataError("units= and form= take arrays or DataFrames; a DataArray states its own units: give it "
                            "in scaled units (see bouncelab.core.units)", option=io_option(self.units, self.form_in),
                            hints=[Hint("landing", Code("landing.values"), "its numbers, in the units and form given")])
        names = COMPONENTS if self.form_in == "cartesian" else POLAR_COMPONENTS
        pd = sys.modules.get("pandas")  # a DataFrame exists only if pandas was imported
        if pd is not None and isinstance(landing, pd.DataFrame):
            self.index = landing.index
            cols = [str(c) for c in landing.columns]
            if not isinstance(landing.columns, pd.RangeIndex):
                order = _order(cols, names)
                if order is None:
                    raise DataError(f"landing DataFrame columns must be named {list(names)} for form "
                                    f"{self.form_in!r} (any order; a suffix 0 is allowed); got {cols}",
                                    option="landing")
                landing = landing.iloc[:, order]
            landing = landing.to_numpy()
        if np.ma.isMaskedArray(landing) and np.ma.getmaskarray(landing).any():
            raise DataError("landing has masked (missing) values; remove or fill them first", option="landing")
        arr = np.asarray(np.ma.getdata(landing))
        if arr.dtype.kind not in "iuf" or arr.ndim == 0 or arr.shape[-1] != 3:
            raise DataError(f"landing must be a real (..., 3) array of {list(names)}; got "
                            f"{arr.dtype} values of shape {arr.shape}", option="landing")
        self.lead = arr.shape[:-1]
        if self.form_in == "cartesian":  # named here, in the units given, before the conversion rescales it
            check_downward(arr.reshape(-1, 3)[:, 1], unit=(unit_pair(self.units) or ("radii/s",))[0])
        # the unit guard judges the converted landings, as it judges every landing
        return physical_to_scaled(arr, units=self.units, form=self.form_in, kind="landing", radius_m=self.radius_m)

    def liftoff(self, out: np.ndarray) -> Any:
        """Scaled (n, 3) lift-offs in the caller's units, form and kind."""
        res = scaled_to_physical(out, units=self.units, form=self.form_out, kind="liftoff", radius_m=self.radius_m)
        if self.index is not None:
            import pandas as pd  # (imported already: the landings were a DataFrame)

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
