"""Units written in the file itself: at the end of a column header (``"vx0 [m/s]"``,
``"omega0_rpm"``) or in a units row.

Only recognises unit text; the conversions are :mod:`bouncelab.data.units`.
"""

from __future__ import annotations

import re

from bouncelab.data.units import canonical_unit
from bouncelab.errors import DataError

_UNIT_KINDS = ("velocity", "spin")
_PER_SECOND = {"1/s", "s-1", "s^-1", "/s"}


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


def _header_unit(name: str) -> tuple[str | None, bool]:
    unit = _split_header(name)[1]
    return unit, unit is not None
