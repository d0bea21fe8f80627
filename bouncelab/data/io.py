"""Reading and writing bounce campaigns: CSV, TSV, text, Excel, MATLAB and netCDF.

:func:`load_campaign` turns a measurement file (one row per bounce) into a
campaign :class:`xarray.Dataset` in the paper's scaled units (see
:mod:`bouncelab.data.units` and :mod:`bouncelab.data.campaign`);
:func:`save_campaign` writes a campaign to netCDF so that :func:`load_campaign`
reads it back bit for bit.

Sources
-------
``"A"`` or ``"B"`` (a *string*, any case)
    The campaign embedded in the package (``bouncelab/data/files/campaign_A.nc``
    and ``campaign_B.nc``). Any other string, and any :class:`pathlib.Path`
    (so ``Path("A")`` is the file ``A``), is a file path.
``.csv``, ``.tsv``, ``.txt``
    Text table, first non-blank line is the header. The delimiter is sniffed
    (tab, semicolon, comma, else runs of whitespace). Lines starting with ``#``
    or ``%`` and blank lines are skipped. Encoding UTF-8 (a BOM is fine), else
    Latin-1. With a semicolon, tab or whitespace delimiter a decimal comma
    (``1,5``) is accepted. In a whitespace-delimited file a header name must not
    contain spaces, except a bracketed unit (``vx0 [m/s]`` is fine).
``.xlsx`` (``.xls``)
    First sheet, or ``sheet=`` (name or 0-based index); the first non-empty row
    is the header. Needs ``openpyxl`` (``pip install bouncelab[excel]``); ``.xls``
    needs ``xlrd``.
``.mat`` (MATLAB v5/v7, not v7.3)
    Each numeric vector of length n is a column named after the variable; an
    (n, k) matrix ``M`` gives columns ``M_1`` ... ``M_k`` (rows are bounces); a
    cell array of strings is a text column (e.g. the setting); the fields of a
    struct (``S.vx0``) or of a 1 x n struct array (``table2struct(T)``) are
    columns named after the field (``S.vx0`` if two structs share the field
    name). MATLAB ``table`` objects cannot be read: save
    ``table2struct(T, 'ToScalar', true)`` instead.
``.nc``, ``.netcdf``
    A file written by :func:`save_campaign` (it has ``landing`` and ``liftoff``
    variables) is loaded as is, attributes included. Any other netCDF file is a
    table: each 1-D variable is a column (an (n, k) variable gives ``V_1`` ...
    ``V_k``).

Columns
-------
A file holds one row per bounce and, for landing (touch-down, subscript 0) and
lift-off (subscript F), the horizontal velocity ``xdot``, the vertical
velocity ``ydot`` and the spin ``omega``; optionally a launcher setting (test
condition) label and the half-widths of the 95 % prediction intervals.

With ``columns=None`` the columns are found from the synonyms in
:data:`COLUMN_SYNONYMS`. Names are compared after *normalisation*: lower case,
``ω`` read as ``omega`` and ``ẋ`` as ``xdot``, and everything but letters and
digits removed, so ``"X_dot 0"``, ``"xdot0"`` and ``"x-dot-0"`` are the same
name. A header may end in a unit, which is not part of the name:
``"vx0 [m/s]"``, ``"Vx0 (m/s)"``, ``"omega0_rpm"``, ``"spin (rev/min)"``,
``"vx0 m/s"``. A name is *stem* + *phase* or, for a phase of two or more
characters and a stem of two or more, *phase* + *stem* (``in_vx``, not
``i_vx``; ``w_in``, not ``in_w``) or *phase* + *stem* + *phase*:

==========  =================================================================
stem        ``xdot``: xdot, dx, dxdt, vx, velx, xvel, xvelocity, velocityx, u,
            ux, horizontalvelocity, horizontalspeed, hvel, vh, vhoriz,
            vhorizontal
            ``ydot``: ydot, dy, dydt, vy, vely, yvel, yvelocity, velocityy, v,
            uy, verticalvelocity, verticalspeed, vvel, vv, vvert, vvertical
            ``omega``: omega, w, om, spin, spinrate, angularvelocity, angvel,
            omegaz, wz
landing     0, i, in, inb, inbound, incoming, incident, impact, land, landing,
            pre, before, initial, init, touchdown, td
lift-off    f, 1, out, outb, outbound, outgoing, rebound, lift, liftoff, post,
            after, final, takeoff, lo
==========  =================================================================

so the landing ``xdot`` is found under ``xdot0``, ``x_dot_0``, ``vx0``,
``vx_in``, ``u0``, ``xdot_in``, ``inbound_vx``, ``Landing Vx [m/s]``,
``Inbound horizontal velocity (m/s)``..., the lift-off one under ``xdotF``,
``vxF``, ``vx_out``, ``vx1``, ``outbound_vx``..., the spins under ``omega0``,
``w0``, ``spin0``, ``spin_in``, ``omegaF``, ``wF``, ``spin_out``... The
prediction-interval half-widths are the same names followed (or preceded) by
``pi``, ``pi95``, ``hw``, ``halfwidth``, ``ci``, ``ci95``, ``err``, ``error``,
``unc`` or ``uncertainty`` (``vx0_pi``, ``omegaF_err``); they are used only
when all three of a state are present. The setting column is one of
``setting(s)``, ``setting_id``, ``setting_no``, ``setting_number``,
``launcher_setting(s)``, ``condition(s)``, ``condition_id``,
``test_condition(s)``, ``group``, ``group_id``, ``setup``, ``config``,
``configuration``, ``case``, ``test_case``; numeric labels become integers
(``"01"`` becomes 1), other labels stay strings. If a role matches no column
or several, :func:`load_campaign` raises a
:class:`~bouncelab.errors.DataError` that lists the file's columns and spells
out the ``columns=`` argument to pass. A typical file that needs no argument::

    Test condition,Vx0 (m/s),Vy0 (m/s),Spin0 (rpm),VxF (m/s),VyF (m/s),SpinF (rpm)
    1,20.1,-15.2,3000,9.5,5.1,1500
    1,19.8,-15.0,3050,9.7,5.0,1480

With ``columns=`` given, it maps roles to the file's names::

    load_campaign("bounces.csv", columns={
        "landing": ["Vx in", "Vy in", "Spin in"],      # xdot0, ydot0, omega0
        "liftoff": ["Vx out", "Vy out", "Spin out"],   # xdotF, ydotF, omegaF
        "setting": "Test",                              # optional
        "landing_pi": ["dVx in", "dVy in", "dSpin in"], # optional
        "liftoff_pi": ["dVx out", "dVy out", "dSpin out"],
    })

Requested names are matched with the same tolerance (``"vx in"`` finds
``"VX_IN [m/s]"``); a name that matches two file columns is an error unless it
is spelled exactly as one of them. ``landing`` and ``liftoff`` are required;
only the roles listed are read.

Units
-----
Values are converted to scaled units (radii/s, rad/s) with the ball radius
``ball_radius_m``. The unit of a column is given by ``units=``
(``{"velocity": "m/s", "spin": "rpm"}``, either key optional, applying to the
prediction intervals too) and/or by the file: the unit at the end of the
column's header name or, failing that, a *units row* right under the header (a
row whose cells are units such as ``m/s``, ``rpm``). If both are given for a
column and disagree, the load fails; each column may have its own unit, and
the units read are recorded in the ``source_units`` attr. Known units are those of
:mod:`bouncelab.data.units` (velocity: m/s, ft/s, mph, km/h, radius/s = 1/s
= s^-1; spin: rad/s, rpm = rev/min = rot per min, rev/s = Hz, deg/s; ``1/s`` on a
spin column means rad/s). With no unit anywhere, velocities are taken as
radii/s and spins as rad/s, but a file whose median landing ``|ydot0|`` is
below 20 radii/s (0.43 m/s, no real golf landing) is refused as probably in
physical units. Whatever the units, a velocity above 10 000 radii/s (213 m/s)
or a spin above 5 000 rad/s (48 000 rpm) is refused as a unit mistake.
Examples::

    load_campaign("bounces.csv", units={"velocity": "m/s", "spin": "rpm"})
    load_campaign("bounces.xlsx", sheet="Campaign B", units={"spin": "rev/s"})
    load_campaign("scaled.txt")                      # radii/s and rad/s

A campaign netCDF file is already in scaled units: ``columns=`` and
``units=`` are refused, its stored ``ball_radius_m`` is kept, and
``campaign=``/``surface=`` replace the stored names only when given.

Errors
------
Every problem with the file is a :class:`~bouncelab.errors.DataError` whose
message names the file, the column as spelled in the file and the data row
(the first row under the header is row 1; blank and comment lines are not
counted, and the message also gives the line of a text file or the cell of a
spreadsheet). Nothing is written or kept when a load fails.
"""

