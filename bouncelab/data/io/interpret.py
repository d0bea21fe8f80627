"""From one :class:`~bouncelab.data.io.read.Table` to numbers in known units: one pipeline of small functions.

A :class:`Role` (state, component) says what a column holds; :func:`select_auto` or :func:`select_explicit`
picks a :class:`Column` for each; :func:`read_columns` parses them; :func:`with_units` scales them;
:func:`campaign_from_table` goes on to polar states, intervals and the unit guard. The landings of ``bouncelab
predict`` and the shots ask the same steps for their own columns. Each refusal is a DataError naming the file, the
column as spelled there and the data row, with the options that would put it right as hints.
"""

from __future__ import annotations

import math
import re
import sys
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core import plausibility, units
from bouncelab.core.errors import DataError, DroppedRowsWarning, Hint
from bouncelab.core.units import COMPONENTS, Z95
from bouncelab.core.validation import as_states
from bouncelab.data.campaign import build_campaign, validate_campaign
from bouncelab.data.io import names as syn
from bouncelab.data.io.read import MISSING, Table, is_empty

#: What ``missing=`` accepts: refuse incomplete rows (default) or drop them with a warning.
MISSING_POLICIES = ("raise", "drop")
#: What ``intervals=`` may say a file's interval columns hold: 95 % half-widths, or one standard deviation.
INTERVAL_KINDS = ("pi95", "sd")
STATES, PI_STATES, POLAR = syn.STATES, syn.PI_STATES, syn.POLAR_ROLES
_SAID = {"landing": "landing", "liftoff": "lift-off"}  # a state as messages write it
KINDS = {"xdot": "velocity", "ydot": "velocity", "omega": "spin", "speed": "velocity", "angle": "angle"}
_A = {"velocity": "a velocity", "spin": "a spin", "angle": "an angle"}  # a kind of unit in a sentence
#: The units a column is read in when neither the file nor ``units=`` gives one.
DEFAULT_UNITS = {"velocity": "radius/s", "spin": "rad/s", "angle": "deg"}
_DROP = Hint("missing", "drop", "drops incomplete rows")
_WIDEN = Hint("plausible", None, "PLAUSIBLE_RANGES.widened(...) accepts such values on purpose")
_RADIAN_LIKE = math.pi + 0.35  # a radian column read as degrees: every angle within +-(pi + a few tenths)
_MAX_ANGLE_HW = 90.0  # an angle half-width beyond this spans every direction: a unit or column mistake
_INT64_MAX = np.iinfo(np.int64).max
_POLAR_WORDS = ("speed", "angle", "spin")  # the polar components as a mapping in columns= names them
_WHERE = "in the column mapping (columns= in Python, --columns on the command line)"


class Role(NamedTuple):
    """What a column holds: a state (``landing``, ``liftoff_pi``, ``setting``...) and a component (``xdot``...)."""

    state: str
    comp: str = ""

    @classmethod
    def of(cls, text: str) -> Role:
        return cls(*text.split("."))

    def __str__(self) -> str:
        return f"{self.state}.{self.comp}" if self.comp else self.state

    @property
    def pi(self) -> bool:
        return self.state.endswith("_pi")


SETTING = Role("setting")


@dataclass(frozen=True)
class Column:
    """A column read for a role: its name, whether its whole header matched, its unit and ``origin``, its numbers."""

    name: str
    whole: bool = True
    unit: str = ""
    origin: str = ""
    raw: np.ndarray | None = None
    scaled: np.ndarray | None = None


@dataclass(frozen=True)
class Rows:
    """The table being read: its named columns, the file's data row (0-based) of each row kept, the ball radius."""

    t: Table
    frame: pd.DataFrame
    rows: np.ndarray
    radius: float = units.BALL_RADIUS_M
    plausible: plausibility.PlausibleRanges | None = plausibility.PLAUSIBLE_RANGES
    decimal_comma: bool = False

    @property
    def names(self) -> list[str]:
        return list(self.frame.columns)

    def err(self, message: str, column: str | None = None, i: int | None = None, hints=()) -> DataError:
        """A DataError of ``column`` at row ``i`` (of the rows kept): the file's line or cell in the message."""
        if i is None:
            return DataError(message, file=self.t.file, column=column, hints=hints)
        row = int(self.rows[i])
        where = f" ({self.t.locate(row, column)})" if self.t.locate is not None else ""
        return DataError(message + where, file=self.t.file, column=column, row=row + 1, hints=hints,
                         row_label=None if self.t.labels is None else self.t.labels[row])

    def cell(self, name: str, i: int, unit: str | None = None) -> str:
        """A cell as written in the file, with its unit (``'3.404 m/s'``): never a converted number."""
        v = self.t.text(name)[self.rows[i]] if self.t.text is not None else self.t.cells[name].iloc[self.rows[i]]
        text = v.strip() if isinstance(v, str) else repr(v.item() if isinstance(v, np.generic) else v)
        return text if unit is None else f"{text} {unit}"


def start(t: Table, radius_m: float = units.BALL_RADIUS_M, plausible=plausibility.PLAUSIBLE_RANGES) -> Rows:
    """The rows of a table, its unnamed columns left out; a header unit the units row contradicts refused."""
    for name in t.cells.columns:
        unit, (said, where) = syn.split_header(name)[1], t.units.get(name, ("", ""))
        if unit and where == "units row" and unit.strip().lower() != said.strip().lower() and (
                not syn.unit_of(unit) or syn.unit_of(unit) != syn.unit_of(said)):
            raise DataError(f"the header gives the unit {unit!r} but the units row under it says {said!r}", file=t.file,
                            column=name)
    frame = t.cells if all(t.cells.columns) else t.cells.loc[:, [bool(n) for n in t.cells.columns]]
    return Rows(t, frame, np.arange(len(frame)), radius_m, plausible)


def warn(message: str, category: type[Warning] = UserWarning) -> None:
    """A warning pointing at the caller's line: the first frame outside bouncelab.data."""
    depth, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__", "").startswith("bouncelab.data"):
        frame, depth = frame.f_back, depth + 1
    warnings.warn(message, category, stacklevel=depth)


