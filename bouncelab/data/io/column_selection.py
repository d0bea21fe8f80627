"""Choosing the file column of each role: the names given in ``columns=``, or the synonym table."""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from bouncelab.data.io.header_units import _split_header
from bouncelab.data.io.synonyms import _PI_STATES, _ROLES, _STATES, _normalize, _role_of
from bouncelab.data.io.table import _Column, _Table
from bouncelab.data.units import COMPONENTS
from bouncelab.errors import DataError


@dataclass
class _Choice:
    column: _Column
    by_full_name: bool  # matched by its whole header, so a bracket in it may be part of the name


def _find_requested(table: _Table, requested: str, role: str) -> _Choice:
    exact = [c for c in table.columns if c.name == requested.strip()]
    if len(exact) == 1:
        return _Choice(exact[0], True)
    req_full = _normalize(requested)
    req_base = _normalize(_split_header(requested)[0])
    keys = {k for k in (req_full, req_base) if k}
    found = [c for c in table.columns if c.full_key in keys or c.base_key in keys]
    if len(found) == 1:
        return _Choice(found[0], found[0].full_key in keys)
    names = [c.name for c in table.columns]
    if not found:
        raise DataError(
            f"no column matches {requested!r} (asked for as {role}); the file's columns are {names}",
            file=table.file, column=requested,
        )
    raise DataError(
        f"{requested!r} (asked for as {role}) matches several columns: "
        f"{[c.name for c in found]}; pass the exact name of the one to use",
        file=table.file, column=requested,
    )


def _select_explicit(table: _Table, columns: Mapping[str, Any]) -> dict[str, _Choice]:
    allowed = (*_STATES, "setting", *_PI_STATES)
    if not isinstance(columns, Mapping):
        raise DataError(
            f"columns= must be a mapping such as {{'landing': [...], 'liftoff': [...]}}; "
            f"got {type(columns).__name__}", file=table.file,
        )
    unknown = [k for k in columns if k not in allowed]
    if unknown:
        raise DataError(f"columns= has unknown keys {unknown}; allowed keys are {list(allowed)}",
                        file=table.file)
    chosen: dict[str, _Choice] = {}
    for state in (*_STATES, *_PI_STATES):
        names = columns.get(state)
        if names is None:
            if state in _STATES:
                raise DataError(f"columns= must name the 3 {state} columns (xdot, ydot, omega)",
                                file=table.file)
            continue
        if isinstance(names, str) or not isinstance(names, Sequence) or len(names) != 3:
            raise DataError(
                f"columns[{state!r}] must be a list of 3 column names (xdot, ydot, omega); got {names!r}",
                file=table.file,
            )
        for comp, name in zip(COMPONENTS, names, strict=True):
            chosen[f"{state}.{comp}"] = _find_requested(table, str(name), f"{state} {comp}")
    if columns.get("setting") is not None:
        chosen["setting"] = _find_requested(table, str(columns["setting"]), "setting")
    return chosen


def _candidates(table: _Table) -> dict[str, list[_Choice]]:
    """File columns matching each role's synonyms; a whole-name match hides a base-name one."""
    found: dict[str, list[_Choice]] = {role: [] for role in _ROLES}
    for col in table.columns:
        role = _role_of(col.full_key)
        if role is not None:
            found[role].append(_Choice(col, True))
        elif (role := _role_of(col.base_key)) is not None:
            found[role].append(_Choice(col, False))
    return found


def _select_auto(table: _Table) -> dict[str, _Choice]:
    found = _candidates(table)
    chosen: dict[str, _Choice] = {}
    problems = []
    for role in (*(f"{s}.{c}" for s in _STATES for c in COMPONENTS), "setting"):
        cands = found[role]
        if len(cands) == 1:
            chosen[role] = cands[0]
        elif len(cands) > 1:
            problems.append(f"{role}: several candidates {[c.column.name for c in cands]}")
        elif role != "setting":
            problems.append(f"{role}: no column found")
    for state in _PI_STATES:
        roles = [f"{state}.{c}" for c in COMPONENTS]
        if all(len(found[r]) == 1 for r in roles):
            chosen.update({r: found[r][0] for r in roles})
        elif any(len(found[r]) > 1 for r in roles):
            problems.extend(f"{r}: several candidates {[c.column.name for c in found[r]]}"
                            for r in roles if len(found[r]) > 1)
        elif any(found[r] for r in roles):
            warnings.warn(
                f"{table.file}: ignoring the incomplete {state} columns "
                f"{[found[r][0].column.name for r in roles if found[r]]}; "
                "name all three in columns= to use them",
                UserWarning, stacklevel=4,
            )
    if problems:
        raise DataError(_auto_detect_message(table, found, problems), file=table.file)
    return chosen


def _auto_detect_message(table: _Table, found: dict[str, list[_Choice]], problems: list[str]) -> str:
    def pick(role: str) -> str:
        cands = found[role]
        if len(cands) == 1:
            return repr(cands[0].column.name)
        if cands:
            return repr("<one of " + ", ".join(c.column.name for c in cands) + ">")
        return repr(f"<{role.replace('.', ' ')} column>")

    parts = [f"{s!r}: [{', '.join(pick(f'{s}.{c}') for c in COMPONENTS)}]" for s in _STATES]
    if found["setting"]:
        parts.append(f"'setting': {pick('setting')}")
    for s in _PI_STATES:
        if any(found[f"{s}.{c}"] for c in COMPONENTS):
            parts.append(f"{s!r}: [{', '.join(pick(f'{s}.{c}') for c in COMPONENTS)}]")
    hint = ""
    if any("angle" in c.full_key for c in table.columns):
        hint = ("\nThe file seems to give speed and angle: convert them to xdot, ydot with "
                "bouncelab.data.units.landing_from_speed_angle_spin first.")
    return (
        "cannot tell which columns hold the bounce data (" + "; ".join(problems) + ").\n"
        f"The file's columns are {[c.name for c in table.columns]}.\n"
        "Name them explicitly (replace each <...>):\n"
        f"    load_campaign({table.file!r}, columns={{{', '.join(parts)}}})" + hint
    )
