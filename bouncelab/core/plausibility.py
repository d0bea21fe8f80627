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

Two kinds of check use them:

* sets of bounces (files, :func:`~bouncelab.data.campaign.make_campaign`, :func:`bouncelab.fit`
  on bare arrays): :func:`implausibility`, :func:`scaled_units_error`, :func:`check_scaled`;
  every value against the upper limits, and the lower ones on the whole set (a median landing
  speed, a peak spin) to tell units apart;
* landings given to a law (``predict``, ``regime``, ``bouncelab predict``): :func:`landing_faults`
  and :func:`landing_error` hold **each landing** to ``min_landing_speed`` (1 m/s) ...
  ``max_speed`` (90 m/s) for its speed ``sqrt(xdot0^2 + ydot0^2)``, ``max_spin`` (20 000 rpm) and
  ``min_landing_angle`` (5 degrees) for its angle of incidence ``atan(-ydot0 / |xdot0|)``, on its
  scaled Cartesian state, so that one landing gets the same verdict in every form (Cartesian
  or speed, angle and spin) and unit (scaled or physical).

Examples
--------
>>> import numpy as np
>>> from bouncelab.core.plausibility import implausibility
>>> landing = np.array([[900.0, -700.0, 3000.0]])   # 3000 rad/s: rpm read as rad/s
>>> liftoff = np.array([[400.0, 200.0, 300.0]])
>>> implausibility(landing, liftoff).reason  # doctest: +ELLIPSIS
'3000 rad/s is 28648 rpm, beyond 20000 rpm...'
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from bouncelab.core._parallel import run_rows
from bouncelab.core.errors import Code, DataError, Hint, ParameterError
from bouncelab.core.landing_checks import FAST, FLAT, INVALID, SLOW, SPIN, STATE_LIMIT, is_landing, landing_fault
from bouncelab.core.units import BALL_RADIUS_M, COMPONENTS, SPEED_UNITS, SPIN_UNITS, canonical_unit
from bouncelab.core.validation import check_values

__all__ = [
    "CANDIDATE_UNITS",
    "PLAUSIBLE_RANGES",
    "Implausibility",
    "LandingFaults",
    "PlausibleRanges",
    "check_scaled",
    "guard_limits",
    "implausibility",
    "landing_angle_error",
    "landing_error",
    "landing_fault",
    "landing_faults",
    "landing_limits",
    "landing_status",
    "plausible_units",
    "scaled_units_error",
    "widen_hints",
]

_RPM = 2.0 * math.pi / 60.0  # rad/s per rpm


@dataclass(frozen=True)
class PlausibleRanges:
    """Magnitudes a golf bounce can have, in physical units.

    Attributes
    ----------
    max_speed
        Largest ``|xdot|`` or ``|ydot|`` (the speed, for states given as speed, angle and spin),
        landing or lift-off, in m/s (default 90 m/s: faster
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
    min_landing_angle
        Smallest angle of incidence below the horizontal, ``atan(-ydot0 / |xdot0|)``, in degrees,
        of a landing given to a law (default 5 degrees; the paper's landings come in at 16.4 to
        89.5 degrees): angles in radians read as degrees are all below 1.6 degrees.
    min_landing_speed
        Smallest speed ``sqrt(xdot0^2 + ydot0^2)`` of any one landing given to a law, in m/s
        (default 1.0 m/s; the paper's slowest landing is 1.93 m/s): m/s given as radii/s make
        every landing below 47 m/s slower than this.
    """

    max_speed: float = 90.0
    max_spin: float = 20_000.0
    min_median_landing_speed: float = 1.0
    min_peak_spin: float = 300.0
    min_landing_angle: float = 5.0
    min_landing_speed: float = 1.0

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            number = isinstance(value, numbers.Real) and not isinstance(value, bool) and not math.isnan(value)
            # An upper limit may be math.inf (no limit); a lower one may be 0 (no limit).
            ok = number and (value > 0 if f.name.startswith("max_") else 0 <= value < math.inf)
            if not ok:
                what = "a positive number" if f.name.startswith("max_") else "a finite number >= 0"
                drop = "math.inf" if f.name.startswith("max_") else "0"
                raise ParameterError(f"PlausibleRanges.{f.name} must be {what} in {_UNITS[f.name]} "
                                     f"({drop} drops the limit); got {value!r}", parameter=f.name, value=value)

    def widened(self, **changes: float) -> PlausibleRanges:
        """A copy with some limits changed (``PLAUSIBLE_RANGES.widened(max_spin=40_000)``).

        Raises
        ------
        ParameterError
            An unknown limit (naming the known ones), or a value that is not a limit (an upper
            limit must be positive, a lower one finite and >= 0).
        """
        known = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(changes) - set(known))
        if unknown:
            raise ParameterError(f"PlausibleRanges has no limit {unknown}; its limits are {known}",
                                 parameter=unknown[0], value=changes[unknown[0]])
        return dataclasses.replace(self, **changes)