def check_units_arg(given: Any, file: str) -> dict[str, str]:
    """``units=`` as canonical units; unknown keys and units, and relative ones, refused."""
    if given is not None and (not isinstance(given, Mapping) or set(given) - {"velocity", "spin", "angle"}):
        raise DataError(f"units must be a mapping of 'velocity', 'spin' and/or 'angle' to units; got {given!r}",
                        file=file)
    out = {}
    for kind, unit in ((k, u) for k, u in (given or {}).items() if u is not None):
        if isinstance(unit, str) and syn.relative_word(unit) is not None:
            raise DataError(f"the {kind} unit given, {unit!r}, is a relative unit: give an absolute one (a half-width "
                            "in per cent times its value / 100)", file=file)
        try:
            out[kind] = units.canonical_unit(unit, kind)
        except DataError as exc:
            raise DataError(f"the {kind} unit given: {exc.message}", file=file) from None
    return out


def find(r: Rows, requested: str, role: str) -> Column:
    """The one column a name in ``columns=`` matches (exactly, else case-, punctuation- and unit-insensitively)."""
    if r.names.count(requested.strip()) == 1:
        return Column(requested.strip())
    keys = {k for k in (syn.normalize(requested), syn.normalize(syn.split_header(requested)[0])) if k}
    found = [n for n in r.names if syn.normalize(n) in keys or syn.normalize(syn.split_header(n)[0]) in keys]
    if len(found) == 1:
        return Column(found[0], syn.normalize(found[0]) in keys)
    raise r.err(f"{requested!r} (asked for as {role}) matches several columns: {found}; give the exact name" if found
                else f"no column matches {requested!r} (asked for as {role}); the file's columns are {r.names}",
                requested)


def candidates(r: Rows, extra: Mapping[str, str] | None = None) -> dict[Role, list[Column]]:
    """The columns whose names match each role's synonyms (or ``extra``'s names)."""
    found: dict[Role, list[Column]] = {Role.of(role): [] for role in syn.ROLES}
    for name in r.names:
        if (match := syn.synonym_role(name, extra)) is not None:
            found[Role.of(match[0])].append(Column(name, match[1]))
    return found


def select_explicit(r: Rows, columns: Any) -> dict[Role, Column]:
    """The columns ``columns=`` names; a half-width named as a state (or the reverse), a speed in a list refused."""
    keys = (*STATES, *PI_STATES)
    if not isinstance(columns, Mapping) or set(columns) - {*keys, "setting"}:
        raise r.err(f"columns must be a mapping with the keys {[*STATES, 'setting', *PI_STATES]}; got {columns!r}")
    cols: dict[Role, Column] = {}
    for key in (k for k in keys if columns.get(k) is not None or k in STATES):
        if (roles := _state_roles(columns.get(key))) is None:
            raise r.err(f"the columns of {key!r} are a list (xdot, ydot, omega) or a mapping {{'speed': ..., 'angle': "
                        f"..., 'spin': ...}}; got {columns.get(key)!r}")
        cols.update({Role(key, c): find(r, n, f"{key} {c}") for c, n in roles.items()})
    if columns.get("setting") is not None:
        cols[SETTING] = find(r, str(columns["setting"]), "setting")
    said = {k: Role.of((syn.synonym_role(c.name) or ("",))[0] or ".") for k, c in cols.items() if k != SETTING}
    for k in (k for k, s in said.items() if s.comp and s.pi != k.pi):
        base = k.state.removesuffix("_pi")
        raise r.err(f"the columns given for {k.state!r} include one of the wrong kind: {cols[k].name!r} says it holds "
                    f"{_what(said[k])}, not {_what(k, Role(k.state, 'speed') in cols, asked=True)}; a state's own "
                    f"columns go under {base!r}, their half-widths under {base + '_pi'!r} (or rename the column if it "
                    "holds what is asked)", cols[k].name, hints=[Hint("columns")])
    for key in keys:
        if key in PI_STATES and Role(key, "speed") in cols and Role(key[:-3], "speed") not in cols:
            s = _SAID[key[:-3]]
            raise r.err(f"polar half-widths are given for {key!r}, but the {s} is read from Cartesian columns: they "
                        f"are propagated through a polar state; give the {s} as speed, angle, spin too, or {key!r} as "
                        "xdot, ydot, omega half-widths", hints=[Hint("columns")])
        if isinstance(columns.get(key), Mapping) or not (
                wrong := [c for c in COMPONENTS if Role(key, c) in said and said[Role(key, c)].comp in POLAR[:2]]):
            continue
        named = {s.comp: cols[k].name for k, s in said.items() if k.state == key and s.state == key}
        named.setdefault("omega", cols[Role(key, "omega")].name if not said[Role(key, "omega")].comp else None)
        k = Role(key, wrong[0])
        raise r.err(f"the column name {cols[k].name!r} says it holds {_what(said[k])}, but the list given for {key!r} "
                    f"reads it as {_what(k, asked=True)}: speed, angle and spin{' half-widths' if k.pi else ''} are "
                    "named by a mapping (a list is read as xdot, ydot, omega), or rename the column if it holds what "
                    "is asked", cols[k].name, hints=[Hint("columns", {key: {
                        w: named.get(c) or f"<{key} {w} column>" for w, c in zip(_POLAR_WORDS, POLAR, strict=True)}})])
    return cols


def select_auto(r: Rows) -> dict[Role, Column]:
    """The columns found by their names' synonyms, Cartesian or polar for each state, and their intervals."""
    found, cols, problems = candidates(r), {}, []
    forms = {s: "polar" if _names(found, s, ("speed", "angle")) and not _names(found, s, ("xdot", "ydot")) else
             "cartesian" for s in STATES}
    for s, other in zip(STATES, reversed(STATES), strict=True):
        if not _names(found, s, ("xdot", "ydot", "speed", "angle")):
            forms[s] = forms[other]  # nothing found: suggest the form the other state has
        if forms[s] == "cartesian" and any(len(found[Role(s, c)]) != 1 for c in ("xdot", "ydot")) and (
                polar := _names(found, s, ("speed", "angle"))):
            problems.append(f"{s}: both Cartesian columns {_names(found, s, ('xdot', 'ydot'))} and polar ones {polar}")
    for role in (*(Role(s, c) for s in STATES for c in (COMPONENTS if forms[s] == "cartesian" else POLAR)), SETTING):
        if len(found[role]) == 1:
            cols[role] = found[role][0]
        elif found[role] or role != SETTING:
            problems.append(f"{role}: " + (f"several candidates {_names(found, *role)}" if found[role] else
                                           "no column found"))
    faults = [f for s in STATES if (f := _auto_intervals(r, found, s, forms[s], problems, cols)) is not None]
    hint = Hint("columns", _columns_call(found, forms), "replace each <...>")
    if problems:
        note = ("; a state given as speed, angle and spin is named by a mapping {'speed': ..., 'angle': ..., "
                "'spin': ...}, not a list" if any(forms[s] == "cartesian" and _names(found, s, ("speed", "angle"))
                                                  for s in STATES) else "")
        raise r.err(f"cannot tell which columns hold the bounce data ({'; '.join(problems)}); the file's columns are "
                    f"{r.names}{note}", hints=[hint])
    if faults:
        raise r.err(faults[0], hints=[hint])
    return cols


