import numpy as np

import bouncelab as bl

variants = {                                        # name -> options of bl.fit(PiecewiseAffine, ...)
    "svm": {"method": "svm"},                       # the paper's procedure: the SVM's plane (default reading)
    "svm-sv": {"method": "svm", "svm_plane": "support_vectors"},  # the literal reading: lstsq through all SVs
    "plane": {"method": "plane"},                   # bouncelab's default: the plane minimising delta
}
for campaign in "AB":
    ds = bl.load_campaign(campaign, surrogate="published")
    found = {name: [] for name in variants}
    for seed in range(10):                          # ten random paper-style splits
        train, test = bl.split_by_setting(ds, seed=seed)
        for name, options in variants.items():
            res = bl.fit(bl.PiecewiseAffine, train, test=test, seed=seed, **options)
            found[name].append((res.delta, res.test_delta, res.mismatched, res.test_mismatched))
    print(f"campaign {campaign}: mean (sd) over 10 splits, per cent")
    print(f"    {'method':<8}{'fitted delta':>15}{'held-out delta':>16}{'mismatched fit':>16}{'held out':>16}")
    for name, rows in found.items():
        m, s = np.mean(rows, axis=0), np.std(rows, axis=0, ddof=1)
        print(f"    {name:<8}" + "".join(f"{100 * a:>9.2f} ({100 * b:.2f})" for a, b in zip(m, s, strict=True)))
    print(f"    generating plane:         {bl.PiecewiseAffine.published(campaign).plane_equation()}")
    for name, options in variants.items():
        plane = bl.fit(bl.PiecewiseAffine, ds, **options).model.plane_equation()
        print(f"    {name + ' on all bounces:':<26}{plane}")
