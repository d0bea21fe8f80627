"""Dump every figure to compare bit for bit: python golden.py SRC OUT.npz"""
import sys, warnings
sys.path.insert(0, sys.argv[1])
import numpy as np, bouncelab as bl
from bouncelab.laws import registered_laws
assert bl.__file__.startswith(sys.argv[1]), bl.__file__
warnings.simplefilter("ignore")
rng = np.random.default_rng(7)
out = {}
def rand_law(name):
    cls = registered_laws()[name]
    vals = {}
    for spec in cls.parameter_specs:
        lo, hi = spec.bound_arrays(); v = rng.uniform(lo, hi)
        vals[spec.name] = v.reshape(spec.shape) if spec.shape else float(v[0])
    return cls(**vals)
names = ["Rigid", "PennerFixed", "PennerVarying", "PiecewiseAffine", "TangentialRestitution", "CompliantImpact", "CraterContact", "TurfContact"]
for name in names:
    n = 70_000 if name not in ("TurfContact", "CraterContact") else 3000
    p = np.column_stack([rng.uniform(-2500, 2500, n), rng.uniform(-1900, -60, n), rng.uniform(-600, 1800, n)])
    for k in range(3):
        law = rand_law(name)
        out[f"{name}{k}_pred"] = law.predict(p, plausible=None)
        out[f"{name}{k}_reg"] = law.regime(p, plausible=None, codes=True)
        out[f"{name}{k}_one"] = np.array([law.predict_one(*row, plausible=None) for row in p[:200]])
        out[f"{name}{k}_small"] = law.predict(p[:5], plausible=None)
    try:
        pub = registered_laws()[name].published("A")
        q = bl.load_campaign("A").landing.values
        out[f"{name}_pubA"] = pub.predict(q)
        out[f"{name}_pubA_phys"] = pub.predict(q * 0.02135, units={"velocity": "m/s", "spin": "rad/s"})
    except Exception as e:
        pass
ds = bl.load_campaign("B")
for law in [bl.Rigid, bl.PennerFixed, bl.PiecewiseAffine]:
    res = bl.fit(law, ds, seed=0)
    out[f"fit_{law.__name__}"] = np.array(list(res.model.flat_parameters().values()) + [res.delta], dtype=float)
np.savez(sys.argv[2], **out)
print(len(out), "arrays")
