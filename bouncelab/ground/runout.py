r"""From landing to rest: bounces, flights, skid and roll, for many landings at once.

:func:`run` takes a ball touching the ground at the origin (its lowest point there, at
time 0) with a velocity and a spin, and follows it to rest on a :class:`Surface`:

1. **Bounce.** A landing (velocity into the ground) bounces with the surface's law, lifted
   to 3-D as the law states (:mod:`bouncelab.ground.bounce3d`).
2. **Flight** under gravity (9.81 m/s², along -z; in scaled units :math:`g = 9.81/R`
   radii/s²), in closed form; optionally with air (:class:`Air`: quadratic drag and a
   Magnus lift, integrated with RK4). The spin is constant in flight. The next landing is
   where the ball's lowest point meets the ground plane again.
3. **No longer leaves.** A lift-off whose next flight would rise less than ``min_apex_m``
   along the normal (apex :math:`v_n^2 / 2 g_n` without air, :math:`g_n = g\,n_z`; default
   :data:`DEFAULT_MIN_APEX_M` = 2 mm, a tenth of the ball's radius) — or that the law sends
   into the ground (:math:`v_n \le 0`) — ends the bounces: the ball stays on the ground with
   its tangential velocity and its spin (the small normal speed is dropped). So does the
   ``max_bounces``-th bounce (the shot is then flagged ``bounce_limit``: a law whose
   lift-offs never fall below the apex, such as the published piecewise-affine law with its
   positive :math:`\dot y_F` offsets, would bounce for ever).
4. **Skid.** While the contact point slips, sliding friction :math:`\mu_s g_n` opposes the
   slip :math:`u = v + n\times\omega` and gravity's component along the slope :math:`g_t`
   pulls: :math:`\dot v = g_t - \mu_s g_n \hat u` and, as for the bounce,
   :math:`\dot u = g_t - \tfrac72\mu_s g_n \hat u`. On flat ground the slip stops after
   :math:`t = 2|u_0| / (7\mu_s g)`, when the velocity has changed by
   :math:`-\tfrac27 u_0` (a ball with no spin rolls on at 5/7 of its speed).
5. **Roll** without slipping (:math:`n\times\omega = -v`): rolling resistance decelerates the
   ball by :math:`\mu_r g_n` against its velocity and gravity pulls it by
   :math:`\tfrac57 g_t` (a rolling solid sphere), until it stops. :math:`\mu_r` comes from
   the surface's Stimpmeter reading :math:`S`: :math:`\mu_r g = v_0^2 / 2S` with
   :math:`v_0` = 1.83 m/s, so a ball leaving the Stimpmeter's ramp on flat ground stops at
   :math:`S`. On a slope the deceleration grows with the normal load: up and down the fall
   line :math:`S_\uparrow = v_0^2 / 2(\mu_r g\cos\theta + \tfrac57 g\sin\theta)`,
   :math:`S_\downarrow = v_0^2 / 2(\mu_r g\cos\theta - \tfrac57 g\sin\theta)`, and the USGA's
   slope formula :math:`2 S_\uparrow S_\downarrow / (S_\uparrow + S_\downarrow)` gives
   :math:`S / \cos\theta`: the flat reading to within :math:`1/\cos\theta - 1` (0.06 % at 2°,
   0.24 % at 4°). A ball stays at rest where :math:`\tfrac57 g \sin\theta \le \mu_r g\cos\theta`;
   a steeper slope (or one where :math:`\tan\theta \ge \tfrac72\mu_s`) is refused, since the
   ball would never stop on an endless plane.

The spin about the normal does not act on the path; each bounce multiplies it by the
surface's ``pivot_retention`` and it is carried unchanged on the ground. Rolling resistance
is not applied while skidding (sliding friction dominates it).

Both ground phases solve :math:`\dot q = a - k\hat q` (:math:`|a| < k`) in closed form:
a straight stop when :math:`q_0 \parallel a` (flat ground, or along the fall line), and
otherwise a curve bending towards :math:`a` whose speed, time and displacement are
powers of :math:`\tan(\psi/2)`, :math:`\psi` the angle between :math:`q` and :math:`a`
(derived in :func:`bouncelab.ground._kernels.glide`; it agrees with
``scipy.integrate.solve_ivp`` to 1e-9 of the run, tested).

A law with a compiled kernel (every built-in law) runs each shot from its landing to rest in
one compiled kernel, the law's 3-D lift inside it, the shots shared between threads
(:func:`bouncelab.ground._kernels.run_loop`); a law written in NumPy bounces all the shots
landing in the same round in one ``law.predict``, with the same compiled pieces around it.
The kernels use IEEE arithmetic in a fixed order (:data:`bouncelab.core._jit.ROW_FLAGS`), so
a shot gives the same bits whatever the batch it is in, its position there and the number of
threads. The path (:attr:`RunResult.path`) runs the shots once more to record their bounces.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core.checks import count
from bouncelab.core.errors import (
    BouncelabWarning,
    DataError,
    LargeResultWarning,
    NonphysicalLiftoffWarning,
    ParameterError,
)
from bouncelab.ground._inputs import (
    Units,
    as_vectors,
    broadcast_rows,
    normal_text,
    positive,
    unit_normals,
    within_limit,
)
from bouncelab.ground.bounce3d import compiled_lift, flags_3d, from_plane, lift_plane, to_plane
from bouncelab.ground.surface import GRAVITY, Surface, preset

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

__all__ = [
    "DEFAULT_MAX_BOUNCES",
    "DEFAULT_MIN_APEX_M",
    "DEFAULT_RATE",
    "EVENTS",
    "PHASES",
    "Air",
    "BounceLimitWarning",
    "RunResult",
    "run",
]

#: A lift-off whose flight would rise less than this (metres, along the normal) ends the bounces.
DEFAULT_MIN_APEX_M = 0.002
#: Bounces after which a ball is put on the ground whatever its lift-off (flagged ``bounce_limit``).
DEFAULT_MAX_BOUNCES = 100
#: The largest ``max_bounces`` accepted.
MAX_BOUNCES = 1_000_000
#: Samples per second of :attr:`RunResult.path` unless ``rate=`` says otherwise.
DEFAULT_RATE = 100.0
#: Phase codes of the path: ``phase == 0`` is flight, etc.
PHASES = ("flight", "skid", "roll", "rest")
#: Event codes of the path's ``event_kind``.
EVENTS = ("bounce", "skid_end", "rest")
#: Path values (shots x samples x 10) from which :meth:`RunResult.sample` warns about memory.
PATH_VALUES_WARN = 200_000_000
#: Values of a path (:meth:`RunResult.sample`) beyond which it is refused, before any allocation (8 GB).
PATH_VALUES_MAX = 1_000_000_000
_AXES = ("x", "y", "z")


class BounceLimitWarning(BouncelabWarning):
    """Some shots were still bouncing at ``max_bounces`` and were put on the ground (``bounce_limit``)."""


@dataclass(frozen=True)
class Air:
    r"""Air in flight: quadratic drag and a Magnus lift with constant coefficients.

    Acceleration :math:`-\tfrac{\rho A}{2m}\,(C_D |v| v - C_L |v|\, \hat\omega\times v)` plus
    gravity, :math:`A = \pi R^2`, :math:`C_L = \min(c_L S, C_{L,max})` with the spin ratio
    :math:`S = R|\omega|/|v|`; the spin does not decay in flight. The defaults are
    *illustrative* magnitudes for a golf ball at bounce speeds (a drag coefficient of about
    0.25, lift rising with the spin ratio), not fitted to anything: set your own.

    Parameters
    ----------
    drag_coefficient
        :math:`C_D` (>= 0).
    lift_slope
        :math:`c_L`, lift coefficient per unit spin ratio (>= 0).
    lift_max
        Largest lift coefficient (>= 0).
    density_kg_m3
        Air density (1.204 kg/m³: dry air at 20 °C, sea level).
    mass_kg
        Ball mass (0.04593 kg, the Rules of Golf's maximum).
    """

    drag_coefficient: float = 0.25
    lift_slope: float = 1.0
    lift_max: float = 0.3
    density_kg_m3: float = 1.204
    mass_kg: float = 0.04593

    def __post_init__(self) -> None:
        for name in ("drag_coefficient", "lift_slope", "lift_max"):
            positive(getattr(self, name), name, allow_zero=True)
        for name in ("density_kg_m3", "mass_kg"):
            positive(getattr(self, name), name)

    def kernel_parameters(self, radius_m: float) -> np.ndarray:
        """``[kd, kq, c_L, C_L,max]`` in scaled units (kd, kq per radius)."""
        k = self.density_kg_m3 * math.pi * radius_m ** 3 / (2.0 * self.mass_kg)
        return np.array([k * self.drag_coefficient, k, self.lift_slope, self.lift_max])


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product of (n, 3) arrays, summed in a fixed order."""
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.column_stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]])


