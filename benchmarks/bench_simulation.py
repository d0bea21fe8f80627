"""Time to simulate a campaign (693 bounces, campaign B), and its measurement against the library's
one-bounce estimator.

Run: ``python benchmarks/bench_simulation.py`` (``--quick``: one timing of each, for CI). Times
``simulate_campaign`` on the paper's design of campaign B (launch, turf, filming, measurement), then, on the
same frames, the vectorised ``bouncelab.simulation.measure_frames`` against
``bouncelab.analysis.measurement.measure_bounce`` called once per bounce (the peer: same estimators, one bounce
at a time), prints the ratio and checks that the two give the same states and intervals.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.analysis.measurement import measure_bounce
from bouncelab.simulation import Camera, LogNormal, Normal, Turf, measure_frames, simulate_campaign


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--campaign", default="B")
    ap.add_argument("--repeats", type=int, default=None, help="seeds timed (default 5; 1 with --quick)")
    ap.add_argument("--quick", action="store_true", help="one timing of each: checks the benchmark runs (CI)")
    args = ap.parse_args(argv)
    args.repeats = args.repeats or (1 if args.quick else 5)
    turf = Turf(bl.TangentialRestitution(r=0.3, mu=0.6, e_t=0.3),
                {"r": LogNormal(0.15), "mu": LogNormal(0.2), "e_t": Normal(0.1)})
    simulate_campaign(args.campaign, turf, seed=0)  # compile the kernel loop outside the timing
    times = []
    for seed in range(args.repeats):
        start = time.perf_counter()
        ds = simulate_campaign(args.campaign, turf, seed=seed)
        times.append(time.perf_counter() - start)
    n = ds.sizes["bounce"]
    print(f"simulate_campaign({args.campaign!r}): {n} bounces, median {np.median(times):.3f} s "
          f"(min {min(times):.3f}, max {max(times):.3f}) over {args.repeats} seeds")

    frames = Camera().film(ds["true_landing"].values, ds["true_liftoff"].values, ds["contact_time"].values,
                           np.random.default_rng(0))
    start = time.perf_counter()
    m = measure_frames(frames)
    t_vec = time.perf_counter() - start
    start = time.perf_counter()
    refs = [measure_bounce(frames.track(i)) for i in range(n)]
    t_peer = time.perf_counter() - start
    # the same numbers: every bounce measure_frames measured, state and interval, against measure_bounce's
    worst = max(float(np.abs(getattr(m, key)[i] - ref[key].values).max() / np.abs(ref[key].values).max())
                for i, ref in enumerate(refs) if m.ok[i] for key in ("landing", "liftoff", "landing_pi", "liftoff_pi"))
    print(f"measurement of {n} bounces: measure_frames {t_vec:.3f} s, measure_bounce per bounce {t_peer:.3f} s "
          f"(ratio {t_peer / t_vec:.1f}x); {int(m.ok.sum())} measured by both, largest relative difference "
          f"{worst:.1e}")
    return {"simulate_s": float(np.median(times)), "measure_frames_s": t_vec, "measure_bounce_s": t_peer,
            "largest_difference": worst}


if __name__ == "__main__":
    main()
