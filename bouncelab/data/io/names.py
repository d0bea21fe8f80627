"""Column names: the synonym table that tells which column holds what, and the unit written in a name.

A *role* is ``"<state>.<component>"`` (``"landing.xdot"``, ``"liftoff_pi.omega"``, ``"landing.speed"``...)
or ``"setting"``. Names are compared in normalised form (:func:`normalize`); a unit at the end of a
header (``"vx0 [m/s]"``, ``"omega0_rpm"``) is not part of the name (:func:`split_header`).
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Mapping
from contextlib import suppress
from typing import Any

import numpy as np
import pandas as pd

from bouncelab.core.errors import DataError
from bouncelab.core.units import COMPONENTS, canonical_unit

STATES, PI_STATES = ("landing", "liftoff"), ("landing_pi", "liftoff_pi")
_STEMS: dict[str, tuple[str, ...]] = {
    "xdot": ("xdot", "dx", "dxdt", "vx", "velx", "xvel", "xvelocity", "velocityx", "u", "ux",
             "horizontalvelocity", "horizontalspeed", "hvel", "vh", "vhoriz", "vhorizontal"),
    "ydot": ("ydot", "dy", "dydt", "vy", "vely", "yvel", "yvelocity", "velocityy", "v", "uy",
             "verticalvelocity", "verticalspeed", "vvel", "vv", "vvert", "vvertical"),
    "omega": ("omega", "w", "om", "spin", "spinrate", "angularvelocity", "angvel", "omegaz", "wz"),
}
_PHASES: dict[str, tuple[str, ...]] = {
    "landing": ("0", "i", "in", "inb", "inbound", "incoming", "incident", "impact", "land", "landing",
                "pre", "before", "initial", "init", "touchdown", "td"),
    "liftoff": ("f", "1", "out", "outb", "outbound", "outgoing", "rebound", "lift", "liftoff", "post",
                "after", "final", "takeoff", "lo"),
}
# Interval markers, by what the name says the column holds: the half-width of a 95 % interval (what a campaign
# stores), one standard deviation (times Z95 on loading), or either, which the loader will not guess.
PI95_MARKERS = ("pi", "pi95", "hw", "halfwidth", "ci", "ci95")
SD_MARKERS = ("sd", "std", "stdev", "stddev", "sigma")
AMBIGUOUS_MARKERS = ("err", "error", "unc", "uncertainty")
_PI_MARKERS = (*PI95_MARKERS, *SD_MARKERS, *AMBIGUOUS_MARKERS)
_SETTING_NAMES = ("setting", "settings", "settingid", "settingno", "settingnumber", "launchersetting",
                  "launchersettings", "condition", "conditions", "conditionid", "testcondition", "testconditions",
                  "group", "groupid", "setup", "config", "configuration", "case", "testcase")

#: The synonym table used when ``columns=None``, in normalised form (docs/data.md, "Columns"): the stems
#: of each component, the landing and lift-off phase markers, the interval markers and the setting names.
#: A state column is ``stem + phase``, ``phase + stem`` or ``phase + stem + phase`` (a phase before the
#: stem must have two or more characters, and the stem too); an interval column is a state column name
#: with a marker before or after it.
COLUMN_SYNONYMS: dict[str, tuple[str, ...]] = {**_STEMS, **_PHASES, "pi": _PI_MARKERS, "setting": _SETTING_NAMES}
_NOT_SYNONYMS = frozenset({"indx"})  # a common column name the rules would read as bounce data


def _build_state_keys() -> dict[str, str]:
    """Every Cartesian state name (``vx0``, ``in_vx``, ``in_vx_0``...) and its role."""
    table = {}
    for state, phases in _PHASES.items():
        words = [ph for ph in phases if len(ph) > 1]  # a phase before the stem is a word: "in_vx", not "i_vx", "ivy"
        for comp, stems in _STEMS.items():
            for stem in stems:  # and a one-letter stem takes a phase only after it: "w_in", not "low"
                pre = words if len(stem) > 1 else []
                keys = [stem + ph for ph in phases] + [p + stem + q for p in pre for q in ("", *phases)]
                table.update({k: f"{state}.{comp}" for k in keys if k not in _NOT_SYNONYMS})
    return table


_STATE_KEYS = _build_state_keys()
# Speed and angle (launch-monitor files); the spin is the omega stem. Kept out of role_of, so that a
# Cartesian file with derived speeds and angles reads as a Cartesian one.
POLAR_STEMS: dict[str, tuple[str, ...]] = {"speed": ("speed", "ballspeed", "totalspeed", "velocity", "vel", "vtot",
                                                     "vtotal"), "angle": ("angle", "theta")}
_POLAR_KEYS: dict[str, str] = {
    "launchangle": "liftoff.angle", "launchspeed": "liftoff.speed", "launchspin": "liftoff.omega",
    "descentangle": "landing.angle", "incidenceangle": "landing.angle", "angleofincidence": "landing.angle",
    **{key: f"{state}.{comp}" for state, phases in _PHASES.items() for comp, stems in POLAR_STEMS.items()
       for stem in stems for key in [stem + ph for ph in phases] + [ph + stem for ph in phases if len(ph) > 1]},
}
#: The components of a state given in polar form, in order (the spin is the ``omega`` role).
POLAR_ROLES = ("speed", "angle", "omega")
ROLES = (*(f"{s}.{c}" for s in (*STATES, *PI_STATES) for c in (*COMPONENTS, "speed", "angle")), "setting")
_BRACKET = re.compile(r"^(.*?)[\s_]*[\[\(\{]([^\[\]\(\)\{\}]*)[\]\)\}]\s*$")
# Relative units: a value as a fraction of another, which bouncelab does not read.
_RELATIVE_WORDS = frozenset({"percent", "percentage", "pct", "rel", "relative", "fraction", "frac"})


def normalize(name: str) -> str:
    """Lower-case letters and digits only; ``ω`` -> omega, ``ẋ`` -> xdot."""
    text = unicodedata.normalize("NFKD", str(name)).replace("ω", "omega").replace("Ω", "omega")
    return re.sub(r"[^a-z0-9]", "", text.replace("\u0307", "dot").lower())


def marked(key: str, table: Mapping[str, str]) -> tuple[str, str] | None:
    """(``<state>_pi.<component>``, marker) of a name of ``table`` with an interval marker around it, else None."""
    for m in _PI_MARKERS:
        for rest in (key[: -len(m)] if key.endswith(m) else None, key[len(m):] if key.startswith(m) else None):
            if rest and rest in table:
                return table[rest].replace(".", "_pi."), m
    return None


def role_of(key: str, polar: bool = False) -> str | None:
    """The role a normalised column name stands for (Cartesian, or with ``polar`` the speed and angle roles)."""
    if not polar and key in _SETTING_NAMES:
        return "setting"
    table = _POLAR_KEYS if polar else _STATE_KEYS
    found = table.get(key) or marked(key, table)
    return found if found is None or isinstance(found, str) else found[0]


def synonym_role(name: str, extra: Mapping[str, str] | None = None) -> tuple[str, bool] | None:
    """(role, whether the whole name says it) of a column's name, else without its unit; ``extra``: more names."""
    for key, whole in ((normalize(name), True), (normalize(split_header(name)[0]), False)):
        if (role := role_of(key) or role_of(key, polar=True) or (extra or {}).get(key)) is not None:
            return role, whole
    return None


