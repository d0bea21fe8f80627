"""Reading a file into one pandas DataFrame, each format by its library, with where each row is in the file.

``pandas.read_csv`` reads text tables (after the delimiter, the header, title lines, a units row and
comment lines are found here), ``pandas.read_excel`` workbooks, ``scipy.io.loadmat`` MATLAB files and
``xarray.open_dataset`` netCDF files. The result is a :class:`Table`; what its cells mean is for
:mod:`bouncelab.data.io.interpret`.
"""

from __future__ import annotations

import codecs
import csv
import importlib.util
import io
import re
import signal
import subprocess
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core.errors import DataError, Hint
from bouncelab.data.io.names import is_units_row, parse_number, unit_cell

EXCEL_SUFFIXES, NETCDF_SUFFIXES = (".xlsx", ".xls"), (".nc", ".netcdf")
# Cells a person reads as "no value": spreadsheet error codes and the usual placeholders.
MISSING = frozenset({"", "na", "n/a", "n.a.", "nan", "null", "none", "missing", "-", "--", "?", "#n/a", "#na",
                     "#value!", "#ref!", "#div/0!", "#num!", "#name?", "#null!"})
# pandas 3 reads floats exactly (Python's correctly rounded conversion) by default; pandas 2 when asked.
_EXACT = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}


def module_available(name: str) -> bool:
    return importlib.util.find_spec(name) is not None


def is_empty(v: Any) -> bool:
    """An empty cell: None, NaN, pd.NA, blank text."""
    return (isinstance(v, str) and not v.strip()) or (not isinstance(v, str) and bool(pd.isna(v)))


@dataclass
class Table:
    """A file's columns as one DataFrame (one row per data row, names as in the file) and where its rows are.

    ``units`` holds units given beside the names (a units row under the header, a netCDF ``units``
    attribute): column -> (unit text, where). ``where(row, column)`` says where data row ``row``
    (0-based) is (``"line 5"``, ``"cell E5 of sheet 'B'"``); ``labels`` are a DataFrame's row labels;
    ``text(column)`` gives a text file's cells as written; ``lengths`` the length of each column of a
    file of separate arrays (``.mat``, netCDF), padded in ``frame``.
    """

    file: str
    frame: pd.DataFrame
    units: dict[str, tuple[str, str]] = field(default_factory=dict)
    where: Callable[[int, str | None], str] | None = None
    labels: list | None = None
    text_cells: bool = True  # NaN and blank text are empty cells (not an array's NaN)
    decimal_comma: bool = False  # a semicolon, tab or blank-separated text table may write 1,5
    delimiter: str | None = None
    lengths: dict[str, int] | None = None
    text: Callable[[str], list[str]] | None = None
    refused: DataError | None = None  # a row the reader refused, reported once the header is checked


# ------------------------------------------------------------------------------------------------ text tables

_BREAK = re.compile(rb"\r\n|\r|\n")  # lines end at these only, as in spreadsheets


def _comment(line: str) -> bool:
    return line.lstrip().startswith(("#", "%"))


def _split(line: str, delim: str | None) -> list[str]:
    return line.split() if delim is None else next(csv.reader([line], delimiter=delim))


def _sniff(lines: list[str]) -> str | None:
    """The delimiter most lines agree on: tab, semicolon or comma; ``None`` for runs of blanks."""
    best: tuple[str, int] | None = None
    for d in ("\t", ";", ","):
        try:
            counts = [len(_split(line, d)) for line in lines]
        except csv.Error:
            continue
        n = counts[0]
        if n >= 2 and not (len(counts) > 1 and sum(c == n for c in counts[1:]) * 2 < len(counts) - 1):
            best = (d, n) if best is None or n > best[1] else best
    return None if best is None else best[0]


def _data_shaped(cells: list[str], width: int) -> bool:
    """A ``#`` line after the header is data (``#N/A,20.1,...``) if it is shaped like a row: within one cell of
    the header's width (trailing separators not counted), at least half of it numbers."""
    while cells and not cells[-1]:
        cells = cells[:-1]
    numeric = sum(parse_number(c) is not None for c in cells[1:])
    return width >= 2 and abs(len(cells) - width) <= 1 and numeric * 2 >= len(cells) - 1


