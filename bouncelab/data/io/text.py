"""Reading ``.csv``, ``.tsv`` and ``.txt`` tables: encoding, comment lines, delimiter sniffing."""

from __future__ import annotations

import csv
import re
from pathlib import Path

from bouncelab.data.io.table import _finish_table, _Table
from bouncelab.errors import DataError


def _read_text(path: Path, file: str) -> _Table:
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    lines = [
        (i + 1, line) for i, line in enumerate(text.splitlines())
        if line.strip() and not line.lstrip().startswith(("#", "%"))
    ]
    if not lines:
        raise DataError("the file is empty (no header, no data)", file=file)
    delim = _sniff([line for _, line in lines[:50]])

    def split(line: str) -> list[str]:
        if delim is None:
            return line.split()
        return next(csv.reader([line], delimiter=delim))

    header = split(lines[0][1])
    if delim is None:
        header = _merge_bracket_tokens(header)
    names = [h.strip() for h in header]
    while names and not names[-1]:
        names.pop()
    linenos = [no for no, _ in lines[1:]]
    rows = [[c.strip() for c in split(line)] for _, line in lines[1:]]

    def locate(i: int, col: str) -> str:
        return f"line {linenos[i]}"

    return _finish_table(file, names, rows, locate=locate, blank=lambda c: not c,
                         strict_width=True, decimal_comma=delim != ",")


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
