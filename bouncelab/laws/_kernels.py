"""Compiled kernels for the built-in laws (numba, compiled lazily and cached on disk).

Each law's mathematics lives in exactly one scalar function here
(``_rigid``, which also serves TangentialRestitution, and ``_penner``); the array kernels apply it to every
bounce. ``law`` selects the scalar function by an integer id, a branch that is
perfectly predicted inside the loop and so costs nothing measurable, and lets
one cached kernel serve every built-in law.

All arrays are C-contiguous float64; ``P[i] = [xdot0, ydot0, omega0]`` in
scaled units with ``ydot0 < 0`` (validated by the caller, not here).
"""

from __future__ import annotations

import math
import types

import numpy as np
from numba import njit, prange

from bouncelab.laws._ids import (
    PENNER_FIXED,
    PENNER_VARYING,
    RIGID,
    ROLL,
    SLIP_BACKWARD,
    SLIP_FORWARD,
    TANGENTIAL,
)

HALF_PI = 0.5 * math.pi


@njit(cache=True, inline="always")
def _rigid(xd, yd, w, r, mu, et=0.0):
    """Eq. (rigid_bounce), optionally with tangential restitution ``et``; returns (xF, yF, wF, regime).

    All three cases of eq. (rigid_bounce) are one clipped impulse. A tangential impulse J per
    unit mass changes xdot by J and omega by 5/2 J (I = 2/5 m R^2), so v_P by 7/2 J. The
    impulse that stops the contact point (or, with et > 0, reverses it to -et v_P) is
    J = -(1 + et) v_P / 3.5; Coulomb friction caps |J| at mu (1 + r) |ydot0|. Uncapped is the
    roll case, capped the two slip cases. Branch-free, so the compiler vectorises it.
    """
    cap = -mu * (1.0 + r) * yd  # mu (1 + r) |ydot0|, as ydot0 < 0
    j_grip = -(1.0 + et) * (xd + w) / 3.5
    j = min(max(j_grip, -cap), cap)
    code = SLIP_FORWARD if j_grip < -cap else (SLIP_BACKWARD if j_grip > cap else ROLL)
    return xd + j, -r * yd, w + 2.5 * j, code


# Cephes sin.c coefficients: sin and cos on [0, pi/4] to about 1 ulp. beta lies in [0, pi/2], so
# one reflection covers it; libm's sin and cos were half of PennerVarying.predict's time.
_SC = (1.58962301576546568060e-10, -2.50507477628578072866e-8, 2.75573136213857245213e-6,
       -1.98412698295895385996e-4, 8.33333333332211858878e-3, -1.66666666666666307295e-1)
_CC = (-1.13585365213876817300e-11, 2.08757008419747316778e-9, -2.75573141792967388112e-7,
       2.48015872888517045348e-5, -1.38888888888730564116e-3, 4.16666666666665929218e-2)
_PIO2_HI = 1.5707963267948966  # pi/2 split in two doubles for an exact reflection
_PIO2_LO = 6.123233995736766e-17


@njit(cache=True, inline="always")
def _sin_cos_small(x):
    z = x * x
    s = x + x * z * (((((_SC[0] * z + _SC[1]) * z + _SC[2]) * z + _SC[3]) * z + _SC[4]) * z + _SC[5])
    c = 1.0 - 0.5 * z + z * z * (((((_CC[0] * z + _CC[1]) * z + _CC[2]) * z + _CC[3]) * z + _CC[4]) * z
                                  + _CC[5])
    return s, c


@njit(cache=True, inline="always")
def sincos_quadrant(x):
    """(sin x, cos x) for x in [0, pi/2]; within 2 ulp of math.sin / math.cos there."""
    if x <= 0.25 * math.pi:
        return _sin_cos_small(x)
    s, c = _sin_cos_small((_PIO2_HI - x) + _PIO2_LO)
    return c, s


@njit(cache=True, inline="always")
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
    vtf, vnf, wf, code = _rigid(vt, vn, om, r, mu)
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def speed_times_angle(xd, yd):
    """s * phi of eq. (penner_angle): landing speed (radii/s) times landing angle (rad)."""
    return math.sqrt(xd * xd + yd * yd) * atan_ratio(-yd, abs(xd))


@njit(cache=True, inline="always")
def _law(law, xd, yd, w, sphi, t0, t1, t2):
    """Dispatch to a law's scalar function; ``sphi`` is s * phi, used by PennerVarying only."""
    if law == RIGID:
        return _rigid(xd, yd, w, t0, t1)
    if law == PENNER_FIXED:
        return _penner(xd, yd, w, t0, t1, t2)
    if law == PENNER_VARYING:
        return _penner(xd, yd, w, t0, t1, min(t2 * sphi, HALF_PI))  # beta capped at 90 degrees
    return _rigid(xd, yd, w, t0, t1, t2)  # TANGENTIAL: t2 is e_t


# Below this many bounces a serial loop wins: waking the thread pool costs up to a millisecond.
PARALLEL_MIN = 20_000


def _predict_loop(P, t0, t1, t2, out, law):
    for i in prange(P.shape[0]):
        sphi = speed_times_angle(P[i, 0], P[i, 1]) if law == PENNER_VARYING else 0.0
        a, b, c, _ = _law(law, P[i, 0], P[i, 1], P[i, 2], sphi, t0, t1, t2)
        out[i, 0] = a
        out[i, 1] = b
        out[i, 2] = c


def _regime_loop(P, t0, t1, t2, codes, law):
    for i in prange(P.shape[0]):
        sphi = speed_times_angle(P[i, 0], P[i, 1]) if law == PENNER_VARYING else 0.0
        codes[i] = _law(law, P[i, 0], P[i, 1], P[i, 2], sphi, t0, t1, t2)[3]


