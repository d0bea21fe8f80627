"""A surface fitted to 5,000 launch-monitor shots with ``bouncelab.ground.fit_surface``, timed.

Run: ``python benchmarks/bench_fit_surface.py`` (a few minutes) or ``--quick`` (1,000 shots, under a
minute). Target (issue 33, item 4): the fit on 5,000 shots in under a minute on the project's
2-core machine, so that a simulator developer can fit per club and per surface.

The shots are synthetic (their rest points simulated with ``bouncelab.ground.predict_shots`` on a
known PennerFixed surface, 2 m of noise on the totals) with driver-like landings at the medians of
the issue's public export: 27.6 m/s, 37.7 degrees, 2,440 rpm at launch. Side by side in one run:

* ``ground.run`` once on all the shots (what one objective evaluation costs);
* ``fit_surface`` with its defaults (5 folds held out plus the final fit: six fits), serially;
* the same with a ``ProcessPoolExecutor`` of 2 workers (the folds in parallel; identical results).

The table gives wall seconds, the evaluations, the fit's time in units of one ``ground.run`` on all
the shots, and the ratios; for the serial fit also its CPU time (the fit runs on one core: on a
shared machine its wall time is its CPU time divided by the share of a core it got). Times vary with
the machine's load (printed): indicative unless it is quiet.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.ground import Surface, fit_surface, predict_shots

RPM = 2.0 * np.pi / 60.0
KNOWN = Surface("known", bl.PennerFixed(r=0.3, mu=0.6, beta_deg=19.0), sliding_friction=0.35, stimp_m=1.2)
DECAY, GAIN, NOISE_M = 0.04, 1.5, 2.0


def shots(n: int, seed: int = 0) -> pd.DataFrame:
    """Driver-like shots (SI units, launch spin) whose totals come from ``KNOWN``, plus noise."""
    rng = np.random.default_rng(seed)
    frame = pd.DataFrame({
        "landing_speed": rng.normal(27.6, 2.0, n), "landing_angle": np.radians(rng.normal(37.7, 3.0, n)),
        "spin": rng.normal(2440.0, 500.0, n) * RPM, "spin_axis": np.radians(rng.normal(0.0, 8.0, n)),
        "launch_angle": np.radians(rng.normal(12.0, 2.0, n)),
        "carry": rng.normal(230.0, 20.0, n), "side": rng.normal(0.0, 15.0, n),
        "flight_time": rng.normal(6.5, 0.4, n), "club": np.where(rng.random(n) < 0.5, "Driver", "3 Wood")})
    frame.attrs["spin_at"] = "launch"
    rest = predict_shots(frame, KNOWN, spin_decay=DECAY, heading_gain=GAIN)
    frame["total"] = rest["total"] + rng.normal(0.0, NOISE_M, n)
    frame["side_total"] = rest["side_total"]
    return frame


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="1,000 shots instead of 5,000")
    parser.add_argument("--shots", type=int, default=None, help="number of shots (default 5,000; 1,000 with --quick)")
    parser.add_argument("--no-pool", action="store_true", help="skip the ProcessPoolExecutor run")
    args = parser.parse_args(argv)
    n = args.shots or (1000 if args.quick else 5000)
    data = shots(n)
    predict_shots(data.head(20), KNOWN, spin_decay=DECAY, heading_gain=GAIN)  # compile (or load) the kernels
    print(f"{n} driver-like shots, median roll {np.median(data['total'] - data['carry']):.1f} m, noise {NOISE_M} m; "
          f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")

    t = time.perf_counter()
    reps = 5
    for _ in range(reps):
        predict_shots(data, KNOWN, spin_decay=DECAY, heading_gain=GAIN)
    one_run = (time.perf_counter() - t) / reps

    t, cpu = time.perf_counter(), time.process_time()
    serial = fit_surface(data, seed=0)
    t_serial, cpu_serial = time.perf_counter() - t, time.process_time() - cpu
    rows = [("ground.run on all shots (one evaluation)", one_run, 1, ""),
            ("fit_surface, serial (5 folds + final)", t_serial, serial.n_evaluations,
             f"CPU {cpu_serial:.1f} s ({cpu_serial / t_serial:.0%} of a core)")]
    if not args.no_pool:
        with ProcessPoolExecutor(2) as pool:
            t = time.perf_counter()
            pooled = fit_surface(data, seed=0, executor=pool)
            t_pool = time.perf_counter() - t
        same = pooled.params.valuesdict() == serial.params.valuesdict() and pooled.heldout.equals(serial.heldout)
        rows.append(("fit_surface, ProcessPoolExecutor(2)", t_pool, pooled.n_evaluations,
                     f"{t_serial / t_pool:.2f}x serial; identical: {same}"))
    print(f"\n{'':<44}{'seconds':>9}{'evaluations':>13}{'in runs':>9}  ratio")
    for name, sec, evals, note in rows:
        print(f"{name:<44}{sec:>9.2f}{evals:>13}{sec / one_run:>9.0f}  {note}")
    e = serial.errors.loc["all"]
    print(f"\nheld-out median |roll error| {e['median_abs_error']:.2f} m (median |noise| "
          f"{0.6745 * NOISE_M:.2f} m expected), target: the fit on 5,000 shots under 60 s -> serial "
          f"{t_serial:.1f} s ({t_serial / 60:.2f} of the target; its CPU time {cpu_serial:.1f} s)")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