from __future__ import annotations

import csv
import importlib.util
import math
import os
import re
import tempfile
import unicodedata
import warnings
import zipfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.data.campaign import make_campaign, validate_campaign
from bouncelab.data.units import (
    BALL_RADIUS_M,
    COMPONENTS,
    canonical_unit,
    spin_to_scaled,
    velocity_to_scaled,
)
from bouncelab.data.validation import as_states
from bouncelab.errors import DataError

__all__ = [
    "COLUMN_SYNONYMS",
    "EMBEDDED_CAMPAIGNS",
    "SUPPORTED_SUFFIXES",
    "load_campaign",
    "save_campaign",
]

#: File suffixes :func:`load_campaign` reads (case-insensitive).
SUPPORTED_SUFFIXES = (".csv", ".tsv", ".txt", ".xlsx", ".xls", ".mat", ".nc", ".netcdf")

#: Names of the campaigns shipped with the package (``load_campaign("A")``).
EMBEDDED_CAMPAIGNS = ("A", "B")

_NETCDF_SUFFIXES = (".nc", ".netcdf")
_EXCEL_SUFFIXES = (".xlsx", ".xls")

# Plausibility limits that catch a wrong unit (scaled units).
_MIN_MEDIAN_LANDING_YDOT = 20.0  # radii/s: 0.43 m/s
_MAX_VELOCITY = 10_000.0  # radii/s: 213 m/s
_MAX_SPIN = 5_000.0  # rad/s: 48 000 rpm

_STATES = ("landing", "liftoff")
_PI_STATES = ("landing_pi", "liftoff_pi")
_ROLE_KINDS = {"xdot": "velocity", "ydot": "velocity", "omega": "spin"}
_UNIT_KINDS = ("velocity", "spin")
_MISSING = {"", "na", "n/a", "null", "none", "-", "--", "?"}
_PER_SECOND = {"1/s", "s-1", "s^-1", "/s"}

# --------------------------------------------------------------------------
# Synonym table
# --------------------------------------------------------------------------

_STEMS: dict[str, tuple[str, ...]] = {
    "xdot": (
        "xdot", "dx", "dxdt", "vx", "velx", "xvel", "xvelocity", "velocityx", "u", "ux",
        "horizontalvelocity", "horizontalspeed", "hvel", "vh", "vhoriz", "vhorizontal",
    ),
    "ydot": (
        "ydot", "dy", "dydt", "vy", "vely", "yvel", "yvelocity", "velocityy", "v", "uy",
        "verticalvelocity", "verticalspeed", "vvel", "vv", "vvert", "vvertical",
    ),
    "omega": (
        "omega", "w", "om", "spin", "spinrate", "angularvelocity", "angvel", "omegaz", "wz",
    ),
}
_PHASES: dict[str, tuple[str, ...]] = {
    "landing": (
        "0", "i", "in", "inb", "inbound", "incoming", "incident", "impact", "land", "landing",
        "pre", "before", "initial", "init", "touchdown", "td",
    ),
    "liftoff": (
        "f", "1", "out", "outb", "outbound", "outgoing", "rebound", "lift", "liftoff", "post",
        "after", "final", "takeoff", "lo",
    ),
}
_PI_MARKERS = ("pi", "pi95", "hw", "halfwidth", "ci", "ci95", "err", "error", "unc", "uncertainty")
_SETTING_NAMES = (
    "setting", "settings", "settingid", "settingno", "settingnumber", "launchersetting",
    "launchersettings", "condition", "conditions", "conditionid", "testcondition",
    "testconditions", "group", "groupid", "setup", "config", "configuration", "case", "testcase",
)


