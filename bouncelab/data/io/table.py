"""The table every reader returns (the file's columns of raw cells, their units and where each
data row is in the file) and turning it into a campaign: parse the cells, convert to scaled units
and validate, with every error located in the file.
"""

from __future__ import annotations

import importlib.util
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.data.campaign import make_campaign
from bouncelab.data.io.columns import (
    _PI_STATES,
    _ROLE_KINDS,
    _STATES,
    _column_unit,
    _describe_units,
    _normalize,
    _select_auto,
    _select_explicit,
    _split_header,
    _unit_of,
)
from bouncelab.data.plausibility import (
    CANDIDATE_UNITS,
    PLAUSIBLE_RANGES,
    PlausibleRanges,
    declare_units_hint,
    implausibility,
    plausible_units,
)
from bouncelab.data.units import COMPONENTS, spin_to_scaled, velocity_to_scaled
from bouncelab.data.validation import as_states
from bouncelab.errors import DataError


def _module_available(name: str) -> bool:
    return importlib.util.find_spec(name) is not None


@dataclass
class _Column:
    name: str  # as spelled in the file
    values: Any  # list of raw cells, or a 1-D ndarray
    unit_text: str | None = None  # unit from the header suffix or a units row
    unit_in_header: bool = False
    unit_where: str = ""  # where the unit was read, when not the header or a units row
    text: Callable[[], list[str]] | None = None  # cells as written, of a column read in bulk (fastcsv)

    @property
    def full_key(self) -> str:
        return _normalize(self.name)

    @property
    def base_key(self) -> str:
        return _normalize(_split_header(self.name)[0])


@dataclass
class _Table:
    file: str
    columns: list[_Column]
    n_rows: int
    text_cells: bool  # raw cells (text/Excel): "" and NaN are empty cells
    locate: Callable[[int, str], str] | None = None  # row index, column -> "line 5"
    offset: int = 0  # rows consumed by a units row
    decimal_comma: bool = False

    def where(self, index: int, column: str) -> str:
        if self.locate is None:
            return ""
        return f" ({self.locate(index + self.offset, column)})"


def _err(table: _Table, message: str, column: str | None = None, index: int | None = None) -> DataError:
    """A DataError at data row ``index`` (0-based) of ``column``."""
    if index is None:
        return DataError(message, file=table.file, column=column)
    return DataError(message + table.where(index, column or ""), file=table.file, column=column, row=index + 1)


def _finish_table(
    file: str,
    names: list[str],
    rows: list[list[Any]],
    *,
    locate: Callable[[int, str], str],
    blank: Callable[[Any], bool],
    strict_width: bool,
    decimal_comma: bool = False,
) -> _Table:
    """Build a table from a header and rows of cells; checks duplicates and a units row."""
    seen: dict[str, int] = {}
    for j, name in enumerate(names):
        if not name:
            continue
        if name in seen:
            raise DataError(
                f"the header names column {name!r} twice (columns {seen[name] + 1} and {j + 1}); "
                "rename one of them", file=file, column=name,
            )
        seen[name] = j
    table = _Table(file, [], 0, True, locate, 0, decimal_comma)
    units_row: list[str | None] = [None] * len(names)
    if rows and _is_units_row(rows[0][: len(names)], blank):
        cells = [None if blank(c) else str(c).strip().strip("[](){}").strip() for c in rows[0]]
        units_row = (cells + [None] * len(names))[: len(names)]
        rows = rows[1:]
        table.offset = 1
    if strict_width:
        for i, r in enumerate(rows):
            if any(not blank(c) for c in r[len(names):]):
                raise _err(table, f"the row has {len(r)} values but the header names {len(names)} columns",
                           None, i)
    for j, name in enumerate(names):
        if not name:
            continue
        unit = _split_header(name)[1]
        in_header = unit is not None
        if in_header and units_row[j] and not _same_unit(unit, units_row[j]):
            raise DataError(
                f"the header gives the unit {unit!r} but the units row under it says {units_row[j]!r}; "
                "make them agree or remove one", file=file, column=name,
            )
        if unit is None and units_row[j]:
            unit = units_row[j]
        values = [r[j] if j < len(r) else "" for r in rows]
        table.columns.append(_Column(name, values, unit, in_header))
    table.n_rows = len(rows)
    return table


def _same_unit(a: str, b: str) -> bool:
    ua, ub = _unit_of(a), _unit_of(b)
    return a.strip().lower() == b.strip().lower() or (bool(ua) and ua == ub)


