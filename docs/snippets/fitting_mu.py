import numpy as np

import bouncelab as bl

for campaign in "AB":
    ds = bl.load_campaign(campaign, surrogate="published")
    p0 = ds.landing.values
    fitted = bl.fit(bl.Rigid, ds).model
    r = fitted.r
    grip = np.max(np.abs(p0[:, 0] + p0[:, 2]) / (3.5 * (1 + r) * np.abs(p0[:, 1])))
    print(f"campaign {campaign}: fitted {fitted}; with r = {r:.3f} every bounce grips once mu > {grip:.2f}")
    for mu in (0.1, 0.2, fitted.mu, 0.5, 1.0, 1.5, 3.0, 10.0):
        law = bl.Rigid(r=r, mu=mu)
        d = bl.score(law, ds, by=None).loc["all", "delta"]
        print(f"    mu = {mu:6.3f}: delta = {d:.4f}, bounces gripping {np.mean(law.regime(p0) == 'roll'):6.1%}")
    pub = bl.Rigid.published(campaign)
    print(f"    the paper's {pub}: delta on this surrogate {bl.score(pub, ds, by=None).loc['all', 'delta']:.4f}")
