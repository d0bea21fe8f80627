"""Fit time of the rigid family on one ~700-bounce campaign, against SciPy's differential evolution.

Run: ``python benchmarks/bench_fit.py`` (about 10 s). For each law, bouncelab.fit (default
NLopt DIRECT_L + Nelder-Mead, compiled objective) is timed over several seeds, and
``scipy.optimize.differential_evolution(tol=1e-12, polish=True)`` on a straightforward NumPy
delta is timed in the same run on the same data and bounds. Targets (issue 3): median fit under
50 ms, at least 20x faster than the peer, at equal delta (within 1e-7).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.optimize import differential_evolution

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from benchmarks import numpy_reference

LAWS = ("Rigid", "PennerVarying", "PennerFixed", "TangentialRestitution")


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--campaign", default="B", help="embedded campaign (B has 693 bounces)")
    ap.add_argument("--seeds", type=int, default=11, help="bouncelab fits per law")
    ap.add_argument("--peer-seeds", type=int, default=2, help="differential-evolution runs per law")
    args = ap.parse_args(argv)
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
