"""Reading netCDF files: a campaign written by :func:`~bouncelab.data.io.save_campaign`, or any
other file as a table of its 1-D (and 2-D) variables.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.data.campaign import validate_campaign
from bouncelab.data.io.columns import _header_unit
from bouncelab.data.io.table import _check_duplicates, _Column, _module_available, _Table, _table_of_columns
from bouncelab.data.units import BALL_RADIUS_M
from bouncelab.errors import DataError

_NETCDF_SUFFIXES = (".nc", ".netcdf")


def _open_netcdf(path: Path, file: str) -> xr.Dataset:
    try:
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            return ds.load()
    except (ValueError, OSError, TypeError) as exc:
        hint = ""
        if not (_module_available("netCDF4") or _module_available("h5netcdf")):
            hint = " (a netCDF-4/HDF5 file needs pip install h5netcdf or netCDF4)"
        raise DataError(f"cannot read it as netCDF: {exc}{hint}", file=file) from None


def _table_from_dataset(ds: xr.Dataset, file: str) -> _Table:
    columns = []
    for name, var in ds.variables.items():
        vals = var.values
        if vals.ndim == 1:
            columns.append(_Column(str(name), _dataset_values(vals), *_header_unit(str(name))))
        elif vals.ndim == 2:
            for k in range(vals.shape[1]):
                sub = f"{name}_{k + 1}"
                columns.append(_Column(sub, _dataset_values(vals[:, k]), *_header_unit(sub)))
    if not columns:
        raise DataError("the netCDF file holds no 1-D variables (columns)", file=file)
    _check_duplicates([c.name for c in columns], file)
    return _table_of_columns(file, columns)


def _dataset_values(vals: np.ndarray) -> Any:
    if vals.dtype.kind in "iuf":
        return vals.astype(float)
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
    attrs = dict(ds.attrs)
    attrs.setdefault("data_kind", "measured")
    attrs.setdefault("source", source)
    # validate_campaign restores what netCDF-3 changes (int32 integers, object strings).
    out = validate_campaign(ds.assign_attrs(attrs), file=file)
    if campaign is not None:
        out.attrs["campaign"] = str(campaign)
    if surface is not None:
        out.attrs["surface"] = str(surface)
    return out
