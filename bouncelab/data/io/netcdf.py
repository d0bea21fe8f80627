"""Reading netCDF files: a campaign written by :func:`~bouncelab.data.io.save_campaign`, or any
other file as a table of its 1-D (and 2-D) variables.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core.errors import DataError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, check_scaled, implausibility
from bouncelab.core.units import BALL_RADIUS_M
from bouncelab.data.campaign import validate_campaign
from bouncelab.data.io.columns import _header_unit
from bouncelab.data.io.table import _check_duplicates, _Column, _module_available, _Table, _table_of_columns

_NETCDF_SUFFIXES = (".nc", ".netcdf")


def _open_netcdf(path: Path, file: str) -> xr.Dataset:
    try:
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            return ds.load()
    except Exception as exc:
        hint = ""
        if not (_module_available("netCDF4") or _module_available("h5netcdf")):
            hint = " (a netCDF-4/HDF5 file needs pip install h5netcdf or netCDF4)"
        raise DataError(f"cannot read it as netCDF: {exc}{hint}", file=file) from None


def _column(name: str, vals: np.ndarray, attrs: dict) -> _Column:
    """A column named after its variable; its unit from the name, else the CF ``units`` attribute."""
    unit, in_name = _header_unit(name)
    cf = attrs.get("units")
    if unit is None and isinstance(cf, str) and cf.strip():
        return _Column(name, _dataset_values(vals), cf.strip(), False, "units attribute")
    return _Column(name, _dataset_values(vals), unit, in_name)


def _table_from_dataset(ds: xr.Dataset, file: str) -> _Table:
    columns = []
    for name, var in ds.variables.items():
        vals = var.values
        if vals.ndim == 1:
            columns.append(_column(str(name), vals, var.attrs))
        elif vals.ndim == 2:
            for k in range(vals.shape[1]):
                columns.append(_column(f"{name}_{k + 1}", vals[:, k], var.attrs))
    if not columns:
        raise DataError("the netCDF file holds no 1-D variables (columns)", file=file)
    _check_duplicates([c.name for c in columns], file)
    return _table_of_columns(file, columns)


def _dataset_values(vals: np.ndarray) -> Any:
    if vals.dtype.kind == "f":
        return vals.astype(float)
    if vals.dtype.kind in "iu":
        return vals  # integers stay exact (setting IDs)
    if vals.dtype.kind == "S":
        return [v.decode("utf-8", "replace") for v in vals]
    return list(vals)


def _campaign_from_netcdf(
    ds: xr.Dataset,
    *,
    file: str,
    source: str,
    columns: Any,
    units: Any,
    campaign: str | None,
    surface: str | None,
    ball_radius_m: float,
    plausible: PlausibleRanges = PLAUSIBLE_RANGES,
) -> xr.Dataset:
    if columns is not None or units is not None:
        raise DataError(
            "this is a bouncelab campaign file (scaled units, named variables): "
            "do not pass columns= or units=", file=file,
        )
    stored_radius = ds.attrs.get("ball_radius_m")
    if (stored_radius is not None and ball_radius_m != BALL_RADIUS_M
            and float(stored_radius) != float(ball_radius_m)):
        raise DataError(
            f"the campaign was scaled with ball_radius_m={float(stored_radius)!r}, "
            f"not {ball_radius_m!r}; a campaign file cannot be rescaled on loading", file=file,
        )
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        unit = ds[var].attrs.get("units") if var in ds.variables else None
        if unit is not None and str(unit).strip().lower() not in ("scaled", ""):
            raise DataError(
                f"the variable {var!r} says units={unit!r}, but a campaign file holds scaled units "
                "(radii/s and rad/s, units='scaled'); convert it with bouncelab.core.units.to_scaled "
                "and save it with save_campaign, or rename the variables to load the file as a table",
                file=file, column=var,
            )
    if "setting" in ds.data_vars:  # a setting stored as a variable is still the setting
        ds = ds.set_coords("setting")
    if "setting" in ds.coords and ds["setting"].attrs.get("bouncelab_dtype") == "int64":
        try:  # save_campaign's netCDF-3 spelling of int64 settings
            labels = np.array([int(str(v)) for v in ds["setting"].values], dtype=np.int64)
        except (ValueError, OverflowError):
            raise DataError("the setting labels marked int64 are not all integers", file=file,
                            column="setting") from None
        attrs_s = {k: v for k, v in ds["setting"].attrs.items() if k != "bouncelab_dtype"}
        ds = ds.assign_coords(setting=("bounce", labels, attrs_s))
    attrs = dict(ds.attrs)
    attrs.setdefault("data_kind", "measured")
    attrs.setdefault("source", source)
    # validate_campaign restores what netCDF-3 changes (int32 integers, object strings).
    out = validate_campaign(ds.assign_attrs(attrs), file=file)
    why = implausibility(out["landing"].values, out["liftoff"].values,
                         radius_m=float(out.attrs.get("ball_radius_m", BALL_RADIUS_M)), ranges=plausible)
    if why is not None:
        raise DataError(f"{why.state} {why.component} of bounce {why.row}: {why.reason}; the file is not in "
                        "scaled units (radii/s, rad/s) as a campaign file must be", file=file, column=why.state,
                        row=None if why.row is None else why.row + 1)
    try:  # and the lower limits: all spins tiny, landings far too slow (a damaged file, or m/s and rpm)
        check_scaled(out["landing"].values, out["liftoff"].values,
                     radius_m=float(out.attrs.get("ball_radius_m", BALL_RADIUS_M)), ranges=plausible)
    except DataError as exc:
        raise DataError(f"{exc}; a campaign file holds scaled units (radii/s, rad/s)", file=file) from None
    if campaign is not None:
        out.attrs["campaign"] = str(campaign)
    if surface is not None:
        out.attrs["surface"] = str(surface)
    return out
