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

from bouncelab.core.errors import DataError
from bouncelab.core.units import COMPONENTS, Z95, canonical_unit
from bouncelab.data.io import hints

if TYPE_CHECKING:
    from bouncelab.data.io.table import _Column, _Table


_STATES = ("landing", "liftoff")
_PI_STATES = ("landing_pi", "liftoff_pi")
_NAMES = {"landing": "landing", "liftoff": "lift-off"}  # a state as messages write it


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
# Interval markers, by what the name says the column holds: the half-width of a 95 % interval (what a
# campaign stores), one standard deviation (multiplied by Z95 on loading), or an uncertainty that could be
# either, which the loader will not guess (intervals= says which).
_PI95_MARKERS = ("pi", "pi95", "hw", "halfwidth", "ci", "ci95")
_SD_MARKERS = ("sd", "std", "stdev", "stddev", "sigma")
_AMBIGUOUS_MARKERS = ("err", "error", "unc", "uncertainty")
_PI_MARKERS = (*_PI95_MARKERS, *_SD_MARKERS, *_AMBIGUOUS_MARKERS)
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

# Polar columns (launch-monitor style): speed and angle to the horizontal; the spin is the omega stem.
# Kept out of _role_of, so that a Cartesian file with derived speeds and angles reads as before.
_POLAR_STEMS: dict[str, tuple[str, ...]] = {
    "speed": ("speed", "ballspeed", "totalspeed", "velocity", "vel", "vtot", "vtotal"),
    "angle": ("angle", "theta"),
}
# Whole names that say which state without a phase marker ("launch angle" is the lift-off's).
_POLAR_NAMES = {
    "launchangle": "liftoff.angle", "launchspeed": "liftoff.speed", "launchspin": "liftoff.omega",
    "descentangle": "landing.angle", "incidenceangle": "landing.angle", "angleofincidence": "landing.angle",
}


def _build_polar_keys() -> dict[str, str]:
    table: dict[str, str] = dict(_POLAR_NAMES)
    for state, phases in _PHASES.items():
        prefixes = [ph for ph in phases if len(ph) > 1]
        for comp, stems in _POLAR_STEMS.items():
            for stem in stems:
                keys = {stem + ph for ph in phases} | {pre + stem for pre in prefixes}
                for key in keys:
                    if table.setdefault(key, f"{state}.{comp}") != f"{state}.{comp}":  # pragma: no cover
                        raise AssertionError(f"polar synonym {key!r} is two roles")
    if set(table) & set(_STATE_KEYS):  # pragma: no cover - checked in tests
        raise AssertionError(f"polar synonyms {set(table) & set(_STATE_KEYS)} are Cartesian ones too")
    return table


_POLAR_KEYS = _build_polar_keys()
#: The components of a state given in polar form, in order (the spin is the ``omega`` role).
POLAR_ROLES = ("speed", "angle", "omega")
_SETTING_KEYS = frozenset(_SETTING_NAMES)
_ROLES = (
    *(f"{s}.{c}" for s in (*_STATES, *_PI_STATES) for c in COMPONENTS),
    *(f"{s}.{c}" for s in (*_STATES, *_PI_STATES) for c in ("speed", "angle")),
    "setting",
)


def _role_of(key: str) -> str | None:
    """The role a normalised column name stands for, per :data:`COLUMN_SYNONYMS`."""
    if key in _SETTING_KEYS:
        return "setting"
    if key in _STATE_KEYS:
        return _STATE_KEYS[key]
    found = _marked(key, _STATE_KEYS)
    return None if found is None else found[0]


def _marked(key: str, table: Mapping[str, str]) -> tuple[str, str] | None:
    """(``<state>_pi.<component>``, marker) of a name that is a state name of ``table`` with an interval
    marker before or after it (``vx0_pi``, ``sd_speed_in``), else None."""
    for m in _PI_MARKERS:
        for rest in (key[: -len(m)] if key.endswith(m) else None,
                     key[len(m):] if key.startswith(m) else None):
            if rest and rest in table:
                state, comp = table[rest].split(".")
                return f"{state}_pi.{comp}", m
    return None


def _polar_role_of(key: str) -> str | None:
    """The polar role (``landing.speed``, ``liftoff.angle``...) a normalised column name stands for.

    A polar name with an interval marker before or after it is the half-width of that column
    (``speed_in_pi`` is ``landing_pi.speed``), as :func:`_role_of` reads Cartesian ones.
    """
    if key in _POLAR_KEYS:
        return _POLAR_KEYS[key]
    found = _marked(key, _POLAR_KEYS)
    return None if found is None else found[0]


