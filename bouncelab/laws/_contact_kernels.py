r"""Compiled kernels of the contact laws (numba; loaded on first use, cached on disk).

``compliant_kernel`` (:class:`~bouncelab.laws.compliant.CompliantImpact`), ``turf_kernel``
(:class:`~bouncelab.laws.turf.TurfContact`) and ``crater_kernel``
(:class:`~bouncelab.laws.crater.CraterContact`) follow the protocol of
:class:`~bouncelab.laws.CompiledLaw`: ``kernel(xdot0, ydot0, omega0, *parameters) ->
(xdotF, ydotF, omegaF, regime)``, the law's parameters by name (and what its ``_kernel_args`` adds);
the integrators below take them packed in a tuple ``theta`` in that order, with a step count. The
physics and its accuracy are documented in the law modules; this file holds the arithmetic.

Scaled units: lengths in ball radii, the ball a uniform sphere (I = 2/5 m R^2),
forces per unit mass. A tangential force F at the contact point changes xdot at
rate F, omega at rate 5/2 F and so v_P = xdot + omega at rate 7/2 F.
"""

from __future__ import annotations

import math

from bouncelab.core._jit import jit

# Regime codes shared by both contact laws.
SLIP = 0       # the contact point slips throughout (after the bristle/spring has loaded)
GRIP = 1       # the contact point stops (sticks) during contact and leaves with v_P of the landing's sign
REVERSED = 2   # the contact point leaves slipping the other way (spin reversal of v_P)

MAX_PHASES = 24  # stick/slip phases per bounce before the kernel gives up switching (never reached in tests)
SCAN = 32        # CompliantImpact: scan points per contact time or per tangential period, whichever is shorter
ROOT_ITER = 80   # CompliantImpact: cap on root-refinement iterations per switch
ROOT_TOL = 1e-14  # CompliantImpact: switching times located to this fraction of the contact time


# ============================================================================= CompliantImpact
# Normal motion: delta'' = -N, N = delta + 2 zeta delta' (omega_n = 1: time in units of 1/omega_n).
@jit(inline="always")
def _normal(t, v0, z, wd):
    """(N, dN/dt, ddelta/dt) of the damped normal oscillator at time t (closed form)."""
    e = math.exp(-z * t)
    s = math.sin(wd * t)
    c = math.cos(wd * t)
    dd = v0 * e * (c - (z / wd) * s)
    n = v0 * e * (((1.0 - 2.0 * z * z) / wd) * s + 2.0 * z * c)
    return n, dd - 2.0 * z * n, dd


@jit(inline="always")
def _stick_state(tau, u0, v1, kap):
    """Spring displacement u and contact-point velocity v after time tau stuck (harmonic, closed form)."""
    c = math.cos(kap * tau)
    s = math.sin(kap * tau)
    return u0 * c + (v1 / kap) * s, v1 * c - u0 * kap * s


@jit
def _stick_g(t, t0, u0, v1, kap, kt, mu, v0, z, wd):
    """Margin of the friction cone while stuck: mu N - k_t |u| (stick ends where it turns negative)."""
    n, _, _ = _normal(t, v0, z, wd)
    u, _ = _stick_state(t - t0, u0, v1, kap)
    return mu * n - kt * abs(u)


@jit
def _slip_f(t, t0, j0, sig, vp0, kt, mu, v0, z, wd, dd0):
    """Slip velocity of the slider times the slip direction (slip ends where it turns negative)."""
    _, ndot, dd = _normal(t, v0, z, wd)
    j = j0 - sig * mu * (dd0 - dd)  # impulse of -sig mu N since t0: integral of N is the change of -delta'
    return sig * (vp0 + 3.5 * j) - mu * ndot / kt


@jit(inline="always")
def _switch_f(stick, t, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0):
    """The function whose root is the next switch: the end of sticking (``stick``) or of slipping."""
    if stick:
        return _stick_g(t, t0, u0, v1, kap, kt, mu, v0, z, wd)
    return _slip_f(t, t0, j0, sig, vp0, kt, mu, v0, z, wd, dd0)


