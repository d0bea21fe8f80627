"""Time of ``bouncelab.assess`` and ``bouncelab.calibrate`` on a 693-bounce campaign, beside the plain fit; and the
coverage of ``calibrate``'s default intervals on campaigns from a known process.

Run: ``python benchmarks/bench_assess.py`` (a few minutes without TurfContact's calibration; add
``--turf`` for it, issue 30's target 20 minutes; ``--quick`` for a short check that the script runs). Issue 24's
targets, on 2 cores:

* ``assess`` of a rigid-family law (default Rigid, with assess's default counts: 5 folds,
  100 bootstrap resamples, 4 global starts, profiles of 11 + 2 x 3 points per parameter) under 10 s;
* ``calibrate`` of a rigid-family law (default Rigid, ``vary=["r", "mu"]``, run until converged)
  under 2 minutes;
* ``calibrate`` of TurfContact (``vary=["mu", "lam"]``) under 20 minutes: one chain, its walkers
  evaluated in one batched law call whose rows the threads of the process share (``--chains N`` with
  ``--workers`` runs N chains on the dask workers instead; each chain still needs the full length, so that
  does not shorten the run).

``--coverage`` measures issue 30's done-when instead: Rigid with r and mu drawn per launcher setting (the
repeats of a setting share its spot; 100 settings x 6 repeats, both regimes, known measurement noise), with and
without interval columns; ``calibrate(vary=["r", "mu"])`` with defaults; the error of the population medians and
the share of fresh measured bounces on new spots (``--fresh`` 10 fresh campaigns of 200 new settings x 6: 12,000
bounces; over single campaigns of 1,200 the share ranges up to 0.05) inside the default 95 % intervals, per
component, over the bounces and averaged over the fresh settings, and whether ``check()`` gives the same shares.

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


def _timed_cpu(f, *args, **kwargs):
    """Wall time, this process's CPU time (all its threads) and the result: on a shared machine the CPU time says
    what the work cost, the wall time what it took beside the other jobs."""
    t, c = time.perf_counter(), time.process_time()
    out = f(*args, **kwargs)
    return time.perf_counter() - t, time.process_time() - c, out


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
    ap.add_argument("--coverage", action="store_true",
                    help="measure the coverage of calibrate's default intervals on known campaigns instead")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1], help="campaign seeds of --coverage")
    ap.add_argument("--settings", type=int, default=100, help="launcher settings of --coverage's campaigns")
    ap.add_argument("--fresh", type=int, default=10,
                    help="fresh campaigns (each twice --settings new settings x 6) a coverage is measured on")
    ap.add_argument("--profile", action="store_true",
                    help="with --coverage: where the brute-force likelihood of each campaign puts mu's median, and "
                         "how sharply (what any estimator can do on it)")
    ap.add_argument("--quick", action="store_true", help="small counts: a check that the script runs (CI)")
    args = ap.parse_args(argv)
    if args.coverage:
        settings = 10 if args.quick else args.settings
        if args.profile:
            likelihood_profile(args.seeds, settings)
        return coverage(args.seeds, settings, fresh=1 if args.quick else args.fresh, quick=args.quick)
    quick = {"n_bootstrap": 40, "starts": 1, "profile_points": 3, "local_points": 0} if args.quick else {}
    if args.quick:
        args.turf = False

    ds = bl.load_campaign(args.campaign, surrogate=args.surrogate)
    n = ds.sizes["bounce"]
    print(f"campaign {args.campaign} ({args.surrogate} surrogate, SYNTHETIC), {n} bounces; "
          f"{os.cpu_count()} CPUs; load average before: {_load()}", flush=True)
    rows: list[dict] = []
    for law in {args.assess_law, args.calibrate_law, *(["TurfContact"] if args.turf else [])}:
        _warm_up(law, args.campaign, args.surrogate)

    # assess
    fit_s, _ = _timed(bl.fit, args.assess_law, ds)
    secs, result = _timed(bl.assess, args.assess_law, ds, seed=0, **quick)
    rows.append({"task": f"assess {args.assess_law}", "s": secs, "fit_s": fit_s, "target_s": 10.0,
                 "note": ", ".join(f"{k}: {v}" for k, v in result.verdicts.items())})
    print(f"  assess {args.assess_law}: {secs:.1f} s (plain fit {fit_s:.3f} s)", flush=True)
    cluster = client = None
    if args.workers:
        cluster, client = _client(args.workers)
        client.run(_warm_up, args.assess_law, args.campaign, args.surrogate)
        bl.assess(args.assess_law, ds, n_bootstrap=40, starts=1, profile_points=3, local_points=0, executor=client)
        secs_c, remote = _timed(bl.assess, args.assess_law, ds, seed=0, executor=client, **quick)
        same = remote.parameters.equals(result.parameters) and remote.profiles.equals(result.profiles)
        rows.append({"task": f"assess {args.assess_law}, {args.workers} workers", "s": secs_c, "fit_s": fit_s,
                     "target_s": 10.0, "note": "same result as serial" if same else "DIFFERS from serial"})
        print(f"  assess {args.assess_law} on {args.workers} workers: {secs_c:.1f} s", flush=True)

    # calibrate, rigid family
    fit_s, _ = _timed(bl.fit, args.calibrate_law, ds)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", bl.errors.BouncelabWarning)
        secs, cpu, post = _timed_cpu(bl.calibrate, args.calibrate_law, ds, vary=["r", "mu"], seed=0,
                                     **({"steps": 30} if args.quick else {}))
    unconverged = any(issubclass(w.category, ConvergenceWarning) for w in caught)
    d = post.diagnostics
    rows.append({"task": f"calibrate {args.calibrate_law} (vary r, mu)", "s": secs, "fit_s": fit_s, "target_s": 120.0,
                 "note": f"{'converged' if post.converged and not unconverged else 'NOT converged'}; CPU {cpu:.0f} s; "
                         f"{d['walkers']} walkers x {d['steps']} steps, acceptance {d['acceptance']:.2f}, "
                         f"max autocorrelation {max(d['autocorr']):.0f}, max R-hat {max(d['rhat']):.3f}"})
    print(f"  calibrate {args.calibrate_law}: {secs:.1f} s, {rows[-1]['note']}", flush=True)

    # calibrate, TurfContact
    if args.turf:
        fit_s, _ = _timed(bl.fit, bl.TurfContact, ds)
        chains = args.chains or 1
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", bl.errors.BouncelabWarning)
            load_before = _load()
            secs, cpu, post = _timed_cpu(bl.calibrate, bl.TurfContact, ds, vary=args.turf_vary, seed=0, chains=chains,
                                         executor=client if args.chains else None)
        d = post.diagnostics
        where = f"{chains} chain(s)" + (f" on {args.workers} workers" if client is not None and args.chains
                                         else f", batched walkers on {bl.laws.num_threads()} threads")
        rows.append({"task": f"calibrate TurfContact (vary {', '.join(args.turf_vary)})", "s": secs, "fit_s": fit_s,
                     "target_s": 1200.0,
                     "note": f"{'converged' if post.converged else 'NOT converged: ' + d['reason']}; {where}; "
                         f"CPU {cpu:.0f} s; load average {load_before} before, {_load()} after; "
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


# ------------------------------------------------------------------------------ coverage on a known process
def spot_campaign(n_settings: int, repeats: int, seed: int, intervals: bool = True, draws: bool = False):
    """The done-when's campaign, the tests' own (``tests/test_calibrate.py::spot_campaign``): Rigid with r
    (logit-normal: median 0.5, scale 0.25) and mu (log-normal: 0.4, 0.3) drawn per launcher setting, the repeats of
    a setting on its spot, measured with known normal errors (stated as 95 % intervals when ``intervals``); with
    ``draws`` also the settings' own draws."""
    from tests.test_calibrate import spot_campaign as campaign

    return campaign(n_settings, repeats, seed=seed, intervals=intervals, draws=draws)


