import bouncelab as bl

ds = bl.load_campaign("A")
cmp = bl.compare(ds, ["Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine"], split="setting", seed=0)
print(cmp.table[["r", "mu", "beta_deg", "train_delta", "test_delta"]].round(3))
