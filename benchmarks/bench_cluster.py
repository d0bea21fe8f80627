"""Bootstrap time serial vs a two-worker dask cluster, and a check that both give the same numbers.

Run: ``python benchmarks/bench_cluster.py`` (about a minute; needs the ``cluster`` extra; ``--quick`` for a short
check that the script runs). The
bootstrap of one law on an embedded campaign is timed serially and on a ``LocalCluster`` of two
worker processes with one thread each (the code is the same on a real cluster: pass its
``Client``). Cluster start-up and the workers' first load of the compiled laws are outside the
timing (a short warm-up bootstrap runs first); the ratio is serial time / cluster time. The peer,
the standard library's ``ProcessPoolExecutor`` with as many processes, is timed in the same run;
the machine's load average is printed, since other jobs on a shared machine slow the workers.
Every run's resamples must be bit-identical to the serial ones.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

# Quiet the workers' logs (closing a cluster logs lost heartbeats); read by the worker processes at start.
os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "critical")
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl


def _warm_up(law: str, campaign: str) -> None:
    bl.bootstrap(bl.laws.registered_laws()[law], bl.load_campaign(campaign, surrogate="published"), n=2)


def _on_cluster(law, ds, args):
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        client.run(_warm_up, args.law, args.campaign)  # every worker loads the compiled kernels
        bl.bootstrap(law, ds, n=4 * args.workers, executor=client)
        t = time.perf_counter()
        result = bl.bootstrap(law, ds, n=args.n, seed=1, executor=client)
        return time.perf_counter() - t, result


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--law", default="PennerFixed", help="law to bootstrap (default PennerFixed)")
    ap.add_argument("--campaign", default="B", help="embedded campaign (B has 693 bounces)")
    ap.add_argument("-n", type=int, default=200, help="resamples (default 200)")
    ap.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--quick", action="store_true",
                    help="8 resamples of Rigid on campaign A: a check that the script runs (CI); measures nothing")
    args = ap.parse_args(argv)
    if args.quick:
        args.law, args.campaign, args.n = "Rigid", "A", 8
    load0 = os.getloadavg()[0]
    ds = bl.load_campaign(args.campaign, surrogate="published")
    law = bl.laws.registered_laws()[args.law]
    bl.bootstrap(law, ds, n=2)  # compile / load the kernels here outside the timing
    t = time.perf_counter()
    serial = bl.bootstrap(law, ds, n=args.n, seed=1)
    t_serial = time.perf_counter() - t
    t_cluster, remote = _on_cluster(law, ds, args)
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(args.workers) as pool:  # the peer: the standard library's process pool
        list(pool.map(_warm_up, [args.law] * args.workers, [args.campaign] * args.workers))
        t = time.perf_counter()
        pooled = bl.bootstrap(law, ds, n=args.n, seed=1, executor=pool)
        t_pool = time.perf_counter() - t
    same = all(r.samples.equals(serial.samples) and r.estimate == serial.estimate
               for r in (remote, pooled))
    print(f"bootstrap of {args.law} on campaign {args.campaign} ({ds.sizes['bounce']} bounces), {args.n} resamples "
          f"by setting, on {os.cpu_count()} CPUs")
    w = args.workers
    for label, value in (("serial", f"{t_serial:.2f} s"),
                         (f"LocalCluster, {w} worker processes", f"{t_cluster:.2f} s"),
                         (f"ProcessPoolExecutor, {w} processes", f"{t_pool:.2f} s"),
                         ("ratio serial / cluster", f"{t_serial / t_cluster:.2f}x"),
                         ("ratio serial / process pool", f"{t_serial / t_pool:.2f}x"),
                         ("load average (1 min), start / end", f"{load0:.1f} / {os.getloadavg()[0]:.1f}")):
        print(f"  {label:<36} {value:>8}")
    print(f"  {'identical resamples':<36} {same!s:>8}")
    if not same:
        raise SystemExit("the cluster's bootstrap differs from the serial one")
    return {"serial_s": t_serial, "cluster_s": t_cluster, "pool_s": t_pool, "ratio": t_serial / t_cluster,
            "identical": same}


if __name__ == "__main__":
    main()