#: The synonym table used when ``columns=None``, in normalised form (see the
#: module docstring): the stems of each component, the landing and lift-off
#: phase markers, the prediction-interval markers and the setting names. A
#: state column is ``stem + phase``, ``phase + stem`` or ``phase + stem +
#: phase`` (both phases of the same state; a phase before the stem must have
#: two or more characters and the stem too); a prediction-interval column is a
#: state column name with a ``pi`` marker before or after it.
COLUMN_SYNONYMS: dict[str, tuple[str, ...]] = {
    **_STEMS, **_PHASES, "pi": _PI_MARKERS, "setting": _SETTING_NAMES,
}


# Common column names that the rules below would otherwise read as bounce data.
_NOT_SYNONYMS = frozenset({"indx"})


def _build_state_keys() -> dict[str, str]:
    table: dict[str, str] = {}
    for state, phases in _PHASES.items():
        # A phase before the stem must be a word ("in_vx", not "i_vx" or "ivy"), and
        # one-letter stems take it only after ("w_in", but not "low" or "prev").
        prefixes = [ph for ph in phases if len(ph) > 1]
        for comp, stems in _STEMS.items():
            role = f"{state}.{comp}"
            for stem in stems:
                keys = {stem + ph for ph in phases}
                if len(stem) > 1:
                    keys.update(pre + stem for pre in prefixes)
                    keys.update(pre + stem + ph for pre in prefixes for ph in phases)
                for key in keys - _NOT_SYNONYMS:
                        if table.setdefault(key, role) != role:  # pragma: no cover - checked in tests
                            raise AssertionError(f"synonym {key!r} is both {table[key]} and {role}")
    return table


_STATE_KEYS = _build_state_keys()
_SETTING_KEYS = frozenset(_SETTING_NAMES)
_ROLES = (
    *(f"{s}.{c}" for s in (*_STATES, *_PI_STATES) for c in COMPONENTS),
    "setting",
)


def _role_of(key: str) -> str | None:
    """The role a normalised column name stands for, per :data:`COLUMN_SYNONYMS`."""
    if key in _SETTING_KEYS:
        return "setting"
    if key in _STATE_KEYS:
        return _STATE_KEYS[key]
    for m in _PI_MARKERS:
        for rest in (key[: -len(m)] if key.endswith(m) else None,
                     key[len(m):] if key.startswith(m) else None):
            if rest and rest in _STATE_KEYS:
                state, comp = _STATE_KEYS[rest].split(".")
                return f"{state}_pi.{comp}"
    return None


# --------------------------------------------------------------------------
# Names and units
# --------------------------------------------------------------------------


def _normalize(name: str) -> str:
    """Lower-case letters and digits only; ``ω`` -> omega, ``ẋ`` -> xdot."""
    text = unicodedata.normalize("NFKD", str(name))
    text = text.replace("ω", "omega").replace("Ω", "omega").replace("\u0307", "dot")
    return re.sub(r"[^a-z0-9]", "", text.lower())


def _unit_of(text: str) -> dict[str, str]:
    """Canonical unit of ``text`` per kind it is valid for (empty if not a unit)."""
    found = {}
    for kind in _UNIT_KINDS:
        try:
            found[kind] = canonical_unit(text, kind)
        except DataError:
            pass
    if "spin" not in found and str(text).strip().lower().replace(" ", "") in _PER_SECOND:
        found["spin"] = "rad/s"  # 1/s, s^-1 on a spin column: rad/s
    return found


_BRACKET = re.compile(r"^(.*?)[\s_]*[\[\(\{]([^\[\]\(\)\{\}]*)[\]\)\}]\s*$")


def _split_header(name: str) -> tuple[str, str | None]:
    """Split ``"vx0 [m/s]"`` into ``("vx0", "m/s")``; ``(name, None)`` without a unit."""
    m = _BRACKET.match(name)
    if m and m.group(1).strip():
        return m.group(1).strip(), m.group(2).strip()
    tokens = [t for t in re.split(r"[\s_]+", name.strip()) if t]
    for k in (3, 2, 1):
        if len(tokens) > k:
            for joiner in ("", "/"):
                cand = joiner.join(tokens[-k:])
                if _unit_of(cand):
                    return " ".join(tokens[:-k]), cand
    return name, None


# --------------------------------------------------------------------------
# Tables read from files
# --------------------------------------------------------------------------


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


def _col_letter(j: int) -> str:
    out = ""
    j += 1
    while j:
        j, r = divmod(j - 1, 26)
        out = chr(65 + r) + out
    return out