def _normalize(name: str) -> str:
    """Lower-case letters and digits only; ``ω`` -> omega, ``ẋ`` -> xdot."""
    text = unicodedata.normalize("NFKD", str(name))
    text = text.replace("ω", "omega").replace("Ω", "omega").replace("\u0307", "dot")
    return re.sub(r"[^a-z0-9]", "", text.lower())


_UNIT_KINDS = ("velocity", "spin")
_PER_SECOND = {"1/s", "s-1", "s^-1", "/s"}


def _unit_of(text: str) -> dict[str, str]:
    """Canonical unit of ``text`` per kind it is valid for (empty if not a unit)."""
    found = {}
    for kind in _UNIT_KINDS:
        try:
            found[kind] = canonical_unit(text, kind)  # also the CF / UDUNITS spellings ("rev min-1")
        except DataError:
            pass
    if "spin" not in found and str(text).strip().lower().replace(" ", "") in _PER_SECOND:
        found["spin"] = "rad/s"  # 1/s, s^-1 on a spin column: rad/s
    angle = _ANGLE_UNITS.get(str(text).strip().lower().replace(" ", ""))
    if angle is not None:
        found["angle"] = angle
    return found


_ANGLE_UNITS = {"deg": "deg", "degree": "deg", "degrees": "deg", "°": "deg", "rad": "rad", "radian": "rad",
                "radians": "rad"}


def _canonical(unit: str, kind: str) -> str:
    """canonical_unit, and for angles ``deg`` or ``rad``."""
    if kind != "angle":
        return canonical_unit(unit, kind)
    canon = _ANGLE_UNITS.get(str(unit).strip().lower().replace(" ", ""))
    if canon is None:
        raise DataError(f"unknown angle unit {unit!r}; known angle units: deg, rad")
    return canon


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


# Keys of a state given as a mapping in columns=: Cartesian or polar (spin is the omega role).
_CARTESIAN_KEYS = {"xdot": "xdot", "ydot": "ydot", "omega": "omega"}
_POLAR_MAP_KEYS = {"speed": "speed", "angle": "angle", "spin": "omega", "omega": "omega"}


def _state_roles(state: str, names: Any) -> dict[str, str] | None:
    """Component -> requested name for one state (or its intervals) of columns=: a list (xdot, ydot,
    omega), or a mapping with the keys xdot, ydot, omega or speed, angle, spin."""
    if isinstance(names, Mapping):
        keys = set(map(str, names))
        if keys == set(_CARTESIAN_KEYS):
            return {_CARTESIAN_KEYS[k]: str(v) for k, v in names.items()}
        if keys in ({"speed", "angle", "spin"}, {"speed", "angle", "omega"}):
            return {_POLAR_MAP_KEYS[k]: str(v) for k, v in names.items()}
        return None
    if isinstance(names, str) or not isinstance(names, Sequence) or len(names) != 3:
        return None
    return {comp: str(name) for comp, name in zip(COMPONENTS, names, strict=True)}


def _select_explicit(table: _Table, columns: Mapping[str, Any]) -> dict[str, _Choice]:
    allowed = (*_STATES, "setting", *_PI_STATES)
    opt = hints.option("columns", table.hint_style)
    if not isinstance(columns, Mapping):
        raise DataError(
            f"{opt} must be a mapping such as {{'landing': [...], 'liftoff': [...]}}; "
            f"got {type(columns).__name__}", file=table.file,
        )
    unknown = [k for k in columns if k not in allowed]
    if unknown:
        raise DataError(f"{opt} has unknown keys {unknown}; allowed keys are {list(allowed)}",
                        file=table.file)
    chosen: dict[str, _Choice] = {}
    mapped: set[str] = set()  # the keys named by a mapping: their components are as the caller says
    for state in (*_STATES, *_PI_STATES):
        names = columns.get(state)
        if names is None:
            if state in _STATES:
                raise DataError(f"{opt} must name the 3 {state} columns (xdot, ydot, omega; or speed, angle, "
                                "spin)", file=table.file)
            continue
        roles = _state_roles(state, names)
        if roles is None:
            raise DataError(
                f"{opt}[{state!r}] must be a list of 3 column names (xdot, ydot, omega) or a mapping "
                f"{{'speed': ..., 'angle': ..., 'spin': ...}}; got {names!r}", file=table.file,
            )
        if isinstance(names, Mapping):
            mapped.add(state)
        for comp, name in roles.items():
            chosen[f"{state}.{comp}"] = _find_requested(table, name, f"{state} {comp}")
    if columns.get("setting") is not None:
        chosen["setting"] = _find_requested(table, str(columns["setting"]), "setting")
    _check_forms(table, chosen, opt, mapped)
    return chosen