def _auto_intervals(r: Rows, found: dict[Role, list[Column]], state: str, form: str, problems: list[str],
                    cols: dict[Role, Column]) -> str | None:
    """One state's interval columns by name into ``cols`` (Cartesian, or a polar state's polar); else the fault."""
    pi, said = f"{state}_pi", _SAID[state]
    if several := [f"{pi}.{c}: several candidates {_names(found, pi, (c,))}" for c in (*COMPONENTS, *POLAR[:2])
                   if len(found[Role(pi, c)]) > 1]:
        problems.extend(several)
        return None
    cartesian, polar = ([c for c in comps if found[Role(pi, c)]] for comps in (COMPONENTS, POLAR[:2]))
    missing = [w for w, c in zip(_POLAR_WORDS, POLAR, strict=True) if not found[Role(pi, c)]]
    if len(cartesian) == 3 and (form == "cartesian" or not polar):
        cols.update({Role(pi, c): found[Role(pi, c)][0] for c in COMPONENTS})
    elif polar and form == "cartesian":  # ignoring them loses the intervals, never gives a wrong number
        warn(f"{r.t.file}: ignoring the {pi} columns {_names(found, pi, (*polar, *cartesian))}: the {said} is read "
             f"from its Cartesian columns (xdot, ydot, omega), and half-widths of its speed or angle "
             f"({', '.join(_names(found, pi, polar))}) are propagated only through a polar state; loaded without "
             f"{said} intervals. To use them, name the {said} as speed, angle and spin and {pi!r} as a mapping, or "
             f"its xdot, ydot, omega half-widths as a list, {_WHERE}")
    elif polar and {"xdot", "ydot"} & set(cartesian):
        return (f"the {said} has both Cartesian half-widths {_names(found, pi, ('xdot', 'ydot'))} and polar ones "
                f"{_names(found, pi, polar)}; say which to read ({pi!r} as a list of xdot, ydot, omega or a mapping "
                "of speed, angle, spin)")
    elif polar and missing:
        return (f"the {said} has polar half-widths {_names(found, pi, POLAR)} but none for its "
                f"{' and '.join(missing)}: all three (speed, angle, spin) are needed to propagate them to xdot, ydot, "
                f"omega; add the missing column, or name it (or leave {pi!r} out to load without intervals)")
    elif polar:
        cols.update({Role(pi, c): found[Role(pi, c)][0] for c in POLAR})
    elif cartesian:
        warn(f"{r.t.file}: ignoring the incomplete {pi} columns {_names(found, pi, COMPONENTS)}; name all three "
             f"(xdot, ydot, omega{'; or speed, angle, spin' if form == 'polar' else ''}) {_WHERE} to use them")
    return None


def check_absolute_units(r: Rows, cols: Mapping[Role, Column]) -> None:
    """Refuse a state or interval column in a relative unit (2 % of 25 m/s read as 2 m/s)."""
    for role, col in ((k, c) for k, c in cols.items() if k != SETTING):
        row_unit = r.t.units.get(col.name, (None, "header"))
        if (unit := syn.relative_unit(col.name, row_unit[0])) is None:
            continue
        what = _what(role, Role(role.state, "speed") in cols, asked=True)[4:].removesuffix(" half-width")
        where = "header" if syn.split_header(col.name)[1] is not None else row_unit[1]
        raise r.err(f"the {where} gives the {what} half-width in {unit!r}, a relative unit: bouncelab reads "
                    "half-widths only in an absolute unit (that of the value or one of its kind); convert the column "
                    "first, multiplying each half-width in per cent by its value / 100 (2 % of 25 m/s is 0.5 m/s), "
                    "and give it the value's unit" if role.pi else f"the {where} gives the {what} in {unit!r}, a "
                    f"relative unit: a measured {what} needs an absolute unit (m/s, rpm, deg...); convert the column, "
                    "or name the one holding the value", col.name)


def interval_scales(r: Rows, cols: Mapping[Role, Column], intervals: str | None) -> dict[Role, float]:
    """The factor making each interval column a 95 % half-width (1, or Z95 for a standard deviation)."""
    scales, unsure = {}, []
    meaning = {"pi95": "a 95 % half-width", "sd": "one standard deviation"}
    for role, col in ((k, c) for k, c in cols.items() if k.pi):
        marker = syn.interval_marker(col.name)
        says = "pi95" if marker in syn.PI95_MARKERS else "sd" if marker in syn.SD_MARKERS else None
        if intervals is not None and says is not None and says != intervals:
            raise r.err(f"the interval columns are said to hold {meaning[intervals]}, but the name of {col.name!r} "
                        f"({marker!r}) says {meaning[says]}", col.name,
                        hints=[Hint("intervals", says, "as the name says")])
        if intervals is None and marker in syn.AMBIGUOUS_MARKERS:
            unsure.append(col.name)
        else:
            scales[role] = Z95 if (intervals or says) == "sd" else 1.0
    if unsure:
        raise r.err(f"the interval columns {unsure} may hold standard deviations or 95 % half-widths, and the names do "
                    "not say which (a standard deviation read as a half-width is 1.96 times too narrow)", unsure[0],
                    hints=[Hint("intervals", "sd", f"standard deviations, multiplied by {Z95:.2f} to 95 % half-widths"),
                           Hint("intervals", "pi95", "95 % half-widths, as a campaign stores them")])
    return scales


def missing_rows(r: Rows, names: Sequence[str]) -> dict[int, tuple[str, Any]]:
    """Rows with a missing cell in one of ``names``: row -> (column, cell) of the first."""
    out: dict[int, tuple[str, Any]] = {}
    for s in (r.frame[n] for n in dict.fromkeys(names) if r.frame[n].dtype.kind not in "iub"):
        bad = s.isna() if s.dtype.kind == "f" else s.isna() | s.astype(str).str.strip().str.lower().isin(MISSING)
        for i in np.flatnonzero(bad.to_numpy(dtype=bool)):
            out.setdefault(int(i), (s.name, s.iloc[i]))
    return dict(sorted(out.items()))


