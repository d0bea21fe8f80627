"""The format backends: each reads one kind of file (or a DataFrame) into one :class:`Table`.

A backend finds the header, a units row under it and where each row is in the file; what the cells mean is for
:mod:`bouncelab.data.io.interpret`. pandas reads text tables (the delimiter told by :class:`csv.Sniffer`) and
workbooks, ``scipy.io.loadmat`` MATLAB files, xarray netCDF files. :data:`BACKENDS` maps each suffix to its backend.
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
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache
from itertools import islice
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core.errors import DataError, Hint
from bouncelab.core.files import read_regular_file
from bouncelab.data.io.names import is_number, is_units_row, unit_cell

#: The name a DataFrame has in messages (``file '<DataFrame>', column 'vy0', row 3 (row label 'b7'): ...``).
DATAFRAME_NAME = "<DataFrame>"
# Cells a person reads as "no value": spreadsheet error codes and the usual placeholders.
MISSING = frozenset({"", "na", "n/a", "n.a.", "nan", "null", "none", "missing", "-", "--", "?", "#n/a", "#na",
                     "#value!", "#ref!", "#div/0!", "#num!", "#name?", "#null!"})
_BREAK = re.compile(rb"\r\n|\r|\n")  # lines end at these only, as in spreadsheets
NETCDF_SUFFIXES = (".nc", ".netcdf")
#: Seconds the crash probe of a ``.mat`` file may take before the file is refused.
MAT_PROBE_TIMEOUT_S = 60.0
_LOADMAT = dict(squeeze_me=True, struct_as_record=False, chars_as_strings=True)
_PROBE = f"import sys, scipy.io\ntry: scipy.io.loadmat(sys.argv[1], **{_LOADMAT!r})\nexcept BaseException: pass\n"


def module_available(name: str) -> bool:
    return importlib.util.find_spec(name) is not None


def is_empty(v: Any) -> bool:
    """An empty cell: None, NaN, pd.NA, blank text."""
    return (isinstance(v, str) and not v.strip()) or (not isinstance(v, str) and bool(pd.isna(v)))


@dataclass(frozen=True)
class Table:
    """A file's data rows (``cells``: names as in the file; numbers where the format or pandas typed a whole
    column, else the cells as written); ``units``: column -> (unit, where) given beside the names; ``locate(row,
    column)``: where data row ``row`` (0-based) is (``"line 5"``, ``"cell E5 of sheet 'B'"``); ``text(column)``: a
    text file's cells as written; ``labels``: a DataFrame's row labels; ``delimiter``: a text file's (not a comma:
    decimal commas may be written); ``lengths``: each column's length in a file of separate arrays (padded)."""

    file: str
    cells: pd.DataFrame
    units: Mapping[str, tuple[str, str]] = field(default_factory=dict)
    locate: Callable[[int, str | None], str] | None = None
    text: Callable[[str], list[str]] | None = None
    labels: list | None = None
    delimiter: str | None = ","
    lengths: Mapping[str, int] | None = None


def check_names(names: Sequence[str], file: str) -> None:
    """A header names each column once."""
    for j, name in enumerate(names):
        if name and (k := list(names).index(name)) != j:
            raise DataError(f"the header names column {name!r} twice (columns {k + 1} and {j + 1}); rename one of them",
                            file=file, column=name)


def units_row(names: Sequence[str], cells: Sequence, blank: Callable[[Any], bool]) -> dict[str, tuple[str, str]]:
    """The units a row under the header gives (``m/s, m/s, rpm``), or {} if it is no units row."""
    if not cells or not is_units_row(list(cells)[: len(names)], blank):
        return {}
    return {n: (unit_cell(c), "units row") for n, c in zip(names, cells, strict=False)
            if n and not blank(c) and unit_cell(c)}


def looks_like_title(title: list, header: list, first_row: list, blank: Callable[[Any], bool]) -> bool:
    """Whether a line above the header is a title: fewer cells and no number, under it a header then data or units."""
    t, h, d = ([c for c in row if not blank(c)] for row in (title, header, first_row))
    return (0 < len(t) < len(h) and len(h) >= 2 and not any(map(is_number, t)) and not any(map(is_number, h))
            and (any(map(is_number, d)) or is_units_row(first_row, blank)))