def _rows(fn: Any, n: int, *args: Any) -> None:
    from bouncelab.core._parallel import run_rows

    run_rows(fn, n, *args)


def _kernels():
    from bouncelab.ground import _kernels

    return _kernels


def _check_slopes(nrm: np.ndarray, surface: Surface) -> None:
    """Refuse slopes on which a ball never stops (rolling or skidding), naming the row."""
    tan = np.sqrt(nrm[:, 0] ** 2 + nrm[:, 1] ** 2) / nrm[:, 2]
    bad = (tan >= 1.4 * surface.rolling_resistance) | (tan >= 3.5 * surface.sliding_friction)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise DataError(f"normal row {row + 1} = {normal_text(nrm[row])} is a slope of "
                        f"{math.degrees(math.atan(tan[row])):.3g} degrees; on {surface.name!r} (stimp "
                        f"{surface.stimp_m:.3g} m) a ball comes to rest only on slopes under "
                        f"{surface.max_slope_deg():.3g} degrees (5/7 g sin(theta) < mu_r g cos(theta)); on a "
                        f"steeper endless plane it never stops", column="normal", row=row + 1)


def run(velocity: Any, spin: Any, surface: Surface | str, normal: Any = (0.0, 0.0, 1.0),
        units: Mapping[str, str] | str | None = None, *, radius_m: float | None = None,
        rate: float = DEFAULT_RATE, air: Air | None = None, min_apex_m: float = DEFAULT_MIN_APEX_M,
        max_bounces: int = DEFAULT_MAX_BOUNCES) -> RunResult:
    """Follow landings (or balls on the ground) to rest: bounces, flights, skid and roll.

    See the module documentation for the model. The ball touches the ground at the origin
    at time 0; positions are those of its lowest point (the centre minus ``R n``).

    Parameters
    ----------
    velocity, spin
        Velocities and spin vectors, (3,) or (n, 3) (a single row is repeated), right-handed,
        z up: backspin for travel in +x is a negative y spin. A velocity into the ground
        (``v . n < 0``) is a landing; one along the ground (``|v . n| <= 1e-9 |v|``) starts
        on the ground, skidding or rolling as its contact-point velocity says. A velocity
        away from the ground is refused, and so is any component beyond
        :data:`~bouncelab.core.validation.STATE_LIMIT` in scaled units (radii/s, rad/s).
    surface
        A :class:`~bouncelab.ground.Surface` or the name of a preset
        (:data:`bouncelab.ground.surface.PRESET_NAMES`).
    normal
        The ground's normal, (3,) or (n, 3) (normalised here, of any magnitude; z > 0): a
        planar slope.
    units
        None (scaled: radii/s, rad/s, lengths in ball radii) or ``{"velocity": "m/s",
        "spin": "rpm"}`` (lengths then in metres), for inputs and results.
    radius_m
        Ball radius in metres (default 21.35 mm); it also scales gravity in scaled units.
    rate
        Samples per second of :attr:`RunResult.path`.
    air
        An :class:`Air` for drag and lift in flight (default None: no air).
    min_apex_m
        Bounces whose next flight would rise less than this (metres) end the bouncing.
    max_bounces
        Bounces after which the ball is put on the ground whatever its lift-off.

    Returns
    -------
    RunResult
        ``rest_position`` (n, 3), ``totals`` (a DataFrame per shot), ``path`` (an xarray
        Dataset, built on first use), ...

    Raises
    ------
    DataError
        Bad shapes or values (absurd magnitudes included), a velocity away from the ground, a
        normal not pointing up, a slope too steep for the ball to stop on this surface (row
        named), unknown units.
    ParameterError
        A bad surface, ``rate``, ``min_apex_m`` or ``max_bounces``; a law giving a non-finite
        lift-off.
    LawDefinitionError
        A law stating a lift the ground does not know (:mod:`bouncelab.ground.bounce3d`).

    Warns
    -----
    BounceLimitWarning
        Shots still bouncing at ``max_bounces``.

    Examples
    --------
    The Stimpmeter's ball (1.83 m/s, rolling) on a 10 ft green stops 10 ft away:

    >>> from bouncelab.ground import Surface, run
    >>> import bouncelab as bl
    >>> green = Surface(name="g", law=bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_ft=10)
    >>> r = run([1.83, 0, 0], [0, 1.83 / 0.02135, 0], green, units={"velocity": "m/s", "spin": "rad/s"})
    >>> float(r.rest_position[0, 0] / 0.3048).__round__(9)
    10.0
    """
    if isinstance(surface, str):
        surface = preset(surface)
    if not isinstance(surface, Surface):
        raise ParameterError(f"surface must be a bouncelab.ground.Surface or a preset name; got "
                             f"{type(surface).__name__}", parameter="surface")
    rate = positive(rate, "rate")
    hmin_m = positive(min_apex_m, "min_apex_m")
    max_bounces = count(max_bounces, "max_bounces", 1, maximum=MAX_BOUNCES)
    if air is not None and not isinstance(air, Air):
        raise ParameterError(f"air must be a bouncelab.ground.Air or None; got {type(air).__name__}", parameter="air")
    u = Units(units, radius_m)
    radius = u.radius_m
    v, _ = as_vectors(velocity, "velocity")
    w, _ = as_vectors(spin, "spin")
    nrm, _ = unit_normals(normal, upward=True)
    n = broadcast_rows([("velocity", v), ("spin", w), ("normal", nrm)])
    v = within_limit(u.velocity_in(v), "velocity", v, u.velocity_unit)
    w = within_limit(u.spin_in(w), "spin", w, u.spin_unit)
    v = np.ascontiguousarray(np.broadcast_to(v, (n, 3)), dtype=float)
    w = np.ascontiguousarray(np.broadcast_to(w, (n, 3)), dtype=float)
    nrm = np.ascontiguousarray(np.broadcast_to(nrm, (n, 3)))
    _check_slopes(nrm, surface)
    vn = _dot(v, nrm)
    tol = 1e-9 * np.sqrt(_dot(v, v))
    away = vn > tol
    if away.any():
        row = int(np.flatnonzero(away)[0])
        raise DataError(f"velocity row {row + 1} moves away from the ground (v . n = "
                        f"{u.velocity_out(vn[row]):.6g} {u.velocity_unit} > 0): a run starts with a landing "
                        f"(v . n < 0) or on the ground (v . n = 0)", column="velocity", row=row + 1)
    sim = _Simulation(surface, radius, GRAVITY / radius, hmin_m / radius, int(max_bounces),
                      None if air is None else air.kernel_parameters(radius), v, w, nrm, vn < -tol)
    if sim.limit.any():
        rows = np.flatnonzero(sim.limit)
        warnings.warn(f"{len(rows)} of {n} shots were still bouncing after max_bounces={max_bounces} (first: row "
                      f"{rows[0] + 1}) and were put on the ground there (totals['bounce_limit']); the law's lift-offs "
                      f"do not fall below min_apex_m={hmin_m:g} m", BounceLimitWarning, stacklevel=2)
    return RunResult(sim, u, rate, air)


