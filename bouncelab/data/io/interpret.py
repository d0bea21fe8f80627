"""From one table (a DataFrame read from any source) to a campaign: which column holds what, in which unit,
what the interval columns hold, and every refusal, a :class:`~bouncelab.core.errors.DataError` naming the
file, the column as spelled there and the data row, with the options that would put it right as
:class:`~bouncelab.core.errors.Hint` s (docs/data.md describes the behaviour).
"""

from __future__ import annotations

import math
import re
import sys
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core import plausibility, units
from bouncelab.core.errors import DataError, DroppedRowsWarning, Hint
from bouncelab.core.units import BALL_RADIUS_M, COMPONENTS, Z95
from bouncelab.core.validation import as_states
from bouncelab.data.campaign import make_campaign, validate_campaign
from bouncelab.data.io import names as syn
from bouncelab.data.io.read import MISSING, Table, is_empty

#: What ``missing=`` accepts: refuse incomplete rows (default) or drop them with a warning.
MISSING_POLICIES = ("raise", "drop")
#: What ``intervals=`` may say a file's interval columns hold: 95 % half-widths, or one standard deviation.
INTERVAL_KINDS = ("pi95", "sd")
STATES, PI_STATES, POLAR = syn.STATES, syn.PI_STATES, syn.POLAR_ROLES
_SAID = {"landing": "landing", "liftoff": "lift-off"}  # a state as messages write it
KINDS = {"xdot": "velocity", "ydot": "velocity", "omega": "spin", "speed": "velocity", "angle": "angle"}
_ASSUMED = {"velocity": "radius/s", "spin": "rad/s", "angle": "deg"}
_DROP = Hint("missing", "drop", "drops incomplete rows")
_WIDEN = Hint("plausible", None, "PLAUSIBLE_RANGES.widened(...) accepts such values on purpose")
_RADIAN_LIKE = math.pi + 0.35  # a radian column read as degrees: every angle within +-(pi + a few tenths)
_MAX_ANGLE_HW = 90.0  # an angle half-width beyond this spans every direction: a unit or column mistake
_INT64_MAX = np.iinfo(np.int64).max


def warn(message: str, category: type[Warning] = UserWarning) -> None:
    """A warning pointing at the caller's line: the first frame outside bouncelab.data."""
    depth, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__", "").startswith("bouncelab.data"):
        frame, depth = frame.f_back, depth + 1
    warnings.warn(message, category, stacklevel=depth)


def check_units_arg(given: Any, file: str) -> dict[str, str]:
    """``units=`` as canonical units; unknown keys and units, and relative ones, refused."""
    if given is None:
        return {}
    if not isinstance(given, Mapping) or [k for k in given if k not in ("velocity", "spin", "angle")]:
        raise DataError(f"units must be a mapping with the keys 'velocity', 'spin' and/or 'angle', e.g. {{'velocity': "
                        f"'m/s', 'spin': 'rpm'}}; got {given!r}", file=file)
    out = {}
    for kind, unit in ((k, u) for k, u in given.items() if u is not None):
        if isinstance(unit, str) and syn.relative_word(unit) is not None:
            raise DataError(f"the {kind} unit given, {unit!r}, is a relative unit: values and half-widths are read "
                            "only in absolute units (convert a half-width in per cent first: times its value / 100)",
                            file=file)
        try:
            out[kind] = units.canonical_unit(unit, kind)
        except DataError as exc:
            raise DataError(f"the {kind} unit given: {exc.message}", file=file) from None
    return out


class Choice(NamedTuple):
    name: str  # the column as spelled in the file
    whole: bool  # matched by its whole header, so a bracket in it may be part of the name