def is_comment(line: str) -> bool:
    return line.lstrip().startswith(("#", "%"))


def _split(line: str, delim: str | None) -> list[str]:
    return line.split() if delim is None else next(csv.reader([line], delimiter=delim))


def _sniff(lines: list[str]) -> str | None:
    """Tab, semicolon or comma, as :class:`csv.Sniffer` tells (else what splits the header most); None: blanks."""
    try:
        delim = csv.Sniffer().sniff("\n".join(lines), delimiters="\t;,").delimiter
    except csv.Error:
        delim = max("\t;,", key=lines[0].count)
    return delim if lines[0].count(delim) else None


def _data_shaped(cells: list[str], width: int) -> bool:
    """Whether a ``#`` line is shaped like a row: the header's width give or take one, at least half of it numbers."""
    while cells and not cells[-1]:
        cells = cells[:-1]
    return width >= 2 and abs(len(cells) - width) <= 1 and sum(map(is_number, cells[1:])) * 2 >= len(cells) - 1


def encoding(raw: bytes) -> str:
    """UTF-8 (with or without a BOM) if ``raw`` is, else Latin-1."""
    if not raw.isascii():
        try:
            raw.decode("utf-8-sig")
        except UnicodeDecodeError:
            return "latin-1"
    return "utf-8"


class Line(NamedTuple):
    no: int  # 1-based
    text: str
    start: int  # its first byte
    end: int  # the byte after its line break


def lines(raw: bytes, start: int = 0, enc: str = "latin-1", first: int = 1):
    """The non-blank lines of ``raw`` from byte ``start`` (line ``first``)."""
    pos, no = start, first
    for m in _BREAK.finditer(raw, start):
        if (text := raw[pos:m.start()].decode(enc)).strip():
            yield Line(no, text, pos, m.end())
        pos, no = m.end(), no + 1
    if (text := raw[pos:].decode(enc)).strip():
        yield Line(no, text, pos, len(raw))


class _Header(NamedTuple):
    names: list[str]
    delim: str | None  # None: runs of blanks
    units: dict[str, tuple[str, str]]
    at: int  # the byte where the data lines start
    first_no: int  # the line number of the first of them


def _titles_above(text: list[str], k: int, h: int) -> bool:
    """Whether line ``h`` is the header and the lines from ``k`` to it are titles (:func:`looks_like_title`)."""
    below = [t for t in text[h:h + 50] if not is_comment(t)]
    if len(below) < 2 or is_comment(text[h]):
        return False
    delim = _sniff(below)
    try:
        header, first, *titles = (_split(t, delim) for t in (*below[:2], *text[k:h]) if not is_comment(t))
    except csv.Error:
        return False
    return all(looks_like_title(t, header, first, lambda c: not c.strip()) for t in titles)


def _find_header(file: str, raw: bytes, head: list[Line], header_row: int | None) -> _Header:
    """The header (line ``header_row``, else the first neither a comment nor a title), its delimiter, its units row."""
    text = [ln.text for ln in head]
    if (k := next((k for k, t in enumerate(text) if not is_comment(t)), None)) is None:
        raise DataError("the file is empty (no header, no data)", file=file)
    if header_row is None:
        h = next((h for h in range(k + 1, min(k + 11, len(head) - 1)) if _titles_above(text, k, h)), k)
    elif (h := next((j for j, ln in enumerate(head) if ln.no == header_row), None)) is None:
        said = (f"the file has {n} lines" if header_row > (n := len(raw.splitlines())) else
                f"line {header_row} is blank; a header names the columns")
        raise DataError(f"header row {header_row}: {said}", file=file)
    below = [t for t in text[h + 1:h + 50] if not is_comment(t)]
    delim = _sniff([text[h], *below])
    try:
        names = [c.strip() for c in _split(text[h], delim)] if delim is not None else [
            n.replace("\x00", " ") for n in re.sub(r"\s+(?=[\[\(\{][^\s\]\)\}]*[\]\)\}](\s|$))", "\x00",
                                                 text[h]).split()]  # "vx0 [m/s]" is one name
        list(csv.reader(below, delimiter=delim or " "))  # a cell beyond the csv module's limit is no number
    except csv.Error as exc:
        raise DataError(f"line {head[h].no}: cannot split the header or the lines under it: {exc}", file=file) from None
    while names and not names[-1]:
        names.pop()
    check_names(names, file)
    k = next((k for k in range(h + 1, len(head)) if not is_comment(text[k])), None)
    if k is not None and not any(_data_shaped(_split(t, delim), len(names)) for t in text[h + 1:k]):
        cells = _split(text[k], delim)  # a units row is the first row: not under a commented-out row
        if (delim is not None or len(cells) == len(names)) and (units := units_row(names, cells, lambda c: not c)):
            return _Header(names, delim, units, head[k].end, head[k].no + 1)
    return _Header(names, delim, {}, head[h].end, head[h].no + 1)


