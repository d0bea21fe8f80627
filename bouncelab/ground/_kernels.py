r"""Compiled kernels of the ground phase (numba; built on first use, cached on disk).

Plain scalar code: ``+ - * /``, ``math.sqrt`` and a few libm calls, loops and branches, no
NumPy call inside a row (the C, JavaScript and C# exports translate these functions). Every
row is independent, in scaled units (radii, radii/s, rad/s, seconds), with the
floating-point flags :data:`bouncelab.core._jit.ROW_FLAGS` only (no contraction into fused
multiply-adds, no reassociation, no approximate functions): a shot gives the same bits
whatever the batch it is in, its position there and the number of threads. Besides
``+ - * /`` and ``math.sqrt`` (correctly rounded), the kernels call libm's ``pow`` (curved
skids and rolls on slopes) and ``atan2`` (lift-off angles), as the contact laws call
``exp``, ``sin`` and ``cos``.

Structure: one kernel per job, each a loop over rows ``[start, stop)`` that
:func:`bouncelab.core._parallel.run_rows` shares between threads:

* :func:`bounce_loop` (``ground.bounce``): the 3-D bounce of each landing;
* :func:`run_loop` (``ground.run``): each landing to rest, its bounces, flights, skid and
  roll; it also records each bounce when asked (the path);
* :func:`sample_rows` (``RunResult.path``): the states of each shot at given times;
* :func:`angle_rows` (the totals).

The law enters through its *lift*, a scalar function
``lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args) -> (vF, omegaF)`` built around the
law's compiled kernel by :func:`lift_of` (see :mod:`bouncelab.ground.bounce3d` for the
three lifts); :func:`bounce_loop` and :func:`run_loop` are built once per lift (a closure
over it, compiled and cached like the laws' own loops). Everything else is a function of
this module compiled once: the frames, :func:`flight`, :func:`to_rest` and :func:`glide`.
A law without a compiled kernel (a law written in NumPy) is bounced by ``law.predict`` in
rounds, with the row loops :func:`to_plane_rows`, :func:`from_plane_rows` and
:func:`advance_rows`, then :func:`ground_rows`: the same scalar functions.

Layouts
-------
``F`` (contact frames, ``(m, 9)``): ``t`` (3), ``b`` (3), then ``v . b``, ``omega . t`` and
``omega . n``: what the 2-D law does not touch (see :mod:`bouncelab.ground.bounce3d`).
``OUT`` (a run's results per shot, ``(n, OUT_COLUMNS)``): columns 0-11 the ground phase
(:func:`to_rest`: skid time, skid-end position (3) and velocity (3), roll time, rest position
(3), rest time), 12-21 the ground entry (velocity (3), spin (3), position (3), time), 22-27
the first lift-off (velocity (3), spin (3); unset without a bounce). ``COUNTS`` (int64,
``(n, 4)``): bounces, lift-offs into the ground, lift-offs gaining energy, whether the shot hit
``max_bounces`` (0 or 1).
"""

from __future__ import annotations

import math
import threading
from typing import Any

import numpy as np

from bouncelab.core._jit import ROW_FLAGS, jit
from bouncelab.laws.nonphysical import ENERGY_RTOL

#: A glide is straight when ``|q x a| <= PARALLEL |q| |a|`` or ``|a| <= PARALLEL k`` (see :func:`glide`).
PARALLEL = 1.0e-12
#: RK4 steps per vacuum flight time of a flight with air (see ``_air_flight``).
AIR_STEPS = 64
#: Most RK4 steps of one flight with air.
AIR_MAX_STEPS = 1_000_000
#: Halvings of the last step to find where a flight with air meets the ground.
AIR_BISECT = 60
#: Most Newton steps to find where a curved glide is at a given time (it takes 3-6).
CURVE_STEPS = 60
#: I / (m R^2) of a solid sphere: the spin's share of the kinetic energy (scaled units).
INERTIA = 0.4

# Phase codes of the path (bouncelab.ground.runout.PHASES).
FLIGHT, SKID, ROLL, REST = 0, 1, 2, 3

# Columns of OUT (module notes).
ENTRY = 12
FIRST = 22
OUT_COLUMNS = 28


# ------------------------------------------------------------------------------ frames
@jit(inline="always")
def _any_tangent(nx, ny, nz):
    """A unit vector perpendicular to n: the x axis projected on the plane (the y axis if n is near x)."""
    if abs(nx) < 0.9:
        ex, ey, ez = 1.0, 0.0, 0.0
    else:
        ex, ey, ez = 0.0, 1.0, 0.0
    d = ex * nx + ey * ny + ez * nz
    tx = ex - d * nx
    ty = ey - d * ny
    tz = ez - d * nz
    s = math.sqrt(tx * tx + ty * ty + tz * tz)
    return tx / s, ty / s, tz / s


@jit(inline="always")
def _along(x, y, z, nx, ny, nz):
    """(x, y, z) minus its component along the unit vector n."""
    d = x * nx + y * ny + z * nz
    return x - d * nx, y - d * ny, z - d * nz


@jit(inline="always")
def _unit(x, y, z):
    """``(True, x / |x|, ...)`` for a vector of non-zero length, else ``(False, 0, 0, 0)``."""
    xx = x * x + y * y + z * z
    if xx > 0.0:
        s = math.sqrt(xx)
        return True, x / s, y / s, z / s
    return False, 0.0, 0.0, 0.0


@jit(inline="always")
def travel_frame(vx, vy, vz, nx, ny, nz):
    """The plane of travel of a ball touching the plane of unit normal n: h and b = n x h.

    h is the unit vector of the velocity along the ground ``v - (v . n) n``; when there is
    none (a landing along the normal), :func:`_any_tangent`. The projection is made twice:
    once leaves a rounding error of order ``eps |v|`` along n, which would tilt h out of the
    plane when the velocity along the ground is that small (on flat ground the second pass
    subtracts an exact zero).
    """
    tx, ty, tz = _along(vx, vy, vz, nx, ny, nz)
    tx, ty, tz = _along(tx, ty, tz, nx, ny, nz)
    found, tx, ty, tz = _unit(tx, ty, tz)
    if not found:
        tx, ty, tz = _any_tangent(nx, ny, nz)
    return tx, ty, tz, ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx


