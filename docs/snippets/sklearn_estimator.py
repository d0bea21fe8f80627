import numpy as np
import pandas as pd
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, GroupKFold, cross_val_score

import bouncelab as bl

ds = bl.load_campaign("A", surrogate="published")
X, Y, groups = ds.landing.values, ds.liftoff.values, ds.setting.values  # landings, lift-offs, launcher settings

# A law as a 3-output regressor: fit(X, Y), predict(X), score = -delta (greater is better).
est = bl.BounceRegressor("PennerFixed").fit(X, Y)
print(est)
print(est.law_)
print("score (-delta):", round(est.score(X, Y), 4), " predict:", est.predict(X[:1]).round(1))

# Cross-validation that holds out whole launcher settings.
scores = cross_val_score(bl.BounceRegressor("Rigid"), X, Y, groups=groups, cv=GroupKFold(n_splits=5))
print("Rigid, held-out -delta per fold:", scores.round(4))

# A grid over laws, a law's option (law__<name>) and fit settings (held parameters, objective).
grid = [
    {"law": ["Rigid", "PennerVarying", "PennerFixed", "TangentialRestitution"]},
    {"law": ["PennerFixed"], "law__fade_xdot": [20.0, 100.0]},
    {"law": ["PennerFixed"], "fixed": [{"beta_deg": 5.0}, {"beta_deg": 15.0}], "objective": ["delta", "omega"]},
]
search = GridSearchCV(bl.BounceRegressor(), grid, cv=GroupKFold(n_splits=5)).fit(X, Y, groups=groups)
res = pd.DataFrame(search.cv_results_)
res["params"] = res["params"].map(lambda p: ", ".join(f"{k}={v}" for k, v in p.items()))
print(res.sort_values("rank_test_score")[["params", "mean_test_score", "std_test_score"]]
      .to_string(index=False, float_format=lambda v: f"{v:.4f}"))
print("best:", search.best_params_, "->", search.best_estimator_.law_)

# Estimators clone; laws are immutable values, so a law is its own clone.
print(clone(est).get_params()["law"], np.isclose(search.best_score_, res["mean_test_score"].max()))
