"""How loader messages name the options a person can change: Python keywords or command-line flags.

A loader error often ends in advice ("pass ``units={'spin': 'rpm'}``"). From the ``bouncelab``
command the same advice must name the flag (``--spin-unit rpm``). The loader is told which
language to speak (``load_campaign(..., hint_style="cli")``, which only the command line passes)
and builds every piece of advice through the functions here; messages are never rewritten after
the fact.
"""

from __future__ import annotations

import json
from typing import Any

from bouncelab.core.errors import DataError

#: The languages loader messages can speak: Python keywords (default) or the command's flags.
HINT_STYLES = ("python", "cli")

# Python keyword -> command-line flag of each loader option.
_FLAGS = {
    "columns": "--columns", "sheet": "--sheet", "missing": "--missing", "header_row": "--header-row",
    "units": "--velocity-unit/--spin-unit",
    "intervals": "--intervals", "surrogate": "--surrogate",
}
_UNIT_FLAGS = {"velocity": "--velocity-unit", "spin": "--spin-unit", "angle": "--angle-unit"}


def check_style(style: Any) -> str:
    """``style`` if it is one of :data:`HINT_STYLES`, else a DataError naming ``hint_style``."""
    if style not in HINT_STYLES:
        raise DataError(f"hint_style must be one of {', '.join(map(repr, HINT_STYLES))}; got {style!r}")
    return style


def option(name: str, style: str) -> str:
    """The option itself: ``columns=`` (Python) or ``--columns`` (command line)."""
    return _FLAGS[name] if style == "cli" else f"{name}="


def setting(name: str, value: Any, style: str) -> str:
    """An option with its value: ``missing='drop'`` or ``--missing drop``."""
    return f"{_FLAGS[name]} {value}" if style == "cli" else f"{name}={value!r}"


def unit_setting(kind: str, unit: str, style: str) -> str | None:
    """How to declare a unit: ``units={'spin': 'rpm'}`` or ``--spin-unit rpm`` (None: no flag for it)."""
    if style == "cli":
        flag = _UNIT_FLAGS.get(kind)
        return None if flag is None else f"{flag} {unit}"
    return f"units={{{kind!r}: {unit!r}}}"


def columns_call(file: str, parts: list[tuple[str, Any]], style: str) -> str:
    """The ``columns=`` argument (or ``--columns`` JSON) that names ``parts`` (key, names) explicitly."""
    if style == "cli":
        return "--columns '" + json.dumps(dict(parts)) + "'"
    return f"load_campaign({file!r}, columns={{{', '.join(f'{k!r}: {v!r}' for k, v in parts)}}})"


def columns_entry(key: str, names: Any, style: str) -> str:
    """One entry of ``columns=`` (or ``--columns`` JSON): ``columns={'landing': {'speed': ...}}``."""
    if style == "cli":
        return "--columns '" + json.dumps({key: names}) + "'"
    return f"columns={{{key!r}: {names!r}}}"


def declare_units_hint(kind: str, units: tuple[str, ...] | list[str], *, style: str = "python") -> str:
    """How to declare the unit of ``kind``: ``"units={'spin': 'rpm'}"`` (or a choice of several).

    Every loader message that asks for a unit goes through here, so that it speaks the caller's
    language: ``style="python"`` names the keyword, ``style="cli"`` the ``bouncelab`` flag
    (``--spin-unit rpm``). (Moved here from ``bouncelab.core.plausibility``, whose errors carry hints
    as data; the loader's own wording goes with this module.)
    """
    if style == "cli":
        flag = "--velocity-unit" if kind == "velocity" else "--spin-unit"
        options = " or ".join(f"{flag} {u}" for u in units)
    else:
        options = " or ".join(f"units={{{kind!r}: {u!r}}}" for u in units)
    example = "[m/s]" if kind == "velocity" else "[rpm]"
    return f"pass {options}, or put the unit in the column header (e.g. 'name {example}')"
