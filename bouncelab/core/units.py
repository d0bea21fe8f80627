"""Units and sign conventions, in one place.

bouncelab works in the paper's *scaled units* throughout and converts only at
the edges (file loading, the command line, the helpers here):

* lengths in ball radii, so ``xdot`` and ``ydot`` are in radii per second;
* spin ``omega`` in rad/s;
* ``y`` points up, so a landing has ``ydot < 0``;
* ``omega`` is anticlockwise in the plane of motion (x to the right), so
  ``omega > 0`` is backspin for a ball travelling in +x;
* the contact point P (the lowest point of the ball) has tangential velocity
  ``v_P = xdot + omega``.

The ball radius is 21.35 mm by default (:data:`BALL_RADIUS_M`); every
conversion takes ``radius_m`` to use another ball.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Mapping

import numpy as np

from bouncelab.core.checks import positive, real_array, shown
from bouncelab.core.errors import DataError, Hint

__all__ = [
    "ANGLE_UNITS",
    "BALL_RADIUS_M",
    "BALL_RADIUS_RANGE_M",
    "COMPONENTS",
    "COMPONENT_UNITS",
    "INERTIA_FACTOR",
    "SPEED_UNITS",
    "SPIN_UNITS",
    "Z95",
    "ball_radius",
    "from_scaled",
    "landing_from_speed_angle_spin",
    "physical_to_scaled",
    "polar_from_state",
    "polar_halfwidths_to_cartesian",
    "scaled_to_physical",
    "speed_angle_spin",
    "spin_from_scaled",
    "spin_to_scaled",
    "state_from_polar",
    "tangential_velocity",
    "to_scaled",
    "unit_pair",
    "velocity_from_scaled",
    "velocity_to_scaled",
]

#: Default golf-ball radius in metres (the paper's ball, R&A rules minimum diameter 42.67 mm).
BALL_RADIUS_M = 0.02135

#: Moment of inertia of the ball as a fraction of m R^2 (a uniform solid sphere, 2/5, as the rigid bounce of
#: the paper assumes); used for kinetic energies ``E = (m R^2 / 2) (xdot^2 + ydot^2 + k omega^2)``.
INERTIA_FACTOR = 0.4

#: The conventions of every state bouncelab holds (written into campaigns and law files).
CONVENTIONS = (
    "scaled units: xdot, ydot in ball radii per second, omega in rad/s; y up (landing ydot < 0); "
    "omega anticlockwise (omega > 0 is backspin for a ball moving in +x); v_P = xdot + omega"
)

#: The 97.5 % quantile of the standard normal: a campaign's prediction intervals are 95 % half-widths, one
#: standard deviation times Z95 (the paper's intervals; a file's standard deviations are converted on loading).
Z95 = 1.959963984540054

#: Names of the three components of a landing or lift-off state, in order.
COMPONENTS = ("xdot", "ydot", "omega")

#: Units of each component in scaled form.
COMPONENT_UNITS = ("radius/s", "radius/s", "rad/s")

_FT = 0.3048
_MILE = 1609.344

#: Speed units: metres per second for one unit (``None`` means scaled radii/s).
SPEED_UNITS: dict[str, float | None] = {
    "m/s": 1.0,
    "ft/s": _FT,
    "mph": _MILE / 3600.0,
    "km/h": 1000.0 / 3600.0,
    "radius/s": None,
}

#: Spin units: rad/s for one unit.
SPIN_UNITS: dict[str, float] = {
    "rad/s": 1.0,
    "rpm": 2.0 * math.pi / 60.0,
    "rev/s": 2.0 * math.pi,
    "deg/s": math.pi / 180.0,
}

# Spellings accepted for each unit (lower case, spaces removed).
_ALIASES: dict[str, str] = {
    "m/s": "m/s", "mps": "m/s", "ms-1": "m/s", "ms^-1": "m/s", "m.s-1": "m/s",
    "ft/s": "ft/s", "fps": "ft/s", "ft/sec": "ft/s",
    "mph": "mph", "mi/h": "mph", "miles/h": "mph",
    "km/h": "km/h", "kph": "km/h", "kmh": "km/h",
    "radius/s": "radius/s", "radii/s": "radius/s", "r/s": "radius/s", "scaled": "radius/s",
    "1/s": "radius/s", "s-1": "radius/s", "s^-1": "radius/s", "/s": "radius/s",
    "rad/s": "rad/s", "rads-1": "rad/s", "rad/sec": "rad/s", "rads^-1": "rad/s",
    "rpm": "rpm", "rev/min": "rpm", "r/min": "rpm", "rotpermin": "rpm", "revpermin": "rpm",
    # per minute without a unit of angle (CF/UDUNITS "min-1", ISO 80000-3's rotational frequency): revolutions
    "1/min": "rpm", "/min": "rpm", "min-1": "rpm", "min^-1": "rpm",
    "rev/s": "rev/s", "rps": "rev/s", "hz": "rev/s",
    "deg/s": "deg/s", "°/s": "deg/s",
}

#: Angle units (of speed, angle and spin files): degrees per unit.
ANGLE_UNITS: dict[str, float] = {"deg": 1.0, "rad": 180.0 / math.pi}

# Spellings that name a unit of one kind only: per second on a spin is rad/s (on a velocity radii/s, above),
# and the angles of polar files.
_KIND_ALIASES: dict[str, dict[str, str]] = {
    "spin": {"1/s": "rad/s", "s-1": "rad/s", "s^-1": "rad/s", "/s": "rad/s"},
    "angle": {"deg": "deg", "degree": "deg", "degrees": "deg", "°": "deg", "rad": "rad", "radian": "rad",
              "radians": "rad"},
}

# CF / UDUNITS spellings ("m s-1", "radian/s", "revolutions per minute", "min-1") rewritten to the aliases
# above, in order: every way of naming a unit (units=, a header, a units row, a netCDF attribute, a flag)
# goes through canonical_unit, so all accept the same names.
_CF_WORDS = (
    (r"⁻¹", "-1"), (r"\s*\*\*\s*-1", "-1"),
    (r"\b(meters?|metres?)\b", "m"), (r"\b(foot|feet)\b", "ft"), (r"\bkilometers?|kilometres?\b", "km"),
    (r"\b(miles?)\b", "mi"), (r"\b(hours?|hr)\b", "h"), (r"\b(seconds?|sec)\b", "s"),
    (r"\b(minutes?)\b", "min"), (r"\b(radians?)\b", "rad"), (r"\b(degrees?)\b", "deg"),
    (r"\b(revolutions?|rotations?|revs?)\b", "rev"), (r"\s+per\s+", "/"),
    (r"\s*\.?\s*(s|h|min)\s*\^?\s*-1\b", r"/\1"),
)


def _cf_spelling(text: str) -> str:
    """``text`` with CF / UDUNITS words and exponents rewritten (``"rev min-1"`` -> ``"rev/min"``)."""
    out = str(text).strip().lower()
    for pattern, repl in _CF_WORDS:
        out = re.sub(pattern, repl, out)
    return out.replace(" ", "")


def canonical_unit(unit: str, kind: str) -> str:
    """Return the canonical spelling of ``unit`` for ``kind`` ("velocity", "spin" or "angle").

    Accepts the spellings of :data:`SPEED_UNITS`, :data:`SPIN_UNITS` and
    :data:`ANGLE_UNITS`, their common aliases, and CF / UDUNITS forms: ``"m s-1"``,
    ``"metres per second"``, ``"rad s-1"``, ``"revolutions per minute"``,
    ``"min-1"``, ``"min^-1"``, ``"1/min"`` (a unit per minute without an angle is
    revolutions per minute, rpm); ``"1/s"`` (``"s-1"``) is radii/s for a velocity
    and rad/s for a spin. This is the one table of unit names: the loader, the
    command line and the conversions all read units through it.

    Raises
    ------
    DataError
        If the unit is unknown or of the wrong kind (a spin unit for a velocity).
    """
    key = str(unit).strip().lower().replace(" ", "")
    own = _KIND_ALIASES.get(kind, {})
    canon = own.get(key) or _ALIASES.get(key)
    if canon is None:
        cf = _cf_spelling(unit)
        canon = own.get(cf) or _ALIASES.get(cf)
    table = {"velocity": SPEED_UNITS, "angle": ANGLE_UNITS}.get(kind, SPIN_UNITS)
    if canon is None or canon not in table:
        known = ", ".join(table)
        raise DataError(f"unknown {kind} unit {unit!r}; known {kind} units: {known}", option=kind)
    return canon


def velocity_to_scaled(value, unit: str = "m/s", *, radius_m: float = BALL_RADIUS_M):
    """Convert a velocity from ``unit`` to radii/s.

    ``v_scaled = v[m/s] / R[m]``.
    """
    canon = canonical_unit(unit, "velocity")
    _check_radius(radius_m)
    factor = SPEED_UNITS[canon]
    v = _numeric(value, "velocity")
    with np.errstate(over="ignore"):  # 1e308 m/s becomes inf, which the state checks refuse by name
        return v if factor is None else v * (factor / radius_m)


def velocity_from_scaled(value, unit: str = "m/s", *, radius_m: float = BALL_RADIUS_M):
    """Convert a velocity from radii/s to ``unit``."""
    canon = canonical_unit(unit, "velocity")
    _check_radius(radius_m)
    factor = SPEED_UNITS[canon]
    v = _numeric(value, "velocity")
    with np.errstate(over="ignore"):
        return v if factor is None else v * (radius_m / factor)


def spin_to_scaled(value, unit: str = "rpm"):
    """Convert a spin rate from ``unit`` to rad/s (the scaled spin unit)."""
    factor = SPIN_UNITS[canonical_unit(unit, "spin")]
    return _numeric(value, "spin") * factor


def spin_from_scaled(value, unit: str = "rpm"):
    """Convert a spin rate from rad/s to ``unit``."""
    factor = SPIN_UNITS[canonical_unit(unit, "spin")]
    return _numeric(value, "spin") / factor


def to_scaled(state, *, velocity: str = "m/s", spin: str = "rpm", radius_m: float = BALL_RADIUS_M):
    """Convert an (..., 3) state ``[xdot, ydot, omega]`` in physical units to scaled units."""
    s = _state_array(state)
    s[..., :2] = velocity_to_scaled(s[..., :2], velocity, radius_m=radius_m)
    s[..., 2] = spin_to_scaled(s[..., 2], spin)
    return s


def from_scaled(state, *, velocity: str = "m/s", spin: str = "rpm", radius_m: float = BALL_RADIUS_M):
    """Convert an (..., 3) state in scaled units to ``velocity`` and ``spin`` units."""
    s = _state_array(state)
    s[..., :2] = velocity_from_scaled(s[..., :2], velocity, radius_m=radius_m)
    s[..., 2] = spin_from_scaled(s[..., 2], spin)
    return s


def landing_from_speed_angle_spin(
    speed,
    angle_deg,
    spin,
    *,
    speed_unit: str = "m/s",
    spin_unit: str = "rpm",
    radius_m: float = BALL_RADIUS_M,
):
    """Landing state ``[xdot0, ydot0, omega0]`` (scaled) from speed, angle of incidence and spin.

    ``xdot0 = s cos(alpha)``, ``ydot0 = -s sin(alpha)`` with ``alpha`` the angle of
    incidence below the horizontal (paper Fig. 2) and the ball travelling in +x;
    ``spin > 0`` is backspin.

    Examples
    --------
    The paper's typical driver landing (93.6 ft/s, 37.3 degrees, 34.9 rev/s of backspin):

    >>> landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s").round(1)
    array([1063. , -809.8,  219.3])
    """
    s = velocity_to_scaled(speed, speed_unit, radius_m=radius_m)
    _require(np.isfinite(s) & (s > 0), speed, "landing speed must be positive and finite", column="speed")
    angle = _numeric(angle_deg, "angle of incidence")
    a = np.deg2rad(angle)
    _require((a > 0) & (a <= np.pi / 2), angle, "angle of incidence must be in (0, 90] degrees for a landing",
             column="angle")
    w = spin_to_scaled(spin, spin_unit)
    _require(np.isfinite(w), spin, "spin must be finite", column="spin")
    s, a, w = np.broadcast_arrays(s, a, w)
    return np.stack([s * np.cos(a), -s * np.sin(a), w], axis=-1)


def speed_angle_spin(
    state,
    *,
    speed_unit: str = "m/s",
    spin_unit: str = "rpm",
    radius_m: float = BALL_RADIUS_M,
    kind: str = "landing",
) -> Mapping[str, np.ndarray]:
    """Speed, angle to the horizontal (degrees) and spin of (..., 3) states.

    ``state`` must be in scaled units (radii/s, rad/s), as everywhere in bouncelab;
    ``speed_unit`` and ``spin_unit`` choose only the units of the *result*. With
    ``kind="landing"`` (default) the angle is positive *below* the horizontal (the
    inverse of :func:`landing_from_speed_angle_spin`); with ``kind="liftoff"`` it is
    positive *above* it, so a ball that goes up has a positive lift-off angle. Either
    way it is measured from the horizontal on the side the ball travels (in [-90, 90]);
    :func:`polar_from_state` keeps the direction of travel too.
    """
    if kind not in ("landing", "liftoff"):
        raise DataError(f"kind must be 'landing' or 'liftoff'; got {kind!r}", option="kind")
    s = _state_array(state)
    speed = np.hypot(s[..., 0], s[..., 1])
    sign = -1.0 if kind == "landing" else 1.0
    angle = np.rad2deg(np.arctan2(sign * s[..., 1], np.abs(s[..., 0])))
    return {
        "speed": velocity_from_scaled(speed, speed_unit, radius_m=radius_m),
        "angle_deg": angle,
        "spin": spin_from_scaled(s[..., 2], spin_unit),
    }


#: Names of the three polar components (speed, angle in degrees, spin).
POLAR_COMPONENTS = ("speed", "angle", "spin")
FORMS = ("cartesian", "polar")


def state_from_polar(polar, *, kind: str = "landing", speed_unit: str = "m/s", spin_unit: str = "rpm",
                     radius_m: float = BALL_RADIUS_M) -> np.ndarray:
    """Scaled ``[xdot, ydot, omega]`` from (..., 3) ``[speed, angle_deg, spin]`` of a landing or a lift-off.

    The angle is measured from the direction of travel (+x) and is **positive
    below the horizontal for a landing** (the angle of incidence, paper Fig. 2)
    and **positive above it for a lift-off**:

    * landing: ``xdot0 = s cos(a)``, ``ydot0 = -s sin(a)``, with ``0 < a < 180`` degrees
      (above 90 the ball moves in -x);
    * lift-off: ``xdotF = s cos(a)``, ``ydotF = s sin(a)``, with ``-180 < a <= 180`` (above
      90 the ball goes back towards the launcher, at or below 0 into the ground).

    Spin keeps the bouncelab sign (> 0 is backspin for a ball moving in +x).

    Raises
    ------
    DataError
        Non-numeric values, a negative or non-finite speed, an angle outside the
        range of ``kind`` (naming the element), an unknown unit.
    """
    s = _state_array(polar)
    if kind not in ("landing", "liftoff"):
        raise DataError(f"kind must be 'landing' or 'liftoff'; got {kind!r}", option="kind")
    speed = velocity_to_scaled(s[..., 0], speed_unit, radius_m=radius_m)
    angle = s[..., 1]
    _require(np.isfinite(speed) & (speed > 0 if kind == "landing" else speed >= 0), s[..., 0],
             f"{kind} speed must be {'positive' if kind == 'landing' else 'non-negative'} and finite", column="speed")
    if kind == "landing":
        _require((angle > 0) & (angle < 180), angle,
                 "landing angle must be in (0, 180) degrees below the horizontal (positive downward; "
                 "above 90 the ball moves in -x)", column="angle")
    else:
        _require((angle > -180) & (angle <= 180), angle,
                 "lift-off angle must be in (-180, 180] degrees above the horizontal (positive upward)", column="angle")
    spin = spin_to_scaled(s[..., 2], spin_unit)
    _require(np.isfinite(spin), s[..., 2], "spin must be finite", column="spin")
    a = np.deg2rad(angle)
    sign = -1.0 if kind == "landing" else 1.0
    return np.stack([speed * np.cos(a), sign * speed * np.sin(a), spin], axis=-1)


def polar_from_state(state, *, kind: str = "liftoff", speed_unit: str = "m/s", spin_unit: str = "rpm",
                     radius_m: float = BALL_RADIUS_M) -> np.ndarray:
    """(..., 3) ``[speed, angle_deg, spin]`` of scaled states; the inverse of :func:`state_from_polar`.

    A lift-off angle is positive above the horizontal (``atan2(ydotF, xdotF)``, in
    (-180, 180]); a landing angle positive below it (``atan2(-ydot0, xdot0)``).
    """
    if kind not in ("landing", "liftoff"):
        raise DataError(f"kind must be 'landing' or 'liftoff'; got {kind!r}", option="kind")
    s = _state_array(state)
    y = -s[..., 1] if kind == "landing" else s[..., 1]
    return np.stack([
        velocity_from_scaled(np.hypot(s[..., 0], s[..., 1]), speed_unit, radius_m=radius_m),
        np.rad2deg(np.arctan2(y, s[..., 0])),
        spin_from_scaled(s[..., 2], spin_unit),
    ], axis=-1)


def polar_halfwidths_to_cartesian(polar, halfwidths, *, kind: str = "landing", speed_unit: str = "m/s",
                                  spin_unit: str = "rpm", radius_m: float = BALL_RADIUS_M) -> np.ndarray:
    r"""Scaled half-widths ``[xdot, ydot, omega]`` of states measured as speed, angle and spin.

    First-order (linear) propagation, through :func:`state_from_polar`, of the
    half-widths of the speed ``v``, the angle ``a`` and the spin, taking the
    speed and angle errors as independent:

    .. math::

        h_{\dot x} = \sqrt{(\cos a \, h_v)^2 + (v \sin a \, h_a)^2}, \qquad
        h_{\dot y} = \sqrt{(\sin a \, h_v)^2 + (v \cos a \, h_a)^2}, \qquad
        h_\omega = h_s,

    with ``v`` and ``h_v`` in radii/s, ``a`` and ``h_a`` in radians and ``h_s``
    (the spin's half-width) in rad/s. Neither the sign convention of the angle
    (below the horizontal for a landing, above it for a lift-off) nor that of
    ``ydot`` changes a half-width, so both kinds give the same result.

    Parameters
    ----------
    polar
        (..., 3) ``[speed, angle_deg, spin]``, as for :func:`state_from_polar`.
    halfwidths
        (..., 3) half-widths ``[h_speed, h_angle_deg, h_spin]``, each >= 0, in the
        units of ``polar`` (speed and spin units, angle in degrees); broadcast
        against ``polar``.
    kind
        ``"landing"`` or ``"liftoff"``: which angles ``polar`` may hold (see
        :func:`state_from_polar`).
    speed_unit, spin_unit
        Units of the speed and spin and of their half-widths.
    radius_m
        Ball radius in metres, to scale the velocities.

    Returns
    -------
    numpy.ndarray
        (..., 3) half-widths of ``[xdot, ydot, omega]`` in radii/s, radii/s and rad/s.

    Raises
    ------
    DataError
        Anything :func:`state_from_polar` refuses in ``polar``; a half-width that is
        negative, NaN or infinite (naming the element); non-numeric or boolean values,
        shapes that do not broadcast, an unknown unit; a result that overflows to
        infinity (naming the element).

    Notes
    -----
    The propagation is exact for the derivatives at the measured point and is
    accurate while ``h_a`` (in radians) and ``h_v / v`` are small; it keeps the
    coverage of the input half-widths (95 % in, 95 % out) when the errors are
    Gaussian. The ``xdot`` and ``ydot`` errors it produces are correlated (both
    come from the same speed and angle errors); half-widths per component cannot
    hold that correlation.

    Examples
    --------
    A 25 m/s landing at 40 degrees with half-widths of 0.5 m/s and 1 degree:

    >>> polar_halfwidths_to_cartesian([25.0, 40.0, 3000], [0.5, 1.0, 100]).round(2)
    array([22.24, 21.72, 10.47])
    """
    _refuse_bools(polar, "polar values [speed, angle, spin]", "polar")
    _refuse_bools(halfwidths, "half-widths [speed, angle, spin]", "halfwidths")
    s = _state_array(polar)
    h = _numeric(halfwidths, "half-widths [speed, angle, spin]", "halfwidths")
    if h.shape[-1:] != (3,):
        raise DataError(f"half-widths need 3 components (speed, angle, spin) in their last axis; got shape {h.shape}",
                        option="halfwidths")
    try:
        np.broadcast_shapes(s.shape, h.shape)
    except ValueError:
        raise DataError(f"the half-widths' shape {h.shape} does not broadcast against the polar values' shape "
                        f"{s.shape}; give one row of half-widths per row of values, or one for all",
                        option="halfwidths") from None
    state_from_polar(s, kind=kind, speed_unit=speed_unit, spin_unit=spin_unit, radius_m=radius_m)  # validates
    # A negative half-width would be squared away below: refuse it (and NaN, inf) first.
    _require(np.isfinite(h) & (h >= 0), h, "prediction-interval half-widths must be finite and >= 0",
             option="halfwidths")
    v = velocity_to_scaled(s[..., 0], speed_unit, radius_m=radius_m)
    h_v = velocity_to_scaled(h[..., 0], speed_unit, radius_m=radius_m)
    a, h_a = np.deg2rad(s[..., 1]), np.deg2rad(h[..., 1])  # d(v cos a)/da needs radians
    h_s = spin_to_scaled(h[..., 2], spin_unit)
    cos, sin = np.cos(a), np.sin(a)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is inf: refused below, naming the element
        out = np.stack(np.broadcast_arrays(np.hypot(cos * h_v, v * sin * h_a), np.hypot(sin * h_v, v * cos * h_a),
                                           h_s), axis=-1)
    if not np.isfinite(out).all():
        first = tuple(int(i) for i in np.argwhere(~np.isfinite(out))[0])
        raise DataError(f"the propagated half-width {COMPONENTS[first[-1]]} overflows (element "
                        f"{first}): the speeds or half-widths are too large to be measurements",
                        column=COMPONENTS[first[-1]], row=first[0] + 1 if len(first) > 1 else None)
    return out


def _refuse_bools(value, what: str, option: str) -> None:
    """DataError if ``value`` (the argument ``option``) holds booleans (True is not a speed of 1): numpy would
    read them as 0 and 1."""
    if isinstance(value, bool | np.bool_):
        raise DataError(f"{what} must be numeric: real numbers; got a boolean", option=option)
    if isinstance(value, list | tuple):
        for v in value:
            _refuse_bools(v, what, option)
        return
    try:
        kind = np.asarray(value).dtype.kind
    except Exception:
        return
    if kind == "b" or (kind == "O" and any(isinstance(v, bool | np.bool_) for v in np.asarray(value).flat)):
        raise DataError(f"{what} must be numeric: real numbers; got boolean values", option=option)


#: The example of a ``units=`` argument that errors about it give.
_UNITS_EXAMPLE = Hint("units", {"velocity": "m/s", "spin": "rpm"})


def unit_pair(units) -> tuple[str, str] | None:
    """``(velocity unit, spin unit)`` from a ``units=`` argument; None for scaled units.

    ``units`` is None or ``"scaled"`` (scaled units) or a mapping with exactly the
    keys ``"velocity"`` and ``"spin"``; anything else is a :class:`DataError` on
    option ``units``.
    """
    if units is None or (isinstance(units, str) and units.strip().lower() == "scaled"):
        return None
    if not isinstance(units, Mapping):
        raise DataError(f"units must be None (scaled), 'scaled' or a mapping of a 'velocity' and a 'spin' unit; "
                        f"got {units!r}", option="units", hints=[_UNITS_EXAMPLE])
    unknown = sorted(set(map(str, units)) - {"velocity", "spin"})
    missing = [k for k in ("velocity", "spin") if k not in units]
    if unknown or missing:
        raise DataError(f"units needs exactly the keys 'velocity' and 'spin'; missing {missing}, unknown {unknown}",
                        option="units", hints=[_UNITS_EXAMPLE])
    return canonical_unit(units["velocity"], "velocity"), canonical_unit(units["spin"], "spin")


def _form_pair(form) -> tuple[str, str]:
    pair = (form, form) if isinstance(form, str) else tuple(form) if isinstance(form, tuple | list) else ()
    if len(pair) != 2 or any(f not in FORMS for f in pair):
        raise DataError(f"form must be 'cartesian', 'polar' or a pair (landing form, lift-off form) of them; "
                        f"got {form!r}", option="form")
    return pair


def _convert(states, units, form: str, radius_m: float, polar, cartesian) -> np.ndarray:
    """``polar`` or ``cartesian`` applied to ``states`` with the units and form checked once."""
    pair = unit_pair(units)
    vel, spin = pair if pair is not None else ("radius/s", "rad/s")
    _check_radius(radius_m)
    if form == "polar":
        return polar(states, speed_unit=vel, spin_unit=spin, radius_m=radius_m)
    if form != "cartesian":
        raise DataError(f"form must be 'cartesian' or 'polar'; got {form!r}", option="form")
    return cartesian(states, velocity=vel, spin=spin, radius_m=radius_m)


def physical_to_scaled(states, *, units=None, form: str = "cartesian", kind: str = "landing",
                       radius_m: float = BALL_RADIUS_M) -> np.ndarray:
    """Scaled ``[xdot, ydot, omega]`` from (..., 3) states in ``units`` and ``form`` ("cartesian" or "polar").

    ``units`` is None (scaled: radii/s and rad/s) or ``{"velocity": ..., "spin": ...}``
    (any of :data:`SPEED_UNITS` and :data:`SPIN_UNITS`); the polar form is
    ``[speed, angle_deg, spin]`` (see :func:`state_from_polar` for the angles).
    """
    return _convert(states, units, form, radius_m, functools.partial(state_from_polar, kind=kind), to_scaled)


def scaled_to_physical(states, *, units=None, form: str = "cartesian", kind: str = "liftoff",
                       radius_m: float = BALL_RADIUS_M) -> np.ndarray:
    """(..., 3) scaled states in ``units`` and ``form``; the inverse of :func:`physical_to_scaled`."""
    return _convert(states, units, form, radius_m, functools.partial(polar_from_state, kind=kind), from_scaled)


def tangential_velocity(state):
    """Tangential velocity of the contact point, ``v_P = xdot + omega`` (radii/s), of (..., 3) states."""
    s = _state_array(state)
    return s[..., 0] + s[..., 2]


#: Ball radii that ``ball_radius_m`` arguments accept (metres): a table-tennis ball to a basketball, so that a
#: radius given in millimetres (21.35) or centimetres is refused rather than taken as metres.
BALL_RADIUS_RANGE_M = (0.005, 0.2)


def ball_radius(value: object, *, file: str | None = None) -> float:
    """A ``ball_radius_m`` argument as a float of metres, or a DataError naming it.

    A number (not a bool or text), finite, positive and within :data:`BALL_RADIUS_RANGE_M`.
    """
    try:
        radius = positive(value, "ball_radius_m", error=DataError)
    except DataError:
        raise DataError(f"ball_radius_m must be a positive length in metres; got {shown(value)}", file=file,
                        option="ball_radius_m") from None
    low, high = BALL_RADIUS_RANGE_M
    if not low <= radius <= high:
        raise DataError(f"ball_radius_m={radius:g} is not a ball's radius in metres (a golf ball's is {BALL_RADIUS_M}; "
                        f"accepted: {low:g} to {high:g} m); give the radius in metres, e.g. {radius:g} mm is "
                        f"{radius / 1000:g}", file=file, option="ball_radius_m")
    return radius


def _check_radius(radius_m: float) -> None:
    positive(radius_m, "radius_m", error=DataError)


def _require(ok: np.ndarray, value, message: str, *, column: str | None = None, option: str | None = None) -> None:
    """Raise DataError naming the first value where ``ok`` is false (NaN compares false, so fails), and the
    quantity (``column``: ``"speed"``, ``"angle"``, ``"spin"``) or argument (``option``) it belongs to."""
    ok = np.asarray(ok)
    if not ok.all():
        vals = np.broadcast_to(np.asarray(value, dtype=float), ok.shape)
        first = np.argwhere(~ok)[0] if ok.ndim else ()
        where = f" (element {tuple(int(i) for i in first)})" if ok.ndim else ""
        raise DataError(f"{message}; got {float(vals[tuple(first)])!r}{where}", column=column, option=option)


def _numeric(value, what: str, option: str | None = None) -> np.ndarray:
    """``value`` as a new float array (never the caller's own array), or DataError (naming the argument
    ``option`` when it is one)."""
    return np.array(real_array(value, option or what, what, error=DataError))


def _state_array(state) -> np.ndarray:
    """``state`` as a new (..., 3) float array, or DataError."""
    s = _numeric(state, "a state [xdot, ydot, omega]")
    if s.shape[-1:] != (3,):
        raise DataError(f"a state needs 3 components (xdot, ydot, omega) in its last axis; got shape {s.shape}")
    return s
