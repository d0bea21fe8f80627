"""Landings alone (no lift-offs): a table of landing states read by column name, or rows of three numbers.

This is what ``bouncelab predict --input`` reads. A file with a header is read by the campaign
loader's text reader (title lines, a units row under the header, ``#`` comments, the delimiter
sniffed, a decimal comma, every error located by line) and its columns are recognised by the
loader's synonym table: a landing given as ``xdot0, ydot0, omega0`` (any of the loader's
Cartesian names, ``vx_in``, ``w0``...) or as ``speed, angle, spin`` (the angle of incidence below
the horizontal), in any order. Since these columns can only be landings, names without a phase
marker count too (``xdot``, ``vx``, ``speed``, ``spin``...). Other columns (lift-offs, intervals,
settings, notes) are left alone. Units come from the header or the units row (``m/s,deg,rpm``),
else from ``units=``, else the scaled ones (radii/s, rad/s) and degrees. A file without a header
is read as before: three numbers a line, ``xdot0 ydot0 omega0``.
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bouncelab.core.errors import DataError
from bouncelab.core.units import BALL_RADIUS_M, COMPONENTS, ball_radius, spin_to_scaled, velocity_to_scaled
from bouncelab.core.validation import as_states
from bouncelab.data.io import hints
from bouncelab.data.io.columns import (
    _POLAR_STEMS,
    _STEMS,
    POLAR_ROLES,
    _candidates,
    _check_units_arg,
    _Choice,
    _column_unit,
    _normalize,
    _polar_role_of,
    _role_of,
    _split_header,
    check_absolute_units,
)
from bouncelab.data.io.table import (
    _check_landing_sign,
    _decimal_convention,
    _err,
    _is_empty_cell,
    _missing_rows,
    _numbers,
    _polar_state,
    _relocate,
    _Table,
)

__all__ = ["LandingTable", "read_landings"]

#: The units a landing is read in when neither the file nor ``units=`` gives one.
DEFAULT_UNITS = {"velocity": "radius/s", "spin": "rad/s", "angle": "deg"}

# Names without a phase marker (``xdot``, ``vx``, ``speed``, ``spin``): in a file of landings alone they can
# only be the landing's. One-letter stems are left out (``v`` is a ydot in the synonym table, but a speed
# to many), except ``w``, which is only ever a spin.
_BARE: dict[str, str] = {}
for _comp, _stems in (*_STEMS.items(), *_POLAR_STEMS.items()):
    for _stem in _stems:
        if len(_stem) > 1 or _stem == "w":
            if _BARE.setdefault(_stem, _comp) != _comp:  # pragma: no cover - the tables are disjoint
                raise AssertionError(f"bare name {_stem!r} is two components")
_ORDER = ("xdot", "ydot", "omega", "speed", "angle")
_SHOWN = {"xdot": "xdot", "ydot": "ydot", "omega": "spin", "speed": "speed", "angle": "angle"}
_NAMING = ("name the columns xdot0, ydot0, omega0, or speed, angle, spin (the angle of incidence below the "
           "horizontal), e.g. a header 'speed,angle,spin' with a units row 'm/s,deg,rpm' under it; or leave the "
           "header out to give three numbers a line, xdot0 ydot0 omega0")


@dataclass(frozen=True)
class LandingTable:
    """Landings read by :func:`read_landings`.

    Attributes
    ----------
    states
        (n, 3) landings ``[xdot0, ydot0, omega0]`` in scaled units (radii/s, rad/s).
    form
        ``"cartesian"`` or ``"polar"`` (columns read by name), or ``"rows"`` (no header: three
        numbers a line, ``xdot0 ydot0 omega0``).
    values
        (n, 3) the numbers as the file gives them: ``xdot, ydot, omega`` or ``speed, angle, spin``.
    units
        The unit of each kind read (``velocity``, ``spin``; ``angle`` for a polar file).
    unit_origins
        Where each unit came from: ``"header"`` (the header or the units row), ``"units="`` (the
        caller) or ``"default"``.
    columns
        The file's columns read, in the order of ``values`` (empty for a file without header).
    """

    states: np.ndarray
    form: str
    values: np.ndarray
    units: dict[str, str]
    unit_origins: dict[str, str] = field(default_factory=dict)
    columns: tuple[str, ...] = ()


def read_landings(
    file: str | os.PathLike[str],
    *,
    data: bytes | None = None,
    units: Mapping[str, str] | None = None,
    radius_m: float = BALL_RADIUS_M,
    hint_style: str = "python",
) -> LandingTable:
    """Read a text file of landing states (no lift-offs) by column name.

    Parameters
    ----------
    file
        The file's path; with ``data``, only its name in messages (e.g. ``"<stdin>"``).
    data
        The file's bytes, when they do not come from ``file`` (standard input).
    units
        ``{"velocity": ..., "spin": ..., "angle": "deg" | "rad"}``, each optional: the units of
        columns whose header (or units row) gives none. A header unit that differs is an error.
    radius_m
        Ball radius of the scaling, in metres.
    hint_style
        ``"python"`` or ``"cli"``: how messages name the options (``units=`` or ``--spin-unit``).

    Returns
    -------
    LandingTable

    Raises
    ------
    FileNotFoundError
        ``file`` does not exist (and no ``data`` is given).
    DataError
        Naming the file, the column and the line: columns that cannot be told apart or are
        missing, an empty or non-numeric cell, an unknown or conflicting unit, a landing that
        does not come down (``ydot0 >= 0``, a landing angle outside (0, 90] degrees).
    """
    from bouncelab.data.io.load import _check_regular_file, _read_bytes

    style = hints.check_style(hint_style)
    name = os.fspath(file)
    radius = ball_radius(radius_m, file=name)
    given = _check_units_arg(units, name, style)
    path = None
    if data is None:
        path = Path(name).expanduser()
        if not path.exists():
            raise FileNotFoundError(f"no such file: {name!r}")
        if path.is_dir():
            raise DataError("it is a folder, not a file of landings", file=name)
        _check_regular_file(path, name)  # a FIFO would hang, /dev/zero never end: the loader's own checks
        data = _read_bytes(path, name)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = data.decode("latin-1")  # as the campaign loader reads a file that is not UTF-8
    if "\x00" in text:
        raise DataError("the file holds NUL bytes: it is not a text file of landings", file=name)
    lines = re.split(r"\r\n|\r|\n", text)
    first = next((k for k, line in enumerate(lines) if line.strip() and not line.lstrip().startswith(("#", "%"))),
                 None)
    if first is None:
        raise DataError("no landing rows found (the file is empty or holds only comments)", file=name)
    if any(_number(c) is not None for c in _cells(lines[first].split("#", 1)[0])):
        return _rows(name, lines, given, radius)  # no header: a first line with a number is data
    from bouncelab.data.io.text import _read_text

    # A header that names landing columns is the header (the loader would take it for a title above a line
    # with more cells, such as a stray note under it); comments after a row are dropped, as lines of their own are.
    header_row = first + 1 if _names_a_landing(lines[first]) else None
    body = "\n".join(line if line.lstrip().startswith(("#", "%")) else re.sub(r"\s+#.*$", "", line) for line in lines)
    table = _read_text(None, name, body.encode("utf-8"), header_row=header_row, style=style)
    table.hint_style = style
    return _by_name(table, given, radius)


def _names_a_landing(line: str) -> bool:
    """Whether a header line names a landing's column (``xdot0``, ``vx``, ``speed [m/s]``...)."""
    for cell in re.split(r"[,;\t]|\s+", line):
        if cell.strip() and _role(cell.strip()) is not None:
            return True
    return False