@jit
def _switch_time(stick, a, b, tc, scale, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0):
    """The switching time in (a, b] by Illinois false position, the bracket kept (``b``, on the far side)."""
    fa = max(_switch_f(stick, a, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0) + scale, 0.0)
    fb = _switch_f(stick, b, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0) + scale
    side = 0
    for _k in range(ROOT_ITER):
        den = fb - fa
        m = (a * fb - b * fa) / den if den != 0.0 else 0.5 * (a + b)
        if not (a < m < b):
            m = 0.5 * (a + b)
            if m <= a or m >= b:
                break
        fm = _switch_f(stick, m, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0) + scale
        if fm < 0.0:
            b = m
            fb = fm
            if side < 0:
                fa *= 0.5
            side = -1
        else:
            a = m
            fa = fm
            if side > 0:
                fb *= 0.5
            side = 1
        if b - a <= ROOT_TOL * tc:
            break
    return b


@jit
def compliant_kernel(xd, yd, w, r, mu, kappa, z, wd, tc):
    """CompliantImpact; ``z, wd, tc`` (damping ratio, damped frequency, contact time) from its restitution
    (computed once per law, CompliantImpact._kernel_args)."""
    return _compliant(xd, yd, w, (r, mu, kappa, z, wd, tc))


@jit
def _compliant(xd, yd, w, theta):
    """theta = (r, mu, kappa, zeta, omega_d, t_c)."""
    r = theta[0]
    mu = theta[1]
    kap = theta[2]
    z = theta[3]
    wd = theta[4]
    tc = theta[5]
    kt = kap * kap / 3.5
    v0 = -yd
    vp0 = xd + w
    h = min(tc, 2.0 * math.pi / kap) / SCAN
    scale = 1e-13 * (abs(vp0) + v0 + 1e-300)
    n_s = (1.0 - 2.0 * z * z) / wd
    eh = math.exp(-z * h)
    sh = math.sin(wd * h)
    ch = math.cos(wd * h)
    cu = math.cos(kap * h)
    su = math.sin(kap * h)
    t0 = 0.0
    u0 = 0.0
    j0 = 0.0
    stuck = True
    sticks = 0
    crossed = False
    for _ in range(MAX_PHASES):
        v1 = vp0 + 3.5 * j0
        if stuck:
            # scan for the first grid point where the friction cone is left; the closed forms are
            # advanced along the grid by exact rotations and decay factors (no exp/sin/cos per point)
            a = t0
            b = t0
            found = False
            ex = math.exp(-z * t0)
            sn = math.sin(wd * t0)
            cs = math.cos(wd * t0)
            u = u0
            v = v1
            while b < tc:
                a = b
                b = b + h
                if b >= tc:
                    break
                sn, cs = sn * ch + cs * sh, cs * ch - sn * sh
                ex *= eh
                u, v = u * cu + v * (su / kap), v * cu - u * (kap * su)
                if v * vp0 < 0.0:
                    crossed = True
                if mu * v0 * ex * (n_s * sn + 2.0 * z * cs) - kt * abs(u) < -scale:
                    found = True
                    break
            if not found:
                b = tc
                if _stick_g(tc - 1e-12 * tc, t0, u0, v1, kap, kt, mu, v0, z, wd) >= -scale:
                    u, v = _stick_state(tc - t0, u0, v1, kap)
                    j0 = (v - vp0) / 3.5
                    t0 = tc
                    break
            # root of g in (a, b]: Illinois false position, bracket kept
            b = _switch_time(True, a, b, tc, scale, t0, u0, v1, kap, 0.0, 1.0, vp0, kt, mu, v0, z, wd, 0.0)
            u, v = _stick_state(b - t0, u0, v1, kap)
            j0 = (v - vp0) / 3.5
            t0 = b
            u0 = u
            stuck = False
        else:
            sig = 1.0 if u0 > 0.0 else -1.0
            _, _, dd0 = _normal(t0, v0, z, wd)
            a = t0
            b = t0
            found = False
            ex = math.exp(-z * t0)
            sn = math.sin(wd * t0)
            cs = math.cos(wd * t0)
            while True:
                a = b
                b = b + h
                if b >= tc:
                    break
                sn, cs = sn * ch + cs * sh, cs * ch - sn * sh
                ex *= eh
                dd = v0 * ex * (cs - (z / wd) * sn)
                n = v0 * ex * (n_s * sn + 2.0 * z * cs)
                if sig * (vp0 + 3.5 * (j0 - sig * mu * (dd0 - dd))) - mu * (dd - 2.0 * z * n) / kt < -scale:
                    found = True
                    break
            if not found:
                _, _, dd = _normal(tc, v0, z, wd)
                j0 = j0 - sig * mu * (dd0 - dd)
                t0 = tc
                break
            b = _switch_time(False, a, b, tc, scale, t0, u0, v1, kap, j0, sig, vp0, kt, mu, v0, z, wd, dd0)
            n, _, dd = _normal(b, v0, z, wd)
            j0 = j0 - sig * mu * (dd0 - dd)
            u0 = sig * mu * n / kt
            t0 = b
            stuck = True
            sticks += 1
    if t0 < tc:
        # switch budget spent (a chattering graze; not met in tests): finish the contact slipping
        # against the contact point's motion, as the cap mu N allows
        vnow = vp0 + 3.5 * j0
        if vnow != 0.0:
            sig = 1.0 if vnow > 0.0 else -1.0
            _, _, dd0 = _normal(t0, v0, z, wd)
            _, _, dd = _normal(tc, v0, z, wd)
            dj = mu * (dd0 - dd)
            j0 = j0 - sig * min(dj, abs(vnow) / 3.5)
    vpf = vp0 + 3.5 * j0
    if vp0 != 0.0 and vpf * vp0 < 0.0:
        code = REVERSED
    elif sticks > 0 or crossed or vp0 == 0.0:
        code = GRIP
    else:
        code = SLIP
    return xd + j0, -r * yd, w + 2.5 * j0, code


