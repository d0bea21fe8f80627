"""Landings alone (no lift-offs), as ``bouncelab predict --input`` reads them: the loader's pipeline asked for
landings only.

A file with a header is read by the text backend and the steps of :mod:`bouncelab.data.io.interpret`: a landing
as ``xdot0, ydot0, omega0`` or ``speed, angle, spin`` (any of the loader's names, and names without a phase marker:
``vx``, ``speed``...), in any order, other columns left alone; units from the header or a units row, else
``units=``, else the scaled ones and degrees. A file without a header is three numbers a line (blank, comma or
semicolon separated): the columns ``xdot0 ydot0 omega0``. A comment may follow a row (``1 -2 3  # note``).
"""

from __future__ import annotations

import codecs
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bouncelab.core.errors import DataError, MissingFileError
from bouncelab.core.files import check_regular_file, read_regular_file
from bouncelab.core.units import BALL_RADIUS_M, COMPONENTS, ball_radius
from bouncelab.data.io import interpret as ip
from bouncelab.data.io.interpret import DEFAULT_UNITS, KINDS, Role
from bouncelab.data.io.names import _STEMS, POLAR_ROLES, POLAR_STEMS, is_number, synonym_role
from bouncelab.data.io.read import encoding, is_comment, is_empty, lines, read_text

__all__ = ["DEFAULT_UNITS", "LandingTable", "read_landings"]

# Names without a phase marker (``xdot``, ``vx``, ``speed``, ``spin``): in a file of landings alone they can only be
# the landing's. One-letter stems are left out (``v`` is a ydot to the synonyms, a speed to many), but ``w``.
_BARE = {stem: f"landing.{comp}" for comp, stems in (*_STEMS.items(), *POLAR_STEMS.items()) for stem in stems
         if len(stem) > 1 or stem == "w"}
_SHOWN = {"xdot": "xdot", "ydot": "ydot", "omega": "spin", "speed": "speed", "angle": "angle"}  # in this order
_ROWS = ("xdot0", "ydot0", "omega0")  # the columns of a file without a header
_NAMING = ("name the columns xdot0, ydot0, omega0, or speed, angle, spin (the angle of incidence below the "
           "horizontal), e.g. a header 'speed,angle,spin' with a units row 'm/s,deg,rpm' under it; or leave the "
           "header out to give three numbers a line, xdot0 ydot0 omega0")


@dataclass(frozen=True)
class LandingTable:
    """Landings read by :func:`read_landings`: ``states`` (n, 3) ``[xdot0, ydot0, omega0]`` in scaled units;
    ``form`` ``"cartesian"``, ``"polar"`` (read by name) or ``"rows"`` (no header); ``values`` the numbers as
    the file gives them (``xdot, ydot, omega`` or ``speed, angle, spin``); ``units`` the unit of each kind read
    and ``unit_origins`` where it came from (``"header"``, ``"units="`` or ``"default"``); ``columns`` the file's
    columns read, in the order of ``values``."""

    states: np.ndarray
    form: str
    values: np.ndarray
    units: dict[str, str]
    unit_origins: dict[str, str] = field(default_factory=dict)
    columns: tuple[str, ...] = ()


def read_landings(file: str | os.PathLike[str], *, data: bytes | None = None, units: Mapping[str, str] | None = None,
                  radius_m: float = BALL_RADIUS_M) -> LandingTable:
    """Read a text file of landing states (no lift-offs) by column name.

    ``file`` is the file's path, or with ``data`` (its bytes, e.g. standard input) only its name in messages;
    ``units`` ``{"velocity": ..., "spin": ..., "angle": "deg" | "rad"}`` gives the units of columns whose
    header (or units row) gives none; ``radius_m`` is the ball radius of the scaling, in metres.

    Raises
    ------
    FileNotFoundError
        ``file`` does not exist (and no ``data`` is given).
    DataError
        Naming the file, the column and the line: columns that cannot be told apart or are missing, an empty
        or non-numeric cell, an unknown or conflicting unit, a landing that does not come down.
    """
    name = os.fspath(file)
    radius, given = ball_radius(radius_m, file=name), ip.check_units_arg(units, name)
    if data is None:
        if not (path := Path(name).expanduser()).exists():
            raise MissingFileError(f"no such file: {name!r}", file=name)
        if path.is_dir():
            raise DataError("it is a folder, not a file of landings", file=name)
        check_regular_file(path, name)  # a FIFO would hang, /dev/zero never end
        data = read_regular_file(path, name)
    raw = re.sub(rb"(?<=\S)[ \t]+#[^\r\n]*", b"", data.removeprefix(codecs.BOM_UTF8))  # a comment after a row
    first = next((ln for ln in lines(raw, 0, encoding(raw)) if not is_comment(ln.text)), None)
    if first is None and b"\x00" not in raw:
        raise DataError("no landing rows found (the file is empty or holds only comments)", file=name)
    if first is not None and any(map(is_number, re.split(r"[,;\s]+", first.text.strip()))):  # no header
        table = read_text(None, name, raw=re.sub(rb"[,;]", b" ", raw), names=_ROWS)
        return _read(ip.start(table, radius, None), given, dict(zip(
            (Role("landing", c) for c in COMPONENTS), map(ip.Column, _ROWS), strict=True)))
    # A header that names landing columns is the header (not a title above a stray note with more cells).
    named = first is not None and any((m := synonym_role(c.strip(), _BARE)) and m[0].startswith("landing.")
                                      for c in re.split(r"[,;\t]|\s+", first.text) if c.strip())
    return _read(ip.start(read_text(None, name, raw=raw, header_row=first.no if named else None), radius, None), given)


