"""Shared validation of bounce-state arrays.

Every public entry point that takes landing or lift-off states calls
:func:`as_states` once; the laws, metrics and fitters then work on clean
``(n, 3)`` float64 arrays and never re-check.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core import checks
from bouncelab.core._parallel import run_chunked
from bouncelab.core.checks import _NOT_REAL
from bouncelab.core.errors import DataError
from bouncelab.core.landing_checks import STATE_LIMIT, is_landing
from bouncelab.core.units import COMPONENT_UNITS, COMPONENTS

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["NORM_MIN", "STATE_LIMIT", "States", "as_states", "check_downward", "check_same_length", "check_values",
           "inverse_norms", "is_dataarray", "is_landing", "real_array", "refuse_non_numeric"]

States = Any  # an (..., 3) array-like, a DataFrame with named columns, or an xarray.DataArray

#: Smallest landing norm ||p0|| (radii/s) by which delta and Delta q may divide.
NORM_MIN = 1.0e-6


def as_states(
    states: States,
    name: str = "landing",
    *,
    landing: bool = False,
    file: str | None = None,
    defer_check: bool = False,
) -> tuple[np.ndarray, Callable[[np.ndarray], Any]]:
    """Validate ``states`` and return them as a C-contiguous (n, 3) float64 array.

    Parameters
    ----------
    states
        An array-like whose last axis holds ``[xdot, ydot, omega]`` (scaled
        units), or an :class:`xarray.DataArray` with a ``component`` dimension.
    name
        What the states are, for error messages ("landing", "liftoff", ...).
    landing
        If true, also require ``ydot < 0`` (a landing moves downward).
    file
        File the data came from, for error messages.
    defer_check
        Leave the value checks (finite, magnitude, sign of ydot) to the caller, which makes
        them in its own pass over the values (a law's, :meth:`BounceModel.predict
        <bouncelab.BounceModel.predict>`) and calls :func:`check_values` to name a bad value.
        Labelled input (a DataFrame) is checked here all the same, to name its own rows.

    Returns
    -------
    array, wrap
        The (n, 3) array and a function that turns an (n, 3) result, or an (n,)
        result with one value per bounce, back into the caller's kind: same
        leading shape, or a DataArray with the same dimensions and coordinates.

    Raises
    ------
    DataError
        Wrong shape, non-numeric, NaN or infinite values, or a landing with
        ``ydot >= 0``; the message names the row and component.
    """
    if is_dataarray(states):
        return _from_dataarray(states, name, landing=landing, file=file, defer_check=defer_check)
    labelled = states
    states = _from_labelled(states, name, file)
    if np.ma.isMaskedArray(states):
        mask = np.ma.getmaskarray(states)
        if mask.any():
            flat = mask.reshape(-1, mask.shape[-1]) if mask.ndim > 1 else mask.reshape(1, -1)
            row, col = np.argwhere(flat)[0]
            raise DataError(f"{name} has masked (missing) values ({int(flat.any(axis=1).sum())} bounce(s) "
                            "affected); remove or fill them first", file=file,
                            column=f"{name}.{COMPONENTS[col]}" if col < 3 else None, row=int(row) + 1)
        states = np.ma.getdata(states)
    arr = real_array(states, name, "xdot, ydot, omega", file=file)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise DataError(
            f"{name} must have shape (n, 3) with columns [xdot, ydot, omega]; got shape {arr.shape}",
            file=file, option=name,
        )
    lead = arr.shape[:-1]
    flat = np.ascontiguousarray(arr.reshape(-1, 3))
    if labelled is not states:  # pandas: an error names the caller's own row label and column
        try:
            _check_values(flat, name, landing=landing, file=file)
        except DataError as exc:
            raise _in_pandas_terms(exc, labelled, name) from None
    elif not defer_check:
        _check_values(flat, name, landing=landing, file=file)
    elif flat.shape[0] == 0:  # a shape, not a value: refused whoever checks the values
        raise DataError(f"{name} holds no bounces", file=file, option=name)

    def wrap(result: np.ndarray) -> Any:
        return _relabel(labelled, result.reshape((*lead, *result.shape[1:])))  # a tuple: lead may be ()

    return flat, wrap


def _pandas() -> Any:
    """pandas if it is imported (a DataFrame exists only then: never imported just to ask), else None."""
    return sys.modules.get("pandas")


def _relabel(like: Any, result: np.ndarray) -> Any:
    """A result of the same kind as the input: a DataFrame (same index, columns xdot, ydot, omega) for a
    DataFrame, a Series for a Series; anything else unchanged."""
    pd = _pandas()
    if pd is None:
        return result
    if isinstance(like, pd.DataFrame):
        if result.ndim == 2:
            return pd.DataFrame(result, index=like.index, columns=list(COMPONENTS))
        return pd.Series(result, index=like.index)
    if isinstance(like, pd.Series) and result.ndim == 1:
        return pd.Series(result, index=list(COMPONENTS), name=like.name)
    return result


def _from_labelled(states: Any, name: str, file: str | None) -> Any:
    """A pandas DataFrame or Series read by its column (index) names, not their order."""
    pd = _pandas()
    if pd is None or isinstance(states, np.ndarray):
        return states
    if isinstance(states, pd.DataFrame):
        labels = [str(c) for c in states.columns]
        if isinstance(states.columns, pd.RangeIndex) and len(labels) == 3:
            return states.to_numpy()
        order = _component_order(labels)
        if order is None:
            raise DataError(f"{name} DataFrame columns must be named {list(COMPONENTS)} (any order; a suffix 0 or "
                            f"F is allowed); got {labels}", file=file, option=name)
        return states.iloc[:, order].to_numpy()
    if isinstance(states, pd.Series):
        labels = [str(c) for c in states.index]
        if isinstance(states.index, pd.RangeIndex):
            return states.to_numpy()
        order = _component_order(labels)
        if order is None:
            raise DataError(f"{name} Series index must be {list(COMPONENTS)}; got {labels}", file=file, option=name)
        return states.iloc[order].to_numpy()
    return states


def _in_pandas_terms(exc: DataError, frame: Any, name: str) -> DataError:
    """``exc`` (about the (n, 3) array read from ``frame``) restated with the frame's row label and column name."""
    pd = _pandas()
    if pd is None or not isinstance(frame, pd.DataFrame) or exc.row is None:
        return exc
    column = exc.column
    if column is not None and column.startswith(f"{name}."):
        labels = [str(c) for c in frame.columns]
        order = _component_order(labels)
        component = column[len(name) + 1:]
        if order is not None and component in COMPONENTS:
            column = f"{name}.{labels[order[COMPONENTS.index(component)]]}"
    return DataError(exc.message, file=exc.file, column=column, row=exc.row, row_label=frame.index[exc.row - 1],
                     option=exc.option, hints=exc.hints)


def _component_order(labels: list[str]) -> list[int] | None:
    """Positions of xdot, ydot, omega among ``labels`` (exact names, or with one suffix 0 / F / _0 / _F)."""
    for suffix in ("", "0", "_0", "F", "_F"):
        names = [c + suffix for c in COMPONENTS]
        if all(labels.count(n) == 1 for n in names):
            return [labels.index(n) for n in names]
    return None


def refuse_non_numeric(raw: np.ndarray, name: str, components: str, *, file: str | None = None) -> None:
    """DataError when ``raw`` holds complex, boolean, text, bytes, structured or date values (which
    ``astype(float)`` would silently turn into numbers); ``components`` names what the numbers are."""
    what = _NOT_REAL.get(raw.dtype.kind)
    if what is not None:
        raise DataError(f"{name} must be numeric: real numbers ({components}); got {what} values", file=file,
                        option=name)


def real_array(value: Any, name: str, components: str, *, file: str | None = None) -> np.ndarray:
    """``value`` as a float64 array, or a DataError naming ``name``: values that are not numbers, and those
    that ``astype(float)`` would silently turn into numbers, are refused (:func:`bouncelab.core.checks.real_array`:
    also, in an array of Python objects, text, bools, None and integers beyond a float)."""
    return checks.real_array(value, name, f"real numbers ({components})", error=DataError, file=file)


def is_dataarray(obj: Any) -> bool:
    """Whether ``obj`` is an xarray DataArray (without importing xarray to ask)."""
    xr = sys.modules.get("xarray")  # a DataArray exists only if xarray was imported: never imported just to ask
    return xr is not None and isinstance(obj, xr.DataArray)


def _from_dataarray(da: xr.DataArray, name: str, *, landing: bool, file: str | None, defer_check: bool = False):
    if "component" not in da.dims:
        raise DataError(
            f"{name} DataArray needs a 'component' dimension (xdot, ydot, omega); "
            f"its dimensions are {da.dims}",
            file=file, option=name,
        )
    if da.sizes["component"] != 3:
        raise DataError(f"{name} needs 3 components; 'component' has size {da.sizes['component']}", file=file,
                        option=name)
    values = da.values
    axis = da.dims.index("component")
    if "component" in da.coords:
        labels = [str(v) for v in da["component"].values]
        if sorted(labels) != sorted(COMPONENTS):
            raise DataError(
                f"{name} component labels must be {list(COMPONENTS)}; got {labels}", file=file, option=name
            )
        if labels != list(COMPONENTS):  # reorder with numpy: xarray's .sel costs milliseconds
            values = np.take(values, [labels.index(c) for c in COMPONENTS], axis=axis)
    other = [d for d in da.dims if d != "component"]
    values = np.moveaxis(values, axis, -1)
    arr, _ = as_states(values, name, landing=landing, file=file, defer_check=defer_check)
    lead = values.shape[:-1]
    dims = (*other, "component")
    coords = {k: v for k, v in da.coords.items() if "component" not in v.dims}

    import xarray as xr

    def wrap(result: np.ndarray) -> xr.DataArray:
        if result.ndim == 1:  # one value per bounce
            return xr.DataArray(result.reshape(lead), dims=other, coords=coords)
        return xr.DataArray(
            result.reshape(*lead, 3),
            dims=dims,
            coords={**coords, "component": list(COMPONENTS), "unit": ("component", list(COMPONENT_UNITS))},
        )

    return arr, wrap


#: From this many bounces on, a compiled single pass checks the values first (3x faster than NumPy).
FAST_CHECK_MIN = 50_000


def check_values(arr: np.ndarray, name: str, *, landing: bool, file: str | None = None) -> None:
    """The value checks of :func:`as_states` on a (n, 3) float64 array (DataError naming row and column)."""
    _check_values(arr, name, landing=landing, file=file)


def _check_values(arr: np.ndarray, name: str, *, landing: bool, file: str | None) -> None:
    if arr.shape[0] == 0:
        raise DataError(f"{name} holds no bounces", file=file, option=name)
    if arr.shape[0] >= FAST_CHECK_MIN:
        from bouncelab.core._scans import all_valid  # (compiled: imports numba)

        if all(run_chunked(all_valid, arr.shape[0], arr, landing, STATE_LIMIT)):
            return
    bad = ~np.isfinite(arr)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        what = "NaN" if np.isnan(arr[row, col]) else "infinite"
        n_bad = int(bad.any(axis=1).sum())
        raise DataError(
            f"{name} value is {what} ({n_bad} bounce(s) affected)",
            file=file, column=f"{name}.{COMPONENTS[col]}", row=int(row) + 1,
        )
    big = np.abs(arr) > STATE_LIMIT
    if big.any():
        row, col = np.argwhere(big)[0]
        raise DataError(
            f"{name} value {float(arr[row, col])!r} is beyond {STATE_LIMIT:g} in scaled units (radii/s, rad/s); "
            f"no bounce is that fast - are the data in another unit? ({int(big.any(axis=1).sum())} bounce(s) "
            "affected)", file=file, column=f"{name}.{COMPONENTS[col]}", row=int(row) + 1,
        )
    if landing:
        check_downward(arr[:, 1], name, file=file)


def check_downward(ydot: np.ndarray, name: str = "landing", *, unit: str = "", file: str | None = None) -> None:
    """DataError naming the first landing whose ``ydot >= 0`` (``unit``: how the value is quoted, if not scaled)."""
    up = ydot >= 0
    if up.any():
        row = int(np.argmax(up))
        raise DataError(
            f"landing ydot must be negative (y points up, a landing moves down); "
            f"got {float(ydot[row])!r}{' ' + unit if unit else ''} ({int(up.sum())} bounce(s) affected)",
            file=file, column=f"{name}.ydot", row=row + 1,
        )


def inverse_norms(p0: np.ndarray, name: str = "landing", file: str | None = None) -> np.ndarray:
    """``1 / ||p0||`` of every landing (the weights of delta and Delta q), computed without underflow.

    Raises
    ------
    DataError
        A landing whose norm is below :data:`NORM_MIN` radii/s (its error could not be weighed).
    """
    m = np.max(np.abs(p0), axis=1)
    safe = np.where(m > 0, m, 1.0)
    norm = m * np.sqrt(np.einsum("ij,ij->i", p0 / safe[:, None], p0 / safe[:, None]))
    small = norm < NORM_MIN
    if small.any():
        row = int(np.argmax(small))
        raise DataError(
            f"{name} state has norm {float(norm[row]):.3g} radii/s, below {NORM_MIN:g}: delta and Delta q divide "
            f"each bounce's error by it ({int(small.sum())} bounce(s) affected)", file=file, row=row + 1,
        )
    return 1.0 / norm


def check_same_length(a: np.ndarray, b: np.ndarray, name_a: str, name_b: str, *, option: str | None = None) -> None:
    """Raise DataError unless two (n, 3) arrays describe the same bounces (``option``: the argument it names,
    default ``name_b``)."""
    if a.shape != b.shape:
        raise DataError(f"{name_a} has shape {a.shape} but {name_b} has shape {b.shape}; one row per bounce in each",
                        option=option or name_b)
