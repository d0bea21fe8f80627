"""Reading ``.csv``, ``.tsv`` and ``.txt`` tables: encoding, comment lines, delimiter sniffing."""

from __future__ import annotations

import csv
import re
from pathlib import Path

from bouncelab.core.errors import DataError
from bouncelab.data.io.fastcsv import read_plain_csv
from bouncelab.data.io.table import (
    _MISSING,
    _finish_table,
    _header_row_error,
    _looks_like_title,
    _parse_number,
    _Table,
)


def _read_text(path: Path, file: str, raw: bytes, *, header_row: int | None = None,
               style: str = "python") -> _Table:
    # A plain comma-separated file of numbers is read in bulk (the same table); a file with a chosen header
    # row, title lines or anything unusual takes the cell-by-cell path below.
    fast = read_plain_csv(file, raw, path) if header_row is None else None
    if fast is not None:
        return fast
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    if "\x00" in text:
        raise DataError("the file holds NUL bytes: it is not a text table (a binary or damaged file?)", file=file)
    # Lines end at \n, \r\n or \r only, as in the csv module and spreadsheets: str.splitlines would also
    # split at U+0085 (a Latin-1 "…" byte), form feeds and others.
    all_lines = re.split(r"\r\n|\r|\n", text)
    if all_lines and not all_lines[-1]:
        all_lines.pop()
    lines = [(i + 1, line) for i, line in enumerate(all_lines) if line.strip()]
    # Comment lines (# or %) before the header are skipped; after it, see _is_comment.
    k = 0
    while k < len(lines) and _starts_comment(lines[k][1]):
        k += 1
    if k == len(lines):
        raise DataError("the file is empty (no header, no data)", file=file)
    k = _header_index(lines, k, len(all_lines), file, header_row, style)
    header_no, header_line = lines[k]
    body = lines[k + 1:]
    delim = _sniff([header_line] + [line for _, line in body[:49] if not _starts_comment(line)])

    def split(line: str) -> list[str]:
        if delim is None:
            return line.split()
        return next(csv.reader([line], delimiter=delim))

    try:
        header = split(header_line)
    except csv.Error as exc:
        raise DataError(f"line {header_no}: cannot split the header: {exc}", file=file) from None
    if delim is None:
        header = _merge_bracket_tokens(header)
    names = [h.strip() for h in header]
    while names and not names[-1]:
        names.pop()
    linenos: list[int] = []
    rows: list[list[str]] = []
    for no, line in body:
        try:
            cells = [c.strip() for c in split(line)]
        except csv.Error as exc:
            raise DataError(f"line {no}: cannot split it into cells: {exc}", file=file, row=len(rows) + 1) from None
        if _starts_comment(line) and not _is_data_row(cells, len(names)):
            continue
        if _starts_comment(line) and cells[0].lower() not in _MISSING:
            raise DataError(
                f"line {no} starts with {line.lstrip()[0]!r} like a comment but holds a row of "
                f"{len(cells)} values like the data: delete the line if it is commented out, or remove "
                f"the {line.lstrip()[0]!r}", file=file, row=len(rows) + 1,
            )
        if delim is None and len(cells) != len(names):
            # Runs of blanks separate the cells: an empty cell cannot be seen, the next value slides in.
            raise DataError(
                f"line {no} has {len(cells)} values but the header names {len(names)} columns; in a "
                "whitespace-separated file an empty cell cannot be told from the separator: write NA "
                "in it, or use a comma- or tab-separated file", file=file, row=len(rows) + 1,
            )
        linenos.append(no)
        rows.append(cells)

    def locate(i: int, col: str) -> str:
        return f"line {linenos[i]}"

    table = _finish_table(file, names, rows, locate=locate, blank=lambda c: not c,
                          strict_width=True, decimal_comma=delim != ",")
    table.delimiter = delim
    return table


def _starts_comment(line: str) -> bool:
    return line.lstrip().startswith(("#", "%"))


def _is_data_row(cells: list[str], width: int) -> bool:
    """A line after the header that starts with ``#`` is data (``#N/A,20.1,...``) if it is shaped like a row:
    within one cell of the header's width (trailing separators not counted), at least half of it numbers."""
    while cells and not cells[-1]:
        cells = cells[:-1]
    if width < 2 or abs(len(cells) - width) > 1:
        return False
    numeric = sum(_parse_number(c) is not None for c in cells[1:])
    return numeric * 2 >= len(cells) - 1


def _merge_bracket_tokens(tokens: list[str]) -> list[str]:
    out: list[str] = []
    for t in tokens:
        if out and re.fullmatch(r"[\[\(\{].*[\]\)\}]", t):
            out[-1] += " " + t
        else:
            out.append(t)
    return out


def _sniff(lines: list[str]) -> str | None:
    """Delimiter of a text table: tab, semicolon or comma; ``None`` for whitespace."""
    best: tuple[str, int] | None = None
    for d in ("\t", ";", ","):
        try:
            counts = [len(next(csv.reader([line], delimiter=d))) for line in lines]
        except csv.Error:
            continue
        n = counts[0]
        if n < 2:
            continue
        agree = sum(c == n for c in counts[1:])
        if len(counts) > 1 and agree * 2 < len(counts) - 1:
            continue
        if best is None or n > best[1]:
            best = (d, n)
    return None if best is None else best[0]


def _header_index(lines: list[tuple[int, str]], k: int, n_lines: int, file: str, header_row: int | None,
                  style: str) -> int:
    """Index in ``lines`` of the header: line ``header_row`` (1-based, every line counted), else the first
    line ``k`` that is not a comment, or the first line after it below which title lines end (see
    _looks_like_title: every line above it is a title, it is a header and the line under it data)."""
    if header_row is not None:
        if header_row > n_lines:
            raise _header_row_error(file, header_row, f"the file has {n_lines} lines", style)
        found = [j for j, (no, _) in enumerate(lines) if no == header_row]
        if not found:
            raise _header_row_error(file, header_row, f"line {header_row} is blank; a header names the columns",
                                    style)
        return found[0]
    for h in range(k + 1, min(k + 11, len(lines) - 1)):
        below = [line for _, line in lines[h:h + 50] if not _starts_comment(line)]
        above = [line for _, line in lines[k:h] if not _starts_comment(line)]
        if len(below) < 2 or _starts_comment(lines[h][1]):
            continue
        delim = _sniff(below)
        try:
            header, first, *titles = (line.split() if delim is None else next(csv.reader([line], delimiter=delim))
                                      for line in (below[0], below[1], *above))
        except csv.Error:
            continue
        if all(_looks_like_title(t, header, first, blank=lambda c: not c.strip()) for t in titles):
            return h
    return k
