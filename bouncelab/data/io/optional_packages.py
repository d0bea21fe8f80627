"""Whether an optional package (openpyxl, xlrd, netCDF4, h5netcdf) is installed."""

from __future__ import annotations

import importlib.util


def _module_available(name: str) -> bool:
    return importlib.util.find_spec(name) is not None
