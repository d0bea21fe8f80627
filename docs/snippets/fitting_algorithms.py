import time

import numpy as np

import bouncelab as bl
from bouncelab.fitting import GLOBAL_ALGORITHMS

laws = [bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.TangentialRestitution]
data = {c: bl.load_campaign(c, surrogate="published") for c in "AB"}
for law in laws:                                     # load the compiled kernels before timing
    bl.fit(law, data["A"])
best, runs = {}, []
for algo in GLOBAL_ALGORITHMS:
    for campaign, ds in data.items():
        for law in laws:
            for seed in range(3):
                t = time.perf_counter()
                res = bl.fit(law, ds, algorithm=algo, seed=seed)
                runs.append((algo, campaign, law.__name__, seed, res.delta, time.perf_counter() - t))
                key = (campaign, law.__name__)
                best[key] = min(best.get(key, np.inf), res.delta)
print("24 fits per algorithm: 4 laws x campaigns A, B x seeds 0-2; local polish NELDERMEAD (the default)")
print(f"{'algorithm':<10}{'reached the best delta':>24}{'worst excess delta':>20}{'median ms':>11}")
for algo in GLOBAL_ALGORITHMS:
    mine = [r for r in runs if r[0] == algo]
    excess = np.array([r[4] - best[(r[1], r[2])] for r in mine])
    print(f"{algo:<10}{int((excess <= 1e-6).sum()):>18d} / {len(mine)}{excess.max():>20.1e}"
          f"{1e3 * np.median([r[5] for r in mine]):>11.1f}")
for r in runs:
    if r[4] - best[(r[1], r[2])] > 1e-6:
        print(f"missed: {r[0]}, campaign {r[1]}, {r[2]}, seed {r[3]}: delta {r[4]:.4f} "
              f"instead of {best[(r[1], r[2])]:.4f}")
