import bouncelab as bl

law = bl.Rigid(r=0.5, mu=0.4)
print(law, law.params.valuesdict(), law.is_fitted, bl.Rigid.default_bounds())
print(law.params)                               # parameters as objects: value, bounds, unit, vary, description
print(law.replace(mu=0.2))                      # laws are values: replace() returns a changed copy
try:
    law.mu = 0.2
except AttributeError as exc:
    print("AttributeError:", exc)
try:
    bl.Rigid().predict([[1000.0, -800.0, 300.0]])   # an unfitted law
except bl.NotFittedError as exc:
    print("NotFittedError:", exc)
try:
    bl.Rigid(r=1.3, mu=0.4)
except bl.ParameterError as exc:
    print("ParameterError:", exc)

# predict takes (..., 3) array-likes or a labelled DataArray and returns the same kind.
ds = bl.load_campaign("A", surrogate="published")
pred = law.predict(ds.landing)
print(type(pred).__name__, pred.dims, pred.sizes["bounce"])
print(law.regime(ds.landing).to_series().value_counts())
print(law.to_dict())
