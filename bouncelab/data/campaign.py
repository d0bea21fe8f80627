"""The campaign container: bounces as a labelled :class:`xarray.Dataset`.

A campaign has dimensions ``bounce`` and ``component`` and holds

``landing`` (bounce, component)
    ``[xdot0, ydot0, omega0]`` just before touch-down, scaled units.
``liftoff`` (bounce, component)
    ``[xdotF, ydotF, omegaF]`` just after lift-off, scaled units.
``landing_pi``, ``liftoff_pi`` (bounce, component), optional
    Half-widths of the 95 % prediction intervals of each measurement.
``setting`` (bounce), optional coordinate
    Launcher setting of each bounce (repeats share a setting).

The ``component`` coordinate is ``["xdot", "ydot", "omega"]`` with a ``unit``
coordinate beside it; attrs name the campaign, surface, ball radius, source
and whether the data are measured or a synthetic surrogate.
"""

from __future__ import annotations

import contextlib
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import checks
from bouncelab.core.errors import DataError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, check_scaled
from bouncelab.core.units import (
    BALL_RADIUS_M,
    COMPONENT_UNITS,
    COMPONENTS,
    CONVENTIONS,
    Z95,
    ball_radius,
    canonical_unit,
)
from bouncelab.core.validation import as_states, check_same_length

__all__ = [
    "CONVENTIONS",
    "interval_sds",
    "make_campaign",
    "setting_labels",
    "synthetic_warning",
    "validate_campaign",
]

#: Text stored in every campaign's attrs so a file explains its own sign conventions.

DATA_KINDS = ("measured", "synthetic surrogate", "unknown")


def make_campaign(
    landing,
    liftoff,
    *,
    setting=None,
    landing_pi=None,
    liftoff_pi=None,
    campaign: str = "",
    surface: str = "",
    ball_radius_m: float = BALL_RADIUS_M,
    source: str = "",
    data_kind: str = "unknown",
    attrs: dict[str, Any] | None = None,
    plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
) -> xr.Dataset:
    """Build a validated campaign Dataset from (n, 3) arrays in scaled units.

    Parameters
    ----------
    landing, liftoff
        (n, 3) arrays ``[xdot, ydot, omega]`` in radii/s and rad/s.
    setting
        Optional length-n launcher setting label of each bounce (int or str).
    landing_pi, liftoff_pi
        Optional (n, 3) half-widths of the 95 % prediction intervals (same units).
    campaign, surface, source
        Descriptive attrs.
    ball_radius_m
        Ball radius used for the scaling, in metres (within
        :data:`~bouncelab.core.units.BALL_RADIUS_RANGE_M`; see :func:`~bouncelab.core.units.ball_radius`).
    data_kind
        ``"measured"``, ``"synthetic surrogate"`` or ``"unknown"``.
    attrs
        Further attrs to store. They cannot replace ``conventions`` (which
        describes the arrays' scaled units), and a ``data_kind`` given here is
        checked like the argument.
    plausible
        The magnitudes a golf bounce can have
        (:data:`~bouncelab.core.plausibility.PLAUSIBLE_RANGES`, the loader's ranges). Values
        that only a unit mistake makes are refused: any speed beyond 90 m/s or spin beyond
        20 000 rpm, a median landing speed below 1 m/s (m/s given as radii/s), a campaign
        spinning nowhere faster than 300 rpm. Widen them on purpose with
        ``PLAUSIBLE_RANGES.widened(max_spin=...)``; ``None`` checks nothing.

    Raises
    ------
    DataError
        On any bad array (shape, NaN, a landing with ``ydot >= 0``, ...), and on values
        implausible in scaled units: the message names the column (``xdot0`` ... ``omegaF``),
        the unit the numbers look like and how to convert or widen.

    Notes
    -----
    The arrays are copied: changing the caller's arrays afterwards does not
    change (or invalidate) the campaign.
    """
    for name, value in (("campaign", campaign), ("surface", surface), ("source", source), ("data_kind", data_kind)):
        checks.text(value, name, error=DataError)  # written into every file: text a file can hold
    p0, _ = as_states(landing, "landing", landing=True)
    pf, _ = as_states(liftoff, "liftoff")
    check_same_length(p0, pf, "landing", "liftoff")
    check_scaled(p0, pf, radius_m=ball_radius(ball_radius_m), ranges=plausible)
    pis = {key: None if pi is None else _interval(p0, pi, key) for key, pi in (("landing_pi", landing_pi),
                                                                             ("liftoff_pi", liftoff_pi))}
    # as_states may return the caller's own array; the campaign must not share memory with it.
    return build_campaign(p0.copy(), pf.copy(), setting=setting, **pis, campaign=campaign, surface=surface,
                          ball_radius_m=ball_radius_m, source=source, data_kind=data_kind, attrs=attrs)


def _interval(p0: np.ndarray, pi: Any, key: str) -> np.ndarray:
    arr, _ = as_states(pi, key)
    check_same_length(p0, arr, "landing", key)
    if (arr < 0).any():
        row = int(np.argmax((arr < 0).any(axis=1)))
        raise DataError("prediction-interval half-widths must be >= 0", column=key, row=row + 1)
    return arr.copy()