def _serial_and_parallel(loop):
    """A serial and a parallel compiled variant of ``loop``, each cached under its own name.

    numba keys its on-disk cache by the Python function's qualified name and line, not by
    the ``parallel`` flag: compiled from one function object, the two variants would share
    a cache entry and one of them would silently run the other's code.
    """
    variants = []
    for parallel in (False, True):
        name = f"{loop.__name__}_{'parallel' if parallel else 'serial'}"
        f = types.FunctionType(loop.__code__, loop.__globals__, name)
        f.__qualname__ = name
        variants.append(njit(cache=True, fastmath=True, parallel=parallel)(f))
    return variants


_predict_serial, _predict_parallel = _serial_and_parallel(_predict_loop)
_regime_serial, _regime_parallel = _serial_and_parallel(_regime_loop)


def predict(law, P, t0, t1, t2, out):
    """Lift-off states of every bounce into ``out`` (n, 3)."""
    kernel = _predict_parallel if P.shape[0] >= PARALLEL_MIN else _predict_serial
    kernel(P, t0, t1, t2, out, law)


def regime(law, P, t0, t1, t2, codes):
    """Regime code of every bounce into ``codes`` (n,) int8."""
    kernel = _regime_parallel if P.shape[0] >= PARALLEL_MIN else _regime_serial
    kernel(P, t0, t1, t2, codes, law)


@njit(cache=True)
def speeds_times_angles(P):
    """s * phi of every landing (precomputed once per fit for PennerVarying)."""
    out = np.empty(P.shape[0])
    for i in range(P.shape[0]):
        out[i] = speed_times_angle(P[i, 0], P[i, 1])
    return out


@njit(cache=True, fastmath=True)
def error_sums(law, P0, PF, inv_norm, sphi, t0, t1, t2):
    """Sums over bounces of ||p_F - P_F||/||p_0|| and of |q_F - Q_F|/||p_0|| for each q.

    Dividing by n gives delta (eq. error) and Delta q (eq. error_individual).
    ``sphi`` holds s * phi of each landing (only read for PennerVarying).
    Serial on purpose: for ~10^3 bounces thread start-up costs more than it saves.
    """
    sd = 0.0
    sx = 0.0
    sy = 0.0
    sw = 0.0
    for i in range(P0.shape[0]):
        a, b, c, _ = _law(law, P0[i, 0], P0[i, 1], P0[i, 2], sphi[i], t0, t1, t2)
        ex = PF[i, 0] - a
        ey = PF[i, 1] - b
        ew = PF[i, 2] - c
        g = inv_norm[i]
        sd += math.sqrt(ex * ex + ey * ey + ew * ew) * g
        sx += abs(ex) * g
        sy += abs(ey) * g
        sw += abs(ew) * g
    return sd, sx, sy, sw


@njit(cache=True, fastmath=True)
def unit_objective(law, P0, PF, inv_norm, sphi, u, spec, weights):
    """The fitter's objective at a point ``u`` of the unit box, in one compiled call.

    ``spec`` rows: base values, lower bounds, spans, kernel scale factors (degrees to
    radians) and free flags of the three kernel parameters; free parameters take their
    values from ``u`` in order. Returns the ``weights``-weighted sum of delta and Delta q.
    """
    t = np.empty(3)
    j = 0
    for k in range(3):
        if spec[4, k] > 0.0:
            t[k] = spec[1, k] + u[j] * spec[2, k]
            j += 1
        else:
            t[k] = spec[0, k]
        t[k] *= spec[3, k]
    sd, sx, sy, sw = error_sums(law, P0, PF, inv_norm, sphi, t[0], t[1], t[2])
    return (weights[0] * sd + weights[1] * sx + weights[2] * sy + weights[3] * sw) / P0.shape[0]


def _affine_loop(P, normal, offset, A1, b1, A2, b2, out):
    for i in prange(P.shape[0]):
        x = P[i, 0]
        y = P[i, 1]
        w = P[i, 2]
        if normal[0] * x + normal[1] * y + normal[2] * w < offset:
            A = A1
            b = b1
        else:
            A = A2
            b = b2
        for j in range(3):
            out[i, j] = A[j, 0] * x + A[j, 1] * y + A[j, 2] * w + b[j]


_affine_serial, _affine_parallel = _serial_and_parallel(_affine_loop)


def affine_predict(P, normal, offset, A1, b1, A2, b2, out):
    """Piecewise-affine law: A1 p + b1 where normal . p < offset, else A2 p + b2."""
    kernel = _affine_parallel if P.shape[0] >= PARALLEL_MIN else _affine_serial
    kernel(P, normal, offset, A1, b1, A2, b2, out)


def warm_up() -> None:
    """Compile (or load from the cache) every kernel once, e.g. before timing."""
    P = np.array([[100.0, -100.0, 10.0]] * PARALLEL_MIN)
    out = np.empty_like(P)
    for law in (RIGID, PENNER_FIXED, PENNER_VARYING, TANGENTIAL):
        for rows in (P, P[:1]):  # the parallel and the serial kernel
            predict(law, rows, 0.5, 0.5, 0.1, out[: len(rows)])
            regime(law, rows, 0.5, 0.5, 0.1, np.empty(len(rows), np.int8))
        error_sums(law, P[:1], P[:1], np.ones(1), speeds_times_angles(P[:1]), 0.5, 0.5, 0.1)
        unit_objective(law, P[:1], P[:1], np.ones(1), speeds_times_angles(P[:1]), np.full(3, 0.5),
                       np.ones((5, 3)), np.ones(4))
    eye = np.eye(3)
    for rows in (P, P[:1]):
        affine_predict(rows, np.ones(3), 0.0, eye, np.zeros(3), eye, np.zeros(3), out[: len(rows)])
