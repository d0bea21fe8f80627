"""Landings to rest with ``bouncelab.ground.run`` against the Python per-bounce loop it replaces.

Run: ``python benchmarks/bench_ground.py`` (about a minute). ``run`` takes 10^5 landings
(the paper's Table 1 ranges, any heading, some sidespin, flat ground) to rest on a preset
surface; the plain-Python side takes each shot through the same model one bounce at a
time (``law.predict`` on one landing per bounce, the 3-D lift, flights, skid and roll in
Python floats) on a subset, checked to agree with ``run``, and its time per shot is scaled
to 10^5 shots. The table prints seconds for 10^5 landings and the ratio. Target (issue 25,
item 6): ``run`` under 10 s for 10^5 landings on 2 cores. Times vary with the machine's
load: the figures are indicative unless the machine is quiet.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from bouncelab.core._parallel import num_threads
from bouncelab.ground import Surface, preset, run
from bouncelab.ground.surface import GRAVITY

R = 0.02135
SI = {"velocity": "m/s", "spin": "rad/s"}


def landings(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Velocities (m/s) and spins (rad/s) over the paper's Table 1 (both campaigns), any heading, some sidespin."""
    rng = np.random.default_rng(seed)
    speed = rng.uniform(2.0, 38.7, n)
    angle = np.radians(rng.uniform(16.4, 89.5, n))
    heading = rng.uniform(0, 2 * np.pi, n)
    back = rng.uniform(-3880, 16200, n) * 2 * np.pi / 60
    side = rng.uniform(-1000, 1000, n) * 2 * np.pi / 60
    h = np.column_stack([np.cos(heading), np.sin(heading), np.zeros(n)])
    v = speed[:, None] * (np.cos(angle)[:, None] * h + np.sin(angle)[:, None] * [0.0, 0.0, -1.0])
    axis = np.column_stack([-h[:, 1], h[:, 0], np.zeros(n)])  # n x h: spin about it is topspin, so backspin is minus
    w = -back[:, None] * axis + side[:, None] * [0.0, 0.0, 1.0]
    return v, w


# ------------------------------------------------------------------------------ the per-bounce Python loop
def python_run(v: np.ndarray, w: np.ndarray, surface: Surface, min_apex_m: float = 0.002,
               max_bounces: int = 100) -> np.ndarray:
    """Rest positions (m) of shots on flat ground, one shot and one bounce at a time (the loop ``run`` replaces)."""
    law = surface.law
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
            # the contact frame: t along the slip u = v_t + z x omega, or the velocity; travel along +t
            ux, uy = vx - wy, vy + wx
            s = math.hypot(ux, uy)
            if s == 0:
                ux, uy, s = vx, vy, math.hypot(vx, vy)
            tx, ty = (ux / s, uy / s) if s > 0 else (1.0, 0.0)
            if vx * tx + vy * ty < 0:
                tx, ty = -tx, -ty
            bx, by = -ty, tx
            p2 = np.array([[vx * tx + vy * ty, vz, -(wx * bx + wy * by)]])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                xf, zf, wf = law.predict(p2, plausible=None)[0]
            vb, wt = vx * bx + vy * by, wx * tx + wy * ty
            vx, vy, vz = xf * tx + vb * bx, xf * ty + vb * by, zf
            wx, wy, wz = wt * tx - wf * bx, wt * ty - wf * by, keep * wz
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="landings for run (default 10^5)")
    parser.add_argument("--python-n", type=int, default=2_000, help="landings for the Python loop (scaled up)")
    parser.add_argument("--surface", default="green-medium", help="preset surface (default green-medium)")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    surface = preset(args.surface)
    v, w = landings(args.n)
    run(v[:100], w[:100], surface, units=SI)  # compile (or load the cache) before timing
    times = []
    for _ in range(args.repeats):
        t = time.perf_counter()
        result = run(v, w, surface, units=SI)
        times.append(time.perf_counter() - t)
    t_run = float(np.median(times))
    t = time.perf_counter()
    totals = result.totals
    t_totals = time.perf_counter() - t
    m = min(args.python_n, args.n)
    t = time.perf_counter()
    ref = python_run(v[:m], w[:m], surface)
    t_py = (time.perf_counter() - t) * args.n / m
    err = np.abs(ref - result.rest_position[:m]).max() / np.abs(result.rest_position[:m]).max()
    n2 = np.array([0.0, 0.02, 1.0]) / math.hypot(0.02, 1.0)  # a 2 % slope: curved skids and rolls (RK4)
    v2 = v - np.outer(np.maximum(v @ n2, 0.0), n2) * 2.0  # every landing into the sloped ground
    times = []
    for _ in range(args.repeats):
        t = time.perf_counter()
        run(v2, w, surface, normal=n2, units=SI)
        times.append(time.perf_counter() - t)
    t_slope = float(np.median(times))
    sub = min(10_000, args.n)
    t = time.perf_counter()
    ds = result.sample(20.0) if sub == args.n else run(v[:sub], w[:sub], surface, units=SI, rate=20.0).path
    t_path = time.perf_counter() - t
    print(f"{args.n:,} landings to rest on {surface.name!r} (flat), {num_threads()} threads; "
          f"median of {args.repeats}; bounces per shot {totals['bounces'].mean():.2f} (max {totals['bounces'].max()})")
    print(f"{'':<44}{'seconds':>10}{'shots/s':>12}")
    print(f"{'bouncelab.ground.run':<44}{t_run:>10.2f}{args.n / t_run:>12,.0f}")
    print(f"{'bouncelab.ground.run on a 2 % slope':<44}{t_slope:>10.2f}{args.n / t_slope:>12,.0f}")
    print(f"{'Python per-bounce loop (scaled from ' + format(m, ',') + ')':<44}{t_py:>10.1f}{args.n / t_py:>12,.0f}")
    print(f"ratio (Python loop / run, flat): {t_py / t_run:.0f}x; the two agree to {err:.1e} of the longest run")
    print(f"(totals: {t_totals:.2f} s; path of {sub:,} shots at 20 samples/s, {ds.sizes['time']} samples: "
          f"{t_path:.2f} s)")


if __name__ == "__main__":
    main()