@jit(inline="always")
def contact_frame(vx, vy, vz, wx, wy, wz, nx, ny, nz):
    """The plane of the slip of a ball touching the plane of unit normal n: t and b = n x t.

    t is the direction of the tangential contact-point velocity ``u = v_t + n x omega``; when
    it vanishes, of the tangential velocity; when both vanish, :func:`_any_tangent`. Its sign
    makes the ball travel along +t (``v . t >= 0``), as the paper's balls travel in +x. u is
    projected on the plane once more: near zero slip its rounding error along n (of order
    ``eps |v|``) would tilt t out of the plane (on flat ground it subtracts an exact zero).
    """
    vtx, vty, vtz = _along(vx, vy, vz, nx, ny, nz)
    ux, uy, uz = _along(vtx + (ny * wz - nz * wy), vty + (nz * wx - nx * wz), vtz + (nx * wy - ny * wx), nx, ny, nz)
    found, tx, ty, tz = _unit(ux, uy, uz)
    if not found:
        found, tx, ty, tz = _unit(vtx, vty, vtz)
        if not found:
            tx, ty, tz = _any_tangent(nx, ny, nz)
    if vtx * tx + vty * ty + vtz * tz < 0.0:
        tx, ty, tz = -tx, -ty, -tz
    bx = ny * tz - nz * ty
    by = nz * tx - nx * tz
    bz = nx * ty - ny * tx
    return tx, ty, tz, bx, by, bz


@jit(inline="always")
def frame_of(slip, vx, vy, vz, wx, wy, wz, nx, ny, nz):
    """The slip's frame (:func:`contact_frame`) if ``slip``, else the plane of travel (:func:`travel_frame`)."""
    if slip:
        return contact_frame(vx, vy, vz, wx, wy, wz, nx, ny, nz)
    return travel_frame(vx, vy, vz, nx, ny, nz)


@jit(inline="always")
def from_frame(xf, yf, wf, vb, wt, wn, tx, ty, tz, bx, by, bz, nx, ny, nz):
    """``v = xF t + yF n + vb b`` and ``omega = wt t - wF b + wn n``: a lift-off from its frame's components."""
    return (xf * tx + yf * nx + vb * bx, xf * ty + yf * ny + vb * by, xf * tz + yf * nz + vb * bz,
            wt * tx - wf * bx + wn * nx, wt * ty - wf * by + wn * ny, wt * tz - wf * bz + wn * nz)


# ------------------------------------------------------------------------------ the lifts of a law
_BUILT: dict[tuple, tuple[Any, Any]] = {}
_BUILT_LOCK = threading.Lock()


def _built(key: tuple, keep_alive: Any, make: Any) -> Any:
    """``make()`` once per key and process (the key holds ids: ``keep_alive`` keeps them from being reused)."""
    with _BUILT_LOCK:
        hit = _BUILT.get(key)
        if hit is None or hit[0] is not keep_alive:
            hit = (keep_alive, make())
            _BUILT[key] = hit
        return hit[1]


def lift_of(kind: str, kernel: Any) -> Any:
    """The compiled lift of a law: ``lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args) -> (vF, omegaF)``.

    ``kind`` is ``"own"`` (``kernel`` is the law's ``kernel_3d``, acting in the plane of travel),
    ``"travel"`` or ``"slip"`` (``kernel`` is the law's 2-D kernel, acting in that plane); ``args``
    the law's kernel arguments, ``keep`` the fraction of the lift-off's spin about n kept. See
    :mod:`bouncelab.ground.bounce3d`.
    """
    def make() -> Any:
        if kind == "own":
            @jit(fastmath=ROW_FLAGS)
            def lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args):
                hx, hy, hz, bx, by, bz = travel_frame(vx, vy, vz, nx, ny, nz)
                x = vx * hx + vy * hy + vz * hz
                y = vx * nx + vy * ny + vz * nz
                w = -(wx * bx + wy * by + wz * bz)
                vb = vx * bx + vy * by + vz * bz
                wh = wx * hx + wy * hy + wz * hz
                wn = wx * nx + wy * ny + wz * nz
                xf, yf, wf, vbf, whf, wnf = kernel(x, y, w, vb, wh, wn, *args)
                return from_frame(xf, yf, wf, vbf, whf, wnf * keep, hx, hy, hz, bx, by, bz, nx, ny, nz)
        else:
            slip = kind == "slip"

            @jit(fastmath=ROW_FLAGS)
            def lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args):
                tx, ty, tz, bx, by, bz = frame_of(slip, vx, vy, vz, wx, wy, wz, nx, ny, nz)
                x = vx * tx + vy * ty + vz * tz
                y = vx * nx + vy * ny + vz * nz
                w = -(wx * bx + wy * by + wz * bz)  # t x n = -b
                xf, yf, wf, _ = kernel(x, y, w, *args)
                vb = vx * bx + vy * by + vz * bz
                wt = wx * tx + wy * ty + wz * tz
                wn = (wx * nx + wy * ny + wz * nz) * keep
                return from_frame(xf, yf, wf, vb, wt, wn, tx, ty, tz, bx, by, bz, nx, ny, nz)
        return lift

    if kind not in ("own", "travel", "slip"):
        raise ValueError(f"unknown lift {kind!r}")
    return _built(("lift", kind, id(kernel)), kernel, make)


