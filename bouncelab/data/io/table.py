"""The table every reader returns: the file's columns of raw cells, their units and
where each data row is in the file (for error messages).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from bouncelab.data.io.header_units import _split_header, _unit_of
from bouncelab.data.io.synonyms import _normalize
from bouncelab.errors import DataError


@dataclass
class _Column:
    name: str  # as spelled in the file
    values: Any  # list of raw cells, or a 1-D ndarray
    unit_text: str | None = None  # unit from the header suffix or a units row
    unit_in_header: bool = False

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
        if unit is None and units_row[j]:
            unit = units_row[j]
        values = [r[j] if j < len(r) else "" for r in rows]
        table.columns.append(_Column(name, values, unit, in_header))
    table.n_rows = len(rows)
    return table


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