def _is_units_row(cells: Sequence[Any], blank: Callable[[Any], bool]) -> bool:
    texts = [str(c).strip().strip("[](){}").strip() for c in cells if not blank(c)]
    if not texts or any(_parse_number(t) is not None for t in texts):
        return False
    return sum(bool(_unit_of(t)) for t in texts) * 2 >= len(texts)


def _parse_number(text: str, *, decimal_comma: bool = False) -> float | None:
    s = text.strip().replace("\u2212", "-")
    if "_" in s:
        return None
    try:
        return float(s)
    except ValueError:
        pass
    if decimal_comma and re.fullmatch(r"[+-]?\d*,\d+([eE][+-]?\d+)?", s):
        return float(s.replace(",", "."))
    return None


def _check_duplicates(names: list[str], file: str) -> None:
    seen = set()
    for n in names:
        if n in seen:
            raise DataError(f"two columns are named {n!r}; rename one of them", file=file, column=n)
        seen.add(n)


def _table_of_columns(file: str, columns: list[_Column]) -> _Table:
    """A table from whole columns (MATLAB, netCDF); lengths are checked once selected."""
    return _Table(file, columns, max(len(c.values) for c in columns), text_cells=False)


def _is_empty_cell(v: Any) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v)) or (isinstance(v, str) and not v.strip())


# Cells a person reads as "no value": spreadsheet error codes and the usual placeholders.
_MISSING = frozenset({
    "", "na", "n/a", "n.a.", "nan", "null", "none", "missing", "-", "--", "?",
    "#n/a", "#na", "#value!", "#ref!", "#div/0!", "#num!", "#name?", "#null!",
})
_INT64_MAX = np.iinfo(np.int64).max


def _is_missing(v: Any) -> bool:
    return _is_empty_cell(v) or (isinstance(v, str) and v.strip().lower() in _MISSING)


def _numbers(table: _Table, col: _Column) -> tuple[np.ndarray, DataError | None]:
    """Column as floats, and the error of its first bad cell (or None)."""
    vals = col.values
    if isinstance(vals, np.ndarray) and vals.dtype.kind == "f":
        return vals, None  # NaN and inf are reported by as_states
    if isinstance(vals, np.ndarray) and vals.dtype.kind in "iu":
        return vals.astype(float), None
    if not table.decimal_comma and vals and all(isinstance(v, str) for v in vals):
        # Fast path: numpy's correctly rounded parse of plain decimal text; anything else (empty, NA,
        # inf, "1_0", a decimal comma) falls through to the located cell-by-cell parse below.
        try:
            fast = np.array(vals, dtype=float)
        except (ValueError, OverflowError):
            fast = None
        if fast is not None and np.isfinite(fast).all() and not any("_" in v for v in vals):
            return fast, None
    out = np.empty(len(vals))
    for i, v in enumerate(vals):
        x: float | None = None
        if table.text_cells and _is_empty_cell(v):
            return out, _err(table, "empty cell; every bounce needs a value", col.name, i)
        if isinstance(v, str):
            if _is_missing(v):
                return out, _err(table, f"missing value {v.strip()!r}; every bounce needs a value",
                                 col.name, i)
            x = _parse_number(v, decimal_comma=table.decimal_comma)
        elif isinstance(v, int | float | np.number) and not isinstance(v, bool | np.bool_):
            x = float(v)
        if x is None:
            return out, _err(table, f"non-numeric value {v!r}", col.name, i)
        out[i] = x
    return out, None


_GROUPED = re.compile(r"[+-]?\d{1,3}([.,]\d{3})+")  # "3.000", "3,000": thousands or decimals?
_COMMA_DECIMAL = re.compile(r"[+-]?\d*,\d+([eE][+-]?\d+)?")


