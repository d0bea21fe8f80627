"""Launch-monitor shots in: TrackMan, FlightScope and GSPro exports, or any table naming landing speed, angle, spin,
carry and total, as an :class:`xarray.Dataset` with a ``shot`` dimension in SI units (:func:`load_shots`).

The file is read by the loader's backends and pipeline (:mod:`bouncelab.data.io.read`,
:mod:`bouncelab.data.io.interpret`): a units row under the header (TrackMan's ``[mph]``, ``[deg]``, ``[rpm]``,
``[yds]``, ``[s]``), units in the headers (``Carry (yds)``), missing cells refused or dropped with a warning
naming the rows, every bad cell a :class:`~bouncelab.core.errors.DataError` naming the file, the column and the
row; numbers only a wrong unit makes are refused (:mod:`bouncelab.core.plausibility`).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import units as u
from bouncelab.core.errors import DataError, Hint, MissingFileError, ParameterError
from bouncelab.core.files import check_regular_file
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges
from bouncelab.data.io import interpret as ip
from bouncelab.data.io import read
from bouncelab.data.io.names import normalize, split_header

__all__ = ["SHOT_COLUMNS", "SHOT_FORMATS", "SHOT_VARIABLES", "load_shots"]

#: Each variable of :func:`load_shots`: its kind of unit, its SI unit and what it is.
SHOT_VARIABLES: dict[str, tuple[str, str, str]] = {
    "landing_speed": ("velocity", "m/s", "ball speed at landing"),
    "landing_angle": ("angle", "deg", "angle of descent at landing, below the horizontal"),
    "spin": ("spin", "rad/s", "ball spin rate (total, about the spin axis)"),
    "spin_axis": ("angle", "deg", "tilt of the spin axis (positive: curving right, as the monitor gives it)"),
    "launch_angle": ("angle", "deg", "vertical launch angle, above the horizontal (orients the spin axis)"),
    "carry": ("distance", "m", "carry distance along the target line"),
    "total": ("distance", "m", "total distance, carry and roll-out"),
    "side": ("distance", "m", "lateral offset at landing (positive: right, as the monitor gives it)"),
    "side_total": ("distance", "m", "lateral offset at rest (positive: right, as the monitor gives it)"),
    "flight_time": ("time", "s", "time from launch to landing"),
}
#: The column names recognised for each variable (compared case-, space- and punctuation-insensitively, a unit in
#: the header aside), from TrackMan's, FlightScope's and GSPro's exports and plain names; of two columns that
#: match, the one whose name comes first here is read. ``landing_spin`` names a spin measured at landing (``spin``
#: is the launch spin the monitors export).
SHOT_COLUMNS: dict[str, tuple[str, ...]] = {
    "landing_speed": ("Carry Flat - Ball Speed", "Land Speed", "Landing Speed", "Landing Ball Speed",
                      "Ball Speed at Landing", "Descent Speed"),
    "landing_angle": ("Carry Flat - Land. Angle", "Land. Angle", "Land Angle", "Landing Angle", "Descent Angle",
                      "Descent V", "Angle of Descent"),
    "spin": ("Spin Rate", "Spin", "Total Spin", "TotalSpin", "Ball Spin", "Launch Spin"),
    "landing_spin": ("Landing Spin", "Land Spin", "Spin at Landing", "Landing Spin Rate"),
    "spin_axis": ("Spin Axis", "Axis"),
    "launch_angle": ("Launch Angle", "Launch V", "VLA", "Vertical Launch Angle", "Launch Angle V"),
    "carry": ("Carry Flat - Length", "Carry", "Carry Distance", "Carry Dist"),
    "total": ("Total", "Est. Total Flat - Length", "Total Distance", "Total Dist", "TotalDistance"),
    "side": ("Carry Flat - Side", "Side", "Lateral", "Offline", "Carry Side", "Carry Lateral", "Carry Offline"),
    "side_total": ("Side Total", "Est. Total Flat - Side", "Total Side", "Total Lateral", "Total Offline"),
    "flight_time": ("Carry Flat - Time", "Flight Time", "Hang Time", "Air Time"),
    "club": ("Club", "Club Type", "Club Name"),
}
#: Names only one monitor's export has, which tell the format (attrs ``format``); anything else is ``"generic"``.
SHOT_FORMATS: dict[str, tuple[str, ...]] = {
    "TrackMan": ("Carry Flat - Length", "Carry Flat - Land. Angle", "Carry Flat - Ball Speed", "Side Total",
                 "Est. Total Flat - Length", "Max Height - Height", "Dyn. Loft"),
    "FlightScope": ("Descent V", "Launch V", "Launch H"),
    "GSPro": ("VLA", "HLA", "TotalSpin", "BackSpin", "SideSpin"),
}
_KEYS = {normalize(name): (var, k) for var, names in SHOT_COLUMNS.items() for k, name in enumerate(names)}
# Units the loader's table of units does not have: lengths (to metres) and times (to seconds).
_OTHER_UNITS = {"distance": {"m": 1.0, "yd": 0.9144, "ft": u._FT, "cm": 0.01}, "time": {"s": 1.0, "ms": 1e-3}}
_SPELLINGS = {"meter": "m", "meters": "m", "metre": "m", "metres": "m", "yds": "yd", "yards": "yd", "yard": "yd",
              "feet": "ft", "foot": "ft", "sec": "s", "secs": "s", "second": "s", "seconds": "s"}
_SUGGEST = {"velocity": ("mph", "m/s"), "spin": ("rpm",)}
_MAX = {"distance": 550.0, "time": 20.0}  # no golf shot carries 550 m, nor flies 20 s: beyond, a unit mistake


def load_shots(source: str | os.PathLike[str] | Any, *, columns: Mapping[str, str] | None = None,
               units: Mapping[str, str] | None = None, missing: str = "raise", sheet: str | int | None = None,
               header_row: int | None = None, plausible: PlausibleRanges = PLAUSIBLE_RANGES) -> xr.Dataset:
    """Read launch-monitor shots (a TrackMan, FlightScope or GSPro export, or any table naming them) in SI units.

    Columns recognised (:data:`SHOT_COLUMNS`, case-, space- and punctuation-insensitively, a unit in the header
    aside), by the variable they give:

    ===============  ===================================================================================
    landing_speed    TrackMan ``Carry Flat - Ball Speed``; ``Land Speed``, ``Landing Speed``, ``Descent Speed``
    landing_angle    TrackMan ``Carry Flat - Land. Angle``; FlightScope ``Descent V``; ``Descent Angle``,
                     ``Landing Angle``
    spin             TrackMan ``Spin Rate``; GSPro ``TotalSpin``/``Total Spin``; FlightScope ``Spin``: the spin
                     at launch. A column ``Landing Spin`` is the spin at landing instead (attrs ``spin_at``).
    spin_axis        ``Spin Axis``
    launch_angle     TrackMan ``Launch Angle``; FlightScope ``Launch V``; GSPro ``VLA``
    carry            TrackMan ``Carry Flat - Length``; ``Carry``, ``Carry Distance``
    total            TrackMan ``Total`` (or ``Est. Total Flat - Length``); ``Total Distance``
    side             TrackMan ``Carry Flat - Side``; FlightScope ``Lateral``; GSPro ``Offline``; ``Side``
    side_total       TrackMan ``Side Total`` (or ``Est. Total Flat - Side``); ``Total Side``
    flight_time      TrackMan ``Carry Flat - Time``; ``Flight Time``, ``Hang Time``
    club             ``Club``, ``Club Type`` (text, kept as written)
    ===============  ===================================================================================

    Other columns (club speed, ball speed at launch, heights...) are left alone. Units come from a units row under the
    header (TrackMan's ``[mph]``, ``[deg]``, ``[rpm]``, ``[yds]``, ``[ft]``, ``[s]``), the header (``Carry
    (yds)``, ``Ball (mph)``) or ``units=``; a speed, spin or distance without one is refused (a carry of 250 is
    yards or metres: bouncelab does not guess); angles without one are degrees, times seconds.

    Parameters
    ----------
    source
        A ``.csv``, ``.tsv``, ``.txt``, ``.xlsx`` or ``.xls`` file, or a :class:`pandas.DataFrame` (its column
        names the header; a units row under it counts).
    columns
        ``{variable: column name}`` for columns the names above do not find (``{"landing_angle": "Land V"}``);
        ``"landing_spin"`` names a spin measured at landing.
    units
        ``{"velocity": "mph", "spin": "rpm", "angle": "deg", "distance": "yd", "time": "s"}``, each optional,
        for columns whose header or units row gives none (a header or units row that says otherwise is refused).
    missing
        ``"raise"`` (default): an empty or missing cell (``NA``, ``-``...) in a column read is an error naming
        it; ``"drop"``: such shots are left out with a :class:`~bouncelab.core.errors.DroppedRowsWarning` naming
        them, listed in attrs ``dropped_rows`` (the file's data rows, 1-based). A column empty in every row is
        not read (attrs ``empty_columns``).
    sheet, header_row
        As for :func:`~bouncelab.data.io.load_campaign`: an Excel sheet; the 1-based line of the header.
    plausible
        The magnitudes a golf ball can have (:data:`~bouncelab.core.plausibility.PLAUSIBLE_RANGES`: speeds to
        ``max_speed``, spins to ``max_spin``); beyond them, and beyond 550 m or 20 s, a number is refused as a
        unit mistake.

    Returns
    -------
    xarray.Dataset
        Dimension ``shot`` (coordinate 0, 1, ...; coordinate ``row``, the file's data row, 1-based). Variables
        where the file has them (:data:`SHOT_VARIABLES`): ``landing_speed`` (m/s), ``landing_angle`` (degrees
        below the horizontal), ``spin`` (rad/s; attrs ``spin_at``: ``"launch"`` or ``"landing"``),
        ``spin_axis`` and ``launch_angle`` (deg), ``carry``, ``total``, ``side``, ``side_total`` (m),
        ``flight_time`` (s), ``club`` (text). Each has attrs ``units``, ``long_name``, ``source_column`` and
        ``source_units``. The Dataset's attrs: ``source`` (the file, or ``"pandas.DataFrame"``), ``format``
        (``"TrackMan"``, ``"FlightScope"``, ``"GSPro"`` or ``"generic"``), ``spin_at``, ``data_kind`` and a
        ``note`` that a monitor's carry, total and landing are its own estimates.

    Raises
    ------
    DataError
        Naming the file, the column and the row: no such file (a :class:`~bouncelab.core.errors.MissingFileError`,
        also a ``FileNotFoundError``), a FIFO or a device, no column recognised, a bad or missing cell, an unknown or
        conflicting unit, a number only another unit makes, a landing angle outside (0, 90] degrees.

    Examples
    --------
    >>> shots = load_shots("session.csv", missing="drop")  # doctest: +SKIP
    >>> shots.landing_speed.attrs["units"]  # doctest: +SKIP
    'm/s'
    """
    frame = "pandas" in sys.modules and isinstance(source, sys.modules["pandas"].DataFrame)
    where = read.DATAFRAME_NAME if frame else os.fspath(source)
    if missing not in ip.MISSING_POLICIES:
        raise DataError(f"missing must be one of {', '.join(map(repr, ip.MISSING_POLICIES))}; got {missing!r}")
    if not isinstance(plausible, PlausibleRanges):
        raise ParameterError(f"plausible must be a PlausibleRanges, e.g. PLAUSIBLE_RANGES.widened(max_spin=...); got "
                             f"{plausible!r}")
    given = _units_arg(units, where)
    if frame:
        if sheet is not None or header_row is not None:
            raise DataError("sheet and header_row do not apply to a DataFrame", file=where)
        table = read.read_dataframe(source, where)
    else:
        if not (path := Path(where).expanduser()).exists():
            raise MissingFileError("no such file", file=where)
        suffix = path.suffix.lower()
        if path.is_dir() or suffix not in (".csv", ".tsv", ".txt", ".xlsx", ".xls"):
            raise DataError("a shot export is a .csv, .tsv, .txt, .xlsx or .xls file; got "
                            f"{path.suffix or path.name!r}", file=where)
        check_regular_file(path, where)
        backend = read.BACKENDS[suffix]
        if sheet is not None and "sheet" not in backend.options:
            raise DataError(f"sheet {sheet!r} was given, but it does not apply to this file (only Excel files have "
                            "sheets)", file=where)
        table = backend.read(path, where, **{k: v for k, v in (("sheet", sheet), ("header_row", header_row))
                                             if k in backend.options})
    r = ip.start(table, plausible=None)
    if len(r.frame) == 0:
        raise DataError("the file has a header but no shots", file=where)
    cols = _select(r, columns)
    empty = [c.name for c in cols.values() if ip.missing_rows(r, [c.name]).keys() == set(range(len(r.frame)))]
    cols = {k: c for k, c in cols.items() if c.name not in empty}  # a column the monitor left blank is not read
    club = cols.pop(ip.Role("shot", "club"), None)
    if not cols:
        raise DataError(f"no column of the file holds a number to read; the columns are {r.names}", file=where)
    r, cols, dropped = ip.read_columns(r, cols, missing=missing, what="shot")
    data, described = {}, []
    for role, col in cols.items():
        var = "spin" if role.comp == "landing_spin" else role.comp
        kind, si, long_name = SHOT_VARIABLES[var]
        unit, factor = _unit(r, col, kind, given)
        values = col.raw * factor if kind != "angle" else np.rad2deg(col.raw) if unit == "rad" else col.raw
        _guard(r, replace(col, unit=unit), var, kind, values, plausible)
        described.append(f"{col.name}: {unit}")
        data[var] = ("shot", values, {"units": si, "long_name": long_name, "source_column": col.name,
                                      "source_units": unit})
    spin_at = "landing" if ip.Role("shot", "landing_spin") in cols else "launch" if "spin" in data else None
    if spin_at is not None:
        data["spin"][2]["spin_at"] = spin_at
    if club is not None:
        labels = [str(v).strip() if not read.is_empty(v) else "" for v in r.frame[club.name].tolist()]
        data["club"] = ("shot", np.array(labels, dtype=str), {"long_name": "club", "source_column": club.name})
    names = {normalize(split_header(n)[0]) for n in r.names}
    fmt = max(SHOT_FORMATS, key=lambda f: len(names & {normalize(n) for n in SHOT_FORMATS[f]}))
    fmt = fmt if names & {normalize(n) for n in SHOT_FORMATS[fmt]} else "generic"
    attrs = {"source": "pandas.DataFrame" if frame else str(Path(where).resolve()), "format": fmt,
             "source_units": ", ".join(described), "data_kind": "measured (launch-monitor estimates)",
             "note": "a launch monitor's landing, carry and total are its own estimates (its model of the flight "
                     "and the roll), not measurements of the turf"}
    attrs |= {"spin_at": spin_at} if spin_at else {}
    attrs |= {"dropped_rows": [i + 1 for i in dropped]} if missing == "drop" else {}
    attrs |= {"empty_columns": empty} if empty else {}
    n = len(r.rows)
    return xr.Dataset(data, coords={"shot": np.arange(n), "row": ("shot", r.rows + 1, {"long_name": "data row"})},
                      attrs=attrs)


def _units_arg(units: Any, where: str) -> dict[str, str]:
    """``units=`` with its distance and time units checked here and the others by the loader."""
    if units is not None and not isinstance(units, Mapping):
        raise DataError(f"units must be a mapping such as {{'velocity': 'mph', 'distance': 'yd'}}; got {units!r}",
                        file=where)
    other = {k: _other_unit(v, k, where) for k, v in (units or {}).items() if k in _OTHER_UNITS and v is not None}
    rest = {k: v for k, v in (units or {}).items() if k not in _OTHER_UNITS}
    return {**ip.check_units_arg(rest, where), **other}


def shot_unit_factor(text: str, kind: str) -> float:
    """The factor to SI of a ``kind`` (``"distance"`` or ``"time"``) unit as written (``"yds"``, ``"ft"``, ``"ms"``),
    or a DataError listing the known ones."""
    return _OTHER_UNITS[kind][_other_unit(text, kind, None)]


def _other_unit(text: str, kind: str, file: str | None, column: str | None = None) -> str:
    key = str(text).strip().lower().replace(" ", "").strip("[](){}")
    if (key := _SPELLINGS.get(key, key)) not in _OTHER_UNITS[kind]:
        raise DataError(f"unknown {kind} unit {text!r}; known {kind} units: {', '.join(_OTHER_UNITS[kind])}",
                        file=file, column=column)
    return key


def _select(r: ip.Rows, columns: Mapping[str, str] | None) -> dict[ip.Role, ip.Column]:
    """The column of each variable: by name (:data:`SHOT_COLUMNS`), or as ``columns=`` names it."""
    known = (*SHOT_VARIABLES, "landing_spin", "club")
    if columns is not None and (not isinstance(columns, Mapping) or set(columns) - set(known)):
        raise DataError(f"columns must be a mapping of variables {list(known)} to column names; got {columns!r}",
                        file=r.t.file)
    found: dict[str, list[tuple[int, str]]] = {}  # variable -> (rank of the name matched, column)
    for name in r.names:
        for key in dict.fromkeys((normalize(name), normalize(split_header(name)[0]))):
            if (match := _KEYS.get(key)) is not None and (match[0] != "club" or key == normalize(name)):  # Club (mph)
                found.setdefault(match[0], []).append((match[1], name))
                break
    cols = {}
    for var in known:
        best = sorted(found.get(var, []), key=lambda m: m[0])  # first in SHOT_COLUMNS wins: Total over Est. Total
        if (columns or {}).get(var) is not None:
            cols[ip.Role("shot", var)] = ip.find(r, str(columns[var]), var)
        elif len(best) > 1 and best[0][0] == best[1][0]:
            names = [n for k, n in best if k == best[0][0]]
            raise DataError(f"the columns {names} all name the {var.replace('_', ' ')}; name the one to read",
                            file=r.t.file, column=names[0], hints=[Hint("columns", {var: names[0]})])
        elif best:
            cols[ip.Role("shot", var)] = ip.Column(best[0][1], normalize(best[0][1]) in _KEYS)
    if ip.Role("shot", "spin") in cols and ip.Role("shot", "landing_spin") in cols:
        raise DataError(f"the file has a launch spin {cols[ip.Role('shot', 'spin')].name!r} and a landing spin "
                        f"{cols[ip.Role('shot', 'landing_spin')].name!r}; name the one to read (columns=)",
                        file=r.t.file, hints=[Hint("columns", {"spin": cols[ip.Role('shot', 'spin')].name})])
    if not cols:
        raise DataError(f"no column of the file names a shot's landing speed, landing angle, spin, carry or total; "
                        f"the columns are {r.names}; name them with columns= (e.g. {{'landing_angle': ...}})",
                        file=r.t.file, hints=[Hint("columns", {"landing_angle": "<column>", "total": "<column>"})])
    return cols


def _unit(r: ip.Rows, col: ip.Column, kind: str, given: Mapping[str, str]) -> tuple[str, float]:
    """A column's unit (header, units row, ``units=``; angles deg and times s if none) and its factor to SI."""
    if kind in ("velocity", "spin", "angle"):
        unit = ip.column_unit(r, col, kind, given, {"velocity": "", "spin": "", "angle": "deg"})[0]
        if not unit:
            raise DataError(f"the file gives no {kind} unit for {col.name!r} (a units row, the header or units= "
                            f"says it; e.g. '{col.name} [{'mph' if kind == 'velocity' else 'rpm'}]'): bouncelab does "
                            "not guess", file=r.t.file, column=col.name,
                            hints=[Hint("units", {kind: x}) for x in _SUGGEST[kind]])
        factor = (u.SPEED_UNITS[unit] if kind == "velocity" else u.SPIN_UNITS[unit] if kind == "spin" else 1.0)
        if factor is None:  # radii/s: no speed of a shot is given in ball radii
            raise DataError(f"{col.name!r} is said to be in {unit}, a unit of bounce files, not of shots: give it in "
                            "m/s, mph, km/h or ft/s", file=r.t.file, column=col.name)
        return unit, factor
    text, where = (t, "header") if (t := split_header(col.name)[1]) is not None else r.t.units.get(col.name, (None, ""))
    unit = None if text is None else _other_unit(text, kind, r.t.file, col.name)
    if unit is not None and kind in given and unit != given[kind]:
        raise DataError(f"the {where} says {unit} but the {kind} unit given is {given[kind]}; remove one of them or "
                        "make them agree", file=r.t.file, column=col.name, hints=[Hint("units", {kind: unit})])
    if (unit := unit or given.get(kind) or ("s" if kind == "time" else None)) is None:
        raise DataError(f"the file gives no distance unit for {col.name!r} (a carry of 250 is yards or metres: "
                        "bouncelab does not guess); a units row, the header or units= says it", file=r.t.file,
                        column=col.name, hints=[Hint("units", {"distance": "yd"}), Hint("units", {"distance": "m"})])
    return unit, _OTHER_UNITS[kind][unit]


def _guard(r: ip.Rows, col: ip.Column, var: str, kind: str, values: np.ndarray, plausible: PlausibleRanges) -> None:
    """Refuse a number only a wrong unit makes (the first in the file's order), and landing angles that are none."""
    limit = {"velocity": plausible.max_speed, "spin": plausible.max_spin * u.SPIN_UNITS["rpm"],
             **_MAX}.get(kind, 90.0 if var in ("landing_angle", "launch_angle") else 360.0)
    bad = np.abs(values) > limit
    if var == "landing_angle":
        bad |= ~(values > 0)
    if var == "flight_time" or var in ("carry", "total"):
        bad |= values < 0
    if not bad.any():
        return
    i = int(np.argmax(bad))
    if var == "landing_angle" and values[i] <= 90:
        raise r.err(f"landing angle {r.cell(col.name, i, col.unit)} is not plausible: a landing angle is positive "
                    "below the horizontal, in (0, 90] degrees", col.name, i)
    # the value and the limit in one unit (spins in rpm, as monitors give them), converted only if written in another
    unit, scale = ("rpm", u.SPIN_UNITS["rpm"]) if kind == "spin" else (SHOT_VARIABLES[var][1], 1.0)
    said = r.cell(col.name, i, col.unit)
    value = " is" if col.unit == unit else f" is {values[i] / scale:.5g} {unit},"
    raise r.err(f"{var.replace('_', ' ')} {said}{value} "
                f"{'negative' if values[i] < 0 else f'beyond {limit / scale:g} {unit}'}, which no golf shot has: "
                "the unit is wrong "
                "(check the units row, the header or units=)", col.name, i,
                [Hint("plausible", None, "PLAUSIBLE_RANGES.widened(...) accepts such values on purpose")]
                if kind in ("velocity", "spin") else [])
