"""Which NLopt algorithms reach the minimum of delta: the measurement behind bouncelab's defaults.

Run: ``python benchmarks/bench_algorithms.py`` (about 30 s for the default 48 problems; ``--problems 200``
takes about 2 minutes; ``--quick``: 4 problems, one per law, a few seconds, for CI).
Random fitting problems (each rigid-family law, 20 to 700 bounces, noise 2 to 20 % of |p0|, random
true parameters) are solved by every global algorithm followed by every local polish, through
``bouncelab.fitting.search.global_search`` with fit()'s default budget (``default_maxeval``);
the best known minimum of each problem is the lowest value found by any of them or by
``scipy.optimize.differential_evolution`` (tol=1e-12, two seeds). A run fails when its delta is
more than 1e-9 above that. The table gives failures and median evaluations per combination.
"""

from __future__ import annotations

import argparse
import itertools
import os
import sys
import time

import numpy as np
from scipy.optimize import differential_evolution

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.fitting.fitter import default_maxeval
from bouncelab.fitting.objective import ErrorMeasure
from bouncelab.fitting.search import GLOBAL_ALGORITHMS, LOCAL_ALGORITHMS, global_search

LAWS = (bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.TangentialRestitution)


def problem(rng: np.random.Generator, i: int):
    cls = LAWS[i % len(LAWS)]
    n = int(rng.choice([20, 60, 300, 700]))
    p0 = np.column_stack([rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n), rng.uniform(-1700, 1700, n)])
    truth = cls(**{s.name: rng.uniform(*s.bounds) for s in cls.parameter_specs})
    noise = rng.choice([0.02, 0.08, 0.2])
    scatter = noise * np.linalg.norm(p0, axis=1, keepdims=True) * rng.standard_normal((n, 3))
    pf = truth.predict(p0, plausible=None) + scatter  # random landings, grazing ones too: the law's maths
    measure = ErrorMeasure(cls(), np.ascontiguousarray(p0), pf)
    lo = np.array([s.bounds[0] for s in cls.parameter_specs])
    hi = np.array([s.bounds[1] for s in cls.parameter_specs])
    return cls.__name__, n, (lambda u: measure.errors(lo + u * (hi - lo))[0]), len(lo)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problems", type=int, default=None, help="random problems (default 48; 4 with --quick)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="4 problems, one per law: checks the benchmark runs (CI)")
    args = ap.parse_args(argv)
    if args.problems is None:
        args.problems = len(LAWS) if args.quick else 48
    rng = np.random.default_rng(args.seed)
    combos = list(itertools.product(GLOBAL_ALGORITHMS, LOCAL_ALGORITHMS))
    fails = dict.fromkeys(combos, 0)
    evals: dict = {c: [] for c in combos}
    times: dict = {c: [] for c in combos}
    for i in range(args.problems):
        _, n, f, d = problem(rng, i)
        f(np.full(d, 0.5))  # compile or load the law's kernels outside the timing
        found = {}
        for combo in combos:
            t = time.perf_counter()
            out = global_search(f, np.full(d, 0.5), algorithm=combo[0], local_algorithm=combo[1], seed=i,
                                maxeval=default_maxeval(d, n))
            times[combo].append(time.perf_counter() - t)
            found[combo] = out.fun
            evals[combo].append(out.n_global + out.n_local)
        best = min(found.values())
        for s in range(2):
            best = min(best, differential_evolution(f, [(0.0, 1.0)] * d, tol=1e-12, seed=s).fun)
        for combo, value in found.items():
            fails[combo] += value - best > 1e-9
    print(f"{args.problems} random fitting problems (seed {args.seed}); a failure is delta > best known + 1e-9")
    print(f"{'global':<10}{'local':<12}{'failures':>9}{'median evals':>14}{'median ms':>11}")
    for combo in sorted(combos, key=lambda c: (fails[c], np.median(evals[c]))):
        print(f"{combo[0]:<10}{combo[1]:<12}{fails[combo]:>9}{np.median(evals[combo]):>14.0f}"
              f"{1e3 * np.median(times[combo]):>11.1f}")
    return fails


if __name__ == "__main__":
    main()