def _read_excel(path: Path, file: str, sheet: str | int | None) -> _Table:
    suffix = path.suffix.lower()
    if suffix == ".xlsx" and not _module_available("openpyxl"):
        raise ImportError(
            f"reading the Excel file {file!r} needs openpyxl: pip install bouncelab[excel]"
        )
    if suffix == ".xls" and not _module_available("xlrd"):
        raise ImportError(
            f"reading the old-style Excel file {file!r} needs xlrd: pip install xlrd "
            "(or save it as .xlsx and pip install bouncelab[excel])"
        )
    import pandas as pd

    try:
        with pd.ExcelFile(path) as xf:
            names = list(xf.sheet_names)
            if sheet is None:
                sheet = 0
            if isinstance(sheet, int) and not isinstance(sheet, bool):
                if not 0 <= sheet < len(names):
                    raise DataError(
                        f"sheet index {sheet} out of range; the workbook's sheets are {names}",
                        file=file,
                    )
                sheet_name = names[sheet]
            elif str(sheet) in names:
                sheet_name = str(sheet)
            else:
                raise DataError(f"no sheet {sheet!r}; the workbook's sheets are {names}", file=file)
            df = pd.read_excel(xf, sheet_name=sheet_name, header=None, dtype=object)
    except DataError:
        raise
    except (ValueError, OSError, KeyError, zipfile.BadZipFile) as exc:
        raise DataError(f"cannot read it as an Excel workbook: {exc}", file=file) from None

    def blank(c: Any) -> bool:
        return c is None or (isinstance(c, float) and math.isnan(c)) or (isinstance(c, str) and not c.strip())

    grid = df.values.tolist()
    sheet_rows = list(range(1, len(grid) + 1))
    keep = [k for k, r in enumerate(grid) if not all(blank(c) for c in r)]
    if not keep:
        raise DataError(f"sheet {sheet_name!r} is empty (no header, no data)", file=file)
    header = grid[keep[0]]
    names_ = ["" if blank(c) else str(c).strip() for c in header]
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

    return _finish_table(file, names_, rows, locate=locate, blank=blank, strict_width=False)


def _module_available(name: str) -> bool:
    return importlib.util.find_spec(name) is not None


def _read_mat(path: Path, file: str) -> _Table:
    import scipy.io
    from scipy.io.matlab import mat_struct

    try:
        raw = scipy.io.loadmat(str(path), squeeze_me=True, struct_as_record=False, chars_as_strings=True)
    except NotImplementedError:
        raise DataError(
            "MATLAB v7.3 (HDF5) files cannot be read; in MATLAB save it with "
            "save(name, ..., '-v7') or write a CSV", file=file,
        ) from None
    except (ValueError, TypeError, OSError) as exc:
        raise DataError(f"cannot read it as a MATLAB .mat file: {exc}", file=file) from None

    entries: list[tuple[str, str, bool, Any]] = []  # (short, qualified, from_struct, values)
    opaque: list[str] = []

    def add(short: str, parent: str | None, values: Any) -> None:
        qual = short if parent is None else f"{parent}.{short}"
        entries.append((short, qual, parent is not None, values))

    def collect(name: str, parent: str | None, val: Any) -> None:
        qual = name if parent is None else f"{parent}.{name}"
        if isinstance(val, mat_struct):
            for f in val._fieldnames:
                collect(f, qual, getattr(val, f))
            return
        if isinstance(val, bool):
            return
        if isinstance(val, int | float | str | np.number):
            add(name, parent, [val])
            return
        if not isinstance(val, np.ndarray):
            opaque.append(qual)
            return
        if val.dtype.kind == "O" and val.size and all(isinstance(e, mat_struct) for e in val.flat):
            elems = list(val.flat)
            for f in elems[0]._fieldnames:
                cells = [_scalar(getattr(e, f, None)) for e in elems]
                if all(c is not None for c in cells):
                    add(f, qual, cells)
            return
        if val.dtype.kind in "iuf":
            if val.ndim == 0:
                add(name, parent, val.reshape(1).astype(float))
            elif val.ndim == 1:
                add(name, parent, val.astype(float))
            elif val.ndim == 2:
                for k in range(val.shape[1]):
                    add(f"{name}_{k + 1}", parent, val[:, k].astype(float))
            return
        if val.dtype.kind == "U":
            add(name, parent, [str(v) for v in np.atleast_1d(val)])
            return
        if val.dtype.kind == "O" and val.ndim == 1:
            cells = [_scalar(e) for e in val]
            if all(c is not None for c in cells):
                add(name, parent, cells)

    for name, val in raw.items():
        if not name.startswith("__"):
            collect(name, None, val)

    counts: dict[str, int] = {}
    for short, *_ in entries:
        counts[short] = counts.get(short, 0) + 1
    columns = []
    for short, qual, from_struct, values in entries:
        name = qual if (from_struct and counts[short] > 1) else short
        columns.append(_Column(name, values, *_header_unit(name)))
    _check_duplicates([c.name for c in columns], file)
    if not columns:
        hint = (f"; {opaque} cannot be read (a MATLAB table? save table2struct(T, 'ToScalar', true))"
                if opaque else "")
        raise DataError(f"the file holds no numeric vectors, matrices or structs{hint}", file=file)
    return _table_of_columns(file, columns)


def _scalar(v: Any) -> Any:
    """A MATLAB scalar (number or string) as a Python value, else ``None``."""
    if isinstance(v, np.ndarray):
        if v.size != 1:
            return None
        v = v.reshape(()).item()
    if isinstance(v, bool):
        return None
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, int | float | str | np.number):
        return v.item() if isinstance(v, np.number) else v
    return None


def _header_unit(name: str) -> tuple[str | None, bool]:
    unit = _split_header(name)[1]
    return unit, unit is not None


def _check_duplicates(names: list[str], file: str) -> None:
    seen = set()
    for n in names:
        if n in seen:
            raise DataError(f"two columns are named {n!r}; rename one of them", file=file, column=n)
        seen.add(n)


def _table_of_columns(file: str, columns: list[_Column]) -> _Table:
    """A table from whole columns (MATLAB, netCDF); lengths are checked once selected."""
    return _Table(file, columns, max(len(c.values) for c in columns), text_cells=False)


