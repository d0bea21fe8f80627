"""Landings to rest: ``bouncelab.ground.run`` side by side with a per-shot ``predict_one`` loop and with C.

Run: ``python benchmarks/bench_ground.py`` (about a minute; ``--quick``: small sizes, a few seconds once
the kernels are compiled). In one run, on the same landings (the paper's Table 1 ranges, any heading,
backspin or topspin, flat ``green-medium``, whose law is the published PennerVarying of campaign B with its
tilt faded, ``fade_xdot``):

* ``bouncelab.ground.run`` on one thread and on all (``BOUNCELAB_NUM_THREADS``);
* the peer a simulator developer would write (issue 30): a plain-Python loop over the shots and their
  bounces calling ``law.predict_one`` per bounce in the plane of travel, flights, skid and roll in Python
  floats (timed on a subset and scaled), checked to agree with ``run``;
* the same model in C (issue 34, item 3: ``run`` within 3x of an exported C ``bouncelab_run`` on one
  core): the ground kernels (``bouncelab/ground/_kernels.py``) and the law's ``kernel_3d`` translated by
  hand, line for line, into one ``bouncelab_run(v, w, n, rest, &t)`` per shot in SI units, compiled with
  ``cc -O2 -ffp-contract=off`` (no fused multiply-adds, as the kernels) and called once for all the shots;
  checked to agree with ``run`` bit for bit. Skipped without a C compiler. (The exporter will generate this
  from the kernels; until then this is the hand-written stand-in, for flat and sloped ground without air.)

The table prints seconds and shots per second, and the ratios. With sidespin (spin about the normal) the
3-D Penner bounce differs from a 2-D law in the plane of travel (on the tilted plane the sidespin moves the
contact point sideways), so the side-by-side landings carry backspin only; ``run`` with sidespin is timed
beside them. Times vary with the machine's load: the figures are indicative unless the machine is quiet.
"""

from __future__ import annotations

import argparse
import ctypes
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from bouncelab.core._parallel import num_threads
from bouncelab.ground import Surface, preset, run
from bouncelab.ground.surface import GRAVITY
from bouncelab.laws import _kernels as lk
from bouncelab.laws import set_num_threads

R = 0.02135
SI = {"velocity": "m/s", "spin": "rad/s"}