class Reading:
    """One table being read: the columns chosen for each role, their numbers and units; errors located in it."""

    def __init__(self, t: Table, radius_m: float = BALL_RADIUS_M, plausible=plausibility.PLAUSIBLE_RANGES):
        self.t, self.file, self.radius, self.plausible = t, t.file, radius_m, plausible
        seen: dict[str, int] = {}
        for j, name in enumerate(t.frame.columns):
            if name and seen.setdefault(name, j) != j:
                raise DataError(f"the header names column {name!r} twice (columns {seen[name] + 1} and {j + 1}); "
                                "rename one of them", file=t.file, column=name)
        if t.refused is not None:
            raise t.refused
        for name in seen:
            unit, row = syn.split_header(name)[1], t.units.get(name)
            if unit and row and row[1] == "units row" and not _same_unit(unit, row[0]):
                raise DataError(f"the header gives the unit {unit!r} but the units row under it says {row[0]!r}; make "
                                "them agree or remove one", file=t.file, column=name)
        self.frame = t.frame if all(t.frame.columns) else t.frame.loc[:, [bool(n) for n in t.frame.columns]]
        self.names = list(self.frame.columns)
        self.rows = np.arange(len(self.frame))  # the file's data row (0-based) of each row kept
        self.chosen: dict[str, Choice] = {}
        self.parsed: dict[str, np.ndarray] = {}
        self.scaled: dict[str, np.ndarray] = {}
        self.unit_of: dict[str, tuple[str, str]] = {}  # role -> (unit, where it came from)

    def err(self, message: str, column: str | None = None, i: int | None = None, hints=()) -> DataError:
        """A DataError at row ``i`` (0-based, of the rows kept) of ``column``: a file's line or cell in the message,
        a DataFrame's row label as a field."""
        if i is None:
            return DataError(message, file=self.file, column=column, hints=hints)
        row = int(self.rows[i])
        label = None if self.t.labels is None else self.t.labels[row]
        where = f" ({self.t.where(row, column)})" if self.t.where is not None else ""
        return DataError(message + where, file=self.file, column=column, row=row + 1, row_label=label, hints=hints)

    def col(self, role: str) -> str:
        return self.chosen[role].name

    def cell(self, name: str, i: int, unit: str | None = None) -> str:
        """A cell as written in the file, with its unit (``'3.404 m/s'``): never a converted number."""
        row = int(self.rows[i])
        v = self.t.text(name)[row] if self.t.text is not None else self.t.frame[name].iloc[row]
        text = v.strip() if isinstance(v, str) else repr(v.item() if isinstance(v, np.generic) else v)
        return text if unit is None else f"{text} {unit}"

    def unit_text(self, name: str) -> tuple[str | None, str]:
        """The unit a column's header, units row or units attribute gives, and where."""
        unit = syn.split_header(name)[1]
        return (unit, "header") if unit is not None else self.t.units.get(name, (None, ""))

    # -- which column holds what
    def find(self, requested: str, role: str) -> Choice:
        if [n for n in self.names if n == requested.strip()] == [requested.strip()]:
            return Choice(requested.strip(), True)
        keys = {k for k in (syn.normalize(requested), syn.normalize(syn.split_header(requested)[0])) if k}
        found = [n for n in self.names if syn.normalize(n) in keys or syn.normalize(syn.split_header(n)[0]) in keys]
        if len(found) == 1:
            return Choice(found[0], syn.normalize(found[0]) in keys)
        raise DataError(f"{requested!r} (asked for as {role}) matches several columns: {found}; give the exact name of "
                        "the one to use" if found else f"no column matches {requested!r} (asked for as {role}); the "
                        f"file's columns are {self.names}", file=self.file, column=requested)

    def candidates(self) -> dict[str, list[Choice]]:
        """The columns whose names match each role's synonyms; a whole-name match hides a base-name one."""
        found: dict[str, list[Choice]] = {role: [] for role in syn.ROLES}
        for name in self.names:
            for key, whole in ((syn.normalize(name), True), (syn.normalize(syn.split_header(name)[0]), False)):
                if (role := syn.role_of(key) or syn.role_of(key, polar=True)) is not None:
                    found[role].append(Choice(name, whole))
                    break
        return found

    def select_explicit(self, columns: Any) -> None:
        keys = (*STATES, *PI_STATES)
        if not isinstance(columns, Mapping) or [k for k in columns if k not in (*keys, "setting")]:
            raise DataError(f"columns must be a mapping with the keys {[*STATES, 'setting', *PI_STATES]}, e.g. "
                            f"{{'landing': [...], 'liftoff': [...]}}; got {columns!r}", file=self.file)
        for key in (k for k in keys if columns.get(k) is not None or k in STATES):
            if (roles := _state_roles(columns.get(key))) is None:
                raise DataError(f"the columns given for {key!r} must be a list of 3 column names (xdot, ydot, omega) "
                                f"or a mapping {{'speed': ..., 'angle': ..., 'spin': ...}}; got {columns.get(key)!r}",
                                file=self.file)
            self.chosen.update({f"{key}.{c}": self.find(n, f"{key} {c}") for c, n in roles.items()})
        if columns.get("setting") is not None:
            self.chosen["setting"] = self.find(str(columns["setting"]), "setting")
        said = {r: syn.synonym_role(ch.name) or "" for r, ch in self.chosen.items() if r != "setting"}
        # A half-width named as a state's column or the reverse is refused; so is a column named as a speed or angle in
        # a list (read as xdot, ydot, omega: 40 degrees would be a velocity of 40). A mapping says what each column is.
        for r in (r for r, t in said.items() if "." in t and ("_pi." in t) != ("_pi." in r)):
            key, polar = r.split(".")[0], f"{r.split('.')[0]}.speed" in self.chosen
            raise DataError(f"the columns given for {key!r} include one of the wrong kind: {self.col(r)!r} says it "
                            f"holds {_what(said[r])}, not {_what(r, polar, asked=True)}; a state's own columns go under"
                            f" {key.removesuffix('_pi')!r}, their half-widths under"
                            f" {key.removesuffix('_pi') + '_pi'!r} (or rename the column if it holds what is asked)",
                            file=self.file, column=self.col(r), hints=[Hint("columns")])
        for key in keys:
            if key in PI_STATES and f"{key}.speed" in self.chosen and f"{key[:-3]}.speed" not in self.chosen:
                raise DataError(f"polar half-widths (speed, angle, spin) are given for {key!r}, but the "
                                f"{_SAID[key[:-3]]} is read from Cartesian columns (xdot, ydot, omega): they are "
                                f"propagated through the polar state they belong to; give the {_SAID[key[:-3]]} as "
                                f"{{'speed': ..., 'angle': ..., 'spin': ...}} too, or {key!r} as a list of its xdot, "
                                "ydot, omega half-widths", file=self.file, hints=[Hint("columns")])
            wrong = [c for c in COMPONENTS if not isinstance(columns.get(key), Mapping) and f"{key}.{c}" in said
                     and said[f"{key}.{c}"].split(".")[-1] in ("speed", "angle")]
            if wrong:
                def pick(comp: str, key: str = key) -> str:  # the column whose name says it is ``comp``
                    found = [self.col(f"{key}.{c}") for c in COMPONENTS if said[f"{key}.{c}"] == f"{key}.{comp}"]
                    found += [self.col(f"{key}.omega")] if comp == "omega" and not said[f"{key}.omega"] else []
                    return found[0] if found else f"<{key} {'spin' if comp == 'omega' else comp} column>"

                r = f"{key}.{wrong[0]}"
                raise DataError(
                    f"the column name {self.col(r)!r} says it holds {_what(said[r])}, but the list given for {key!r} "
                    f"reads it as {_what(r, asked=True)}: speed, angle and spin"
                    f"{' half-widths' if key in PI_STATES else ''} are named by a mapping (a list is read as "
                    "xdot, ydot, omega), or rename the column if it holds "
                    "what is asked", file=self.file, column=self.col(r), hints=[Hint("columns", {key: {
                        k: pick(c) for k, c in zip(("speed", "angle", "spin"), POLAR, strict=True)}})])

    def select_auto(self) -> None:
        found = self.candidates()
        forms = {s: _form(found, s) for s in STATES}
        problems: list[str] = []
        for s, other in zip(STATES, reversed(STATES), strict=True):
            if not any(found[f"{s}.{c}"] for c in ("xdot", "ydot", "speed", "angle")):
                forms[s] = forms[other]  # nothing found: suggest the form the other state has
            if forms[s] == "cartesian" and any(len(found[f"{s}.{c}"]) != 1 for c in ("xdot", "ydot")) and any(
                    found[f"{s}.{c}"] for c in ("speed", "angle")):
                cart = [c.name for r in ("xdot", "ydot") for c in found[f"{s}.{r}"]]
                problems.append(f"{s}: both Cartesian columns {cart} "
                                f"and polar ones {[c.name for r in ('speed', 'angle') for c in found[f'{s}.{r}']]}")
        roles = [f"{s}.{c}" for s in STATES for c in (COMPONENTS if forms[s] == "cartesian" else POLAR)]
        for role in (*roles, "setting"):
            if len(found[role]) == 1:
                self.chosen[role] = found[role][0]
            elif found[role] or role != "setting":
                problems.append(f"{role}: several candidates {[c.name for c in found[role]]}" if found[role] else
                                f"{role}: no column found")
        faults = [f for s in STATES if (f := self._auto_intervals(found, s, forms[s], problems)) is not None]
        hint = Hint("columns", _columns_call(found, forms), "replace each <...>")
        if problems:
            note = ("; a state given as speed, angle and spin is named by a mapping {'speed': ..., 'angle': ..., "
                    "'spin': ...}, not a list" if any(forms[s] == "cartesian" and any(found[f"{s}.{c}"] for c in (
                        "speed", "angle")) for s in STATES) else "")
            raise DataError(f"cannot tell which columns hold the bounce data ({'; '.join(problems)}); the file's "
                            f"columns are {self.names}{note}", file=self.file, hints=[hint])
        if faults:
            raise DataError(faults[0], file=self.file, hints=[hint])

    def _auto_intervals(self, found: dict[str, list[Choice]], state: str, form: str, problems: list[str]) -> str | None:
        """Choose one state's interval columns by name; what is wrong with them, if anything. Complete Cartesian
        half-widths are read; polar ones of a Cartesian state (nothing to propagate them through) and a lone spin's
        are ignored with a warning; a polar state's need all three and no Cartesian ones beside them."""
        pi, said = f"{state}_pi", _SAID[state]
        if several := [f"{pi}.{c}: several candidates {[ch.name for ch in found[f'{pi}.{c}']]}"
                       for c in (*COMPONENTS, "speed", "angle") if len(found[f"{pi}.{c}"]) > 1]:
            problems.extend(several)
            return None

        def names(comps: Sequence[str]) -> list[str]:
            return [found[f"{pi}.{c}"][0].name for c in comps if found[f"{pi}.{c}"]]

        cartesian = [c for c in COMPONENTS if found[f"{pi}.{c}"]]
        polar = [c for c in ("speed", "angle") if found[f"{pi}.{c}"]]
        missing = [k for k, c in zip(("speed", "angle", "spin"), POLAR, strict=True) if not found[f"{pi}.{c}"]]
        where = "in the column mapping (columns= in Python, --columns on the command line)"
        if len(cartesian) == 3 and (form == "cartesian" or not polar):
            self.chosen.update({f"{pi}.{c}": found[f"{pi}.{c}"][0] for c in COMPONENTS})
        elif polar and form == "cartesian":  # ignoring them loses the intervals, never gives a wrong number
            warn(f"{self.file}: ignoring the {pi} columns {names((*polar, *cartesian))}: the {said} is read from its "
                 f"Cartesian columns (xdot, ydot, omega), and half-widths of its speed or angle "
                 f"({', '.join(names(polar))}) are propagated only through a polar state; loaded without {said} "
                 "intervals. To use them, name the "
                 f"{said} as speed, angle and spin and {pi!r} as a mapping, or its xdot, ydot, omega half-widths as a "
                 f"list, {where}")
        elif polar and {"xdot", "ydot"} & set(cartesian):
            return (f"the {said} has both Cartesian half-widths {names(('xdot', 'ydot'))} and polar ones "
                    f"{names(polar)}; say which to read ({pi!r} as a list of xdot, ydot, omega or a mapping of "
                    "speed, angle, spin)")
        elif polar and missing:
            return (f"the {said} has polar half-widths {names(POLAR)} but none for its {' and '.join(missing)}: all "
                    "three (speed, angle, spin) are needed to propagate them to xdot, ydot, omega; add the missing "
                    f"column, or name it (or leave {pi!r} out to load without intervals)")
        elif polar:
            self.chosen.update({f"{pi}.{c}": found[f"{pi}.{c}"][0] for c in POLAR})
        elif cartesian:
            which = "xdot, ydot, omega" + ("; or speed, angle, spin" if form == "polar" else "")
            warn(f"{self.file}: ignoring the incomplete {pi} columns {names(COMPONENTS)}; name all three ({which}) "
                 f"{where} to use them")
        return None

    # -- what the chosen columns hold
    def check_absolute_units(self) -> None:
        """Refuse a state or interval column in a relative unit (2 % of 25 m/s read as 2 m/s)."""
        for role, ch in self.chosen.items():
            row_unit = self.t.units.get(ch.name, (None, "header"))
            if role == "setting" or (unit := syn.relative_unit(ch.name, row_unit[0])) is None:
                continue
            state, comp = role.split(".")
            what = _what(f"{state}.{comp}", f"{state}.speed" in self.chosen, asked=True).removeprefix("the ")
            what = what.removesuffix(" half-width")
            where = "header" if syn.split_header(ch.name)[1] is not None else row_unit[1]
            raise DataError(
                f"the {where} gives the {what} half-width in {unit!r}, a relative unit: bouncelab reads half-widths "
                "only in an absolute unit (that of the value or one of its kind); convert the column first, "
                "multiplying each half-width in per cent by its value / 100 (2 % of 25 m/s is 0.5 m/s), and give it "
                "the value's unit"
                if state in PI_STATES else f"the {where} gives the {what} in {unit!r}, a relative unit: a measured "
                f"{what} needs an absolute unit (m/s, rpm, deg...); convert the column, or name the one holding the "
                "value",
                file=self.file, column=ch.name)

    def interval_scales(self, intervals: str | None) -> dict[str, float]:
        """The factor that makes each interval column a 95 % half-width: 1, or Z95 for a standard deviation.
        ``intervals=None`` lets the names say; an ``err``/``unc`` name, which could be either, is refused."""
        scales: dict[str, float] = {}
        unsure: list[str] = []
        meaning = {"pi95": "a 95 % half-width", "sd": "one standard deviation"}
        for role, ch in ((r, ch) for r, ch in self.chosen.items() if "_pi." in r):
            marker = syn.interval_marker(ch.name)
            says = "pi95" if marker in syn.PI95_MARKERS else "sd" if marker in syn.SD_MARKERS else None
            if intervals is not None and says is not None and says != intervals:
                raise DataError(f"the interval columns are said to hold {meaning[intervals]}, but the name of "
                                f"{ch.name!r} ({marker!r}) says it holds {meaning[says]} (rename the column if it "
                                "does not)",
                                file=self.file, column=ch.name, hints=[Hint("intervals", says, "as the name says")])
            if intervals is None and marker in syn.AMBIGUOUS_MARKERS:
                unsure.append(ch.name)
            else:
                scales[role] = Z95 if (intervals or says) == "sd" else 1.0
        if unsure:
            raise DataError(
                f"the interval column{'s' if len(unsure) > 1 else ''} {unsure} may hold one standard deviation or the "
                "half-width of a 95 % interval, and the name does not say which (a standard deviation read as a "
                "half-width would give intervals 1.96 times too narrow)", file=self.file, column=unsure[0],
                hints=[Hint("intervals", "sd", f"standard deviations, multiplied by {Z95:.2f} to 95 % half-widths"),
                       Hint("intervals", "pi95", "95 % half-widths, as a campaign stores them")])
        return scales

    def missing_rows(self, names: Sequence[str]) -> dict[int, tuple[str, Any]]:
        """Rows with a missing cell in one of ``names``: row -> (column, cell) of the first."""
        out: dict[int, tuple[str, Any]] = {}
        for s in (self.frame[n] for n in dict.fromkeys(names) if self.frame[n].dtype.kind not in "iub"):
            bad = s.isna() if s.dtype.kind == "f" else s.map(lambda v: is_empty(v) or str(v).strip().lower() in MISSING)
            for i in np.flatnonzero(bad.to_numpy(dtype=bool)):
                out.setdefault(int(i), (s.name, s.iloc[i]))
        return dict(sorted(out.items()))

    def drop_missing(self, names: Sequence[str]) -> list[int]:
        """Leave out the rows with a missing cell in ``names``, with a warning; the file's data rows dropped."""
        if not (bad := self.missing_rows(names)):
            return []
        if len(bad) == len(self.frame):
            raise DataError(f"every row has a missing value (e.g. column {bad[0][0]!r}, row 1): nothing is left to "
                            "load", file=self.file)

        def show(i: int, name: str, v: Any) -> str:
            where = (f"{self.t.where(i, name)}: " if self.t.where else "" if self.t.labels is None else
                     f"row label {self.t.labels[i]!r}: ")
            what = "NaN" if isinstance(v, float) else "empty" if is_empty(v) else repr(v.strip())
            return f"row {i + 1} ({where}{name!r} is {what})"

        warn(f"{self.file}: dropped {len(bad)} incomplete row(s) of {len(self.frame)}: "
             + "; ".join(show(i, *cell) for i, cell in bad.items()), DroppedRowsWarning)
        keep = np.setdiff1d(np.arange(len(self.frame)), list(bad))
        self.frame, self.rows = self.frame.iloc[keep], self.rows[keep]
        return list(bad)

    def decimal_convention(self, names: Sequence[str]) -> None:
        """Whether a semicolon, tab or blank-separated table writes decimals with a comma (``15,2``), refusing what
        does not say: ``3.000`` then (3000 or 3.0?), a file mixing ``15,2`` and ``15.2``, and ``3,000`` (or
        ``1.500`` in a semicolon file) with no other decimal."""
        if not self.t.decimal_comma:
            return
        comma = dot = None  # the first evidence: (row, column, text)
        grouped = []
        for name in names:
            for i, t in enumerate(self.frame[name].tolist()):
                if not isinstance(t, str) or not (t := t.strip()) or ("," not in t and "." not in t):
                    continue
                if re.fullmatch(r"[+-]?[1-9]\d{0,2}([.,]\d{3})+", t):  # 0.250 cannot be thousands
                    grouped.append((i, name, t))
                elif re.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", t):
                    comma = (i, name, t) if comma is None or i < comma[0] else comma
                elif "." in t and syn.parse_number(t) is not None:
                    dot = (i, name, t) if dot is None or i < dot[0] else dot
        if comma and dot:
            (i, name, t), first = max(comma, dot), min(comma, dot)
            raise self.err(f"{t!r} writes its decimals differently from {first[2]!r} (column {first[1]!r}, row "
                           f"{int(self.rows[first[0]]) + 1}); write every number with the same decimal mark", name, i)
        self.t.decimal_comma = comma is not None
        for i, name, t in sorted(grouped):
            if (comma is not None and "." in t) or (dot is not None and "," in t):
                why = (f"the file writes decimals with a {'comma' if comma else 'dot'} ({(comma or dot)[2]!r}), so the "
                       f"{'dot' if comma else 'comma'} is a thousands separator or a slip")
            elif comma is None and dot is None and ("," in t or self.t.delimiter == ";"):  # a semicolon file: a
                why = (f"nothing else in the file says whether the {'comma' if ',' in t else 'dot'} is a decimal mark "
                       "or a thousands separator")  # decimal-comma locale's export, where 1.500 may well be 1500
            else:
                continue
            raise self.err(f"{t!r} is ambiguous: {why}; write it without the separator "
                           f"({t.replace('.', '').replace(',', '')}) or with the file's decimal mark", name, i)

    def numbers(self, name: str) -> tuple[np.ndarray, DataError | None]:
        """A column as floats, and the error of its first bad cell (or None)."""
        s = self.frame[name]
        if s.dtype.kind in "iuf" and pd.api.types.is_numeric_dtype(s):
            vals = s.to_numpy() if s.dtype == np.float64 else s.to_numpy(dtype=float, na_value=np.nan)
            if self.t.text_cells and np.isnan(vals).any():  # a missing cell, as in a file (an array's NaN: later)
                i = int(np.flatnonzero(np.isnan(vals))[0])
                said = f"missing value {self.cell(name, i)!r}" if self.t.text is not None else "missing value (NaN)"
                return vals, self.err(f"{said}; every bounce needs a value", name, i, [_DROP])
            return vals, None
        cells = s.tolist()
        if not self.t.decimal_comma and cells and all(isinstance(v, str) and "_" not in v for v in cells):
            try:  # numpy's correctly rounded parse of plain decimal text; anything else is parsed cell by cell
                if np.isfinite(fast := np.array(cells, dtype=float)).all():
                    return fast, None
            except (ValueError, OverflowError):
                pass
        out = np.empty(len(cells))
        for i, v in enumerate(cells):
            if self.t.text_cells and is_empty(v):
                return out, self.err("empty cell; every bounce needs a value", name, i, [_DROP])
            if isinstance(v, str) and v.strip().lower() in MISSING:
                return out, self.err(f"missing value {v.strip()!r}; every bounce needs a value", name, i, [_DROP])
            x = syn.parse_number(v, decimal_comma=self.t.decimal_comma) if isinstance(v, str) else float(v) if (
                isinstance(v, int | float | np.number) and not isinstance(v, bool | np.bool_)) else None
            if x is None:
                return out, self.err(f"non-numeric value {v!r}", name, i)
            out[i] = x
        return out, None

    def setting(self, name: str) -> np.ndarray:
        """Setting labels as written: whole numbers as int64 (exact; text beyond int64), else strings."""
        s = self.frame[name]
        if s.dtype.kind in "iu" and not s.hasnans:  # whole numbers read as integers are what their text says
            if s.dtype.kind == "u" and len(s) and int(s.max()) > _INT64_MAX:
                return np.array([str(int(v)) for v in s])
            return s.to_numpy().astype(np.int64)
        labels: list[Any] = []
        for i, v in enumerate([self.t.text(name)[r] for r in self.rows] if self.t.text is not None else s.tolist()):
            if is_empty(v) or str(v).strip().lower() in MISSING or (isinstance(v, float) and not math.isfinite(v)):
                shown = "empty" if is_empty(v) and not isinstance(v, float) else repr(
                    v.strip() if isinstance(v, str) else v)
                raise self.err(f"missing setting label ({shown}); every bounce needs one", name, i, [_DROP])
            if isinstance(v, str) and (x := syn.parse_number(v)) is not None and not math.isfinite(x):
                raise self.err(f"setting label {v.strip()!r} is not a finite number nor a name; every bounce needs a "
                               "label", name, i)
            labels.append(v.strip() if isinstance(v, str) else v)
        numbers = [_label_number(v) for v in labels]
        if all(isinstance(x, int) for x in numbers):  # beyond int64: kept exact as text
            fits = all(abs(x) <= _INT64_MAX for x in numbers)
            return np.array(numbers, dtype=np.int64) if fits else np.array([str(x) for x in numbers])
        if all(isinstance(x, float) for x in numbers):
            return np.array(numbers, dtype=float)
        return np.array([str(int(v)) if isinstance(v, float) and v.is_integer() else str(v) for v in labels])

    def column_unit(self, role: str, given: dict[str, str]) -> tuple[str, str]:
        """The unit of a chosen column and where it came from (``units=``, header, assumed)."""
        kind, ch = KINDS[role.split(".")[1]], self.chosen[role]
        text, where = self.unit_text(ch.name)
        known = {} if text is None else syn.unit_of(text)
        header = known.get(kind)
        if text is not None and header is None and (known or not (ch.whole and where == "header")):
            what = f"{_a(next(iter(known)))} unit, not {_a(kind)} unit" if known else "not a known unit"
            try:
                units.canonical_unit(text, kind)
            except DataError as exc:
                raise DataError(f"the {where} gives the unit {text!r}, {what}; {exc.message}", file=self.file,
                                column=ch.name) from None
        if kind in given and header is not None and header != given[kind]:
            raise DataError(f"the header says {header} but the {kind} unit given is {given[kind]}; remove one of them "
                            "or make them agree", file=self.file, column=ch.name,
                            hints=[Hint("units", {kind: header}, "as the header says")])
        if kind in given:
            return given[kind], "units="
        return (header, "header") if header is not None else (_ASSUMED[kind], "assumed")

    def convert(self, role: str, unit: str) -> np.ndarray:
        kind, v = KINDS[role.split(".")[1]], self.parsed[role]
        if kind == "velocity":
            return units.velocity_to_scaled(v, unit, radius_m=self.radius)
        return units.spin_to_scaled(v, unit) if kind == "spin" else np.rad2deg(v) if unit == "rad" else v  # degrees

    def polar_state(self, state: str) -> None:
        """A state given as speed, angle and spin to xdot, ydot (in place), refusing what is not a bounce: speeds
        >= 0, the ball moving in +x, the angle positive below the horizontal for a landing, above it for a lift-off."""
        sp, an, om = (f"{state}.{c}" for c in POLAR)
        speed, angle, said = self.parsed[sp], self.scaled[an], _SAID[state]
        if (infinite := ~np.isfinite(np.column_stack([speed, self.parsed[an], self.parsed[om]]))).any():
            i, k = (int(v) for v in np.argwhere(infinite)[0])
            role = (sp, an, om)[k]
            cell = self.cell(self.col(role), i, self.unit_of[role][0])
            raise self.err(f"{said} {('speed', 'angle', 'spin')[k]} {cell} is not a finite number; every bounce "
                           "needs a finite speed, angle and spin", self.col(role), i)
        if self.unit_of[an][1] == "assumed" and len(angle) and np.max(np.abs(angle)) <= _RADIAN_LIKE:
            raise DataError(f"the file gives no unit for the {said} angles and every one is within "
                            f"+-{_RADIAN_LIKE:.2f}: read as degrees (the default) they are implausibly flat, they look "
                            f"like radians; say which (a unit in the header says it too: '{self.col(an)} (rad)' "
                            "or '(deg)')", file=self.file,
                            column=self.col(an), hints=[Hint("units", {"angle": "rad"})])
        landing = state == "landing"
        bad_speed = ~(speed > 0) if landing else ~(speed >= 0)
        bad_angle = ~((angle > 0) & (angle <= 90)) if landing else ~((angle >= 0) & (angle < 180))
        if (rows := np.flatnonzero(bad_speed | bad_angle)).size:
            i = int(rows[0])
            if bad_speed[i]:
                raise self.err(f"{said} speed {self.cell(self.col(sp), i, self.unit_of[sp][0])}: a speed must be "
                               f"{'positive' if landing else 'zero or positive'}; polar files give speeds >= 0 with "
                               "the ball moving in +x (the angle gives the direction)", self.col(sp), i)
            raise self.err(f"{said} angle {self.cell(self.col(an), i, self.unit_of[an][0])} is not plausible: " + (
                "a landing angle is positive below the horizontal, in (0, 90] degrees for a ball coming down in +x (a "
                "file that measures it the other way needs the column negated)" if landing else "a lift-off angle is "
                "positive above the horizontal, in [0, 180) degrees (0 to 90 going on in +x, above 90 going back; a "
                "negative one would send the ball into the ground)"), self.col(an), i)
        cart = units.state_from_polar(np.column_stack([speed, angle, self.parsed[om]]), kind=state,
                                      speed_unit=self.unit_of[sp][0], spin_unit=self.unit_of[om][0],
                                      radius_m=self.radius)
        a = np.deg2rad(angle)  # the components in the file's speed unit, for the unit checks and their messages
        for comp, scaled, parsed in (("xdot", cart[:, 0], speed * np.cos(a)),
                                     ("ydot", cart[:, 1], (-1.0 if landing else 1.0) * speed * np.sin(a))):
            self.scaled[f"{state}.{comp}"], self.parsed[f"{state}.{comp}"] = scaled, parsed
            self.unit_of[f"{state}.{comp}"], self.chosen[f"{state}.{comp}"] = self.unit_of[sp], self.chosen[sp]

    def polar_intervals(self, state: str, scales: Mapping[str, float]) -> None:
        """Propagate a polar state's speed, angle and spin half-widths to xdot, ydot, omega ones (in place), to
        first order with independent errors; checked as written first (the propagation squares a sign away)."""
        pi = f"{state}_pi"
        roles = [f"{pi}.{c}" for c in POLAR]
        raw = np.column_stack([self.parsed[r] for r in roles])
        bad = ~(np.isfinite(raw) & (raw >= 0))
        bad[:, 1] |= self.plausible is not None and self.scaled[roles[1]] > _MAX_ANGLE_HW
        if bad.any():
            i, k = (int(v) for v in np.argwhere(bad)[0])
            why = "is negative" if raw[i, k] < 0 else "is not a finite number" if not np.isfinite(raw[i, k]) else (
                f"is wider than any plausible angle half-width ({_MAX_ANGLE_HW:g} deg spans every direction a landing "
                "can come from): check the column's unit")
            raise self.err(f"{self.interval_cell(roles[k], i, scales)} {why}", self.col(roles[k]), i)
        polar, hws = (np.column_stack([self.scaled[f"{s}.{c}"] for c in POLAR]) for s in (state, pi))

        def propagate(p: np.ndarray, h: np.ndarray) -> np.ndarray:
            return units.polar_halfwidths_to_cartesian(p, h, kind=state, speed_unit="radius/s", spin_unit="rad/s",
                                                       radius_m=self.radius)

        try:
            hw = propagate(polar, hws)
        except DataError as exc:  # a number too large for floats once scaled: name the row
            for i in range(len(polar)):
                try:
                    propagate(polar[i], hws[i])
                except DataError as row_exc:
                    cells = ", ".join(self.cell(self.col(r), i, self.unit_of[r][0]) for r in roles)
                    raise self.err(f"the {_SAID[state]} half-widths {cells} cannot be propagated: {row_exc.message}",
                                   self.col(roles[0]), i) from None
            raise exc from None  # pragma: no cover - a row that fails alone
        for k, comp in enumerate(COMPONENTS):
            self.scaled[f"{pi}.{comp}"] = hw[:, k]
        for comp in ("xdot", "ydot"):  # so that a later message about them names a column of the file
            self.chosen[f"{pi}.{comp}"] = self.chosen[f"{pi}.speed"]
            self.unit_of[f"{pi}.{comp}"] = self.unit_of[f"{pi}.speed"]

    def interval_cell(self, role: str, i: int, scales: Mapping[str, float]) -> str:
        """An interval cell for messages, quoting the number that was checked (a standard deviation x 1.96)."""
        unit = self.unit_of[role][0] if role in self.unit_of else None
        cell, scale = self.cell(self.col(role), i, unit), scales.get(role, 1.0)
        return f"prediction-interval half-width {cell}" if scale == 1.0 else (
            f"standard deviation {cell} (x {scale:.2f}: {self.parsed[role][i] * scale:.6g}"
            f"{'' if unit is None else ' ' + unit} as a 95 % half-width)")

    def check_landing_sign(self) -> None:
        """A Cartesian landing going up, quoted as written (as_states would quote radii/s)."""
        if "landing.speed" in self.chosen:
            return  # a polar landing is checked by its angle
        up = np.flatnonzero(self.scaled["landing.ydot"] >= 0)
        if up.size and np.isfinite([self.scaled[f"landing.{c}"][: up[0] + 1] for c in COMPONENTS]).all():
            i, name = int(up[0]), self.col("landing.ydot")
            raise self.err("landing ydot must be negative (y points up, a landing moves down); the file gives "
                           f"{self.cell(name, i, self.unit_of['landing.ydot'][0])} (a file whose y points down needs "
                           "the column negated)", name, i)

    def states(self, state: str, landing: bool = False) -> np.ndarray:
        """A state's (n, 3) scaled array, validated, errors named in the file's terms."""
        try:
            return as_states(np.column_stack([self.scaled[f"{state}.{c}"] for c in COMPONENTS]), state,
                             landing=landing, file=self.file)[0]
        except DataError as exc:
            ch = self.chosen.get(exc.column or "") or self.chosen.get(f"{exc.column}.xdot")
            raise self.err(exc.message, exc.column if ch is None else ch.name,
                           None if exc.row is None else exc.row - 1) from None

    def check_plausible(self, arrays: tuple[np.ndarray, np.ndarray]) -> None:
        """Refuse numbers whose unit is not given and not certain, and numbers only a wrong unit makes (``arrays``:
        the scaled landings and lift-offs)."""
        roles = [f"{s}.{c}" for s in STATES for c in COMPONENTS]
        for kind in ("velocity", "spin"):
            assumed = [r for r in roles if KINDS[r.split(".")[1]] == kind and self.unit_of[r][1] == "assumed"]
            if not assumed:
                continue

            def convert(factor: float, assumed: list[str] = assumed) -> tuple[np.ndarray, np.ndarray]:
                arrs = {r: self.parsed[r] * factor if r in assumed else self.scaled[r] for r in roles}
                return tuple(np.column_stack([arrs[f"{s}.{c}"] for c in COMPONENTS]) for s in STATES)

            verdicts = plausibility.plausible_units(kind, convert, radius_m=self.radius, ranges=self.plausible)
            default = plausibility.CANDIDATE_UNITS[kind][0]
            if (fits := [u for u, why in verdicts.items() if why is None]) == [default]:
                continue
            names = list(dict.fromkeys(self.col(r) for r in assumed))  # a polar speed backs xdot and ydot
            why = verdicts[default]
            said = f"the file gives no {kind} unit for {', '.join(map(repr, names))}"
            unit = "m/s" if kind == "velocity" else "rpm"
            header = f"a unit in the column header says it too, e.g. '{names[0]} [{unit}]'"
            msg = (f"{said}, and its numbers are plausible in {', '.join(fits[:-1])} and in {fits[-1]}"
                   + (f" (not in {default}: {why.reason})" if why is not None else "")
                   + f"; bouncelab does not guess ({header})" if len(fits) > 1 else
                   f"{said}; read as {default}, {why.reason}; the numbers look like {fits[0]} ({header})" if fits else
                   f"{said}; read as {default}, {why.reason}, and they are not plausible in "
                   f"{', '.join(plausibility.CANDIDATE_UNITS[kind])} either: check the column, or declare its unit "
                   "and widen the plausible ranges")
            hints = [Hint("units", {kind: u}) for u in fits or [default]] + ([] if fits else [_WIDEN])
            if why is not None and why.row is not None:
                raise self.err(msg, self.col(f"{why.state}.{why.component}"), why.row, hints)
            raise DataError(msg, file=self.file, column=names[0] if len(names) == 1 else None, hints=hints)
        if (why := plausibility.implausibility(*arrays, radius_m=self.radius, ranges=self.plausible)) is not None:
            role = f"{why.state}.{why.component}"
            unit, origin = self.unit_of[role]
            said = self.cell(self.col(role), why.row, unit) if why.row is not None else f"in {unit}"
            others = [Hint("units", {why.kind: u}) for u in plausibility.CANDIDATE_UNITS[why.kind] if u != unit]
            raise self.err(f"{said} (unit from {origin}): {why.reason}; the {why.kind} unit is wrong (a unit in the "
                           "column header also says it), or the values need wider plausible ranges", self.col(role),
                           why.row, [*others, _WIDEN])