def interval_marker(name: str) -> str | None:
    """The interval marker in a column's name (``err`` of ``vx0_err [m/s]``), or None (``dVx in``)."""
    for key in (normalize(name), normalize(split_header(name)[0])):
        for table in (_STATE_KEYS, _POLAR_KEYS):
            if (found := marked(key, table)) is not None:
                return found[1]
    # A name given in columns= need not be a state's (``a_sd``, ``sigma vx``): its last or first word still says.
    words = [w for w in re.split(r"[^a-z0-9]+", split_header(name)[0].lower()) if w]
    return next((w for w in words[-1:] + words[:1] if w in _PI_MARKERS), None)


def unit_of(text: str) -> dict[str, str]:
    """Canonical unit of ``text`` for each kind it is a unit of (velocity, spin, angle); empty if none."""
    found = {}
    for kind in ("velocity", "spin", "angle"):
        with suppress(DataError):
            found[kind] = canonical_unit(text, kind)
    return found


def split_header(name: str) -> tuple[str, str | None]:
    """Split ``"vx0 [m/s]"`` into ``("vx0", "m/s")`` (also ``vx0_mps``, ``vx0 m/s``); ``(name, None)`` if no unit."""
    if (m := _BRACKET.match(name)) and m.group(1).strip():
        return m.group(1).strip(), m.group(2).strip()
    tokens = [t for t in re.split(r"[\s_]+", name.strip()) if t]
    for k in (k for k in (3, 2, 1) if len(tokens) > k):
        for joiner in ("", "/"):
            if unit_of(cand := joiner.join(tokens[-k:])):
                return " ".join(tokens[:-k]), cand
    return name, None


def relative_word(text: str | None) -> str | None:
    """The relative unit (``%``, ``percent``, ``pct``, ``rel``...) ``text`` gives, or None."""
    if text is None:
        return None
    if "%" in text or "‰" in text:
        return "%"
    words = [w for w in re.split(r"[^a-z]+", text.lower()) if w]
    return "per cent" if "per" in words and "cent" in words else next((w for w in words if w in _RELATIVE_WORDS), None)


def relative_unit(name: str, unit_text: str | None) -> str | None:
    """The relative unit a column's name or unit gives: ``%`` anywhere, a word as the unit or the last word."""
    base, unit = split_header(name)
    last = [w for w in re.split(r"[\s_]+", base.strip()) if w][-1:]
    return ("%" if "%" in name or "‰" in name else relative_word(unit_text) or relative_word(unit)
            or (relative_word(last[0]) if last and last[0].lower() in _RELATIVE_WORDS else None))


def to_numbers(cells: Any, decimal_comma: bool = False) -> np.ndarray:
    """Cells as floats by :func:`pandas.to_numeric` (the one number parser), NaN if none; ``-0`` keeps its sign."""
    text = pd.Series(cells, dtype=object).astype(str).str.strip().str.replace("\u2212", "-", regex=False)
    vals = pd.to_numeric(text.str.replace(",", ".", regex=False) if decimal_comma else text, errors="coerce")
    return np.copysign(vals.to_numpy(dtype=float), np.where(text.str.startswith("-"), -1.0, 1.0))


def is_number(cell: Any) -> bool:
    """Whether a cell holds a number (text that :func:`to_numbers` reads, or a number that is not a bool)."""
    if isinstance(cell, str):
        return not np.isnan(to_numbers([cell])[0])
    return isinstance(cell, int | float | np.number) and not isinstance(cell, bool | np.bool_)


def unit_cell(cell: object) -> str:
    return str(cell).strip().strip("[](){}").strip()


def is_units_row(cells: list, blank) -> bool:
    """Whether a row under the header gives units: no number, at least half of it units (known, or bracketed)."""
    texts = [str(c).strip() for c in cells if not blank(c)]
    if not texts or any(is_number(unit_cell(t)) for t in texts):
        return False
    return sum(bool(unit_of(unit_cell(t))) or bool(re.fullmatch(r"\[[^\[\]]*\]", t)) for t in texts) * 2 >= len(texts)
