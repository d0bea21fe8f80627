"""Time of ``bouncelab.assess`` and ``bouncelab.calibrate`` on a 693-bounce campaign, beside the plain fit.

Run: ``python benchmarks/bench_assess.py`` (about a minute without TurfContact's calibration; add
``--turf`` for it, which takes about a quarter of an hour). Issue 24's targets, on 2 cores:

* ``assess`` of a rigid-family law (default Rigid, with assess's default counts: 5 folds,
  100 bootstrap resamples, 4 global starts, profiles of 11 + 2 x 3 points per parameter) under 10 s;
* ``calibrate`` of a rigid-family law (default Rigid, ``vary=["r", "mu"]``, run until converged)
  under 2 minutes;
* ``calibrate`` of TurfContact (``vary=["mu", "lam"]``) under 20 minutes: one chain, its walkers
  shared by the threads of the process (``--chains N`` with ``--workers`` runs N chains on the dask
  workers instead; each chain still needs the full length, so that does not shorten the run).

Each row prints the time of the plain ``bouncelab.fit`` of the same law on the same data. The
compiled kernels are loaded before any timing (one small fit). ``--workers N`` also times
``assess`` on a ``LocalCluster`` of N one-thread worker processes (the start-up of the cluster is
outside the timing; the result is checked equal to the serial one). The machine's load average is
printed before and after: on a shared machine other jobs slow every figure.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "critical")
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.fitting.hierarchical import ConvergenceWarning


def _load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def _warm_up(law: str, campaign: str, surrogate: str) -> None:
    ds = bl.load_campaign(campaign, surrogate=surrogate)
    bl.fit(law, ds.isel(bounce=slice(0, 40)), maxeval=20)


def _timed(f, *args, **kwargs):
    t = time.perf_counter()
    out = f(*args, **kwargs)
    return time.perf_counter() - t, out


def _client(workers: int):
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    return cluster, Client(cluster)


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--campaign", default="B", help="embedded campaign (B has 693 bounces)")
    ap.add_argument("--surrogate", default="turf", help="embedded surrogate: turf (default) or published")
    ap.add_argument("--assess-law", default="Rigid", help="rigid-family law to assess")
    ap.add_argument("--calibrate-law", default="Rigid", help="rigid-family law to calibrate (vary r and mu)")
    ap.add_argument("--workers", type=int, default=0,
                    help="also time assess on a LocalCluster of this many workers (and --chains on it)")
    ap.add_argument("--turf", action="store_true", help="also calibrate TurfContact (about 15 minutes)")
    ap.add_argument("--turf-vary", nargs="+", default=["mu", "lam"], help="TurfContact parameters that vary")
    ap.add_argument("--chains", type=int, default=None,
                    help="TurfContact's chains (default 1; with --workers they run on the cluster)")
    args = ap.parse_args(argv)

    ds = bl.load_campaign(args.campaign, surrogate=args.surrogate)
    n = ds.sizes["bounce"]
    print(f"campaign {args.campaign} ({args.surrogate} surrogate, SYNTHETIC), {n} bounces; "
          f"{os.cpu_count()} CPUs; load average before: {_load()}", flush=True)
    rows: list[dict] = []
    for law in {args.assess_law, args.calibrate_law, *(["TurfContact"] if args.turf else [])}:
        _warm_up(law, args.campaign, args.surrogate)

    # assess
    fit_s, _ = _timed(bl.fit, args.assess_law, ds)
    secs, result = _timed(bl.assess, args.assess_law, ds, seed=0)
    rows.append({"task": f"assess {args.assess_law}", "s": secs, "fit_s": fit_s, "target_s": 10.0,
                 "note": ", ".join(f"{k}: {v}" for k, v in result.verdicts.items())})
    print(f"  assess {args.assess_law}: {secs:.1f} s (plain fit {fit_s:.3f} s)", flush=True)
    cluster = client = None
    if args.workers:
        cluster, client = _client(args.workers)
        client.run(_warm_up, args.assess_law, args.campaign, args.surrogate)
        bl.assess(args.assess_law, ds, n_bootstrap=4, starts=1, profile_points=3, local_points=0, client=client)
        secs_c, remote = _timed(bl.assess, args.assess_law, ds, seed=0, client=client)
        same = remote.parameters.equals(result.parameters) and remote.profiles.equals(result.profiles)
        rows.append({"task": f"assess {args.assess_law}, {args.workers} workers", "s": secs_c, "fit_s": fit_s,
                     "target_s": 10.0, "note": "same result as serial" if same else "DIFFERS from serial"})
        print(f"  assess {args.assess_law} on {args.workers} workers: {secs_c:.1f} s", flush=True)

    # calibrate, rigid family
    fit_s, _ = _timed(bl.fit, args.calibrate_law, ds)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", bl.errors.BouncelabWarning)
        secs, post = _timed(bl.calibrate, args.calibrate_law, ds, vary=["r", "mu"], seed=0)
    unconverged = any(issubclass(w.category, ConvergenceWarning) for w in caught)
    d = post.diagnostics
    rows.append({"task": f"calibrate {args.calibrate_law} (vary r, mu)", "s": secs, "fit_s": fit_s, "target_s": 120.0,
                 "note": f"{'converged' if post.converged and not unconverged else 'NOT converged'}; "
                         f"{d['walkers']} walkers x {d['steps']} steps, acceptance {d['acceptance']:.2f}, "
                         f"max autocorrelation {max(d['autocorr']):.0f}, max R-hat {max(d['rhat']):.3f}"})
    print(f"  calibrate {args.calibrate_law}: {secs:.1f} s, {rows[-1]['note']}", flush=True)

    # calibrate, TurfContact
    if args.turf:
        fit_s, _ = _timed(bl.fit, bl.TurfContact, ds)
        chains = args.chains or 1
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", bl.errors.BouncelabWarning)
            secs, post = _timed(bl.calibrate, bl.TurfContact, ds, vary=args.turf_vary, seed=0, chains=chains,
                                client=client if args.chains else None)
        d = post.diagnostics
        where = f"{chains} chain(s)" + (f" on {args.workers} workers" if client is not None and args.chains
                                         else f", walkers on {bl.laws.num_threads()} threads")
        rows.append({"task": f"calibrate TurfContact (vary {', '.join(args.turf_vary)})", "s": secs, "fit_s": fit_s,
                     "target_s": 1200.0,
                     "note": f"{'converged' if post.converged else 'NOT converged: ' + d['reason']}; {where}; "
                             f"{d['walkers']} walkers x {d['steps']} steps, acceptance {d['acceptance']:.2f}, "
                             f"max autocorrelation {max(d['autocorr']):.0f}, max R-hat {max(d['rhat']):.3f}"})
        print(f"  calibrate TurfContact: {secs:.0f} s, {rows[-1]['note']}", flush=True)
        print(post.report(), flush=True)
    if client is not None:
        client.close()
        cluster.close()

    print(f"\nload average after: {_load()}")
    print("| task | time, s | target, s | met | plain fit, s | |\n|---|---:|---:|---|---:|---|")
    for r in rows:
        met = "yes" if r["s"] <= r["target_s"] else "NO"
        print(f"| {r['task']} | {r['s']:.1f} | {r['target_s']:.0f} | {met} | {r['fit_s']:.3f} | {r['note']} |")
    return rows


if __name__ == "__main__":
    main()