def looks_like_title(title: list, header: list, first_row: list, blank: Callable[[Any], bool]) -> bool:
    """Whether a line above the header is a title or note (``Bounce test 2026-03-14, turf B``). Conservative, so
    that a data row is never taken for a header: fewer cells than the header under it and no number, the
    header has no number, and the row under it has one or is a units row."""
    def numeric(c: Any) -> bool:
        return not isinstance(c, bool | np.bool_) and (isinstance(c, int | float | np.number) or (
            isinstance(c, str) and parse_number(c) is not None))

    t, h, d = ([c for c in row if not blank(c)] for row in (title, header, first_row))
    return (0 < len(t) < len(h) and len(h) >= 2 and not any(map(numeric, t)) and not any(map(numeric, h))
            and (any(map(numeric, d)) or is_units_row(first_row, blank)))


def _header_index(lines: list[tuple[int, str, int]], k: int) -> int:
    """The header: the first line that is not a comment (``k``), or a line below it above which every line
    is a title (:func:`looks_like_title`)."""
    for h in range(k + 1, min(k + 11, len(lines) - 1)):
        below = [t for _, t, _ in lines[h:h + 50] if not _comment(t)]
        above = [t for _, t, _ in lines[k:h] if not _comment(t)]
        if len(below) < 2 or _comment(lines[h][1]):
            continue
        delim = _sniff(below)
        try:
            header, first, *titles = (_split(t, delim) for t in (below[0], below[1], *above))
        except csv.Error:
            continue
        if all(looks_like_title(t, header, first, lambda c: not c.strip()) for t in titles):
            return h
    return k


def _lines(raw: bytes, start: int, enc: str):
    """(line number, text, end) of each line of ``raw`` from byte ``start`` (line 1)."""
    pos, no = start, 0
    for m in _BREAK.finditer(raw, start):
        no += 1
        yield no, raw[pos:m.start()].decode(enc), m.end()
        pos = m.end()
    if pos < len(raw):
        yield no + 1, raw[pos:].decode(enc), len(raw)


def _plain(raw: bytes, at: int, delim: str | None) -> bool:
    """Whether pandas reads each non-blank line of ``raw`` from ``at`` as a row: no comment line, no tab-only line."""
    for mark in (b"#", b"%"):
        k = raw.find(mark, at)
        while k >= 0:
            if not raw[max(raw.rfind(b"\n", at, k), raw.rfind(b"\r", at, k), at - 1) + 1:k].strip():
                return False
            k = raw.find(mark, k + 1)
    return not (delim == "\t" and re.compile(rb"(?:^|[\r\n])[ \t]*\t[ \t]*(?:[\r\n]|$)").search(raw, at))


