r"""Where the horizontal impulse acts: the per-bounce lever arm Δω/Δẋ.

A horizontal impulse J (per unit mass, radii/s) applied at the contact point of a
uniform sphere (I = 2/5 m R², scaled units) changes ẋ by J and ω by 5/2 J, so

.. math:: \ell = \frac{\Delta\omega}{\Delta\dot x} = \frac{\omega_F - \omega_0}{\dot x_F - \dot x_0} = 2.5

for every law whose whole horizontal impulse acts at the contact point (Rigid,
Penner's laws in the lab frame only approximately, Walton's law, a pure tangential
spring). An impulse through the ball's centre (a normal force from a crater wall,
"ploughing") changes ẋ but not ω. If a fraction f of the horizontal impulse passes
through the centre, ℓ = 2.5 (1 − f), so

.. math:: f = 1 - \ell / 2.5

is the *centre fraction*. ℓ is computed for measured bounces and for any law's
predictions on the same landings, so the two can be compared bounce by bounce.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core import checks
from bouncelab.core.errors import DataError
from bouncelab.data.inputs import campaign_arrays

__all__ = ["CONTACT_POINT_LEVER_ARM", "MIN_DXDOT_FRACTION", "impulse_lever_arm", "lever_arm_summary"]

#: Δω/Δẋ of an impulse at the contact point of a uniform sphere (I = 2/5 m R²).
CONTACT_POINT_LEVER_ARM = 2.5
#: Default threshold: bounces with |Δẋ| below this fraction of the landing speed ‖p₀‖ get no lever arm (NaN).
MIN_DXDOT_FRACTION = 0.02


def _lever(p0: np.ndarray, pf: np.ndarray, min_fraction: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    dx = pf[:, 0] - p0[:, 0]
    dw = pf[:, 2] - p0[:, 2]
    defined = np.abs(dx) >= min_fraction * np.linalg.norm(p0, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        lever = np.where(defined, dw / np.where(defined, dx, 1.0), np.nan)
    return dx, dw, lever


def impulse_lever_arm(data: Any, *, min_fraction: float = MIN_DXDOT_FRACTION) -> xr.Dataset:
    """Per-bounce lever arm ℓ = Δω/Δẋ of the horizontal impulse, and the centre fraction 1 − ℓ/2.5.

    Parameters
    ----------
    data
        A campaign Dataset, or a ``(landing, liftoff)`` pair of (n, 3) arrays in scaled units
        (e.g. a law's predictions: ``(landing, law.predict(landing))``).
    min_fraction
        Bounces whose |Δẋ| is below ``min_fraction`` times their landing speed ‖p₀‖
        (radii/s) get NaN: there the ratio is dominated by measurement noise.

    Returns
    -------
    xarray.Dataset
        Dimension ``bounce``; variables ``dxdot`` (radii/s), ``domega`` (rad/s),
        ``lever_arm`` (rad/radius, i.e. per radius of Δẋ; NaN where undefined) and
        ``centre_fraction`` (dimensionless).

    Examples
    --------
    >>> import numpy as np, bouncelab as bl
    >>> p0 = np.array([[1000.0, -800.0, 300.0]])
    >>> float(impulse_lever_arm((p0, bl.Rigid(r=0.5, mu=0.4).predict(p0)))["lever_arm"][0])
    2.5
    """
    if not checks.finite(min_fraction, "min_fraction", error=DataError, low=0.0, want="a number in [0, 1)") < 1:
        raise DataError(f"min_fraction must be in [0, 1); got {min_fraction!r}", option="min_fraction")
    p0, pf, _ = campaign_arrays(data, name="data")
    dx, dw, lever = _lever(p0, pf, min_fraction)
    ds = xr.Dataset(
        {
            "dxdot": ("bounce", dx, {"units": "radius/s"}),
            "domega": ("bounce", dw, {"units": "rad/s"}),
            "lever_arm": ("bounce", lever, {"units": "1", "long_name": "domega / dxdot"}),
            "centre_fraction": ("bounce", 1.0 - lever / CONTACT_POINT_LEVER_ARM, {"units": "1"}),
        }
    )
    if isinstance(data, xr.Dataset):
        if "bounce" in data.coords:
            ds = ds.assign_coords(bounce=data["bounce"].values)
        ds.attrs.update(data.attrs)
    return ds


def lever_arm_summary(data: Any, laws: Iterable[Any] = (), *,
                      min_fraction: float = MIN_DXDOT_FRACTION) -> pd.DataFrame:
    """Median and quartiles of the lever arm for the data and for each law on the same landings.

    Parameters
    ----------
    data
        A campaign Dataset or ``(landing, liftoff)`` pair.
    laws
        Fitted laws (or a :class:`~bouncelab.FitResult` / comparison entries with a
        ``model`` attribute); each predicts the lift-off of the data's landings.

    Returns
    -------
    pandas.DataFrame
        One row per source (``"data"``, then each law by class name, numbered if
        repeated): ``n_defined``, ``median``, ``q25``, ``q75`` of ℓ, and
        ``centre_fraction`` = 1 − median/2.5.
    """
    p0, pf, _ = campaign_arrays(data, name="data")
    rows: dict[str, dict[str, float]] = {}

    def add(name: str, liftoff: np.ndarray) -> None:
        _, _, lever = _lever(p0, liftoff, min_fraction)
        ok = lever[np.isfinite(lever)]
        q = np.quantile(ok, [0.25, 0.5, 0.75]) if ok.size else np.full(3, np.nan)
        key = name
        i = 2
        while key in rows:
            key = f"{name} ({i})"
            i += 1
        rows[key] = {"n_defined": float(ok.size), "median": q[1], "q25": q[0], "q75": q[2],
                     "centre_fraction": 1.0 - q[1] / CONTACT_POINT_LEVER_ARM}

    add("data", pf)
    for law in laws:
        model = getattr(law, "model", law)
        add(type(model).__name__, np.asarray(model.predict(p0, plausible=None)))  # campaign data: checked
    out = pd.DataFrame.from_dict(rows, orient="index")
    out["n_defined"] = out["n_defined"].astype(int)
    out.index.name = "source"
    return out
