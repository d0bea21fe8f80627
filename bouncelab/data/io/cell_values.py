"""The values of the selected columns: numbers (empty, missing and non-numeric cells are
located errors) and setting labels.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bouncelab.data.io.table import _Column, _err, _is_empty_cell, _parse_number, _Table
from bouncelab.errors import DataError

_MISSING = {"", "na", "n/a", "null", "none", "-", "--", "?"}


def _numbers(table: _Table, col: _Column) -> tuple[np.ndarray, DataError | None]:
    """Column as floats, and the error of its first bad cell (or None)."""
    vals = col.values
    if isinstance(vals, np.ndarray) and vals.dtype.kind == "f":
        return vals, None  # NaN and inf are reported by as_states
    out = np.empty(len(vals))
    for i, v in enumerate(vals):
        x: float | None = None
        if table.text_cells and _is_empty_cell(v):
            return out, _err(table, "empty cell; every bounce needs a value", col.name, i)
        if isinstance(v, str):
            if v.strip().lower() in _MISSING:
                return out, _err(table, f"missing value {v.strip()!r}; every bounce needs a value",
                                 col.name, i)
            x = _parse_number(v, decimal_comma=table.decimal_comma)
        elif isinstance(v, int | float | np.number) and not isinstance(v, bool | np.bool_):
            x = float(v)
        if x is None:
            return out, _err(table, f"non-numeric value {v!r}", col.name, i)
        out[i] = x
    return out, None


def _setting_values(table: _Table, col: _Column) -> np.ndarray:
    vals = col.values
    if isinstance(vals, np.ndarray) and vals.dtype.kind == "f":
        bad = ~np.isfinite(vals)
        if bad.any():
            i = int(np.argmax(bad))
            raise _err(table, f"setting label is {vals[i]!r}; every bounce needs one", col.name, i)
        return vals
    labels: list[Any] = []
    for i, v in enumerate(vals):
        if _is_empty_cell(v):
            raise _err(table, "empty setting cell; every bounce needs a setting label", col.name, i)
        labels.append(v.strip() if isinstance(v, str) else v)
    numbers = [
        _parse_number(v) if isinstance(v, str)
        else (float(v) if isinstance(v, int | float | np.number) and not isinstance(v, bool) else None)
        for v in labels
    ]
    if all(x is not None and math.isfinite(x) for x in numbers):
        return np.array(numbers, dtype=float)
    return np.array([_label(v) for v in labels])


def _label(v: Any) -> str:
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)
