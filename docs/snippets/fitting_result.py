import bouncelab as bl

ds = bl.load_campaign("A", surrogate="published")
res = bl.fit(bl.Rigid, ds, bounds={"mu": (1.2, 3.0)})   # a box where every bounce grips
print(repr(res))
print("at_bounds:", res.at_bounds, " insensitive:", res.insensitive)
print(res)                                               # the report: see the mu line and the note
print(sorted(res.to_dict()))
