import numpy as np

import bouncelab as bl
from bouncelab.laws import BounceModel, Parameter

RIGID = bl.Rigid(r=0.5, mu=0.5)


class RedundantRigid(BounceModel):
    """A rigid bounce whose restitution is r1 * r2: only the product can be found from bounces."""

    parameter_specs = (Parameter("r1", (0.0, 1.0), (0.0, 1.0), "1", "restitution factor 1"),
                       Parameter("r2", (0.0, 1.0), (0.0, 1.0), "1", "restitution factor 2"),
                       Parameter("mu", (0.0, 1.5), (0.0, float("inf")), "1", "friction"))
    regimes = bl.Rigid.regimes

    def __init__(self, r1=None, r2=None, mu=None):
        self.r1, self.r2, self.mu = r1, r2, mu
        super().__init__()

    def _predict(self, p, theta):
        return RIGID._predict(p, np.array([theta[0] * theta[1], theta[2]]))

    def _regime(self, p, theta):
        return RIGID._regime(p, np.array([theta[0] * theta[1], theta[2]]))


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