def _open_netcdf(path: Path, file: str) -> xr.Dataset:
    try:
        with xr.open_dataset(path, decode_times=False, decode_timedelta=False) as ds:
            return ds.load()
    except (ValueError, OSError, TypeError) as exc:
        hint = ""
        if not (_module_available("netCDF4") or _module_available("h5netcdf")):
            hint = " (a netCDF-4/HDF5 file needs pip install h5netcdf or netCDF4)"
        raise DataError(f"cannot read it as netCDF: {exc}{hint}", file=file) from None


def _table_from_dataset(ds: xr.Dataset, file: str) -> _Table:
    columns = []
    for name, var in ds.variables.items():
        vals = var.values
        if vals.ndim == 1:
            columns.append(_Column(str(name), _dataset_values(vals), *_header_unit(str(name))))
        elif vals.ndim == 2:
            for k in range(vals.shape[1]):
                sub = f"{name}_{k + 1}"
                columns.append(_Column(sub, _dataset_values(vals[:, k]), *_header_unit(sub)))
    if not columns:
        raise DataError("the netCDF file holds no 1-D variables (columns)", file=file)
    _check_duplicates([c.name for c in columns], file)
    return _table_of_columns(file, columns)


def _dataset_values(vals: np.ndarray) -> Any:
    if vals.dtype.kind in "iuf":
        return vals.astype(float)
    if vals.dtype.kind == "S":
        return [v.decode("utf-8", "replace") for v in vals]
    return list(vals)


# --------------------------------------------------------------------------
# Column selection
# --------------------------------------------------------------------------


@dataclass
class _Choice:
    column: _Column
    by_full_name: bool  # matched by its whole header, so a bracket in it may be part of the name


def _find_requested(table: _Table, requested: str, role: str) -> _Choice:
    exact = [c for c in table.columns if c.name == requested.strip()]
    if len(exact) == 1:
        return _Choice(exact[0], True)
    req_full = _normalize(requested)
    req_base = _normalize(_split_header(requested)[0])
    keys = {k for k in (req_full, req_base) if k}
    found = [c for c in table.columns if c.full_key in keys or c.base_key in keys]
    if len(found) == 1:
        return _Choice(found[0], found[0].full_key in keys)
    names = [c.name for c in table.columns]
    if not found:
        raise DataError(
            f"no column matches {requested!r} (asked for as {role}); the file's columns are {names}",
            file=table.file, column=requested,
        )
    raise DataError(
        f"{requested!r} (asked for as {role}) matches several columns: "
        f"{[c.name for c in found]}; pass the exact name of the one to use",
        file=table.file, column=requested,
    )


def _select_explicit(table: _Table, columns: Mapping[str, Any]) -> dict[str, _Choice]:
    allowed = (*_STATES, "setting", *_PI_STATES)
    if not isinstance(columns, Mapping):
        raise DataError(
            f"columns= must be a mapping such as {{'landing': [...], 'liftoff': [...]}}; "
            f"got {type(columns).__name__}", file=table.file,
        )
    unknown = [k for k in columns if k not in allowed]
    if unknown:
        raise DataError(f"columns= has unknown keys {unknown}; allowed keys are {list(allowed)}",
                        file=table.file)
    chosen: dict[str, _Choice] = {}
    for state in (*_STATES, *_PI_STATES):
        names = columns.get(state)
        if names is None:
            if state in _STATES:
                raise DataError(f"columns= must name the 3 {state} columns (xdot, ydot, omega)",
                                file=table.file)
            continue
        if isinstance(names, str) or not isinstance(names, Sequence) or len(names) != 3:
            raise DataError(
                f"columns[{state!r}] must be a list of 3 column names (xdot, ydot, omega); got {names!r}",
                file=table.file,
            )
        for comp, name in zip(COMPONENTS, names, strict=True):
            chosen[f"{state}.{comp}"] = _find_requested(table, str(name), f"{state} {comp}")
    if columns.get("setting") is not None:
        chosen["setting"] = _find_requested(table, str(columns["setting"]), "setting")
    return chosen


def _candidates(table: _Table) -> dict[str, list[_Choice]]:
    """File columns matching each role's synonyms; a whole-name match hides a base-name one."""
    found: dict[str, list[_Choice]] = {role: [] for role in _ROLES}
    for col in table.columns:
        role = _role_of(col.full_key)
        if role is not None:
            found[role].append(_Choice(col, True))
        elif (role := _role_of(col.base_key)) is not None:
            found[role].append(_Choice(col, False))
    return found


def _select_auto(table: _Table) -> dict[str, _Choice]:
    found = _candidates(table)
    chosen: dict[str, _Choice] = {}
    problems = []
    for role in (*(f"{s}.{c}" for s in _STATES for c in COMPONENTS), "setting"):
        cands = found[role]
        if len(cands) == 1:
            chosen[role] = cands[0]
        elif len(cands) > 1:
            problems.append(f"{role}: several candidates {[c.column.name for c in cands]}")
        elif role != "setting":
            problems.append(f"{role}: no column found")
    for state in _PI_STATES:
        roles = [f"{state}.{c}" for c in COMPONENTS]
        if all(len(found[r]) == 1 for r in roles):
            chosen.update({r: found[r][0] for r in roles})
        elif any(len(found[r]) > 1 for r in roles):
            problems.extend(f"{r}: several candidates {[c.column.name for c in found[r]]}"
                            for r in roles if len(found[r]) > 1)
        elif any(found[r] for r in roles):
            warnings.warn(
                f"{table.file}: ignoring the incomplete {state} columns "
                f"{[found[r][0].column.name for r in roles if found[r]]}; "
                "name all three in columns= to use them",
                UserWarning, stacklevel=4,
            )
    if problems:
        raise DataError(_auto_detect_message(table, found, problems), file=table.file)
    return chosen


