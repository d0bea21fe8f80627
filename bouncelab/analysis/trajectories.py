"""Synthetic tracked trajectories: what a high-speed-camera tracker reports for one bounce.

:func:`simulate_tracked_bounce` produces, frame by frame, the quantities the
paper's extraction procedure works from (section "Data extraction"): the
ball-centre position found by circle detection, the spin estimated from the
rotation between consecutive frames, and the height of the lowest visible point
of the ball, whose abrupt changes of velocity mark touch-down and lift-off.
The true landing and lift-off states are stored with the track, so estimators
(:mod:`bouncelab.analysis.measurement`) can be checked against the truth.

Units are the paper's scaled units: lengths in ball radii, velocities in
radii/s, spin in rad/s (anticlockwise, so backspin is positive for a ball
moving in +x), time in seconds, ``y`` up with the surface at ``y = 0`` (the
ball centre is at ``y = 1`` when the ball touches it).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr
from scipy.integrate import solve_ivp

from bouncelab.core import checks
from bouncelab.core.errors import DataError
from bouncelab.core.units import BALL_RADIUS_M

__all__ = [
    "AIR_DENSITY",
    "BALL_MASS_KG",
    "DRAG_COEFFICIENT",
    "DRAG_SCALED",
    "GRAVITY",
    "GRAVITY_SCALED",
    "PHASES",
    "drag_scaled",
    "simulate_tracked_bounce",
]

#: Standard gravity, m/s^2.
GRAVITY = 9.81

#: Gravity in scaled units, radii/s^2: ``g / R`` = 459.5 for the 21.35 mm ball.
GRAVITY_SCALED = GRAVITY / BALL_RADIUS_M

#: Air density, kg/m^3.
AIR_DENSITY = 1.2

#: Drag coefficient of a golf ball at typical bounce speeds (dimpled ball, post-crisis).
DRAG_COEFFICIENT = 0.25

#: Ball mass, kg (the Rules of Golf maximum, 45.93 g).
BALL_MASS_KG = 0.0459


def drag_scaled(
    *,
    rho: float = AIR_DENSITY,
    cd: float = DRAG_COEFFICIENT,
    radius_m: float = BALL_RADIUS_M,
    mass_kg: float = BALL_MASS_KG,
) -> float:
    """Quadratic-drag coefficient in scaled units, per radius.

    The drag deceleration is ``a = -k |v| v``. In SI units
    ``k_SI = rho C_d A / (2 m)`` (1/m) with ``A = pi R^2``; with lengths and
    velocities measured in radii, ``a/R = -(k_SI R) |v/R| (v/R)``, so

    .. math:: k = \\frac{\\rho C_d \\pi R^3}{2 m}

    which is dimensionless (per radius of travel) and equals ``9.99e-5`` for
    the defaults (``rho = 1.2 kg/m^3``, ``C_d = 0.25``, ``R = 21.35 mm``,
    ``m = 45.9 g``): a ball at 1000 radii/s (21 m/s) decelerates by
    100 radii/s^2, about a fifth of gravity.
    """
    for name, value in (("rho", rho), ("cd", cd), ("radius_m", radius_m), ("mass_kg", mass_kg)):
        if not (np.isfinite(value) and value >= 0):
            raise DataError(f"{name} must be a finite non-negative number; got {value!r}", option=name)
    if mass_kg <= 0:
        raise DataError(f"mass_kg must be positive; got {mass_kg!r}", option="mass_kg")
    return 0.5 * rho * cd * math.pi * radius_m**3 / mass_kg


#: Default quadratic-drag coefficient in scaled units (per radius), ``~1.0e-4``.
DRAG_SCALED = drag_scaled()

#: Phase labels of the frames of a track.
PHASES = ("before", "contact", "after")

#: Frame rates a simulated track may have (frames/s: the estimators' own range,
#: :data:`bouncelab.analysis.measurement.FRAME_RATE_RANGE`) and the most frames a phase of it may hold
#: (a larger simulation is refused before anything is allocated).
FPS_LIMITS = (1.0, 1.0e7)
MAX_FRAMES = 1_000_000

# During contact the turf hides part of the ball: circle detection and feature
# matching degrade. The generator multiplies the noise by these factors there.
_CONTACT_POSITION_NOISE_FACTOR = 10.0
_CONTACT_SPIN_NOISE_FACTOR = 5.0


def simulate_tracked_bounce(
    landing,
    liftoff,
    *,
    fps: float = 5000.0,
    n_before: int = 40,
    n_after: int = 40,
    contact_frames: float = 8.0,
    position_noise: float = 0.003,
    angle_noise: float = 0.008,
    drag: float = DRAG_SCALED,
    gravity: float = GRAVITY_SCALED,
    frame_offset: float | None = None,
    seed: int | np.random.Generator | None = None,
) -> xr.Dataset:
    """Simulate the per-frame output of a ball tracker for one bounce.

    Parameters
    ----------
    landing, liftoff
        True states ``[xdot, ydot, omega]`` (radii/s, radii/s, rad/s) *at* the
        touch-down and lift-off instants. A landing needs ``ydot < 0`` and a
        lift-off ``ydot > 0``.
    fps
        Camera frame rate, frames/s (the paper's camera ran at 5000-10000);
        the frame period is ``dt = 1/fps``.
    n_before, n_after
        Number of frames recorded before touch-down and after lift-off.
    contact_frames
        Contact duration in frame periods (may be fractional):
        ``t_F - t_0 = contact_frames * dt`` (default 8, i.e. 1.6 ms at 5 kfps).
    position_noise
        Standard deviation of the tracked centre coordinates, radii. The
        default 0.003 radii (0.064 mm, ~0.15 px for a 55 px ball radius) gives
        prediction-interval half-widths of about 45 radii/s for the paper's
        velocity estimate at 5 kfps: ~5 % of a typical landing velocity, the
        size the paper reports for most of its intervals.
    angle_noise
        Standard deviation of the rotation angle estimated between two
        consecutive frames, rad (default 0.008 rad = 0.46 deg). Each per-frame
        spin sample is that angle over ``dt``, so its noise is
        ``angle_noise / dt`` = 40 rad/s at 5 kfps, and the 95 % interval of
        the mean of 40 samples is ~13 rad/s, ~5 % of a typical spin.
    drag
        Quadratic-drag coefficient ``k`` in scaled units, per radius
        (:func:`drag_scaled`; default ``1.0e-4`` for a golf ball in air).
    gravity
        Gravitational acceleration, radii/s^2 (default ``9.81 / 0.02135``).
    frame_offset
        Where touch-down falls between frames, as a fraction of a frame period
        in ``[0, 1)``: touch-down happens ``frame_offset * dt`` before the first
        contact frame. ``None`` (default) draws it uniformly.
    seed
        Seed or :class:`numpy.random.Generator`; the same seed gives the same track.

    Returns
    -------
    xarray.Dataset
        Dimension ``frame`` (``n_before + n_contact + n_after`` frames) with
        coordinate ``t`` (s, first frame at ``t = 0``) and variables

        ``x``, ``y``
            Tracked ball-centre coordinates, radii (surface at ``y = 0``).
        ``spin``
            Spin estimated from the rotation between the previous frame and
            this one, ``(theta_k - theta_{k-1}) / dt`` plus noise, rad/s.
        ``lowest``
            Height above the surface of the lowest visible point of the ball,
            radii: ``y - 1`` in flight, the (noisy) surface line ``0`` during
            contact, when the turf hides the bottom of the ball.
        ``phase``
            ``"before"``, ``"contact"`` or ``"after"`` (ground truth).

        attrs: ``true_touchdown_time`` and ``true_liftoff_time`` (s),
        ``true_landing`` and ``true_liftoff`` (the states passed in, which are
        the states at those instants), and the simulation settings.

    Notes
    -----
    **Flight.** Before touch-down and after lift-off the ball centre obeys

    .. math:: \\ddot{\\mathbf{r}} = -g\\,\\hat{\\mathbf{y}} - k\\,|\\dot{\\mathbf{r}}|\\,\\dot{\\mathbf{r}},

    integrated with an 8th-order Runge-Kutta method (``solve_ivp``,
    DOP853, relative tolerance 1e-11) backward in time from touch-down and
    forward from lift-off (exactly, as a parabola, when ``drag == 0``). Spin is
    constant in flight (aerodynamic spin decay is ~1 %/s, negligible over a
    clip); the Magnus lift is not modelled.

    **Contact.** The ball touches the surface at ``t_0`` with its centre at
    ``(0, 1)`` and leaves it at ``t_F = t_0 + contact_frames * dt`` at
    ``(x_F, 1)`` with ``x_F = (t_F - t_0)(xdot_0 + xdot_F)/2``. In between the
    centre follows the cubic Hermite curve matching positions and velocities at
    both ends (it dips below ``y = 1`` as the ball compresses and sinks into
    the surface) and the spin changes linearly from ``omega_0`` to
    ``omega_F``. The tracker output is unreliable there: positions carry 10x
    and spins 5x the flight noise, and ``lowest`` is the surface line.

    **Noise.** Independent Gaussian errors: ``position_noise`` on each tracked
    coordinate (``lowest`` in flight shares the ``y`` error, being derived from
    the same circle fit), and ``angle_noise / dt`` on each spin sample (the
    rotation between each pair of frames is estimated separately by feature
    matching, so spin errors are taken as independent between samples).

    Examples
    --------
    >>> track = simulate_tracked_bounce([1063.0, -810.0, 219.0], [700.0, 280.0, -550.0], seed=1)
    >>> sorted(track.data_vars)
    ['lowest', 'phase', 'spin', 'x', 'y']
    >>> track.attrs["true_landing"].tolist()
    [1063.0, -810.0, 219.0]
    """
    p0 = _state(landing, "landing")
    pf = _state(liftoff, "liftoff")
    if not p0[1] < 0:
        raise DataError(f"a landing must move downward (ydot < 0); got ydot = {p0[1]!r}", column="landing")
    if not pf[1] > 0:
        raise DataError(
            f"a lift-off must move upward (ydot > 0) for the ball to leave the surface; got ydot = {pf[1]!r}",
            column="liftoff",
        )
    fps = checks.finite(fps, "fps", error=DataError, low=FPS_LIMITS[0], high=FPS_LIMITS[1],
                        want=f"a frame rate from {FPS_LIMITS[0]:g} to {FPS_LIMITS[1]:g} frames/s")
    contact_frames = checks.finite(contact_frames, "contact_frames", error=DataError, low=0.0, high=MAX_FRAMES,
                                   want=f"a number of frames > 0 and at most {MAX_FRAMES:,}")
    if contact_frames <= 0:
        raise DataError(f"contact_frames must be > 0; got {contact_frames!r}", option="contact_frames")
    for name, value in (("n_before", n_before), ("n_after", n_after)):
        checks.count(value, name, 1, maximum=MAX_FRAMES, error=DataError)
    for name, value in (
        ("position_noise", position_noise),
        ("angle_noise", angle_noise),
        ("drag", drag),
        ("gravity", gravity),
    ):
        checks.positive(value, name, allow_zero=True, error=DataError)
    rng = checks.generator(seed, error=DataError)
    if frame_offset is None:
        frame_offset = float(rng.uniform(0.0, 1.0))
    elif not checks.finite(frame_offset, "frame_offset", error=DataError, low=0.0, want="a number in [0, 1)") < 1:
        raise DataError(f"frame_offset must be in [0, 1); got {frame_offset!r}", option="frame_offset")

    dt = 1.0 / fps
    t_c = contact_frames * dt
    # Frame k is at k*dt; frame n_before is the first one at or after touch-down.
    t0 = (n_before - frame_offset) * dt
    tf = t0 + t_c
    n_contact = int(np.floor((tf - n_before * dt) / dt + 1e-12)) + 1
    n = n_before + n_contact + n_after
    t = np.arange(n) * dt
    phase = np.array(["before"] * n_before + ["contact"] * n_contact + ["after"] * n_after)
    before = phase == "before"
    contact = phase == "contact"
    after = phase == "after"

    x = np.empty(n)
    y = np.empty(n)
    x_f = t_c * (p0[0] + pf[0]) / 2.0
    x[before], y[before] = _flight((0.0, 1.0, p0[0], p0[1]), t0, t[before], drag, gravity)
    x[after], y[after] = _flight((x_f, 1.0, pf[0], pf[1]), tf, t[after], drag, gravity)
    s = (t[contact] - t0) / t_c
    h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    x[contact] = h10 * t_c * p0[0] + h01 * x_f + h11 * t_c * pf[0]
    y[contact] = h00 + h10 * t_c * p0[1] + h01 + h11 * t_c * pf[1]

    def theta(tt: np.ndarray) -> np.ndarray:
        """Rotation angle (rad) since touch-down, spin linear in time during contact."""
        in_c = np.clip(tt - t0, 0.0, t_c)
        ang = p0[2] * np.minimum(tt - t0, 0.0)
        ang = ang + p0[2] * in_c + (pf[2] - p0[2]) * in_c**2 / (2.0 * t_c)
        return ang + pf[2] * np.clip(tt - t0 - t_c, 0.0, None)

    spin_true = (theta(t) - theta(t - dt)) / dt

    pos_sd = np.where(contact, _CONTACT_POSITION_NOISE_FACTOR, 1.0) * position_noise
    spin_sd = np.where(contact, _CONTACT_SPIN_NOISE_FACTOR, 1.0) * angle_noise / dt
    x_obs = x + pos_sd * rng.standard_normal(n)
    y_obs = y + pos_sd * rng.standard_normal(n)
    spin_obs = spin_true + spin_sd * rng.standard_normal(n)
    lowest = np.where(contact, position_noise * rng.standard_normal(n), y_obs - 1.0)

    length = {"units": "radius"}
    attrs: dict[str, Any] = {
        "true_touchdown_time": t0,
        "true_liftoff_time": tf,
        "true_landing": p0,
        "true_liftoff": pf,
        "fps": fps,
        "contact_frames": contact_frames,
        "frame_offset": float(frame_offset),
        "position_noise": float(position_noise),
        "angle_noise": float(angle_noise),
        "drag": float(drag),
        "gravity": float(gravity),
        "seed": seed if isinstance(seed, int | np.integer) else "none",
        "data_kind": "synthetic",
        "conventions": (
            "scaled units: x, y in ball radii, surface at y = 0, y up; spin in rad/s anticlockwise "
            "(spin > 0 is backspin for a ball moving in +x); t in s"
        ),
    }
    return xr.Dataset(
        {
            "x": ("frame", x_obs, {**length, "long_name": "tracked ball-centre x"}),
            "y": ("frame", y_obs, {**length, "long_name": "tracked ball-centre y"}),
            "spin": ("frame", spin_obs, {
                "units": "rad/s", "long_name": "spin from the rotation since the previous frame",
            }),
            "lowest": ("frame", lowest, {
                **length, "long_name": "height of the lowest visible point of the ball",
            }),
            "phase": ("frame", phase, {"long_name": "true phase of the frame"}),
        },
        coords={
            "frame": ("frame", np.arange(n)),
            "t": ("frame", t, {"units": "s", "long_name": "frame time"}),
        },
        attrs=attrs,
    )


def _flight(state, t_start: float, t_eval: np.ndarray, drag: float, gravity: float):
    """Positions (x, y) at ``t_eval`` of a ball in flight that has ``state`` at ``t_start``.

    ``state = (x, y, xdot, ydot)``; integrates backward when ``t_eval < t_start``.
    """
    x0, y0, u0, v0 = (float(v) for v in state)
    if t_eval.size == 0:
        return np.empty(0), np.empty(0)
    tau = t_eval - t_start
    if drag == 0.0:
        return x0 + u0 * tau, y0 + v0 * tau - 0.5 * gravity * tau**2

    def rhs(_t: float, s: np.ndarray) -> list[float]:
        speed = math.hypot(s[2], s[3])
        return [s[2], s[3], -drag * speed * s[2], -gravity - drag * speed * s[3]]

    order = np.argsort(np.abs(tau))
    t_end = t_eval[order[-1]]
    sol = solve_ivp(
        rhs,
        (t_start, t_end),
        [x0, y0, u0, v0],
        method="DOP853",
        t_eval=t_eval[order],
        rtol=1e-11,
        atol=1e-12,
    )
    if not sol.success:  # pragma: no cover - smooth ODE, never expected
        raise DataError(f"flight integration failed: {sol.message}")
    xs = np.empty_like(t_eval)
    ys = np.empty_like(t_eval)
    xs[order] = sol.y[0]
    ys[order] = sol.y[1]
    return xs, ys


def _state(value, name: str) -> np.ndarray:
    s = np.array(checks.real_array(value, name, "3 numbers [xdot, ydot, omega]", error=DataError)).reshape(-1)
    if s.shape != (3,):
        raise DataError(f"{name} must be 3 numbers [xdot, ydot, omega]; got shape {s.shape}", column=name, option=name)
    if not np.isfinite(s).all():
        raise DataError(f"{name} has a NaN or infinite component: {s.tolist()}", column=name)
    return s