@jit(inline="always")
def energy(vx, vy, vz, wx, wy, wz):
    """``|v|^2 + 2/5 |omega|^2``: twice the kinetic energy per unit mass (scaled units)."""
    return vx * vx + vy * vy + vz * vz + INERTIA * (wx * wx + wy * wy + wz * wz)


def bounce_loop(lift: Any) -> Any:
    """The row loop of ``ground.bounce`` around a lift: lift-offs into VF, WF; FLAGS (int8, (n, 2)) into the
    ground (``vF . n <= 0``) and gaining energy (beyond :data:`~bouncelab.laws.nonphysical.ENERGY_RTOL`)."""
    def make() -> Any:
        @jit(nogil=True, fastmath=ROW_FLAGS)
        def bounce_rows(V, W, N, keep, args, VF, WF, FLAGS, start, stop):
            for i in range(start, stop):
                vx, vy, vz = V[i, 0], V[i, 1], V[i, 2]
                wx, wy, wz = W[i, 0], W[i, 1], W[i, 2]
                nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
                ax, ay, az, bx, by, bz = lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args)
                VF[i, 0], VF[i, 1], VF[i, 2] = ax, ay, az
                WF[i, 0], WF[i, 1], WF[i, 2] = bx, by, bz
                FLAGS[i, 0] = ax * nx + ay * ny + az * nz <= 0.0
                FLAGS[i, 1] = energy(ax, ay, az, bx, by, bz) > energy(vx, vy, vz, wx, wy, wz) * (1.0 + ENERGY_RTOL)
            return True
        return bounce_rows

    return _built(("bounce", id(lift)), lift, make)


# ------------------------------------------------------------------------------ rows for laws without a kernel
@jit(nogil=True, fastmath=ROW_FLAGS)
def to_plane_rows(V, W, N, slip, P2, F, start, stop):
    """The 2-D landings ``[v . t, v . n, omega . (t x n)]`` into P2 and the frames into F (module layout)."""
    for i in range(start, stop):
        vx, vy, vz = V[i, 0], V[i, 1], V[i, 2]
        wx, wy, wz = W[i, 0], W[i, 1], W[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        tx, ty, tz, bx, by, bz = frame_of(slip, vx, vy, vz, wx, wy, wz, nx, ny, nz)
        P2[i, 0] = vx * tx + vy * ty + vz * tz
        P2[i, 1] = vx * nx + vy * ny + vz * nz
        P2[i, 2] = -(wx * bx + wy * by + wz * bz)  # t x n = -b
        F[i, 0] = tx
        F[i, 1] = ty
        F[i, 2] = tz
        F[i, 3] = bx
        F[i, 4] = by
        F[i, 5] = bz
        F[i, 6] = vx * bx + vy * by + vz * bz
        F[i, 7] = wx * tx + wy * ty + wz * tz
        F[i, 8] = wx * nx + wy * ny + wz * nz
    return True


@jit(nogil=True, fastmath=ROW_FLAGS)
def from_plane_rows(P2F, F, N, keep, VF, WF, start, stop):
    """3-D lift-offs from the 2-D ones (:func:`from_frame`, the spin about n times ``keep``)."""
    for i in range(start, stop):
        a, b, c, d, e, f = from_frame(P2F[i, 0], P2F[i, 1], P2F[i, 2], F[i, 6], F[i, 7], F[i, 8] * keep,
                                      F[i, 0], F[i, 1], F[i, 2], F[i, 3], F[i, 4], F[i, 5], N[i, 0], N[i, 1], N[i, 2])
        VF[i, 0], VF[i, 1], VF[i, 2] = a, b, c
        WF[i, 0], WF[i, 1], WF[i, 2] = d, e, f
    return True


# ------------------------------------------------------------------------------ flights
@jit(inline="always")
def _air_accel(vx, vy, vz, wx, wy, wz, g, kd, kq, cl_slope, cl_max):
    """Acceleration in flight (scaled): gravity -g z, drag -kd |v| v, lift kq CL |v| (w_hat x v)."""
    s = math.sqrt(vx * vx + vy * vy + vz * vz)
    ax = -kd * s * vx
    ay = -kd * s * vy
    az = -g - kd * s * vz
    wm = math.sqrt(wx * wx + wy * wy + wz * wz)
    if s > 0.0 and wm > 0.0 and cl_slope > 0.0:
        cl = min(cl_slope * wm / s, cl_max)  # spin ratio S = R |omega| / |v| is |omega| / |v| in scaled units
        f = kq * cl * s / wm
        ax += f * (wy * vz - wz * vy)
        ay += f * (wz * vx - wx * vz)
        az += f * (wx * vy - wy * vx)
    return ax, ay, az


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, h, g, kd, kq, cl_slope, cl_max):
    """One classical RK4 step of (position, velocity) in air."""
    a1x, a1y, a1z = _air_accel(vx, vy, vz, wx, wy, wz, g, kd, kq, cl_slope, cl_max)
    v2x, v2y, v2z = vx + 0.5 * h * a1x, vy + 0.5 * h * a1y, vz + 0.5 * h * a1z
    a2x, a2y, a2z = _air_accel(v2x, v2y, v2z, wx, wy, wz, g, kd, kq, cl_slope, cl_max)
    v3x, v3y, v3z = vx + 0.5 * h * a2x, vy + 0.5 * h * a2y, vz + 0.5 * h * a2z
    a3x, a3y, a3z = _air_accel(v3x, v3y, v3z, wx, wy, wz, g, kd, kq, cl_slope, cl_max)
    v4x, v4y, v4z = vx + h * a3x, vy + h * a3y, vz + h * a3z
    a4x, a4y, a4z = _air_accel(v4x, v4y, v4z, wx, wy, wz, g, kd, kq, cl_slope, cl_max)
    c = h / 6.0
    npx = px + c * (vx + 2.0 * v2x + 2.0 * v3x + v4x)
    npy = py + c * (vy + 2.0 * v2y + 2.0 * v3y + v4y)
    npz = pz + c * (vz + 2.0 * v2z + 2.0 * v3z + v4z)
    nvx = vx + c * (a1x + 2.0 * a2x + 2.0 * a3x + a4x)
    nvy = vy + c * (a1y + 2.0 * a2y + 2.0 * a3y + a4y)
    nvz = vz + c * (a1z + 2.0 * a2z + 2.0 * a3z + a4z)
    return npx, npy, npz, nvx, nvy, nvz


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def _air_flight(px, py, pz, vx, vy, vz, wx, wy, wz, nx, ny, nz, g, kd, kq, cl_slope, cl_max, tsample, out, k0):
    """Flight with air from a lift-off on the plane until the ball is back on it.

    Classical RK4 with the step ``T_vac / AIR_STEPS`` (T_vac the flight time without air);
    the last step, where the height along n changes sign, is halved ``AIR_BISECT`` times to
    find the landing. Returns the flight time, the landing position and velocity. With
    ``tsample`` (times from the lift-off, ascending) the positions and velocities at those
    times within the flight are written to ``out[k0 + j]`` (6 columns); returns also the
    number of samples written.
    """
    vn = vx * nx + vy * ny + vz * nz
    h = 2.0 * vn / (g * nz) / AIR_STEPS
    t = 0.0
    j = 0
    nsample = tsample.shape[0]
    steps = 0
    while True:
        qx, qy, qz, ux, uy, uz = _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, h, g, kd, kq, cl_slope, cl_max)
        height = qx * nx + qy * ny + qz * nz
        steps += 1
        if height <= 0.0 or steps >= AIR_MAX_STEPS:
            break
        while j < nsample and tsample[j] < t + h:
            d = tsample[j] - t
            sx, sy, sz, svx, svy, svz = _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, d, g, kd, kq, cl_slope,
                                                  cl_max)
            out[k0 + j, 0], out[k0 + j, 1], out[k0 + j, 2] = sx, sy, sz
            out[k0 + j, 3], out[k0 + j, 4], out[k0 + j, 5] = svx, svy, svz
            j += 1
        px, py, pz, vx, vy, vz = qx, qy, qz, ux, uy, uz
        t += h
    lo = 0.0
    hi = h
    for _ in range(AIR_BISECT):
        mid = 0.5 * (lo + hi)
        qx, qy, qz, ux, uy, uz = _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, mid, g, kd, kq, cl_slope, cl_max)
        if qx * nx + qy * ny + qz * nz > 0.0:
            lo = mid
        else:
            hi = mid
    while j < nsample and tsample[j] < t + hi:
        d = tsample[j] - t
        sx, sy, sz, svx, svy, svz = _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, d, g, kd, kq, cl_slope, cl_max)
        out[k0 + j, 0], out[k0 + j, 1], out[k0 + j, 2] = sx, sy, sz
        out[k0 + j, 3], out[k0 + j, 4], out[k0 + j, 5] = svx, svy, svz
        j += 1
    qx, qy, qz, ux, uy, uz = _air_step(px, py, pz, vx, vy, vz, wx, wy, wz, hi, g, kd, kq, cl_slope, cl_max)
    d = qx * nx + qy * ny + qz * nz  # within rounding of 0: put the landing on the plane
    return t + hi, qx - d * nx, qy - d * ny, qz - d * nz, ux, uy, uz, j


