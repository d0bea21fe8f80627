""":func:`save_campaign`: writing a campaign to netCDF so that loading it gives it back bit for bit."""

from __future__ import annotations

import errno
import os
from pathlib import Path

import numpy as np
import xarray as xr

from bouncelab.core.atomic import atomic_path
from bouncelab.core.errors import DataError, OutputError
from bouncelab.data.campaign import validate_campaign
from bouncelab.data.io.read import NETCDF_SUFFIXES, module_available


def save_campaign(ds: xr.Dataset, path: str | os.PathLike[str], *, engine: str | None = None) -> Path:
    """Write a campaign to a netCDF file that :func:`~bouncelab.data.io.load_campaign` reads back exactly.

    Values, the ``setting`` coordinate (numbers or strings), the prediction intervals and the attrs survive
    the round trip bit for bit. The file is written to a temporary name and renamed: a failed save leaves no
    file and an existing one untouched; an existing file keeps its permission bits, a symlink stays a symlink.

    Parameters
    ----------
    ds
        A campaign Dataset (checked with :func:`~bouncelab.data.campaign.validate_campaign`).
    path
        Destination, ending in ``.nc`` or ``.netcdf``, in an existing folder.
    engine
        xarray netCDF engine; default ``"netcdf4"`` or ``"h5netcdf"`` if installed, else ``"scipy"`` (netCDF-3).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    DataError
        ``ds`` is not a valid campaign, an attr cannot be stored, or the suffix is not a netCDF one.
    OutputError
        The file cannot be written (a missing or read-only folder, a folder in the way, a full disk): an
        ``OSError`` naming the path (``err.path``), its ``reason`` and ``errno``; nothing is written.
    """
    if not isinstance(path, str | os.PathLike):
        raise OutputError(f"save_campaign writes to a file's path; got {type(path).__name__} {path!r:.60}",
                          path=repr(path), reason="not a path")
    path = Path(path).expanduser()
    file = os.fspath(path)
    if path.suffix.lower() not in NETCDF_SUFFIXES:
        raise DataError(f"save_campaign writes netCDF; give the file a .nc suffix (got {path.suffix or 'none'!r})",
                        file=file)
    if not path.parent.is_dir():
        raise OutputError(f"cannot save {file!r}: the folder {os.fspath(path.parent)!r} does not exist", path=file,
                          reason="the folder does not exist", errno=errno.ENOENT)
    checked = validate_campaign(ds, file=file)
    for key, value in checked.attrs.items():
        if isinstance(value, list | tuple | np.ndarray):
            ok = (arr := np.asarray(value)).ndim == 1 and arr.dtype.kind in "iuf"
        else:
            ok = isinstance(value, str | int | float | np.floating | np.integer) and not isinstance(value, bool)
        if not ok:
            raise DataError(f"attribute {key!r} = {value!r} cannot be stored in netCDF (use a string, a number or a "
                            "1-D list of numbers)", file=file)
    engine = engine or next((e.lower() for e in ("netCDF4", "h5netcdf") if module_available(e)), "scipy")
    checked = _storable_settings(checked, engine)
    # Atomic, keeping the target's permission bits, and writing through a symlink (bouncelab.core.atomic).
    try:
        with atomic_path(path) as tmp:
            checked.to_netcdf(tmp, engine=engine)
    except OutputError:
        raise
    except OSError as exc:  # read-only folder, a folder in the way, disk full: say which path
        reason = exc.strerror or str(exc)
        raise OutputError(f"cannot save {file!r}: {reason}; nothing was written", path=file, reason=reason,
                          errno=exc.errno) from exc
    return path


def _storable_settings(ds: xr.Dataset, engine: str) -> xr.Dataset:
    """Settings beyond int32 as marked text: netCDF-3 (the scipy engine) has no 64-bit integers."""
    if engine != "scipy" or "setting" not in ds.coords or ds["setting"].dtype.kind not in "iu":
        return ds
    s = ds["setting"].values
    if s.size == 0 or (s.min() >= np.iinfo(np.int32).min and s.max() <= np.iinfo(np.int32).max):
        return ds
    attrs = {**ds["setting"].attrs, "bouncelab_dtype": "int64"}
    return ds.assign_coords(setting=("bounce", np.array([str(int(v)) for v in s]), attrs))
