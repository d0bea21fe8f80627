"""Landings to rest: ``bouncelab.ground.run`` side by side with a per-shot ``predict_one`` loop and with C.

Run: ``python benchmarks/bench_ground.py`` (about a minute; ``--quick``: small sizes, a few seconds once
the kernels are compiled). In one run, on the same landings (the paper's Table 1 ranges, any heading,
backspin or topspin, flat ``green-medium``, whose law is the published PennerVarying of campaign B with its
tilt faded, ``fade_xdot``):

* ``bouncelab.ground.run`` on one thread and on all (``BOUNCELAB_NUM_THREADS``);
* the peer a simulator developer would write (issue 30): a plain-Python loop over the shots and their
  bounces calling ``law.predict_one`` per bounce in the plane of travel, flights, skid and roll in Python
  floats (timed on a subset and scaled), checked to agree with ``run``;
* the same surface exported to C (issue 34, item 3: ``run`` within 3x of the exported C ``bouncelab_run`` on
  one core): ``bouncelab.export.export_surface(surface, "c")`` translates the ground's own kernels
  (``bouncelab/ground/_kernels.py``: ``run_rows`` with the law's lift) into a header; a C loop calls its
  ``bouncelab_run(v, w, n, rest, &t)`` once per shot in SI units (input checks and unit conversion
  included, as ``run`` does them), compiled with ``cc -O2 -ffp-contract=off`` (no fused multiply-adds, as
  the kernels); checked to agree with ``run`` bit for bit. Skipped without a C compiler.

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
from bouncelab.export import export_surface
from bouncelab.ground import Surface, preset, run
from bouncelab.ground.surface import GRAVITY
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
#: The loop a simulator would write around the exported header: one bouncelab_run per shot.
C_LOOP = r"""
#define BOUNCELAB_API  /* external linkage: ctypes calls bouncelab_run_many */
#include "surface.h"

void bouncelab_run_many(long count, const double *v, const double *w, const double *n, double *rest,
                        double *t_rest, int *bounces) {
    for (long i = 0; i < count; i++)
        bounces[i] = bouncelab_run(v + 3 * i, w + 3 * i, n + 3 * i, rest + 3 * i, t_rest + i);
}
"""


def c_library(folder: str, surface: Surface) -> ctypes.CDLL | None:
    """The surface exported as a C header (``bouncelab.export.export_surface``) and the loop above, compiled into
    ``folder`` with ``cc -O2 -ffp-contract=off`` (None without a C compiler)."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        return None
    export_surface(surface, "c", os.path.join(folder, "surface.h"))
    src = os.path.join(folder, "loop.c")
    lib = os.path.join(folder, "libground.so")
    with open(src, "w") as f:
        f.write(C_LOOP)
    subprocess.run([cc, "-std=c99", "-O2", "-ffp-contract=off", "-fPIC", "-shared", "-o", lib, src, "-lm"],
                   check=True)
    dll = ctypes.CDLL(lib)
    dbl = ctypes.POINTER(ctypes.c_double)
    dll.bouncelab_run_many.argtypes = [ctypes.c_long, dbl, dbl, dbl, dbl, dbl, ctypes.POINTER(ctypes.c_int)]
    return dll


def c_run(dll: ctypes.CDLL, v: np.ndarray, w: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, float]:
    """Rest positions (m) from the exported C, and the seconds its loop took."""
    dbl = ctypes.POINTER(ctypes.c_double)
    v, w = np.ascontiguousarray(v, dtype=float), np.ascontiguousarray(w, dtype=float)
    n = np.ascontiguousarray(np.broadcast_to(n, v.shape), dtype=float)
    rest, t_rest = np.empty_like(v), np.empty(len(v))
    bounces = np.empty(len(v), dtype=np.intc)
    t = time.perf_counter()
    dll.bouncelab_run_many(len(v), v.ctypes.data_as(dbl), w.ctypes.data_as(dbl), n.ctypes.data_as(dbl),
                           rest.ctypes.data_as(dbl), t_rest.ctypes.data_as(dbl),
                           bounces.ctypes.data_as(ctypes.POINTER(ctypes.c_int)))
    elapsed = time.perf_counter() - t
    if (bounces < 0).any():
        raise RuntimeError(f"the exported bouncelab_run refused {int((bounces < 0).sum())} shots")
    return rest, elapsed


# ------------------------------------------------------------------------------ the benchmark
def best(f, repeats: int) -> float:
    """Median seconds of ``repeats`` calls."""
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def alternating(f, g, repeats: int) -> tuple[float, float, float]:
    """Median seconds of f and of g called in turn (f, g, f, g...), and the median of the rounds' ratios f / g: the
    two sides see the same load."""
    tf, tg = [], []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        tf.append(time.perf_counter() - t)
        tg.append(g())
    return float(np.median(tf)), float(np.median(tg)), float(np.median(np.array(tf) / np.array(tg)))


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
    folder = tempfile.TemporaryDirectory()
    dll = c_library(folder.name, surface)
    flat = np.array([0.0, 0.0, 1.0])
    t_c = t_c_slope = None
    try:
        set_num_threads(1)
        result = run(v, w, surface, units=SI)
        if dll is None:
            t_run1 = best(lambda: run(v, w, surface, units=SI), args.repeats)
            t_slope1 = best(lambda: run(v2, w, surface, normal=n2, units=SI), args.repeats)
        else:  # run and the exported C in turn, round by round
            t_run1, t_c, ratio = alternating(lambda: run(v, w, surface, units=SI),
                                             lambda: c_run(dll, v, w, flat)[1], args.repeats)
            t_slope1, t_c_slope, ratio_slope = alternating(lambda: run(v2, w, surface, normal=n2, units=SI),
                                                           lambda: c_run(dll, v2, w, n2)[1], args.repeats)
        t_side1 = best(lambda: run(vs, ws, surface, units=SI), args.repeats)
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

    if dll is not None:
        rest_c, _ = c_run(dll, v, w, flat)
        same_c = bool((rest_c == result.rest_position).all())
        err_c = float(np.abs(rest_c - result.rest_position).max() / scale)
        slope_c, _ = c_run(dll, v2, w, n2)
        same_slope = bool((slope_c == run(v2, w, surface, normal=n2, units=SI).rest_position).all())
        rows += [("exported C bouncelab_run loop (cc -O2), 1 core", t_c),
                 ("exported C on the 2 % slope, 1 core", t_c_slope)]
    folder.cleanup()

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
        print(f"ground.run (1 thread) / exported C, timed in turn (median of the rounds' ratios): {ratio:.2f}x flat, "
              f"{ratio_slope:.2f}x on the slope (target: within 3x); the exported C gives the same bits as run: flat "
              f"{same_c}, slope {same_slope} (largest difference {err_c:.1e} of the longest run)")
    else:
        print("no C compiler (cc): the C side was skipped")
    print(f"(totals: {t_totals:.3f} s; path of {sub:,} shots at 20 samples/s, {ds.sizes['time']} samples, run "
          f"included: {t_path:.2f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