@jit(inline="always")
def _vacuum_flight(px, py, pz, vx, vy, vz, nx, ny, nz, g):
    """Flight under gravity alone: time, landing position (on the plane) and landing velocity."""
    vn = vx * nx + vy * ny + vz * nz
    tf = 2.0 * vn / (g * nz)
    qx = px + vx * tf
    qy = py + vy * tf
    qz = pz + vz * tf - 0.5 * g * tf * tf
    d = qx * nx + qy * ny + qz * nz
    return tf, qx - d * nx, qy - d * ny, qz - d * nz, vx, vy, vz - g * tf


@jit(inline="always")
def leaves(vn, nz, g, hmin):
    """Whether a lift-off with normal velocity vn rises above hmin along the normal (apex vn^2 / 2 g nz)."""
    return vn > 0.0 and vn * vn > 2.0 * g * nz * hmin


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def flight(px, py, pz, vx, vy, vz, wx, wy, wz, nx, ny, nz, g, air, empty, dummy):
    """From a lift-off at p to the next landing: flight time, landing position and velocity.

    Under gravity alone in closed form (``air`` empty), or with ``air = [kd, kq, c_L, C_L,max]``
    by RK4 (``_air_flight``; ``empty`` and ``dummy`` are its (0,) and (0, 6) sample arrays).
    """
    if air.shape[0] == 0:
        return _vacuum_flight(px, py, pz, vx, vy, vz, nx, ny, nz, g)
    tf, qx, qy, qz, ux, uy, uz, _ = _air_flight(px, py, pz, vx, vy, vz, wx, wy, wz, nx, ny, nz, g, air[0], air[1],
                                                air[2], air[3], empty, dummy, 0)
    return tf, qx, qy, qz, ux, uy, uz