def landings(n: int, seed: int = 0, sidespin: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (m/s) and spins (rad/s) over the paper's Table 1 (both campaigns), any heading; backspin about
    n x heading, and with ``sidespin`` up to 1000 rpm about the normal."""
    rng = np.random.default_rng(seed)
    speed = rng.uniform(2.0, 38.7, n)
    angle = np.radians(rng.uniform(16.4, 89.5, n))
    heading = rng.uniform(0, 2 * np.pi, n)
    back = rng.uniform(-3880, 16200, n) * 2 * np.pi / 60
    side = rng.uniform(-1000, 1000, n) * 2 * np.pi / 60 * sidespin
    h = np.column_stack([np.cos(heading), np.sin(heading), np.zeros(n)])
    v = speed[:, None] * (np.cos(angle)[:, None] * h + np.sin(angle)[:, None] * [0.0, 0.0, -1.0])
    axis = np.column_stack([-h[:, 1], h[:, 0], np.zeros(n)])  # n x h: spin about it is topspin, so backspin is minus
    w = -back[:, None] * axis + side[:, None] * [0.0, 0.0, 1.0]
    return v, w


# ------------------------------------------------------------------------------ the predict_one loop
def python_run(v: np.ndarray, w: np.ndarray, surface: Surface, min_apex_m: float = 0.002,
               max_bounces: int = 100) -> np.ndarray:
    """Rest positions (m) of shots on flat ground, one shot and one bounce at a time, ``law.predict_one`` per bounce.

    The 2-D law acts in the plane of travel (h along the velocity on the ground, b = z x h): landing
    ``(v.h, v.z, -omega.b)``; the velocity across and the spin about h and z are kept.
    """
    one = surface.law.predict_one
    g = GRAVITY / R
    hmin = min_apex_m / R
    keep = surface.pivot_retention
    mu_s, mu_r = surface.sliding_friction, surface.rolling_resistance
    out = np.empty((len(v), 3))
    for i in range(len(v)):
        vx, vy, vz = (float(c) / R for c in v[i])
        wx, wy, wz = (float(c) for c in w[i])
        px = py = 0.0
        bounces = 0
        while vz < 0:
            s = math.sqrt(vx * vx + vy * vy)
            hx, hy = (vx / s, vy / s) if s > 0 else (1.0, 0.0)
            bx, by = -hy, hx
            xf, zf, wf = one(vx * hx + vy * hy, vz, -(wx * bx + wy * by), plausible=None)
            vb, wh = vx * bx + vy * by, wx * hx + wy * hy
            vx, vy, vz = xf * hx + vb * bx, xf * hy + vb * by, zf
            wx, wy, wz = wh * hx - wf * bx, wh * hy - wf * by, keep * wz
            bounces += 1
            if vz > 0 and vz * vz > 2 * g * hmin and bounces < max_bounces:
                tf = 2 * vz / g
                px, py, vz = px + vx * tf, py + vy * tf, -vz
            else:
                vz = 0.0
        # skid (flat: straight), then roll (straight)
        ux, uy = vx - wy, vy + wx
        u = math.hypot(ux, uy)
        ts = u / (3.5 * mu_s * g)
        c = 0.5 * ts  # Q = u0 T / 2 for a straight stop
        px += vx * ts + (2 / 7) * (ux * c - ux * ts)
        py += vy * ts + (2 / 7) * (uy * c - uy * ts)
        rx, ry = vx - (2 / 7) * ux, vy - (2 / 7) * uy
        tr = math.hypot(rx, ry) / (mu_r * g)
        px += rx * 0.5 * tr
        py += ry * 0.5 * tr
        out[i] = (px * R, py * R, 0.0)
    return out


# ------------------------------------------------------------------------------ the same model in C
def _doubles(name: str, values: tuple[float, ...]) -> str:
    return f"static const double {name}[{len(values)}] = {{{', '.join(repr(float(x)) for x in values)}}};"


C_SOURCE = r"""
/* bouncelab's ground phase (PennerVarying with fade_xdot, vacuum flights), translated by hand from
   bouncelab/ground/_kernels.py and bouncelab/laws/_kernels.py, operation for operation. */
#include <math.h>
#include <stdint.h>

CONSTANTS

static double dmin(double a, double b) { return a < b ? a : b; }

static void sin_cos_small(double x, double *s, double *c) {
    double z = x * x;
    *s = x + x * z * (((((SC[0] * z + SC[1]) * z + SC[2]) * z + SC[3]) * z + SC[4]) * z + SC[5]);
    *c = 1.0 - 0.5 * z + z * z * (((((CC[0] * z + CC[1]) * z + CC[2]) * z + CC[3]) * z + CC[4]) * z + CC[5]);
}
static void sincos_quadrant(double x, double *s, double *c) {
    if (x <= 0.25 * M_PI) { sin_cos_small(x, s, c); return; }
    sin_cos_small((PIO2_HI - x) + PIO2_LO, c, s);
}
static double atan_ratio(double num, double den) {
    double x, y, more;
    if (num > T3P8 * den) { x = -den / num; y = HALF_PI; more = MOREBITS; }
    else if (num > 0.66 * den) { x = (num - den) / (num + den); y = 0.25 * M_PI; more = 0.5 * MOREBITS; }
    else { x = num / den; y = 0.0; more = 0.0; }
    double z = x * x;
    double p = (((AP[0] * z + AP[1]) * z + AP[2]) * z + AP[3]) * z + AP[4];
    double q = ((((z + AQ[0]) * z + AQ[1]) * z + AQ[2]) * z + AQ[3]) * z + AQ[4];
    return y + (x * z * p / q + x + more);
}
static double fade(double xd, double scale) { return scale <= 0.0 ? 1.0 : dmin(fabs(xd) / scale, 1.0); }

/* the law's kernel_3d: the rigid bounce on the plane tilted by beta = k_p s phi towards the ball */
static void law_3d(double x, double y, double w, double vb, double wh, double wn, double r, double mu,
                   double k_p, double fade_xdot, double o[6]) {
    double beta = dmin(k_p * (sqrt(x * x + y * y) * atan_ratio(-y, fabs(x))) * fade(x, fade_xdot), HALF_PI);
    double s, c;
    sincos_quadrant(beta, &s, &c);
    double vt = x * c + y * s, vn = y * c - x * s, wt = wh * c + wn * s, wnn = wn * c - wh * s;
    double cap = -mu * (1.0 + r) * vn;
    double jt = (1.0 + 0.0) * (-(vt + w) / 3.5), jb = (1.0 + 0.0) * (-(vb + wt) / 3.5);
    double m = sqrt(jt * jt + jb * jb);
    if (m > cap) { jt = jt / m * cap; jb = jb / m * cap; }
    double vtf = vt + jt, vbf = vb + jb, vnf = -r * vn, wf = w + 2.5 * jt, wtf = wt + 2.5 * jb;
    o[0] = vtf * c - vnf * s; o[1] = vtf * s + vnf * c; o[2] = wf; o[3] = vbf;
    o[4] = wtf * c - wnn * s; o[5] = wtf * s + wnn * c;
}

static void along(double *x, double *y, double *z, double nx, double ny, double nz) {
    double d = *x * nx + *y * ny + *z * nz;
    *x = *x - d * nx; *y = *y - d * ny; *z = *z - d * nz;
}
static void lift(const double v[3], const double w[3], const double n[3], const double law[4], double keep,
                 double vf[3], double wf[3]) {
    double nx = n[0], ny = n[1], nz = n[2];
    double hx = v[0], hy = v[1], hz = v[2];
    along(&hx, &hy, &hz, nx, ny, nz);
    along(&hx, &hy, &hz, nx, ny, nz);
    double vv = hx * hx + hy * hy + hz * hz;
    if (vv > 0.0) { double s = sqrt(vv); hx = hx / s; hy = hy / s; hz = hz / s; }
    else {
        double ex = 1.0, ey = 0.0, ez = 0.0;
        if (!(fabs(nx) < 0.9)) { ex = 0.0; ey = 1.0; }
        double d = ex * nx + ey * ny + ez * nz;
        hx = ex - d * nx; hy = ey - d * ny; hz = ez - d * nz;
        double s = sqrt(hx * hx + hy * hy + hz * hz);
        hx = hx / s; hy = hy / s; hz = hz / s;
    }
    double bx = ny * hz - nz * hy, by = nz * hx - nx * hz, bz = nx * hy - ny * hx;
    double x = v[0] * hx + v[1] * hy + v[2] * hz, y = v[0] * nx + v[1] * ny + v[2] * nz;
    double ww = -(w[0] * bx + w[1] * by + w[2] * bz), vb = v[0] * bx + v[1] * by + v[2] * bz;
    double wh = w[0] * hx + w[1] * hy + w[2] * hz, wn = w[0] * nx + w[1] * ny + w[2] * nz;
    double o[6];
    law_3d(x, y, ww, vb, wh, wn, law[0], law[1], law[2], law[3], o);
    double xf = o[0], yf = o[1], wF = o[2], vbf = o[3], whf = o[4], wnf = o[5] * keep;
    vf[0] = xf * hx + yf * nx + vbf * bx; vf[1] = xf * hy + yf * ny + vbf * by; vf[2] = xf * hz + yf * nz + vbf * bz;
    wf[0] = whf * hx - wF * bx + wnf * nx; wf[1] = whf * hy - wF * by + wnf * ny; wf[2] = whf * hz - wF * bz + wnf * nz;
}

/* dq/dt = a - k q/|q| to the stop: time and Q = integral of q dt (no samples) */
static double glide(double ax, double ay, double az, double k, double qx, double qy, double qz, double Q[3]) {
    double q0 = sqrt(qx * qx + qy * qy + qz * qz);
    if (q0 == 0.0) { Q[0] = Q[1] = Q[2] = 0.0; return 0.0; }
    double aa = sqrt(ax * ax + ay * ay + az * az);
    double cx = qy * az - qz * ay, cy = qz * ax - qx * az, cz = qx * ay - qy * ax;
    if (aa <= PARALLEL * k || sqrt(cx * cx + cy * cy + cz * cz) <= PARALLEL * q0 * aa) {
        double d = k - (ax * qx + ay * qy + az * qz) / q0;
        double tt = q0 / d, h = 0.5 * tt;
        Q[0] = qx * h; Q[1] = qy * h; Q[2] = qz * h;
        return tt;
    }
    double ex = ax / aa, ey = ay / aa, ez = az / aa;
    double qe = qx * ex + qy * ey + qz * ez;
    double px = qx - qe * ex, py = qy - qe * ey, pz = qz - qe * ez;
    double pp = sqrt(px * px + py * py + pz * pz);
    px = px / pp; py = py / pp; pz = pz / pp;
    double x0 = qe >= 0.0 ? pp / (q0 + qe) : (q0 - qe) / pp;
    double qm1 = (k - aa) / aa, s = q0 / (1.0 + x0 * x0), x02 = x0 * x0;
    double tt = s / aa * (1.0 / qm1 + x02 / (qm1 + 2.0));
    double fe = s * s / aa * (1.0 / (2.0 * qm1) - x02 * x02 / (2.0 * qm1 + 4.0));
    double fp = 2.0 * s * s / aa * (x0 / (2.0 * qm1 + 1.0) + x02 * x0 / (2.0 * qm1 + 3.0));
    Q[0] = fe * ex + fp * px; Q[1] = fe * ey + fp * py; Q[2] = fe * ez + fp * pz;
    return tt;
}

static double surface_law[4], surface_keep, surface_mu_s, surface_mu_r, ball_radius, gravity, min_apex;
static long surface_max_bounces;

void bouncelab_setup(const double law[4], double keep, double mu_s, double mu_r, double radius_m, double g_m_s2,
                     double min_apex_m, long max_bounces) {
    for (int i = 0; i < 4; i++) surface_law[i] = law[i];
    surface_keep = keep; surface_mu_s = mu_s; surface_mu_r = mu_r; ball_radius = radius_m;
    gravity = g_m_s2 / radius_m; min_apex = min_apex_m / radius_m; surface_max_bounces = max_bounces;
}

/* One shot: SI in (m/s, rad/s, a unit normal), the rest position (m) and time (s) out; the number of bounces. */
int bouncelab_run(const double v_si[3], const double w[3], const double n[3], double rest[3], double *t_rest) {
    double g = gravity, nx = n[0], ny = n[1], nz = n[2];
    double k = 1.0 / ball_radius; /* as bouncelab.core.units: v * (factor / R), factor 1 for m/s */
    double v[3] = {v_si[0] * k, v_si[1] * k, v_si[2] * k};
    double wv[3] = {w[0], w[1], w[2]};
    double t = 0.0, p[3] = {0.0, 0.0, 0.0};
    int nb = 0;
    double vn = v[0] * nx + v[1] * ny + v[2] * nz;
    if (vn < -1e-9 * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])) {
        for (;;) {
            double a[3], b[3];
            lift(v, wv, n, surface_law, surface_keep, a, b);
            double an = a[0] * nx + a[1] * ny + a[2] * nz;
            nb += 1;
            wv[0] = b[0]; wv[1] = b[1]; wv[2] = b[2];
            if (an > 0.0 && an * an > 2.0 * g * nz * min_apex && nb < surface_max_bounces) {
                double tf = 2.0 * an / (g * nz);
                double qx = p[0] + a[0] * tf, qy = p[1] + a[1] * tf, qz = p[2] + a[2] * tf - 0.5 * g * tf * tf;
                double d = qx * nx + qy * ny + qz * nz;
                p[0] = qx - d * nx; p[1] = qy - d * ny; p[2] = qz - d * nz;
                v[0] = a[0]; v[1] = a[1]; v[2] = a[2] - g * tf;
                t += tf;
                continue;
            }
            v[0] = a[0] - an * nx; v[1] = a[1] - an * ny; v[2] = a[2] - an * nz;
            break;
        }
    } else {
        v[0] = v[0] - vn * nx; v[1] = v[1] - vn * ny; v[2] = v[2] - vn * nz;
    }
    double gn = g * nz, gx = gn * nx, gy = gn * ny, gz = gn * nz - g;
    double ux = v[0] + (ny * wv[2] - nz * wv[1]), uy = v[1] + (nz * wv[0] - nx * wv[2]);
    double uz = v[2] + (nx * wv[1] - ny * wv[0]);
    double S[3], Q[3];
    double ts = glide(gx, gy, gz, 3.5 * surface_mu_s * gn, ux, uy, uz, S);
    double c = 5.0 / 14.0 * ts * ts;
    double ex = p[0] + v[0] * ts + c * gx + (2.0 / 7.0) * (S[0] - ux * ts);
    double ey = p[1] + v[1] * ts + c * gy + (2.0 / 7.0) * (S[1] - uy * ts);
    double ez = p[2] + v[2] * ts + c * gz + (2.0 / 7.0) * (S[2] - uz * ts);
    c = 5.0 / 7.0 * ts;
    double rx = v[0] + c * gx - (2.0 / 7.0) * ux, ry = v[1] + c * gy - (2.0 / 7.0) * uy;
    double rz = v[2] + c * gz - (2.0 / 7.0) * uz;
    double tr = glide(5.0 / 7.0 * gx, 5.0 / 7.0 * gy, 5.0 / 7.0 * gz, surface_mu_r * gn, rx, ry, rz, Q);
    rest[0] = (ex + Q[0]) * ball_radius; rest[1] = (ey + Q[1]) * ball_radius; rest[2] = (ez + Q[2]) * ball_radius;
    *t_rest = t + ts + tr;
    return nb;
}

