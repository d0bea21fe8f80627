"""The table every reader returns (the file's columns of raw cells, their units and where each
data row is in the file) and turning it into a campaign: parse the cells, convert to scaled units
and validate, with every error located in the file.
"""

from __future__ import annotations

import importlib.util
import math
import re
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core.errors import DataError, DroppedRowsWarning
from bouncelab.core.plausibility import (
    CANDIDATE_UNITS,
    PLAUSIBLE_RANGES,
    PlausibleRanges,
    implausibility,
    plausible_units,
)
from bouncelab.core.units import (
    COMPONENTS,
    polar_halfwidths_to_cartesian,
    spin_to_scaled,
    state_from_polar,
    velocity_from_scaled,
    velocity_to_scaled,
)
from bouncelab.core.validation import as_states
from bouncelab.data.campaign import make_campaign
from bouncelab.data.io import hints
from bouncelab.data.io.columns import (
    _NAMES,
    _PI_STATES,
    _ROLE_KINDS,
    _STATES,
    POLAR_ROLES,
    _column_unit,
    _describe_units,
    _normalize,
    _select_auto,
    _select_explicit,
    _split_header,
    _unit_of,
    check_absolute_units,
    interval_scales,
)


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
    hint_style: str = "python"  # how messages name options: Python keywords or CLI flags (io/hints.py)
    kept: list[int] | None = None  # the file's data row (0-based) of each row, once rows are dropped
    delimiter: str | None = None  # of a text file (None: runs of blanks, or not a text file)
    row_labels: list[Any] | None = None  # a DataFrame's index: errors carry the label (DataError.row_label)

    def data_row(self, index: int) -> int:
        """The file's 0-based data row of row ``index`` of the table."""
        return index if self.kept is None else self.kept[index]

    def where(self, index: int, column: str) -> str:
        if self.locate is None:
            return ""
        return f" ({self.locate(self.data_row(index) + self.offset, column)})"


def _err(table: _Table, message: str, column: str | None = None, index: int | None = None) -> DataError:
    """A DataError at data row ``index`` (0-based) of ``column``."""
    if index is None:
        return DataError(message, file=table.file, column=column)
    row = table.data_row(index)
    if table.row_labels is not None:  # a DataFrame: "row 3 (row label 'shot-2')", as predict says it
        return DataError(message, file=table.file, column=column, row=row + 1, row_label=table.row_labels[row])
    return DataError(message + table.where(index, column or ""), file=table.file, column=column, row=row + 1)


def _cell(col: _Column, index: int, unit: str | None = None) -> str:
    """A cell as written in the file, with its unit (``'3.404 m/s'``), for messages: never a converted number."""
    v = col.text()[index] if col.text is not None else col.values[index]  # a bulk-read column keeps its text
    text = v.strip() if isinstance(v, str) else repr(v.item() if isinstance(v, np.generic) else v)
    return text if unit is None else f"{text} {unit}"


def _interval_cell(col: _Column, index: int, unit: str | None, scale: float, value: float) -> str:
    """An interval cell for messages: ``prediction-interval half-width 0.5 m/s``, or for a standard deviation
    (``value`` as parsed, times ``scale``) ``standard deviation 15000 rpm (x 1.96: 29399.5 rpm as a 95 %
    half-width)``, so that the message quotes the number that was checked."""
    cell = _cell(col, index, unit)
    if scale == 1.0:
        return f"prediction-interval half-width {cell}"
    return (f"standard deviation {cell} (x {scale:.2f}: {value * scale:.6g}{'' if unit is None else ' ' + unit} "
            "as a 95 % half-width)")


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


def _drop_hint(table: _Table) -> str:
    return f"{hints.setting('missing', 'drop', table.hint_style)} drops incomplete rows"


#: What ``missing=`` accepts: refuse incomplete rows (default) or drop them with a warning.
MISSING_POLICIES = ("raise", "drop")


