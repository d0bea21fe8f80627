"""The unit of each selected column (``units=``, its header or units row, else assumed) and
the ``source_units`` summary.
"""

from __future__ import annotations

from collections.abc import Mapping

from bouncelab.data.io.column_selection import _Choice
from bouncelab.data.io.header_units import _UNIT_KINDS, _unit_of
from bouncelab.data.io.table import _Column, _Table
from bouncelab.data.units import canonical_unit
from bouncelab.errors import DataError

_ROLE_KINDS = {"xdot": "velocity", "ydot": "velocity", "omega": "spin"}


def _check_units_arg(units: Mapping[str, str] | None, file: str) -> dict[str, str]:
    if units is None:
        return {}
    if not isinstance(units, Mapping):
        raise DataError(
            f"units= must be a mapping such as {{'velocity': 'm/s', 'spin': 'rpm'}}; got {units!r}",
            file=file,
        )
    bad = [k for k in units if k not in _UNIT_KINDS]
    if bad:
        raise DataError(f"units= has unknown keys {bad}; use 'velocity' and/or 'spin'", file=file)
    out = {}
    for kind, unit in units.items():
        if unit is None:
            continue
        try:
            out[kind] = canonical_unit(unit, kind)
        except DataError as exc:
            raise DataError(f"units={{{kind!r}: {unit!r}}}: {exc.message}", file=file) from None
    return out


def _column_unit(table: _Table, choice: _Choice, kind: str, given: dict[str, str]) -> tuple[str, str]:
    """Unit of a selected column and where it came from ("units=", "header", "assumed")."""
    col = choice.column
    header = None
    if col.unit_text is not None:
        known = _unit_of(col.unit_text)
        header = known.get(kind)
        if header is None and (known or not (choice.by_full_name and col.unit_in_header)):
            where = "header" if col.unit_in_header else "units row"
            what = f"a {next(iter(known))} unit, not a {kind} unit" if known else "not a known unit"
            try:
                canonical_unit(col.unit_text, kind)
            except DataError as exc:
                raise DataError(f"the {where} gives the unit {col.unit_text!r}, {what}; {exc.message}",
                                file=table.file, column=col.name) from None
    if kind in given:
        if header is not None and header != given[kind]:
            raise DataError(
                f"the header says {header} but units= says {kind} {given[kind]}; "
                "remove one of them or make them agree", file=table.file, column=col.name,
            )
        return given[kind], "units="
    if header is not None:
        return header, "header"
    return ("radius/s" if kind == "velocity" else "rad/s"), "assumed"


def _describe_units(unit_of: dict[str, tuple[str, str]], chosen: dict[str, _Column]) -> str:
    parts = []
    for kind in _UNIT_KINDS:
        roles = [r for r in unit_of if _ROLE_KINDS[r.split(".")[1]] == kind]
        found = {unit_of[r] for r in roles}
        if len({u for u, _ in found}) == 1:
            unit, origin = next(iter(found))
            parts.append(f"{kind} {unit}" + (" (assumed)" if origin == "assumed" else ""))
        else:
            parts.append(f"{kind} " + ", ".join(f"{chosen[r].name}: {unit_of[r][0]}" for r in roles))
    return ", ".join(parts)