def drop_missing(r: Rows, names: Sequence[str]) -> tuple[Rows, list[int]]:
    """The rows without a missing cell in ``names``, and the file's data rows dropped (a warning names them)."""
    if not (bad := missing_rows(r, names)):
        return r, []
    if len(bad) == len(r.frame):
        raise r.err(f"every row has a missing value (e.g. column {bad[0][0]!r}, row 1): nothing is left to load")

    def show(i: int, name: str, v: Any) -> str:
        where = (f"{r.t.locate(i, name)}: " if r.t.locate else "" if r.t.labels is None else
                 f"row label {r.t.labels[i]!r}: ")
        what = "NaN" if isinstance(v, float) else "empty" if is_empty(v) else repr(v.strip())
        return f"row {i + 1} ({where}{name!r} is {what})"

    warn(f"{r.t.file}: dropped {len(bad)} incomplete row(s) of {len(r.frame)}: "
         + "; ".join(show(i, *cell) for i, cell in bad.items()), DroppedRowsWarning)
    keep = np.setdiff1d(np.arange(len(r.frame)), list(bad))
    return replace(r, frame=r.frame.iloc[keep], rows=r.rows[keep]), list(bad)


def decimal_convention(r: Rows, names: Sequence[str]) -> Rows:
    """Whether a semicolon, tab or blank-separated file writes decimal commas; an ambiguous ``3.000`` refused."""
    if r.t.delimiter == ",":
        return r
    names = [n for n in dict.fromkeys(names) if r.frame[n].dtype.kind not in "iufb"]
    t = pd.Series(r.frame[names].to_numpy().ravel(), dtype=object).str.strip()  # row by row, non-text NaN
    marked = t.str.contains(r"[.,]", na=False)
    grouped = marked & t.str.fullmatch(r"[+-]?[1-9]\d{0,2}([.,]\d{3})+", na=False)  # 0.250 cannot be thousands
    comma = marked & ~grouped & t.str.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", na=False)
    dot = marked & ~grouped & ~comma & t.str.contains(".", regex=False, na=False)
    dot[dot] = ~np.isnan(syn.to_numbers(t[dot]))

    def first(mask: pd.Series) -> tuple[int, str, str] | None:  # (row, column, text) of the first in row order
        return None if not (k := np.flatnonzero(mask)).size else (int(k[0]) // len(names), names[k[0] % len(names)],
                                                                   t[k[0]])

    comma, dot = first(comma), first(dot)
    if comma and dot:
        (i, name, text), was = max(comma, dot), min(comma, dot)
        raise r.err(f"{text!r} writes its decimals differently from {was[2]!r} (column {was[1]!r}, row "
                    f"{int(r.rows[was[0]]) + 1}); write every number with the same decimal mark", name, i)
    if comma or dot:
        why = (f"the file writes decimals with a {'comma' if comma else 'dot'} ({(comma or dot)[2]!r}), so the "
               f"{'dot' if comma else 'comma'} is a thousands separator or a slip")
        bad = first(grouped & t.str.contains("." if comma else ",", regex=False, na=False))
    else:  # a decimal-comma locale's export (semicolons), where 1.500 may well be 1500
        bad = first(grouped & (t.str.contains(",", regex=False, na=False) | (r.t.delimiter == ";")))
        why = (f"nothing else in the file says whether the {'comma' if bad and ',' in bad[2] else 'dot'} is a decimal "
               "mark or a thousands separator")
    if bad is not None:
        raise r.err(f"{bad[2]!r} is ambiguous: {why}; write it without the separator "
                    f"({bad[2].replace('.', '').replace(',', '')}) or with the file's decimal mark", bad[1], bad[0])
    return replace(r, decimal_comma=comma is not None)


def _missing(v: Any) -> bool:
    return is_empty(v) or str(v).strip().lower() in MISSING


def numbers(r: Rows, name: str, what: str = "bounce") -> tuple[np.ndarray, DataError | None]:
    """A column as floats, and the error of its first bad cell (or None)."""
    s = r.frame[name]
    if typed := s.dtype.kind in "iuf" and pd.api.types.is_numeric_dtype(s):
        vals = s.to_numpy() if s.dtype == np.float64 else s.to_numpy(dtype=float, na_value=np.nan)
        if s.dtype.kind in "iu" and r.t.text is not None and not vals.all():  # pandas reads "-0" as the integer 0
            vals = np.copysign(vals, np.where([r.t.text(name)[k].lstrip()[:1] == "-" for k in r.rows], -1.0, 1.0))
    else:
        vals = syn.to_numbers(s.to_numpy(), r.decimal_comma)
    if not (bad := np.flatnonzero(np.isnan(vals))).size or (typed and r.t.lengths is not None):
        return vals, None  # an array's NaN is refused as a value
    i = int(bad[0])
    v = r.t.text(name)[r.rows[i]] if typed and r.t.text is not None else s.iloc[i]
    if not _missing(v):
        return vals, r.err(f"non-numeric value {v!r}", name, i)
    said = ("missing value (NaN)" if typed and r.t.text is None else "empty cell" if is_empty(v) else
            f"missing value {v.strip()!r}")
    return vals, r.err(f"{said}; every {what} needs a value", name, i, [_DROP])


def setting(r: Rows, name: str) -> np.ndarray:
    """Setting labels as written: whole numbers as int64 (exact; text beyond int64), else strings."""
    s = r.frame[name]
    if s.dtype.kind in "iu" and not s.hasnans:  # whole numbers read as integers are what their text says
        big = s.dtype.kind == "u" and len(s) and int(s.max()) > _INT64_MAX
        return np.array([str(int(v)) for v in s]) if big else s.to_numpy().astype(np.int64)
    cells = [r.t.text(name)[k] for k in r.rows] if r.t.text is not None else s.tolist()
    parsed = syn.to_numbers([v if isinstance(v, str) else "" for v in cells])  # of the labels written as text
    for i, v in enumerate(cells):
        if _missing(v) or (isinstance(v, float) and not math.isfinite(v)):
            shown = "empty" if is_empty(v) and not isinstance(v, float) else repr(
                v.strip() if isinstance(v, str) else v)
            raise r.err(f"missing setting label ({shown}); every bounce needs one", name, i, [_DROP])
        if isinstance(v, str) and np.isinf(parsed[i]):
            raise r.err(f"setting label {v.strip()!r} is not a finite number nor a name; every bounce needs a label",
                        name, i)
    labels = [v.strip() if isinstance(v, str) else v for v in cells]
    found = [_label_number(v, x) for v, x in zip(labels, parsed, strict=True)]
    if all(isinstance(x, int) for x in found):  # beyond int64: kept exact as text
        fits = all(abs(x) <= _INT64_MAX for x in found)
        return np.array(found, dtype=np.int64) if fits else np.array([str(x) for x in found])
    if all(isinstance(x, float) for x in found):
        return np.array(found, dtype=float)
    return np.array([str(int(v)) if isinstance(v, float) and v.is_integer() else str(v) for v in labels])


