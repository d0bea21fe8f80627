import numpy as np

import bouncelab as bl
from bouncelab.laws import BounceModel, Parameter

RIGID = bl.Rigid(r=0.5, mu=0.5)


class RedundantRigid(BounceModel):
    """A rigid bounce whose restitution is r1 * r2: only the product can be found from bounces."""

    r1 = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution factor 1")
    r2 = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution factor 2")
    mu = Parameter(bounds=(0.0, 1.5), physical=(0.0, float("inf")), doc="friction")
    regimes = bl.Rigid.regimes

    def _predict(self, p, r1, r2, mu):
        return RIGID._predict(p, r=r1 * r2, mu=mu)

    def _regime(self, p, r1, r2, mu):
        return RIGID._regime(p, r=r1 * r2, mu=mu)


# 40 launcher settings x 6 repeats, lift-offs from r1 = 0.9, r2 = 0.6, mu = 0.35 plus noise
rng = np.random.default_rng(1)
base = np.column_stack([rng.uniform(200, 1200, 40), rng.uniform(-900, -200, 40), rng.uniform(-500, 800, 40)])
landing = np.repeat(base, 6, axis=0) + rng.normal(0, [10, 10, 20], (240, 3))
liftoff = RedundantRigid(r1=0.9, r2=0.6, mu=0.35).predict(landing) + rng.normal(0, [8, 8, 30], (240, 3))
data = bl.make_campaign(landing, liftoff, setting=np.repeat(np.arange(40), 6))

result = bl.assess(RedundantRigid, data, n_bootstrap=30)
print(result.parameters[["estimate", "ci_low", "ci_high", "profile_low", "profile_high", "verdict", "correlated"]]
      .round(4).to_string())
print("near-null Jacobian directions:", result.null_directions)
