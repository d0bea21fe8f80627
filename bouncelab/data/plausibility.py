"""What a golf bounce can measure: the ranges that tell a unit mistake from a real number.

A golf ball that lands on turf has a speed of a few to some fifty metres per second and a spin
of a few thousand rpm: the paper's Table 1 spans landing speeds of 1.93 to 56.1 m/s and spins
of -3880 to 16200 rpm over both campaigns. A number far outside such ranges is not a strange
bounce but a wrong unit: 3000 "rad/s" that were rpm is 28 600 rpm, 50 "radii/s" that were
ft/s is a 1 m/s landing. This module holds those ranges in one place
(:data:`PLAUSIBLE_RANGES`), checks states against them (:func:`implausibility`) and lists the
units in which a column of numbers without a unit would be plausible
(:func:`plausible_units`); the file loader uses it, and so can anything else that takes
numbers from a person.

The ranges are deliberately wide (a factor of about 1.5 around the paper's extremes): they
catch unit mistakes (factors of 3.3, 9.5, 47 or 60), not unusual shots. To accept data beyond
them on purpose, pass wider ranges, e.g.
``load_campaign(path, units=..., plausible=PLAUSIBLE_RANGES.widened(max_spin=40_000))``.

Examples
--------
>>> import numpy as np
>>> from bouncelab.data.plausibility import implausibility
>>> landing = np.array([[900.0, -700.0, 3000.0]])   # 3000 rad/s: rpm read as rad/s
>>> liftoff = np.array([[400.0, 200.0, 300.0]])
>>> implausibility(landing, liftoff).reason  # doctest: +ELLIPSIS
'3000 rad/s is 28648 rpm, beyond 20000 rpm...'
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from bouncelab.data.units import BALL_RADIUS_M, COMPONENTS, SPEED_UNITS, SPIN_UNITS, canonical_unit

__all__ = [
    "CANDIDATE_UNITS",
    "PLAUSIBLE_RANGES",
    "Implausibility",
    "PlausibleRanges",
    "declare_units_hint",
    "implausibility",
    "plausible_units",
]

_RPM = 2.0 * math.pi / 60.0  # rad/s per rpm


@dataclass(frozen=True)
class PlausibleRanges:
    """Magnitudes a golf bounce can have, in physical units.

    Attributes
    ----------
    max_speed
        Largest ``|xdot|`` or ``|ydot|``, landing or lift-off, in m/s (default 90 m/s: faster
        than the fastest drive; the paper's fastest landing is 56.1 m/s).
    max_spin
        Largest ``|omega|``, landing or lift-off, in rpm (default 20 000 rpm; the paper's
        spins span -3880 to 16 200 rpm).
    min_median_landing_speed
        Smallest median landing speed ``sqrt(xdot0^2 + ydot0^2)`` of a file, in m/s (default
        1.0 m/s; the paper's slowest landing is 1.93 m/s). Used only to tell units apart when a
        file gives none.
    min_peak_spin
        Smallest largest ``|omega|`` of a file, landing and lift-off together, in rpm (default
        300 rpm: a ball rolling off the turf at 5 m/s already spins at 2200 rpm). Used only to
        tell units apart when a file gives none.
    """

    max_speed: float = 90.0
    max_spin: float = 20_000.0
    min_median_landing_speed: float = 1.0
    min_peak_spin: float = 300.0

    def widened(self, **changes: float) -> PlausibleRanges:
        """A copy with some limits changed (``PLAUSIBLE_RANGES.widened(max_spin=40_000)``)."""
        return dataclasses.replace(self, **changes)


#: The default ranges (see :class:`PlausibleRanges`).
PLAUSIBLE_RANGES = PlausibleRanges()

#: Units tried, in this order, for a column that gives none; the first is bouncelab's scaled unit.
CANDIDATE_UNITS: dict[str, tuple[str, ...]] = {
    "velocity": ("radius/s", "m/s", "ft/s", "km/h", "mph"),
    "spin": ("rad/s", "rpm", "rev/s"),
}


@dataclass(frozen=True)
class Implausibility:
    """Why a set of bounces cannot be in the units they are said to be in.

    Attributes
    ----------
    state, component
        Where: ``"landing"`` or ``"liftoff"``, and ``"xdot"``, ``"ydot"`` or ``"omega"``.
    row
        0-based bounce at fault, or ``None`` for a property of the whole set (a median).
    kind
        ``"velocity"`` or ``"spin"``.
    reason
        A sentence in physical units, e.g. ``"3000 rad/s is 28648 rpm, beyond 20000 rpm, which no
        golf ball reaches"``.
    """

    state: str
    component: str
    row: int | None
    kind: str
    reason: str


def implausibility(
    landing,
    liftoff,
    *,
    radius_m: float = BALL_RADIUS_M,
    ranges: PlausibleRanges = PLAUSIBLE_RANGES,
    kinds: tuple[str, ...] = ("velocity", "spin"),
    lower: bool = False,
) -> Implausibility | None:
    """The first reason why ``landing`` and ``liftoff`` (scaled units) cannot be golf bounces, or ``None``.

    Parameters
    ----------
    landing, liftoff
        (n, 3) arrays ``[xdot, ydot, omega]`` in radii/s and rad/s.
    radius_m
        Ball radius used for the scaling, in metres (``v[m/s] = v[radii/s] * R``).
    ranges
        The limits (default :data:`PLAUSIBLE_RANGES`).
    kinds
        Which quantities to check.
    lower
        Also apply the lower limits (``min_median_landing_speed``, ``min_peak_spin``), which
        only make sense for telling units apart.
    """
    states = {"landing": np.asarray(landing, dtype=float), "liftoff": np.asarray(liftoff, dtype=float)}
    if "velocity" in kinds:
        for state, arr in states.items():
            for k in (0, 1):
                speed = np.abs(arr[:, k]) * radius_m
                big = speed > ranges.max_speed
                if big.any():
                    i = int(np.argmax(big))
                    return Implausibility(
                        state, COMPONENTS[k], i, "velocity",
                        f"{_fmt(arr[i, k])} radii/s is {_fmt(arr[i, k] * radius_m)} m/s, faster than "
                        f"{ranges.max_speed:g} m/s, which no golf ball reaches",
                    )
        if lower and len(states["landing"]):
            med = float(np.median(np.hypot(states["landing"][:, 0], states["landing"][:, 1]))) * radius_m
            if med < ranges.min_median_landing_speed:
                return Implausibility(
                    "landing", "ydot", None, "velocity",
                    f"the median landing speed would be {_fmt(med)} m/s, slower than "
                    f"{ranges.min_median_landing_speed:g} m/s, which no golf landing is",
                )
    if "spin" in kinds:
        for state, arr in states.items():
            rpm = np.abs(arr[:, 2]) / _RPM
            big = rpm > ranges.max_spin
            if big.any():
                i = int(np.argmax(big))
                return Implausibility(
                    state, "omega", i, "spin",
                    f"{_fmt(arr[i, 2])} rad/s is {_fmt(arr[i, 2] / _RPM)} rpm, beyond {ranges.max_spin:g} rpm, "
                    "which no golf ball reaches",
                )
        if lower:
            peak = max((float(np.max(np.abs(a[:, 2]))) for a in states.values() if len(a)), default=math.inf)
            if peak / _RPM < ranges.min_peak_spin:
                return Implausibility(
                    "landing", "omega", None, "spin",
                    f"no ball would spin faster than {_fmt(peak / _RPM)} rpm, below {ranges.min_peak_spin:g} rpm, "
                    "which a bouncing golf ball exceeds",
                )
    return None


def plausible_units(
    kind: str,
    convert,
    *,
    radius_m: float = BALL_RADIUS_M,
    ranges: PlausibleRanges = PLAUSIBLE_RANGES,
) -> dict[str, Implausibility | None]:
    """For each unit of :data:`CANDIDATE_UNITS` ``[kind]``, why the numbers cannot be in it (``None``: they can).

    ``convert(factor)`` returns the ``(landing, liftoff)`` scaled arrays obtained when the
    columns without a unit are multiplied by ``factor`` (the factor to scaled units of the
    candidate unit); columns whose unit is known are already scaled.
    """
    out: dict[str, Implausibility | None] = {}
    for unit in CANDIDATE_UNITS[kind]:
        landing, liftoff = convert(scale_factor(unit, kind, radius_m))
        out[unit] = implausibility(landing, liftoff, radius_m=radius_m, ranges=ranges, kinds=(kind,), lower=True)
    return out


def scale_factor(unit: str, kind: str, radius_m: float = BALL_RADIUS_M) -> float:
    """The factor that turns a value in ``unit`` into scaled units (radii/s or rad/s)."""
    canon = canonical_unit(unit, kind)
    if kind == "spin":
        return SPIN_UNITS[canon]
    factor = SPEED_UNITS[canon]
    return 1.0 if factor is None else factor / radius_m


def declare_units_hint(kind: str, units: tuple[str, ...] | list[str], *, style: str = "python") -> str:
    """How to declare the unit of ``kind``: ``"units={'spin': 'rpm'}"`` (or a choice of several).

    Every loader message that asks for a unit goes through here, so that it speaks the caller's
    language: ``style="python"`` names the keyword, ``style="cli"`` the ``bouncelab`` flag
    (``--spin-unit rpm``).
    """
    if style == "cli":
        flag = "--velocity-unit" if kind == "velocity" else "--spin-unit"
        options = " or ".join(f"{flag} {u}" for u in units)
    else:
        options = " or ".join(f"units={{{kind!r}: {u!r}}}" for u in units)
    example = "[m/s]" if kind == "velocity" else "[rpm]"
    return f"pass {options}, or put the unit in the column header (e.g. 'name {example}')"


def _fmt(x: float) -> str:
    if 1000 <= abs(x) < 1e9:
        return f"{x:.0f}"
    return f"{x:.4g}"
