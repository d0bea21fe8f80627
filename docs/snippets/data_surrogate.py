import numpy as np

import bouncelab as bl
from bouncelab.laws.plane_fitting import mismatched_fraction
from bouncelab.simulation.surrogate import SurrogateSpec, generate_surrogate

print(SurrogateSpec.for_campaign("A"))
for campaign in "AB":
    ds = bl.load_campaign(campaign, surrogate="published")
    law = bl.PiecewiseAffine.published(campaign)           # the law that generated it
    t = bl.score(law, ds)                                  # by measured slip/roll class
    paper = bl.published.TABLE2.loc[campaign]
    print(f"campaign {campaign}: {ds.sizes['bounce']} bounces, {np.unique(ds.setting).size} settings")
    print(f"    published law on the surrogate: delta {t.loc['all', 'delta']:.2%} "
          f"(roll {t.loc['roll', 'delta']:.2%}, slip {t.loc['slip', 'delta']:.2%}); "
          f"in the paper {paper.loc['overall', 'delta']:.2%} (roll {paper.loc['roll', 'delta']:.2%}, "
          f"slip {paper.loc['slip', 'delta']:.2%})")
    p0, pf = ds.landing.values, ds.liftoff.values
    print(f"    mismatched (measured class vs side of its plane): {mismatched_fraction(law, p0, pf):.1%}; "
          f"in the paper {paper.loc['overall', 'mismatched']:.2%}")
    print(f"    lift-offs with ydot <= 0: {int((pf[:, 1] <= 0).sum())}; "
          f"landings with xdot < 0: {int((p0[:, 0] < 0).sum())}")

other = generate_surrogate("B", seed=1)                    # another draw of the same design
print(other.sizes["bounce"], other.attrs["source"])
print(other.attrs["warning"])