def coverage(seeds: list[int], settings: int, fresh: int = 10, quick: bool = False) -> list[dict]:
    """One row per campaign (with and without interval columns, per seed), then a summary over the seeds.

    Besides the done-when's figures each row gives what the campaign itself allows: the error of the medians of
    its own setting draws (an estimator that saw every draw would have it), whether the posterior's 95 % intervals
    of the population medians and setting scales hold the generating values, and the coverage that the generating
    process itself (a posterior holding the truth, ``tests/test_calibrate.py::_truth``) gets on the same fresh
    bounces: the part of a row's coverage that is the fresh campaigns' own draw. A coverage is the share of the
    bounces of ``fresh`` fresh campaigns (seeds seed + 1000, + 1001, ...), with the range over those campaigns: on
    one campaign of 1,200 bounces it moves about (up to 0.05 over ten)."""
    import numpy as np

    from tests.test_calibrate import LOGIT, MU_MED, R_MED, S_MU, S_R, _truth, fresh_campaigns, pooled_coverage

    print(f"calibrate(Rigid, vary=['r', 'mu']) with defaults on {settings} settings x 6 repeats per seed; fresh: "
          f"{fresh} x {2 * settings} new settings x 6; load average before: {_load()}", flush=True)
    rows = []
    for intervals in (True, False):
        truth = _truth()
        for seed in seeds:
            data, z = spot_campaign(settings, 6, seed, intervals, draws=True)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", bl.errors.BouncelabWarning)
                secs, post = _timed(bl.calibrate, bl.Rigid, data, vary=["r", "mu"], seed=0,
                                    **({"steps": 30} if quick else {}))
            news = fresh_campaigns(seed, intervals, fresh, settings=2 * settings)
            cover, by_setting, each = pooled_coverage(post, news)
            check = post.check(news[0]).loc["all", ["xdot", "ydot", "omega"]].to_numpy(dtype=float)
            q = post.samples[["r", "mu"]].quantile([0.025, 0.5, 0.975])
            sc = post.scales()
            converged = post.converged and not any(issubclass(w.category, ConvergenceWarning) for w in caught)
            row = {"intervals": "yes" if intervals else "no", "seed": seed, "s": secs,
                   "converged": "yes" if converged else "NO",
                   "r_err_pct": 100 * (q.loc[0.5, "r"] / R_MED - 1),
                   "mu_err_pct": 100 * (q.loc[0.5, "mu"] / MU_MED - 1),
                   # the population medians the campaign's own setting draws give (their mean in the transformed space)
                   "r_draws_pct": 100 * (LOGIT.inverse(LOGIT.forward(R_MED) + z[:, 0].mean()) / R_MED - 1),
                   "mu_draws_pct": 100 * (np.exp(z[:, 1].mean()) - 1),
                   "draw_sd": z.std(axis=0, ddof=1),
                   "medians_held": bool(q.loc[0.025, "r"] <= R_MED <= q.loc[0.975, "r"])
                   + bool(q.loc[0.025, "mu"] <= MU_MED <= q.loc[0.975, "mu"]),
                   "setting_scales_held": sum(bool(sc.loc[v, "setting_low"] <= t <= sc.loc[v, "setting_high"])
                                              for v, t in (("r", S_R), ("mu", S_MU))),
                   "cover": cover, "cover_by_setting": by_setting.to_numpy(),
                   "cover_low": each.min(axis=0), "cover_high": each.max(axis=0),
                   "truth_cover": pooled_coverage(truth, news)[0],
                   "check_same": bool(np.array_equal(check, each[0])),
                   "scales": {v: (sc.loc[v, "setting"], sc.loc[v, "setting_low"], sc.loc[v, "setting_high"])
                              for v in ("r", "mu")}}
            rows.append(row)
            print(f"  intervals={row['intervals']} seed {seed}: {secs:.0f} s, converged {row['converged']}; r "
                  f"{row['r_err_pct']:+.1f} % (own draws {row['r_draws_pct']:+.1f} %), mu {row['mu_err_pct']:+.1f} % "
                  f"(own draws {row['mu_draws_pct']:+.1f} %); coverage {np.round(row['cover'], 3)} (per fresh campaign "
                  f"{np.round(row['cover_low'], 3)} to {np.round(row['cover_high'], 3)}), by setting "
                  f"{np.round(row['cover_by_setting'], 3)}, the truth's {np.round(row['truth_cover'], 3)}; "
                  f"check() same: {row['check_same']}", flush=True)
    print(f"\nload average after: {_load()}")
    print("| intervals | seed | r error | (own draws) | mu error | (own draws) | coverage xdot, ydot, omega | "
          "per fresh campaign | the truth's coverage | check() same | setting scale r (95 %) | mu | draws' sd r, mu | "
          "time, s | converged |")
    print("|---|---:|---:|---:|---:|---:|---|---|---|---|---|---|---|---:|---|")
    for r in rows:
        sr, sm = r["scales"]["r"], r["scales"]["mu"]
        print(f"| {r['intervals']} | {r['seed']} | {r['r_err_pct']:+.1f} % | {r['r_draws_pct']:+.1f} % | "
              f"{r['mu_err_pct']:+.1f} % | {r['mu_draws_pct']:+.1f} % | {', '.join(f'{v:.3f}' for v in r['cover'])} | "
              f"{', '.join(f'{a:.3f}-{b:.3f}' for a, b in zip(r['cover_low'], r['cover_high'], strict=True))} | "
              f"{', '.join(f'{v:.3f}' for v in r['truth_cover'])} | {'yes' if r['check_same'] else 'NO'} | "
              f"{sr[0]:.3f} [{sr[1]:.3f}, {sr[2]:.3f}] | {sm[0]:.3f} [{sm[1]:.3f}, {sm[2]:.3f}] | "
              f"{r['draw_sd'][0]:.3f}, {r['draw_sd'][1]:.3f} | {r['s']:.0f} | {r['converged']} |")
    print(f"(generating: r median {R_MED}, mu median {MU_MED}, setting scales {S_R}, {S_MU})")
    _coverage_summary(rows)
    return rows