def _synonym_role(col: _Column) -> str | None:
    """The role a column's name stands for in the synonym table (whole name first), or None."""
    return (_role_of(col.full_key) or _polar_role_of(col.full_key) or _role_of(col.base_key)
            or _polar_role_of(col.base_key))


def _check_forms(table: _Table, chosen: dict[str, _Choice], opt: str, mapped: set[str] = frozenset()) -> None:
    """Refuse explicit columns whose kind (state or interval) or form (Cartesian or polar) does not fit.

    A column whose name has an interval marker (``speed_in_pi``, ``vx0_err``) named as a state's, or a
    state's (``speed_in``, ``vx0``) named as a half-width, is refused for lists and mappings alike: the
    marker is a strong signal. A column the synonym table recognises as a speed or an angle
    (``speed_in``, ``angle_in_pi``) named in a list (read as xdot, ydot, omega) would be a silently
    wrong number (an angle of 40 degrees read as 40 m/s); a mapping (``{'speed': 'v_in', ...}``,
    ``{'xdot': ..., ...}``, keys in ``mapped``) says what each column holds, and is trusted even when a
    loose synonym says the other form (``v_in`` is also a ydot name). Names the table does not
    recognise (``a``, ``v_b``) are taken as given. Polar half-widths are propagated through the polar
    state they belong to, so they need one.
    """
    for key in (*_STATES, *_PI_STATES):
        _check_kind(table, chosen, key, opt)
    for state in _STATES:
        if state not in mapped:
            _check_form(table, chosen, state, opt)
    for state, pi in zip(_STATES, _PI_STATES, strict=True):
        if f"{pi}.speed" in chosen and f"{state}.speed" not in chosen:
            raise DataError(
                f"{opt}[{pi!r}] gives polar half-widths (speed, angle, spin) but {opt}[{state!r}] reads the "
                f"{_NAMES[state]} from Cartesian columns (xdot, ydot, omega): polar half-widths are propagated "
                f"through the polar state they belong to; give the {_NAMES[state]} as {{'speed': ..., 'angle': "
                f"..., 'spin': ...}} too, or {pi!r} as a list of the xdot, ydot, omega half-widths",
                file=table.file)
        if pi not in mapped:
            _check_form(table, chosen, pi, opt)


def _check_kind(table: _Table, chosen: dict[str, _Choice], key: str, opt: str) -> None:
    """Refuse the columns of ``columns=[key]`` whose names say a state where a half-width is asked, or the reverse."""
    interval = key in _PI_STATES
    comps = [r.split(".", 1)[1] for r in chosen if r.split(".", 1)[0] == key]
    wrong = []
    for comp in comps:
        role = _synonym_role(chosen[f"{key}.{comp}"].column)
        if role is not None and "." in role and ("_pi." in role) != interval:
            wrong.append((comp, role))
    if not wrong:
        return
    one = len(wrong) == 1
    cols = [chosen[f"{key}.{comp}"].column for comp, _ in wrong]

    def said(role: str) -> str:  # what a column's name says it holds
        state, comp = role.split(".")
        what = f"{_NAMES[state.removesuffix('_pi')]} {'spin' if comp == 'omega' else comp}"
        return f"a half-width of the {what} (a prediction interval)" if "_pi." in role else f"the {what} itself"

    def asked(comp: str) -> str:
        polar = f"{key}.speed" in chosen
        what = f"{_NAMES[key.removesuffix('_pi')]} {'spin' if comp == 'omega' and polar else comp}"
        return f"the {what} half-width" if interval else f"the {what}"

    names = "; ".join(f"{c.name!r} says it holds {said(role)}, not {asked(comp)}"
                      for c, (comp, role) in zip(cols, wrong, strict=True))
    state = key.removesuffix("_pi")
    fix = (f"name a state's own columns in {opt}[{state!r}] and their half-widths in {opt}[{state + '_pi'!r}]")
    raise DataError(
        f"{opt}[{key!r}] names {'a column' if one else 'columns'} of the wrong kind: {names}; read as asked, "
        f"{'a half-width would be a measurement' if not interval else 'a measurement would be a half-width'}; "
        f"{fix}, or rename the column{'' if one else 's'} if {'it does' if one else 'they do'} hold what is asked",
        file=table.file, column=cols[0].name)