def _what(role: str, polar: bool = False, asked: bool = False) -> str:
    """What a role is, in words: ``the landing speed``, ``a half-width of the landing spin (a prediction interval)``;
    ``asked``: ``the landing omega half-width`` (the spin of a polar state)."""
    state, comp = role.split(".")
    what = f"{_SAID[state.removesuffix('_pi')]} {'spin' if comp == 'omega' and (polar or not asked) else comp}"
    if asked:
        return f"the {what} half-width" if "_pi." in role else f"the {what}"
    return f"a half-width of the {what} (a prediction interval)" if "_pi." in role else f"the {what} itself"


def _same_unit(a: str, b: str) -> bool:
    return a.strip().lower() == b.strip().lower() or (bool(syn.unit_of(a)) and syn.unit_of(a) == syn.unit_of(b))


def _a(word: str) -> str:
    return ("an " if word[:1].lower() in "aeiou" else "a ") + word


def _state_roles(names: Any) -> dict[str, str] | None:
    """Component -> requested name for one entry of columns=: a list (xdot, ydot, omega), or a mapping with the keys
    xdot, ydot, omega or speed, angle, spin (or omega)."""
    if isinstance(names, Mapping):
        ok = set(map(str, names)) in ({"xdot", "ydot", "omega"}, {"speed", "angle", "spin"},
                                      {"speed", "angle", "omega"})
        return {("omega" if k == "spin" else str(k)): str(v) for k, v in names.items()} if ok else None
    if isinstance(names, str) or not isinstance(names, Sequence) or len(names) != 3:
        return None
    return dict(zip(COMPONENTS, map(str, names), strict=True))


