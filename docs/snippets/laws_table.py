import bouncelab as bl

for cls in (bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.TangentialRestitution):
    print(f"{cls.__name__}: regimes {cls.regimes}")
    for p in cls.parameter_specs:
        print(f"    {p.name:<9} unit {p.unit:<9} default bounds {p.bounds!s:<16} physical range {p.physical}"
              f"  - {p.description}")
numbers = sum(p.size for p in bl.PiecewiseAffine.parameter_specs)
print(f"PiecewiseAffine: regimes {bl.PiecewiseAffine.regimes}, {numbers} numbers")
for p in bl.PiecewiseAffine.parameter_specs:
    print(f"    {p.name:<9} shape {p.shape!s:<8} unit {p.unit:<27} - {p.description}")