def _check_form(table: _Table, chosen: dict[str, _Choice], key: str, opt: str) -> None:
    """Refuse the columns of ``columns=[key]`` (a state or its intervals) whose names say the other form."""
    polar = f"{key}.speed" in chosen
    asked = POLAR_ROLES if polar else COMPONENTS
    if f"{key}.{asked[0]}" not in chosen:
        return  # not given
    interval = key in _PI_STATES
    named = {comp: _synonym_role(chosen[f"{key}.{comp}"].column) for comp in asked}
    other = ("xdot", "ydot") if polar else ("speed", "angle")
    # Only a name of the same kind counts: a state's column named as a state's, an interval's as an interval's.
    wrong = [(comp, role) for comp, role in named.items()
             if role is not None and "." in role and ("_pi." in role) == interval and role.split(".")[1] in other]
    if not wrong:
        return
    spin = {"omega": "spin"} if polar else {}
    one = len(wrong) == 1
    cols = [chosen[f"{key}.{comp}"].column for comp, _ in wrong]
    by_state: dict[str, list[str]] = {}  # what the names say, per state
    for _, role in wrong:
        state, comp = role.split(".")
        by_state.setdefault(_NAMES[state.removesuffix("_pi")], []).append(comp)
    said = " and the ".join(f"{s} {' and '.join(comps)}" for s, comps in by_state.items())
    read = " and ".join(spin.get(comp, comp) for comp, _ in wrong)
    said = f"the half-width{'' if one else 's'} of the {said}" if interval else f"the {said}"
    read += f" half-width{'' if one else 's'}" if interval else ""

    def pick(comp: str) -> str:  # the column whose name says it is ``comp`` of ``key``, for the fix
        for c in asked:
            if named[c] == f"{key}.{comp}":
                return chosen[f"{key}.{c}"].column.name
        if comp == "omega" and named["omega"] is None:  # the spin is the omega of either form
            return chosen[f"{key}.omega"].column.name
        return f"<{key} {'spin' if comp == 'omega' and not polar else comp} column>"

    if polar:  # their names say Cartesian: a list
        entry = hints.columns_entry(key, [pick(c) for c in COMPONENTS], table.hint_style)
        fix = (f"the xdot, ydot and omega half-widths are named by a list: {entry}" if interval else
               f"a state given as xdot, ydot and omega is named by a list: {entry}")
    else:  # their names say polar: a mapping
        entry = hints.columns_entry(key, {k: pick(c) for k, c in zip(("speed", "angle", "spin"), POLAR_ROLES,
                                                                        strict=True)}, table.hint_style)
        fix = (f"speed, angle and spin half-widths are named by a mapping (and propagated to xdot, ydot, omega): "
               f"{entry}" if interval else
               f"a state given as speed, angle and spin is named by a mapping (a list is read as xdot, ydot, "
               f"omega): {entry}")
    raise DataError(
        f"the column name{'' if one else 's'} {' and '.join(repr(c.name) for c in cols)} "
        f"{'says it holds' if one else 'say they hold'} {said}, but {opt}[{key!r}] reads "
        f"{'it' if one else 'them'} as the {read}; {fix}; or rename the column{'' if one else 's'} if "
        f"{'it does' if one else 'they do'} hold what is asked", file=table.file, column=cols[0].name)


def _candidates(table: _Table) -> dict[str, list[_Choice]]:
    """File columns matching each role's synonyms; a whole-name match hides a base-name one."""
    found: dict[str, list[_Choice]] = {role: [] for role in _ROLES}
    for col in table.columns:
        role = _role_of(col.full_key) or _polar_role_of(col.full_key)
        if role is not None:
            found[role].append(_Choice(col, True))
        elif (role := _role_of(col.base_key) or _polar_role_of(col.base_key)) is not None:
            found[role].append(_Choice(col, False))
    return found


def _state_form(found: dict[str, list[_Choice]], state: str) -> str:
    """``"polar"`` if a state has speed/angle columns and no xdot/ydot ones, else ``"cartesian"``.

    A file with both (measured components and derived speeds) keeps reading the components when they
    are complete; with both and incomplete components it is ambiguous (see _select_auto).
    """
    cart = any(found[f"{state}.{c}"] for c in ("xdot", "ydot"))
    polar = any(found[f"{state}.{c}"] for c in ("speed", "angle"))
    return "polar" if polar and not cart else "cartesian"


