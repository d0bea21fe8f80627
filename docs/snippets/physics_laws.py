"""The physics-based laws on the embedded campaigns: delta beside the paper's laws, lever arms, figures."""

import time

import numpy as np

import bouncelab as bl
from bouncelab.analysis import lever_arm_summary
from bouncelab.plots import plot_lever_arm, save_figure

LAWS = [bl.Rigid, bl.PennerFixed, bl.PiecewiseAffine, bl.TangentialRestitution, bl.CompliantImpact, bl.TurfContact,
        bl.CraterContact]

for campaign in "AB":
    ds = bl.load_campaign(campaign, surrogate="published")
    fits = {}
    print(f"campaign {campaign} ({ds.sizes['bounce']} bounces, {ds.attrs.get('data_kind', '')})")
    for law in LAWS:
        start = time.perf_counter()
        fits[law.__name__] = res = bl.fit(law, ds, seed=0)
        print(f"  {law.__name__:22s} delta = {res.delta:.4f}   ({time.perf_counter() - start:5.1f} s)")
        if law in (bl.CompliantImpact, bl.TurfContact, bl.CraterContact):
            print("   ", res.model)
            for line in res.model._summary_lines():
                print("   ", line)
    print(lever_arm_summary(ds, list(fits.values())).round(3).to_string())
    shown = [fits[k] for k in ("Rigid", "PennerFixed", "PiecewiseAffine", "TurfContact")]
    save_figure(plot_lever_arm(ds, shown), f"lever_arm_{campaign}.png")
    turf = fits["TurfContact"].model
    speeds = np.array([100.0, 300.0, 500.0, 700.0, 900.0])
    print("  TurfContact restitution of vertical landings at", speeds, "radii/s:", turf.restitution(speeds).round(3))
    vp0 = ds["landing"].values[:, 0] + ds["landing"].values[:, 2]
    for name in ("CompliantImpact", "TurfContact", "CraterContact"):
        m = fits[name].model
        out = m.predict(ds["landing"].values)
        vpf = out[:, 0] + out[:, 2]
        counts = {r: int((m.regime(ds["landing"].values) == r).sum()) for r in m.regimes}
        print(f"  {name} regimes {counts}; v_P reversed in {int((vp0 * vpf < 0).sum())} bounces")
    meas = ds["liftoff"].values[:, 0] + ds["liftoff"].values[:, 2]
    print(f"  data: v_P reversed in {int((vp0 * meas < 0).sum())} bounces")
