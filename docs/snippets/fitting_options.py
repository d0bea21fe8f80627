import bouncelab as bl

ds = bl.load_campaign("A", surrogate="published")

# The objective: delta (default), one Delta q, or a weighted sum.
print(bl.fit(bl.Rigid, ds, objective="omega").model)
print(bl.fit(bl.Rigid, ds, objective={"delta": 1.0, "omega": 0.5}).model)

# Bounds: a search box per parameter; low == high holds a parameter fixed.
print(bl.fit(bl.PennerFixed, ds, bounds={"beta_deg": (12.9, 12.9)}).model)
print(bl.fit(bl.Rigid, ds, bounds={"mu": (0.0, 3.0)}).model)
try:
    bl.fit(bl.Rigid, ds, bounds={"r": (0.0, 1.2)})
except bl.ParameterError as exc:
    print("ParameterError:", exc)

# Held parameters: names (at the law's own values) or a mapping name -> value.
print(bl.fit(bl.PennerFixed(beta_deg=12.9), ds, fixed=["beta_deg"]).model)
print(bl.fit(bl.PennerFixed, ds, fixed={"r": 0.42, "beta_deg": 12.9}).model)

# Method options are the method's own, checked: the paper's procedure for Rigid takes mu_objective only.
try:
    bl.fit(bl.Rigid, ds, method="structured", algorithm="CRS2_LM")
except bl.FitError as exc:
    print("FitError:", exc)

# A start: parameters given to the instance start the search (they must lie in the box).
print(bl.fit(bl.PennerVarying(r=0.45, mu=0.97, k_p=1.5e-4), ds).model)

# Algorithm and seed: the same seed and data give the same result.
a = bl.fit(bl.PennerVarying, ds, algorithm="CRS2_LM", seed=1)
b = bl.fit(bl.PennerVarying, ds, algorithm="CRS2_LM", seed=1)
print(a.algorithm, a.model == b.model, f"{a.delta:.6f}")

# The paper's two-stage procedure for Rigid: r by least squares on ydot, then mu.
s = bl.fit(bl.Rigid, ds, method="structured")
print(s.model, f"delta = {s.delta:.4f}")
print(s.notes[0])