def _select_auto(table: _Table, warn_depth: int = 0) -> dict[str, _Choice]:
    """The columns of each role found from their names (``warn_depth``: frames between the loader and its caller)."""
    found = _candidates(table)
    chosen: dict[str, _Choice] = {}
    problems = []
    forms = {s: _state_form(found, s) for s in _STATES}
    for s, other in zip(_STATES, reversed(_STATES), strict=True):
        if not any(found[f"{s}.{c}"] for c in ("xdot", "ydot", "speed", "angle")):
            forms[s] = forms[other]  # nothing found: suggest the form the other state has
    for s in _STATES:
        cart_ok = all(len(found[f"{s}.{c}"]) == 1 for c in ("xdot", "ydot"))
        if forms[s] == "cartesian" and not cart_ok and any(found[f"{s}.{c}"] for c in ("speed", "angle")):
            problems.append(f"{s}: both Cartesian columns "
                            f"{[c.column.name for r in ('xdot', 'ydot') for c in found[f'{s}.{r}']]} and polar ones "
                            f"{[c.column.name for r in ('speed', 'angle') for c in found[f'{s}.{r}']]}")
    roles = [f"{s}.{c}" for s in _STATES for c in (COMPONENTS if forms[s] == "cartesian" else POLAR_ROLES)]
    for role in (*roles, "setting"):
        cands = found[role]
        if len(cands) == 1:
            chosen[role] = cands[0]
        elif len(cands) > 1:
            problems.append(f"{role}: several candidates {[c.column.name for c in cands]}")
        elif role != "setting":
            problems.append(f"{role}: no column found")
    interval_errors = []
    for state in _STATES:
        picked, several, error = _auto_intervals(table, found, state, forms[state], warn_depth)
        chosen.update(picked)
        problems.extend(several)
        interval_errors += [error] if error is not None else []
    if problems:
        raise DataError(_auto_detect_message(table, found, problems, forms), file=table.file)
    if interval_errors:
        raise DataError(interval_errors[0] + "\n    " + _columns_call(table, found, forms), file=table.file)
    return chosen


def _auto_intervals(table: _Table, found: dict[str, list[_Choice]], state: str, form: str,
                    warn_depth: int = 0) -> tuple[dict[str, _Choice], list[str], str | None]:
    """The interval columns of one state found from their names: the choice, the roles with several
    candidates, and what else is wrong with them (a message ending in a colon, for the columns= call).

    Complete Cartesian half-widths are read as such (for a Cartesian state even beside polar ones, as
    its state is read beside derived speeds and angles). Polar half-widths of a Cartesian state (a stray
    ``speed_in_unc``) have nothing to be propagated through: they are ignored with a warning naming them,
    as incomplete Cartesian half-widths are, and so is a lone spin half-width (of neither form). Polar
    half-widths of a polar state need all three of speed, angle and spin, and no Cartesian ones beside
    them; anything else is refused, since which numbers to propagate would be a guess.
    """
    pi, name = f"{state}_pi", _NAMES[state]
    several = [f"{pi}.{c}: several candidates {[ch.column.name for ch in found[f'{pi}.{c}']]}"
               for c in (*COMPONENTS, "speed", "angle") if len(found[f"{pi}.{c}"]) > 1]
    if several:
        return {}, several, None

    def names(comps: Sequence[str]) -> list[str]:
        return [found[f"{pi}.{c}"][0].column.name for c in comps if found[f"{pi}.{c}"]]

    cartesian = [r for r in COMPONENTS if found[f"{pi}.{r}"]]
    polar = [r for r in ("speed", "angle") if found[f"{pi}.{r}"]]
    if len(cartesian) == 3 and (form == "cartesian" or not polar):
        return {f"{pi}.{c}": found[f"{pi}.{c}"][0] for c in COMPONENTS}, [], None
    opt = hints.option("columns", table.hint_style)
    if polar and form == "cartesian":
        # Nothing to propagate them through: ignoring them loses the intervals, never gives a wrong number.
        warnings.warn(
            f"{table.file}: ignoring the {pi} columns {names((*polar, *cartesian))}: the {name} is read from its "
            f"Cartesian columns (xdot, ydot, omega), and half-widths of its speed or angle ({', '.join(names(polar))}) "
            f"are propagated only through a polar state; loaded without {name} intervals. To use them, name the "
            f"{name} as speed, angle and spin and {pi!r} as a mapping, or its xdot, ydot, omega half-widths as a "
            f"list, in {opt}",
            UserWarning, stacklevel=5 + warn_depth,
        )
        return {}, [], None
    if polar and {"xdot", "ydot"} & set(cartesian):
        return {}, [], (f"the {name} has both Cartesian half-widths {names(('xdot', 'ydot'))} and polar ones "
                    f"{names(polar)}; say which to read in {opt} ({pi!r} as a list of xdot, ydot, omega or a "
                    "mapping of speed, angle, spin):")
    if polar:
        missing = [k for k, c in zip(("speed", "angle", "spin"), POLAR_ROLES, strict=True) if not found[f"{pi}.{c}"]]
        if not missing:
            return {f"{pi}.{c}": found[f"{pi}.{c}"][0] for c in POLAR_ROLES}, [], None
        return {}, [], (f"the {name} has polar half-widths {names(POLAR_ROLES)} but none for its "
                    f"{' and '.join(missing)}: all three (speed, angle, spin) are needed to propagate them to "
                    f"xdot, ydot, omega; add the missing column, or name it (or leave {pi!r} out to load without "
                    f"intervals) in {opt}:")
    if cartesian:
        which = "xdot, ydot, omega" + ("; or speed, angle, spin" if form == "polar" else "")
        warnings.warn(
            f"{table.file}: ignoring the incomplete {pi} columns {names(COMPONENTS)}; "
            f"name all three ({which}) in {opt} to use them",
            UserWarning, stacklevel=5 + warn_depth,
        )
    return {}, [], None


