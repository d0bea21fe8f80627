"""Reference implementations of the contact laws with scipy.integrate.solve_ivp (the code a researcher would write).

The same equations as :class:`bouncelab.CompliantImpact`, :class:`bouncelab.TurfContact` and
:class:`bouncelab.CraterContact`, integrated bounce by bounce with ``solve_ivp`` (DOP853) and its event location for
every mode switch. Used by the tests at a few points (accuracy) and by
``benchmarks/bench_contact.py`` (speed at equal accuracy).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["compliant_reference", "crater_reference", "turf_reference"]


def compliant_reference(p0, r: float, mu: float, kappa: float, rtol: float = 1e-12, atol: float = 1e-12):
    """Lift-off state of CompliantImpact by solve_ivp. State [delta, delta', J, u]; time in 1/omega_n."""
    from bouncelab.laws.compliant import _damping_of_restitution

    xd, yd, w = (float(v) for v in p0)
    z = _damping_of_restitution(r)
    kt = kappa * kappa / 3.5
    vp0 = xd + w
    y = np.array([0.0, -yd, 0.0, 0.0])
    t = 0.0
    stick = True
    sig = 1.0
    scale = abs(yd) + abs(vp0)

    def normal(s):
        n = s[0] + 2.0 * z * s[1]
        return n, s[1] - 2.0 * z * n  # N, dN/dt (delta'' = -N)

    for _ in range(50):
        def rhs(_t, s, stick=stick, sig=sig):
            n, ndot = normal(s)
            if stick:
                f, ud = -kt * s[3], vp0 + 3.5 * s[2]
            else:
                f, ud = -sig * mu * n, sig * mu * ndot / kt
            return [s[1], -n, f, ud]

        def lift(_t, s):
            return normal(s)[0] if _t > 0 else scale

        def switch(_t, s, stick=stick, sig=sig):
            n, ndot = normal(s)
            if stick:
                return mu * n - kt * abs(s[3]) + (scale * 1e-300 if _t == 0 else 0.0)
            return sig * (vp0 + 3.5 * s[2]) - mu * ndot / kt

        lift.terminal, lift.direction = True, -1
        switch.terminal, switch.direction = True, -1
        sol = solve_ivp(rhs, (t, t + 20.0), y, method="DOP853", rtol=rtol, atol=atol * scale,
                        events=[lift, switch])
        y = sol.y[:, -1].copy()
        t = sol.t[-1]
        if sol.t_events[0].size:
            break
        if sol.t_events[1].size:
            if stick:
                sig = 1.0 if y[3] > 0 else -1.0
                stick = False
            else:
                n, _ = normal(y)
                y[3] = sig * mu * n / kt
                stick = True
            # step past the switch so the event just found is not found again at the start
            continue
        break
    j = y[2]
    return np.array([xd + j, -r * yd, w + 2.5 * j])


def turf_reference(p0, theta, rtol: float = 1e-11, atol: float = 1e-12):
    """Lift-off state of TurfContact by solve_ivp. State [delta, delta', d, xdot, omega, u]."""
    lk, cms, ey, mu, lkt, lam = (float(v) for v in theta)
    k, c, kt = 10.0**lk, cms * 1e-3, 10.0**lkt
    pl = 0.4 * lam * c * k
    xd, yd, w = (float(v) for v in p0)
    vp0 = xd + w
    scale = abs(yd) + abs(xd) + abs(w)
    y = np.array([0.0, -yd, 0.0, xd, w, 0.0])
    t = 0.0
    plastic = False
    stick = vp0 == 0.0
    sig = 1.0 if vp0 > 0 else -1.0
    tmax = 100.0 * (1.25 * yd * yd / k) ** 0.4 / abs(yd)

    def force(s):
        e = max(s[0] - s[2], 0.0)
        n = max(k * e * math.sqrt(e) * (1.0 + c * s[1]), 0.0)
        return e, n

    for _ in range(200):
        def rhs(_t, s, plastic=plastic, stick=stick, sig=sig):
            _, n = force(s)
            fp = 0.0
            if n > 0.0 and s[0] > 0.0:
                dw = min(s[0], 1.0)
                fp = -pl * dw * dw * math.sqrt(dw) * s[3]
            if stick:
                fb, ud = -kt * s[5], s[3] + s[4]
            else:
                fb, ud = -sig * mu * n, 0.0
            return [s[1], -n, s[1] if plastic else 0.0, fb + fp, 2.5 * fb, ud]

        def ev_yield(_t, s, plastic=plastic):
            return s[1] if plastic else ey - (s[0] - s[2])

        def ev_tan(_t, s, plastic=plastic, stick=stick, sig=sig):
            e, n = force(s)
            if stick:
                return mu * n - kt * abs(s[5])
            se = math.sqrt(e)
            ndot = -k * e * se * c * n if plastic else k * (1.5 * se * s[1] * (1 + c * s[1]) - e * se * c * n)
            return sig * (s[3] + s[4]) - mu * ndot / kt

        def ev_lift(_t, s):
            return min(s[0] - s[2], ey * (1.0 + c * s[1])) if _t > 0 else 1.0

        for ev in (ev_yield, ev_tan, ev_lift):
            ev.terminal, ev.direction = True, -1
        sol = solve_ivp(rhs, (t, t + tmax), y, method="DOP853", rtol=rtol, atol=atol * scale,
                        events=[ev_yield, ev_tan, ev_lift])
        y = sol.y[:, -1].copy()
        t = sol.t[-1]
        if sol.t_events[2].size or (not sol.t_events[0].size and not sol.t_events[1].size):
            break
        if sol.t_events[0].size:
            plastic = not plastic
        else:
            if stick:
                sig = 1.0 if y[5] > 0 else -1.0
                stick = False
            else:
                _, n = force(y)
                y[5] = sig * mu * n / kt
                stick = True
    return np.array([y[3], -y[1], y[4]])


def crater_reference(p0, theta, fade_xdot: float = 50.0, rtol: float = 1e-11, atol: float = 1e-12):
    """Lift-off state and regime of CraterContact by solve_ivp, from the equations of its docstring.

    ``theta`` = (r0, v_r, mu_k, mu_s, v_s, lam, kappa, e_t, beta0, beta_n, beta_t). State [v_t, omega]
    in the crater wall's frame, integrated over the normal impulse p in [0, P]; an event where the contact
    point stops (v_P = v_t + omega = 0). Every stop gets the stick test (also one reached after slipping
    back: the regime is then ``grip``); a stuck contact stays stuck, its phase in closed form. The recoil's
    energy cap is read as: the recoil adds at most the kinetic energy lost so far (normal loss included),
    so the bounce never gains energy. Returns (xdotF, ydotF, omegaF, regime).
    """
    r0, v_r, mu_k, mu_s, v_s, lam, kappa, e_t, beta0, beta_n, beta_t = (float(v) for v in theta)
    xd, yd, w = (float(v) for v in p0)
    mirror = xd < 0.0
    if mirror:  # a ball moving in -x is the mirror image
        xd, w = -xd, -w
    beta = (beta0 + beta_n * abs(yd) / 1000.0 + beta_t * xd / 1000.0) * min(xd / fade_xdot, 1.0)
    b = math.radians(min(beta, 60.0))
    cb, sb = math.cos(b), math.sin(b)
    vt0, vn = cb * xd + sb * yd, -sb * xd + cb * yd
    an = abs(vn)
    r = r0 / (1.0 + an / v_r)
    total = (1.0 + r) * an
    lam_n = lam / an
    lever = 1.0 + 2.5 * kappa  # dv_P/dp = 3.5 f + lever g

    def mu(v):
        return mu_k + (mu_s - mu_k) * math.exp(-v / v_s)

    def plough(s):
        return -lam_n * (s[0] + kappa * s[1])

    y = np.array([vt0, w])
    vp0 = vt0 + w
    scale = abs(xd) + abs(yd) + abs(w)
    p = 0.0
    sig = 1.0 if vp0 > 0 else -1.0
    pstar = None
    reversed_ = False
    if vp0 == 0.0:  # lands with its contact point at rest: the stick test below at p = 0
        sig = 0.0
    for _ in range(100):
        if sig == 0.0:  # v_P = 0: does friction (at most mu_s) hold it against the ploughing torque?
            g = plough(y)
            if abs(lever * g) / 3.5 <= mu_s:
                pstar = p
                break
            sig = 1.0 if g > 0 else -1.0  # slips the way ploughing drives it
            if p > 0.0:
                reversed_ = True

        def rhs(_p, s, sig=sig):
            g = plough(s)
            # mu continued analytically past v_P = 0 (not clipped there): the solver's step across the
            # event stays smooth, and the event is located on an accurate dense output
            f = -sig * mu(max(sig * (s[0] + s[1]), -20.0 * v_s))  # (bounded for trial steps far beyond)
            return [g + f, 2.5 * (f + kappa * g)]

        def stop(_p, s, sig=sig, p_start=p):
            return sig * (s[0] + s[1]) if _p > p_start else 1.0

        stop.terminal, stop.direction = True, -1
        sol = solve_ivp(rhs, (p, total), y, method="DOP853", rtol=rtol, atol=atol * scale, events=[stop])
        y = sol.y[:, -1].copy()
        p = sol.t[-1]
        if not sol.t_events[0].size or p >= total:
            break
        y = sol.y_events[0][0].copy()
        p = sol.t_events[0][0]
        sig = 0.0
    if pstar is not None:
        # stuck to the end: v_P = 0, omega = -v_t, dv_t/dp = g + f with f = -lever g / 3.5 and
        # g = -lam_n (1 - kappa) v_t, i.e. dv_t/dp = -(5/7) lam_n (1 - kappa)^2 v_t (closed form)
        u = (5.0 * y[0] - 2.0 * y[1]) / 7.0  # the rolling speed: v_t on the stick line
        vt = u * math.exp(-(5.0 / 7.0) * lam_n * (1.0 - kappa) ** 2 * (total - pstar))
        y = np.array([vt, -vt])
        # bristle recoil: v_P = -e_t v_P0 (1 - p*/P), rolling speed unchanged, energy gain capped by the loss
        e0 = 0.5 * (vt0 * vt0 + vn * vn) + 0.2 * w * w
        e1 = 0.5 * (y[0] ** 2 + (r * an) ** 2) + 0.2 * y[1] ** 2
        vpf = -e_t * vp0 * (1.0 - pstar / total)
        cap = math.sqrt(7.0 * max(e0 - e1, 0.0))  # tangential energy at fixed rolling speed: 0.7 u^2 + v_P^2 / 7
        vpf = math.copysign(min(abs(vpf), cap), vpf)
        y = y + np.array([1.0, 2.5]) * vpf / 3.5
        regime = "grip"
    else:
        regime = "reversed" if reversed_ else "slip"
    vtf, vnf = y[0], r * an
    xf, yf, wf = cb * vtf - sb * vnf, sb * vtf + cb * vnf, y[1]
    if mirror:
        xf, wf = -xf, -wf
    return xf, yf, wf, regime