def _decimal_convention(table: _Table, cols: list[_Column]) -> None:
    """Decide whether a text table writes decimals with a comma, refusing files that do not say.

    In a semicolon, tab or whitespace file ``15,2`` is a decimal comma; then ``3.000`` may be a
    thousands dot (3000) or a decimal (3.0), so it is refused, as is a file mixing ``15,2`` and
    ``15.2``. ``3,000`` with no other decimal in the file is refused too (3 or 3000?).
    """
    if not table.decimal_comma:
        return
    comma: tuple[int, str, str] | None = None  # first evidence: (row, column, text)
    dot: tuple[int, str, str] | None = None
    grouped: list[tuple[int, str, str]] = []
    for col in cols:
        if isinstance(col.values, np.ndarray):
            continue
        for i, v in enumerate(col.values):
            if not isinstance(v, str) or ("," not in v and "." not in v):
                continue
            t = v.strip()
            if _GROUPED.fullmatch(t):
                grouped.append((i, col.name, t))
            elif _COMMA_DECIMAL.fullmatch(t):
                if comma is None or i < comma[0]:
                    comma = (i, col.name, t)
            elif "." in t and _parse_number(t) is not None and (dot is None or i < dot[0]):
                dot = (i, col.name, t)
    if comma and dot:
        i, name, t = max(comma, dot)
        first = min(comma, dot)
        raise _err(table, f"{t!r} writes its decimals differently from {first[2]!r} (column {first[1]!r}, "
                   f"row {first[0] + 1}); write every number with the same decimal mark", name, i)
    table.decimal_comma = comma is not None
    for i, name, t in sorted(grouped):
        if comma is not None and "." in t:
            why = f"the file writes decimals with a comma ({comma[2]!r}), so the dot is a thousands separator or a slip"
        elif dot is not None and "," in t:
            why = f"the file writes decimals with a dot ({dot[2]!r}), so the comma is a thousands separator or a slip"
        elif comma is None and dot is None:
            mark = "comma" if "," in t else "dot"
            if mark == "dot":
                continue  # no decimal comma anywhere: 3.000 is 3.0
            why = f"nothing else in the file says whether the {mark} is a decimal mark or a thousands separator"
        else:
            continue
        raise _err(table, f"{t!r} is ambiguous: {why}; write it without the separator "
                   f"({t.replace('.', '').replace(',', '')}) or with the file's decimal mark", name, i)


def _setting_values(table: _Table, col: _Column) -> np.ndarray:
    """Setting labels as written: whole numbers as int64 (exact; as text beyond int64), else strings.

    A missing label (empty, ``n/a``, ``NaN``, ``#N/A``...) is an error naming the cell, not a setting.
    """
    vals = col.values if col.text is None else col.text()  # labels are typed from their text
    if isinstance(vals, np.ndarray) and vals.dtype.kind in "iu":
        if vals.dtype.kind == "u" and vals.size and int(vals.max()) > _INT64_MAX:
            return np.array([str(int(v)) for v in vals])
        return vals.astype(np.int64)
    labels: list[Any] = []
    for i, v in enumerate(vals.tolist() if isinstance(vals, np.ndarray) else vals):
        if _is_missing(v) or (isinstance(v, float) and not math.isfinite(v)):
            shown = "empty" if _is_empty_cell(v) and not isinstance(v, float) else repr(v.strip() if isinstance(v, str)
                                                                                     else v)
            raise _err(table, f"missing setting label ({shown}); every bounce needs one", col.name, i)
        if isinstance(v, str) and (x := _parse_number(v)) is not None and not math.isfinite(x):
            raise _err(table, f"setting label {v.strip()!r} is not a finite number nor a name; "
                       "every bounce needs a label", col.name, i)
        labels.append(v.strip() if isinstance(v, str) else v)
    numbers = [_label_number(v) for v in labels]
    if all(isinstance(x, int) for x in numbers):
        if all(abs(x) <= _INT64_MAX for x in numbers):
            return np.array(numbers, dtype=np.int64)
        return np.array([str(x) for x in numbers])  # too long for int64: kept exact as text
    if all(isinstance(x, float) for x in numbers):
        return np.array(numbers, dtype=float)
    return np.array([_label(v) for v in labels])


def _label_number(v: Any) -> int | float | None:
    """A setting label as an exact int, a float (non-whole, up to 15 significant digits), or None."""
    if isinstance(v, bool | np.bool_):
        return None
    if isinstance(v, int | np.integer):
        return int(v)
    if isinstance(v, float | np.floating):
        v = float(v)
        if v.is_integer() and abs(v) < 2.0**53:
            return int(v)
        return v if not v.is_integer() else None
    if not isinstance(v, str):
        return None
    text = v.strip().replace("\u2212", "-")
    if re.fullmatch(r"[+-]?\d+", text):
        return int(text)  # exact, however long ("01" is 1)
    x = _parse_number(text)
    if x is None or not math.isfinite(x):
        return None
    if x.is_integer() and abs(x) < 2.0**53:
        return int(x)
    digits = len(re.sub(r"[^0-9]", "", text.lower().split("e")[0]).strip("0"))
    return x if not x.is_integer() and digits <= 15 else None


def _label(v: Any) -> str:
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