_UNITS = {"max_speed": "m/s", "max_spin": "rpm", "min_median_landing_speed": "m/s", "min_peak_spin": "rpm",
          "min_landing_angle": "degrees", "min_landing_speed": "m/s"}

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


def widen_hints(limit: str) -> tuple[Hint, Hint]:
    """How to accept numbers beyond the limit ``limit`` of :class:`PlausibleRanges` on purpose: the hints
    ``plausible=PLAUSIBLE_RANGES.widened(limit=...)`` and ``plausible=None`` (which checks nothing)."""
    return (Hint("plausible", Code(f"PLAUSIBLE_RANGES.widened({limit}=...)")), Hint("plausible", Code("None")))


#: Column names of the states' components, as in the paper (``xdot0`` ... ``omegaF``).
STATE_COLUMNS: dict[str, tuple[str, str, str]] = {
    "landing": ("xdot0", "ydot0", "omega0"),
    "liftoff": ("xdotF", "ydotF", "omegaF"),
}


def scaled_units_error(
    landing,
    liftoff=None,
    *,
    radius_m: float = BALL_RADIUS_M,
    ranges: PlausibleRanges = PLAUSIBLE_RANGES,
    units: Mapping[str, str] | None = None,
    lower: bool = True,
    landing_columns: tuple[str, str, str] = ("xdot0", "ydot0", "omega0"),
) -> DataError | None:
    """The error for states that a wrong unit made, or ``None`` when they are plausible golf bounces.

    This is the unit guard of everything that takes sets of bounces without a file around them
    (:func:`~bouncelab.data.campaign.make_campaign`, :func:`bouncelab.fit` on bare arrays; landings
    given to a law have :func:`landing_error`). The whole set is checked against ``ranges``: every value against
    the upper limits, and, as the loader does for a column without a unit, the median landing
    speed and (landing and lift-off given) the peak spin against the lower ones, since m/s read
    as radii/s make every landing slower than 1 m/s.

    Parameters
    ----------
    landing, liftoff
        (n, 3) arrays ``[xdot, ydot, omega]`` in scaled units (radii/s, rad/s), already
        validated; ``liftoff=None`` checks landings alone (then without the peak-spin limit: a
        landing may have no spin).
    radius_m
        Ball radius of the scaling, in metres.
    ranges
        The limits.
    units
        The units the numbers were given in (``{"velocity": "m/s", "spin": "rpm"}``), default
        the scaled ones: the message quotes the number as given and looks for the unit it was in.
    lower
        Whether the lower limits can fault the numbers (default True); ``False`` when their units
        were declared, as for a file with declared units. The units the numbers look like are
        always found with both limits.
    landing_columns
        How the error names the landing's three columns (e.g. ``("speed", "speed", "spin")`` for
        a check of the speeds of landings given as speed, angle and spin, put in the first column).

    Returns
    -------
    DataError or None
        Naming the column (``xdot0`` ... ``omegaF``), the bounce (row, 1-based) when one bounce
        is at fault, the units the numbers would be plausible in and how to convert them; its
        hints (:func:`widen_hints`) say how to accept the numbers on purpose.
    """
    p0 = np.asarray(landing, dtype=float)
    pf = np.empty((0, 3)) if liftoff is None else np.asarray(liftoff, dtype=float)
    given = {kind: canonical_unit((units or {}).get(kind, CANDIDATE_UNITS[kind][0]), kind)
             for kind in ("velocity", "spin")}

    def check(a0: np.ndarray, af: np.ndarray, kind: str, with_lower: bool = True) -> Implausibility | None:
        # A landing alone may have no spin: the peak-spin lower limit needs lift-offs too.
        use_lower = with_lower and (liftoff is not None or kind == "velocity")
        return implausibility(a0, af, radius_m=radius_m, ranges=ranges, kinds=(kind,), lower=use_lower)

    faults = {kind: why for kind in ("velocity", "spin") if (why := check(p0, pf, kind, lower)) is not None}
    if not faults:
        return None
    likely: dict[str, list[str]] = {}
    for kind in faults:
        cols = [0, 1] if kind == "velocity" else [2]
        as_given = scale_factor(given[kind], kind, radius_m)
        likely[kind] = []
        for unit in CANDIDATE_UNITS[kind]:
            if canonical_unit(unit, kind) == given[kind]:
                continue
            factor = scale_factor(unit, kind, radius_m) / as_given
            a0, af = p0.copy(), pf.copy()
            a0[:, cols] *= factor
            af[:, cols] *= factor
            if check(a0, af, kind) is None:
                likely[kind].append(unit)
    kind, why = next(iter(faults.items()))
    as_given = scale_factor(given[kind], kind, radius_m)
    shown = {"radius/s": "radii/s"}.get(given[kind], given[kind])
    if why.row is not None:
        value = (p0 if why.state == "landing" else pf)[why.row, COMPONENTS.index(why.component)] / as_given
        said = "" if as_given == 1.0 else f"{_fmt(value)} {shown}: "
        limit = "max_speed" if kind == "velocity" else "max_spin"
    else:
        said = f"read in {shown}, "
        limit = "min_median_landing_speed" if kind == "velocity" else "min_peak_spin"
    msg = f"{said}{why.reason}; "
    if likely[kind]:
        msg += f"the numbers look like {' or '.join(likely[kind])}"
    else:
        others = [u for u in CANDIDATE_UNITS[kind] if canonical_unit(u, kind) != given[kind]]
        msg += f"the numbers are not plausible in {', '.join(others)} either"
    if "spin" in faults and kind != "spin":
        msg += (f" (and the spins too: {faults['spin'].reason}"
                + (f"; they look like {' or '.join(likely['spin'])})" if likely["spin"] else ")"))
    found = {k: units_ for k, units_ in likely.items() if units_}
    if found:
        pair = {k: CANDIDATE_UNITS[k][0] for k in ("velocity", "spin")} | {k: u[0] for k, u in found.items()}
        msg += (": states are in scaled units (radii/s, rad/s): convert them first, e.g. "
                f"bouncelab.core.units.to_scaled(states, velocity={pair['velocity']!r}, spin={pair['spin']!r})")
    else:
        msg += ": check them"
    names = landing_columns if why.state == "landing" else STATE_COLUMNS["liftoff"]
    return DataError(msg, column=names[COMPONENTS.index(why.component)], row=None if why.row is None else why.row + 1,
                     hints=widen_hints(limit))