# ============================================================================= TurfContact
TURF_STEPS = 64  # RK4 steps per estimated elastic contact time (see turf.py for the accuracy this gives)
EVENT_ITER = 50  # cap on Illinois iterations locating one event inside a step
MAX_STEPS_FACTOR = 64  # a contact may last this many estimated contact times (deep plastic craters)


@jit(inline="always")
def _turf_rhs(dl, dld, dp, xd, w, u, plastic, stick, sig, k, c, mu, kt, pl):
    """Derivatives of (delta, delta', d_p, xdot, omega, u) and the normal force N."""
    e = dl - dp
    if e < 0.0:
        e = 0.0
    n = k * e * math.sqrt(e) * (1.0 + c * dld)
    if n < 0.0:
        n = 0.0
    fp = 0.0
    if n > 0.0 and dl > 0.0:
        dw = min(dl, 1.0)  # the crater wall in front of the ball is no higher than its equator
        fp = -pl * dw * dw * math.sqrt(dw) * xd
    if stick:
        fb = -kt * u
        ud = xd + w
    else:
        fb = -sig * mu * n
        ud = 0.0
    dpd = dld if plastic else 0.0
    return dld, -n, dpd, fb + fp, 2.5 * fb, ud, n


@jit(inline="always")
def _turf_step(s0, s1, s2, s3, s4, s5, h, plastic, stick, sig, k, c, mu, kt, pl):
    """One classical Runge-Kutta (RK4) step of size h in a fixed contact mode."""
    a0, a1, a2, a3, a4, a5, _ = _turf_rhs(s0, s1, s2, s3, s4, s5, plastic, stick, sig, k, c, mu, kt, pl)
    g = 0.5 * h
    b0, b1, b2, b3, b4, b5, _ = _turf_rhs(s0 + g * a0, s1 + g * a1, s2 + g * a2, s3 + g * a3, s4 + g * a4,
                                          s5 + g * a5, plastic, stick, sig, k, c, mu, kt, pl)
    c0, c1, c2, c3, c4, c5, _ = _turf_rhs(s0 + g * b0, s1 + g * b1, s2 + g * b2, s3 + g * b3, s4 + g * b4,
                                          s5 + g * b5, plastic, stick, sig, k, c, mu, kt, pl)
    d0, d1, d2, d3, d4, d5, _ = _turf_rhs(s0 + h * c0, s1 + h * c1, s2 + h * c2, s3 + h * c3, s4 + h * c4,
                                          s5 + h * c5, plastic, stick, sig, k, c, mu, kt, pl)
    q = h / 6.0
    return (s0 + q * (a0 + 2.0 * b0 + 2.0 * c0 + d0), s1 + q * (a1 + 2.0 * b1 + 2.0 * c1 + d1),
            s2 + q * (a2 + 2.0 * b2 + 2.0 * c2 + d2), s3 + q * (a3 + 2.0 * b3 + 2.0 * c3 + d3),
            s4 + q * (a4 + 2.0 * b4 + 2.0 * c4 + d4), s5 + q * (a5 + 2.0 * b5 + 2.0 * c5 + d5))