def _missing_rows(table: _Table, cols: Mapping[str, _Column]) -> dict[int, tuple[str, Any]]:
    """Rows with a missing cell in a selected column: row -> (column, cell) of the first one."""
    out: dict[int, tuple[str, Any]] = {}
    for col in cols.values():
        vals = col.values
        if isinstance(vals, np.ndarray) and vals.dtype.kind in "iub":
            continue
        if isinstance(vals, np.ndarray) and vals.dtype.kind == "f":
            rows = np.flatnonzero(np.isnan(vals)).tolist()
        else:
            rows = [i for i, v in enumerate(vals) if _is_missing(v)]
        for i in rows:
            out.setdefault(i, (col.name, vals[i]))
    return dict(sorted(out.items()))


def _drop_missing(table: _Table, cols: dict[str, _Column],
                  stacklevel: int) -> tuple[_Table, dict[str, _Column], list[int]]:
    """The table without its incomplete rows (of the selected columns), and the 0-based rows dropped."""
    bad = _missing_rows(table, cols)
    if not bad:
        return table, cols, []
    if len(bad) == table.n_rows:
        raise DataError(f"every row has a missing value (e.g. column {bad[0][0]!r}, row 1): nothing is left "
                        "to load", file=table.file)
    keep = [i for i in range(table.n_rows) if i not in bad]
    new = {}
    for role, col in cols.items():
        vals = col.values[keep] if isinstance(col.values, np.ndarray) else [col.values[i] for i in keep]
        new[role] = _Column(col.name, vals, col.unit_text, col.unit_in_header, col.unit_where)
    kept = _Table(table.file, list({id(c): c for c in new.values()}.values()), len(keep), table.text_cells,
                  table.locate, table.offset, table.decimal_comma, table.hint_style, keep, delimiter=table.delimiter,
                  row_labels=table.row_labels)

    def show(i: int) -> str:
        name, v = bad[i]
        what = "empty" if _is_empty_cell(v) and not isinstance(v, float) else (
            repr(v.strip()) if isinstance(v, str) else "NaN")
        where = table.locate(i + table.offset, name) + ": " if table.locate is not None else ""
        return f"row {i + 1} ({where}{name!r} is {what})"

    warnings.warn(DroppedRowsWarning(
        f"{table.file}: dropped {len(bad)} incomplete row(s) of {table.n_rows} (missing='drop'): "
        + "; ".join(show(i) for i in bad)), stacklevel=stacklevel)
    return kept, new, list(bad)


def _numbers(table: _Table, col: _Column) -> tuple[np.ndarray, DataError | None]:
    """Column as floats, and the error of its first bad cell (or None)."""
    vals = col.values
    if isinstance(vals, np.ndarray) and vals.dtype.kind == "f":
        if table.text_cells and np.isnan(vals).any():  # a DataFrame's NaN is a missing cell, as in a file
            i = int(np.flatnonzero(np.isnan(vals))[0])
            return vals, _err(table, f"missing value (NaN); every bounce needs a value ({_drop_hint(table)})",
                              col.name, i)
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
            return out, _err(table, f"empty cell; every bounce needs a value ({_drop_hint(table)})", col.name, i)
        if isinstance(v, str):
            if _is_missing(v):
                return out, _err(table, f"missing value {v.strip()!r}; every bounce needs a value "
                                 f"({_drop_hint(table)})", col.name, i)
            x = _parse_number(v, decimal_comma=table.decimal_comma)
        elif isinstance(v, int | float | np.number) and not isinstance(v, bool | np.bool_):
            x = float(v)
        if x is None:
            return out, _err(table, f"non-numeric value {v!r}", col.name, i)
        out[i] = x
    return out, None


# "3.000", "3,000": thousands or decimals? ("0.250" cannot be thousands: no group starts with 0)
_GROUPED = re.compile(r"[+-]?[1-9]\d{0,2}([.,]\d{3})+")
_COMMA_DECIMAL = re.compile(r"[+-]?\d*,\d+([eE][+-]?\d+)?")