def _label_number(v: Any, parsed: float) -> int | float | None:
    """A label (``parsed``: its text's number) as an exact int, a float of up to 15 significant digits, else None."""
    if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number | str):
        return None
    text = v.replace("\u2212", "-") if isinstance(v, str) else ""
    if isinstance(v, int | np.integer) or re.fullmatch(r"[+-]?\d+", text):
        return int(text or v)  # exact, however long ("01" is 1)
    if not math.isfinite(x := float(parsed if isinstance(v, str) else v)) or (x.is_integer() and abs(x) >= 2.0**53):
        return None
    digits = len(re.sub(r"[^0-9]", "", v.lower().split("e")[0]).strip("0")) if isinstance(v, str) else 0
    return int(x) if x.is_integer() else x if digits <= 15 else None


def read_columns(r: Rows, cols: Mapping[Role, Column], *, missing: str, what: str = "bounce"
                 ) -> tuple[Rows, dict[Role, Column], list[int]]:
    """The columns' numbers as written, rows with a missing cell dropped (and said) or the first bad cell refused."""
    used: dict[str, Role] = {}
    for role, col in cols.items():
        if used.setdefault(col.name, role) != role:
            raise r.err(f"the same column is asked for as {used[col.name]} and as {role}", col.name)
    lengths = {n: r.t.lengths[n] for n in used} if r.t.lengths is not None else {}
    if len(set(lengths.values())) > 1:
        raise r.err(f"the columns have different lengths {lengths}", max(lengths, key=lambda k: lengths[k]))
    r, dropped = drop_missing(r, list(used)) if missing == "drop" else (r, [])
    r = decimal_convention(r, [c.name for role, c in cols.items() if role != SETTING])
    out, errors = {}, []
    for role, col in cols.items():
        try:
            raw, error = (setting(r, col.name), None) if role == SETTING else numbers(r, col.name, what)
        except DataError as exc:
            raw, error = None, exc
        errors += [error] if error is not None else []
        out[role] = replace(col, raw=raw)
    if errors:  # the first bad cell in row order
        raise min(errors, key=lambda e: e.row or 0)
    return r, out, dropped


def column_unit(r: Rows, col: Column, kind: str, given: Mapping[str, str],
                default: Mapping[str, str] = DEFAULT_UNITS) -> tuple[str, str]:
    """The unit of a column and where it came from (``units=``, header, assumed)."""
    text, where = syn.split_header(col.name)[1], "header"
    text, where = (text, where) if text is not None else r.t.units.get(col.name, (None, ""))
    known = {} if text is None else syn.unit_of(text)
    if text is not None and kind not in known and (known or not (col.whole and where == "header")):
        what = f"{_A[next(iter(known))]} unit, not {_A[kind]} unit" if known else "not a known unit"
        try:
            units.canonical_unit(text, kind)
        except DataError as exc:
            raise r.err(f"the {where} gives the unit {text!r}, {what}; {exc.message}", col.name) from None
    if kind in given and kind in known and known[kind] != given[kind]:
        raise r.err(f"the header says {known[kind]} but the {kind} unit given is {given[kind]}", col.name,
                    hints=[Hint("units", {kind: known[kind]}, "as the header says")])
    if kind in given:
        return given[kind], "units="
    return (known[kind], "header") if kind in known else (default[kind], "assumed")


def with_units(r: Rows, cols: dict[Role, Column], given: Mapping[str, str],
               scales: Mapping[Role, float] | None = None) -> dict[Role, Column]:
    """Each column's unit and scaled numbers (radii/s, rad/s, degrees); a half-width without a unit has its value's."""
    out = dict(cols)
    for role in sorted((k for k in cols if k != SETTING), key=lambda k: k.pi):  # states first: intervals follow them
        unit, origin = column_unit(r, cols[role], kind := KINDS[role.comp], given)
        state = Role(role.state.removesuffix("_pi"), role.comp)
        state = Role(state.state, "speed") if state not in out and role.comp in ("xdot", "ydot") else state
        if origin == "assumed" and state != role and out[state].origin != "assumed":
            unit, origin = out[state].unit, "its state column"  # (a Cartesian interval of a polar state: its speed's)
        raw = cols[role].raw
        scaled = (units.velocity_to_scaled(raw, unit, radius_m=r.radius) if kind == "velocity" else
                  units.spin_to_scaled(raw, unit) if kind == "spin" else np.rad2deg(raw) if unit == "rad" else raw)
        out[role] = replace(cols[role], unit=unit, origin=origin, scaled=scaled * (scales or {}).get(role, 1.0))
    return out


def polar_state(r: Rows, cols: dict[Role, Column], state: str) -> dict[Role, Column]:
    """A state given as speed, angle and spin with its xdot, ydot; speeds < 0 and angles out of range refused."""
    sp, an, om = (cols[Role(state, c)] for c in POLAR)
    speed, angle, said, landing = sp.raw, an.scaled, _SAID[state], state == "landing"
    if (infinite := ~np.isfinite(np.column_stack([speed, an.raw, om.raw]))).any():
        i, k = (int(v) for v in np.argwhere(infinite)[0])
        col = (sp, an, om)[k]
        raise r.err(f"{said} {_POLAR_WORDS[k]} {r.cell(col.name, i, col.unit)} is not a finite number; every bounce "
                    "needs a finite speed, angle and spin", col.name, i)
    if an.origin == "assumed" and len(angle) and np.max(np.abs(angle)) <= _RADIAN_LIKE:
        raise r.err(f"the file gives no unit for the {said} angles and all are within +-{_RADIAN_LIKE:.2f}: they look "
                    f"like radians, not degrees; say which (or a header '{an.name} (rad)')", an.name,
                    hints=[Hint("units", {"angle": "rad"})])
    bad_speed = ~(speed > 0) if landing else ~(speed >= 0)
    bad_angle = ~((angle > 0) & (angle <= 90)) if landing else ~((angle >= 0) & (angle < 180))
    if (rows := np.flatnonzero(bad_speed | bad_angle)).size and bad_speed[i := int(rows[0])]:
        raise r.err(f"{said} speed {r.cell(sp.name, i, sp.unit)}: a speed must be "
                    f"{'positive' if landing else 'zero or positive'} (the angle gives the direction)", sp.name, i)
    if rows.size:
        raise r.err(f"{said} angle {r.cell(an.name, i, an.unit)} is not plausible: " + (
            "a landing angle is positive below the horizontal, in (0, 90] degrees (negate a column measured the other "
            "way)" if landing else "a lift-off angle is positive above the horizontal, in [0, 180) degrees (below 0 "
            "the ball goes into the ground)"), an.name, i)
    cart = units.state_from_polar(np.column_stack([speed, angle, om.raw]), kind=state, speed_unit=sp.unit,
                                  spin_unit=om.unit, radius_m=r.radius)
    a = np.deg2rad(angle)  # the components in the file's speed unit, for the unit checks and their messages
    return {**cols, Role(state, "xdot"): replace(sp, scaled=cart[:, 0], raw=speed * np.cos(a)),
            Role(state, "ydot"): replace(sp, scaled=cart[:, 1], raw=(-1.0 if landing else 1.0) * speed * np.sin(a))}


