"""Compiled scalar kernels of the built-in laws (numba; loaded on first use, cached on disk).

Each built-in law is a :class:`~bouncelab.laws.CompiledLaw` whose ``kernel`` is
one function below, ``kernel(xdot0, ydot0, omega0, *parameters) -> (xdotF, ydotF,
omegaF, regime)`` with the law's parameters by name; :mod:`bouncelab.laws.compiled` builds the array loops around it.
The mathematics of each law lives in exactly one scalar function (``_impulse``
for the rigid family, ``_penner`` for Penner's tilted surface). Penner's laws
also have a dedicated objective loop (:func:`penner_error_sums`) that takes each
landing's tilt factor precomputed once per fit.

States are in scaled units, ``ydot0 < 0`` (validated by the caller, not here).
"""

from __future__ import annotations

import math

import numpy as np

from bouncelab.core._jit import ROW_FLAGS, jit
from bouncelab.core._scans import landing_fault_
from bouncelab.core.landing_checks import INVALID

# Regime codes of the rigid family (lab frame: "forward" is +x).
SLIP_FORWARD = 0
ROLL = 1
SLIP_BACKWARD = 2

HALF_PI = 0.5 * math.pi
DEG = math.pi / 180.0


@jit(inline="always")
def _impulse(xd, yd, w, r, mu, et):
    """Rigid bounce with tangential restitution ``et``; returns (xF, yF, wF, regime).

    A tangential impulse J per unit mass changes xdot by J and omega by 5/2 J
    (I = 2/5 m R^2), so v_P by 7/2 J. The impulse that stops the contact point is
    J_stop = -v_P / 3.5; with tangential restitution (Walton's model) a gripping
    ball leaves with v_P reversed to -et v_P, i.e. J_grip = (1 + et) J_stop.
    Coulomb friction caps |J| at mu (1 + r) |ydot0|. Branch-free, so the compiler
    vectorises it.

    The regime follows the paper's rule applied to the law's own lift-off: the ball
    slipped throughout when the cap stops it before v_P reaches zero (|J_stop| > cap);
    otherwise it gripped ("roll"), whether or not it then left with v_P reversed.
    """
    cap = -mu * (1.0 + r) * yd  # mu (1 + r) |ydot0|, as ydot0 < 0
    j_stop = -(xd + w) / 3.5
    j_grip = (1.0 + et) * j_stop
    j = min(max(j_grip, -cap), cap)
    code = SLIP_FORWARD if j_stop < -cap else (SLIP_BACKWARD if j_stop > cap else ROLL)
    return xd + j, -r * yd, w + 2.5 * j, code


# The kernels a law's loops call are compiled functions of their own (not inlined into the loops: numba
# cannot inline a function it calls with the law's arguments unpacked, *args); their helpers are inlined.
@jit
def rigid_kernel(xd, yd, w, r, mu):
    """Eq. (rigid_bounce)."""
    return _impulse(xd, yd, w, r, mu, 0.0)


@jit
def tangential_kernel(xd, yd, w, r, mu, e_t):
    """Walton's hard-sphere law."""
    return _impulse(xd, yd, w, r, mu, e_t)


# Cephes sin.c coefficients: sin and cos on [0, pi/4] to about 1 ulp. beta lies in [0, pi/2], so
# one reflection covers it; libm's sin and cos were half of PennerVarying.predict's time.
_SC = (1.58962301576546568060e-10, -2.50507477628578072866e-8, 2.75573136213857245213e-6,
       -1.98412698295895385996e-4, 8.33333333332211858878e-3, -1.66666666666666307295e-1)
_CC = (-1.13585365213876817300e-11, 2.08757008419747316778e-9, -2.75573141792967388112e-7,
       2.48015872888517045348e-5, -1.38888888888730564116e-3, 4.16666666666665929218e-2)
_PIO2_HI = 1.5707963267948966  # pi/2 split in two doubles for an exact reflection
_PIO2_LO = 6.123233995736766e-17


@jit(inline="always")
def _sin_cos_small(x):
    z = x * x
    s = x + x * z * (((((_SC[0] * z + _SC[1]) * z + _SC[2]) * z + _SC[3]) * z + _SC[4]) * z + _SC[5])
    c = 1.0 - 0.5 * z + z * z * (((((_CC[0] * z + _CC[1]) * z + _CC[2]) * z + _CC[3]) * z + _CC[4]) * z
                                  + _CC[5])
    return s, c