/* What a simulator's loop does: one call per shot. */
void run_many(long count, const double *v, const double *w, const double *n, double *rest, double *t_rest) {
    for (long i = 0; i < count; i++) bouncelab_run(v + 3 * i, w + 3 * i, n + 3 * i, rest + 3 * i, t_rest + i);
}
"""


def c_library(folder: str) -> ctypes.CDLL | None:
    """The C stand-in compiled into ``folder`` (None without a C compiler)."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return None
    consts = "\n".join([
        _doubles("SC", lk._SC), _doubles("CC", lk._CC), _doubles("AP", lk._AP), _doubles("AQ", lk._AQ),
        f"static const double PIO2_HI = {lk._PIO2_HI!r}, PIO2_LO = {lk._PIO2_LO!r}, T3P8 = {lk._T3P8!r};",
        f"static const double MOREBITS = {lk._MOREBITS!r}, HALF_PI = {lk.HALF_PI!r}, PARALLEL = 1e-12;",
    ])
    src = os.path.join(folder, "ground.c")
    lib = os.path.join(folder, "libground.so")
    with open(src, "w") as f:
        f.write(C_SOURCE.replace("CONSTANTS", consts))
    subprocess.run([cc, "-O2", "-ffp-contract=off", "-fPIC", "-shared", "-o", lib, src, "-lm"], check=True)
    dll = ctypes.CDLL(lib)
    dbl = ctypes.POINTER(ctypes.c_double)
    dll.bouncelab_setup.argtypes = [dbl, ctypes.c_double, ctypes.c_double, ctypes.c_double, ctypes.c_double,
                                    ctypes.c_double, ctypes.c_double, ctypes.c_long]
    dll.run_many.argtypes = [ctypes.c_long, dbl, dbl, dbl, dbl, dbl]
    return dll