def _form(found: dict[str, list[Choice]], state: str) -> str:
    """``"polar"`` if a state has speed or angle columns and no xdot or ydot ones, else ``"cartesian"``."""
    polar = any(found[f"{state}.{c}"] for c in ("speed", "angle"))
    return "polar" if polar and not any(found[f"{state}.{c}"] for c in ("xdot", "ydot")) else "cartesian"


def _columns_call(found: dict[str, list[Choice]], forms: dict[str, str]) -> dict[str, Any]:
    """The columns= argument naming what was found, with ``<...>`` for what was not or is ambiguous."""
    def pick(role: str, label: str | None = None) -> str:
        cands = [c.name for c in found[role]]
        return cands[0] if len(cands) == 1 else f"<one of {', '.join(cands)}>" if cands else (
            f"<{label or role.replace('.', ' ')} column>")

    def polar(state: str) -> dict[str, str]:
        return {k: pick(f"{state}.{r}", f"{state} {k}") for k, r in zip(("speed", "angle", "spin"), POLAR, strict=True)}

    out: dict[str, Any] = {s: polar(s) if forms[s] == "polar" else [pick(f"{s}.{c}") for c in COMPONENTS]
                           for s in STATES}
    out |= {"setting": pick("setting")} if found["setting"] else {}
    for s, pi in zip(STATES, PI_STATES, strict=True):
        if forms[s] == "polar" and any(found[f"{pi}.{c}"] for c in ("speed", "angle")):
            out[pi] = polar(pi)
        elif any(found[f"{pi}.{c}"] for c in COMPONENTS):
            out[pi] = [pick(f"{pi}.{c}") for c in COMPONENTS]
    return out