def read_text(file: str, raw: bytes, header_row: int | None = None, path: Path | None = None) -> Table:
    """A ``.csv``, ``.tsv`` or ``.txt`` table: UTF-8 (a BOM is fine) else Latin-1; see docs/data.md. ``path``, the
    file ``raw`` was read from, lets pandas read a large plain file from the disk (in parallel, pandas 3)."""
    if b"\x00" in raw:
        raise DataError("the file holds NUL bytes: it is not a text table (a binary or damaged file?)", file=file)
    enc = "utf-8"
    if not raw.isascii():
        try:
            raw.decode("utf-8")
        except UnicodeDecodeError:
            enc = "latin-1"
    start = 3 if enc == "utf-8" and raw.startswith(codecs.BOM_UTF8) else 0
    lines: list[tuple[int, str, int]] = []  # the head of the file: its non-blank lines
    first, n_lines = None, 0
    for no, text, end in _lines(raw, start, enc):
        n_lines = no
        if text.strip():
            lines.append((no, text, end))
            first = len(lines) - 1 if first is None and not _comment(text) else first
        if first is not None and len(lines) > first + 62 and no > (header_row or 0) + 51:
            n_lines = None  # not read to the end
            break
    if first is None:
        raise DataError("the file is empty (no header, no data)", file=file)
    if header_row is not None:
        if n_lines is not None and header_row > n_lines:
            raise DataError(f"header row {header_row}: the file has {n_lines} lines", file=file)
        h = next((j for j, (no, _, _) in enumerate(lines) if no == header_row), None)
        if h is None:
            raise DataError(f"header row {header_row}: line {header_row} is blank; a header names the columns",
                            file=file)
    else:
        h = _header_index(lines, first)
    header_no, header_line, pos = lines[h]
    delim = _sniff([header_line] + [t for _, t, _ in lines[h + 1:h + 50] if not _comment(t)])
    try:
        names = [c.strip() for c in _split(header_line, delim)]
    except csv.Error as exc:
        raise DataError(f"line {header_no}: cannot split the header: {exc}", file=file) from None
    if delim is None:  # "vx0 [m/s]" in a blank-separated header is one name
        merged: list[str] = []
        for n in names:
            if merged and re.fullmatch(r"[\[\(\{].*[\]\)\}]", n):
                merged[-1] += " " + n
            else:
                merged.append(n)
        names = merged
    while names and not names[-1]:
        names.pop()
    units: dict[str, tuple[str, str]] = {}
    k = next((k for k in range(h + 1, len(lines)) if not _comment(lines[k][1])), None)
    below = None if k is None or any(_data_shaped(_split(t, delim), len(names)) for _, t, _ in lines[h + 1:k]) else (
        lines[k])  # a units row is the first row: not under a commented-out row
    first_line = header_no + 1
    cells = _split(below[1], delim) if below is not None else []
    if cells and (delim is not None or len(cells) == len(names)) and is_units_row(cells[: len(names)], lambda c: not c):
        units = {n: (unit_cell(c), "units row") for n, c in zip(names, cells, strict=False) if n and unit_cell(c)}
        pos, first_line = below[2], below[0] + 1
    width = len(names)

    def wrong_width(lineno: int, n: int, row: int) -> DataError:
        if delim is None:  # runs of blanks separate the cells: an empty cell cannot be seen
            return DataError(f"line {lineno} has {n} values but the header names {width} columns; in a "
                             "whitespace-separated file an empty cell cannot be told from the separator: write NA "
                             "in it, or use a comma- or tab-separated file", file=file, row=row)
        return DataError(f"the row has {n} values but the header names {width} columns (line {lineno})", file=file,
                         row=row)

    body, at = raw, pos  # the data lines: raw from byte pos, or the lines kept of them
    linenos: list[int] = []
    if not _plain(raw, pos, delim):  # comment lines: refuse those shaped like data, skip the others
        kept = []
        for no, text, _ in _lines(raw, pos, enc):
            if text.strip() and _comment(text):
                cells = _split(text, delim)
                if not _data_shaped(cells, len(names)):
                    continue
                if cells[0].strip().lower() not in MISSING:
                    raise DataError(f"line {no + first_line - 1} starts with {text.lstrip()[0]!r} like a comment but "
                                    f"holds a row of {len(cells)} values like the data: delete the line if it is "
                                    f"commented out, or remove the {text.lstrip()[0]!r}", file=file,
                                    row=len(linenos) + 1)
            elif delim is None and text.strip() and len(text.split()) != width:
                raise wrong_width(no + first_line - 1, len(text.split()), len(linenos) + 1)
            if text.strip():
                kept.append(text)
                linenos.append(no + first_line - 1)
        body, at = "\n".join(kept).encode(enc), 0

    store: list[bytes | None] = [body]  # the data text() and line() read again: these bytes, or None: the file
    stamp = (0, 0)

    def data() -> bytes:
        if store[0] is None and (path.stat().st_size, path.stat().st_mtime_ns) != stamp:
            raise DataError("the file changed while it was being read; load it again", file=file)
        return path.read_bytes() if store[0] is None else store[0]

    def line(row: int, column: str | None = None) -> str:
        if not linenos:  # every non-blank line is a row: find them when a message asks
            linenos.extend(no + first_line - 1 for no, text, _ in _lines(data(), at, enc) if text.strip())
        return f"line {linenos[row]}"

    frame = None
    if path is not None and body is raw and enc == "utf-8" and raw.find(b"\r") < 0 and first_line - 1 == sum(
            no < first_line for no, _, _ in lines):  # every line above the data is one pandas skips
        stamp = (path.stat().st_size, path.stat().st_mtime_ns)
        frame = _parse(file, path, first_line - 1, delim, width, enc, as_text=delim != ",")
        rows = raw.count(b"\n", pos) + (not raw.endswith(b"\n") and len(raw) > pos)
        frame = frame if len(frame) == rows and stamp[0] == len(raw) else None  # blank lines, a changed file: memory
        store[0] = None if frame is not None else body  # the bytes need not stay in memory beside the table
    if frame is None:
        frame = _parse(file, body, at, delim, width, enc, as_text=delim != ",")
    extra = frame.iloc[:, width:].ne("").any(axis=1) if frame.shape[1] > width else pd.Series(False, frame.index)
    short = frame.iloc[:, width - 1].eq("") if delim is None and width else pd.Series(False, frame.index)
    refused = None
    if (bad := extra | short).any():
        i = int(np.argmax(bad.to_numpy()))
        n = int(frame.iloc[i].ne("").to_numpy().nonzero()[0].max()) + 1 if delim is not None else int(
            frame.iloc[i].ne("").sum())
        refused = wrong_width(int(line(i).split()[1]), n, i + 1)
    frame = frame.iloc[:, :width].set_axis(names, axis=1)

    @cache
    def text(column: str) -> list[str]:
        j = names.index(column)
        if frame.iloc[:, j].dtype.kind == "O" and all(isinstance(v, str) for v in frame.iloc[:, j]):
            return frame.iloc[:, j].tolist()
        return _parse(file, data(), at, delim, width, enc, as_text=True, usecols=[j]).iloc[:, 0].tolist()

    zeros = {j: z for j in range(width) if frame.iloc[:, j].dtype.kind in "if" and (z := frame.iloc[:, j].to_numpy()
                                                                                      == 0).any()}
    for j, zero in zeros.items() if zeros and body.find(b"-0", at) >= 0 else ():  # "-0" is a number's sign, lost
        neg = zero & np.array([t.lstrip().startswith("-") for t in text(names[j])])  # where pandas read an integer
        if neg.any():
            frame.isetitem(j, np.where(neg, -0.0, frame.iloc[:, j].to_numpy(dtype=float)))
    return Table(file, frame, units, line, decimal_comma=delim != ",", delimiter=delim, text=text, refused=refused)