def landing_angle_error(angles_deg, ranges: PlausibleRanges = PLAUSIBLE_RANGES) -> tuple[int, str] | None:
    """``(row, sentence)`` for the first angle of incidence that looks like radians given as degrees, or None.

    Angles in degrees below ``ranges.min_landing_angle`` are refused: the paper's landings come in
    at 16.4 to 89.5 degrees, and radians read as degrees are all below 1.6 degrees. ``row`` is
    0-based; the sentence says what to do (give degrees), not how to widen the limit.
    """
    angles = np.asarray(angles_deg, dtype=float)
    low = angles < ranges.min_landing_angle
    if not low.any():
        return None
    row = int(np.argmax(low))
    return row, _angle_sentence(float(angles[row]), ranges)


def _angle_sentence(a: float, ranges: PlausibleRanges) -> str:
    """Why an angle of incidence of ``a`` degrees is refused (and, if it could be radians, what to do)."""
    said = (f"an angle of incidence of {a:g} degrees is flatter than any golf landing (min_landing_angle "
            f"{ranges.min_landing_angle:g} degrees; the paper's landings come in at 16.4 to 89.5 degrees)")
    if 0 < a <= math.pi / 2:  # could be radians
        return f"{said}; if it is in radians ({a:g} rad = {math.degrees(a):.4g} degrees), give degrees"
    return said


