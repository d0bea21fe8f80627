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
import os
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from bouncelab.core.errors import DataError
from bouncelab.data.io.table import _finish_table, _is_units_row, _Table

# Bytes a plain data line may hold.
_PLAIN = b"0123456789eE+-.,\r\n"
# Line breaks of str.splitlines other than "\n" and "\r\n": a header region holding one is read cell by cell.
_OTHER_BREAKS = ("\r", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029")
_NEGATIVE_ZERO = re.compile(rb"(?:^|[,\n])-0+(?:[,\r\n]|$)", re.MULTILINE)
_SNIFF_LINES = 49  # data lines the text reader's delimiter sniffing looks at


def read_plain_csv(file: str, data: bytes, path: Path | None = None) -> _Table | None:
    """The table of a plain comma-separated file's bytes ``data``, or ``None`` to read it cell by cell.

    ``path``, the file the bytes were read from, lets pandas read it directly (faster than from memory).
    """
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
    # The data lines, from byte ``pos`` on (searched in place: no copy of a large file).
    if data.translate(None, _PLAIN) != data[:pos].translate(None, _PLAIN):
        return None
    if data.find(b"\r", pos) >= 0 and data.count(b"\r", pos) != data.count(b"\r\n", pos):
        return None
    # No cell may exceed the csv module's field limit, which the text reader enforces: a line that long
    # would hold a newline-free window of half the limit at one of these steps.
    step = csv.field_size_limit() // 2
    if any(data.find(b"\n", k, k + step) < 0 for k in range(pos, len(data) - step + 1, step)):
        return None
    sample: list[str] = []  # the lines the text reader sniffs the delimiter from
    p = pos
    while len(sample) < _SNIFF_LINES and p < len(data):
        q = data.find(b"\n", p)
        q = len(data) if q < 0 else q
        if data[p:q].strip():
            sample.append(data[p:q].rstrip(b"\r").decode("ascii"))
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

    values = None
    from_path = False
    if path is not None:
        # From the file, skipping the lines down to the header, blank lines kept: one row per line, else the
        # skip went wrong. A blank line is a row of empty cells, not taken here: then from memory, as below.
        frame = _parse(path, skiprows=lineno, skip_blank_lines=False)
        n_lines = data.count(b"\n", pos) + (pos < len(data) and not data.endswith(b"\n"))
        if frame is not None and len(frame) == n_lines:
            values = _columns(frame, data, pos, len(names), empty_cells=False)
            from_path = values is not None
    if values is None:
        values = _columns(_parse(io.BytesIO(memoryview(data)[pos:])), data, pos, len(names))
    if values is None:
        return None
    n_rows = len(values[0])

    if from_path:
        # Every line under the header is a row: row i is on line header_no + 1 + i, and the cells' text is
        # read again from the file when asked (so the file's bytes need not stay in memory beside the table).
        assert path is not None
        stamp = _stamp(path)

        def locate(i: int, col: str) -> str:
            return f"line {header_no + 1 + i}"

        def text_of(j: int) -> Callable[[], list[str]]:
            return _cells_from_file(file, path, lineno, j, stamp)
    else:
        lines: list[int] = []

        def locate(i: int, col: str) -> str:
            if not lines:  # only an error asks where a row is: find the lines then
                lines.extend(header_no + k + 1 for k, line in enumerate(data[pos:].splitlines()) if line.strip())
            return f"line {lines[i]}"

        def text_of(j: int) -> Callable[[], list[str]]:
            return _cells(data, pos, j)

    table = _finish_table(file, names, [], locate=locate, blank=lambda c: not c, strict_width=True)
    for column, j in zip(table.columns, [j for j, name in enumerate(names) if name], strict=True):
        column.values = values[j]
        if isinstance(values[j], np.ndarray):  # numbers keep their text, for labels and messages
            column.text = text_of(j)
    table.n_rows = n_rows
    return table


def _stamp(path: Path) -> tuple[int, int]:
    st = os.stat(path)
    return st.st_size, st.st_mtime_ns


def _cells_from_file(file: str, path: Path, skiprows: int, j: int, stamp: tuple[int, int]
                     ) -> Callable[[], list[str]]:
    """Column ``j``'s cells as written, read again from the file, which must not have changed since."""

    def cells() -> list[str]:
        if _stamp(path) != stamp:
            raise DataError("the file changed while it was being read; load it again", file=file)
        return _text_column(path, j, skiprows=skiprows, skip_blank_lines=False)

    return cells


def _text_column(source: Path | io.BytesIO, j: int, *, skiprows: int = 0, skip_blank_lines: bool = True
                 ) -> list[str]:
    """Column ``j`` of plain comma-separated rows, each cell as written."""
    frame = pd.read_csv(source, header=None, sep=",", usecols=[j], dtype=str, skiprows=skiprows, na_filter=False,
                        skip_blank_lines=skip_blank_lines, quoting=csv.QUOTE_NONE, engine="c", encoding="utf-8")
    return frame[j].tolist()


def _parse(source: Path | io.BytesIO, skiprows: int = 0, skip_blank_lines: bool = True) -> pd.DataFrame | None:
    """pandas' reading of plain rows of numbers: Python's float conversion, nothing taken as missing."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # float_precision="round_trip" is deprecated by pandas 3, still exact
            return pd.read_csv(source, header=None, sep=",", skiprows=skiprows, na_filter=False,
                               skip_blank_lines=skip_blank_lines, quoting=csv.QUOTE_NONE,
                               float_precision="round_trip", engine="c", encoding="utf-8")
    except (pd.errors.ParserError, pd.errors.EmptyDataError, ValueError, TypeError, OSError):
        return None


def _columns(frame: pd.DataFrame | None, data: bytes, pos: int, width: int, *,
             empty_cells: bool = True) -> list | None:
    """Each column as numbers (an array) or cells (a list of str), or ``None`` if anything is unusual."""
    if frame is None or frame.shape[1] != width or len(frame) == 0:
        return None
    values: list[object] = []
    for j in range(width):
        series = frame[j]
        kind = series.dtype.kind
        if kind in "iuf":
            arr = series.to_numpy()
            if kind == "f" and not np.isfinite(arr).all():  # a short row's NaN, or "1e999"
                return None
            # "-0" is -0.0 as a number but 0 as an integer, and pandas reads a file in chunks, each typed alone
            if (arr == 0).any() and _NEGATIVE_ZERO.search(data, pos):
                return None
            values.append(arr)
        elif kind == "O" and series.map(type).eq(str).all() and (empty_cells or not series.eq("").any()):
            values.append(series.tolist())  # cells as written: the cell-by-cell parse reports the bad one
        else:  # NaN of a short row, or chunks typed differently (numbers and text)
            return None
    return values


def _cells(data: bytes, pos: int, j: int) -> Callable[[], list[str]]:
    """Column ``j``'s cells as written (a setting label is typed from its text, not its value)."""

    def cells() -> list[str]:
        return _text_column(io.BytesIO(memoryview(data)[pos:]), j)

    return cells