def _auto_detect_message(table: _Table, found: dict[str, list[_Choice]], problems: list[str],
                         forms: dict[str, str]) -> str:
    hint = ""
    if any(forms[s] == "cartesian" and any(found[f"{s}.{c}"] for c in ("speed", "angle")) for s in _STATES):
        hint = ("\nFor a state given as speed, angle and spin, name them as "
                "{'speed': ..., 'angle': ..., 'spin': ...} instead of a list.")
    return (
        "cannot tell which columns hold the bounce data (" + "; ".join(problems) + ").\n"
        f"The file's columns are {[c.name for c in table.columns]}.\n"
        "Name them explicitly (replace each <...>):\n"
        f"    {_columns_call(table, found, forms)}" + hint
    )


def _columns_call(table: _Table, found: dict[str, list[_Choice]], forms: dict[str, str]) -> str:
    """The columns= argument naming what was found, with ``<...>`` for what was not or is ambiguous."""
    def pick(role: str, label: str | None = None) -> str:
        cands = found[role]
        if len(cands) == 1:
            return cands[0].column.name
        if cands:
            return "<one of " + ", ".join(c.column.name for c in cands) + ">"
        return f"<{label or role.replace('.', ' ')} column>"

    def polar(state: str) -> dict[str, str]:  # a speed, angle and spin mapping
        return {k: pick(f"{state}.{r}", f"{state} {k}")
                for k, r in zip(("speed", "angle", "spin"), POLAR_ROLES, strict=True)}

    parts: list[tuple[str, Any]] = []
    for s in _STATES:
        parts.append((s, polar(s) if forms[s] == "polar" else [pick(f"{s}.{c}") for c in COMPONENTS]))
    if found["setting"]:
        parts.append(("setting", pick("setting")))
    for s, pi in zip(_STATES, _PI_STATES, strict=True):
        if forms[s] == "polar" and any(found[f"{pi}.{c}"] for c in ("speed", "angle")):
            parts.append((pi, polar(pi)))
        elif any(found[f"{pi}.{c}"] for c in COMPONENTS):
            parts.append((pi, [pick(f"{pi}.{c}") for c in COMPONENTS]))
    return hints.columns_call(table.file, parts, table.hint_style)


# Relative units: a half-width (or value) as a fraction of its value, which bouncelab does not read.
_RELATIVE_WORDS = frozenset({"percent", "percentage", "pct", "rel", "relative", "fraction", "frac"})


def _relative_word(text: str | None) -> str | None:
    """The relative unit (``%``, ``percent``, ``pct``, ``rel``...) ``text`` gives, or None."""
    if text is None:
        return None
    if "%" in text or "‰" in text:
        return "%"
    words = [w for w in re.split(r"[^a-z]+", text.lower()) if w]
    if "per" in words and "cent" in words:
        return "per cent"
    return next((w for w in words if w in _RELATIVE_WORDS), None)


