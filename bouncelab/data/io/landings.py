"""Landings alone (no lift-offs), as ``bouncelab predict --input`` reads them.

A file with a header is read as the loader reads a text table (:func:`bouncelab.data.io.read.read_text`)
and interpreted by its interpreter (:class:`bouncelab.data.io.interpret.Reading`): a landing as ``xdot0,
ydot0, omega0`` or ``speed, angle, spin`` (any of the loader's names, and names without a phase marker:
``vx``, ``speed``...), in any order, other columns left alone; units from the header or a units row, else
``units=``, else the scaled ones and degrees. A file without a header is three numbers a line.
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
from bouncelab.data.io.interpret import Choice, Reading, check_units_arg
from bouncelab.data.io.names import _STEMS, POLAR_ROLES, POLAR_STEMS, normalize, role_of, split_header
from bouncelab.data.io.read import is_empty, read_text

__all__ = ["DEFAULT_UNITS", "LandingTable", "read_landings"]

#: The units a landing is read in when neither the file nor ``units=`` gives one.
DEFAULT_UNITS = {"velocity": "radius/s", "spin": "rad/s", "angle": "deg"}

# Names without a phase marker (``xdot``, ``vx``, ``speed``, ``spin``): in a file of landings alone they can only be
# the landing's. One-letter stems are left out (``v`` is a ydot to the synonyms, a speed to many), but ``w``.
_BARE = {stem: comp for comp, stems in (*_STEMS.items(), *POLAR_STEMS.items()) for stem in stems
         if len(stem) > 1 or stem == "w"}
_ORDER = ("xdot", "ydot", "omega", "speed", "angle")
_SHOWN = {"xdot": "xdot", "ydot": "ydot", "omega": "spin", "speed": "speed", "angle": "angle"}
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
    from bouncelab.data.io.load import _check_regular_file, _read_bytes

    name = os.fspath(file)
    radius = ball_radius(radius_m, file=name)
    given = check_units_arg(units, name)
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
    # A header that names landing columns is the header (not a title above a stray note with more cells);
    # comments after a row are dropped, as lines of their own are.
    named = any(_role(c.strip()) for c in re.split(r"[,;\t]|\s+", lines[first]) if c.strip())
    body = "\n".join(line if line.lstrip().startswith(("#", "%")) else re.sub(r"\s+#.*$", "", line) for line in lines)
    return _by_name(Reading(read_text(name, body.encode("utf-8"), header_row=first + 1 if named else None), radius,
                            plausible=None), given)


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
    rows, linenos = [], []
    for lineno, line in enumerate(lines, start=1):
        if line.lstrip().startswith(("#", "%")):
            cells = _cells(line)
            if len(cells) in (2, 3, 4) and sum(_number(c) is not None for c in cells[1:]) * 2 >= len(cells) - 1:
                raise DataError(f"line {lineno} starts with {line.lstrip()[0]!r} like a comment but holds a landing "
                                f"row: {line.strip()!r}; give three numbers, or delete the line", file=file,
                                row=len(rows) + 1)
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
            raise DataError(f"line {lineno} is not three finite numbers: {body!r} ({v!r} "
                            f"{'is not a number' if values[k] is None else 'is not finite'})", file=file,
                            column=("xdot0", "ydot0", "omega0")[k], row=len(rows) + 1)
        rows.append(values)
        linenos.append(lineno)
    if not rows:
        raise DataError("no landing rows found", file=file)
    values = np.array(rows, dtype=float)
    unit = {kind: given.get(kind, DEFAULT_UNITS[kind]) for kind in ("velocity", "spin")}
    states = np.column_stack([velocity_to_scaled(values[:, :2], unit["velocity"], radius_m=radius_m),
                              spin_to_scaled(values[:, 2], unit["spin"])])
    if (up := np.flatnonzero(~(states[:, 1] < 0))).size:
        i = int(up[0])
        raise DataError(f"line {linenos[i]}: a landing comes down, so its ydot0 (the second number) must be negative "
                        f"(y points up); got {values[i, 1]:g}. If the file gives speed, angle and spin, put a header "
                        "'speed,angle,spin' over the rows", file=file, column="ydot0", row=i + 1)
    return LandingTable(states, "rows", values, unit, {kind: "units=" if kind in given else "default" for kind in unit})


def _role(name: str) -> str | None:
    """The landing role a column name stands for: the loader's synonyms with a phase (``xdot0``, ``vx_in``,
    ``speed_in``...) or a name without one (``vx``, ``speed``); None for anything else (lift-offs too)."""
    for key in (normalize(name), normalize(split_header(name)[0])):
        role = role_of(key) or role_of(key, polar=True) or (f"landing.{_BARE[key]}" if key in _BARE else None)
        if role is not None:
            return role if role.startswith("landing.") else None
    return None


def _by_name(r: Reading, given: dict[str, str]) -> LandingTable:
    file = r.file
    if len(r.frame) == 0:
        raise DataError("the file has a header but no landing rows", file=file)
    found = r.candidates()  # the loader's synonyms: names with a phase (xdot0, vx_in, speed_in...)
    for name in r.names:
        if not any(name == ch.name for chs in found.values() for ch in chs):
            for key, whole in ((normalize(name), True), (normalize(split_header(name)[0]), False)):
                if key in _BARE:
                    found[f"landing.{_BARE[key]}"].append(Choice(name, whole))
                    break
    landing = {c: found[f"landing.{c}"] for c in _ORDER}
    if several := [(c, chs) for c, chs in landing.items() if len(chs) > 1]:
        c, chs = several[0]
        raise DataError(f"the columns {[ch.name for ch in chs]} all name the landing's {_SHOWN[c]}; keep one, or "
                        "rename the others", file=file, column=chs[0].name)
    has = {c for c, chs in landing.items() if chs}
    if not has:
        others = [ch.name for role, chs in found.items() if role.startswith("liftoff.") for ch in chs]
        said = f"; {others} are lift-off columns, and only landings are read" if others else ""
        raise DataError(f"no column of the header names a landing: the columns are {r.names}{said}; {_NAMING}",
                        file=file)
    if {"xdot", "ydot", "omega"} <= has:
        form, roles = "cartesian", COMPONENTS  # measured components beside derived speeds: the components
    elif {"speed", "angle", "omega"} <= has and not has & {"xdot", "ydot"}:
        form, roles = "polar", POLAR_ROLES
    else:
        read = {_SHOWN[c]: landing[c][0].name for c in _ORDER if c in has}
        raise DataError(f"the header names the landing's {read} but not its "
                        f"{' and '.join(_SHOWN[c] for c in COMPONENTS if c not in has)} (for xdot0, ydot0, omega0) nor "
                        f"its {' and '.join(_SHOWN[c] for c in POLAR_ROLES if c not in has)} (for speed, angle, spin); "
                        f"the columns are {r.names}: {_NAMING}", file=file)
    r.chosen = {f"landing.{c}": landing[c][0] for c in roles}
    cols = [ch.name for ch in r.chosen.values()]
    r.check_absolute_units()
    if missing := r.missing_rows(cols):
        i, (col, cell) = next(iter(missing.items()))
        what = "an empty cell" if is_empty(cell) else f"the missing value {str(cell).strip()!r}"
        row = r.frame.iloc[i].tolist()
        other = [s for s in (",", ";", "\t") if s != r.t.delimiter and any(isinstance(v, str) and s in v for v in row)]
        if other and r.t.delimiter is not None:  # "30;-10;-500" under a comma header: one cell, the rest empty
            raise r.err(f"{what}: the line separates its values with {other[0]!r}, the header with "
                        f"{r.t.delimiter!r}; use one separator throughout", col, i)
        raise r.err(f"{what}; every landing needs a value: fill it in or delete the row", col, i)
    r.decimal_convention(cols)
    parsed = {role: r.numbers(ch.name) for role, ch in r.chosen.items()}
    if errors := [e for _, e in parsed.values() if e is not None]:
        raise min(errors, key=lambda e: e.row or 0)
    r.parsed = {role: v for role, (v, _) in parsed.items()}
    for role in r.chosen:
        r.unit_of[role] = r.column_unit(role, given)
        r.scaled[role] = r.convert(role, r.unit_of[role][0])
    kinds = {"xdot": "velocity", "ydot": "velocity", "speed": "velocity", "omega": "spin", "angle": "angle"}
    velocity = {r.col(role): u for role, (u, _) in r.unit_of.items() if kinds[role.split(".")[1]] == "velocity"}
    if len(set(velocity.values())) > 1:
        raise DataError(f"the velocity columns are in different units {velocity}; give both in one unit", file=file,
                        column=r.col("landing.ydot"))
    values = np.column_stack([r.parsed[role] for role in r.chosen])
    units = {kinds[role.split(".")[1]]: u for role, (u, _) in r.unit_of.items()}
    origins = {kinds[role.split(".")[1]]: {"assumed": "default"}.get(o, o) for role, (_, o) in r.unit_of.items()}
    if form == "polar":
        r.polar_state("landing")  # the loader's checks and conversion
    r.check_landing_sign()
    return LandingTable(r.states("landing", landing=True), form, values, units, origins, tuple(cols))