def _wrong_width(file: str, hd: _Header, given: bool, lineno: int, n: int, row: int) -> DataError:
    width = len(hd.names)
    if given:
        return DataError(f"line {lineno} has {n} values; a row needs {width} ({' '.join(hd.names)})", file=file,
                         row=row)
    if hd.delim is None:  # runs of blanks separate the cells: an empty cell cannot be seen
        return DataError(f"line {lineno} has {n} values but the header names {width} columns; in a whitespace-"
                         "separated file an empty cell cannot be told from the separator: write NA in it, or use a "
                         "comma- or tab-separated file", file=file, row=row)
    return DataError(f"the row has {n} values but the header names {width} columns (line {lineno})", file=file,
                     row=row)


def _uncommented(file: str, raw: bytes, enc: str, hd: _Header) -> tuple[bytes, int]:
    """The data (``raw`` from byte ``at``) with its comment lines emptied, one shaped like a row refused."""
    cut: list[tuple[int, int]] = []  # (start, end) of each comment line's text
    lo = hd.at  # the start of the line of the mark before: each byte is searched once
    for k in sorted(k for mark in (b"#", b"%") for k in _finds(raw, mark, hd.at)):  # bytes.find: at memory speed
        lo = start = max(raw.rfind(b"\n", lo, k), raw.rfind(b"\r", lo, k), lo - 1) + 1
        if raw[start:k].strip():
            continue  # a mark within a line ("3 # note" is a cell)
        end = m.start() if (m := _BREAK.search(raw, k)) else len(raw)
        if _data_shaped(cells := _split(text := raw[start:end].decode(enc), hd.delim), len(hd.names)):
            if cells[0].strip().lower() in MISSING:
                continue  # "#N/A,20.1,...": a row with a missing value
            above = list(lines(raw[:end], hd.at, enc, hd.first_no))
            mark, row = text.lstrip()[0], sum(ln.start not in dict(cut) for ln in above[:-1]) + 1
            raise DataError(f"line {above[-1].no} starts with {mark!r} like a comment but holds a row of {len(cells)} "
                            f"values like the data: delete the line if it is commented out, or remove the {mark!r}",
                            file=file, row=row)
        cut.append((start, end))
    if not cut:
        return raw, hd.at
    bounds = [hd.at, *(b for span in cut for b in span), len(raw)]
    return b"".join(raw[a:b] for a, b in zip(bounds[::2], bounds[1::2], strict=True)), 0


def _finds(raw: bytes, mark: bytes, at: int):
    k = raw.find(mark, at)
    while k >= 0:
        yield k
        k = raw.find(mark, k + 1)