def _relative_unit(col: _Column) -> str | None:
    """The relative unit a column's header, units row or unit attribute gives (``speed_in_pi (%)``,
    ``speed_in_pi_pct``, ``spin_in_pi [rel]``), or None. A ``%`` anywhere in the name counts; a word
    only as the unit (in brackets or the last word), so that ``v_rel_in`` is still a name."""
    if "%" in col.name or "‰" in col.name:
        return "%"
    found = _relative_word(col.unit_text)
    if found is None:
        base, unit = _split_header(col.name)
        found = _relative_word(unit) if unit is not None else None
        last = [w for w in re.split(r"[\s_]+", base.strip()) if w][-1:] if base.strip() else []
        found = found or _relative_word(last[0] if last and last[0].lower() in _RELATIVE_WORDS else None)
    return found


def check_absolute_units(table: _Table, cols: Mapping[str, _Column], style: str) -> None:
    """Refuse a state or interval column whose unit is relative (per cent of its value): read as the value's
    unit it would be a silently wrong number (2 % of 25 m/s as 2 m/s)."""
    for role, col in cols.items():
        if role == "setting":
            continue
        unit = _relative_unit(col)
        if unit is None:
            continue
        state, comp = role.split(".")
        what = f"{_NAMES[state.removesuffix('_pi')]} {'spin' if comp == 'omega' and f'{state}.speed' in cols else comp}"
        where = col.unit_where or ("units row" if col.unit_text is not None and not col.unit_in_header else "header")
        if state in _PI_STATES:
            raise DataError(
                f"the {where} gives the {what} half-width in {unit!r}, a relative unit: bouncelab reads half-widths "
                f"only in an absolute unit (that of the value or one of its kind), never relative ones; convert the "
                f"column first, multiplying each half-width in per cent by its value / 100 (2 % of 25 m/s is "
                f"0.5 m/s), and give it the value's unit", file=table.file, column=col.name)
        raise DataError(
            f"the {where} gives the {what} in {unit!r}, a relative unit: a measured {what} needs an absolute unit "
            f"(m/s, rpm, deg...); convert the column, or name the column that holds the value",
            file=table.file, column=col.name)


#: What ``intervals=`` may say a file's interval columns hold: ``"pi95"`` the half-widths of 95 %
#: intervals (what a campaign stores), ``"sd"`` one standard deviation.
INTERVAL_KINDS = ("pi95", "sd")


def _interval_marker(col: _Column) -> str | None:
    """The interval marker in a column's name (``err`` of ``vx0_err [m/s]``), or None (``dVx in``)."""
    for key in (col.full_key, col.base_key):
        for synonyms in (_STATE_KEYS, _POLAR_KEYS):
            found = _marked(key, synonyms)
            if found is not None:
                return found[1]
    # A name given in columns= need not be a state's (``a_sd``, ``sigma vx``): its last or first word still says.
    words = [w for w in re.split(r"[^a-z0-9]+", _split_header(col.name)[0].lower()) if w]
    for word in (words[-1:] + words[:1]):
        if word in _PI_MARKERS:
            return word
    return None


def interval_scales(table: _Table, cols: Mapping[str, _Column], intervals: str | None,
                    style: str) -> dict[str, float]:
    """The factor that turns each interval column of ``cols`` into 95 % half-widths: 1, or :data:`Z95` for
    standard deviations.

    ``intervals=None`` lets the names decide: a ``pi``/``hw``/``ci`` marker is a 95 % half-width, a
    ``sd``/``std``/``sigma`` one a standard deviation, a name without a marker (named in ``columns=``) a
    95 % half-width, and an ``err``/``unc`` marker, which could be either, a DataError (a standard
    deviation read as a 95 % half-width would be a silently narrow interval). ``"pi95"``/``"sd"`` say
    what every interval column holds; a name that says the other is a DataError.
    """
    scales: dict[str, float] = {}
    unsure: list[str] = []
    for role, col in cols.items():
        if "_pi." not in role:
            continue
        marker = _interval_marker(col)
        says = "pi95" if marker in _PI95_MARKERS else "sd" if marker in _SD_MARKERS else None
        if intervals is not None and says is not None and says != intervals:
            meaning = {"pi95": "a 95 % half-width", "sd": "one standard deviation"}
            raise DataError(
                f"{hints.setting('intervals', intervals, style)} says the interval columns hold {meaning[intervals]}, "
                f"but the name of {col.name!r} ({marker!r}) says it holds {meaning[says]}; rename the column or "
                f"drop {hints.option('intervals', style)}", file=table.file, column=col.name)
        if intervals is None and marker in _AMBIGUOUS_MARKERS:
            unsure.append(col.name)
            continue
        scales[role] = Z95 if (intervals or says) == "sd" else 1.0
    if unsure:
        raise DataError(
            f"the interval column{'s' if len(unsure) > 1 else ''} {unsure} may hold one standard deviation or the "
            f"half-width of a 95 % interval, and the name does not say which (a standard deviation read as a "
            f"half-width would give intervals 1.96 times too narrow): pass {hints.setting('intervals', 'sd', style)} "
            f"(standard deviations, multiplied by {Z95:.2f} to 95 % half-widths) or "
            f"{hints.setting('intervals', 'pi95', style)} (95 % half-widths, as a campaign stores them)",
            file=table.file, column=unsure[0])
    return scales