@jit(inline="always")
def sincos_quadrant(x):
    """(sin x, cos x) for x in [0, pi/2]; within 2 ulp of math.sin / math.cos there."""
    if x <= 0.25 * math.pi:
        return _sin_cos_small(x)
    s, c = _sin_cos_small((_PIO2_HI - x) + _PIO2_LO)
    return c, s


@jit(inline="always")
def _penner(xd, yd, w, r, mu, beta):
    """Rigid bounce on a surface tilted by beta in [0, pi/2] (radians) against the direction of travel.

    A ball moving in -x is the mirror image of one moving in +x (xdot -> -xdot,
    omega -> -omega); xdot0 = 0 counts as +x.
    """
    sgn = 1.0 if xd >= 0.0 else -1.0
    x = sgn * xd
    om = sgn * w
    s, c = sincos_quadrant(beta)
    vt = x * c + yd * s  # along the tilted surface (it rises towards +x)
    vn = yd * c - x * s  # along its outward normal (-sin b, cos b): negative on approach
    vtf, vnf, wf, code = _impulse(vt, vn, om, r, mu, 0.0)
    xf = vtf * c - vnf * s
    yf = vtf * s + vnf * c
    if sgn < 0.0 and code != ROLL:
        code = 2 - code  # the mirror swaps forward and backward slip
    return sgn * xf, yf, sgn * wf, code


# Cephes atan.c coefficients (S. L. Moshier): atan to about 1e-16 relative error, about
# five times faster here than libm's atan2, which dominated PennerVarying.predict.
_T3P8 = 2.41421356237309504880  # tan(3 pi / 8)
_MOREBITS = 6.123233995736765886130e-17
_AP = (-8.750608600031904122785e-1, -1.615753718733365076637e1, -7.500855792314704667340e1,
       -1.228866684490136173410e2, -6.485021904942025371773e1)
_AQ = (2.485846490142306297962e1, 1.650270098316988542046e2, 4.328810604912902668951e2,
       4.853903996359136964868e2, 1.945506571482613964425e2)


@jit(inline="always")
def atan_ratio(num, den):
    """atan(num / den) for num >= 0, den >= 0 (den = 0 gives pi/2); within 2 ulp of math.atan2."""
    if num > _T3P8 * den:
        x = -den / num
        y = HALF_PI
        more = _MOREBITS
    elif num > 0.66 * den:
        x = (num - den) / (num + den)
        y = 0.25 * math.pi
        more = 0.5 * _MOREBITS
    else:
        x = num / den
        y = 0.0
        more = 0.0
    z = x * x
    p = (((_AP[0] * z + _AP[1]) * z + _AP[2]) * z + _AP[3]) * z + _AP[4]
    q = ((((z + _AQ[0]) * z + _AQ[1]) * z + _AQ[2]) * z + _AQ[3]) * z + _AQ[4]
    return y + (x * z * p / q + x + more)


@jit(inline="always")
def speed_times_angle(xd, yd):
    """s * phi of eq. (penner_angle): landing speed (radii/s) times landing angle (rad)."""
    return math.sqrt(xd * xd + yd * yd) * atan_ratio(-yd, abs(xd))


@jit(inline="always")
def fade(xd, scale):
    """Tilt factor min(|xdot0| / scale, 1) of Penner's continuous variant (1 when scale is 0: published law)."""
    if scale <= 0.0:
        return 1.0
    return min(abs(xd) / scale, 1.0)


@jit
def penner_fixed_kernel(xd, yd, w, r, mu, beta_deg, fade_xdot):
    """The tilt beta_deg (degrees), faded below fade_xdot (0: no fade, the published law)."""
    return _penner(xd, yd, w, r, mu, beta_deg * DEG * fade(xd, fade_xdot))


@jit
def penner_varying_kernel(xd, yd, w, r, mu, k_p, fade_xdot):
    """beta = k_p s phi (capped at 90 degrees), faded below fade_xdot (0: no fade)."""
    beta = min(k_p * speed_times_angle(xd, yd) * fade(xd, fade_xdot), HALF_PI)
    return _penner(xd, yd, w, r, mu, beta)


