import bouncelab as bl

ds = bl.load_campaign("B", surrogate="published")
law = bl.PiecewiseAffine.published("B")
p0, pf = ds.landing.values, ds.liftoff.values
pred = law.predict(p0)
print(round(bl.delta(p0, pf, pred), 4), bl.delta_q(p0, pf, pred).round(4))
print(bl.error_table(p0, pf, pred, bl.classify_slip_roll(p0, pf)).round(4))
print(bl.score(law, ds, by="regime").round(4))     # by the law's own regimes (sides of its plane)