#: Relative slack of the landing guard's limits: a landing converted between forms or units (polar and
#: Cartesian, m/s and radii/s) changes in its last bits, and must be judged alike at a limit.
LIMIT_SLACK = 1e-9

#: From this many landings on, :func:`landing_faults` scans them in one compiled pass (NumPy below).
FAST_GUARD_MIN = 4096

#: The paper's slowest landing (Table 1), quoted by the guard's messages, in m/s.
PAPER_SLOWEST_LANDING = 1.93

_FAULT_LIMITS = {"slow": "min_landing_speed", "fast": "max_speed", "spin": "max_spin", "flat": "min_landing_angle"}

#: Limits that no valid landing breaks (``plausible=None``): the guard's comparisons then always pass.
OPEN_LIMITS = (-1.0, 1e300, 1e300, -1.0)


@dataclass(frozen=True)
class LandingFaults:
    """Where a set of landings breaks the per-landing limits of :class:`PlausibleRanges`.

    Attributes
    ----------
    slow, fast, spin, flat
        0-based first landing slower than ``min_landing_speed``, faster than ``max_speed``,
        spinning faster than ``max_spin``, flatter than ``min_landing_angle``; -1 for none.
    invalid
        Whether some rows are not valid landings (NaN, infinite, ``ydot >= 0``...): those are
        left to the value checks of :mod:`bouncelab.core.validation`, which name them.
    """

    slow: int = -1
    fast: int = -1
    spin: int = -1
    flat: int = -1
    invalid: bool = False

    def first(self) -> tuple[str, int] | None:
        """``(fault, row)`` of the first faulty landing (ties: slow, fast, spin, flat), or None."""
        found = [(row, k, name) for k, name in enumerate(_FAULT_LIMITS) if (row := getattr(self, name)) >= 0]
        return None if not found else (min(found)[2], min(found)[0])


#: Largest finite stand-in for an upper limit without a limit (``math.inf``): far beyond any valid landing
#: (squared speeds up to 2e16), and finite, as the compiled loops assume no infinities.
_NO_LIMIT = 1e300


def landing_limits(radius_m: float = BALL_RADIUS_M,
                   ranges: PlausibleRanges = PLAUSIBLE_RANGES) -> tuple[float, float, float, float]:
    """The per-landing limits in scaled units, with :data:`LIMIT_SLACK`: smallest and largest squared
    speed ((radii/s)^2), largest ``|omega|`` (rad/s) and the tangent of the smallest angle of incidence
    (finite: an upper limit of ``math.inf`` is 1e300)."""
    vmin, vmax = ranges.min_landing_speed / radius_m, ranges.max_speed / radius_m
    tan_a = math.tan(math.radians(ranges.min_landing_angle))
    return (vmin * vmin * (1.0 - LIMIT_SLACK), min(vmax * vmax * (1.0 + LIMIT_SLACK), _NO_LIMIT),
            min(ranges.max_spin * _RPM * (1.0 + LIMIT_SLACK), _NO_LIMIT), tan_a * (1.0 - LIMIT_SLACK))


