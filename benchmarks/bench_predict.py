"""Throughput of ``predict`` on 10^6 bounces: against plain NumPy, the unit guard's cost, and PiecewiseAffine
against a hand-written numba loop.

Run: ``python benchmarks/bench_predict.py`` (about 30 s; ``--quick``: 10^5 bounces, a few seconds, for CI).
Everything is timed in the same run on the same landings, as medians of repeated timings, and reported as
ratios:

1. million bounces per second of ``predict`` for the rigid family against straightforward NumPy
   (``benchmarks/numpy_reference.py``). Target (issue 3): at least 50 million bounces/s for every
   rigid-family law.
2. the unit guard: ``predict`` (every landing held to ``PLAUSIBLE_RANGES``) against
   ``predict(plausible=None)``, alternating. Target (issue 31): at most 1.25x.
3. ``PiecewiseAffine.predict`` (unit guard and value checks included) against a hand-written numba loop
   over the same two affine maps (one thread, no checks), with identical results. Target (issue 34): within
   2x.

``--baseline PATH`` instead times the bouncelab found at PATH (a checkout of another version, whose
``bouncelab`` package is imported from there in a subprocess) on the same landings, alternating
with this one ``--rounds`` times, and prints this version's throughput as a ratio of it (issue 7's
target: at least 0.9 of bouncelab 0.1's).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from benchmarks import numpy_reference

LAWS = {
    "Rigid": (bl.Rigid(r=0.544, mu=0.997), (0.544, 0.997)),
    "PennerFixed": (bl.PennerFixed(r=0.42, mu=0.852, beta_deg=12.9), (0.42, 0.852, 12.9)),
    "PennerVarying": (bl.PennerVarying(r=0.448, mu=0.969, k_p=1.543e-4), (0.448, 0.969, 1.543e-4)),
    "TangentialRestitution": (bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3), (0.5, 0.4, 0.3)),
}


def piecewise_law() -> bl.PiecewiseAffine:
    """The published law A's maps with the plane moved by 1 rad/s: a law like any fitted one (the published
    laws also check every prediction for non-physical lift-offs, and warn)."""
    return bl.PiecewiseAffine.published("A").replace(offset=601.0)


def landings(n: int, seed: int = 0) -> np.ndarray:
    """Landings spanning the paper's Table 1 (both campaigns), in scaled units: golf landings, which predict's
    unit guard accepts (the flattest come in at 5.5 degrees: xdot0 is capped at |ydot0| / tan 5.5 deg)."""
    rng = np.random.default_rng(seed)
    xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
    return np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])


def best_of(f, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def alternating(fs: dict, repeats: int) -> dict[str, float]:
    """Median seconds of each function, timed in turn (one call of each per round), so that a machine whose
    load changes during the run weighs on every side alike."""
    times: dict[str, list[float]] = {name: [] for name in fs}
    for _ in range(repeats):
        for name, f in fs.items():
            t = time.perf_counter()
            f()
            times[name].append(time.perf_counter() - t)
    return {name: float(np.median(ts)) for name, ts in times.items()}


def hand_written_piecewise():
    """The piecewise-affine map as one would write it by hand in numba: a plain loop, no checks, one thread."""
    from numba import njit

    @njit(nogil=True, cache=False)
    def run(P, normal, offset, A1, b1, A2, b2, out):
        for i in range(P.shape[0]):
            x, y, w = P[i, 0], P[i, 1], P[i, 2]
            if normal[0] * x + normal[1] * y + normal[2] * w < offset:
                A, b = A1, b1
            else:
                A, b = A2, b2
            out[i, 0] = A[0, 0] * x + A[0, 1] * y + A[0, 2] * w + b[0]
            out[i, 1] = A[1, 0] * x + A[1, 1] * y + A[1, 2] * w + b[1]
            out[i, 2] = A[2, 0] * x + A[2, 1] * y + A[2, 2] * w + b[2]
        return out

    return run


_BASELINE = r"""
import json, sys, time, warnings
sys.path.insert(0, sys.argv[1])
import numpy as np, bouncelab as bl
assert bl.__file__.startswith(sys.argv[1]), bl.__file__
rng = np.random.default_rng(0)
n = int(sys.argv[2])
xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
p = np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])
laws = {"Rigid": bl.Rigid(r=0.544, mu=0.997), "PennerFixed": bl.PennerFixed(r=0.42, mu=0.852, beta_deg=12.9),
        "PennerVarying": bl.PennerVarying(r=0.448, mu=0.969, k_p=1.543e-4),
        "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3),
        "PiecewiseAffine": bl.PiecewiseAffine.published("A").replace(offset=601.0)}
