"""Column roles and the synonym table that recognises a file's column names (``columns=None``).

A *role* is ``"<state>.<component>"`` (``"landing.xdot"``, ``"liftoff_pi.omega"``...) or
``"setting"``; names are compared in normalised form (:func:`_normalize`).
"""

from __future__ import annotations

import re
import unicodedata

from bouncelab.data.units import COMPONENTS

_STATES = ("landing", "liftoff")
_PI_STATES = ("landing_pi", "liftoff_pi")


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
#: docstring of :mod:`bouncelab.data.io`): the stems of each component, the landing and lift-off
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


def _normalize(name: str) -> str:
    """Lower-case letters and digits only; ``ω`` -> omega, ``ẋ`` -> xdot."""
    text = unicodedata.normalize("NFKD", str(name))
    text = text.replace("ω", "omega").replace("Ω", "omega").replace("\u0307", "dot")
    return re.sub(r"[^a-z0-9]", "", text.lower())
