"""Bulk reading of plain comma-separated tables: the fast path of the text reader.

A comma-separated file whose data lines hold nothing but numbers (digits, ``+ - . e E``,
commas and line breaks: no quotes, spaces, comments, missing-value words or other marks) is
read in one pass by pandas' C parser instead of cell by cell. Such a file can hold none of the
cells the text reader refuses or treats specially (``#``/``%`` lines, ``NA``, decimal commas,
quoted cells, blanks in a whitespace file...), so the table it makes is the one the cell-by-cell
reader makes: same columns, same numbers (parsed with Python's correctly rounded conversion, as
the cell-by-cell reader does), same setting labels, same row and line in every error. Whenever
a file is not plain, or pandas finds anything unusual (a ragged row, an empty or non-numeric
cell, an infinite number), this returns ``None`` and the cell-by-cell reader reads the file
and reports what it finds.
"""

from __future__ import annotations

import csv
import io
import re
import warnings
from collections.abc import Callable

import numpy as np
import pandas as pd

from bouncelab.data.io.table import _finish_table, _is_units_row, _Table

# Bytes a plain data line may hold.
_PLAIN = b"0123456789eE+-.,\r\n"
# Line breaks of str.splitlines other than "\n" and "\r\n": a header region holding one is read cell by cell.
_OTHER_BREAKS = ("\r", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029")
_NEGATIVE_ZERO = re.compile(rb"(?:^|[,\n])-0+(?:[,\r\n]|$)", re.MULTILINE)
_SNIFF_LINES = 49  # data lines the text reader's delimiter sniffing looks at


def read_plain_csv(file: str, data: bytes) -> _Table | None:
    """The table of a plain comma-separated file's bytes ``data``, or ``None`` to read it cell by cell."""
    from bouncelab.data.io.text import _sniff, _starts_comment

    # The header: the first line that is neither blank nor a comment, as the text reader finds it.
    # Lines above it are decoded as UTF-8 (the text reader's choice for a file whose data are ASCII).
    pos, lineno = (3 if data.startswith(b"\xef\xbb\xbf") else 0), 0
    while True:
        if pos >= len(data):
            return None
        end = data.find(b"\n", pos)
        end = len(data) if end < 0 else end
        try:
            line = data[pos:end].decode("utf-8")
        except UnicodeDecodeError:
            return None
        line = line[:-1] if line.endswith("\r") else line
        if "\x00" in line or any(c in line for c in _OTHER_BREAKS):
            return None
        lineno, pos = lineno + 1, end + 1
        if line.strip() and not _starts_comment(line):
            header_line, header_no = line, lineno
            break
    raw = data[pos:]
    if raw.translate(None, _PLAIN) or (b"\r" in raw and raw.count(b"\r") != raw.count(b"\r\n")):
        return None
    # No cell may exceed the csv module's field limit, which the text reader enforces: a line that long
    # would hold a newline-free window of half the limit at one of these steps.
    step = csv.field_size_limit() // 2
    if any(raw.find(b"\n", k, k + step) < 0 for k in range(0, len(raw) - step + 1, step)):
        return None
    sample: list[str] = []  # the lines the text reader sniffs the delimiter from
    p = 0
    while len(sample) < _SNIFF_LINES and p < len(raw):
        q = raw.find(b"\n", p)
        q = len(raw) if q < 0 else q
        if raw[p:q].strip():
            sample.append(raw[p:q].rstrip(b"\r").decode("ascii"))
        p = q + 1
    if not sample or _sniff([header_line, *sample]) != ",":
        return None
    if _is_units_row(sample[0].split(","), lambda c: not c):
        return None
    try:
        names = [h.strip() for h in next(csv.reader([header_line], delimiter=","))]
    except csv.Error:
        return None
    while names and not names[-1]:
        names.pop()

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # float_precision="round_trip": Python's own conversion
            frame = pd.read_csv(io.BytesIO(raw), header=None, sep=",", na_filter=False, skip_blank_lines=True,
                                quoting=csv.QUOTE_NONE, float_precision="round_trip", engine="c")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError, TypeError):
        return None
    if frame.shape[1] != len(names) or len(frame) == 0:
        return None
    values: list[object] = []
    for j in range(frame.shape[1]):
        series = frame[j]
        kind = series.dtype.kind
        if kind in "iuf":
            arr = series.to_numpy()
            if kind == "f" and not np.isfinite(arr).all():  # a short row's NaN, or "1e999"
                return None
            # "-0" is -0.0 as a number but 0 as an integer, and pandas reads a file in chunks, each typed alone
            if (arr == 0).any() and _NEGATIVE_ZERO.search(raw):
                return None
            values.append(arr)
        elif kind == "O" and series.map(type).eq(str).all():
            values.append(series.tolist())  # cells as written: the cell-by-cell parse reports the bad one
        else:  # NaN of a short row, or chunks typed differently (numbers and text)
            return None

    lines: list[int] = []

    def locate(i: int, col: str) -> str:
        if not lines:  # only an error asks where a row is: find the lines then
            lines.extend(header_no + k + 1 for k, line in enumerate(raw.splitlines()) if line.strip())
        return f"line {lines[i]}"

    table = _finish_table(file, names, [], locate=locate, blank=lambda c: not c, strict_width=True)
    for column, j in zip(table.columns, [j for j, name in enumerate(names) if name], strict=True):
        column.values = values[j]
        if isinstance(values[j], np.ndarray) and values[j].dtype.kind == "f":
            column.text = _cells(raw, j)
    table.n_rows = len(frame)
    return table


def _cells(raw: bytes, j: int) -> Callable[[], list[str]]:
    """Column ``j``'s cells as written (a setting label is typed from its text, not its value)."""

    def cells() -> list[str]:
        frame = pd.read_csv(io.BytesIO(raw), header=None, sep=",", usecols=[j], dtype=str, na_filter=False,
                            skip_blank_lines=True, quoting=csv.QUOTE_NONE, engine="c")
        return frame[j].tolist()

    return cells