# ------------------------------------------------------------------------------ the rigid family in 3-D
# A law's own 3-D bounce (CompiledLaw.kernel_3d, used by bouncelab.ground): the landing in the frame of the
# plane of travel (h along the velocity on the ground, b = n x h, n the ground's normal; see
# bouncelab.ground.bounce3d), ``(x, y, w, vb, wh, wn) = (v.h, v.n, -omega.b, v.b, omega.h, omega.n)``, and the
# same arguments as the law's 2-D kernel; it returns the lift-off in that frame. ``(x, y, w)`` is the paper's
# 2-D landing, so an in-plane landing (vb = wh = wn = 0) gives the 2-D kernel's lift-off bit for bit.


@jit(inline="always")
def impulse_3d(vt, vb, vn, w, wt, r, mu, et):
    """The 3-D rigid bounce on a plane, in its frame (t, b, n): velocity (vt, vb, vn), spin (wt, -w, wn).

    The contact point (at -n, unit radius) slips at ``(vt + w, vb + wt)`` along (t, b). A tangential
    impulse J per unit mass changes the velocity by J and the spin by ``-5/2 n x J``, so the slip by
    ``7/2 J``, parallel to J: the impulse that stops the slip is ``-slip / 3.5`` along both axes; Walton's
    gripping ball (tangential restitution ``et``) takes ``(1 + et)`` times it, and Coulomb friction caps its
    length at ``mu (1 + r) |vn|``, along the slip. The normal velocity becomes ``-r vn`` and the spin
    about n is unchanged. Returns ``(vtF, vbF, vnF, wF, wtF)``. With ``vb + wt = 0`` (no slip across t)
    this is :func:`_impulse` bit for bit: ``|J| = sqrt(J_t^2)`` is exactly ``|J_t|`` and ``J_t / |J_t|``
    exactly +-1, so a capped impulse is exactly +-cap.
    """
    cap = -mu * (1.0 + r) * vn  # mu (1 + r) |vn|, as vn < 0
    jt = (1.0 + et) * (-(vt + w) / 3.5)
    jb = (1.0 + et) * (-(vb + wt) / 3.5)
    m = math.sqrt(jt * jt + jb * jb)
    if m > cap:
        jt = jt / m * cap
        jb = jb / m * cap
    return vt + jt, vb + jb, -r * vn, w + 2.5 * jt, wt + 2.5 * jb


@jit(inline="always")
def _penner_3d(x, y, w, vb, wh, wn, r, mu, beta):
    """The 3-D rigid bounce on the ground tilted by beta (radians) towards the incoming ball, in the plane of travel.

    The tilted plane's axes are ``t' = c h + s n`` and ``n' = c n - s h`` (b unchanged): the 2-D rotation
    of :func:`_penner` for a ball moving in +x, and the spin's h and n components rotate with it.
    """
    s, c = sincos_quadrant(beta)
    vt = x * c + y * s
    vn = y * c - x * s
    wt = wh * c + wn * s
    wnn = wn * c - wh * s
    vtf, vbf, vnf, wf, wtf = impulse_3d(vt, vb, vn, w, wt, r, mu, 0.0)
    return vtf * c - vnf * s, vtf * s + vnf * c, wf, vbf, wtf * c - wnn * s, wtf * s + wnn * c


@jit
def rigid_kernel_3d(x, y, w, vb, wh, wn, r, mu):
    """Eq. (rigid_bounce) in 3-D: the exact rigid bounce with Coulomb friction along the slip."""
    vtf, vbf, vnf, wf, wtf = impulse_3d(x, vb, y, w, wh, r, mu, 0.0)
    return vtf, vnf, wf, vbf, wtf, wn


@jit
def tangential_kernel_3d(x, y, w, vb, wh, wn, r, mu, e_t):
    """Walton's law in 3-D: the gripping ball's slip reversed to -e_t times itself, along the slip."""
    vtf, vbf, vnf, wf, wtf = impulse_3d(x, vb, y, w, wh, r, mu, e_t)
    return vtf, vnf, wf, vbf, wtf, wn


@jit
def penner_fixed_kernel_3d(x, y, w, vb, wh, wn, r, mu, beta_deg, fade_xdot):
    """:func:`penner_fixed_kernel` in 3-D: the rigid bounce on the plane tilted by its angle towards the ball."""
    return _penner_3d(x, y, w, vb, wh, wn, r, mu, beta_deg * DEG * fade(x, fade_xdot))


@jit
def penner_varying_kernel_3d(x, y, w, vb, wh, wn, r, mu, k_p, fade_xdot):
    """:func:`penner_varying_kernel` in 3-D (beta = k_p s phi of the landing in the plane of travel)."""
    beta = min(k_p * speed_times_angle(x, y) * fade(x, fade_xdot), HALF_PI)
    return _penner_3d(x, y, w, vb, wh, wn, r, mu, beta)