def likelihood_profile(seeds: list[int], settings: int) -> None:
    """Per campaign (with interval columns): the brute-force log likelihood (each setting's repeats integrated over
    its draw on a grid, ``tests/test_calibrate.py::_setting_loglikes``; the landing's error left out) as a function
    of mu's population median, the other numbers at the generating process; a parabola through 9 points within
    +-8 % gives where it peaks and its width (one standard deviation). No estimator can place the median closer than
    that width allows."""
    import numpy as np

    from tests.test_calibrate import _TRUE_X, MU_MED, _setting_loglikes, _two_level

    print("| seed | likelihood's peak of mu's median | its sd | the own draws' |\n|---:|---:|---:|---:|")
    for seed in seeds:
        data, z = spot_campaign(settings, 6, seed, True, draws=True)
        post = _two_level(data.landing.values, data.liftoff.values, data.setting.values, landing_error=False)
        logs = np.linspace(-0.08, 0.08, 9)
        ll = []
        for g in logs:
            x = _TRUE_X.copy()
            x[1] = MU_MED * np.exp(g)
            ll.append(_setting_loglikes(post, x)[1].sum())
        c = np.polyfit(logs, ll, 2)
        peak = -c[1] / (2 * c[0]) if c[0] < 0 else np.nan
        sd = (-2 * c[0]) ** -0.5 if c[0] < 0 else np.nan
        own = 100 * np.expm1(z[:, 1].mean())
        print(f"| {seed} | {100 * np.expm1(peak):+.1f} % | {100 * sd:.1f} % | {own:+.1f} % |", flush=True)