def _parse(file: str, body: bytes | Path, at: int, delim: str | None, width: int, enc: str, *, as_text: bool,
           usecols: list[int] | None = None) -> pd.DataFrame:
    """pandas' reading of the data lines (``body`` from byte ``at``, or the file ``body`` from line ``at``): every cell
    as written (``as_text``) or numbers where a column holds only numbers; nothing taken as missing (``NA`` stays
    text); a longer row widens ``width``."""
    while True:
        source = str(body) if isinstance(body, Path) else io.BytesIO(body)  # shares the bytes
        if not isinstance(body, Path):
            source.seek(at)
        try:
            with warnings.catch_warnings():  # pandas types a long file chunk by chunk: a mixed column is cells
                warnings.simplefilter("ignore", pd.errors.DtypeWarning)
                warnings.simplefilter("error", pd.errors.ParserWarning)  # cells beyond ``width`` would be lost
                return pd.read_csv(source, sep=r"\s+" if delim is None else delim, header=None, index_col=False,
                                   skiprows=at if isinstance(body, Path) else None,
                                   names=range(width), usecols=usecols, dtype=str if as_text else None,
                                   na_filter=False, encoding=enc, quoting=csv.QUOTE_NONE if delim is None else 0,
                                   **_EXACT)
        except pd.errors.EmptyDataError:
            return pd.DataFrame(columns=range(width), dtype=object)
        except pd.errors.ParserWarning:  # the first row is the longer one
            width = 2 * width + 1
        except (pd.errors.ParserError, ValueError) as exc:
            more = re.search(r"Expected \d+ fields in line \d+, saw (\d+)", str(exc))
            if more is None or int(more.group(1)) <= width:
                raise DataError(f"cannot read it as a text table ({exc})", file=file) from None
            width = int(more.group(1))