def _by_name(r: ip.Rows) -> tuple[str, dict[Role, ip.Column]]:
    """The landing's columns, Cartesian or polar, found by name."""
    if len(r.frame) == 0:
        raise r.err("the file has a header but no landing rows")
    found = ip.candidates(r, _BARE)  # the loader's synonyms (names with a phase: xdot0, vx_in...), then bare names
    landing = {c: found[Role("landing", c)] for c in _SHOWN}
    if several := [(c, cols) for c, cols in landing.items() if len(cols) > 1]:
        c, cols = several[0]
        raise r.err(f"the columns {[col.name for col in cols]} all name the landing's {_SHOWN[c]}; keep one, or rename "
                    "the others", cols[0].name)
    if not (has := {c for c, cols in landing.items() if cols}):
        others = [col.name for role, cols in found.items() if role.state == "liftoff" for col in cols]
        said = f"; {others} are lift-off columns, and only landings are read" if others else ""
        raise r.err(f"no column of the header names a landing: the columns are {r.names}{said}; {_NAMING}")
    if {"xdot", "ydot", "omega"} <= has:
        form, roles = "cartesian", COMPONENTS  # measured components beside derived speeds: the components
    elif {"speed", "angle", "omega"} <= has and not has & {"xdot", "ydot"}:
        form, roles = "polar", POLAR_ROLES
    else:
        read = {_SHOWN[c]: landing[c][0].name for c in _SHOWN if c in has}
        raise r.err(f"the header names the landing's {read} but not its "
                    f"{' and '.join(_SHOWN[c] for c in COMPONENTS if c not in has)} (for xdot0, ydot0, omega0) nor its "
                    f"{' and '.join(_SHOWN[c] for c in POLAR_ROLES if c not in has)} (for speed, angle, spin); the "
                    f"columns are {r.names}: {_NAMING}")
    return form, {Role("landing", c): landing[c][0] for c in roles}


def _read(r: ip.Rows, given: dict[str, str], cols: dict[Role, ip.Column] | None = None) -> LandingTable:
    """The loader's steps for the landing columns (``cols``, else found by name): units, missing and bad cells."""
    form, cols = ("rows", cols) if cols is not None else _by_name(r)
    ip.check_absolute_units(r, cols)
    if missing := ip.missing_rows(r, [c.name for c in cols.values()]):
        i, (col, cell) = next(iter(missing.items()))
        what = "an empty cell" if is_empty(cell) else f"the missing value {str(cell).strip()!r}"
        row = r.frame.iloc[i].tolist()
        other = [s for s in (",", ";", "\t") if s != r.t.delimiter and any(isinstance(v, str) and s in v for v in row)]
        if other and r.t.delimiter is not None:  # "30;-10;-500" under a comma header: one cell, the rest empty
            raise r.err(f"{what}: the line separates its values with {other[0]!r}, the header with "
                        f"{r.t.delimiter!r}; use one separator throughout", col, i)
        raise r.err(f"{what}; every landing needs a finite value: fill it in or delete the row", col, i)
    r, cols, _ = ip.read_columns(r, cols, missing="raise", what="landing")
    cols = ip.with_units(r, cols, given)
    velocity = {c.name: c.unit for role, c in cols.items() if KINDS[role.comp] == "velocity"}
    if len(set(velocity.values())) > 1:
        raise r.err(f"the velocity columns are in different units {velocity}; give both in one unit",
                    cols[Role("landing", "ydot")].name)
    values, names = np.column_stack([c.raw for c in cols.values()]), tuple(c.name for c in cols.values())
    unit_of = {KINDS[role.comp]: c.unit for role, c in cols.items()}
    origins = {KINDS[role.comp]: {"assumed": "default"}.get(c.origin, c.origin) for role, c in cols.items()}
    if form == "polar":
        cols = ip.polar_state(r, cols, "landing")  # the loader's checks and conversion
    if form == "rows" and (up := np.flatnonzero(~(cols[Role("landing", "ydot")].scaled < 0))).size:
        raise r.err(f"a landing comes down, so its ydot0 (the second number) must be negative (y points up); got "
                    f"{r.cell('ydot0', int(up[0]))}. If the file gives speed, angle and spin, put a header "
                    "'speed,angle,spin' over the rows", "ydot0", int(up[0]))
    ip.check_landing_sign(r, cols)
    return LandingTable(ip.states(r, cols, "landing"), form, values, unit_of, origins, names)