def _auto_detect_message(table: _Table, found: dict[str, list[_Choice]], problems: list[str]) -> str:
    def pick(role: str) -> str:
        cands = found[role]
        if len(cands) == 1:
            return repr(cands[0].column.name)
        if cands:
            return repr("<one of " + ", ".join(c.column.name for c in cands) + ">")
        return repr(f"<{role.replace('.', ' ')} column>")

    parts = [f"{s!r}: [{', '.join(pick(f'{s}.{c}') for c in COMPONENTS)}]" for s in _STATES]
    if found["setting"]:
        parts.append(f"'setting': {pick('setting')}")
    for s in _PI_STATES:
        if any(found[f"{s}.{c}"] for c in COMPONENTS):
            parts.append(f"{s!r}: [{', '.join(pick(f'{s}.{c}') for c in COMPONENTS)}]")
    hint = ""
    if any("angle" in c.full_key for c in table.columns):
        hint = ("\nThe file seems to give speed and angle: convert them to xdot, ydot with "
                "bouncelab.data.units.landing_from_speed_angle_spin first.")
    return (
        "cannot tell which columns hold the bounce data (" + "; ".join(problems) + ").\n"
        f"The file's columns are {[c.name for c in table.columns]}.\n"
        "Name them explicitly (replace each <...>):\n"
        f"    load_campaign({table.file!r}, columns={{{', '.join(parts)}}})" + hint
    )


# --------------------------------------------------------------------------
# Values and units
# --------------------------------------------------------------------------


def _is_empty_cell(v: Any) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v)) or (isinstance(v, str) and not v.strip())


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


def _check_units_arg(units: Mapping[str, str] | None, file: str) -> dict[str, str]:
    if units is None:
        return {}
    if not isinstance(units, Mapping):
        raise DataError(
            f"units= must be a mapping such as {{'velocity': 'm/s', 'spin': 'rpm'}}; got {units!r}",
            file=file,
        )
    bad = [k for k in units if k not in _UNIT_KINDS]
    if bad:
        raise DataError(f"units= has unknown keys {bad}; use 'velocity' and/or 'spin'", file=file)
    out = {}
    for kind, unit in units.items():
        if unit is None:
            continue
        try:
            out[kind] = canonical_unit(unit, kind)
        except DataError as exc:
            raise DataError(f"units={{{kind!r}: {unit!r}}}: {exc.message}", file=file) from None
    return out


def _column_unit(table: _Table, choice: _Choice, kind: str, given: dict[str, str]) -> tuple[str, str]:
    """Unit of a selected column and where it came from ("units=", "header", "assumed")."""
    col = choice.column
    header = None
    if col.unit_text is not None:
        known = _unit_of(col.unit_text)
        header = known.get(kind)
        if header is None and (known or not (choice.by_full_name and col.unit_in_header)):
            where = "header" if col.unit_in_header else "units row"
            what = f"a {next(iter(known))} unit, not a {kind} unit" if known else "not a known unit"
            try:
                canonical_unit(col.unit_text, kind)
            except DataError as exc:
                raise DataError(f"the {where} gives the unit {col.unit_text!r}, {what}; {exc.message}",
                                file=table.file, column=col.name) from None
    if kind in given:
        if header is not None and header != given[kind]:
            raise DataError(
                f"the header says {header} but units= says {kind} {given[kind]}; "
                "remove one of them or make them agree", file=table.file, column=col.name,
            )
        return given[kind], "units="
    if header is not None:
        return header, "header"
    return ("radius/s" if kind == "velocity" else "rad/s"), "assumed"


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


def _campaign_from_table(
    table: _Table,
    *,
    columns: Mapping[str, Any] | None,
    units: dict[str, str],
    campaign: str,
    surface: str,
    source: str,
    ball_radius_m: float,
) -> xr.Dataset:
    file = table.file
    if table.n_rows == 0:
        raise DataError("the file has a header but no data rows", file=file)
    chosen = _select_explicit(table, columns) if columns is not None else _select_auto(table)
    cols = {role: ch.column for role, ch in chosen.items()}

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
    for role in parsed:
        kind = _ROLE_KINDS[role.split(".")[1]]
        unit, origin = _column_unit(table, chosen[role], kind, units)
        unit_of[role] = (unit, origin)
        if kind == "velocity":
            scaled[role] = velocity_to_scaled(parsed[role], unit, radius_m=ball_radius_m)
        else:
            scaled[role] = spin_to_scaled(parsed[role], unit)

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
            raise _err(table, f"prediction-interval half-width {float(parsed[roles[k]][i])!r} is negative",
                       cols[roles[k]].name, i)

    _check_plausible(table, cols, scaled, parsed, unit_of)

    attrs = {"source_units": _describe_units(unit_of, cols)}
    try:
        return make_campaign(
            states["landing"], states["liftoff"], setting=setting,
            landing_pi=states.get("landing_pi"), liftoff_pi=states.get("liftoff_pi"),
            campaign=campaign, surface=surface, ball_radius_m=ball_radius_m, source=source,
            data_kind="measured", attrs=attrs,
        )
    except DataError as exc:  # pragma: no cover - everything is checked above
        raise _relocate(table, exc, cols) from None


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
    scaled: dict[str, np.ndarray],
    parsed: dict[str, np.ndarray],
    unit_of: dict[str, tuple[str, str]],
) -> None:
    """Refuse numbers that can only come from a unit mistake."""
    median = float(np.median(np.abs(scaled["landing.ydot"])))
    if unit_of["landing.ydot"][1] == "assumed" and median < _MIN_MEDIAN_LANDING_YDOT:
        raise DataError(
            f"the column has no velocity unit (in units= or the file), so radii/s are assumed, "
            f"but the median landing |ydot| is "
            f"{median:.3g} radii/s (below {_MIN_MEDIAN_LANDING_YDOT:g} radii/s = "
            f"{_MIN_MEDIAN_LANDING_YDOT * BALL_RADIUS_M:.2f} m/s, which no golf landing is): "
            "the velocities look like physical units; pass units={'velocity': 'm/s'} "
            "(or the unit they are in)", file=table.file, column=cols["landing.ydot"].name,
        )
    for role in (f"{s}.{c}" for s in _STATES for c in COMPONENTS):
        kind = _ROLE_KINDS[role.split(".")[1]]
        limit = _MAX_VELOCITY if kind == "velocity" else _MAX_SPIN
        big = np.abs(scaled[role]) > limit
        if not big.any():
            continue
        i = int(np.argmax(big))
        unit, origin = unit_of[role]
        said = f"{'assumed' if origin == 'assumed' else 'declared'} {unit}"
        if kind == "velocity":
            msg = (f"{float(parsed[role][i])!r} ({said}) is {scaled[role][i]:.4g} radii/s, faster than "
                   f"{_MAX_VELOCITY:g} radii/s ({_MAX_VELOCITY * BALL_RADIUS_M:.0f} m/s), "
                   "which no golf ball reaches: the velocity unit is wrong "
                   "(pass units={'velocity': ...})")
        else:
            msg = (f"{float(parsed[role][i])!r} ({said}) is {scaled[role][i]:.4g} rad/s, beyond "
                   f"{_MAX_SPIN:g} rad/s ({_MAX_SPIN * 60 / (2 * math.pi):.0f} rpm), which no golf "
                   "ball reaches: the spin unit is wrong"
                   + (" (rpm read as rad/s? pass units={'spin': 'rpm'})" if origin == "assumed"
                      else " (pass units={'spin': ...})"))
        raise _err(table, msg, cols[role].name, i)


