import bouncelab as bl

law = bl.PiecewiseAffine.published("B")
print(law.printed_plane())
print(law.plane_equation())
print(law.plane_unit_equation())                  # always finite, also for planes parallel to the omega axis
print(law.normal, law.offset)
print(law.params["A1"].value)                     # parameters are arrays; params.flat() names every number
print(list(law.params.flat())[:6], "...")
landing = [[1000.0, -800.0, 600.0], [300.0, -200.0, -300.0]]
print(law.regime(landing), law.predict(landing).round(1))
