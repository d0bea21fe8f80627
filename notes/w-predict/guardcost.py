import sys, time, warnings
sys.path.insert(0, sys.argv[1])
import numpy as np, bouncelab as bl
assert bl.__file__.startswith(sys.argv[1])
rng = np.random.default_rng(0); n = 1_000_000
xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
p = np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])
laws = {"Rigid": bl.Rigid(r=0.544, mu=0.997), "PennerFixed": bl.PennerFixed(r=0.42, mu=0.852, beta_deg=12.9),
        "PiecewiseAffine": bl.PiecewiseAffine.published("A").replace(offset=601.0)}
for name, law in laws.items():
    law.predict(p); law.predict(p, plausible=None)
    a, b = [], []
    for _ in range(15):
        t = time.perf_counter(); law.predict(p); a.append(time.perf_counter() - t)
        t = time.perf_counter(); law.predict(p, plausible=None); b.append(time.perf_counter() - t)
    print(f"{name:16s} guarded {np.median(a)*1e3:7.2f} ms  unguarded {np.median(b)*1e3:7.2f} ms  ratio {np.median(a)/np.median(b):.2f}")