def polar_intervals(r: Rows, cols: dict[Role, Column], state: str, scales: Mapping[Role, float]) -> dict[Role, Column]:
    """A polar state's half-widths propagated to xdot, ydot, omega ones, checked first (it squares a sign away)."""
    roles = [Role(f"{state}_pi", c) for c in POLAR]
    raw = np.column_stack([cols[k].raw for k in roles])
    bad = ~(np.isfinite(raw) & (raw >= 0))
    bad[:, 1] |= r.plausible is not None and cols[roles[1]].scaled > _MAX_ANGLE_HW
    if bad.any():
        i, k = (int(v) for v in np.argwhere(bad)[0])
        why = "is negative" if raw[i, k] < 0 else "is not a finite number" if not np.isfinite(raw[i, k]) else (
            f"is wider than any plausible angle half-width ({_MAX_ANGLE_HW:g} deg): check the column's unit")
        raise r.err(f"{interval_cell(r, cols[roles[k]], i, scales.get(roles[k], 1.0))} {why}", cols[roles[k]].name, i)
    polar, hws = (np.column_stack([cols[Role(s, c)].scaled for c in POLAR]) for s in (state, roles[0].state))
    try:
        hw = units.polar_halfwidths_to_cartesian(polar, hws, kind=state, speed_unit="radius/s", spin_unit="rad/s",
                                                 radius_m=r.radius)
    except DataError as exc:  # a number too large for floats once scaled: name the row
        i = exc.row - 1 if exc.row is not None else int(np.flatnonzero(~np.isfinite(hws).all(axis=1))[0])
        cells = ", ".join(r.cell(cols[k].name, i, cols[k].unit) for k in roles)
        raise r.err(f"the {_SAID[state]} half-widths {cells} cannot be propagated: {exc.message}",
                    cols[roles[0]].name, i) from None
    # xdot and ydot keep the speed column, so that a later message about them names a column of the file
    return {**cols, **{Role(roles[0].state, c): replace(cols[roles[2 if c == "omega" else 0]], scaled=hw[:, k])
                       for k, c in enumerate(COMPONENTS)}}


def interval_cell(r: Rows, col: Column, i: int, factor: float) -> str:
    """An interval cell for messages, with the number checked (a standard deviation x 1.96)."""
    cell, unit = r.cell(col.name, i, col.unit or None), f" {col.unit}" if col.unit else ""
    return f"prediction-interval half-width {cell}" if factor == 1.0 else (
        f"standard deviation {cell} (x {factor:.2f}: {col.raw[i] * factor:.6g}{unit} as a 95 % half-width)")


def check_intervals(r: Rows, cols: Mapping[Role, Column], pi: str, arr: np.ndarray, scales: Mapping[Role, float]):
    """Half-widths that are negative, or wider than any plausible value (a unit mistake, not an uncertainty)."""
    roles = [Role(pi, c) for c in COMPONENTS]
    if (arr < 0).any():
        i, k = (int(v) for v in np.argwhere(arr < 0)[0])
        raise r.err(f"prediction-interval half-width {r.cell(cols[roles[k]].name, i)} is negative", cols[roles[k]].name,
                    i)
    limit = np.array([r.plausible.max_speed / r.radius] * 2 + [r.plausible.max_spin * 2 * math.pi / 60])
    if not (arr > limit).any():
        return
    i, k = (int(v) for v in np.argwhere(arr > limit)[0])
    what, state = (f"{r.plausible.max_speed:g} m/s" if k < 2 else f"{r.plausible.max_spin:g} rpm"), pi[:-3]
    if k < 2 and Role(state, "speed") in cols:  # propagated: blame the column whose term dominates
        (v, a), (h_v, h_a) = ((cols[Role(s, "speed")].scaled[i], np.deg2rad(cols[Role(s, "angle")].scaled[i]))
                              for s in (state, pi))
        trig = (abs(math.cos(a)), abs(math.sin(a)))[:: 1 if k == 0 else -1]  # units.polar_halfwidths_to_cartesian
        cell = {s + c: r.cell(cols[Role(s, c)].name, i, cols[Role(s, c)].unit) for s in (pi, state)
                for c in ("speed", "angle")}
        culprit = cols[Role(pi, "speed" if trig[0] * h_v >= v * trig[1] * h_a else "angle")].name
        unit = cols[Role(pi, "speed")].unit
        value = units.velocity_from_scaled(arr[i, k], unit, radius_m=r.radius)
        raise r.err(f"the {_SAID[state]} {COMPONENTS[k]} half-width propagated from the speed half-width "
                    f"{cell[pi + 'speed']} and the angle half-width {cell[pi + 'angle']} (at speed "
                    f"{cell[state + 'speed']}, angle {cell[state + 'angle']}) is {value:.4g} {unit}, wider than any "
                    f"plausible value ({what}): check the unit of {culprit!r}", culprit, i)
    raise r.err(f"{interval_cell(r, cols[roles[k]], i, scales.get(roles[k], 1.0))} is wider than any plausible value "
                f"({what}): check the column's unit", cols[roles[k]].name, i)


def check_landing_sign(r: Rows, cols: Mapping[Role, Column]) -> None:
    """A Cartesian landing going up, quoted as written (as_states would quote radii/s)."""
    col = cols[Role("landing", "ydot")]
    if Role("landing", "speed") not in cols and (up := np.flatnonzero(col.scaled >= 0)).size and np.isfinite(
            [cols[Role("landing", c)].scaled[: up[0] + 1] for c in COMPONENTS]).all():
        raise r.err("landing ydot must be negative (y points up, a landing moves down); the file gives "
                    f"{r.cell(col.name, int(up[0]), col.unit)} (a file whose y points down needs the column negated)",
                    col.name, int(up[0]))