def build_campaign(p0: np.ndarray, pf: np.ndarray, *, setting=None, landing_pi: np.ndarray | None = None,
                   liftoff_pi: np.ndarray | None = None, campaign: str = "", surface: str = "",
                   ball_radius_m: float = BALL_RADIUS_M, source: str = "", data_kind: str = "unknown",
                   attrs: dict[str, Any] | None = None) -> xr.Dataset:
    """The campaign Dataset of arrays already checked (:func:`make_campaign` checks them; the loader checks them
    once, in the file's terms) and owned by the campaign."""
    data_kind = (attrs or {}).get("data_kind", data_kind)
    if data_kind not in DATA_KINDS:
        raise DataError(f"data_kind must be one of {DATA_KINDS}; got {data_kind!r}", option="data_kind")
    n = p0.shape[0]
    dims = ("bounce", "component")
    data_vars: dict[str, Any] = {
        "landing": (dims, p0, {"long_name": "state just before touch-down", "units": "scaled"}),
        "liftoff": (dims, pf, {"long_name": "state just after lift-off", "units": "scaled"}),
    }
    for key, pi in (("landing_pi", landing_pi), ("liftoff_pi", liftoff_pi)):
        if pi is not None:
            data_vars[key] = (dims, pi, {"long_name": "half-width of the 95% prediction interval", "units": "scaled"})
    coords: dict[str, Any] = {
        "bounce": ("bounce", np.arange(n), {"long_name": "bounce index (0-based)"}),
        "component": ("component", list(COMPONENTS)),
        "unit": ("component", list(COMPONENT_UNITS)),
    }
    if setting is not None:
        s = setting_labels(setting, n)
        coords["setting"] = ("bounce", s, {"long_name": "launcher setting"})
    all_attrs = {
        "campaign": str(campaign),
        "surface": str(surface),
        "ball_radius_m": float(ball_radius_m),
        "source": str(source),
        "data_kind": data_kind,
    }
    all_attrs.update(attrs or {})
    all_attrs["conventions"] = CONVENTIONS
    return xr.Dataset(data_vars, coords=coords, attrs=all_attrs)


def synthetic_warning(data: Any) -> str | None:
    """What a report must say of synthetic data: the campaign's own ``warning`` (what made it), or a plain
    "not measured" when it has none; None for measured data and for anything but a campaign Dataset."""
    if not isinstance(data, xr.Dataset) or data.attrs.get("data_kind") != "synthetic surrogate":
        return None
    return str(data.attrs.get("warning") or "These bounces are synthetic, not measured.")


def setting_labels(setting: Any, n: int) -> np.ndarray:
    """Launcher-setting labels as a length-n array of int64 or str, validated.

    Whole-number floats become int64 (netCDF3 stores int32: one dtype survives a
    round trip); objects and bytes become str.

    Raises
    ------
    DataError
        Wrong length, or a missing label (NaN or None), naming the row.
    """
    s = np.asarray(setting)
    if s.shape != (n,):
        raise DataError(f"setting must have one label per bounce ({n}); got shape {s.shape}", column="setting")
    if s.dtype.kind == "f":
        if not np.isfinite(s).all():
            row = int(np.argmax(~np.isfinite(s)))
            raise DataError("setting label is missing (NaN)", column="setting", row=row + 1)
        if np.all(s == np.round(s)) and np.all(np.abs(s) < 2.0**53):  # whole and exact in int64
            s = s.astype(np.int64)
    if s.dtype.kind in "iu":
        s = s.astype(np.int64)
    if s.dtype.kind == "O":
        missing = [i for i, v in enumerate(s) if v is None or (isinstance(v, float) and v != v)]
        if missing:
            raise DataError("setting label is missing (None or NaN)", column="setting", row=missing[0] + 1)
    if s.dtype.kind in "OS":
        s = s.astype(str)
    return s


