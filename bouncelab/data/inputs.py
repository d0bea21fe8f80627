"""What every fitter and analysis accepts as its ``data``: a campaign Dataset, a DataFrame or arrays.

:func:`campaign_arrays` is the one place where ``bouncelab.fit``, the metrics, the analyses and the plots
read their ``data`` argument, so that every entry point validates alike. It sits above the file loader:
a DataFrame (one row per bounce) is read exactly as :func:`bouncelab.load_campaign` reads a file.
"""

from __future__ import annotations

import sys

import numpy as np
import xarray as xr

from bouncelab.core.errors import DataError
from bouncelab.core.validation import as_states, check_same_length
from bouncelab.data.campaign import setting_labels
from bouncelab.data.io import load_campaign

__all__ = ["campaign_arrays"]


def campaign_arrays(data, *, name: str = "data") -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Landing, lift-off and setting arrays from a campaign Dataset or a ``(landing, liftoff)`` pair.

    This is the one place where fitters and analyses accept their ``data``
    argument, so every entry point validates the same way.
    """
    if isinstance(data, xr.Dataset):
        for var in ("landing", "liftoff"):
            if var not in data.data_vars:
                raise DataError(f"{name} has no {var!r} variable; it has {sorted(map(str, data.data_vars))}",
                                column=var, option=name)
        p0, _ = as_states(data["landing"], "landing", landing=True)
        pf, _ = as_states(data["liftoff"], "liftoff")
        check_same_length(p0, pf, "landing", "liftoff")
        setting = data["setting"].values if "setting" in data.coords else None
        return p0, pf, setting
    if isinstance(data, tuple | list) and len(data) in (2, 3):
        p0, _ = as_states(data[0], "landing", landing=True)
        pf, _ = as_states(data[1], "liftoff")
        check_same_length(p0, pf, "landing", "liftoff")
        setting = None if len(data) == 2 or data[2] is None else setting_labels(data[2], p0.shape[0])
        return p0, pf, setting
    if _is_dataframe(data):  # one row per bounce, read as load_campaign reads a file
        return campaign_arrays(load_campaign(data), name=name)
    raise DataError(
        f"{name} must be a campaign Dataset or a (landing, liftoff) pair of (n, 3) arrays; "
        f"got {type(data).__name__}", option=name
    )


def _is_dataframe(obj) -> bool:
    pd = sys.modules.get("pandas")  # never imported just to ask
    return pd is not None and isinstance(obj, pd.DataFrame)