_ROLE_KINDS = {"xdot": "velocity", "ydot": "velocity", "omega": "spin", "speed": "velocity", "angle": "angle"}


def _check_units_arg(units: Mapping[str, str] | None, file: str, style: str = "python") -> dict[str, str]:
    if units is None:
        return {}
    if not isinstance(units, Mapping):
        raise DataError(
            f"units= must be a mapping such as {{'velocity': 'm/s', 'spin': 'rpm'}}; got {units!r}",
            file=file,
        )
    bad = [k for k in units if k not in (*_UNIT_KINDS, "angle")]
    if bad:
        raise DataError(f"units= has unknown keys {bad}; use 'velocity', 'spin' and/or 'angle'", file=file)
    out = {}
    for kind, unit in units.items():
        if unit is None:
            continue
        if isinstance(unit, str) and _relative_word(unit) is not None:
            said = hints.unit_setting(kind, unit, style) or f"units={{{kind!r}: {unit!r}}}"
            raise DataError(f"{said}: {unit!r} is a relative unit; values and half-widths are read only in absolute "
                            f"units (a half-width in per cent is converted first: multiply it by its value / 100)",
                            file=file)
        try:
            out[kind] = _canonical(unit, kind)
        except DataError as exc:
            said = hints.unit_setting(kind, unit, style) or f"units={{{kind!r}: {unit!r}}}"
            raise DataError(f"{said}: {exc.message}", file=file) from None
    return out


def _a(word: str) -> str:
    """``word`` with its indefinite article: ``a velocity``, ``an angle``."""
    return ("an " if word[:1].lower() in "aeiou" else "a ") + word


def _column_unit(table: _Table, choice: _Choice, kind: str, given: dict[str, str]) -> tuple[str, str]:
    """Unit of a selected column and where it came from ("units=", "header", "assumed")."""
    col = choice.column
    header = None
    if col.unit_text is not None:
        known = _unit_of(col.unit_text)
        header = known.get(kind)
        if header is None and (known or not (choice.by_full_name and col.unit_in_header)):
            where = col.unit_where or ("header" if col.unit_in_header else "units row")
            what = f"{_a(next(iter(known)))} unit, not {_a(kind)} unit" if known else "not a known unit"
            try:
                _canonical(col.unit_text, kind)
            except DataError as exc:
                raise DataError(f"the {where} gives the unit {col.unit_text!r}, {what}; {exc.message}",
                                file=table.file, column=col.name) from None
    if kind in given:
        said = f"units= says {kind} {given[kind]}"
        if table.hint_style == "cli" and (flag := hints.unit_setting(kind, given[kind], "cli")):
            said = f"{flag} was given"
        if header is not None and header != given[kind]:
            raise DataError(
                f"the header says {header} but {said}; "
                "remove one of them or make them agree", file=table.file, column=col.name,
            )
        return given[kind], "units="
    if header is not None:
        return header, "header"
    return {"velocity": "radius/s", "spin": "rad/s", "angle": "deg"}[kind], "assumed"


def _describe_units(unit_of: dict[str, tuple[str, str]], chosen: dict[str, _Column]) -> str:
    parts = []
    for kind in (*_UNIT_KINDS, "angle"):
        roles = [r for r in unit_of if _ROLE_KINDS[r.split(".")[1]] == kind]
        if not roles:
            continue  # no angle in a Cartesian file
        found = {unit_of[r] for r in roles}
        if len({u for u, _ in found}) == 1:
            unit, origin = next(iter(found))
            parts.append(f"{kind} {unit}" + (" (assumed)" if origin == "assumed" else ""))
        else:
            parts.append(f"{kind} " + ", ".join(f"{chosen[r].name}: {unit_of[r][0]}" for r in roles))
    return ", ".join(parts)
