"""Throughput of ``predict`` for the rigid family on 10^6 bounces, against plain NumPy.

Run: ``python benchmarks/bench_predict.py`` (about 20 s). Both sides are timed in the same
run on the same landings; the table gives million bounces per second (median of repeats)
and the ratio. Target (issue 3): at least 50 million bounces/s for every rigid-family law.

``--baseline PATH`` also times the bouncelab found at PATH (a checkout of another version, whose
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


_BASELINE = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np, bouncelab as bl
assert bl.__file__.startswith(sys.argv[1]), bl.__file__
rng = np.random.default_rng(0)
n = int(sys.argv[2])
xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
p = np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])
laws = {"Rigid": bl.Rigid(r=0.544, mu=0.997), "PennerFixed": bl.PennerFixed(r=0.42, mu=0.852, beta_deg=12.9),
        "PennerVarying": bl.PennerVarying(r=0.448, mu=0.969, k_p=1.543e-4),
        "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3)}
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


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--baseline", help="path of another bouncelab checkout to time side by side")
    ap.add_argument("--rounds", type=int, default=3, help="alternations with the baseline")
    args = ap.parse_args(argv)
    if args.baseline:
        ours: dict[str, list[float]] = {name: [] for name in LAWS}
        theirs: dict[str, list[float]] = {name: [] for name in LAWS}
        p = landings(args.n)
        for law in LAWS.values():
            law[0].predict(p)
        for _ in range(args.rounds):
            for name, (law, _) in LAWS.items():
                ours[name].append(args.n / best_of(lambda law=law: law.predict(p), args.repeats) / 1e6)
            for name, value in baseline_rounds(args.baseline, args.n, args.repeats).items():
                theirs[name].append(value)
        print(f"predict on {args.n:,} bounces, {os.cpu_count()} cores: this bouncelab against {args.baseline} "
              f"({args.rounds} alternating rounds; million bounces per second, medians)")
        print(f"{'law':<24}{'this':>10}{'baseline':>10}{'ratio':>8}  >= 0.9")
        rows = []
        for name in LAWS:
            a, b = float(np.median(ours[name])), float(np.median(theirs[name]))
            rows.append({"law": name, "bouncelab": a, "baseline": b})
            print(f"{name:<24}{a:>10.1f}{b:>10.1f}{a / b:>8.2f}  {'met' if a / b >= 0.9 else 'NOT'}")
        return rows
    p = landings(args.n)
    rows = []
    for name, (law, theta) in LAWS.items():
        law.predict(p)  # compile or load the kernel, start the thread pool and touch the memory first
        ours = best_of(lambda law=law: law.predict(p), args.repeats)
        peer = best_of(lambda name=name, theta=theta: numpy_reference.predict(name, p, theta),
                       max(3, args.repeats // 3))
        same = np.allclose(law.predict(p), numpy_reference.predict(name, p, theta), rtol=1e-10, atol=1e-8)
        rows.append({"law": name, "bouncelab": args.n / ours / 1e6, "numpy": args.n / peer / 1e6, "agree": same})
    print(f"predict on {args.n:,} bounces, {os.cpu_count()} cores (million bounces per second, median)")
    print(f"{'law':<24}{'bouncelab':>12}{'NumPy':>10}{'ratio':>9}  target >= 50  results agree")
    for r in rows:
        ok = "met" if r["bouncelab"] >= 50 else "NOT MET"
        print(f"{r['law']:<24}{r['bouncelab']:>12.1f}{r['numpy']:>10.1f}{r['bouncelab'] / r['numpy']:>8.1f}x  "
              f"{ok:<12} {r['agree']}")
    return rows


if __name__ == "__main__":
    main()