class _Simulation:
    """The scaled state of a run: per shot its results (the module layout of ``_kernels``: ``out``, ``counts``),
    and its bounces for the path (:meth:`records`).

    A law with a compiled kernel runs each shot to rest in one compiled loop (``_kernels.run_loop``);
    a law written in NumPy bounces in rounds, all the shots landing in a round in one ``law.predict``.
    """

    def __init__(self, surface: Surface, radius: float, g: float, hmin: float, max_bounces: int,
                 air: np.ndarray | None, v: np.ndarray, w: np.ndarray, nrm: np.ndarray, landing: np.ndarray) -> None:
        self.surface = surface
        self.radius = radius
        self.g = g
        self.hmin = hmin
        self.max_bounces = max_bounces
        self.air = np.empty(0) if air is None else air
        self.mu_s = surface.sliding_friction
        self.mu_r = surface.rolling_resistance
        self.n = len(v)
        self.normal = nrm
        self.v0, self.w0 = v, w
        self.landing = landing.astype(np.int8)
        self._records: tuple[np.ndarray, ...] | None = None
        self._lift = compiled_lift(surface.law)
        if self._lift is not None:  # the kernel writes every value read (the first lift-off only of shots that bounce)
            self.out = np.empty((self.n, _kernels().OUT_COLUMNS))
            self.counts = np.empty((self.n, 4), dtype=np.int64)
            self._run(self.out, self.counts, np.zeros(1, dtype=np.int64), *_no_records())
        else:
            self.out = np.zeros((self.n, _kernels().OUT_COLUMNS))
            self.counts = np.zeros((self.n, 4), dtype=np.int64)
            self._records = self._rounds()
        out = self.out
        if not np.isfinite(out[:, :_kernels().ENTRY]).all():
            row = int(np.flatnonzero(~np.isfinite(out[:, :_kernels().ENTRY]).all(axis=1))[0])
            raise ParameterError(f"{type(surface.law).__name__} gave shot {row + 1} a non-finite lift-off: its run to "
                                 f"rest has no finite answer", parameter="law")

    # ----------------------------------------------------------------- per shot (compiled laws)
    def _run(self, out: np.ndarray, counts: np.ndarray, offsets: np.ndarray, bt: np.ndarray, bp: np.ndarray,
             bv: np.ndarray, bw: np.ndarray) -> None:
        lift, args = self._lift
        keep = self.surface.pivot_retention
        _rows(_kernels().run_loop(lift), self.n, self.v0, self.w0, self.normal, self.landing, args, keep, self.g,
              self.hmin, self.max_bounces, self.air, self.mu_s, self.mu_r, out, counts, offsets, bt, bp, bv, bw)

    def records(self) -> tuple[np.ndarray, ...]:
        """``(offsets, bt, bp, bv, bw)``: the bounces of shot i at rows ``offsets[i]:offsets[i+1]``, their landing
        times and positions, lift-off velocities and spins (a compiled run runs again to record them)."""
        if self._records is None:
            offsets = np.concatenate([[0], np.cumsum(self.nb)]).astype(np.int64)
            m = int(offsets[-1])
            rec = (np.empty(m), np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3)))
            if m:
                self._run(np.empty_like(self.out), np.empty_like(self.counts), offsets, *rec)
            self._records = (offsets, *rec)
        return self._records

    # ----------------------------------------------------------------- in rounds (laws written in NumPy)
    def _rounds(self) -> tuple[np.ndarray, ...]:
        """Bounce every landing shot in rounds (one ``law.predict`` per round), then skid and roll (compiled rows)."""
        k = _kernels()
        n, nrm, v, w = self.n, self.normal, self.v0, self.w0
        law = self.surface.law
        plane = lift_plane(law)
        keep = self.surface.pivot_retention
        entry = np.zeros((n, 10))
        entry[:, 0:3] = v - _dot(v, nrm)[:, None] * nrm  # balls on the ground: without the tiny normal part
        entry[:, 3:6] = w
        rounds = []
        idx = np.flatnonzero(self.landing)
        t = np.zeros(len(idx))
        p = np.zeros((len(idx), 3))
        vc, wc, nc = v[idx], w[idx], nrm[idx]
        r = 0
        while idx.size:
            m = len(idx)
            p2, frames = to_plane(vc, wc, nc, plane)
            with warnings.catch_warnings():  # flagged per bounce below; the run handles them (module notes)
                warnings.simplefilter("ignore", NonphysicalLiftoffWarning)
                out = np.asarray(law.predict(p2, plausible=None), dtype=float)
            if not np.isfinite(out).all():
                raise ParameterError(f"{type(law).__name__} returned a non-finite lift-off for the 2-D landing "
                                     f"{p2[np.flatnonzero(~np.isfinite(out).all(axis=1))[0]].tolist()}",
                                     parameter="law")
            vf, wf = from_plane(out, frames, nc, keep)
            into, gain = flags_3d(vc, wc, vf, wf, nc)
            leave = np.empty(m, dtype=np.int8)
            t1, p1, v1 = np.empty(m), np.empty((m, 3)), np.empty((m, 3))
            last = r + 1 >= self.max_bounces
            _rows(k.advance_rows, m, vf, wf, nc, t, p, self.g, self.hmin, last, self.air, leave, t1, p1, v1)
            rounds.append((idx, t, p, vf, wf))
            self.counts[idx, 1] += into
            self.counts[idx, 2] += gain
            stay = leave != 1
            where = idx[stay]
            entry[where, 0:3] = v1[stay]
            entry[where, 3:6] = wf[stay]
            entry[where, 6:9] = p1[stay]
            entry[where, 9] = t1[stay]
            self.counts[idx[leave == 2], 3] = 1
            go = leave == 1
            idx, t, p, vc, wc, nc = idx[go], t1[go], p1[go], v1[go], wf[go], nc[go]
            r += 1
        for ridx, *_ in rounds:
            self.counts[ridx, 0] += 1
        offsets = np.concatenate([[0], np.cumsum(self.counts[:, 0])]).astype(np.int64)
        total = int(offsets[-1])
        bt, bp, bv, bw = np.empty(total), np.empty((total, 3)), np.empty((total, 3)), np.empty((total, 3))
        for r, (ridx, t, p, vf, wf) in enumerate(rounds):
            pos = offsets[ridx] + r
            bt[pos], bp[pos], bv[pos], bw[pos] = t, p, vf, wf
        first = self.counts[:, 0] > 0
        self.out[first, k.FIRST:k.FIRST + 3] = bv[offsets[:-1][first]]
        self.out[first, k.FIRST + 3:k.FIRST + 6] = bw[offsets[:-1][first]]
        self.out[:, k.ENTRY:k.ENTRY + 10] = entry
        _rows(k.ground_rows, n, entry, nrm, self.g, self.mu_s, self.mu_r, self.out)
        return offsets, bt, bp, bv, bw

    # ----------------------------------------------------------------- what the results read
    @property
    def nb(self) -> np.ndarray:
        return self.counts[:, 0]

    @property
    def limit(self) -> np.ndarray:
        return self.counts[:, 3].astype(bool)

    @property
    def entry_position(self) -> np.ndarray:
        k = _kernels().ENTRY
        return self.out[:, k + 6:k + 9]

    @property
    def entry_time(self) -> np.ndarray:
        return self.out[:, _kernels().ENTRY + 9]

    def first_liftoff(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Which shots bounced, and the velocity and spin of their first lift-off."""
        k = _kernels().FIRST
        has = self.nb > 0
        return has, self.out[has, k:k + 3], self.out[has, k + 3:k + 6]

    def sample(self, times: np.ndarray) -> tuple[np.ndarray, ...]:
        """Positions, velocities, spins (n, len(times), 3) and phases (n, len(times)) at ``times`` (scaled)."""
        k = _kernels()
        nt = len(times)
        pos = np.empty((self.n, nt, 3))
        vel = np.empty((self.n, nt, 3))
        spin = np.empty((self.n, nt, 3))
        phase = np.empty((self.n, nt), dtype=np.int8)
        offsets, bt, bp, bv, bw = self.records()
        _rows(k.sample_rows, self.n, np.ascontiguousarray(times, dtype=float), self.normal, self.g, self.mu_s,
              self.mu_r, self.air, offsets, bt, bp, bv, bw, self.out, pos, vel, spin, phase)
        return pos, vel, spin, phase


def _no_records() -> tuple[np.ndarray, ...]:
    return np.empty(0), np.empty((0, 3)), np.empty((0, 3)), np.empty((0, 3))


class RunResult:
    """What :func:`run` returns: rest positions, totals per shot, and the path (built on first use).

    Attributes
    ----------
    rest_position : numpy.ndarray
        (n, 3) where each ball comes to rest (its lowest point), in metres with physical
        units, ball radii with scaled units.
    rest_time : numpy.ndarray
        (n,) seconds from the first landing to rest.
    totals : pandas.DataFrame
        One row per shot (see :meth:`totals`).
    surface : Surface
        The surface of the run.
    rate : float
        Samples per second of :attr:`path`.
    """

    def __init__(self, sim: _Simulation, units: Units, rate: float, air: Air | None) -> None:
        self._sim = sim
        self._units = units
        self.rate = rate
        self.air = air
        self.surface = sim.surface
        self.rest_position = units.length_out(sim.out[:, 8:11].copy())
        self.rest_time = sim.out[:, 11].copy()

    def __len__(self) -> int:
        return self._sim.n

    def __repr__(self) -> str:
        t = self.totals
        return (f"RunResult({len(self)} shots on {self.surface.name!r}: bounces {int(t['bounces'].min())}-"
                f"{int(t['bounces'].max())}, total run {t['total_run'].min():.4g} to {t['total_run'].max():.4g} "
                f"{self._units.length}, at rest after {self.rest_time.max():.3g} s at most)")

    def _repr_html_(self) -> str:
        from bouncelab.ground._display import run_result_html  # the notebook view

        return run_result_html(self)

    @property
    def length_unit(self) -> str:
        """Unit of lengths in the results: ``"m"`` or ``"radius"``."""
        return self._units.length

    @property
    def heading(self) -> np.ndarray:
        """(n, 3) unit heading of each shot: its landing velocity along the ground (if none, the fall-back tangent of
        the plane of travel, as the bounce takes it: the x axis projected on the ground)."""
        s = self._sim
        vt = s.v0 - _dot(s.v0, s.normal)[:, None] * s.normal
        h = np.empty_like(vt)
        for i in range(3):
            h[:, i] = vt[:, i]
        norm = np.sqrt(_dot(vt, vt))
        none = norm == 0
        h[~none] = vt[~none] / norm[~none, None]
        if none.any():  # the plane of travel's fall-back tangent, as the bounce takes it
            _, frames = to_plane(s.v0[none], s.w0[none], s.normal[none], "travel")
            h[none] = frames[:, :3]
        return h

    @cached_property
    def totals(self) -> pd.DataFrame:
        """Per shot, in the run's units (lengths in metres or radii, speeds and spins in the units given).

        Columns: ``liftoff_speed``, ``liftoff_angle_deg`` (above the ground plane; <= 0 into
        it) and ``liftoff_backspin`` (spin about ``n x heading``, positive backspin) of the
        first bounce (NaN for a ball that started on the ground); ``bounces``;
        ``bounce_carry``, the distance along the heading covered while bouncing; ``roll``,
        along the heading from there to rest (skid and roll; negative when the ball spins
        back); ``total_run`` = bounce_carry + roll (the rest position along the heading);
        ``lateral``, the rest position across it (positive to the left, along
        ``n x heading``); ``skid_time``, ``roll_time``, ``time_to_rest`` (s);
        ``into_ground`` and ``energy_gain``, how many of its 3-D bounces the law sent into the
        ground (``vF . n <= 0``) or gave more energy (``|v|^2 + 2/5 |omega|^2``, beyond
        :data:`~bouncelab.laws.nonphysical.ENERGY_RTOL`); ``bounce_limit``, whether it was
        still bouncing at ``max_bounces``.
        """
        import pandas as pd

        s, u = self._sim, self._units
        h = self.heading
        side = _cross(s.normal, h)
        speed = np.full(s.n, np.nan)
        angle = np.full(s.n, np.nan)
        back = np.full(s.n, np.nan)
        has, vf, wf = s.first_liftoff()
        if has.any():
            out = np.empty((len(vf), 2))
            _rows(_kernels().angle_rows, len(vf), vf, np.ascontiguousarray(s.normal[has]), h[has], out)
            speed[has] = u.velocity_out(out[:, 0])
            angle[has] = out[:, 1]
            back[has] = u.spin_out(-_dot(wf, side[has]))  # omega . (h x n) = -omega . (n x h)
        rest = s.out[:, 8:11]
        carry = _dot(s.entry_position, h)
        run_ = _dot(rest, h)
        return pd.DataFrame({
            "liftoff_speed": speed, "liftoff_angle_deg": angle, "liftoff_backspin": back,
            "bounces": s.nb, "bounce_carry": u.length_out(carry), "roll": u.length_out(run_ - carry),
            "total_run": u.length_out(run_), "lateral": u.length_out(_dot(rest, side)),
            "skid_time": s.out[:, 0], "roll_time": s.out[:, 7], "time_to_rest": s.out[:, 11],
            "into_ground": s.counts[:, 1], "energy_gain": s.counts[:, 2], "bounce_limit": s.limit,
        }, index=pd.RangeIndex(s.n, name="shot"))

    @cached_property
    def path(self) -> xr.Dataset:
        """The path at :attr:`rate` samples per second (see :meth:`sample`), built on first use."""
        return self.sample(self.rate)

    def sample(self, rate: float | None = None) -> xr.Dataset:
        """The path of every shot at ``rate`` samples per second, with its events.

        Dimensions ``shot``, ``time`` (``k / rate`` seconds from the first landing, until
        the last shot is at rest; a ball at rest stays there), ``axis`` (x, y, z) and
        ``event``. Variables: ``position`` (the ball's lowest point), ``velocity``,
        ``spin``, ``phase`` (int8 codes into :data:`PHASES`: flight, skid, roll, rest; at an
        event's time the phase after it), and the events of each shot in time order,
        ``event_time``, ``event_kind`` (int8 codes into :data:`EVENTS`: bounce, skid_end,
        rest; -1 pads) and ``event_position``. Lengths in metres (physical units) or radii,
        velocities and spins in the run's units. Memory: about 80 bytes per shot and sample.
        """
        import xarray as xr

        rate = self.rate if rate is None else positive(rate, "rate")
        s, u = self._sim, self._units
        end = float(self.rest_time.max()) if s.n else 0.0
        span = end * rate  # (inf for an absurd rate: refused below)
        nt = math.floor(span) + 2 if span <= PATH_VALUES_MAX else PATH_VALUES_MAX + 1
        if s.n * nt * 10 > PATH_VALUES_MAX:  # refused before anything is allocated
            raise ParameterError(f"the path of {s.n:,} shots over {end:.3g} s at rate={rate:g} samples/s would hold "
                                 f"{s.n * nt * 10:.3g} values ({s.n * nt * 80 / 1e9:.3g} GB), more than "
                                 f"{PATH_VALUES_MAX:.0e} (bouncelab.ground.runout.PATH_VALUES_MAX); sample fewer "
                                 "shots or a lower rate", parameter="rate", value=rate)
        if s.n * nt * 10 > PATH_VALUES_WARN:
            warnings.warn(f"the path of {s.n:,} shots at {rate:g} samples/s holds {s.n * nt * 10 / 1e6:,.0f} M values "
                          f"({s.n * nt * 80 / 1e9:.1f} GB); sample fewer shots or a lower rate",
                          LargeResultWarning, stacklevel=2)
        times = np.arange(nt) / rate
        pos, vel, spin, phase = s.sample(times)
        u.in_place_out(pos, vel, spin)
        nev = int(s.nb.max(initial=0)) + 2
        ev_t = np.full((s.n, nev), np.nan)
        ev_k = np.full((s.n, nev), -1, dtype=np.int8)
        ev_p = np.full((s.n, nev, 3), np.nan)
        mrow = s.nb
        r = np.arange(s.n)
        offsets, bt, bp, _, _ = s.records()
        shot = np.repeat(r, mrow)  # the bounces, shot by shot, in time order
        col = np.arange(len(shot)) - np.repeat(offsets[:-1], mrow)
        ev_t[shot, col] = bt
        ev_p[shot, col] = bp
        ev_k[shot, col] = 0
        ev_t[r, mrow] = s.entry_time + s.out[:, 0]
        ev_k[r, mrow] = 1
        ev_p[r, mrow] = s.out[:, 1:4]
        ev_t[r, mrow + 1] = s.out[:, 11]
        ev_k[r, mrow + 1] = 2
        ev_p[r, mrow + 1] = s.out[:, 8:11]
        length = u.length
        ds = xr.Dataset(
            {
                "position": (("shot", "time", "axis"), pos, {"units": length}),
                "velocity": (("shot", "time", "axis"), vel, {"units": u.velocity_unit}),
                "spin": (("shot", "time", "axis"), spin, {"units": u.spin_unit}),
                "phase": (("shot", "time"), phase,
                          {"flag_values": list(range(len(PHASES))), "flag_meanings": " ".join(PHASES)}),
                "event_time": (("shot", "event"), ev_t, {"units": "s"}),
                "event_kind": (("shot", "event"), ev_k,
                               {"flag_values": list(range(len(EVENTS))), "flag_meanings": " ".join(EVENTS),
                                "padding": -1}),
                "event_position": (("shot", "event", "axis"), u.length_out(ev_p), {"units": length}),
            },
            coords={"shot": np.arange(s.n), "time": ("time", times, {"units": "s"}), "axis": list(_AXES)},
            attrs={"surface": s.surface.to_json(), "ball_radius_m": s.radius, "gravity_m_s2": GRAVITY,
                   "min_apex_m": s.hmin * s.radius, "air": "none" if self.air is None else repr(self.air),
                   "conventions": "right-handed axes, z up; the ball touches the ground at the origin at time 0; "
                                  "positions are its lowest point; spin is the angular-velocity vector "
                                  "(backspin for travel in +x has a negative y component)"},
        )
        return ds