def read_text(path: Path | None, file: str, *, raw: bytes | None = None, header_row: int | None = None,
              names: Sequence[str] | None = None) -> Table:
    """A ``.csv``, ``.tsv`` or ``.txt`` table (``raw``, else read from ``path``): UTF-8 (a BOM is fine) else Latin-1;
    see docs/data.md. With ``names`` the file has no header: every line that is not a comment is a row of these
    columns, blank-separated. The bytes stay in memory: messages quote cells as written and name their lines."""
    raw = read_regular_file(path, file) if raw is None else raw
    if b"\x00" in raw:
        raise DataError("the file holds NUL bytes: it is not a text table (a binary or damaged file?)", file=file)
    enc = encoding(raw)
    start = len(codecs.BOM_UTF8) if enc == "utf-8" and raw.startswith(codecs.BOM_UTF8) else 0
    head = list(islice(lines(raw, start, enc), max(64, (header_row or 0) + 51)))  # the non-blank lines of the head
    given = names is not None
    hd = _Header(list(names), None, {}, start, 1) if given else _find_header(file, raw, head, header_row)
    body, at = _uncommented(file, raw, enc, hd)
    width, delim = len(hd.names), hd.delim
    frame = _parse(file, body, at, delim, width, enc, as_text=delim != ",")
    if delim == "\t":  # a line of tabs is a blank line
        frame = frame[frame.ne("").any(axis=1)].reset_index(drop=True)
    linenos: list[int] = []

    def locate(row: int, column: str | None = None) -> str:
        if not linenos:  # found when a message asks
            linenos.extend(ln.no for ln in lines(body, at, enc, hd.first_no))
        return f"line {linenos[row]}"

    bad = frame.iloc[:, width:].ne("").any(axis=1)  # a cell beyond the header's width
    if delim is None:
        bad |= frame.iloc[:, width - 1].eq("")  # a short row: no empty cell can be seen
    if bad.any():
        cells = frame.iloc[i := int(np.argmax(bad.to_numpy()))].ne("").to_numpy()
        n = int(cells.nonzero()[0].max()) + 1 if delim is not None else int(cells.sum())
        raise _wrong_width(file, hd, given, int(locate(i).split()[1]), n, i + 1)
    frame = frame.iloc[:, :width].set_axis(hd.names, axis=1)

    @cache
    def text(column: str) -> list[str]:
        if frame[column].dtype.kind == "O" and all(isinstance(v, str) for v in frame[column]):
            return frame[column].tolist()
        j = hd.names.index(column)
        return _parse(file, body, at, delim, width, enc, as_text=True, usecols=[j]).iloc[:, 0].tolist()

    return Table(file, frame, hd.units, locate, text, delimiter=delim)


def _parse(file: str, body: bytes, at: int, delim: str | None, width: int, enc: str, *, as_text: bool,
           usecols: list[int] | None = None) -> pd.DataFrame:
    """pandas' reading of ``body`` from ``at``: text (``as_text``) or typed columns, no NA; a longer row widens."""
    while True:
        (source := io.BytesIO(body)).seek(at)  # shares the bytes
        try:
            with warnings.catch_warnings():  # pandas types a long file chunk by chunk: a mixed column is cells
                warnings.simplefilter("ignore", pd.errors.DtypeWarning)
                warnings.simplefilter("error", pd.errors.ParserWarning)  # cells beyond ``width`` would be lost
                return pd.read_csv(source, sep=r"\s+" if delim is None else delim, header=None, index_col=False,
                                   names=range(width), usecols=usecols, dtype=str if as_text else None,
                                   na_filter=False, encoding=enc, quoting=csv.QUOTE_NONE if delim is None else 0,
                                   skipinitialspace=delim == "\t")
        except pd.errors.EmptyDataError:
            return pd.DataFrame(columns=range(width), dtype=object)
        except pd.errors.ParserWarning:  # the first row is the longer one
            width = 2 * width + 1
        except (pd.errors.ParserError, ValueError) as exc:
            more = re.search(r"Expected \d+ fields in line \d+, saw (\d+)", str(exc))
            if more is None or int(more.group(1)) <= width:
                raise DataError(f"cannot read it as a text table ({exc})", file=file) from None
            width = int(more.group(1))


def _col_letter(j: int) -> str:
    out, j = "", j + 1
    while j:
        j, r = divmod(j - 1, 26)
        out = chr(65 + r) + out
    return out


