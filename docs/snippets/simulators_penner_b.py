import warnings

import numpy as np

import bouncelab as bl
from bouncelab.core import published

# 100,000 landings drawn uniformly within the paper's Table 1 ranges for campaign B.
t = published.TABLE1.loc["B"]
rng = np.random.default_rng(0)
landings = np.column_stack([rng.uniform(t.loc[q, "min"], t.loc[q, "max"], 100_000)
                            for q in ("speed", "angle", "spin")])
print(t.loc[["speed", "angle", "spin"]])
si = {"velocity": "m/s", "spin": "rpm"}
for cls in (bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.PiecewiseAffine):
    for campaign in ("A", "B"):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            _, flags = cls.published(campaign).predict(landings, units=si, form="polar", return_flags=True)
        c = flags.counts()
        print(f"{cls.__name__:<16} {campaign}: into the ground {c['into_ground'] / c['n']:6.1%}, "
              f"energy gain {c['energy_gain'] / c['n']:5.1%}, warned: {bool(caught)}")

# What the warning says:
bl.PennerFixed.published("B").predict(landings[:1000], units=si, form="polar")
