"""Reading ``.xlsx`` (openpyxl) and ``.xls`` (xlrd) workbooks: one sheet, first non-empty row as header."""

from __future__ import annotations

from pathlib import Path

from bouncelab.core.errors import DataError
from bouncelab.data.io import hints
from bouncelab.data.io.table import (
    _finish_table,
    _header_row_error,
    _is_empty_cell,
    _looks_like_title,
    _module_available,
    _Table,
)

_EXCEL_SUFFIXES = (".xlsx", ".xls")


def _col_letter(j: int) -> str:
    out = ""
    j += 1
    while j:
        j, r = divmod(j - 1, 26)
        out = chr(65 + r) + out
    return out


def _hidden_sheets(xf) -> set[str]:
    """Names of the hidden (and very hidden) sheets of an open pandas.ExcelFile."""
    book = getattr(xf, "book", None)
    hidden: set[str] = set()
    for ws in getattr(book, "worksheets", []):  # openpyxl
        if getattr(ws, "sheet_state", "visible") != "visible":
            hidden.add(ws.title)
    for sh in getattr(book, "sheets", lambda: [])() if hasattr(book, "sheet_by_index") else []:  # xlrd
        if getattr(sh, "visibility", 0):
            hidden.add(sh.name)
    return hidden


def _read_excel(path: Path, file: str, sheet: str | int | None, *, header_row: int | None = None,
                style: str = "python") -> _Table:
    suffix = path.suffix.lower()
    # A missing reader is a DataError naming the file and what to install (the 'excel' extra has both).
    if suffix == ".xlsx" and not _module_available("openpyxl"):
        raise DataError("reading an Excel workbook (.xlsx) needs the package openpyxl: "
                        "pip install 'bouncelab[excel]' (or pip install openpyxl)", file=file)
    if suffix == ".xls" and not _module_available("xlrd"):
        raise DataError("reading an old-style Excel workbook (.xls) needs the package xlrd: "
                        "pip install 'bouncelab[excel]' (or pip install xlrd), or save it as .xlsx", file=file)
    import pandas as pd

    try:
        with pd.ExcelFile(path) as xf:
            names = list(xf.sheet_names)
            hidden = _hidden_sheets(xf)
            if sheet is None:
                visible = [k for k, n in enumerate(names) if n not in hidden]
                if not visible:
                    raise DataError(f"every sheet of the workbook is hidden ({names}); name one with "
                                    f"{hints.option('sheet', style)}", file=file)
                sheet = visible[0]  # the first sheet a person sees in Excel, not a hidden one
            if isinstance(sheet, int) and not isinstance(sheet, bool):
                if not 0 <= sheet < len(names):
                    raise DataError(
                        f"sheet index {sheet} out of range; the workbook's sheets are {names}",
                        file=file,
                    )
                sheet_name = names[sheet]
            elif str(sheet) in names:
                sheet_name = str(sheet)
            elif style == "cli" and str(sheet).strip().isdigit() and int(sheet) < len(names):
                sheet_name = names[int(sheet)]  # --sheet 1: no sheet of that name, so the 0-based index
            else:
                raise DataError(f"no sheet {sheet!r}; the workbook's sheets are {names}", file=file)
            df = pd.read_excel(xf, sheet_name=sheet_name, header=None, dtype=object)
    except DataError:
        raise
    except Exception as exc:
        raise DataError(f"cannot read it as an Excel workbook ({type(exc).__name__}: {exc})", file=file) from None

    grid = df.values.tolist()
    sheet_rows = list(range(1, len(grid) + 1))
    keep = [k for k, r in enumerate(grid) if not all(_is_empty_cell(c) for c in r)]
    if not keep:
        raise DataError(f"sheet {sheet_name!r} is empty (no header, no data)", file=file)
    if header_row is not None:
        if header_row > len(grid):
            raise _header_row_error(file, header_row, f"sheet {sheet_name!r} has {len(grid)} rows", style)
        if header_row - 1 not in keep:
            raise _header_row_error(file, header_row, f"row {header_row} of sheet {sheet_name!r} is empty; a "
                                    "header names the columns", style)
        first = keep.index(header_row - 1)
        keep = keep[first:]
    else:
        while len(keep) > 2 and _looks_like_title(grid[keep[0]], grid[keep[1]], grid[keep[2]], _is_empty_cell):
            keep = keep[1:]  # a title or note above the header
    header = grid[keep[0]]
    names_ = ["" if _is_empty_cell(c) else str(c).strip() for c in header]
    while names_ and not names_[-1]:
        names_.pop()
    data_idx = keep[1:]
    rows = [grid[k] for k in data_idx]
    col_of = {n: j for j, n in enumerate(names_) if n}

    def locate(i: int, col: str) -> str:
        r = sheet_rows[data_idx[i]]
        if col in col_of:
            return f"cell {_col_letter(col_of[col])}{r} of sheet {sheet_name!r}"
        return f"row {r} of sheet {sheet_name!r}"

    return _finish_table(file, names_, rows, locate=locate, blank=_is_empty_cell, strict_width=False)
