"""Reference implementations of the contact laws with scipy.integrate.solve_ivp (the code a researcher would write).

The same equations as :class:`bouncelab.CompliantImpact` and :class:`bouncelab.TurfContact`,
integrated bounce by bounce with ``solve_ivp`` (DOP853) and its event location for
every mode switch. Used by the tests at a few points (accuracy) and by
``benchmarks/bench_contact.py`` (speed at equal accuracy).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["compliant_reference", "turf_reference"]


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