def _label_number(v: Any) -> int | float | None:
    """A setting label as an exact int, a float (non-whole, up to 15 significant digits), or None."""
    if isinstance(v, bool | np.bool_) or not isinstance(v, int | float | np.number | str):
        return None
    text = v.strip().replace("\u2212", "-") if isinstance(v, str) else ""
    if isinstance(v, int | np.integer) or re.fullmatch(r"[+-]?\d+", text):
        return int(text or v)  # exact, however long ("01" is 1)
    x = float(v) if not isinstance(v, str) else syn.parse_number(v)
    if x is None or not math.isfinite(x):
        return None
    if x.is_integer():
        return int(x) if abs(x) < 2.0**53 else None
    digits = len(re.sub(r"[^0-9]", "", v.lower().split("e")[0]).strip("0")) if isinstance(v, str) else 0
    return x if digits <= 15 else None


def _describe_units(unit_of: dict[str, tuple[str, str]], chosen: dict[str, Choice]) -> str:
    parts = []
    for kind in ("velocity", "spin", "angle"):
        if not (roles := [r for r in unit_of if KINDS[r.split(".")[1]] == kind]):
            continue  # no angle in a Cartesian file
        if len({unit_of[r][0] for r in roles}) == 1:
            unit, origin = unit_of[roles[0]]
            parts.append(f"{kind} {unit}" + (" (assumed)" if origin == "assumed" else ""))
        else:
            parts.append(f"{kind} " + ", ".join(f"{chosen[r].name}: {unit_of[r][0]}" for r in roles))
    return ", ".join(parts)


