"""Column names and units: the synonym table that recognises a file's columns, the unit written in a
header or units row, choosing the column of each role (``columns=`` or the synonyms) and its unit.

A *role* is ``"<state>.<component>"`` (``"landing.xdot"``, ``"liftoff_pi.omega"``...) or
``"setting"``; names are compared in normalised form (:func:`_normalize`).
"""

from __future__ import annotations

import re
import unicodedata
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from bouncelab.data.units import COMPONENTS, canonical_unit
from bouncelab.errors import DataError

if TYPE_CHECKING:
    from bouncelab.data.io.table import _Column, _Table


_STATES = ("landing", "liftoff")
_PI_STATES = ("landing_pi", "liftoff_pi")


_STEMS: dict[str, tuple[str, ...]] = {
    "xdot": (
        "xdot", "dx", "dxdt", "vx", "velx", "xvel", "xvelocity", "velocityx", "u", "ux",
        "horizontalvelocity", "horizontalspeed", "hvel", "vh", "vhoriz", "vhorizontal",
    ),
    "ydot": (
        "ydot", "dy", "dydt", "vy", "vely", "yvel", "yvelocity", "velocityy", "v", "uy",
        "verticalvelocity", "verticalspeed", "vvel", "vv", "vvert", "vvertical",
    ),
    "omega": (
        "omega", "w", "om", "spin", "spinrate", "angularvelocity", "angvel", "omegaz", "wz",
    ),
}
_PHASES: dict[str, tuple[str, ...]] = {
    "landing": (
        "0", "i", "in", "inb", "inbound", "incoming", "incident", "impact", "land", "landing",
        "pre", "before", "initial", "init", "touchdown", "td",
    ),
    "liftoff": (
        "f", "1", "out", "outb", "outbound", "outgoing", "rebound", "lift", "liftoff", "post",
        "after", "final", "takeoff", "lo",
    ),
}
_PI_MARKERS = ("pi", "pi95", "hw", "halfwidth", "ci", "ci95", "err", "error", "unc", "uncertainty")
_SETTING_NAMES = (
    "setting", "settings", "settingid", "settingno", "settingnumber", "launchersetting",
    "launchersettings", "condition", "conditions", "conditionid", "testcondition",
    "testconditions", "group", "groupid", "setup", "config", "configuration", "case", "testcase",
)


#: The synonym table used when ``columns=None``, in normalised form (see the
#: docstring of :mod:`bouncelab.data.io`): the stems of each component, the landing and lift-off
#: phase markers, the prediction-interval markers and the setting names. A
#: state column is ``stem + phase``, ``phase + stem`` or ``phase + stem +
#: phase`` (both phases of the same state; a phase before the stem must have
#: two or more characters and the stem too); a prediction-interval column is a
#: state column name with a ``pi`` marker before or after it.
COLUMN_SYNONYMS: dict[str, tuple[str, ...]] = {
    **_STEMS, **_PHASES, "pi": _PI_MARKERS, "setting": _SETTING_NAMES,
}


# Common column names that the rules below would otherwise read as bounce data.
_NOT_SYNONYMS = frozenset({"indx"})


def _build_state_keys() -> dict[str, str]:
    table: dict[str, str] = {}
    for state, phases in _PHASES.items():
        # A phase before the stem must be a word ("in_vx", not "i_vx" or "ivy"), and
        # one-letter stems take it only after ("w_in", but not "low" or "prev").
        prefixes = [ph for ph in phases if len(ph) > 1]
        for comp, stems in _STEMS.items():
            role = f"{state}.{comp}"
            for stem in stems:
                keys = {stem + ph for ph in phases}
                if len(stem) > 1:
                    keys.update(pre + stem for pre in prefixes)
                    keys.update(pre + stem + ph for pre in prefixes for ph in phases)
                for key in keys - _NOT_SYNONYMS:
                        if table.setdefault(key, role) != role:  # pragma: no cover - checked in tests
                            raise AssertionError(f"synonym {key!r} is both {table[key]} and {role}")
    return table


