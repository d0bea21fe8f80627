import os
import sys

import numpy as np

import bouncelab as bl
from bouncelab.fitting.fitter import default_maxeval
from bouncelab.fitting.search import global_search

sys.path.insert(0, os.environ["REPO"])                     # the repository root, for benchmarks/
from benchmarks.bench_algorithms import problem

# Problem 193 of `python benchmarks/bench_algorithms.py --problems 200 --seed 5`.
rng = np.random.default_rng(5)
for i in range(194):
    law, n, f, d = problem(rng, i)                         # f: delta at a point of the unit box
scale = np.array([hi for lo, hi in bl.PennerFixed.default_bounds().values()])   # r, mu, beta_deg
print(f"problem {i}: {law}, {n} bounces")
opts = {"algorithm": "DIRECT_L", "local_algorithm": "NELDERMEAD", "seed": i, "maxeval": default_maxeval(d, n)}
for rounds, label in ((0, "no scan"), (2, "scan and probe (default)")):
    out = global_search(f, np.full(d, 0.5), scan_rounds=rounds, **opts)
    r, mu, beta = out.x * scale
    print(f"    {label:<25} r = {r:.4f}, mu = {mu:.4f}, beta = {beta:.2f} deg: delta = {out.fun:.7f}"
          f" ({out.n_global} + {out.n_local} evaluations)")
print("delta along mu, the other parameters as found:")
for mu in np.arange(0.6825, 0.7201, 0.00375):
    y = out.x.copy()
    y[1] = mu / scale[1]
    print(f"    mu = {mu:.5f}: delta = {f(y):.7f}")