def states(r: Rows, cols: Mapping[Role, Column], state: str) -> np.ndarray:
    """A state's (n, 3) scaled array, validated once, errors named in the file's terms."""
    try:
        return as_states(np.column_stack([cols[Role(state, c)].scaled for c in COMPONENTS]), state,
                         landing=state == "landing", file=r.t.file)[0]
    except DataError as exc:
        col = cols.get(Role.of(exc.column) if "." in (exc.column or "") else Role(exc.column or "", "xdot"))
        raise r.err(exc.message, exc.column if col is None else col.name,
                    None if exc.row is None else exc.row - 1) from None


def check_plausible(r: Rows, cols: Mapping[Role, Column], arrays: tuple[np.ndarray, np.ndarray]) -> None:
    """Refuse numbers whose unit is not given and not certain, and numbers only a wrong unit makes."""
    roles = [Role(s, c) for s in STATES for c in COMPONENTS]
    for kind in ("velocity", "spin"):
        if not (assumed := [k for k in roles if KINDS[k.comp] == kind and cols[k].origin == "assumed"]):
            continue

        def convert(factor: float, assumed: list[Role] = assumed) -> tuple[np.ndarray, np.ndarray]:
            arrs = {k: cols[k].raw * factor if k in assumed else cols[k].scaled for k in roles}
            return tuple(np.column_stack([arrs[Role(s, c)] for c in COMPONENTS]) for s in STATES)

        verdicts = plausibility.plausible_units(kind, convert, radius_m=r.radius, ranges=r.plausible)
        default = plausibility.CANDIDATE_UNITS[kind][0]
        if (fits := [u for u, why in verdicts.items() if why is None]) == [default]:
            continue
        names = list(dict.fromkeys(cols[k].name for k in assumed))  # a polar speed backs xdot and ydot
        why, said = verdicts[default], f"the file gives no {kind} unit for {', '.join(map(repr, names))}"
        example = "m/s" if kind == "velocity" else "rpm"
        header = f"a unit in the column header says it too, e.g. '{names[0]} [{example}]'"
        msg = (f"{said}, and its numbers are plausible in {', '.join(fits[:-1])} and in {fits[-1]}"
               + (f" (not in {default}: {why.reason})" if why is not None else "")
               + f"; bouncelab does not guess ({header})" if len(fits) > 1 else
               f"{said}; read as {default}, {why.reason}; the numbers look like {fits[0]} ({header})" if fits else
               f"{said}; read as {default}, {why.reason}, and they are not plausible in "
               f"{', '.join(plausibility.CANDIDATE_UNITS[kind])} either: check the column, or declare its unit "
               "and widen the plausible ranges")
        hints = [Hint("units", {kind: u}) for u in fits or [default]] + ([] if fits else [_WIDEN])
        if why is not None and why.row is not None:
            raise r.err(msg, cols[Role(why.state, why.component)].name, why.row, hints)
        raise r.err(msg, names[0] if len(names) == 1 else None, hints=hints)
    if (why := plausibility.implausibility(*arrays, radius_m=r.radius, ranges=r.plausible)) is not None:
        col = cols[Role(why.state, why.component)]
        said = r.cell(col.name, why.row, col.unit) if why.row is not None else f"in {col.unit}"
        others = [Hint("units", {why.kind: u}) for u in plausibility.CANDIDATE_UNITS[why.kind] if u != col.unit]
        raise r.err(f"{said} (unit from {col.origin}): {why.reason}; the {why.kind} unit is wrong, or the values need "
                    "wider plausible ranges", col.name, why.row, [*others, _WIDEN])


def campaign_from_table(t: Table, *, columns: Any, given: dict[str, str], campaign: str, surface: str, source: str,
                        ball_radius_m: float, plausible=plausibility.PLAUSIBLE_RANGES, missing: str = "raise",
                        intervals: str | None = None) -> xr.Dataset:
    """The campaign a table holds (see :func:`bouncelab.data.io.load_campaign`)."""
    r = start(t, ball_radius_m, plausible)
    if len(r.frame) == 0:
        raise r.err("the file has a header but no data rows")
    cols = select_auto(r) if columns is None else select_explicit(r, columns)
    check_absolute_units(r, cols)
    scales = interval_scales(r, cols, intervals)
    r, cols, dropped = read_columns(r, cols, missing=missing)
    cols = with_units(r, cols, given, scales)
    attrs: dict[str, Any] = {"source_units": _describe_units(cols)}
    read = {s: " and ".join(sorted({"95 % half-widths" if f == 1 else "standard deviations x 1.96"
                                    for k, f in scales.items() if k.state == f"{s}_pi"})) for s in STATES}
    if any(read.values()):
        attrs["interval_source"] = ", ".join(f"{s} {read[s]}" for s in STATES if read[s])
    if polar := [s for s in STATES if Role(s, "speed") in cols]:
        attrs["source_form"] = ", ".join(f"{s} {'polar' if s in polar else 'cartesian'}" for s in STATES)
        for state in polar:
            cols = polar_state(r, cols, state)
    if polar_pi := [s for s in STATES if Role(f"{s}_pi", "speed") in cols]:  # derived, not measured: say so
        attrs["interval_form"] = ", ".join(
            f"{s} " + ("polar (speed, angle and spin half-widths propagated to first order, speed and angle errors "
                       "independent)" if s in polar_pi else "cartesian")
            for s in STATES if Role(f"{s}_pi", "omega") in cols)
        for state in polar_pi:
            cols = polar_intervals(r, cols, state, scales)
    check_landing_sign(r, cols)
    arrays = {s: states(r, cols, s) for s in (*STATES, *PI_STATES) if Role(s, "xdot") in cols}
    for pi in (s for s in PI_STATES if s in arrays):
        check_intervals(r, cols, pi, arrays[pi], scales)
    check_plausible(r, cols, (arrays["landing"], arrays["liftoff"]))
    if missing == "drop":
        attrs["dropped_rows"] = [i + 1 for i in dropped]  # the file's data rows, 1-based as in errors
    return build_campaign(arrays["landing"], arrays["liftoff"], setting=cols[SETTING].raw if SETTING in cols else None,
                          landing_pi=arrays.get("landing_pi"), liftoff_pi=arrays.get("liftoff_pi"), campaign=campaign,
                          surface=surface, ball_radius_m=ball_radius_m, source=source, data_kind="measured",
                          attrs=attrs)