# ------------------------------------------------------------------------------------------------ Excel

def _col_letter(j: int) -> str:
    out, j = "", j + 1
    while j:
        j, r = divmod(j - 1, 26)
        out = chr(65 + r) + out
    return out


def read_excel(path: Path, file: str, sheet: str | int | None, header_row: int | None = None) -> Table:
    """One sheet of an ``.xlsx`` (openpyxl) or ``.xls`` (xlrd) workbook: the first visible one, or ``sheet``."""
    for suffix, package, more in ((".xlsx", "openpyxl", ""), (".xls", "xlrd", ", or save it as .xlsx")):
        if path.suffix.lower() == suffix and not module_available(package):
            raise DataError(f"reading {'an old-style ' if suffix == '.xls' else 'an '}Excel workbook ({suffix}) needs "
                            f"the package {package}: pip install 'bouncelab[excel]' (or pip install {package}){more}",
                            file=file)
    try:
        with pd.ExcelFile(path) as xf:
            names, book = list(xf.sheet_names), xf.book
            hidden = {ws.title for ws in getattr(book, "worksheets", []) if getattr(ws, "sheet_state", "") == "hidden"
                      or getattr(ws, "sheet_state", "") == "veryHidden"}  # openpyxl
            if hasattr(book, "sheet_by_index"):  # xlrd
                hidden |= {sh.name for sh in book.sheets() if getattr(sh, "visibility", 0)}
            if sheet is None:
                visible = [k for k, n in enumerate(names) if n not in hidden]
                if not visible:
                    raise DataError(f"every sheet of the workbook is hidden ({names}); name the one to read", file=file,
                                    hints=[Hint("sheet", names[0])])
                sheet = visible[0]  # the first sheet a person sees in Excel
            if isinstance(sheet, str) and sheet.isdigit() and sheet not in names:
                sheet = int(sheet)  # "1" (as a command line gives it): the sheet named "1", else the index 1
            index = isinstance(sheet, int) and not isinstance(sheet, bool)
            if index and not 0 <= sheet < len(names):
                raise DataError(f"sheet index {sheet} out of range; the workbook's sheets are {names}", file=file)
            if not index and str(sheet) not in names:
                raise DataError(f"no sheet {sheet!r}; the workbook's sheets are {names}", file=file)
            sheet_name = names[sheet] if index else str(sheet)
            grid = pd.read_excel(xf, sheet_name=sheet_name, header=None, dtype=object).values.tolist()
    except DataError:
        raise
    except Exception as exc:
        raise DataError(f"cannot read it as an Excel workbook ({type(exc).__name__}: {exc})", file=file) from None
    keep = [k for k, r in enumerate(grid) if not all(map(is_empty, r))]
    if not keep:
        raise DataError(f"sheet {sheet_name!r} is empty (no header, no data)", file=file)
    if header_row is not None:
        if header_row > len(grid) or header_row - 1 not in keep:
            what = (f"sheet {sheet_name!r} has {len(grid)} rows" if header_row > len(grid) else
                    f"row {header_row} of sheet {sheet_name!r} is empty; a header names the columns")
            raise DataError(f"header row {header_row}: {what}", file=file)
        keep = keep[keep.index(header_row - 1):]
    while header_row is None and len(keep) > 2 and looks_like_title(*(grid[k] for k in keep[:3]), is_empty):
        keep = keep[1:]  # a title or note above the header
    header = ["" if is_empty(c) else str(c).strip() for c in grid[keep[0]]]
    while header and not header[-1]:
        header.pop()
    rows = [(grid[k] + [None] * len(header))[: len(header)] for k in keep[1:]]
    sheet_rows = [k + 1 for k in keep[1:]]
    units: dict[str, tuple[str, str]] = {}
    if rows and is_units_row(rows[0], is_empty):
        units = {n: (unit_cell(c), "units row") for n, c in zip(header, rows[0], strict=True) if n and not is_empty(c)}
        rows, sheet_rows = rows[1:], sheet_rows[1:]

    def where(row: int, column: str | None = None) -> str:
        if column in header:
            return f"cell {_col_letter(header.index(column))}{sheet_rows[row]} of sheet {sheet_name!r}"
        return f"row {sheet_rows[row]} of sheet {sheet_name!r}"

    return Table(file, pd.DataFrame(rows, columns=header, dtype=object), units, where)