@jit(inline="always")
def _turf_events(s0, s1, s2, s3, s4, s5, plastic, stick, sig, k, c, mu, kt, ey, pl):
    """Switching functions, each positive while its mode holds: (yield, tangential, lift-off)."""
    e_raw = s0 - s2
    e = max(e_raw, 0.0)
    se = math.sqrt(e)
    n = k * e * se * (1.0 + c * s1)
    if n < 0.0:
        n = 0.0
    g_yield = s1 if plastic else ey - e
    if stick:
        g_tan = mu * n - kt * abs(s5)
    else:
        if plastic:
            ndot = -k * e * se * c * n
        else:
            ndot = k * (1.5 * se * s1 * (1.0 + c * s1) - e * se * c * n)
        g_tan = sig * (s3 + s4) - mu * ndot / kt
    # the turf stops pushing when the compression or the damped factor (1 + c delta') reaches zero
    g_lift = min(e_raw, ey * (1.0 + c * s1))
    return g_yield, g_tan, g_lift


@jit
def _turf_event_value(which, s0, s1, s2, s3, s4, s5, h, plastic, stick, sig, k, c, mu, kt, ey, pl):
    t0, t1, t2, t3, t4, t5 = _turf_step(s0, s1, s2, s3, s4, s5, h, plastic, stick, sig, k, c, mu, kt, pl)
    g = _turf_events(t0, t1, t2, t3, t4, t5, plastic, stick, sig, k, c, mu, kt, ey, pl)
    return g[which]


@jit
def _turf_locate(which, fa, fb, s0, s1, s2, s3, s4, s5, h, plastic, stick, sig, k, c, mu, kt, ey, pl):
    """Step size in (0, h] at which switching function ``which`` crosses zero (Illinois false position)."""
    a = 0.0
    b = h
    side = 0
    for _ in range(EVENT_ITER):
        den = fb - fa
        m = (a * fb - b * fa) / den if den != 0.0 else 0.5 * (a + b)
        if not (a < m < b):
            m = 0.5 * (a + b)
        fm = _turf_event_value(which, s0, s1, s2, s3, s4, s5, m, plastic, stick, sig, k, c, mu, kt, ey, pl)
        if fm < 0.0:
            b = m
            fb = fm
            if side < 0:
                fa *= 0.5
            side = -1
        else:
            a = m
            fa = fm
            if side > 0:
                fb *= 0.5
            side = 1
        if b - a <= 1e-11 * h:
            break
    return b


