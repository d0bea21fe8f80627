import bouncelab as bl

ds = bl.load_campaign("B")                       # embedded campaign B: a synthetic surrogate
law = bl.fit(bl.PennerFixed, ds).model           # Penner's tilted-surface law, fitted by minimising delta
print(law)
landing = bl.units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
liftoff = law.predict(landing)                   # the paper's typical driver landing, in scaled units
print({k: round(float(v), 1) for k, v in bl.units.speed_angle_spin(liftoff, speed_unit="ft/s").items()})
print(law.regime(landing))
print(bl.score(law, ds).round(4))