def c_run(dll: ctypes.CDLL, surface: Surface, v: np.ndarray, w: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, float]:
    """Rest positions (m) from the C stand-in, and the seconds its loop took."""
    law = surface.law
    values = law.parameters
    params = np.array([values["r"], values["mu"], values["k_p"], law.fade_xdot or 0.0])
    dbl = ctypes.POINTER(ctypes.c_double)
    dll.bouncelab_setup(params.ctypes.data_as(dbl), surface.pivot_retention, surface.sliding_friction,
                        surface.rolling_resistance, R, GRAVITY, 0.002, 100)
    v, w = np.ascontiguousarray(v, dtype=float), np.ascontiguousarray(w, dtype=float)
    n = np.ascontiguousarray(np.broadcast_to(n, v.shape), dtype=float)
    rest, t_rest = np.empty_like(v), np.empty(len(v))
    t = time.perf_counter()
    dll.run_many(len(v), v.ctypes.data_as(dbl), w.ctypes.data_as(dbl), n.ctypes.data_as(dbl),
                 rest.ctypes.data_as(dbl), t_rest.ctypes.data_as(dbl))
    return rest, time.perf_counter() - t


# ------------------------------------------------------------------------------ the benchmark
def best(f, repeats: int) -> float:
    """Median seconds of ``repeats`` calls."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="landings for run and C (default 10^5)")
    parser.add_argument("--python-n", type=int, default=2_000, help="landings for the Python loop (scaled up)")
    parser.add_argument("--surface", default="green-medium", help="preset surface (default green-medium)")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="small sizes, a few seconds: checks the script runs")
    args = parser.parse_args(argv)
    if args.quick:
        args.n, args.python_n, args.repeats = 2_000, 100, 2
    surface = preset(args.surface)
    v, w = landings(args.n)
    vs, ws = landings(args.n, sidespin=True)
    n2 = np.array([0.0, 0.02, 1.0]) / math.hypot(0.02, 1.0)  # a 2 % slope: curved skids and rolls
    v2 = v - np.outer(np.maximum(v @ n2, 0.0), n2) * 2.0  # every landing into the sloped ground
    threads = num_threads()
    run(v[:100], w[:100], surface, units=SI).sample(20.0)  # compile (or load the cache) before timing
    run(v2[:100], w[:100], surface, normal=n2, units=SI)

    rows = []
    try:
        set_num_threads(1)
        result = run(v, w, surface, units=SI)
        t_run1 = best(lambda: run(v, w, surface, units=SI), args.repeats)
        t_side1 = best(lambda: run(vs, ws, surface, units=SI), args.repeats)
        t_slope1 = best(lambda: run(v2, w, surface, normal=n2, units=SI), args.repeats)
    finally:
        set_num_threads(threads)
    t_run = best(lambda: run(v, w, surface, units=SI), args.repeats)
    rows += [("ground.run, 1 thread", t_run1), (f"ground.run, {threads} threads", t_run),
             ("ground.run with sidespin, 1 thread", t_side1), ("ground.run on a 2 % slope, 1 thread", t_slope1)]

    m = min(args.python_n, args.n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        python_run(v[:5], w[:5], surface)  # the law's kernel for predict_one: compiled or loaded before timing
        t = time.perf_counter()
        ref = python_run(v[:m], w[:m], surface)
        t_py = (time.perf_counter() - t) * args.n / m
    scale = np.abs(result.rest_position[:m]).max()
    err_py = np.abs(ref - result.rest_position[:m]).max() / scale
    rows.append((f"predict_one loop in Python (scaled from {m:,})", t_py))

    t_c = t_c_slope = None
    with tempfile.TemporaryDirectory() as folder:
        dll = c_library(folder)
        if dll is not None:
            rest_c, _ = c_run(dll, surface, v, w, np.array([0.0, 0.0, 1.0]))
            same_c = bool((rest_c == result.rest_position).all())
            err_c = float(np.abs(rest_c - result.rest_position).max() / scale)
            t_c = best(lambda: c_run(dll, surface, v, w, np.array([0.0, 0.0, 1.0]))[1], args.repeats)
            slope_c, _ = c_run(dll, surface, v2, w, n2)
            same_slope = bool((slope_c == run(v2, w, surface, normal=n2, units=SI).rest_position).all())
            t_c_slope = best(lambda: c_run(dll, surface, v2, w, n2)[1], args.repeats)
            rows += [("C bouncelab_run loop (cc -O2), 1 core", t_c), ("C on the 2 % slope, 1 core", t_c_slope)]

    t = time.perf_counter()
    totals = result.totals
    t_totals = time.perf_counter() - t
    sub = min(10_000, args.n)
    t = time.perf_counter()
    ds = run(v[:sub], w[:sub], surface, units=SI, rate=20.0).path
    t_path = time.perf_counter() - t

    print(f"{args.n:,} landings to rest on {surface.name!r} ({type(surface.law).__name__}, fade_xdot="
          f"{surface.law.fade_xdot}), flat unless said; median of {args.repeats}; {os.cpu_count()} CPUs, load "
          f"average {os.getloadavg()[0]:.2f}; bounces per shot {totals['bounces'].mean():.2f} (max "
          f"{totals['bounces'].max()})")
    print(f"{'':<48}{'seconds':>10}{'shots/s':>14}")
    for name, secs in rows:
        print(f"{name:<48}{secs:>10.4f}{args.n / secs:>14,.0f}")
    print(f"predict_one loop / ground.run (1 thread): {t_py / t_run1:.1f}x; they agree to {err_py:.1e} of the "
          "longest run")
    if t_c is not None:
        print(f"ground.run (1 thread) / C: {t_run1 / t_c:.2f}x flat, {t_slope1 / t_c_slope:.2f}x on the slope; "
              f"C gives the same bits as run: flat {same_c}, slope {same_slope} (largest difference {err_c:.1e})")
    else:
        print("no C compiler (cc): the C side was skipped")
    print(f"(totals: {t_totals:.3f} s; path of {sub:,} shots at 20 samples/s, {ds.sizes['time']} samples, run "
          f"included: {t_path:.2f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