@jit
def turf_integrate(xd, yd, w, theta, nsteps):
    """TurfContact through one contact with ``nsteps`` RK4 steps per estimated elastic contact time."""
    k = 10.0 ** theta[0]
    c = theta[1] * 1e-3
    ey = theta[2]
    mu = theta[3]
    kt = 10.0 ** theta[4]
    pl = 0.4 * theta[5] * c * k
    v0 = -yd
    vp0 = xd + w
    # elastic contact time of N = k e^1.5 (Hertz): e_max = (5 v0^2 / 4k)^(2/5), t_c = 2.943 e_max / v0
    emax = (1.25 * v0 * v0 / k) ** 0.4
    h = 2.943 * emax / v0 / nsteps
    # a stuck contact point oscillates with frequency sqrt(3.5 k_t): resolve it too
    h = min(h, 2.0 * math.pi / math.sqrt(3.5 * kt) / 24.0)
    s0 = 0.0
    s1 = v0
    s2 = 0.0
    s3 = xd
    s4 = w
    s5 = 0.0
    plastic = False
    stick = vp0 == 0.0
    sig = 1.0 if vp0 > 0.0 else -1.0
    sticks = 0
    crossed = False
    started = False
    maxsteps = MAX_STEPS_FACTOR * nsteps * 4
    for _ in range(maxsteps):
        # explicit RK4 is stable for h * rate < 2.78: keep the damping of the normal motion
        # (k c e^1.5) and of the ploughing (pl min(delta, 1)^2.5) below 1.5 per step
        en = max(s0 - s2, 0.0)
        dw = min(max(s0, 0.0), 1.0)
        rate = pl * dw * dw * math.sqrt(dw) + k * c * en * math.sqrt(en)
        hs = h if rate * h <= 1.5 else 1.5 / rate
        ga, gt, gl = _turf_events(s0, s1, s2, s3, s4, s5, plastic, stick, sig, k, c, mu, kt, ey, pl)
        t0, t1, t2, t3, t4, t5 = _turf_step(s0, s1, s2, s3, s4, s5, hs, plastic, stick, sig, k, c, mu, kt, pl)
        fa, ft, fl = _turf_events(t0, t1, t2, t3, t4, t5, plastic, stick, sig, k, c, mu, kt, ey, pl)
        best = hs
        which = -1
        # a function may start a hair below zero right after its own switch: count it as zero
        ga = max(ga, 0.0)
        gt = max(gt, 0.0)
        gl = max(gl, 0.0)
        if fa < 0.0:
            sa = _turf_locate(0, ga, fa, s0, s1, s2, s3, s4, s5, hs, plastic, stick, sig, k, c, mu, kt, ey, pl)
            if sa <= best:
                best = sa
                which = 0
        if ft < 0.0:
            st = _turf_locate(1, gt, ft, s0, s1, s2, s3, s4, s5, hs, plastic, stick, sig, k, c, mu, kt, ey, pl)
            if st <= best:
                best = st
                which = 1
        if started and fl <= 0.0:
            sl = _turf_locate(2, gl, fl, s0, s1, s2, s3, s4, s5, hs, plastic, stick, sig, k, c, mu, kt, ey, pl)
            if sl <= best:
                best = sl
                which = 2
        if which >= 0:
            t0, t1, t2, t3, t4, t5 = _turf_step(s0, s1, s2, s3, s4, s5, best, plastic, stick, sig,
                                                k, c, mu, kt, pl)
        s0, s1, s2, s3, s4, s5 = t0, t1, t2, t3, t4, t5
        started = True
        if stick and (s3 + s4) * vp0 < 0.0:
            crossed = True
        if which == 2:
            break
        if which == 0:
            plastic = not plastic
        elif which == 1:
            e = s0 - s2
            n = k * e * math.sqrt(max(e, 0.0)) * (1.0 + c * s1)
            if stick:
                sig = 1.0 if s5 > 0.0 else -1.0
                stick = False
            else:
                s5 = sig * mu * max(n, 0.0) / kt
                stick = True
                sticks += 1
    vpf = s3 + s4
    if vp0 != 0.0 and vpf * vp0 < 0.0:
        code = REVERSED
    elif sticks > 0 or crossed or vp0 == 0.0:
        code = GRIP
    else:
        code = SLIP
    # the normal motion lifts off when the turf stops pushing; gravity (460 radii/s^2) is neglected
    return s3, -s1, s4, code


@jit
def turf_kernel(xd, yd, w, log10_k, c, e_y, mu, log10_kt, lam):
    """TurfContact with its default TURF_STEPS (c in ms/radius, e_y in radii)."""
    return turf_integrate(xd, yd, w, (log10_k, c, e_y, mu, log10_kt, lam), TURF_STEPS)


# ============================================================================= CraterContact
# The contact is integrated in the normal impulse p (per unit mass) accumulated in the frame of the
# crater wall, from 0 to P = (1 + r)|v_n|: friction and ploughing are forces proportional to the
# normal force, so p is their natural clock and no normal-force history is needed.
CRATER_STEPS = 48      # RK4 steps over the normal impulse of a contact (see CraterContact's accuracy note)
CRATER_ROOT_ITER = 60  # cap on the false-position iterations that locate the instant the contact point stops
CRATER_MAX_BETA = 60.0  # degrees: the crater wall is never steeper than this


@jit(inline="always")
def _crater_rhs(vt, w, sig, lp, kap, mk, dm, vs):
    """d(v_t, omega)/dp while slipping in direction sig: Coulomb friction mu(|v_P|) and the ploughing dashpot."""
    f = -sig * (mk + dm * math.exp(-abs(vt + w) / vs))
    g = -lp * (vt + kap * w)
    return g + f, 2.5 * (f + kap * g)