@jit(nogil=True)
def penner_tilt_factors(P, varying, scale):
    """Per landing, the factor multiplying the law's angle parameter: fade (x s phi for PennerVarying)."""
    out = np.empty(P.shape[0])
    for i in range(P.shape[0]):
        g = fade(P[i, 0], scale)
        out[i] = g * speed_times_angle(P[i, 0], P[i, 1]) if varying else g
    return out


@jit(inline="always")
def add_errors(sd, sx, sy, sw, PF, i, a, b, c, g):
    """The four error sums with row ``i`` added: the prediction ``(a, b, c)`` against the lift-off ``PF[i]``,
    weighted by ``g`` (the row's 1 / norm). Inlined into the error loops: the same operations in the same order
    as written out there before, so the same bits."""
    ex = PF[i, 0] - a
    ey = PF[i, 1] - b
    ew = PF[i, 2] - c
    return (sd + math.sqrt(ex * ex + ey * ey + ew * ew) * g, sx + abs(ex) * g, sy + abs(ey) * g,
            sw + abs(ew) * g)


@jit(nogil=True, fastmath=ROW_FLAGS)
def penner_error_sums(P0, PF, inv_norm, factor, r, mu, angle, start, stop):
    """The four error sums of a Penner law with each landing's tilt factor precomputed.

    beta_i = min(angle * factor_i, pi/2) with ``angle`` in radians (PennerFixed) or
    k_p (PennerVarying, whose factors include s * phi).
    """
    sd = 0.0
    sx = 0.0
    sy = 0.0
    sw = 0.0
    for i in range(start, stop):
        beta = min(angle * factor[i], HALF_PI)
        a, b, c, _ = _penner(P0[i, 0], P0[i, 1], P0[i, 2], r, mu, beta)
        sd, sx, sy, sw = add_errors(sd, sx, sy, sw, PF, i, a, b, c, inv_norm[i])
    return sd, sx, sy, sw


@jit(inline="always")
def _affine(A, b, x, y, w, code):
    return (A[0, 0] * x + A[0, 1] * y + A[0, 2] * w + b[0], A[1, 0] * x + A[1, 1] * y + A[1, 2] * w + b[1],
            A[2, 0] * x + A[2, 1] * y + A[2, 2] * w + b[2], code)


@jit(inline="always")
def _piecewise(x, y, w, normal, offset, A1, b1, A2, b2):
    if normal[0] * x + normal[1] * y + normal[2] * w < offset:
        return _affine(A1, b1, x, y, w, 0)
    return _affine(A2, b2, x, y, w, 1)


@jit
def piecewise_kernel(x, y, w, normal, offset, A1, b1, A2, b2):
    """Side 1 (code 0) where normal . p < offset: A1 p + b1; else side 2 (code 1): A2 p + b2."""
    return _piecewise(x, y, w, normal, offset, A1, b1, A2, b2)


# The piecewise law's loops: the kernel's arithmetic inlined into the row loop (the generic loop calls the
# kernel as a function of its own, passing six arrays per row, which took most of its time).
@jit(nogil=True, fastmath=ROW_FLAGS)
def piecewise_predict_rows(P, normal, offset, A1, b1, A2, b2, out, bits, guard, start, stop):
    """Lift-offs of rows [start, stop) into ``out``, and the unit guard's verdict on them (:func:`row_status`)."""
    status = 0
    for i in range(start, stop):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
        status |= found
        if found & INVALID:  # not a landing: the maths never sees it (refused)
            continue
        a, b, c, _ = _piecewise(x, y, w, normal, offset, A1, b1, A2, b2)
        out[i, 0] = a
        out[i, 1] = b
        out[i, 2] = c
    return status


@jit(nogil=True, fastmath=ROW_FLAGS)
def piecewise_regime_rows(P, normal, offset, A1, b1, A2, b2, codes, bits, guard, start, stop):
    """Regime codes of rows [start, stop) into ``codes`` (as :func:`piecewise_predict_rows`)."""
    status = 0
    for i in range(start, stop):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
        status |= found
        if found & INVALID:  # not a landing: the maths never sees it (refused)
            continue
        codes[i] = _piecewise(x, y, w, normal, offset, A1, b1, A2, b2)[3]
    return status