def campaign_from_table(t: Table, *, columns: Any, given: dict[str, str], campaign: str, surface: str, source: str,
                        ball_radius_m: float, plausible=plausibility.PLAUSIBLE_RANGES, missing: str = "raise",
                        intervals: str | None = None) -> xr.Dataset:
    """The campaign a table holds (see :func:`bouncelab.data.io.load_campaign`)."""
    r = Reading(t, ball_radius_m, plausible)
    if len(r.frame) == 0:
        raise DataError("the file has a header but no data rows", file=t.file)
    if columns is None:
        r.select_auto()
    else:
        r.select_explicit(columns)
    r.check_absolute_units()
    scales = r.interval_scales(intervals)
    used: dict[str, str] = {}
    for role, ch in r.chosen.items():
        if used.setdefault(ch.name, role) != role:
            raise DataError(f"the same column is asked for as {used[ch.name]} and as {role}", file=t.file,
                            column=ch.name)
    lengths = {n: t.lengths[n] for n in used} if t.lengths is not None else {}
    if len(set(lengths.values())) > 1:
        raise DataError(f"the columns have different lengths {lengths}; one value per bounce in each", file=t.file,
                        column=max(lengths, key=lambda k: lengths[k]))
    dropped = r.drop_missing(list(used)) if missing == "drop" else []
    r.decimal_convention([ch.name for role, ch in r.chosen.items() if role != "setting"])
    errors, setting = [], None
    for role, ch in r.chosen.items():
        if role != "setting":
            r.parsed[role], error = r.numbers(ch.name)
            errors += [error] if error is not None else []
    try:
        setting = r.setting(r.col("setting")) if "setting" in r.chosen else None
    except DataError as exc:
        errors.append(exc)
    if errors:  # the first bad cell in row order
        raise min(errors, key=lambda e: e.row or 0)
    for role in sorted(r.parsed, key=lambda role: "_pi" in role):  # states first: their intervals follow them
        unit, origin = r.column_unit(role, given)
        state_role = role.replace("_pi.", ".")
        if state_role != role and state_role not in r.unit_of and state_role.endswith(("xdot", "ydot")):
            state_role = state_role.rsplit(".", 1)[0] + ".speed"  # the Cartesian interval of a polar state
        if origin == "assumed" and state_role != role and r.unit_of[state_role][1] != "assumed":
            unit, origin = r.unit_of[state_role][0], "its state column"  # a half-width has its value's unit
        r.unit_of[role] = (unit, origin)
        r.scaled[role] = r.convert(role, unit) * scales.get(role, 1.0)  # standard deviations -> 95 % half-widths
    attrs: dict[str, Any] = {"source_units": _describe_units(r.unit_of, r.chosen)}
    read: dict[str, set[str]] = {}
    for role, factor in scales.items():
        read.setdefault(role.split("_pi.")[0], set()).add("95 % half-widths" if factor == 1 else
                                                          "standard deviations x 1.96")
    if read:
        attrs["interval_source"] = ", ".join(f"{s} " + " and ".join(sorted(read[s])) for s in STATES if s in read)
    if polar := [s for s in STATES if f"{s}.speed" in r.chosen]:
        attrs["source_form"] = ", ".join(f"{s} {'polar' if s in polar else 'cartesian'}" for s in STATES)
    for state in polar:
        r.polar_state(state)
    if polar_pi := [s for s in STATES if f"{s}_pi.speed" in r.chosen]:  # derived, not measured, half-widths: say so
        attrs["interval_form"] = ", ".join(
            f"{s} " + ("polar (speed, angle and spin half-widths propagated to first order, speed and angle errors "
                       "independent)" if s in polar_pi else "cartesian") for s in STATES if f"{s}_pi.omega" in r.chosen)
    for state in polar_pi:
        r.polar_intervals(state, scales)
    r.check_landing_sign()
    states = {s: r.states(s, landing=s == "landing") for s in (*STATES, *PI_STATES) if f"{s}.xdot" in r.scaled}
    for state in (s for s in PI_STATES if s in states):
        arr, roles = states[state], [f"{state}.{c}" for c in COMPONENTS]
        if (arr < 0).any():
            i, k = (int(v) for v in np.argwhere(arr < 0)[0])
            raise r.err(f"prediction-interval half-width {r.cell(r.col(roles[k]), i)} is negative", r.col(roles[k]), i)
        limit = np.array([plausible.max_speed / ball_radius_m] * 2 + [plausible.max_spin * 2 * math.pi / 60])
        if (arr > limit).any():  # wider than any plausible value: a unit mistake, not an uncertainty
            i, k = (int(v) for v in np.argwhere(arr > limit)[0])
            what = f"{plausible.max_speed:g} m/s" if k < 2 else f"{plausible.max_spin:g} rpm"
            if k < 2 and f"{state[:-3]}.speed" in r.chosen:
                raise _propagated_too_wide(r, state, COMPONENTS[k], i, what)
            raise r.err(f"{r.interval_cell(roles[k], i, scales)} is wider than any plausible value ({what}): check the "
                        "column's unit", r.col(roles[k]), i)
    r.check_plausible((states["landing"], states["liftoff"]))
    if missing == "drop":
        attrs["dropped_rows"] = [i + 1 for i in dropped]  # the file's data rows, 1-based as in errors
    return make_campaign(states["landing"], states["liftoff"], setting=setting, landing_pi=states.get("landing_pi"),
                         liftoff_pi=states.get("liftoff_pi"), campaign=campaign, surface=surface,
                         ball_radius_m=ball_radius_m, source=source, data_kind="measured", attrs=attrs,
                         plausible=None)  # checked above, with the file's units