out = {}
for name, law in laws.items():
    law.predict(p)
    ts = []
    for _ in range(int(sys.argv[3])):
        t = time.perf_counter(); law.predict(p); ts.append(time.perf_counter() - t)
    out[name] = n / float(np.median(ts)) / 1e6
print(json.dumps(out))
"""


def baseline_rounds(path: str, n: int, repeats: int) -> dict[str, float]:
    """Throughput of the bouncelab at ``path`` (million bounces/s), in a fresh interpreter."""
    import json
    import subprocess

    proc = subprocess.run([sys.executable, "-c", _BASELINE, os.path.abspath(path), str(n), str(repeats)],
                          capture_output=True, text=True, check=True)
    return json.loads(proc.stdout)


def side_by_side(path: str, n: int, repeats: int, rounds: int) -> list[dict]:
    """This bouncelab's throughput against the one at ``path``, alternating rounds (``--baseline``)."""
    laws = {name: law for name, (law, _) in LAWS.items()} | {"PiecewiseAffine": piecewise_law()}
    ours: dict[str, list[float]] = {name: [] for name in laws}
    theirs: dict[str, list[float]] = {name: [] for name in laws}
    p = landings(n)
    for law in laws.values():
        law.predict(p)
    for _ in range(rounds):
        for name, law in laws.items():
            ours[name].append(n / best_of(lambda law=law: law.predict(p), repeats) / 1e6)
        for name, value in baseline_rounds(path, n, repeats).items():
            theirs[name].append(value)
    print(f"predict on {n:,} bounces, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}: this "
          f"bouncelab against {path} ({rounds} alternating rounds; million bounces per second, medians)")
    print(f"{'law':<24}{'this':>10}{'baseline':>10}{'ratio':>8}  >= 0.9")
    rows = []
    for name in laws:
        a, b = float(np.median(ours[name])), float(np.median(theirs[name]))
        rows.append({"law": name, "bouncelab": a, "baseline": b})
        print(f"{name:<24}{a:>10.1f}{b:>10.1f}{a / b:>8.2f}  {'met' if a / b >= 0.9 else 'NOT'}")
    return rows