def campaign_from_netcdf(ds: xr.Dataset, *, file: str, source: str, columns: Any, given: Any, campaign: str | None,
                         surface: str | None, ball_radius_m: float, plausible=plausibility.PLAUSIBLE_RANGES,
                         intervals: str | None = None) -> xr.Dataset:
    """A campaign file written by save_campaign: in scaled units, loaded as it is (its arrays checked once)."""
    if columns is not None or given is not None or intervals is not None:
        raise DataError("a bouncelab campaign file (scaled units, named variables) takes no columns, units or "
                        "intervals", file=file)
    stored = ds.attrs.get("ball_radius_m")
    if stored is not None and ball_radius_m != units.BALL_RADIUS_M and \
            units.ball_radius(stored, file=file) != float(ball_radius_m):  # (the file's own value checked first)
        raise DataError(f"the campaign was scaled with a ball radius of {float(stored)!r} m, not {ball_radius_m!r}",
                        file=file)
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        if var in ds.variables and str(ds[var].attrs.get("units", "")).strip().lower() not in ("scaled", ""):
            raise DataError(f"the variable {var!r} says units={ds[var].attrs['units']!r}, but a campaign file holds "
                            "scaled units (units='scaled'): convert it with bouncelab.core.units.to_scaled, or rename "
                            "the variables to load the file as a table", file=file, column=var)
    ds = ds.set_coords("setting") if "setting" in ds.data_vars else ds  # a setting variable is still the setting
    if "setting" in ds.coords and ds["setting"].attrs.get("bouncelab_dtype") == "int64":
        try:  # save_campaign's netCDF-3 spelling of int64 settings
            labels = np.array([int(str(v)) for v in ds["setting"].values], dtype=np.int64)
        except (ValueError, OverflowError):
            raise DataError("setting labels marked int64 are not all integers", file=file, column="setting") from None
        ds = ds.assign_coords(setting=("bounce", labels, {k: v for k, v in ds["setting"].attrs.items()
                                                           if k != "bouncelab_dtype"}))
    out = validate_campaign(ds.assign_attrs({"data_kind": "measured", "source": source, **ds.attrs}), file=file)
    radius = float(out.attrs.get("ball_radius_m", units.BALL_RADIUS_M))
    p0, pf = out["landing"].values, out["liftoff"].values
    # one pass for the upper and the lower limits; the messages below only once it finds a fault
    if plausibility.implausibility(p0, pf, radius_m=radius, ranges=plausible, lower=True) is not None:
        if (why := plausibility.implausibility(p0, pf, radius_m=radius, ranges=plausible)) is not None:
            raise DataError(f"{why.state} {why.component} of bounce {why.row}: {why.reason}; the file is not in scaled "
                            "units (radii/s, rad/s) as a campaign file must be", file=file, column=why.state,
                            row=None if why.row is None else why.row + 1, hints=[_WIDEN])
        # the lower limits: all spins tiny, landings far too slow (a damaged file, or m/s)
        if (exc := plausibility.scaled_units_error(p0, pf, radius_m=radius, ranges=plausible)) is not None:
            raise DataError(f"{exc.message}; a campaign file holds scaled units (radii/s, rad/s)", file=file,
                            column=exc.column, row=exc.row, hints=[h for h in exc.hints if h.option == "plausible"])
    out.attrs.update({k: str(v) for k, v in (("campaign", campaign), ("surface", surface)) if v is not None})
    return out


def _what(role: Role, polar: bool = False, asked: bool = False) -> str:
    """A role in words: ``the landing spin itself``, ``a half-width of ...``; asked: ``the landing omega half-width``"""
    comp = "spin" if role.comp == "omega" and (polar or not asked) else role.comp
    what = f"{_SAID[role.state.removesuffix('_pi')]} {comp}"
    if asked:
        return f"the {what} half-width" if role.pi else f"the {what}"
    return f"a half-width of the {what} (a prediction interval)" if role.pi else f"the {what} itself"


def _names(found: dict[Role, list[Column]], state: str, comps: Sequence[str] | str) -> list[str]:
    return [c.name for comp in ([comps] if isinstance(comps, str) else comps) for c in found[Role(state, comp)]]


def _state_roles(names: Any) -> dict[str, str] | None:
    """Component -> name of one entry of columns=: a list (xdot, ydot, omega) or a mapping of them or of speed, etc."""
    if isinstance(names, Mapping):
        ok = set(map(str, names)) in ({"xdot", "ydot", "omega"}, {"speed", "angle", "spin"},
                                      {"speed", "angle", "omega"})
        return {("omega" if k == "spin" else str(k)): str(v) for k, v in names.items()} if ok else None
    if isinstance(names, str) or not isinstance(names, Sequence) or len(names) != 3:
        return None
    return dict(zip(COMPONENTS, map(str, names), strict=True))


def _columns_call(found: dict[Role, list[Column]], forms: dict[str, str]) -> dict[str, Any]:
    """The columns= argument naming what was found, with ``<...>`` for what was not or is ambiguous."""
    def pick(role: Role, label: str | None = None) -> str:
        cands = _names(found, *role)
        return cands[0] if len(cands) == 1 else f"<one of {', '.join(cands)}>" if cands else (
            f"<{label or f'{role.state} {role.comp}'} column>")

    def state(s: str, form: str) -> Any:
        if form == "polar":
            return {w: pick(Role(s, c), f"{s} {w}") for w, c in zip(_POLAR_WORDS, POLAR, strict=True)}
        return [pick(Role(s, c)) for c in COMPONENTS]

    out: dict[str, Any] = {s: state(s, forms[s]) for s in STATES}
    out |= {"setting": pick(SETTING)} if found[SETTING] else {}
    for s, pi in zip(STATES, PI_STATES, strict=True):
        if forms[s] == "polar" and _names(found, pi, ("speed", "angle")):
            out[pi] = state(pi, "polar")
        elif _names(found, pi, COMPONENTS):
            out[pi] = state(pi, "cartesian")
    return out


def _describe_units(cols: Mapping[Role, Column]) -> str:
    parts = []
    for kind in ("velocity", "spin", "angle"):
        if not (roles := [k for k in cols if k != SETTING and KINDS[k.comp] == kind]):
            continue  # no angle in a Cartesian file
        first = cols[roles[0]]
        parts.append(f"{kind} {first.unit}" + (" (assumed)" if first.origin == "assumed" else "")
                     if len({cols[k].unit for k in roles}) == 1 else
                     f"{kind} " + ", ".join(f"{cols[k].name}: {cols[k].unit}" for k in roles))
    return ", ".join(parts)
