import numpy as np
from sklearn.metrics import adjusted_rand_score

import bouncelab as bl

ds = bl.load_campaign("B", surrogate="published")

# The paper's split: one random bounce of each launcher setting is held out.
train, test = bl.split_by_setting(ds, seed=0)
print(train.sizes["bounce"], test.sizes["bounce"])
res = bl.fit(bl.PennerFixed, train, test=test)
print(f"fitted delta {res.delta:.4f}, held-out delta {res.test_delta:.4f}")

# Grouped k-fold cross-validation: all repeats of a setting fall in the same fold.
cv = bl.cross_validate(bl.PennerFixed, ds, k=5, seed=0)
print(cv)
print(cv.folds[["n_train", "n_test", "train_delta", "test_delta"]].round(4))

# No setting recorded? Infer it by clustering the landing conditions.
bare = ds.drop_vars("setting")
labels = bl.infer_settings(bare)
print(len(np.unique(labels)), "settings inferred; adjusted Rand index against the true ones:",
      round(adjusted_rand_score(ds.setting.values, labels), 3))
bare = bare.assign_coords(setting=("bounce", labels))
print(bl.split_by_setting(bare)[1].sizes["bounce"], "bounces held out")