# ------------------------------------------------------------------------------------------------ a DataFrame

def table_from_dataframe(df: pd.DataFrame, file: str) -> Table:
    """A DataFrame read as a file: its column names are the header (a units row under it counts), its rows the data."""
    names = [" ".join(map(str, c)).strip() if isinstance(df.columns, pd.MultiIndex) else str(c).strip()
             for c in df.columns]
    if not names:
        raise DataError("the DataFrame has no columns", file=file)
    frame, labels, units = df.set_axis(names, axis=1).reset_index(drop=True), list(df.index), {}
    if len(frame) and is_units_row(frame.iloc[0].tolist(), is_empty):
        units = {n: (unit_cell(c), "units row") for n, c in zip(names, frame.iloc[0], strict=True) if not is_empty(c)}
        frame, labels = frame.iloc[1:].reset_index(drop=True).astype(object), labels[1:]
    return Table(file, frame, units, labels=labels)


# ------------------------------------------------------------------------------------------------ arrays

def _arrays(file: str, columns: list[tuple[str, Any]], units: dict[str, tuple[str, str]]) -> Table:
    """A table of separate arrays (``.mat``, netCDF), padded to the longest; the lengths are checked when read."""
    if not columns:
        raise DataError("the file holds no 1-D variables (columns)", file=file)
    frame = pd.concat([pd.Series(v, name=n, dtype=None if isinstance(v, np.ndarray) else object)
                       for n, v in columns], axis=1)
    return Table(file, frame, units, text_cells=False, lengths={n: len(v) for n, v in columns})


def _scalar(v: Any) -> Any:
    """A MATLAB scalar (number or string) as a Python value, else ``None``."""
    if isinstance(v, np.ndarray):
        if v.size != 1:
            return None
        v = v.reshape(()).item()
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, bool) or not isinstance(v, int | float | str | np.number):
        return None
    return v.item() if isinstance(v, np.number) else v


#: Seconds the crash probe of a ``.mat`` file may take before the file is refused.
MAT_PROBE_TIMEOUT_S = 60.0
_LOADMAT = dict(squeeze_me=True, struct_as_record=False, chars_as_strings=True)
_PROBE = f"import sys, scipy.io\ntry: scipy.io.loadmat(sys.argv[1], **{_LOADMAT!r})\nexcept BaseException: pass\n"