def _decimal_convention(table: _Table, cols: list[_Column]) -> None:
    """Decide whether a text table writes decimals with a comma, refusing files that do not say.

    In a semicolon, tab or whitespace file ``15,2`` is a decimal comma; then ``3.000`` may be a
    thousands dot (3000) or a decimal (3.0), so it is refused, as is a file mixing ``15,2`` and
    ``15.2``. ``3,000`` with no other decimal in the file is refused too (3 or 3000?), and so is
    ``1.500`` in a semicolon file (the export of a decimal-comma locale) with no other decimal.
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
            if mark == "dot" and table.delimiter != ";":
                continue  # no decimal comma anywhere in a tab or blank-separated file: 3.000 is 3.0
            # a semicolon file is the spreadsheet export of a decimal-comma locale: 1.500 may well be 1500
            why = f"nothing else in the file says whether the {mark} is a decimal mark or a thousands separator"
        else:
            continue
        raise _err(table, f"{t!r} is ambiguous: {why}; write it without the separator "
                   f"({t.replace('.', '').replace(',', '')}) or with the file's decimal mark", name, i)


def _setting_values(table: _Table, col: _Column) -> np.ndarray:
    """Setting labels as written: whole numbers as int64 (exact; as text beyond int64), else strings.

    A missing label (empty, ``n/a``, ``NaN``, ``#N/A``...) is an error naming the cell, not a setting.
    """
    # Labels are typed from their text ("1.0" is not the label "1"), except whole numbers read in bulk as
    # integers, which are exactly what their text says (and typing 10^6 of them cell by cell takes seconds).
    bulk_ints = isinstance(col.values, np.ndarray) and col.values.dtype.kind in "iu"
    vals = col.values if col.text is None or bulk_ints else col.text()
    if isinstance(vals, np.ndarray) and vals.dtype.kind in "iu":
        if vals.dtype.kind == "u" and vals.size and int(vals.max()) > _INT64_MAX:
            return np.array([str(int(v)) for v in vals])
        return vals.astype(np.int64)
    labels: list[Any] = []
    for i, v in enumerate(vals.tolist() if isinstance(vals, np.ndarray) else vals):
        if _is_missing(v) or (isinstance(v, float) and not math.isfinite(v)):
            shown = "empty" if _is_empty_cell(v) and not isinstance(v, float) else repr(v.strip() if isinstance(v, str)
                                                                                     else v)
            raise _err(table, f"missing setting label ({shown}); every bounce needs one ({_drop_hint(table)})",
                       col.name, i)
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
    missing: str = "raise",
    intervals: str | None = None,
    warn_depth: int = 0,
) -> xr.Dataset:
    file = table.file
    if table.n_rows == 0:
        raise DataError("the file has a header but no data rows", file=file)
    chosen = _select_explicit(table, columns) if columns is not None else _select_auto(table, warn_depth)
    cols = {role: ch.column for role, ch in chosen.items()}
    check_absolute_units(table, cols, table.hint_style)
    interval_scale = interval_scales(table, cols, intervals, table.hint_style)

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
    dropped: list[int] = []
    if missing == "drop":
        table, cols, dropped = _drop_missing(table, cols, 4 + warn_depth)

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
        if state_role != role and state_role not in unit_of and state_role.endswith(("xdot", "ydot")):
            state_role = state_role.rsplit(".", 1)[0] + ".speed"  # the Cartesian interval of a polar state
        if origin == "assumed" and state_role != role and unit_of[state_role][1] != "assumed":
            unit, origin = unit_of[state_role][0], "its state column"  # a half-width has its value's unit
        unit_of[role] = (unit, origin)
        if kind == "velocity":
            scaled[role] = velocity_to_scaled(parsed[role], unit, radius_m=ball_radius_m)
        elif kind == "angle":
            scaled[role] = np.rad2deg(parsed[role]) if unit == "rad" else parsed[role]  # degrees
        else:
            scaled[role] = spin_to_scaled(parsed[role], unit)
        if interval_scale.get(role, 1.0) != 1.0:  # standard deviations -> 95 % half-widths
            scaled[role] = scaled[role] * interval_scale[role]
    attrs = {"source_units": _describe_units(unit_of, cols)}
    read: dict[str, set[str]] = {}  # what the file's interval columns held: a campaign keeps only 95 % half-widths
    for role, factor in interval_scale.items():
        read.setdefault(role.split("_pi.")[0], set()).add("95 % half-widths" if factor == 1.0 else
                                                          "standard deviations x 1.96")
    if read:
        attrs["interval_source"] = ", ".join(f"{s} " + " and ".join(sorted(read[s])) for s in _STATES if s in read)
    polar = [s for s in _STATES if f"{s}.speed" in cols]
    if polar:
        attrs["source_form"] = ", ".join(f"{s} {'polar' if s in polar else 'cartesian'}" for s in _STATES)
    for state in polar:
        _polar_state(table, state, cols, parsed, scaled, unit_of, ball_radius_m)
    polar_pi = [s for s in _STATES if f"{s}_pi.speed" in cols]
    if polar_pi:
        # Derived, not measured, half-widths: say so, so that a reader of the campaign knows.
        attrs["interval_form"] = ", ".join(
            f"{s} " + ("polar (speed, angle and spin half-widths propagated to first order, speed and angle errors "
                       "independent)" if s in polar_pi else "cartesian")
            for s in _STATES if f"{s}_pi.omega" in cols)
    for state in polar_pi:
        _polar_intervals(table, state, cols, parsed, scaled, unit_of, ball_radius_m, plausible, interval_scale)
    _check_landing_sign(table, cols, scaled, unit_of)

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
            raise _err(table, f"prediction-interval half-width {_cell(cols[roles[k]], i)} is negative",
                       cols[roles[k]].name, i)
        if state in _PI_STATES and plausible is not None:
            # a half-width wider than any plausible value is a unit mistake (1e6 rpm), not an uncertainty
            limit = np.array([plausible.max_speed / ball_radius_m] * 2 + [plausible.max_spin * 2 * math.pi / 60])
            if (arr > limit).any():
                i, k = (int(v) for v in np.argwhere(arr > limit)[0])
                what = f"{plausible.max_speed:g} m/s" if k < 2 else f"{plausible.max_spin:g} rpm"
                if k < 2 and f"{state}.speed" in cols:  # propagated from a polar state's half-widths
                    raise _propagated_too_wide(table, state, COMPONENTS[k], i, cols, scaled, unit_of,
                                               ball_radius_m, what)
                unit = unit_of[roles[k]][0] if roles[k] in unit_of else None
                cell = _interval_cell(cols[roles[k]], i, unit, interval_scale.get(roles[k], 1.0), parsed[roles[k]][i])
                raise _err(table, f"{cell} is wider than any plausible value ({what}): check the column's unit",
                           cols[roles[k]].name, i)

    _check_plausible(table, cols, parsed, scaled, unit_of, ball_radius_m, plausible)

    if missing == "drop":
        attrs["dropped_rows"] = [i + 1 for i in dropped]  # the file's data rows, 1-based as in errors
    try:
        return make_campaign(
            states["landing"], states["liftoff"], setting=setting,
            landing_pi=states.get("landing_pi"), liftoff_pi=states.get("liftoff_pi"),
            campaign=campaign, surface=surface, ball_radius_m=ball_radius_m, source=source,
            data_kind="measured", attrs=attrs, plausible=None,  # checked above, with the file's units
        )
    except DataError as exc:  # pragma: no cover - everything is checked above
        raise _relocate(table, exc, cols) from None


# A radian column read as degrees: every angle within +-(pi + a few tenths) degrees.
_RADIAN_LIKE = math.pi + 0.35


def _polar_state(
    table: _Table,
    state: str,
    cols: dict[str, _Column],
    parsed: dict[str, np.ndarray],
    scaled: dict[str, np.ndarray],
    unit_of: dict[str, tuple[str, str]],
    radius_m: float,
) -> None:
    """Convert a state given as speed, angle and spin to xdot, ydot (in place), refusing what is not a bounce.

    Polar files give speeds >= 0 and a ball moving in +x; the angle is positive below the horizontal for
    a landing, above it for a lift-off; spin > 0 is backspin (bouncelab's omega > 0).
    """
    sp, an, om = (f"{state}.{c}" for c in ("speed", "angle", "omega"))
    speed, angle = parsed[sp], scaled[an]
    (angle_unit, angle_origin), speed_unit = unit_of[an], unit_of[sp][0]
    name = _NAMES[state]
    # NaN (an array reader's missing value) and inf ("inf", 1e999, np.inf in a DataFrame), first in row order.
    infinite = ~np.isfinite(np.column_stack([parsed[sp], parsed[an], parsed[om]]))
    if infinite.any():
        i, k = (int(v) for v in np.argwhere(infinite)[0])
        role = (sp, an, om)[k]
        raise _err(table, f"{name} {('speed', 'angle', 'spin')[k]} {_cell(cols[role], i, unit_of[role][0])} is not "
                   "a finite number; every bounce needs a finite speed, angle and spin", cols[role].name, i)
    if angle_origin == "assumed" and len(angle) and np.max(np.abs(angle)) <= _RADIAN_LIKE:
        declare = hints.unit_setting("angle", "rad", table.hint_style)
        raise DataError(
            f"the file gives no unit for the {name} angles and every one is within +-{_RADIAN_LIKE:.2f}: read as "
            "degrees (the default) they are implausibly flat, they look like radians; say which: "
            + (f"{declare}, or " if declare else "") + f"put the unit in the header ('{cols[an].name} (rad)' "
            "or '(deg)')", file=table.file, column=cols[an].name)
    if state == "landing":
        bad_speed = ~(speed > 0)
        bad_angle = ~((angle > 0) & (angle <= 90))
        convention = ("a landing angle is positive below the horizontal, in (0, 90] degrees for a ball coming "
                      "down in +x (a file that measures it the other way needs the column negated)")
    else:
        bad_speed = ~(speed >= 0)
        bad_angle = ~((angle >= 0) & (angle < 180))
        convention = ("a lift-off angle is positive above the horizontal, in [0, 180) degrees (0 to 90 going "
                      "on in +x, above 90 going back; a negative one would send the ball into the ground)")
    rows = np.flatnonzero(bad_speed | bad_angle)
    if rows.size:
        i = int(rows[0])
        if bad_speed[i]:
            need = "positive" if state == "landing" else "zero or positive"
            raise _err(table, f"{name} speed {_cell(cols[sp], i, speed_unit)}: a speed must be {need}; polar "
                       "files give speeds >= 0 with the ball moving in +x (the angle gives the direction)",
                       cols[sp].name, i)
        raise _err(table, f"{name} angle {_cell(cols[an], i, angle_unit)} is not plausible: {convention}",
                   cols[an].name, i)
    cart = state_from_polar(np.column_stack([speed, angle, parsed[om]]), kind=state, speed_unit=speed_unit,
                            spin_unit=unit_of[om][0], radius_m=radius_m)
    scaled[f"{state}.xdot"], scaled[f"{state}.ydot"] = cart[:, 0], cart[:, 1]
    # The components in the file's speed unit, for the unit checks (_check_plausible) and their messages.
    a = np.deg2rad(angle)
    parsed[f"{state}.xdot"] = speed * np.cos(a)
    parsed[f"{state}.ydot"] = (-1.0 if state == "landing" else 1.0) * speed * np.sin(a)
    for comp in ("xdot", "ydot"):
        unit_of[f"{state}.{comp}"] = unit_of[sp]
        cols[f"{state}.{comp}"] = cols[sp]


# A 95 % half-width of an angle beyond this spans every direction a landing can come from: a unit or
# column mistake, not an uncertainty (and far beyond where a first-order propagation means anything).
_MAX_ANGLE_HALFWIDTH_DEG = 90.0


def _polar_intervals(
    table: _Table,
    state: str,
    cols: dict[str, _Column],
    parsed: dict[str, np.ndarray],
    scaled: dict[str, np.ndarray],
    unit_of: dict[str, tuple[str, str]],
    radius_m: float,
    plausible: PlausibleRanges | None,
    scales: Mapping[str, float],
) -> None:
    """Propagate a polar state's speed, angle and spin half-widths to xdot, ydot, omega ones (in place).

    To first order with independent speed and angle errors
    (:func:`~bouncelab.core.units.polar_halfwidths_to_cartesian`), at the state's measured speed and
    angle (converted by :func:`_polar_state` first). The half-widths are checked as written before, since
    the propagation would square a negative one into a positive one.
    """
    pi = f"{state}_pi"
    roles = [f"{pi}.{c}" for c in POLAR_ROLES]
    raw = np.column_stack([parsed[r] for r in roles])
    bad = ~(np.isfinite(raw) & (raw >= 0))  # NaN compares false
    if plausible is not None:
        bad[:, 1] |= scaled[roles[1]] > _MAX_ANGLE_HALFWIDTH_DEG
    if bad.any():
        i, k = (int(v) for v in np.argwhere(bad)[0])
        col = cols[roles[k]]
        cell = _interval_cell(col, i, unit_of[roles[k]][0], scales.get(roles[k], 1.0), raw[i, k])
        if raw[i, k] < 0:
            why = "is negative"
        elif not np.isfinite(raw[i, k]):
            why = "is not a finite number"
        else:
            why = (f"is wider than any plausible angle half-width ({_MAX_ANGLE_HALFWIDTH_DEG:g} deg spans every "
                   "direction a landing can come from): check the column's unit")
        raise _err(table, f"{cell} {why}", col.name, i)
    polar = np.column_stack([scaled[f"{state}.{c}"] for c in POLAR_ROLES])  # radii/s, degrees, rad/s
    halfwidths = np.column_stack([scaled[r] for r in roles])

    def propagate(p: np.ndarray, h: np.ndarray) -> np.ndarray:
        return polar_halfwidths_to_cartesian(p, h, kind=state, speed_unit="radius/s", spin_unit="rad/s",
                                             radius_m=radius_m)

    try:
        hw = propagate(polar, halfwidths)
    except DataError as exc:  # a number too large for floats once scaled: name the row (found again row by row)
        for i in range(len(polar)):
            try:
                propagate(polar[i], halfwidths[i])
            except DataError as row_exc:
                cells = ", ".join(_cell(cols[r], i, unit_of[r][0]) for r in roles)
                raise _err(table, f"the {_NAMES[state]} half-widths {cells} cannot be propagated: {row_exc.message}",
                           cols[roles[0]].name, i) from None
        raise exc from None  # pragma: no cover - a row that fails alone
    for k, comp in enumerate(COMPONENTS):
        scaled[f"{pi}.{comp}"] = hw[:, k]
    for comp in ("xdot", "ydot"):  # so that a later message about them names a column of the file
        cols[f"{pi}.{comp}"] = cols[f"{pi}.speed"]
        unit_of[f"{pi}.{comp}"] = unit_of[f"{pi}.speed"]


def _propagated_too_wide(table: _Table, pi: str, comp: str, i: int, cols: dict[str, _Column],
                         scaled: dict[str, np.ndarray], unit_of: dict[str, tuple[str, str]], radius_m: float,
                         limit: str) -> DataError:
    """A propagated xdot or ydot half-width beyond the plausible, blamed on the column whose term dominates."""
    state = pi.removesuffix("_pi")
    v, a = scaled[f"{state}.speed"][i], np.deg2rad(scaled[f"{state}.angle"][i])
    h_v, h_a = scaled[f"{pi}.speed"][i], np.deg2rad(scaled[f"{pi}.angle"][i])
    # The two terms under the square root (units.polar_halfwidths_to_cartesian).
    by_speed, by_angle = (abs(math.cos(a)) * h_v, v * abs(math.sin(a)) * h_a) if comp == "xdot" else (
        abs(math.sin(a)) * h_v, v * abs(math.cos(a)) * h_a)
    culprit = cols[f"{pi}.speed" if by_speed >= by_angle else f"{pi}.angle"]
    unit = unit_of[f"{pi}.speed"][0]
    value = velocity_from_scaled(scaled[f"{pi}.{comp}"][i], unit, radius_m=radius_m)

    def cell(role: str) -> str:
        return _cell(cols[role], i, unit_of[role][0])

    return _err(table, f"the {_NAMES[state]} {comp} half-width propagated from the speed half-width "
                f"{cell(f'{pi}.speed')} and the angle half-width {cell(f'{pi}.angle')} (at speed "
                f"{cell(f'{state}.speed')}, angle {cell(f'{state}.angle')}) is {value:.4g} {unit}, wider than any "
                f"plausible value ({limit}): check the unit of {culprit.name!r}", culprit.name, i)


def _check_landing_sign(table: _Table, cols: dict[str, _Column], scaled: dict[str, np.ndarray],
                        unit_of: dict[str, tuple[str, str]]) -> None:
    """A Cartesian landing going up, quoted as written in the file (as_states would quote radii/s)."""
    if "landing.speed" in cols:
        return  # a polar landing is checked by its angle
    ydot = scaled["landing.ydot"]
    up = np.flatnonzero(ydot >= 0)
    if not up.size:
        return
    i = int(up[0])
    state = np.column_stack([scaled[f"landing.{c}"] for c in COMPONENTS])
    if not np.isfinite(state[: i + 1]).all():
        return  # a non-finite value comes first: as_states reports it
    col = cols["landing.ydot"]
    raise _err(table, f"landing ydot must be negative (y points up, a landing moves down); the file gives "
               f"{_cell(col, i, unit_of['landing.ydot'][0])} (a file whose y points down needs the column "
               "negated)", col.name, i)


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
        names = list(dict.fromkeys(cols[r].name for r in assumed))  # a polar speed backs xdot and ydot
        why = verdicts[default]
        said = f"the file gives no {kind} unit for {', '.join(map(repr, names))}"
        if len(fits) > 1:
            msg = (f"{said}, and its numbers are plausible in {', '.join(fits[:-1])} and in {fits[-1]}"
                   + (f" (not in {default}: {why.reason})" if why is not None else "")
                   + f"; bouncelab does not guess: {hints.declare_units_hint(kind, fits, style=table.hint_style)}")
        elif fits:
            msg = (f"{said}; read as {default}, {why.reason}; the numbers look like {fits[0]}: "
                   f"{hints.declare_units_hint(kind, fits, style=table.hint_style)}")
        else:
            msg = (f"{said}; read as {default}, {why.reason}, and they are not plausible in "
                   f"{', '.join(CANDIDATE_UNITS[kind])} either: check the column, or "
                   f"{hints.declare_units_hint(kind, [default], style=table.hint_style)} and widen the plausible "
                   f"ranges ({_widen_hint(table)})")
        if why is not None and why.row is not None:
            raise _err(table, msg, cols[f"{why.state}.{why.component}"].name, why.row)
        raise DataError(msg, file=table.file, column=names[0] if len(names) == 1 else None)

    landing, liftoff = (np.column_stack([scaled[f"{s}.{c}"] for c in COMPONENTS]) for s in _STATES)
    why = implausibility(landing, liftoff, radius_m=radius_m, ranges=ranges)
    if why is None:
        return
    role = f"{why.state}.{why.component}"
    unit, origin = unit_of[role]
    said = _cell(cols[role], why.row, unit) if why.row is not None else f"in {unit}"  # as written in the file
    others = [u for u in CANDIDATE_UNITS[why.kind] if u != unit]
    msg = (f"{said} (unit from {origin}): {why.reason}; the {why.kind} unit is wrong: "
           f"{hints.declare_units_hint(why.kind, others, style=table.hint_style)}, or if the values are right "
           f"widen the plausible ranges ({_widen_hint(table)})")
    raise _err(table, msg, cols[role].name, why.row)


def _widen_hint(table: _Table) -> str:
    if table.hint_style == "cli":
        return "only from Python: load_campaign(..., plausible=PLAUSIBLE_RANGES.widened(...))"
    return "plausible=PLAUSIBLE_RANGES.widened(...)"


def _looks_like_title(title: Sequence[Any], header: Sequence[Any], first_row: Sequence[Any],
                      blank: Callable[[Any], bool]) -> bool:
    """Whether a line above the header is a title or note (``Bounce test 2026-03-14, turf B``).

    Conservative, so that a data row is never taken for a header: the line has fewer cells than the
    header under it and no number, the header has no number, and the row under the header has one
    or is a units row.
    """
    def cells(row: Sequence[Any]) -> list[Any]:
        return [c for c in row if not blank(c)]

    def numeric(c: Any) -> bool:
        if isinstance(c, bool | np.bool_):
            return False
        return isinstance(c, int | float | np.number) or (isinstance(c, str) and _parse_number(c) is not None)

    t, h, d = cells(title), cells(header), cells(first_row)
    return (0 < len(t) < len(h) and len(h) >= 2 and not any(map(numeric, t)) and not any(map(numeric, h))
            and (any(map(numeric, d)) or _is_units_row(first_row, blank)))


def _header_row_error(file: str, header_row: int, what: str, style: str) -> DataError:
    return DataError(f"{hints.setting('header_row', header_row, style)}: {what}", file=file)


def _table_from_dataframe(df: Any, file: str) -> _Table:
    """A pandas DataFrame as a table: column names are the header (units in them count), rows the data;
    numeric columns keep their arrays, and messages name the row label."""
    import pandas as pd

    if isinstance(df.columns, pd.MultiIndex):
        names = [" ".join(str(p) for p in c).strip() for c in df.columns]
    else:
        names = [str(c).strip() for c in df.columns]
    if not names:
        raise DataError("the DataFrame has no columns", file=file)
    labels = list(df.index)
    # pd.NA, NaT and NaN are empty cells; everything else stays as it is (text, numbers).
    rows = df.astype(object).where(df.notna(), None).to_numpy(dtype=object).tolist()

    def locate(i: int, col: str) -> str:
        return f"row label {labels[i]!r}"

    table = _finish_table(file, names, rows, locate=locate, blank=_is_empty_cell, strict_width=False)
    table.row_labels = labels[table.offset:]  # data rows only (a units row is not one)
    if table.offset == 0:  # no units row: numeric columns are read as arrays (fast, ints exact)
        for col in table.columns:
            series = df.iloc[:, names.index(col.name)]
            if pd.api.types.is_bool_dtype(series) or not pd.api.types.is_numeric_dtype(series):
                continue
            if series.dtype.kind in "iu" and not series.hasnans:
                col.values = series.to_numpy()
            else:
                col.values = series.to_numpy(dtype=float, na_value=np.nan)
    return table