@jit(inline="always")
def _crater_step(vt, w, h, sig, lp, kap, mk, dm, vs):
    """One classical Runge-Kutta step of size h (in normal impulse) while slipping."""
    a0, a1 = _crater_rhs(vt, w, sig, lp, kap, mk, dm, vs)
    b0, b1 = _crater_rhs(vt + 0.5 * h * a0, w + 0.5 * h * a1, sig, lp, kap, mk, dm, vs)
    c0, c1 = _crater_rhs(vt + 0.5 * h * b0, w + 0.5 * h * b1, sig, lp, kap, mk, dm, vs)
    d0, d1 = _crater_rhs(vt + h * c0, w + h * c1, sig, lp, kap, mk, dm, vs)
    q = h / 6.0
    return vt + q * (a0 + 2.0 * b0 + 2.0 * c0 + d0), w + q * (a1 + 2.0 * b1 + 2.0 * c1 + d1)


@jit
def _crater_stop(vt, w, h, sig, lp, kap, mk, dm, vs):
    """The sub-step tau in (0, h] after which the contact point stops (sig v_P = 0), by Illinois false position.

    A step that starts on the stop line (just after slipping back from a stop) first brackets the
    end of its excursion by doubling sub-steps from 1e-12 h, so the root at its start is not taken.
    """
    a, fa = 0.0, sig * (vt + w)
    b = h
    x1, y1 = _crater_step(vt, w, b, sig, lp, kap, mk, dm, vs)
    fb = sig * (x1 + y1)
    eps = 1e-12 * (abs(vt) + abs(w) + vs)  # v_P is v_t + omega: rounding hides smaller values
    if fa <= eps:
        t = 1e-12 * h
        while t < h:
            x1, y1 = _crater_step(vt, w, t, sig, lp, kap, mk, dm, vs)
            ft = sig * (x1 + y1)
            if ft < -eps:
                if a == 0.0:
                    return t  # back on the stop line at once
                b, fb = t, ft
                break
            if ft > eps:
                a, fa = t, ft
            t *= 2.0
    side = 0
    for _ in range(CRATER_ROOT_ITER):
        if fa - fb <= 0.0:
            break
        c = (a * fb - b * fa) / (fb - fa)
        x1, y1 = _crater_step(vt, w, c, sig, lp, kap, mk, dm, vs)
        fc = sig * (x1 + y1)
        if fc > 0.0:
            a, fa = c, fc
            if side == -1:
                fb *= 0.5
            side = -1
        else:
            b, fb = c, fc
            if side == 1:
                fa *= 0.5
            side = 1
        if b - a <= 1e-12 * h:
            break
    return b