def guard_limits(ranges: PlausibleRanges | None, radius_m: float = BALL_RADIUS_M) -> tuple[float, float, float, float]:
    """:func:`landing_limits`, or :data:`OPEN_LIMITS` for ``ranges=None`` (no guard)."""
    return OPEN_LIMITS if ranges is None else landing_limits(radius_m, ranges)


def landing_status(landing: np.ndarray, limits: tuple[float, float, float, float]) -> int:
    """The guard's verdict on (n, 3) float64 landings: :func:`~bouncelab.core.landing_checks.landing_fault` of
    every valid one, or'ed, with ``INVALID`` if a row is not a valid landing (0: all valid and plausible).
    From :data:`FAST_GUARD_MIN` landings on one compiled pass (tens of ms for 10 million), below it NumPy."""
    p = np.ascontiguousarray(landing, dtype=np.float64)
    if len(p) >= FAST_GUARD_MIN:
        from bouncelab.core._scans import scan_landings  # (compiled: imports numba)

        status = 0
        for part in run_rows(scan_landings, len(p), p, *limits, STATE_LIMIT):
            status |= part
        return status
    valid, faults = _faults(p, limits)
    return (0 if valid.all() else INVALID) | int(np.bitwise_or.reduce(faults[valid], initial=0))


def _faults(p: np.ndarray, limits: tuple[float, float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Which rows of ``p`` are valid landings, and the fault bits of each row (NumPy)."""
    x, y, w = p[:, 0], p[:, 1], p[:, 2]
    with np.errstate(invalid="ignore", over="ignore"):
        return is_landing(x, y, w), landing_fault(x, y, w, *limits)


def landing_faults(landing: np.ndarray, *, radius_m: float = BALL_RADIUS_M,
                   ranges: PlausibleRanges = PLAUSIBLE_RANGES) -> LandingFaults:
    """The landings, one by one, against the per-landing limits (scaled (n, 3) float64 array in).

    A landing is refused when its speed ``sqrt(xdot0^2 + ydot0^2)`` is below ``min_landing_speed``
    or above ``max_speed``, its ``|omega0|`` above ``max_spin``, or its angle of incidence
    ``atan(-ydot0 / |xdot0|)`` below ``min_landing_angle``
    (:func:`~bouncelab.core.landing_checks.landing_fault`). Large arrays are scanned in one compiled pass
    first (:func:`landing_status`); only when it finds a fault are the rows located.
    """
    p = np.ascontiguousarray(landing, dtype=np.float64)
    limits = landing_limits(radius_m, ranges)
    if len(p) >= FAST_GUARD_MIN:
        status = landing_status(p, limits)
        if not status & ~INVALID:
            return LandingFaults(invalid=bool(status & INVALID))
    valid, faults = _faults(p, limits)
    rows = [int(np.argmax(hit)) if (hit := ((faults & bit) != 0) & valid).any() else -1
            for bit in (SLOW, FAST, SPIN, FLAT)]
    return LandingFaults(*rows, invalid=not bool(valid.all()))


def landing_error(
    landing,
    *,
    radius_m: float = BALL_RADIUS_M,
    ranges: PlausibleRanges = PLAUSIBLE_RANGES,
    units: Mapping[str, str] | None = None,
    form: str = "cartesian",
    row_labels=None,
) -> DataError | None:
    """The unit guard of landings given to a law: the error for the first landing no golf bounce has, or None.

    This is the guard of :meth:`BounceModel.predict <bouncelab.BounceModel.predict>`,
    :meth:`~bouncelab.BounceModel.regime` and ``bouncelab predict``: every landing, whatever the
    form and units it was given in, is held to the same limits (:func:`landing_faults`), lower
    ones as well as upper ones, so one landing is accepted or refused alike as ``[xdot, ydot,
    omega]`` or as speed, angle and spin, in scaled or physical units.

    Parameters
    ----------
    landing
        Validated (n, 3) landings ``[xdot0, ydot0, omega0]`` in scaled units.
    radius_m
        Ball radius of the scaling, in metres.
    ranges
        The limits.
    units
        The units the landings were given in (``{"velocity": "m/s", "spin": "rpm"}``), default the
        scaled ones: the message quotes the numbers as given and looks for the unit they were in.
    form
        The form they were given in, ``"cartesian"`` or ``"polar"``: it names the columns
        (``omega0`` or ``spin``, ``speed``).
    row_labels
        The caller's row labels (a pandas index), if any: the error names the label too.

    Returns
    -------
    DataError or None
        Naming the row (1-based), the column where one is at fault (``omega0``/``spin``,
        ``speed`` for polar landings; a Cartesian speed or angle involves two columns, named in
        the message), the limit and the units the numbers look like. Its hints: the ``units``
        the numbers look like (``{"velocity": "m/s", "spin": "rad/s"}``, both kinds, as ``predict``
        takes them), when some are plausible, then how to accept them on purpose
        (:func:`widen_hints`). Rows that are not valid landings give the value check's error
        (NaN, ``ydot >= 0``...).
    """
    p = np.ascontiguousarray(landing, dtype=np.float64)
    faults = landing_faults(p, radius_m=radius_m, ranges=ranges)
    if faults.invalid:
        try:
            check_values(p, "landing", landing=True)
        except DataError as exc:
            return exc
    first = faults.first()
    if first is None:
        return None
    fault, row = first
    polar = form == "polar"
    given = {kind: canonical_unit((units or {}).get(kind, CANDIDATE_UNITS[kind][0]), kind)
             for kind in ("velocity", "spin")}
    as_given = {kind: scale_factor(given[kind], kind, radius_m) for kind in given}
    shown = {kind: {"radius/s": "radii/s"}.get(given[kind], given[kind]) for kind in given}
    min_s2, max_s2, max_w, _ = landing_limits(radius_m, ranges)
    valid = is_landing(p[:, 0], p[:, 1], p[:, 2])
    speeds = np.hypot(p[valid, 0], p[valid, 1])
    spins = np.abs(p[valid, 2])

    def speed_ok(factor: float) -> bool:
        s_lo, s_hi = float(speeds.min()) * factor, float(speeds.max()) * factor
        return s_lo * s_lo >= min_s2 and s_hi * s_hi <= max_s2

    def likely(kind: str) -> list[str]:
        out = []
        for unit in CANDIDATE_UNITS[kind]:
            if canonical_unit(unit, kind) == given[kind]:
                continue
            factor = scale_factor(unit, kind, radius_m) / as_given[kind]
            if speed_ok(factor) if kind == "velocity" else float(spins.max()) * factor <= max_w:
                out.append(unit)
        return out

    x, y, w = p[row]
    speed = math.hypot(x, y)
    column: str | None = None
    if fault in ("slow", "fast"):
        value = speed / as_given["velocity"]
        said = f"{_fmt(value)} {shown['velocity']}" if polar else \
            f"the landing speed sqrt(xdot0^2 + ydot0^2) = {_fmt(value)} {shown['velocity']}"
        mps = "" if given["velocity"] == "m/s" else f" = {_fmt(speed * radius_m)} m/s"
        if fault == "slow":
            reason = (f"{said}{mps} is slower than any golf landing (min_landing_speed {ranges.min_landing_speed:g} "
                      f"m/s; the paper's slowest is {PAPER_SLOWEST_LANDING:g} m/s)")
        else:
            reason = f"{said}{mps} is faster than {ranges.max_speed:g} m/s (max_speed), which no golf ball reaches"
        kind = "velocity"
        column = "speed" if polar else None
    elif fault == "spin":
        value = w / as_given["spin"]
        rpm = " is" if given["spin"] == "rpm" else f" is {_fmt(w / _RPM)} rpm,"
        reason = (f"{_fmt(value)} {shown['spin']}{rpm} beyond {ranges.max_spin:g} rpm (max_spin), which no golf "
                  "ball reaches")
        kind = "spin"
        column = "spin" if polar else "omega0"
    else:
        angle = math.degrees(math.atan2(-y, abs(x)))
        if polar:  # the angle as given, and radians read as degrees
            reason = _angle_sentence(float(f"{angle:.12g}"), ranges)
        else:
            reason = (f"the angle of incidence atan(-ydot0 / |xdot0|) = {angle:.3g} degrees is flatter than any golf "
                      f"landing (min_landing_angle {ranges.min_landing_angle:g} degrees; the paper's landings come in "
                      "at 16.4 to 89.5 degrees)")
        kind = None
        column = "angle" if polar else None
    msg = reason
    hints: list[Hint] = []
    found: dict[str, str] = {}
    if kind is not None:
        units_ = likely(kind)
        if units_:
            msg += f"; the numbers look like {' or '.join(units_)}"
            found[kind] = units_[0]
        else:
            others = [u for u in CANDIDATE_UNITS[kind] if canonical_unit(u, kind) != given[kind]]
            msg += f"; the numbers are not plausible in {', '.join(others)} either"
        if kind == "velocity" and faults.spin >= 0:  # both units wrong: say so, and declare both
            spin_units = likely("spin")
            msg += (f" (and the spins too: row {faults.spin + 1}, {_fmt(p[faults.spin, 2] / as_given['spin'])} "
                    f"{shown['spin']} is beyond {ranges.max_spin:g} rpm"
                    + (f"; they look like {' or '.join(spin_units)})" if spin_units else ")"))
            if spin_units:
                found["spin"] = spin_units[0]
        if found:
            hints.append(Hint("units", dict(given) | found))
        else:
            msg += ": check them"
    elif not polar:
        msg += ": check that xdot0 and ydot0 are the landing's horizontal and vertical velocities, in one unit"
    hints.extend(widen_hints(_FAULT_LIMITS[fault]))
    label = None if row_labels is None else row_labels[row]
    return DataError(msg, column=column, row=row + 1, row_label=label, hints=hints)


def check_scaled(
    landing,
    liftoff,
    *,
    radius_m: float = BALL_RADIUS_M,
    ranges: PlausibleRanges | None = PLAUSIBLE_RANGES,
) -> None:
    """Refuse scaled states that only a unit mistake makes (m/s or rpm given as radii/s or rad/s).

    The guard of :func:`~bouncelab.data.campaign.make_campaign` and :func:`bouncelab.fit`; see
    :func:`scaled_units_error`. ``ranges=None`` checks nothing.

    Raises
    ------
    DataError
        Naming the column (``xdot0`` ... ``omegaF``), the bounce, the likely unit and how to
        convert; its hints say how to widen the ranges (:func:`widen_hints`).

    Examples
    --------
    >>> import numpy as np
    >>> landing = np.array([[20.1, -15.2, 3000.0]])   # m/s and rpm
    >>> liftoff = np.array([[9.5, 5.1, 1500.0]])
    >>> check_scaled(landing, liftoff)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    bouncelab.core.errors.DataError: column 'ydot0': read in radii/s, the median landing speed would be 0.538 m/s...
    """
    if ranges is None:
        return
    error = scaled_units_error(landing, liftoff, radius_m=radius_m, ranges=ranges)
    if error is not None:
        raise error


def _fmt(x: float) -> str:
    if 1000 <= abs(x) < 1e9:
        return f"{x:.0f}"
    return f"{x:.4g}"