def _coverage_summary(rows: list[dict]) -> None:
    """Over the campaigns of each kind: the done-when per campaign (medians within 5 %, every coverage in
    92-98 %), the posterior's 95 % intervals against the generating values, and the mean coverage."""
    import numpy as np

    print("\n| intervals | campaigns | medians within 5 % | of the own draws' medians | coverage in 92-98 % | "
          "median intervals hold truth | setting-scale intervals hold truth | mean coverage | the truth's mean |")
    print("|---|---:|---:|---:|---:|---:|---:|---|---|")
    for kind in ("yes", "no"):
        some = [r for r in rows if r["intervals"] == kind]
        if not some:
            continue
        n = len(some)
        within = sum(abs(r["r_err_pct"]) <= 5 and abs(r["mu_err_pct"]) <= 5 for r in some)
        own = sum(abs(r["r_draws_pct"]) <= 5 and abs(r["mu_draws_pct"]) <= 5 for r in some)
        band = sum(bool(((r["cover"] >= 0.92) & (r["cover"] <= 0.98)).all()) for r in some)
        mean = np.mean([r["cover"] for r in some], axis=0)
        truth = np.mean([r["truth_cover"] for r in some], axis=0)
        print(f"| {kind} | {n} | {within} | {own} | {band} | {sum(r['medians_held'] for r in some)} of {2 * n} | "
              f"{sum(r['setting_scales_held'] for r in some)} of {2 * n} | {', '.join(f'{v:.3f}' for v in mean)} | "
              f"{', '.join(f'{v:.3f}' for v in truth)} |")


if __name__ == "__main__":
    main()