def _cells(text: str) -> list[str]:
    return text.replace(",", " ").replace(";", " ").split()


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _rows(file: str, lines: list[str], given: dict[str, str], radius_m: float) -> LandingTable:
    """A file without header: three numbers a line (comma, semicolon or blank separated), xdot0 ydot0 omega0.
    Any line that is not three finite numbers is an error naming it: no line is skipped silently."""
    from bouncelab.data.io.text import _is_data_row

    rows, linenos = [], []
    for lineno, line in enumerate(lines, start=1):
        if line.lstrip().startswith(("#", "%")):
            if _is_data_row(_cells(line), 3):  # "#N/A,-260,300": a row with a missing value, not a comment
                raise DataError(f"line {lineno} starts with {line.lstrip()[0]!r} like a comment but holds a "
                                f"landing row: {line.strip()!r}; give three numbers, or delete the line",
                                file=file, row=len(rows) + 1)
            continue
        body = line.split("#", 1)[0].strip()
        if not body:
            continue
        parts = _cells(body)
        if len(parts) != 3:
            raise DataError(f"line {lineno} has {len(parts)} values; a landing needs 3 (xdot0 ydot0 omega0)",
                            file=file, row=len(rows) + 1)
        values = [_number(v) for v in parts]
        bad = [(k, v) for k, (v, x) in enumerate(zip(parts, values, strict=True)) if x is None or not math.isfinite(x)]
        if bad:
            k, v = bad[0]
            what = "is not a number" if values[k] is None else "is not finite"
            raise DataError(f"line {lineno} is not three finite numbers: {body!r} ({v!r} {what})", file=file,
                            column=("xdot0", "ydot0", "omega0")[k], row=len(rows) + 1)
        rows.append(values)
        linenos.append(lineno)
    if not rows:
        raise DataError("no landing rows found", file=file)
    values = np.array(rows, dtype=float)
    unit = {kind: given.get(kind, DEFAULT_UNITS[kind]) for kind in ("velocity", "spin")}
    states = np.column_stack([velocity_to_scaled(values[:, :2], unit["velocity"], radius_m=radius_m),
                              spin_to_scaled(values[:, 2], unit["spin"])])
    up = np.flatnonzero(~(states[:, 1] < 0))
    if up.size:
        i = int(up[0])
        raise DataError(f"line {linenos[i]}: a landing comes down, so its ydot0 (the second number) must be "
                        f"negative (y points up); got {values[i, 1]:g}. If the file gives speed, angle and spin, "
                        "put a header 'speed,angle,spin' over the rows", file=file, column="ydot0", row=i + 1)
    origins = {kind: "units=" if kind in given else "default" for kind in unit}
    return LandingTable(states, "rows", values, unit, origins)