# Prediction loops of Penner's laws. The generic loops of CompiledLaw call the kernel per bounce with
# the parameter vector; here the tilt's sine and cosine can be computed once per call when the tilt is
# fixed (no fade), which doubles PennerFixed's throughput. Same scalar functions, same results.


@jit(inline="always")
def _penner_beta(xd, yd, angle, varying, scale):
    g = fade(xd, scale)
    if varying:
        return min(angle * speed_times_angle(xd, yd) * g, HALF_PI)
    return angle * g


_ABS = 0x7FFFFFFFFFFFFFFF  # all bits but the sign


@jit(inline="always")
def valid_bits(x, y, w, limit_bits):
    """A landing's validity from its values' bits (int64): finite and within the limit, ydot < 0.

    :func:`bouncelab.core.validation.is_landing` for loops compiled with fast-math assumptions about NaN:
    for doubles without the sign bit, the integer order of the bits is the order of the values,
    and NaN and infinities lie above every finite value; unlike float comparisons, this cannot be
    changed by fast-math assumptions.
    """
    return (((x & _ABS) <= limit_bits) & ((y & _ABS) <= limit_bits) & ((w & _ABS) <= limit_bits)
            & (y < 0) & ((y & _ABS) != 0))


@jit(inline="always")
def row_status(x, y, w, bx, by, bw, guard):
    """The unit guard's verdict on one landing in a row loop: INVALID if it is not a valid landing
    (:func:`valid_bits` of its bits ``bx, by, bw``), else the limits it breaks
    (:func:`bouncelab.core.plausibility.landing_fault`); ``guard`` is ``(limit bits, *limits)``
    (:func:`bouncelab.laws.compiled.row_checks`). A select, not arithmetic, joins the two: the fault bits of
    a row that is not valid (computed under fast-math from NaN, say) never reach the result."""
    limit_bits, min_s2, max_s2, max_w, tan_a = guard
    fault = landing_fault_(x, y, w, min_s2, max_s2, max_w, tan_a)
    return fault if valid_bits(bx, by, bw, limit_bits) else INVALID


# Every row loop reads its landing and calls row_status in four lines of its own: a helper returning
# (x, y, w, status) gives the same bits but made the generic prediction loop 1.3x slower (measured side
# by side on 10^6 rows, 2.24 against 2.94 ms), so those lines stay written out in each loop.


@jit(nogil=True, fastmath=ROW_FLAGS)
def penner_predict_rows(P, r, mu, angle, varying, scale, out, bits, guard, start, stop):
    """Lift-off of rows [start, stop) into ``out``; ``angle`` is beta in radians (fixed) or k_p (varying).

    Returns the unit guard's verdict on the rows (:func:`row_status`).
    """
    status = 0
    if not varying and scale <= 0.0:
        for i in range(start, stop):
            x = P[i, 0]
            y = P[i, 1]
            w = P[i, 2]
            found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
            status |= found
            if found & INVALID:  # not a landing: the maths never sees it (refused)
                continue
            a, b, c, _ = _penner(x, y, w, r, mu, angle)
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
    elif scale <= 0.0:  # Penner's angle, published (no fade)
        for i in range(start, stop):
            x = P[i, 0]
            y = P[i, 1]
            w = P[i, 2]
            found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
            status |= found
            if found & INVALID:  # not a landing: the maths never sees it (refused)
                continue
            beta = min(angle * speed_times_angle(x, y), HALF_PI)
            a, b, c, _ = _penner(x, y, w, r, mu, beta)
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
    else:
        for i in range(start, stop):
            x = P[i, 0]
            y = P[i, 1]
            w = P[i, 2]
            found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
            status |= found
            if found & INVALID:  # not a landing: the maths never sees it (refused)
                continue
            beta = _penner_beta(x, y, angle, varying, scale)
            a, b, c, _ = _penner(x, y, w, r, mu, beta)
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
    return status


@jit(nogil=True, fastmath=ROW_FLAGS)
def penner_regime_rows(P, r, mu, angle, varying, scale, codes, bits, guard, start, stop):
    """Regime codes of rows [start, stop) into ``codes`` (as :func:`penner_predict_rows`)."""
    status = 0
    for i in range(start, stop):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
        status |= found
        if found & INVALID:  # not a landing: the maths never sees it (refused)
            continue
        beta = _penner_beta(x, y, angle, varying, scale)
        codes[i] = _penner(x, y, w, r, mu, beta)[3]
    return status