@jit(nogil=True, fastmath=ROW_FLAGS)
def advance_rows(VF, WF, N, T, P, g, hmin, last, air, leave, T1, P1, V1, start, stop):
    """After a bounce (laws without a kernel): fly to the next landing (``leave[i] = 1``), or stay on the ground (0).

    A ball leaves when :func:`leaves` and this was not its last allowed bounce (``last``; then
    ``leave[i] = 2`` marks a ball that would have left). Its next landing time, position and
    velocity go to T1, P1, V1. A ball that stays keeps its tangential velocity: V1 receives
    ``v - (v . n) n``.
    """
    empty = np.empty(0)
    dummy = np.empty((0, 6))
    for i in range(start, stop):
        vx, vy, vz = VF[i, 0], VF[i, 1], VF[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        vn = vx * nx + vy * ny + vz * nz
        up = leaves(vn, nz, g, hmin)
        if up and not last:
            leave[i] = 1
            tf, qx, qy, qz, ux, uy, uz = flight(P[i, 0], P[i, 1], P[i, 2], vx, vy, vz, WF[i, 0], WF[i, 1], WF[i, 2],
                                                nx, ny, nz, g, air, empty, dummy)
            T1[i] = T[i] + tf
            P1[i, 0], P1[i, 1], P1[i, 2] = qx, qy, qz
            V1[i, 0], V1[i, 1], V1[i, 2] = ux, uy, uz
        else:
            leave[i] = 2 if up else 0
            T1[i] = T[i]
            P1[i, 0], P1[i, 1], P1[i, 2] = P[i, 0], P[i, 1], P[i, 2]
            V1[i, 0], V1[i, 1], V1[i, 2] = vx - vn * nx, vy - vn * ny, vz - vn * nz
    return True


# ------------------------------------------------------------------------------ on the ground
@jit(inline="always")
def _put(out, row, a, b, c, d, e, f):
    out[row, 0], out[row, 1], out[row, 2] = a, b, c
    out[row, 3], out[row, 4], out[row, 5] = d, e, f


@jit(inline="always")
def _curve_at(r, x0, qm1, s, aa):
    """The curved glide where ``r = (x / x0)^(Qk - 1)`` in [0, 1] (1 at the start, 0 at the stop).

    Returns the time, the two integrals, the speed factor ``S r`` and ``x = tan(psi / 2)``.
    Parametrised by r, not x: near the steepest slope a ball rests on (``Qk -> 1``) the
    speed ``S r (1 + x^2)`` falls through its whole range while x falls by hundreds of orders
    of magnitude, below what a double holds (x underflows to 0 here, where its terms are
    negligible).
    """
    x = x0 * math.pow(r, 1.0 / qm1)
    r2 = r * r
    xx = x * x
    x02 = x0 * x0
    t = s / aa * ((1.0 - r) / qm1 + (x02 - r * xx) / (qm1 + 2.0))
    ie = s * s / aa * ((1.0 - r2) / (2.0 * qm1) - (x02 * x02 - r2 * xx * xx) / (2.0 * qm1 + 4.0))
    ip = 2.0 * s * s / aa * ((x0 - r2 * x) / (2.0 * qm1 + 1.0) + (x02 * x0 - r2 * xx * x) / (2.0 * qm1 + 3.0))
    return t, ie, ip, s * r, x


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def _curve_r(ts, tt, x0, qm1, s, aa):
    """The r in [0, 1] where the curved glide's time is ``ts`` in (0, tt) (safeguarded Newton; t falls as r grows).

    ``dt/dr = -S (1 + x^2) / (A (Qk - 1))``; t is nearly linear in r at both ends of ``Qk``, so
    Newton from ``r = 1 - ts / tt`` takes a few steps.
    """
    lo = 0.0
    hi = 1.0
    r = 1.0 - ts / tt
    for _ in range(CURVE_STEPS):
        t, _ie, _ip, _sr, x = _curve_at(r, x0, qm1, s, aa)
        f = t - ts
        if f > 0.0:
            lo = r
        elif f < 0.0:
            hi = r
        else:
            break
        rn = r + f * aa * qm1 / (s * (1.0 + x * x))
        if not (lo < rn < hi):
            rn = 0.5 * (lo + hi)
        if abs(rn - r) <= 2e-16 or hi - lo <= 2e-16:  # r in [0, 1]: a few units of its last place
            r = rn
            break
        r = rn
    return r


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def glide(ax, ay, az, k, qx, qy, qz, tsample, out, k0):
    r"""Solve dq/dt = a - k q/|q| from q0 until q stops (|a| < k), and Q = integral of q dt, in closed form.

    Both ground phases are this equation: the contact point's slip while skidding
    (a = tangential gravity, k = 7/2 mu_s g_n) and the velocity while rolling
    (a = 5/7 of tangential gravity, k = the rolling deceleration).

    * q0 parallel to a (``|q0 x a| <= PARALLEL |q0| |a|``), or ``|a| <= PARALLEL k`` (flat
      ground): a straight stop, deceleration ``d = k - a . q_hat``, ``T = |q0| / d``,
      ``Q = q0 T / 2``.
    * Otherwise the path curves towards a. With ``q = s (cos psi e + sin psi e_perp)``
      (``e = a / |a|``, ``e_perp`` along q0's part across a) the speed and angle obey
      ``s' = A cos psi - k`` and ``s psi' = -A sin psi`` (A = |a|), so with ``x = tan(psi/2)``,
      ``Qk = k / A > 1`` and ``S = s0 / (1 + x0^2)``:
      ``s = S r (1 + x^2)``, ``r = (x / x0)^(Qk - 1)``; ``x`` falls from x0 to 0 at the stop;
      ``t(x) = S/A [(1 - r)/(Qk - 1) + (x0^2 - r x^2)/(Qk + 1)]`` and
      ``Q(x) = S^2/A [(1 - r^2)/(2Qk - 2) - (x0^4 - r^2 x^4)/(2Qk + 2)] e
      + 2 S^2/A [(x0 - r^2 x)/(2Qk - 1) + (x0^3 - r^2 x^3)/(2Qk + 1)] e_perp``.
      The stop (x = 0) needs only arithmetic; a sample at a given time solves t for r
      (:func:`_curve_r`; ``x = x0 r^(1/(Qk - 1))``).

    With ``tsample`` (times from the start, ascending) the states ``(q, Q)`` at those times
    are written to ``out[k0 + j]`` (6 columns; zero velocity and the final Q after the stop).
    Returns ``(T, Qx, Qy, Qz, samples written)``.
    """
    nsample = tsample.shape[0]
    j = 0
    q0 = math.sqrt(qx * qx + qy * qy + qz * qz)
    if q0 == 0.0:
        while j < nsample:
            _put(out, k0 + j, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            j += 1
        return 0.0, 0.0, 0.0, 0.0, j
    aa = math.sqrt(ax * ax + ay * ay + az * az)
    cx = qy * az - qz * ay
    cy = qz * ax - qx * az
    cz = qx * ay - qy * ax
    if aa <= PARALLEL * k or math.sqrt(cx * cx + cy * cy + cz * cz) <= PARALLEL * q0 * aa:
        d = k - (ax * qx + ay * qy + az * qz) / q0
        tt = q0 / d
        while j < nsample and tsample[j] < tt:
            s = tsample[j]
            f = 1.0 - s / tt
            g = s - 0.5 * s * s / tt
            _put(out, k0 + j, qx * f, qy * f, qz * f, qx * g, qy * g, qz * g)
            j += 1
        h = 0.5 * tt
        while j < nsample:
            _put(out, k0 + j, 0.0, 0.0, 0.0, qx * h, qy * h, qz * h)
            j += 1
        return tt, qx * h, qy * h, qz * h, j
    ex, ey, ez = ax / aa, ay / aa, az / aa
    qe = qx * ex + qy * ey + qz * ez
    px, py, pz = qx - qe * ex, qy - qe * ey, qz - qe * ez
    pp = math.sqrt(px * px + py * py + pz * pz)
    px, py, pz = px / pp, py / pp, pz / pp
    x0 = pp / (q0 + qe) if qe >= 0.0 else (q0 - qe) / pp  # tan(psi0 / 2), without cancellation
    qm1 = (k - aa) / aa
    s = q0 / (1.0 + x0 * x0)
    x02 = x0 * x0
    tt = s / aa * (1.0 / qm1 + x02 / (qm1 + 2.0))
    fe = s * s / aa * (1.0 / (2.0 * qm1) - x02 * x02 / (2.0 * qm1 + 4.0))
    fp = 2.0 * s * s / aa * (x0 / (2.0 * qm1 + 1.0) + x02 * x0 / (2.0 * qm1 + 3.0))
    while j < nsample and tsample[j] < tt:
        if tsample[j] <= 0.0:
            _put(out, k0 + j, qx, qy, qz, 0.0, 0.0, 0.0)
        else:
            r = _curve_r(tsample[j], tt, x0, qm1, s, aa)
            _t, ie, ip, sr, x = _curve_at(r, x0, qm1, s, aa)
            ce = sr * (1.0 - x * x)
            cp = sr * 2.0 * x
            _put(out, k0 + j, ce * ex + cp * px, ce * ey + cp * py, ce * ez + cp * pz,
                 ie * ex + ip * px, ie * ey + ip * py, ie * ez + ip * pz)
        j += 1
    while j < nsample:
        _put(out, k0 + j, 0.0, 0.0, 0.0, fe * ex + fp * px, fe * ey + fp * py, fe * ez + fp * pz)
        j += 1
    return tt, fe * ex + fp * px, fe * ey + fp * py, fe * ez + fp * pz, j


@jit(inline="always")
def _tangential_gravity(nx, ny, nz, g):
    """Gravity (0, 0, -g) minus its component along n, and g_n = g n_z (its push into the ground)."""
    gn = g * nz
    return gn * nx, gn * ny, gn * nz - g, gn


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def to_rest(vx, vy, vz, wx, wy, wz, px, py, pz, t0, nx, ny, nz, g, mu_s, mu_r, empty, dummy):
    """Skid then roll to rest from the ground entry (tangential velocity v, spin w, position p, time t0).

    Returns the skid time, the position (3) and velocity (3) at the end of the skid, the roll
    time, the rest position (3) and the rest time (columns 0-11 of the module's OUT).
    """
    gx, gy, gz, gn = _tangential_gravity(nx, ny, nz, g)
    ux = vx + (ny * wz - nz * wy)
    uy = vy + (nz * wx - nx * wz)
    uz = vz + (nx * wy - ny * wx)
    ts, sx, sy, sz, _ = glide(gx, gy, gz, 3.5 * mu_s * gn, ux, uy, uz, empty, dummy, 0)
    c = 5.0 / 14.0 * ts * ts
    ex = px + vx * ts + c * gx + (2.0 / 7.0) * (sx - ux * ts)
    ey = py + vy * ts + c * gy + (2.0 / 7.0) * (sy - uy * ts)
    ez = pz + vz * ts + c * gz + (2.0 / 7.0) * (sz - uz * ts)
    c = 5.0 / 7.0 * ts
    rx = vx + c * gx - (2.0 / 7.0) * ux
    ry = vy + c * gy - (2.0 / 7.0) * uy
    rz = vz + c * gz - (2.0 / 7.0) * uz
    tr, qx, qy, qz, _ = glide(5.0 / 7.0 * gx, 5.0 / 7.0 * gy, 5.0 / 7.0 * gz, mu_r * gn, rx, ry, rz, empty, dummy, 0)
    return ts, ex, ey, ez, rx, ry, rz, tr, ex + qx, ey + qy, ez + qz, t0 + ts + tr


@jit(nogil=True, fastmath=ROW_FLAGS)
def ground_rows(ENT, N, g, mu_s, mu_r, OUT, start, stop):
    """:func:`to_rest` from the ground entries ``ENT`` (velocity, spin, position, time) into OUT columns 0-11."""
    empty = np.empty(0)
    dummy = np.empty((0, 6))
    for i in range(start, stop):
        res = to_rest(ENT[i, 0], ENT[i, 1], ENT[i, 2], ENT[i, 3], ENT[i, 4], ENT[i, 5], ENT[i, 6], ENT[i, 7],
                      ENT[i, 8], ENT[i, 9], N[i, 0], N[i, 1], N[i, 2], g, mu_s, mu_r, empty, dummy)
        for c in range(12):
            OUT[i, c] = res[c]
    return True


# ------------------------------------------------------------------------------ landing to rest, per shot
def run_loop(lift: Any) -> Any:
    """The row loop of ``ground.run`` around a lift: each shot from its landing (or from the ground) to rest.

    ``run_rows(V, W, N, LANDING, args, keep, g, hmin, max_bounces, air, mu_s, mu_r, OUT, COUNTS,
    OFFSETS, BT, BP, BV, BW, start, stop)``: V, W, N the shots' (n, 3) velocities, spins and unit
    normals; LANDING (int8) whether each lands (else it starts on the ground); ``args`` and
    ``keep`` the lift's; ``hmin`` the lowest apex of a flight; ``air`` ``[kd, kq, c_L, C_L,max]``
    or empty. Writes OUT and COUNTS (module layout). With BT non-empty it also records the
    bounces of shot i at rows ``OFFSETS[i]:OFFSETS[i + 1]`` (known from a first call's COUNTS):
    BT landing time, BP landing position, BV and BW lift-off velocity and spin.
    """
    def make() -> Any:
        @jit(nogil=True, fastmath=ROW_FLAGS)
        def run_rows(V, W, N, LANDING, args, keep, g, hmin, max_bounces, air, mu_s, mu_r, OUT, COUNTS, OFFSETS,
                     BT, BP, BV, BW, start, stop):
            empty = np.empty(0)
            dummy = np.empty((0, 6))
            record = BT.shape[0] > 0
            for i in range(start, stop):
                vx, vy, vz = V[i, 0], V[i, 1], V[i, 2]
                wx, wy, wz = W[i, 0], W[i, 1], W[i, 2]
                nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
                t = 0.0
                px, py, pz = 0.0, 0.0, 0.0
                nb = 0
                into = 0
                gain = 0
                limit = 0
                if LANDING[i] != 0:
                    while True:  # bounce, then fly to the next landing, until the ball stays on the ground
                        ax, ay, az, bx, by, bz = lift(vx, vy, vz, wx, wy, wz, nx, ny, nz, keep, args)
                        an = ax * nx + ay * ny + az * nz
                        if an <= 0.0:
                            into += 1
                        if energy(ax, ay, az, bx, by, bz) > energy(vx, vy, vz, wx, wy, wz) * (1.0 + ENERGY_RTOL):
                            gain += 1
                        if nb == 0:
                            OUT[i, FIRST], OUT[i, FIRST + 1], OUT[i, FIRST + 2] = ax, ay, az
                            OUT[i, FIRST + 3], OUT[i, FIRST + 4], OUT[i, FIRST + 5] = bx, by, bz
                        if record:
                            k = OFFSETS[i] + nb
                            BT[k] = t
                            BP[k, 0], BP[k, 1], BP[k, 2] = px, py, pz
                            BV[k, 0], BV[k, 1], BV[k, 2] = ax, ay, az
                            BW[k, 0], BW[k, 1], BW[k, 2] = bx, by, bz
                        nb += 1
                        wx, wy, wz = bx, by, bz
                        if leaves(an, nz, g, hmin):
                            if nb < max_bounces:
                                tf, px, py, pz, vx, vy, vz = flight(px, py, pz, ax, ay, az, bx, by, bz, nx, ny, nz,
                                                                    g, air, empty, dummy)
                                t += tf
                                continue
                            limit = 1
                        vx, vy, vz = ax - an * nx, ay - an * ny, az - an * nz  # on the ground: its tangential velocity
                        break
                else:
                    vn = vx * nx + vy * ny + vz * nz  # within rounding of 0: a ball on the ground
                    vx, vy, vz = vx - vn * nx, vy - vn * ny, vz - vn * nz
                res = to_rest(vx, vy, vz, wx, wy, wz, px, py, pz, t, nx, ny, nz, g, mu_s, mu_r, empty, dummy)
                for c in range(12):
                    OUT[i, c] = res[c]
                OUT[i, ENTRY], OUT[i, ENTRY + 1], OUT[i, ENTRY + 2] = vx, vy, vz
                OUT[i, ENTRY + 3], OUT[i, ENTRY + 4], OUT[i, ENTRY + 5] = wx, wy, wz
                OUT[i, ENTRY + 6], OUT[i, ENTRY + 7], OUT[i, ENTRY + 8] = px, py, pz
                OUT[i, ENTRY + 9] = t
                COUNTS[i, 0] = nb
                COUNTS[i, 1] = into
                COUNTS[i, 2] = gain
                COUNTS[i, 3] = limit
            return True
        return run_rows

    return _built(("run", id(lift)), lift, make)


# ------------------------------------------------------------------------------ the path
@jit(nogil=True, fastmath=ROW_FLAGS)
def sample_rows(times, N, g, mu_s, mu_r, air, offsets, BT, BP, BV, BW, OUT, POS, VEL, SPIN, PHASE, start, stop):
    """States of each shot at ``times`` (ascending, from the first landing): POS, VEL, SPIN (shot, time, 3), PHASE.

    The bounces of shot i are rows ``offsets[i]:offsets[i+1]`` of BT (landing times), BP
    (landing positions), BV and BW (lift-off velocity and spin); a flight follows every
    bounce but the last. Then the ground phase from the ground entry and its results in OUT
    (module layout). At an event's time the state is the one after it.
    """
    nt = times.shape[0]
    buf = np.empty((nt, 6))
    for i in range(start, stop):
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        gx, gy, gz, gn = _tangential_gravity(nx, ny, nz, g)
        k = 0
        b0 = offsets[i]
        b1 = offsets[i + 1]
        for b in range(b0, b1 - 1):  # flights
            t0 = BT[b]
            t1 = BT[b + 1]
            j0 = k
            while k < nt and times[k] < t1:
                k += 1
            if k == j0:
                continue
            px, py, pz = BP[b, 0], BP[b, 1], BP[b, 2]
            vx, vy, vz = BV[b, 0], BV[b, 1], BV[b, 2]
            wx, wy, wz = BW[b, 0], BW[b, 1], BW[b, 2]
            if air.shape[0] == 0:
                for j in range(j0, k):
                    s = times[j] - t0
                    _put(buf, j, px + vx * s, py + vy * s, pz + vz * s - 0.5 * g * s * s, vx, vy, vz - g * s)
            else:
                rel = times[j0:k] - t0
                res = _air_flight(px, py, pz, vx, vy, vz, wx, wy, wz, nx, ny, nz, g, air[0], air[1], air[2],
                                  air[3], rel, buf, j0)
                for j in range(j0 + res[7], k):  # a sample a rounding after the landing: the landing state
                    _put(buf, j, res[1], res[2], res[3], res[4], res[5], res[6])
            for j in range(j0, k):
                for c in range(3):
                    POS[i, j, c] = buf[j, c]
                    VEL[i, j, c] = buf[j, 3 + c]
                SPIN[i, j, 0], SPIN[i, j, 1], SPIN[i, j, 2] = wx, wy, wz
                PHASE[i, j] = FLIGHT
        # skid
        vx, vy, vz = OUT[i, ENTRY], OUT[i, ENTRY + 1], OUT[i, ENTRY + 2]
        wx, wy, wz = OUT[i, ENTRY + 3], OUT[i, ENTRY + 4], OUT[i, ENTRY + 5]
        ux = vx + (ny * wz - nz * wy)
        uy = vy + (nz * wx - nx * wz)
        uz = vz + (nx * wy - ny * wx)
        tg = OUT[i, ENTRY + 9]
        ts = OUT[i, 0]
        j0 = k
        while k < nt and times[k] < tg + ts:
            k += 1
        if k > j0:
            rel = times[j0:k] - tg
            glide(gx, gy, gz, 3.5 * mu_s * gn, ux, uy, uz, rel, buf, j0)
            for j in range(j0, k):
                s = times[j] - tg
                qx, qy, qz, sx, sy, sz = buf[j, 0], buf[j, 1], buf[j, 2], buf[j, 3], buf[j, 4], buf[j, 5]
                c = 5.0 / 14.0 * s * s
                POS[i, j, 0] = OUT[i, ENTRY + 6] + vx * s + c * gx + (2.0 / 7.0) * (sx - ux * s)
                POS[i, j, 1] = OUT[i, ENTRY + 7] + vy * s + c * gy + (2.0 / 7.0) * (sy - uy * s)
                POS[i, j, 2] = OUT[i, ENTRY + 8] + vz * s + c * gz + (2.0 / 7.0) * (sz - uz * s)
                c = 5.0 / 7.0 * s
                VEL[i, j, 0] = vx + c * gx + (2.0 / 7.0) * (qx - ux)
                VEL[i, j, 1] = vy + c * gy + (2.0 / 7.0) * (qy - uy)
                VEL[i, j, 2] = vz + c * gz + (2.0 / 7.0) * (qz - uz)
                # omega = omega_g - 5/7 n x (u - u0 - g_t s)
                dx = qx - ux - gx * s
                dy = qy - uy - gy * s
                dz = qz - uz - gz * s
                SPIN[i, j, 0] = wx - (5.0 / 7.0) * (ny * dz - nz * dy)
                SPIN[i, j, 1] = wy - (5.0 / 7.0) * (nz * dx - nx * dz)
                SPIN[i, j, 2] = wz - (5.0 / 7.0) * (nx * dy - ny * dx)
                PHASE[i, j] = SKID
        # roll, then rest
        wn = wx * nx + wy * ny + wz * nz
        t2 = tg + ts
        ex, ey, ez = OUT[i, 1], OUT[i, 2], OUT[i, 3]
        rx, ry, rz = OUT[i, 4], OUT[i, 5], OUT[i, 6]
        tr = OUT[i, 7]
        j0 = k
        k = nt
        if k > j0:
            rel = times[j0:k] - t2
            glide(5.0 / 7.0 * gx, 5.0 / 7.0 * gy, 5.0 / 7.0 * gz, mu_r * gn, rx, ry, rz, rel, buf, j0)
            for j in range(j0, k):
                qx, qy, qz = buf[j, 0], buf[j, 1], buf[j, 2]
                POS[i, j, 0] = ex + buf[j, 3]
                POS[i, j, 1] = ey + buf[j, 4]
                POS[i, j, 2] = ez + buf[j, 5]
                VEL[i, j, 0], VEL[i, j, 1], VEL[i, j, 2] = qx, qy, qz
                # rolling: n x omega = -v, so omega = n x v + (omega . n) n
                SPIN[i, j, 0] = ny * qz - nz * qy + wn * nx
                SPIN[i, j, 1] = nz * qx - nx * qz + wn * ny
                SPIN[i, j, 2] = nx * qy - ny * qx + wn * nz
                PHASE[i, j] = ROLL if times[j] < t2 + tr else REST
    return True


@jit(nogil=True, fastmath=ROW_FLAGS)
def angle_rows(V, N, H, OUT, start, stop):
    """Speed, angle above the plane (degrees) and backspin about n x h of the rows (used for the totals).

    ``OUT[:, 0]`` speed, ``OUT[:, 1]`` angle = atan2(v . n, |v_t|) in degrees.
    """
    for i in range(start, stop):
        vx, vy, vz = V[i, 0], V[i, 1], V[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        vn = vx * nx + vy * ny + vz * nz
        tx, ty, tz = vx - vn * nx, vy - vn * ny, vz - vn * nz
        OUT[i, 0] = math.sqrt(vx * vx + vy * vy + vz * vz)
        OUT[i, 1] = math.atan2(vn, math.sqrt(tx * tx + ty * ty + tz * tz)) * (180.0 / math.pi)
    return True
