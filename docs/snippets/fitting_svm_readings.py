import time

import bouncelab as bl

# The paper's Table 2 setting: one bounce per launcher setting held out (seed 0), plane and maps fitted on the rest.
readings = [("hyperplane", "standardize"), ("support_vectors", "standardize"),
            ("margin_support_vectors", "standardize"), ("hyperplane", "none"), ("support_vectors", "none")]
for campaign in ("A", "B"):
    ds = bl.load_campaign(campaign, surrogate="published")
    train, test = bl.split_by_setting(ds, seed=0)
    truth = bl.PiecewiseAffine.published(campaign)
    print(f"campaign {campaign}: {train.sizes['bounce']} fitted, {test.sizes['bounce']} held out; "
          f"the paper's plane: {truth.plane_equation()}")
    p0 = ds.landing.values

    def agree(law, p0=p0, truth=truth):  # share of landings on the side the paper's (generating) plane puts them
        return (law.regime(p0) == truth.regime(p0)).mean()

    print(f"  {'svm_plane':<24}{'scaling':<13}{'plane (paper form)':<42}{'SVs':>5}{'on margin':>10}"
          f"{'held-out delta':>16}{'mismatched':>12}{'same side':>11}{'s':>6}")
    for plane, scaling in readings:
        t = time.perf_counter()
        res = bl.fit(bl.PiecewiseAffine, train, test=test, method="svm", svm_plane=plane, svm_scaling=scaling)
        s = time.perf_counter() - t
        conv = "" if "iteration limit" not in res.stop_reason else " (not converged)"
        print(f"  {plane:<24}{scaling:<13}{res.model.plane_equation():<42}{len(res.extras['svm_support']):>5}"
              f"{len(res.extras['margin_support']):>10}{res.test_delta:>16.4f}{res.test_mismatched:>12.4f}"
              f"{agree(res.model):>11.3f}{s:>6.1f}{conv}")
    res = bl.fit(bl.PiecewiseAffine, train, test=test)
    print(f"  {'delta-optimal plane':<37}{res.model.plane_equation():<42}{'':>15}{res.test_delta:>16.4f}"
          f"{res.test_mismatched:>12.4f}{agree(res.model):>11.3f}")
    print(f"  {'the paper plane and maps':<37}{'(generating law of the surrogate)':<42}{'':>15}"
          f"{bl.delta(test.landing, test.liftoff, truth.predict(test.landing)):>16.4f}"
          f"{bl.laws.plane_fitting.mismatched_fraction(truth, test.landing, test.liftoff):>12.4f}")
