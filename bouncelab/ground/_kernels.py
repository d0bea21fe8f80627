"""Compiled row loops of the ground phase (numba; built on first use, cached on disk).

Every loop here treats its rows independently, in scaled units (radii, radii/s, rad/s,
seconds), with the floating-point flags :data:`bouncelab.core._jit.ROW_FLAGS` only (no
contraction into fused multiply-adds, no reassociation, no approximate functions): a
shot gives the same bits whatever the batch it is in, its position there and the number
of threads. Besides ``+ - * /`` and ``math.sqrt`` (correctly rounded), the loops call
libm's ``pow`` (curved skids and rolls on slopes) and ``atan2`` (lift-off angles), scalar
calls in loops with branches that the compiler does not vectorise, as the contact laws'
``exp``, ``sin`` and ``cos``.

Layouts
-------
``F`` (contact frames, ``(m, 9)``): ``t`` (3), ``b`` (3), then ``v . b``, ``omega . t`` and
``omega . n``: what the 2-D law does not touch (see :mod:`bouncelab.ground.bounce3d`).
"""

from __future__ import annotations

import math

import numpy as np

from bouncelab.core._jit import ROW_FLAGS, jit

#: A glide is straight when ``|q x a| <= PARALLEL |q| |a|`` or ``|a| <= PARALLEL k`` (see :func:`glide`).
PARALLEL = 1.0e-12
#: RK4 steps per vacuum flight time of a flight with air (see ``_air_flight``).
AIR_STEPS = 64
#: Most RK4 steps of one flight with air.
AIR_MAX_STEPS = 1_000_000
#: Halvings of the last step to find where a flight with air meets the ground.
AIR_BISECT = 60

# Phase codes of the path (bouncelab.ground.runout.PHASES).
FLIGHT, SKID, ROLL, REST = 0, 1, 2, 3


# ------------------------------------------------------------------------------ contact frame
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
def contact_frame(vx, vy, vz, wx, wy, wz, nx, ny, nz):
    """The in-plane axis t and b = n x t of a ball touching the plane of unit normal n.

    t is the direction of the tangential contact-point velocity ``u = v_t + n x omega``; when
    it vanishes, of the tangential velocity; when both vanish, :func:`_any_tangent`. Its sign
    makes the ball travel along +t (``v . t >= 0``), as the paper's balls travel in +x.
    """
    vn = vx * nx + vy * ny + vz * nz
    vtx = vx - vn * nx
    vty = vy - vn * ny
    vtz = vz - vn * nz
    ux = vtx + (ny * wz - nz * wy)
    uy = vty + (nz * wx - nx * wz)
    uz = vtz + (nx * wy - ny * wx)
    uu = ux * ux + uy * uy + uz * uz
    if uu > 0.0:
        s = math.sqrt(uu)
        tx, ty, tz = ux / s, uy / s, uz / s
    else:
        vv = vtx * vtx + vty * vty + vtz * vtz
        if vv > 0.0:
            s = math.sqrt(vv)
            tx, ty, tz = vtx / s, vty / s, vtz / s
        else:
            tx, ty, tz = _any_tangent(nx, ny, nz)
    if vtx * tx + vty * ty + vtz * tz < 0.0:
        tx, ty, tz = -tx, -ty, -tz
    bx = ny * tz - nz * ty
    by = nz * tx - nx * tz
    bz = nx * ty - ny * tx
    return tx, ty, tz, bx, by, bz