def _describe_units(unit_of: dict[str, tuple[str, str]], chosen: dict[str, _Column]) -> str:
    parts = []
    for kind in _UNIT_KINDS:
        roles = [r for r in unit_of if _ROLE_KINDS[r.split(".")[1]] == kind]
        found = {unit_of[r] for r in roles}
        if len({u for u, _ in found}) == 1:
            unit, origin = next(iter(found))
            parts.append(f"{kind} {unit}" + (" (assumed)" if origin == "assumed" else ""))
        else:
            parts.append(f"{kind} " + ", ".join(f"{chosen[r].name}: {unit_of[r][0]}" for r in roles))
    return ", ".join(parts)


# --------------------------------------------------------------------------
# netCDF campaigns
# --------------------------------------------------------------------------

def _campaign_from_netcdf(
    ds: xr.Dataset,
    *,
    file: str,
    source: str,
    columns: Any,
    units: Any,
    campaign: str | None,
    surface: str | None,
    ball_radius_m: float,
) -> xr.Dataset:
    if columns is not None or units is not None:
        raise DataError(
            "this is a bouncelab campaign file (scaled units, named variables): "
            "do not pass columns= or units=", file=file,
        )
    stored_radius = ds.attrs.get("ball_radius_m")
    if (stored_radius is not None and ball_radius_m != BALL_RADIUS_M
            and float(stored_radius) != float(ball_radius_m)):
        raise DataError(
            f"the campaign was scaled with ball_radius_m={float(stored_radius)!r}, "
            f"not {ball_radius_m!r}; a campaign file cannot be rescaled on loading", file=file,
        )
    attrs = dict(ds.attrs)
    attrs.setdefault("data_kind", "measured")
    attrs.setdefault("source", source)
    # validate_campaign restores what netCDF-3 changes (int32 integers, object strings).
    out = validate_campaign(ds.assign_attrs(attrs), file=file)
    if campaign is not None:
        out.attrs["campaign"] = str(campaign)
    if surface is not None:
        out.attrs["surface"] = str(surface)
    return out


def _embedded_file(name: str):
    fname = f"campaign_{name}.nc"
    try:
        path = resources.files("bouncelab.data").joinpath("files", fname)
    except (ModuleNotFoundError, TypeError):
        path = Path(__file__).parent / "files" / fname
    if not path.is_file():
        raise FileNotFoundError(
            f"the embedded campaign {name!r} is missing: bouncelab/data/files/{fname} is not "
            "installed (it is generated by the package's surrogate-data generator); "
            "reinstall bouncelab or pass the path of a campaign file"
        )
    return path


# --------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------