def _role(name: str) -> str | None:
    """The landing role (``landing.xdot``... ``landing.angle``) a column name stands for, or None: the loader's
    synonyms with a phase (``xdot0``, ``vx_in``, ``speed_in``...) or a name without one (``vx``, ``speed``)."""
    for key in (_normalize(name), _normalize(_split_header(name)[0])):
        role = _role_of(key) or _polar_role_of(key) or (f"landing.{_BARE[key]}" if key in _BARE else None)
        if role is not None:
            return role if role.startswith("landing.") else None
    return None


def _by_name(table: _Table, given: dict[str, str], radius_m: float) -> LandingTable:
    file = table.file
    if table.n_rows == 0:
        raise DataError("the file has a header but no landing rows", file=file)
    found = _candidates(table)  # the loader's synonyms: names with a phase (xdot0, vx_in, speed_in...)
    for col in table.columns:
        if any(col is ch.column for cands in found.values() for ch in cands):
            continue
        for key, whole in ((col.full_key, True), (col.base_key, False)):
            if key in _BARE:
                found[f"landing.{_BARE[key]}"].append(_Choice(col, whole))
                break
    landing = {c: found[f"landing.{c}"] for c in _ORDER}
    names = [c.name for c in table.columns]
    several = [(c, chs) for c, chs in landing.items() if len(chs) > 1]
    if several:
        c, chs = several[0]
        raise DataError(f"the columns {[ch.column.name for ch in chs]} all name the landing's {_SHOWN[c]}; keep "
                        "one, or rename the others", file=file, column=chs[0].column.name)
    has = {c for c, chs in landing.items() if chs}
    if not has:
        others = [ch.column.name for role, chs in found.items() if role.startswith("liftoff.") for ch in chs]
        said = (f"; {others} are lift-off columns, and only landings are read" if others else "")
        raise DataError(f"no column of the header names a landing: the columns are {names}{said}; {_NAMING}",
                        file=file)
    cartesian = {"xdot", "ydot", "omega"} <= has
    polar = {"speed", "angle", "omega"} <= has
    if cartesian:
        form, roles = "cartesian", COMPONENTS  # measured components beside derived speeds: the components
    elif polar and not has & {"xdot", "ydot"}:
        form, roles = "polar", POLAR_ROLES
    else:
        read = {_SHOWN[c]: landing[c][0].column.name for c in _ORDER if c in has}
        lacking = [_SHOWN[c] for c in COMPONENTS if c not in has]
        lacking_polar = [_SHOWN[c] for c in POLAR_ROLES if c not in has]
        raise DataError(f"the header names the landing's {read} but not its {' and '.join(lacking)} (for xdot0, "
                        f"ydot0, omega0) nor its {' and '.join(lacking_polar)} (for speed, angle, spin); the "
                        f"columns are {names}: {_NAMING}", file=file)
    chosen = {f"landing.{c}": landing[c][0] for c in roles}
    cols = {role: ch.column for role, ch in chosen.items()}
    check_absolute_units(table, cols, table.hint_style)

    read = tuple(c.name for c in cols.values())
    missing = _missing_rows(table, cols)
    if missing:
        i, (col_name, cell) = next(iter(missing.items()))
        what = "an empty cell" if _is_empty_cell(cell) else f"the missing value {str(cell).strip()!r}"
        row = [c.values[i] for c in table.columns]
        other = [s for s in (",", ";", "\t")
                 if s != table.delimiter and any(isinstance(v, str) and s in v for v in row)]
        if other and table.delimiter is not None:  # "30;-10;-500" under a comma header: one cell, the rest empty
            raise _err(table, f"{what}: the line separates its values with {other[0]!r}, the header with "
                       f"{table.delimiter!r}; use one separator throughout", col_name, i)
        raise _err(table, f"{what}; every landing needs a value: fill it in or delete the row", col_name, i)
    _decimal_convention(table, list(cols.values()))
    parsed: dict[str, np.ndarray] = {}
    errors = []
    for role, col in cols.items():
        parsed[role], error = _numbers(table, col)
        if error is not None:
            errors.append(error)
    if errors:
        raise min(errors, key=lambda e: e.row or 0)

    kinds = {"xdot": "velocity", "ydot": "velocity", "speed": "velocity", "omega": "spin", "angle": "angle"}
    unit_of: dict[str, tuple[str, str]] = {}
    scaled: dict[str, np.ndarray] = {}
    for role in cols:
        kind = kinds[role.split(".")[1]]
        unit, origin = _column_unit(table, chosen[role], kind, given)
        unit_of[role] = (unit, origin)
        if kind == "velocity":
            scaled[role] = velocity_to_scaled(parsed[role], unit, radius_m=radius_m)
        elif kind == "spin":
            scaled[role] = spin_to_scaled(parsed[role], unit)
        else:
            scaled[role] = np.rad2deg(parsed[role]) if unit == "rad" else parsed[role]  # degrees
    values = np.column_stack([parsed[r] for r in cols])
    units = {kinds[r.split(".")[1]]: u for r, (u, _) in unit_of.items()}
    origins = {kinds[r.split(".")[1]]: {"assumed": "default"}.get(o, o) for r, (_, o) in unit_of.items()}
    if len({u for r, (u, _) in unit_of.items() if kinds[r.split(".")[1]] == "velocity"}) > 1:
        shown = {cols[r].name: u for r, (u, _) in unit_of.items() if kinds[r.split(".")[1]] == "velocity"}
        raise DataError(f"the velocity columns are in different units {shown}; give both in one unit",
                        file=file, column=cols["landing.ydot"].name)
    if form == "polar":
        _polar_state(table, "landing", cols, parsed, scaled, unit_of, radius_m)  # the loader's checks and conversion
    _check_landing_sign(table, cols, scaled, unit_of)
    arr = np.column_stack([scaled[f"landing.{c}"] for c in COMPONENTS])
    try:
        states, _ = as_states(arr, "landing", landing=True, file=file)
    except DataError as exc:
        raise _relocate(table, exc, cols) from None
    return LandingTable(states, form, values, units, origins, read)