def _propagated_too_wide(r: Reading, pi: str, comp: str, i: int, limit: str) -> DataError:
    """A propagated xdot or ydot half-width beyond the plausible, blamed on the column whose term dominates."""
    state = pi.removesuffix("_pi")
    v, a = r.scaled[f"{state}.speed"][i], np.deg2rad(r.scaled[f"{state}.angle"][i])
    h_v, h_a = r.scaled[f"{pi}.speed"][i], np.deg2rad(r.scaled[f"{pi}.angle"][i])
    by_speed, by_angle = (abs(math.cos(a)) * h_v, v * abs(math.sin(a)) * h_a) if comp == "xdot" else (
        abs(math.sin(a)) * h_v, v * abs(math.cos(a)) * h_a)  # the two terms (units.polar_halfwidths_to_cartesian)
    culprit, unit = r.col(f"{pi}.speed" if by_speed >= by_angle else f"{pi}.angle"), r.unit_of[f"{pi}.speed"][0]
    value = units.velocity_from_scaled(r.scaled[f"{pi}.{comp}"][i], unit, radius_m=r.radius)
    cell = {role: r.cell(r.col(role), i, r.unit_of[role][0]) for role in (f"{pi}.speed", f"{pi}.angle",
                                                                          f"{state}.speed", f"{state}.angle")}
    return r.err(f"the {_SAID[state]} {comp} half-width propagated from the speed half-width {cell[f'{pi}.speed']} and "
                 f"the angle half-width {cell[f'{pi}.angle']} (at speed {cell[f'{state}.speed']}, angle "
                 f"{cell[f'{state}.angle']}) is {value:.4g} {unit}, wider than any plausible value ({limit}): check "
                 f"the unit of {culprit!r}", culprit, i)