def load_campaign(
    source: str | os.PathLike[str],
    *,
    columns: Mapping[str, Any] | None = None,
    units: Mapping[str, str] | None = None,
    campaign: str | None = None,
    surface: str | None = None,
    sheet: str | int | None = None,
    ball_radius_m: float = BALL_RADIUS_M,
) -> xr.Dataset:
    """Load a bounce campaign from a file, or one of the embedded campaigns.

    Parameters
    ----------
    source
        ``"A"`` or ``"B"`` (a string, any case) for an embedded campaign; any
        other string or path is a file: ``.csv``, ``.tsv``, ``.txt``,
        ``.xlsx``, ``.xls``, ``.mat``, ``.nc`` or ``.netcdf``.
    columns
        Which file columns hold what: ``{"landing": [xdot0, ydot0, omega0],
        "liftoff": [xdotF, ydotF, omegaF]}`` plus optional ``"setting"`` (one
        name), ``"landing_pi"`` and ``"liftoff_pi"`` (three names each). Names
        match case-, space-, punctuation- and unit-suffix-insensitively.
        ``None`` detects them from :data:`COLUMN_SYNONYMS`.
    units
        Units of the file's values, ``{"velocity": "m/s", "spin": "rpm"}``
        (either key optional). Without it a unit in a column's header is used,
        else scaled units (radii/s, rad/s) are assumed.
    campaign, surface
        Names stored in the attrs; default: the file stem and ``""`` (for a
        campaign netCDF file, the stored ones).
    sheet
        Excel sheet name or 0-based index (default: the first sheet).
    ball_radius_m
        Ball radius in metres used to scale velocities.

    Returns
    -------
    xarray.Dataset
        A campaign (see :func:`bouncelab.data.campaign.make_campaign`) in scaled
        units, with attrs ``campaign``, ``surface``, ``source`` (absolute path),
        ``data_kind`` (``"measured"`` unless a netCDF file says otherwise),
        ``source_units`` and ``ball_radius_m``.

    Raises
    ------
    FileNotFoundError
        The file, or the embedded campaign's data file, does not exist.
    ImportError
        An Excel file and ``openpyxl`` (``xlrd`` for ``.xls``) is not installed.
    DataError
        Any problem with the contents; the message names the file, the column
        (as spelled in the file) and the data row (first row under the header = 1).

    Examples
    --------
    >>> ds = load_campaign("bounces.csv", units={"velocity": "m/s", "spin": "rpm"})  # doctest: +SKIP
    >>> ds = load_campaign("B")  # doctest: +SKIP
    """
    if isinstance(source, str) and source.strip().upper() in EMBEDDED_CAMPAIGNS:
        name = source.strip().upper()
        res = _embedded_file(name)
        with resources.as_file(res) as path:
            file = f"embedded campaign {name} ({path.name})"
            ds = _open_netcdf(Path(path), file)
            return _campaign_from_netcdf(
                ds, file=file, source=str(path), columns=columns, units=units,
                campaign=campaign, surface=surface, ball_radius_m=ball_radius_m,
            )

    file = os.fspath(source)
    path = Path(file).expanduser()
    if not path.exists():
        hint = ""
        if isinstance(source, str) and not Path(file).suffix and os.sep not in file and len(file) <= 2:
            hint = f" (the embedded campaigns are {' and '.join(map(repr, EMBEDDED_CAMPAIGNS))})"
        raise FileNotFoundError(f"no such file: {file!r}{hint}")
    if path.is_dir():
        raise IsADirectoryError(f"{file!r} is a directory, not a data file")
    suffix = path.suffix.lower()
    if suffix not in SUPPORTED_SUFFIXES:
        raise DataError(
            f"unknown file type {path.suffix or '(no suffix)'!r}; supported suffixes are "
            f"{', '.join(SUPPORTED_SUFFIXES)}", file=file,
        )
    if sheet is not None and suffix not in _EXCEL_SUFFIXES:
        raise DataError("sheet= only applies to Excel files", file=file)
    try:
        radius = float(ball_radius_m)
    except (TypeError, ValueError):
        radius = math.nan
    if not (math.isfinite(radius) and radius > 0):
        raise DataError(f"ball_radius_m must be a positive length in metres; got {ball_radius_m!r}",
                        file=file)
    absolute = str(path.resolve())

    if suffix in _NETCDF_SUFFIXES:
        ds = _open_netcdf(path, file)
        if "landing" in ds.data_vars or "liftoff" in ds.data_vars:
            return _campaign_from_netcdf(
                ds, file=file, source=absolute, columns=columns, units=units,
                campaign=campaign, surface=surface, ball_radius_m=ball_radius_m,
            )
        table = _table_from_dataset(ds, file)
    elif suffix in _EXCEL_SUFFIXES:
        table = _read_excel(path, file, sheet)
    elif suffix == ".mat":
        table = _read_mat(path, file)
    else:
        table = _read_text(path, file)
    return _campaign_from_table(
        table, columns=columns, units=_check_units_arg(units, file),
        campaign=path.stem if campaign is None else str(campaign),
        surface="" if surface is None else str(surface),
        source=absolute, ball_radius_m=radius,
    )


def _netcdf_engine() -> str:
    if _module_available("netCDF4"):
        return "netcdf4"
    if _module_available("h5netcdf"):
        return "h5netcdf"
    return "scipy"


def _check_attr(key: str, value: Any, file: str) -> None:
    ok = isinstance(value, str | float | np.floating | np.integer) or (
        isinstance(value, int) and not isinstance(value, bool)
    )
    if isinstance(value, list | tuple | np.ndarray):
        arr = np.asarray(value)
        ok = arr.ndim == 1 and arr.dtype.kind in "iuf"
    if not ok:
        raise DataError(
            f"attribute {key!r} = {value!r} cannot be stored in netCDF "
            "(use a string, a number or a 1-D list of numbers)", file=file,
        )


def save_campaign(ds: xr.Dataset, path: str | os.PathLike[str], *, engine: str | None = None) -> Path:
    """Write a campaign to a netCDF file that :func:`load_campaign` reads back exactly.

    Values, the ``setting`` coordinate (numbers or strings), the prediction
    intervals and the attrs all survive the round trip bit for bit. The file
    is written to a temporary name and renamed, so a failed save leaves no
    file (and an existing file untouched).

    Parameters
    ----------
    ds
        A campaign Dataset (it is checked with
        :func:`~bouncelab.data.campaign.validate_campaign`; only the campaign
        variables, coordinates and attrs are written).
    path
        Destination, ending in ``.nc`` or ``.netcdf``. Its directory must exist.
    engine
        xarray netCDF engine; default ``"netcdf4"`` or ``"h5netcdf"`` if
        installed, else ``"scipy"`` (netCDF-3, always available).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    DataError
        ``ds`` is not a valid campaign, an attr cannot be stored, or the
        suffix is not a netCDF one; no file is created.
    FileNotFoundError
        The destination directory does not exist.
    """
    path = Path(path).expanduser()
    file = os.fspath(path)
    if path.suffix.lower() not in _NETCDF_SUFFIXES:
        raise DataError(
            f"save_campaign writes netCDF; give the file a .nc suffix (got {path.suffix or 'none'!r})",
            file=file,
        )
    parent = path.parent
    if not parent.is_dir():
        raise FileNotFoundError(f"cannot save {file!r}: the directory {os.fspath(parent)!r} does not exist")
    checked = validate_campaign(ds, file=file)
    for key, value in checked.attrs.items():
        _check_attr(key, value, file)
    fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        checked.to_netcdf(tmp, engine=engine or _netcdf_engine())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path