@jit(nogil=True, fastmath=ROW_FLAGS)
def to_plane_rows(V, W, N, P2, F, start, stop):
    """The 2-D landings ``[v . t, v . n, omega . (t x n)]`` into P2 and the frames into F (module layout)."""
    for i in range(start, stop):
        vx, vy, vz = V[i, 0], V[i, 1], V[i, 2]
        wx, wy, wz = W[i, 0], W[i, 1], W[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        tx, ty, tz, bx, by, bz = contact_frame(vx, vy, vz, wx, wy, wz, nx, ny, nz)
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
    """3-D lift-offs from the 2-D ones.

    ``v = xF t + yF n + (v.b) b`` and ``omega = (omega.t) t - wF b + keep (omega.n) n``.
    """
    for i in range(start, stop):
        xf, yf, wf = P2F[i, 0], P2F[i, 1], P2F[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        tx, ty, tz, bx, by, bz = F[i, 0], F[i, 1], F[i, 2], F[i, 3], F[i, 4], F[i, 5]
        vb, wt, wn = F[i, 6], F[i, 7], F[i, 8] * keep[i]
        VF[i, 0] = xf * tx + yf * nx + vb * bx
        VF[i, 1] = xf * ty + yf * ny + vb * by
        VF[i, 2] = xf * tz + yf * nz + vb * bz
        WF[i, 0] = wt * tx - wf * bx + wn * nx
        WF[i, 1] = wt * ty - wf * by + wn * ny
        WF[i, 2] = wt * tz - wf * bz + wn * nz
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


@jit(nogil=True, fastmath=ROW_FLAGS)
def advance_rows(VF, WF, N, T, P, g, hmin, last, air, leave, T1, P1, V1, start, stop):
    """After a bounce: fly to the next landing (``leave[i] = 1``), or stay on the ground (0).

    A ball leaves when the apex of its next flight without air, ``(v . n)^2 / (2 g n_z)``
    along the normal, is above ``hmin`` (radii) and this was not its last allowed bounce
    (``last``; then ``leave[i] = 2`` marks a ball that would have left). Its next landing
    time, position and velocity go to T1, P1, V1. A ball that stays keeps its tangential
    velocity: V1 receives ``v - (v . n) n``. ``air`` is ``[kd, kq, cl_slope, cl_max]`` or
    empty (no air).
    """
    empty = np.empty(0)
    dummy = np.empty((0, 6))
    for i in range(start, stop):
        vx, vy, vz = VF[i, 0], VF[i, 1], VF[i, 2]
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        vn = vx * nx + vy * ny + vz * nz
        up = vn > 0.0 and vn * vn > 2.0 * g * nz * hmin
        if up and not last:
            leave[i] = 1
            px, py, pz = P[i, 0], P[i, 1], P[i, 2]
            if air.shape[0] == 0:
                tf, qx, qy, qz, ux, uy, uz = _vacuum_flight(px, py, pz, vx, vy, vz, nx, ny, nz, g)
            else:
                tf, qx, qy, qz, ux, uy, uz, _ = _air_flight(px, py, pz, vx, vy, vz, WF[i, 0], WF[i, 1], WF[i, 2],
                                                            nx, ny, nz, g, air[0], air[1], air[2], air[3],
                                                            empty, dummy, 0)
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
def _curve_at(x, x0, qm1, s, aa):
    """Time, the two integrals and the speed factor ``S r`` of the curved glide at ``x = tan(psi / 2)``."""
    r = math.pow(x / x0, qm1)
    r2 = r * r
    xx = x * x
    x02 = x0 * x0
    t = s / aa * ((1.0 - r) / qm1 + (x02 - r * xx) / (qm1 + 2.0))
    ie = s * s / aa * ((1.0 - r2) / (2.0 * qm1) - (x02 * x02 - r2 * xx * xx) / (2.0 * qm1 + 4.0))
    ip = 2.0 * s * s / aa * ((x0 - r2 * x) / (2.0 * qm1 + 1.0) + (x02 * x0 - r2 * xx * x) / (2.0 * qm1 + 3.0))
    return t, ie, ip, s * r


@jit(fastmath=ROW_FLAGS)  # a call, not inlined: the loops that use it compile much faster
def _curve_x(ts, x0, qm1, s, aa):
    """The x in (0, x0] where the curved glide's time is ``ts`` (safeguarded Newton; t falls as x grows)."""
    lo = 0.0
    hi = x0
    x = 0.5 * x0
    for _ in range(200):
        t, _ie, _ip, sr = _curve_at(x, x0, qm1, s, aa)
        f = t - ts
        if f > 0.0:
            lo = x
        else:
            hi = x
        if f == 0.0 or hi - lo <= 1e-15 * x0:
            break
        xn = x + f * aa * x / (sr * (1.0 + x * x))  # Newton: dt/dx = -S r (1 + x^2) / (A x)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        x = xn
    return x


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
      The stop (x = 0) needs only arithmetic; a sample at a given time solves t(x) for x.

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
            x = _curve_x(tsample[j], x0, qm1, s, aa)
            _t, ie, ip, sr = _curve_at(x, x0, qm1, s, aa)
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


@jit(nogil=True, fastmath=ROW_FLAGS)
def ground_rows(VG, WG, PG, TG, N, g, mu_s, mu_r, OUT, start, stop):
    """Skid then roll to rest from the ground entry (VG tangential velocity, WG spin, PG, TG).

    OUT columns: 0 skid time, 1-3 position at the end of the skid, 4-6 velocity there,
    7 roll time, 8-10 rest position, 11 rest time.
    """
    empty = np.empty(0)
    dummy = np.empty((0, 6))
    for i in range(start, stop):
        nx, ny, nz = N[i, 0], N[i, 1], N[i, 2]
        gx, gy, gz, gn = _tangential_gravity(nx, ny, nz, g)
        vx, vy, vz = VG[i, 0], VG[i, 1], VG[i, 2]
        wx, wy, wz = WG[i, 0], WG[i, 1], WG[i, 2]
        ux = vx + (ny * wz - nz * wy)
        uy = vy + (nz * wx - nx * wz)
        uz = vz + (nx * wy - ny * wx)
        ts, sx, sy, sz, _ = glide(gx, gy, gz, 3.5 * mu_s * gn, ux, uy, uz, empty, dummy, 0)
        c = 5.0 / 14.0 * ts * ts
        ex = PG[i, 0] + vx * ts + c * gx + (2.0 / 7.0) * (sx - ux * ts)
        ey = PG[i, 1] + vy * ts + c * gy + (2.0 / 7.0) * (sy - uy * ts)
        ez = PG[i, 2] + vz * ts + c * gz + (2.0 / 7.0) * (sz - uz * ts)
        c = 5.0 / 7.0 * ts
        rx = vx + c * gx - (2.0 / 7.0) * ux
        ry = vy + c * gy - (2.0 / 7.0) * uy
        rz = vz + c * gz - (2.0 / 7.0) * uz
        tr, qx, qy, qz, _ = glide(5.0 / 7.0 * gx, 5.0 / 7.0 * gy, 5.0 / 7.0 * gz, mu_r * gn, rx, ry, rz,
                                  empty, dummy, 0)
        OUT[i, 0] = ts
        OUT[i, 1], OUT[i, 2], OUT[i, 3] = ex, ey, ez
        OUT[i, 4], OUT[i, 5], OUT[i, 6] = rx, ry, rz
        OUT[i, 7] = tr
        OUT[i, 8], OUT[i, 9], OUT[i, 10] = ex + qx, ey + qy, ez + qz
        OUT[i, 11] = TG[i] + ts + tr
    return True


# ------------------------------------------------------------------------------ the path
@jit(nogil=True, fastmath=ROW_FLAGS)
def sample_rows(times, N, g, mu_s, mu_r, air, offsets, BT, BP, BV, BW, VG, WG, PG, TG, GOUT, POS, VEL, SPIN,
                PHASE, start, stop):
    """States of each shot at ``times`` (ascending, from the first landing): POS, VEL, SPIN (shot, time, 3), PHASE.

    The bounces of shot i are rows ``offsets[i]:offsets[i+1]`` of BT (landing times), BP
    (landing positions), BV and BW (lift-off velocity and spin); a flight follows every
    bounce but the last. Then the ground phase from VG, WG, PG, TG with its results GOUT
    (:func:`ground_rows`). At an event's time the state is the one after it.
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
        vx, vy, vz = VG[i, 0], VG[i, 1], VG[i, 2]
        wx, wy, wz = WG[i, 0], WG[i, 1], WG[i, 2]
        ux = vx + (ny * wz - nz * wy)
        uy = vy + (nz * wx - nx * wz)
        uz = vz + (nx * wy - ny * wx)
        tg = TG[i]
        ts = GOUT[i, 0]
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
                POS[i, j, 0] = PG[i, 0] + vx * s + c * gx + (2.0 / 7.0) * (sx - ux * s)
                POS[i, j, 1] = PG[i, 1] + vy * s + c * gy + (2.0 / 7.0) * (sy - uy * s)
                POS[i, j, 2] = PG[i, 2] + vz * s + c * gz + (2.0 / 7.0) * (sz - uz * s)
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
        ex, ey, ez = GOUT[i, 1], GOUT[i, 2], GOUT[i, 3]
        rx, ry, rz = GOUT[i, 4], GOUT[i, 5], GOUT[i, 6]
        tr = GOUT[i, 7]
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