def campaign_from_netcdf(ds: xr.Dataset, *, file: str, source: str, columns: Any, given: Any, campaign: str | None,
                         surface: str | None, ball_radius_m: float, plausible=plausibility.PLAUSIBLE_RANGES,
                         intervals: str | None = None) -> xr.Dataset:
    """A campaign file written by save_campaign: in scaled units, loaded as it is."""
    if columns is not None or given is not None or intervals is not None:
        raise DataError("this is a bouncelab campaign file (scaled units, named variables, 95 % half-widths): it takes "
                        "no column mapping, no units and no interval kind", file=file)
    stored = ds.attrs.get("ball_radius_m")
    if stored is not None and ball_radius_m != BALL_RADIUS_M and float(stored) != float(ball_radius_m):
        raise DataError(f"the campaign was scaled with a ball radius of {float(stored)!r} m, not {ball_radius_m!r}; a "
                        "campaign file cannot be rescaled on loading", file=file)
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        if var in ds.variables and str(ds[var].attrs.get("units", "")).strip().lower() not in ("scaled", ""):
            raise DataError(f"the variable {var!r} says units={ds[var].attrs['units']!r}, but a campaign file holds "
                            "scaled units (radii/s and rad/s, units='scaled'); convert it with "
                            "bouncelab.core.units.to_scaled and save it with save_campaign, or rename the variables to "
                            "load the file as a table", file=file, column=var)
    if "setting" in ds.data_vars:  # a setting stored as a variable is still the setting
        ds = ds.set_coords("setting")
    if "setting" in ds.coords and ds["setting"].attrs.get("bouncelab_dtype") == "int64":
        try:  # save_campaign's netCDF-3 spelling of int64 settings
            labels = np.array([int(str(v)) for v in ds["setting"].values], dtype=np.int64)
        except (ValueError, OverflowError):
            raise DataError("the setting labels marked int64 are not all integers", file=file,
                            column="setting") from None
        ds = ds.assign_coords(setting=("bounce", labels, {k: v for k, v in ds["setting"].attrs.items()
                                                           if k != "bouncelab_dtype"}))
    attrs = dict(ds.attrs)  # in their stored order
    attrs.setdefault("data_kind", "measured")
    attrs.setdefault("source", source)
    out = validate_campaign(ds.assign_attrs(attrs), file=file)
    radius = float(out.attrs.get("ball_radius_m", BALL_RADIUS_M))
    p0, pf = out["landing"].values, out["liftoff"].values
    if (why := plausibility.implausibility(p0, pf, radius_m=radius, ranges=plausible)) is not None:
        raise DataError(f"{why.state} {why.component} of bounce {why.row}: {why.reason}; the file is not in scaled "
                        "units (radii/s, rad/s) as a campaign file must be", file=file, column=why.state,
                        row=None if why.row is None else why.row + 1, hints=[_WIDEN])
    # and the lower limits: all spins tiny, landings far too slow (a damaged file, or m/s)
    exc = plausibility.scaled_units_error(p0, pf, radius_m=radius, ranges=plausible)
    if exc is not None:  # a campaign file holds scaled units: no unit to declare, only wider ranges
        raise DataError(f"{exc.message}; a campaign file holds scaled units (radii/s, rad/s)", file=file,
                        column=exc.column, row=exc.row, hints=[h for h in exc.hints if h.option == "plausible"])
    out.attrs.update({k: str(v) for k, v in (("campaign", campaign), ("surface", surface)) if v is not None})
    return out

