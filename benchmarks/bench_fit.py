"""Fit time of the rigid family on one ~700-bounce campaign, against SciPy's differential evolution.

Run: ``python benchmarks/bench_fit.py`` (about 10 s; ``--quick``: 2 fits and 1 peer run per law, for CI).
For each law, bouncelab.fit (default NLopt DIRECT_L + Nelder-Mead, compiled objective) is timed over
several seeds, and ``scipy.optimize.differential_evolution(tol=1e-12, polish=True)`` on a straightforward
NumPy delta is timed in the same run on the same data and bounds. Targets (issue 3): median fit under
50 ms, at least 20x faster than the peer, at equal delta (within 1e-7).

``--baseline PATH`` instead times the same fits here and in the bouncelab at PATH (a checkout of another
version), alternating ``--rounds`` times, each in a fresh interpreter, and prints the ratios and both deltas.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
from scipy.optimize import differential_evolution

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from benchmarks import numpy_reference

LAWS = ["Rigid", "PennerVarying", "PennerFixed", "TangentialRestitution"]


_FITS = """
import json, sys, time
sys.path.insert(0, sys.argv[1])
import numpy as np
import bouncelab as bl
ds = bl.load_campaign(sys.argv[2], surrogate="published")
p0, pf = np.ascontiguousarray(ds.landing.values), np.ascontiguousarray(ds.liftoff.values)
out = {"module": bl.__file__}
for name in json.loads(sys.argv[3]):
    cls = bl.laws.registered_laws()[name]
    bl.fit(cls, (p0, pf))
    times, deltas = [], []
    for seed in range(int(sys.argv[4])):
        t = time.perf_counter(); res = bl.fit(cls, (p0, pf), seed=seed); times.append(time.perf_counter() - t)
        deltas.append(res.delta)
    out[name] = [float(np.median(times)), max(deltas)]
print(json.dumps(out))
"""


def side_by_side(baseline: str, campaign: str, seeds: int, rounds: int) -> None:
    """The same fits here and at ``baseline``, alternating fresh interpreters; medians over the rounds."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    runs: dict[str, list[dict]] = {here: [], baseline: []}
    for _ in range(rounds):
        for path in runs:
            proc = subprocess.run([sys.executable, "-c", _FITS, os.path.abspath(path), campaign, json.dumps(LAWS),
                                   str(seeds)], capture_output=True, text=True, check=True)
            result = json.loads(proc.stdout.splitlines()[-1])
            assert os.path.dirname(os.path.dirname(result["module"])) == os.path.abspath(path), result["module"]
            runs[path].append(result)
    print(f"fits on campaign {campaign}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}: this "
          f"bouncelab against {baseline} ({rounds} alternating rounds of {seeds} seeds; medians)")
    print(f"{'law':<24}{'this ms':>9}{'baseline ms':>13}{'ratio':>7}{'worst delta':>14}{'baseline':>12}")
    for name in LAWS:
        a = 1e3 * float(np.median([r[name][0] for r in runs[here]]))
        b = 1e3 * float(np.median([r[name][0] for r in runs[baseline]]))
        print(f"{name:<24}{a:>9.1f}{b:>13.1f}{b / a:>7.2f}{runs[here][0][name][1]:>14.6f}"
              f"{runs[baseline][0][name][1]:>12.6f}")


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--campaign", default="B", help="embedded campaign (B has 693 bounces)")
    ap.add_argument("--seeds", type=int, default=None, help="bouncelab fits per law (default 11; 2 with --quick)")
    ap.add_argument("--peer-seeds", type=int, default=None,
                    help="differential-evolution runs per law (default 2; 1 with --quick)")
    ap.add_argument("--baseline", help="path of another bouncelab checkout to time side by side")
    ap.add_argument("--rounds", type=int, default=None,
                    help="alternations with the baseline (default 3; 1 with --quick)")
    ap.add_argument("--quick", action="store_true", help="fewer fits: checks the benchmark runs (CI)")
    args = ap.parse_args(argv)
    quick = {"seeds": 2, "peer_seeds": 1, "rounds": 1} if args.quick else {"seeds": 11, "peer_seeds": 2, "rounds": 3}
    for key, value in quick.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.baseline:
        side_by_side(args.baseline, args.campaign, args.seeds, args.rounds)
        return []
    ds = bl.load_campaign(args.campaign, surrogate="published")
    p0 = np.ascontiguousarray(ds.landing.values)
    pf = np.ascontiguousarray(ds.liftoff.values)
    rows = []
    for name in LAWS:
        cls = bl.laws.registered_laws()[name]
        bl.fit(cls, (p0, pf))  # compile / load kernels outside the timing
        times, deltas = [], []
        for seed in range(args.seeds):
            t = time.perf_counter()
            res = bl.fit(cls, (p0, pf), seed=seed)
            times.append(time.perf_counter() - t)
            deltas.append(res.delta)
        bounds = [s.bounds for s in cls.parameter_specs]
        peer_times, peer_deltas = [], []
        for seed in range(args.peer_seeds):
            t = time.perf_counter()
            de = differential_evolution(
                lambda th, name=name: numpy_reference.delta(p0, pf, numpy_reference.predict(name, p0, th)),
                bounds, tol=1e-12, polish=True, seed=seed,
            )
            peer_times.append(time.perf_counter() - t)
            peer_deltas.append(de.fun)
        rows.append({
            "law": name, "ms": 1e3 * np.median(times), "peer_ms": 1e3 * np.median(peer_times),
            "delta": min(deltas), "worst_delta": max(deltas), "peer_delta": min(peer_deltas),
        })
    print(f"fits on campaign {args.campaign} ({len(p0)} bounces), {os.cpu_count()} cores")
    print(f"{'law':<24}{'bouncelab ms':>13}{'DE+NumPy ms':>13}{'speed-up':>10}  {'worst delta - DE delta':>24}"
          "  <50 ms  >=20x  equal delta")
    for r in rows:
        gap = r["worst_delta"] - r["peer_delta"]
        print(f"{r['law']:<24}{r['ms']:>13.1f}{r['peer_ms']:>13.0f}{r['peer_ms'] / r['ms']:>9.0f}x  {gap:>24.2e}"
              f"  {'met' if r['ms'] < 50 else 'NOT':>6}  {'met' if r['peer_ms'] / r['ms'] >= 20 else 'NOT':>5}"
              f"  {'met' if gap <= 1e-7 else 'NOT'}")
    return rows


if __name__ == "__main__":
    main()