def _campaign_from_table(
    table: _Table,
    *,
    columns: Mapping[str, Any] | None,
    units: dict[str, str],
    campaign: str,
    surface: str,
    source: str,
    ball_radius_m: float,
    plausible: PlausibleRanges = PLAUSIBLE_RANGES,
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

    _decimal_convention(table, [c for role, c in cols.items() if role != "setting"])
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
    for role in sorted(parsed, key=lambda r: "_pi" in r):  # states first: their intervals follow them
        kind = _ROLE_KINDS[role.split(".")[1]]
        unit, origin = _column_unit(table, chosen[role], kind, units)
        state_role = role.replace("_pi.", ".")
        if origin == "assumed" and state_role != role and unit_of[state_role][1] != "assumed":
            unit, origin = unit_of[state_role][0], "its state column"  # a half-width has its value's unit
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

    _check_plausible(table, cols, parsed, scaled, unit_of, ball_radius_m, plausible)

    attrs = {"source_units": _describe_units(unit_of, cols)}
    try:
        return make_campaign(
            states["landing"], states["liftoff"], setting=setting,
            landing_pi=states.get("landing_pi"), liftoff_pi=states.get("liftoff_pi"),
            campaign=campaign, surface=surface, ball_radius_m=ball_radius_m, source=source,
            data_kind="measured", attrs=attrs, plausible=None,  # checked above, with the file's units
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


def _check_plausible(
    table: _Table,
    cols: dict[str, _Column],
    parsed: dict[str, np.ndarray],
    scaled: dict[str, np.ndarray],
    unit_of: dict[str, tuple[str, str]],
    radius_m: float,
    ranges: PlausibleRanges,
) -> None:
    """Refuse numbers whose unit is not given and not certain, and numbers that only a wrong unit makes."""
    roles = [f"{s}.{c}" for s in _STATES for c in COMPONENTS]
    for kind in ("velocity", "spin"):
        assumed = [r for r in roles if _ROLE_KINDS[r.split(".")[1]] == kind and unit_of[r][1] == "assumed"]
        if not assumed:
            continue

        def convert(factor: float, assumed: list[str] = assumed) -> tuple[np.ndarray, np.ndarray]:
            arrs = {r: parsed[r] * factor if r in assumed else scaled[r] for r in roles}
            return tuple(np.column_stack([arrs[f"{s}.{c}"] for c in COMPONENTS]) for s in _STATES)

        verdicts = plausible_units(kind, convert, radius_m=radius_m, ranges=ranges)
        default = CANDIDATE_UNITS[kind][0]
        fits = [u for u, why in verdicts.items() if why is None]
        if fits == [default]:
            continue
        names = [cols[r].name for r in assumed]
        why = verdicts[default]
        said = f"the file gives no {kind} unit for {', '.join(map(repr, names))}"
        if len(fits) > 1:
            msg = (f"{said}, and its numbers are plausible in {', '.join(fits[:-1])} and in {fits[-1]}"
                   + (f" (not in {default}: {why.reason})" if why is not None else "")
                   + f"; bouncelab does not guess: {declare_units_hint(kind, fits)}")
        elif fits:
            msg = (f"{said}; read as {default}, {why.reason}; the numbers look like {fits[0]}: "
                   f"{declare_units_hint(kind, fits)}")
        else:
            msg = (f"{said}; read as {default}, {why.reason}, and they are not plausible in "
                   f"{', '.join(CANDIDATE_UNITS[kind])} either: check the column, or "
                   f"{declare_units_hint(kind, [default])} and widen the plausible ranges "
                   "(plausible=PLAUSIBLE_RANGES.widened(...))")
        if why is not None and why.row is not None:
            raise _err(table, msg, cols[f"{why.state}.{why.component}"].name, why.row)
        raise DataError(msg, file=table.file, column=names[0] if len(names) == 1 else None)

    landing, liftoff = (np.column_stack([scaled[f"{s}.{c}"] for c in COMPONENTS]) for s in _STATES)
    why = implausibility(landing, liftoff, radius_m=radius_m, ranges=ranges)
    if why is None:
        return
    role = f"{why.state}.{why.component}"
    unit, origin = unit_of[role]
    value = float(parsed[role][why.row]) if why.row is not None else None
    said = f"{value!r} {unit}" if value is not None else f"in {unit}"
    msg = (f"{said} (unit from {origin}): {why.reason}; the {why.kind} unit is wrong: "
           f"{declare_units_hint(why.kind, [u for u in CANDIDATE_UNITS[why.kind] if u != unit])}")
    raise _err(table, msg, cols[role].name, why.row)