_STATE_KEYS = _build_state_keys()
_SETTING_KEYS = frozenset(_SETTING_NAMES)
_ROLES = (
    *(f"{s}.{c}" for s in (*_STATES, *_PI_STATES) for c in COMPONENTS),
    "setting",
)


def _role_of(key: str) -> str | None:
    """The role a normalised column name stands for, per :data:`COLUMN_SYNONYMS`."""
    if key in _SETTING_KEYS:
        return "setting"
    if key in _STATE_KEYS:
        return _STATE_KEYS[key]
    for m in _PI_MARKERS:
        for rest in (key[: -len(m)] if key.endswith(m) else None,
                     key[len(m):] if key.startswith(m) else None):
            if rest and rest in _STATE_KEYS:
                state, comp = _STATE_KEYS[rest].split(".")
                return f"{state}_pi.{comp}"
    return None


def _normalize(name: str) -> str:
    """Lower-case letters and digits only; ``ω`` -> omega, ``ẋ`` -> xdot."""
    text = unicodedata.normalize("NFKD", str(name))
    text = text.replace("ω", "omega").replace("Ω", "omega").replace("\u0307", "dot")
    return re.sub(r"[^a-z0-9]", "", text.lower())


_UNIT_KINDS = ("velocity", "spin")
_PER_SECOND = {"1/s", "s-1", "s^-1", "/s"}


# CF / UDUNITS spellings ("m s-1", "radian/s", "revolutions per minute") of the units bouncelab knows.
_CF_WORDS = (
    (r"\b(meters?|metres?)\b", "m"), (r"\b(foot|feet)\b", "ft"), (r"\bkilometers?|kilometres?\b", "km"),
    (r"\b(miles?)\b", "mi"), (r"\b(hours?|hr)\b", "h"), (r"\b(seconds?|sec)\b", "s"),
    (r"\b(minutes?)\b", "min"), (r"\b(radians?)\b", "rad"), (r"\b(degrees?)\b", "deg"),
    (r"\b(revolutions?|rotations?|revs?)\b", "rev"), (r"\s+per\s+", "/"),
    (r"\s*\.?\s*(s|h|min)\s*\^?\s*-1\b", r"/\1"), (r"\s*\*\*\s*-1", "-1"),
)


def _cf_spelling(text: str) -> str:
    out = str(text).strip().lower()
    for pattern, repl in _CF_WORDS:
        out = re.sub(pattern, repl, out)
    return out.replace(" ", "")


def _unit_of(text: str) -> dict[str, str]:
    """Canonical unit of ``text`` per kind it is valid for (empty if not a unit)."""
    found = {}
    for kind in _UNIT_KINDS:
        for spelling in (text, _cf_spelling(text)):
            try:
                found[kind] = canonical_unit(spelling, kind)
                break
            except DataError:
                pass
    if "spin" not in found and str(text).strip().lower().replace(" ", "") in _PER_SECOND:
        found["spin"] = "rad/s"  # 1/s, s^-1 on a spin column: rad/s
    return found


_BRACKET = re.compile(r"^(.*?)[\s_]*[\[\(\{]([^\[\]\(\)\{\}]*)[\]\)\}]\s*$")


def _split_header(name: str) -> tuple[str, str | None]:
    """Split ``"vx0 [m/s]"`` into ``("vx0", "m/s")``; ``(name, None)`` without a unit."""
    m = _BRACKET.match(name)
    if m and m.group(1).strip():
        return m.group(1).strip(), m.group(2).strip()
    tokens = [t for t in re.split(r"[\s_]+", name.strip()) if t]
    for k in (3, 2, 1):
        if len(tokens) > k:
            for joiner in ("", "/"):
                cand = joiner.join(tokens[-k:])
                if _unit_of(cand):
                    return " ".join(tokens[:-k]), cand
    return name, None


def _header_unit(name: str) -> tuple[str | None, bool]:
    unit = _split_header(name)[1]
    return unit, unit is not None


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
            where = col.unit_where or ("header" if col.unit_in_header else "units row")
            what = f"a {next(iter(known))} unit, not a {kind} unit" if known else "not a known unit"
            try:
                canonical_unit(_cf_spelling(col.unit_text), kind)
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