def read_excel(path: Path, file: str, *, sheet: str | int | None = None, header_row: int | None = None) -> Table:
    """One sheet of an ``.xlsx`` (openpyxl) or ``.xls`` (xlrd) workbook: the first visible one, or ``sheet``."""
    old, suffix = path.suffix.lower() == ".xls", path.suffix.lower()
    if not module_available(package := "xlrd" if old else "openpyxl"):
        raise DataError(f"reading {'an old-style' if old else 'an'} Excel workbook ({suffix}) needs the package "
                        f"{package}: pip install 'bouncelab[excel]' (or pip install {package})"
                        f"{', or save it as .xlsx' if old else ''}", file=file)
    try:
        with pd.ExcelFile(path) as xf:
            names, book = list(xf.sheet_names), xf.book
            hidden = {ws.title for ws in getattr(book, "worksheets", []) if getattr(ws, "sheet_state", "") in (
                "hidden", "veryHidden")}  # openpyxl
            if hasattr(book, "sheet_by_index"):  # xlrd
                hidden |= {sh.name for sh in book.sheets() if getattr(sh, "visibility", 0)}
            if sheet is None and not (visible := [k for k, n in enumerate(names) if n not in hidden]):
                raise DataError(f"every sheet of the workbook is hidden ({names}); name the one to read", file=file,
                                hints=[Hint("sheet", names[0])])
            sheet = visible[0] if sheet is None else sheet  # the first sheet a person sees in Excel
            if isinstance(sheet, str) and sheet.isdigit() and sheet not in names:
                sheet = int(sheet)  # "1" (as a command line gives it): the sheet named "1", else the index 1
            if isinstance(sheet, int) and not isinstance(sheet, bool):
                if not 0 <= sheet < len(names):
                    raise DataError(f"sheet index {sheet} out of range; the workbook's sheets are {names}", file=file)
                sheet = names[sheet]
            if (name := str(sheet)) not in names:
                raise DataError(f"no sheet {sheet!r}; the workbook's sheets are {names}", file=file)
            grid = pd.read_excel(xf, sheet_name=name, header=None, dtype=object).values.tolist()
    except DataError:
        raise
    except Exception as exc:
        raise DataError(f"cannot read it as an Excel workbook ({type(exc).__name__}: {exc})", file=file) from None
    if not (keep := [k for k, r in enumerate(grid) if not all(map(is_empty, r))]):
        raise DataError(f"sheet {name!r} is empty (no header, no data)", file=file)
    if header_row is not None and (header_row > len(grid) or header_row - 1 not in keep):
        what = (f"sheet {name!r} has {len(grid)} rows" if header_row > len(grid) else
                f"row {header_row} of sheet {name!r} is empty; a header names the columns")
        raise DataError(f"header row {header_row}: {what}", file=file)
    keep = keep if header_row is None else keep[keep.index(header_row - 1):]
    while header_row is None and len(keep) > 2 and looks_like_title(*(grid[k] for k in keep[:3]), is_empty):
        keep = keep[1:]  # a title or note above the header
    header = ["" if is_empty(c) else str(c).strip() for c in grid[keep[0]]]
    while header and not header[-1]:
        header.pop()
    check_names(header, file)
    rows = [(grid[k] + [None] * len(header))[: len(header)] for k in keep[1:]]
    if rows and (units := units_row(header, rows[0], is_empty)):
        rows, keep = rows[1:], keep[1:]

    def locate(row: int, column: str | None = None) -> str:
        cell = f"cell {_col_letter(header.index(column))}" if column in header else "row "
        return f"{cell}{keep[row + 1] + 1} of sheet {name!r}"

    return Table(file, pd.DataFrame(rows, columns=header, dtype=object), units, locate, delimiter=",")


def read_dataframe(df: pd.DataFrame, file: str) -> Table:
    """A DataFrame read as a file: its column names are the header (a units row under it counts), its rows the data."""
    names = [" ".join(map(str, c)).strip() if isinstance(df.columns, pd.MultiIndex) else str(c).strip()
             for c in df.columns]
    if not names:
        raise DataError("the DataFrame has no columns", file=file)
    check_names(names, file)
    frame, labels = df.set_axis(names, axis=1).reset_index(drop=True), list(df.index)
    if len(frame) and (units := units_row(names, frame.iloc[0].tolist(), is_empty)):
        frame, labels = frame.iloc[1:].reset_index(drop=True).astype(object), labels[1:]
    return Table(file, frame, units if len(frame) else {}, labels=labels)


