"""Turning a table read from a file into a campaign: select the columns, parse the cells,
convert to scaled units and validate, with every error located in the file.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.data.campaign import make_campaign
from bouncelab.data.io.cell_values import _numbers, _setting_values
from bouncelab.data.io.column_selection import _select_auto, _select_explicit
from bouncelab.data.io.column_units import _ROLE_KINDS, _column_unit, _describe_units
from bouncelab.data.io.plausibility import _check_plausible
from bouncelab.data.io.synonyms import _PI_STATES, _STATES
from bouncelab.data.io.table import _Column, _err, _Table
from bouncelab.data.units import COMPONENTS, spin_to_scaled, velocity_to_scaled
from bouncelab.data.validation import as_states
from bouncelab.errors import DataError


def _campaign_from_table(
    table: _Table,
    *,
    columns: Mapping[str, Any] | None,
    units: dict[str, str],
    campaign: str,
    surface: str,
    source: str,
    ball_radius_m: float,
) -> xr.Dataset:
    file = table.file
    if table.n_rows == 0:
        raise DataError("the file has a header but no data rows", file=file)
    chosen = _select_explicit(table, columns) if columns is not None else _select_auto(table)
    cols = {role: ch.column for role, ch in chosen.items()}

    used: dict[str, str] = {}
    for role, col in cols.items():
        if col.name in used:
            raise DataError(f"the same column is asked for as {used[col.name]} and as {role}",
                            file=file, column=col.name)
        used[col.name] = role
    lengths = {c.name: len(c.values) for c in cols.values()}
    if len(set(lengths.values())) > 1:
        longest = max(lengths, key=lambda k: lengths[k])
        raise DataError(f"the columns have different lengths {lengths}; one value per bounce in each",
                        file=file, column=longest)

    # Cell values: report the first bad cell in row order.
    parsed: dict[str, np.ndarray] = {}
    errors: list[DataError] = []
    for role, col in cols.items():
        if role == "setting":
            continue
        parsed[role], error = _numbers(table, col)
        if error is not None:
            errors.append(error)
    setting = None
    if "setting" in cols:
        try:
            setting = _setting_values(table, cols["setting"])
        except DataError as exc:
            errors.append(exc)
    if errors:
        raise min(errors, key=lambda e: e.row or 0)

    # Units.
    unit_of: dict[str, tuple[str, str]] = {}
    scaled: dict[str, np.ndarray] = {}
    for role in parsed:
        kind = _ROLE_KINDS[role.split(".")[1]]
        unit, origin = _column_unit(table, chosen[role], kind, units)
        unit_of[role] = (unit, origin)
        if kind == "velocity":
            scaled[role] = velocity_to_scaled(parsed[role], unit, radius_m=ball_radius_m)
        else:
            scaled[role] = spin_to_scaled(parsed[role], unit)

    states: dict[str, np.ndarray] = {}
    for state in (*_STATES, *_PI_STATES):
        roles = [f"{state}.{c}" for c in COMPONENTS]
        if roles[0] not in scaled:
            continue
        arr = np.column_stack([scaled[r] for r in roles])
        try:
            states[state], _ = as_states(arr, state, landing=state == "landing", file=file)
        except DataError as exc:
            raise _relocate(table, exc, cols) from None
        if state in _PI_STATES and (arr < 0).any():
            i, k = (int(v) for v in np.argwhere(arr < 0)[0])
            raise _err(table, f"prediction-interval half-width {float(parsed[roles[k]][i])!r} is negative",
                       cols[roles[k]].name, i)

    _check_plausible(table, cols, scaled, parsed, unit_of)

    attrs = {"source_units": _describe_units(unit_of, cols)}
    try:
        return make_campaign(
            states["landing"], states["liftoff"], setting=setting,
            landing_pi=states.get("landing_pi"), liftoff_pi=states.get("liftoff_pi"),
            campaign=campaign, surface=surface, ball_radius_m=ball_radius_m, source=source,
            data_kind="measured", attrs=attrs,
        )
    except DataError as exc:  # pragma: no cover - everything is checked above
        raise _relocate(table, exc, cols) from None


def _relocate(table: _Table, exc: DataError, cols: dict[str, _Column]) -> DataError:
    """A validation error re-raised with the file's column name and row location."""
    role = exc.column or ""
    col = cols.get(role) or cols.get(f"{role}.xdot")
    name = col.name if col is not None else exc.column
    if exc.row is None:
        return DataError(exc.message, file=table.file, column=name)
    return _err(table, exc.message, name, exc.row - 1)