@jit
def crater_integrate(xd, yd, w, theta, nsteps):
    """CraterContact with ``nsteps`` RK4 steps over the contact's normal impulse: (xdotF, ydotF, omegaF, regime).

    theta = (r0, v_r, mu_k, mu_s, v_s, lam, kappa, e_t, beta0, beta_n, beta_t, fade_xdot).
    """
    r0, vr, mk, ms, vs, lam, kap, et = theta[0], theta[1], theta[2], theta[3], theta[4], theta[5], theta[6], theta[7]
    b0, bn, bt, fade = theta[8], theta[9], theta[10], theta[11]
    # Mirror a ball moving in -x onto +x (the law is mirror symmetric by construction).
    sg = 1.0 if xd >= 0.0 else -1.0
    x = sg * xd
    om = sg * w
    # The crater wall rises against the direction of travel, steeper for deeper (faster) landings.
    beta = (b0 + bn * abs(yd) / 1000.0 + bt * x / 1000.0) * (math.pi / 180.0)
    if fade > 0.0 and x < fade:
        beta *= x / fade
    beta = min(beta, CRATER_MAX_BETA * math.pi / 180.0)
    cb = math.cos(beta)
    sb = math.sin(beta)
    vt = cb * x + sb * yd
    vn = -sb * x + cb * yd  # < 0 for any landing (x >= 0, yd < 0, beta in [0, 60 deg])
    an = max(-vn, 1e-300)
    r = r0 / (1.0 + an / vr)
    total = (1.0 + r) * an
    lp = lam / an  # ploughing per unit normal impulse: a frictionless ball keeps exp(-lam (1 + r)) of v_t
    dm = ms - mk
    vp0 = vt + om
    # Stuck contact point: friction holds v_P = 0 against the ploughing torque while it can.
    hold = (1.0 - kap) * (1.0 + 2.5 * kap) / 3.5
    decay = 2.5 * (1.0 - kap) * (1.0 - kap) / 3.5
    stuck = False
    pstar = total
    if vp0 > 0.0:
        sig = 1.0
    elif vp0 < 0.0:
        sig = -1.0
    else:
        sig = -1.0 if vt > 0.0 else 1.0
        if lp * abs(vt) * hold <= ms:
            stuck = True
            pstar = 0.0
    sig0 = sig
    h = total / nsteps
    # Friction changes over the slip speed v_s near v_P = 0: there a step may change v_P by at most a
    # quarter of |v_P| + v_s at its current rate (scaled with nsteps, so convergence studies refine it too).
    hv = 0.25 * CRATER_STEPS / nsteps
    p = 0.0
    if stuck:
        vt *= math.exp(-decay * lp * total)
        om = -vt
    else:
        for _ in range(1000 * nsteps):  # far more than any contact needs (tested: p always reaches P)
            if p >= total * (1.0 - 1e-14):
                break
            a0, a1 = _crater_rhs(vt, om, sig, lp, kap, mk, dm, vs)
            vp = abs(vt + om)
            # stable too where friction balances ploughing (steady sliding): the step times the rate at which
            # v_P relaxes there, 3.5 |dmu/dv| + ploughing's, stays below 1/2
            stiff = 3.5 * abs(dm) / vs * math.exp(-vp / vs) + lp * (1.0 + 2.5 * kap)
            step = min(h, total - p, hv * (vp + vs) / (abs(a0 + a1) + 1e-300), 2.0 * hv / (stiff + 1e-300))
            nvt, nom = _crater_step(vt, om, step, sig, lp, kap, mk, dm, vs)
            if sig * (nvt + nom) > 0.0:
                vt, om, p = nvt, nom, p + step
                continue
            # the contact point stops inside this step: locate the instant, then stick or slip back
            tau = _crater_stop(vt, om, step, sig, lp, kap, mk, dm, vs)
            vt, om = _crater_step(vt, om, tau, sig, lp, kap, mk, dm, vs)
            p += tau
            # Stuck, ploughing pushes v_P towards -sign(v_t). If it pushes back to the side the contact
            # came from, the stop itself shows friction holds (the hold test can only miss by rounding).
            pushed = -1.0 if vt > 0.0 else 1.0
            if lp * abs(vt) * hold <= ms or pushed == sig:
                stuck = True
                pstar = p
                vt *= math.exp(-decay * lp * (total - p))
                om = -vt
                break
            sig = pushed
    vnf = r * an
    code = 0
    if stuck:
        code = 1
        # The bristles return part of the tangential motion they stopped (Walton's e_t), more the earlier
        # the contact stuck, never more energy than the contact has dissipated.
        rev = -et * vp0 * (1.0 - pstar / total)
        ke0 = 0.5 * (x * x + yd * yd) + 0.2 * w * w
        room = 7.0 * (ke0 - 0.5 * vnf * vnf - 0.7 * vt * vt)
        if rev * rev > room:
            rev = math.copysign(math.sqrt(max(room, 0.0)), rev)
        m = vt  # the rolling speed 5/7 v_t - 2/7 omega, unchanged by a contact-point impulse
        vt = m + rev / 3.5
        om = 2.5 * rev / 3.5 - m
    elif sig != sig0:
        code = 2
    xf = cb * vt - sb * vnf
    yf = sb * vt + cb * vnf
    return sg * xf, yf, sg * om, code


@jit
def crater_kernel(xd, yd, w, r0, v_r, mu_k, mu_s, v_s, lam, kappa, e_t, beta0, beta_n, beta_t, fade_xdot):
    """CraterContact with its default CRATER_STEPS steps (the CompiledLaw kernel)."""
    return crater_integrate(xd, yd, w, (r0, v_r, mu_k, mu_s, v_s, lam, kappa, e_t, beta0, beta_n, beta_t, fade_xdot),
                            CRATER_STEPS)