def _arrays(file: str, columns: list[tuple[str, Any]], units: dict[str, tuple[str, str]]) -> Table:
    """A table of separate arrays (``.mat``, netCDF), padded to the longest; the lengths are checked when read."""
    if not columns:
        raise DataError("the file holds no 1-D variables (columns)", file=file)
    frame = pd.concat([pd.Series(v, name=n, dtype=None if isinstance(v, np.ndarray) else object)
                       for n, v in columns], axis=1)
    return Table(file, frame, units, lengths={n: len(v) for n, v in columns})


def _scalar(v: Any) -> Any:
    """A MATLAB scalar (number or string) as a Python value, else ``None``."""
    if isinstance(v, np.ndarray) and v.size == 1:
        v = v.reshape(()).item()
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    ok = isinstance(v, int | float | str | np.number) and not isinstance(v, bool)
    return (v.item() if isinstance(v, np.number) else v) if ok else None


def read_mat(path: Path, file: str, **_: Any) -> Table:
    """A MATLAB v5/v7 file: vectors, matrices (``M_1``...), cell arrays of strings, struct fields (``S.vx0``)."""
    import scipy.io
    from scipy.io.matlab import mat_struct

    # A damaged file can crash scipy's reader (one byte of a data-type tag): parse it in a child first.
    try:
        code = subprocess.run([sys.executable, "-c", _PROBE, str(path)], capture_output=True,
                              timeout=MAT_PROBE_TIMEOUT_S, check=False).returncode
    except subprocess.TimeoutExpired:
        raise DataError(f"reading it as a MATLAB file took over {MAT_PROBE_TIMEOUT_S:g} s; the file is damaged",
                        file=file) from None
    if code != 0:
        how = f"signal {signal.Signals(-code).name}" if -code in signal.Signals._value2member_map_ else (
            f"exit status {code}")
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
                entries.extend([(f, qual, cells)] if None not in cells else [])
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


def read_netcdf(path: Path, file: str, **_: Any) -> Table | xr.Dataset:
    """A netCDF file: a campaign as its Dataset, any other a table of its 1-D variables (CF ``units`` kept)."""
    ds = open_netcdf(path, file)
    if "landing" in ds.data_vars or "liftoff" in ds.data_vars:
        return ds
    columns, units = [], {}
    for name, var in ds.variables.items():
        vals = var.values
        if vals.dtype.kind == "S":
            vals = np.array([v.decode("utf-8", "replace") for v in vals.reshape(-1)]).reshape(vals.shape)
        split = [(f"{name}_{k + 1}", vals[:, k]) for k in range(vals.shape[1])] if vals.ndim == 2 else []
        for col, v in [(str(name), vals)] if vals.ndim == 1 else split:
            if isinstance(cf := var.attrs.get("units"), str) and cf.strip():
                units[col] = (cf.strip(), "units attribute")
            columns.append((col, v.astype(float) if v.dtype.kind == "f" else v if v.dtype.kind in "iu" else list(v)))
    return _arrays(file, columns, units)


class Backend(NamedTuple):
    """How one kind of file is read, and the options that apply to it (``sheet``, ``header_row``)."""

    read: Callable[..., Table | xr.Dataset]
    options: tuple[str, ...] = ()


#: The backend of each suffix :func:`~bouncelab.data.io.load_campaign` reads (case-insensitive).
BACKENDS: dict[str, Backend] = {
    **dict.fromkeys((".csv", ".tsv", ".txt"), Backend(read_text, ("header_row",))),
    **dict.fromkeys((".xlsx", ".xls"), Backend(read_excel, ("sheet", "header_row"))),
    ".mat": Backend(read_mat),
    **dict.fromkeys(NETCDF_SUFFIXES, Backend(read_netcdf)),
}