def read_mat(path: Path, file: str) -> Table:
    """A MATLAB v5/v7 file: vectors, (n, k) matrices (``M_1`` ... ``M_k``), cell arrays of strings and the fields
    of structs and struct arrays as columns (``S.vx0`` where two structs share a field name)."""
    import scipy.io
    from scipy.io.matlab import mat_struct

    # A damaged file can crash scipy's reader (one byte of a data-type tag): parse it in a child first.
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE, str(path)], capture_output=True,
                              timeout=MAT_PROBE_TIMEOUT_S, check=False)
    except subprocess.TimeoutExpired:
        raise DataError(f"reading it as a MATLAB file took over {MAT_PROBE_TIMEOUT_S:g} s; the file is damaged",
                        file=file) from None
    if proc.returncode != 0:
        signals = signal.Signals._value2member_map_
        how = (f"signal {signal.Signals(-proc.returncode).name}" if -proc.returncode in signals
               else f"exit status {proc.returncode}")
        raise DataError(f"the MATLAB reader (scipy.io.loadmat) crashed on it ({how}): the file is damaged; save it "
                        "again from MATLAB or write a CSV", file=file)
    try:
        raw = scipy.io.loadmat(str(path), **_LOADMAT)
    except NotImplementedError:
        raise DataError("MATLAB v7.3 (HDF5) files cannot be read; in MATLAB save it with save(name, ..., '-v7') or "
                        "write a CSV", file=file) from None
    except Exception as exc:
        raise DataError(f"cannot read it as a MATLAB .mat file ({type(exc).__name__}: {exc})", file=file) from None
    entries: list[tuple[str, str | None, Any]] = []  # (name, struct, values)
    opaque: list[str] = []

    def collect(name: str, parent: str | None, val: Any) -> None:
        qual = name if parent is None else f"{parent}.{name}"
        if isinstance(val, mat_struct):
            for f in val._fieldnames:
                collect(f, qual, getattr(val, f))
        elif isinstance(val, int | float | str | np.number) and not isinstance(val, bool):
            entries.append((name, parent, [val]))
        elif not isinstance(val, np.ndarray):
            opaque.extend([] if isinstance(val, bool) else [qual])
        elif val.dtype.kind == "O" and val.size and all(isinstance(e, mat_struct) for e in val.flat):
            for f in next(iter(val.flat))._fieldnames:  # a struct array: one scalar per element
                cells = [_scalar(getattr(e, f, None)) for e in val.flat]
                entries.extend([(f, qual, cells)] if all(c is not None for c in cells) else [])
        elif val.dtype.kind in "iuf" and val.ndim <= 2:
            cols = [(name, val.reshape(-1))] if val.ndim < 2 else [(f"{name}_{k + 1}", val[:, k])
                                                                   for k in range(val.shape[1])]
            entries.extend((n, parent, v.astype(float)) for n, v in cols)
        elif val.dtype.kind == "U":
            entries.append((name, parent, [str(v) for v in np.atleast_1d(val)]))
        elif val.dtype.kind == "O" and val.ndim == 1 and None not in (cells := [_scalar(e) for e in val]):
            entries.append((name, parent, cells))

    for name, val in raw.items():
        if not name.startswith("__"):
            collect(name, None, val)
    shorts = [e[0] for e in entries]
    columns = [(f"{parent}.{n}" if parent and shorts.count(n) > 1 else n, v) for n, parent, v in entries]
    if not columns:
        hint = f"; {opaque} cannot be read (a MATLAB table? save table2struct(T, 'ToScalar', true))" if opaque else ""
        raise DataError(f"the file holds no numeric vectors, matrices or structs{hint}", file=file)
    return _arrays(file, columns, {})


def open_netcdf(path: Path, file: str) -> xr.Dataset:
    try:
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            return ds.load()
    except Exception as exc:
        hint = "" if module_available("netCDF4") or module_available("h5netcdf") else (
            " (a netCDF-4/HDF5 file needs pip install h5netcdf or netCDF4)")
        raise DataError(f"cannot read it as netCDF: {exc}{hint}", file=file) from None


def table_from_dataset(ds: xr.Dataset, file: str) -> Table:
    """A netCDF file that is not a campaign: each 1-D variable a column (an (n, k) one ``V_1`` ... ``V_k``), its
    unit from its name or else its CF ``units`` attribute."""
    columns, units = [], {}
    for name, var in ds.variables.items():
        vals = var.values
        if vals.dtype.kind == "S":
            vals = np.array([v.decode("utf-8", "replace") for v in vals.reshape(-1)]).reshape(vals.shape)
        split = [(f"{name}_{k + 1}", vals[:, k]) for k in range(vals.shape[1])] if vals.ndim == 2 else []
        for col, v in [(str(name), vals)] if vals.ndim == 1 else split:
            cf = var.attrs.get("units")
            if isinstance(cf, str) and cf.strip():
                units[col] = (cf.strip(), "units attribute")
            columns.append((col, v.astype(float) if v.dtype.kind == "f" else v if v.dtype.kind in "iu" else list(v)))
    return _arrays(file, columns, units)