def validate_campaign(ds: xr.Dataset, *, file: str | None = None) -> xr.Dataset:
    """Check that ``ds`` is a well-formed campaign and return it in canonical form.

    The returned Dataset has the variables in (bounce, component) order with
    components ``xdot, ydot, omega``; values are unchanged. This checks the form, not the
    plausibility of the magnitudes (that is :func:`make_campaign`'s ``plausible=`` and the
    loader's), so a campaign built with widened ranges stays valid.

    Raises
    ------
    DataError
        Missing ``landing``/``liftoff`` variables or dimensions, bad values.
    """
    if not isinstance(ds, xr.Dataset):
        raise DataError(f"a campaign must be an xarray.Dataset; got {type(ds).__name__}", file=file, option="ds")
    for var in ("landing", "liftoff"):
        if var not in ds.data_vars:
            raise DataError(
                f"campaign has no {var!r} variable; it has {sorted(map(str, ds.data_vars))}", file=file, column=var
            )
        if set(ds[var].dims) != {"bounce", "component"}:
            raise DataError(f"{var!r} must have dimensions (bounce, component); got {ds[var].dims}", file=file,
                            column=var)
    for var in ("landing_pi", "liftoff_pi"):
        if var in ds.data_vars and set(ds[var].dims) != {"bounce", "component"}:
            raise DataError(f"{var!r} must have dimensions (bounce, component); got {ds[var].dims}", file=file,
                            column=var)
    _check_unit_coord(ds, file)
    setting = ds["setting"].values if "setting" in ds.coords else None
    pis = {k: ds[k] for k in ("landing_pi", "liftoff_pi") if k in ds.data_vars}
    p0, _ = as_states(ds["landing"].transpose("bounce", "component"), "landing", landing=True, file=file)
    pf, _ = as_states(ds["liftoff"].transpose("bounce", "component"), "liftoff", file=file)
    check_same_length(p0, pf, "landing", "liftoff")
    kept = {k: v for k, v in ds.attrs.items() if k not in ("conventions",)}
    radius = kept.pop("ball_radius_m", BALL_RADIUS_M)
    if isinstance(radius, str):  # an attribute another tool wrote as text: read as the number it spells, if any
        with contextlib.suppress(ValueError):
            radius = float(radius)
    radius = ball_radius(radius, file=file)  # ("abc", NaN, True: a DataError naming the file)
    out = build_campaign(  # each array checked once; copied so that the campaign owns its memory
        p0.copy(), pf.copy(), setting=setting, **{k: _interval(p0, v.transpose("bounce", "component"), k)
                                                  for k, v in pis.items()},
        campaign=kept.pop("campaign", ""), surface=kept.pop("surface", ""), ball_radius_m=radius,
        source=kept.pop("source", ""), data_kind=kept.pop("data_kind", "unknown"), attrs=kept,
    )
    if "bounce" in ds.coords:
        bounce = ds["bounce"].values
        bounce = bounce.astype(np.int64) if bounce.dtype.kind in "iu" else bounce
        out = out.assign_coords(bounce=("bounce", bounce, dict(ds["bounce"].attrs)))
    for name, coord in ds.coords.items():  # per-bounce labels (e.g. the clip each bounce came from) are kept
        if name in out.coords or coord.dims != ("bounce",):
            continue
        values = coord.values
        if values.dtype.kind == "S" or (values.dtype.kind == "O" and all(isinstance(v, str | bytes) for v in values)):
            values = np.array([v.decode("utf-8", "replace") if isinstance(v, bytes) else v for v in values], dtype=str)
        if values.dtype.kind in "iufU":  # what netCDF stores (netCDF-3 gives text back as objects or bytes)
            out = out.assign_coords({name: ("bounce", values, dict(coord.attrs))})
    return out


def _check_unit_coord(ds: xr.Dataset, file: str | None) -> None:
    """A ``unit`` coordinate along ``component`` must name the scaled units, or the numbers are not scaled."""
    if "unit" not in ds.coords or ds["unit"].dims != ("component",):
        return
    comps = [str(c) for c in ds["component"].values] if "component" in ds.coords else list(COMPONENTS)
    for comp, unit in zip(comps, ds["unit"].values, strict=True):
        if comp not in COMPONENTS:
            continue  # reported by as_states
        kind = "spin" if comp == "omega" else "velocity"
        expected = COMPONENT_UNITS[COMPONENTS.index(comp)]
        try:
            ok = canonical_unit(str(unit), kind) == expected
        except DataError:
            ok = False
        if not ok:
            raise DataError(
                f"the unit coordinate says {comp} is in {str(unit)!r}; a campaign holds scaled units "
                f"({dict(zip(COMPONENTS, COMPONENT_UNITS, strict=True))}): convert with bouncelab.core.units first",
                file=file, column="unit",
            )


def interval_sds(data: Any, n: int | None = None) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Standard deviations of the measurement errors of the landings and the lift-offs, each ``(n, 3)``, from
    a campaign's 95 % prediction-interval half-widths (``landing_pi / Z95``, ``liftoff_pi / Z95``); None for a
    state without intervals, and both None for anything but a campaign Dataset.

    Raises
    ------
    DataError
        Half-widths that are not finite or negative (naming the variable and the row), or of another length
        than ``n`` bounces.
    """
    if not isinstance(data, xr.Dataset):
        return None, None
    out: list[np.ndarray | None] = []
    for var in ("landing_pi", "liftoff_pi"):
        if var not in data.data_vars:
            out.append(None)
            continue
        h = np.asarray(data[var].transpose("bounce", "component").values, dtype=float)
        rows = h.shape[0] if n is None else n
        if h.shape != (rows, 3) or not np.isfinite(h).all() or (h < 0).any():
            bad = ~np.isfinite(h) | (h < 0)
            row = int(np.argmax(bad.any(axis=1))) + 1 if h.shape == (rows, 3) else None
            raise DataError("prediction-interval half-widths must be finite and >= 0", column=var, row=row)
        out.append(h / Z95)
    return out[0], out[1]
