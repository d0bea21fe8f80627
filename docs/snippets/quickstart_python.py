import bouncelab as bl

# 1. Load a campaign: "A" and "B" are embedded (synthetic surrogates); a path loads your own file.
ds = bl.load_campaign("A")
print(ds.sizes["bounce"], "bounces,", ds.attrs["data_kind"])

# 2. Fit a law. A class (or an instance holding a starting point) and the data.
res = bl.fit(bl.PennerFixed, ds, seed=0)

# 3. The report: parameters, bounds, errors overall and per measured class, notes.
print(res)

# 4. Predict lift-off from landing states [xdot0, ydot0, omega0] (radii/s, radii/s, rad/s).
law = res.model
print(law.predict([[1000.0, -800.0, 300.0], [600.0, -300.0, -100.0]]).round(1))
print(law.regime([[1000.0, -800.0, 300.0], [600.0, -300.0, -100.0]]))