def main(argv: list[str] | None = None) -> dict[str, list[dict]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=None, help="bounces (default 10^6; 10^5 with --quick)")
    ap.add_argument("--repeats", type=int, default=None, help="timings per measure (default 15; 3 with --quick)")
    ap.add_argument("--quick", action="store_true", help="a small run that checks the benchmark works (CI)")
    ap.add_argument("--baseline", help="path of another bouncelab checkout to time side by side")
    ap.add_argument("--rounds", type=int, default=3, help="alternations with the baseline")
    args = ap.parse_args(argv)
    n = args.n or (100_000 if args.quick else 1_000_000)
    repeats = args.repeats or (3 if args.quick else 15)
    if args.baseline:
        return {"baseline": side_by_side(args.baseline, n, repeats, 1 if args.quick else args.rounds)}
    p = landings(n)
    print(f"predict on {n:,} bounces, {bl.laws.num_threads()} threads, {os.cpu_count()} CPUs, load average "
          f"{os.getloadavg()[0]:.2f} (medians of {repeats} timings)")

    # ---- 1. against NumPy
    rows = []
    for name, (law, theta) in LAWS.items():
        law.predict(p)  # compile or load the kernel, start the thread pool and touch the memory first
        ours = best_of(lambda law=law: law.predict(p), repeats)
        peer = best_of(lambda name=name, theta=theta: numpy_reference.predict(name, p, theta), max(3, repeats // 3))
        same = np.allclose(law.predict(p), numpy_reference.predict(name, p, theta), rtol=1e-10, atol=1e-8)
        rows.append({"law": name, "bouncelab": n / ours / 1e6, "numpy": n / peer / 1e6, "agree": same})
    print(f"\n1. against NumPy (million bounces per second)\n{'law':<24}{'bouncelab':>12}{'NumPy':>10}{'ratio':>9}"
          "  target >= 50  results agree")
    for r in rows:
        ok = "met" if r["bouncelab"] >= 50 else "NOT MET"
        print(f"{r['law']:<24}{r['bouncelab']:>12.1f}{r['numpy']:>10.1f}{r['bouncelab'] / r['numpy']:>8.1f}x  "
              f"{ok:<12} {r['agree']}")

    # ---- 2. the unit guard's cost
    guard = []
    laws = {name: law for name, (law, _) in LAWS.items()} | {"PiecewiseAffine": piecewise_law()}
    for name, law in laws.items():
        law.predict(p)
        t = alternating({"guarded": lambda law=law: law.predict(p),
                         "unguarded": lambda law=law: law.predict(p, plausible=None)}, repeats)
        guard.append({"law": name, **t})
    print("\n2. the unit guard: predict(p) against predict(p, plausible=None), alternating (ms)")
    print(f"{'law':<24}{'guarded':>10}{'unguarded':>11}{'ratio':>8}  <= 1.25")
    for r in guard:
        ratio = r["guarded"] / r["unguarded"]
        print(f"{r['law']:<24}{r['guarded'] * 1e3:>10.2f}{r['unguarded'] * 1e3:>11.2f}{ratio:>8.2f}  "
              f"{'met' if ratio <= 1.25 else 'NOT'}")

    # ---- 3. PiecewiseAffine against a hand-written numba loop
    law = piecewise_law()
    hand = hand_written_piecewise()
    args = tuple(np.ascontiguousarray(v, dtype=np.float64) if isinstance(v, np.ndarray) else float(v)
                 for v in (law.normal, law.offset, law.A1, law.b1, law.A2, law.b2))
    out = np.empty_like(p)
    hand(p, *args, out)  # compile outside the timing
    same = np.array_equal(law.predict(p), hand(p, *args, np.empty_like(p)))
    threads = bl.laws.num_threads()

    def one_thread():  # the hand-written loop's footing: bouncelab on one thread too
        bl.laws.set_num_threads(1)
        try:
            law.predict(p)
        finally:
            bl.laws.set_num_threads(threads)

    t = alternating({"bouncelab": lambda: law.predict(p), "bouncelab_1": one_thread,
                     "numba": lambda: hand(p, *args, out)}, repeats)
    ratio, ratio_1 = t["bouncelab"] / t["numba"], t["bouncelab_1"] / t["numba"]
    print("\n3. PiecewiseAffine.predict (guard and checks) against a hand-written numba loop (one thread, no checks)")
    print(f"   bouncelab {threads} threads {t['bouncelab'] * 1e3:.2f} ms, 1 thread {t['bouncelab_1'] * 1e3:.2f} ms, "
          f"hand-written {t['numba'] * 1e3:.2f} ms: ratio {ratio:.2f} ({threads} threads), {ratio_1:.2f} (1 thread)  "
          f"<= 2: {'met' if ratio <= 2 else 'NOT'} ({threads} threads), {'met' if ratio_1 <= 2 else 'NOT'} (1 thread); "
          f"identical results: {same}")
    return {"numpy": rows, "guard": guard, "piecewise": [{"ratio": ratio, "ratio_one_thread": ratio_1,
                                                          "identical": same, **t}]}


if __name__ == "__main__":
    main()
