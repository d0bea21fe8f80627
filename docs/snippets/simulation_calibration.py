import bouncelab as bl
from bouncelab.simulation import LogNormal, Normal, Turf
from bouncelab.simulation import calibration as cal

# Today's embedded surrogates (published piecewise law + Gaussian noise), scored against the paper.
tables = [cal.calibration_table(bl.generate_surrogate(key)) for key in "AB"]
print(cal.meets_target(tables))

# A simulated campaign with a stand-in turf law.
turf = Turf(bl.TangentialRestitution(r=0.45, mu=0.8, e_t=0.3),
            {"r": LogNormal(0.15), "mu": LogNormal(0.2), "e_t": Normal(0.1)})
table = cal.calibration_table(bl.simulate_campaign("A", turf, seed=1))
print(table.round(4).to_string())
print("rolling lift-offs:", table.attrs["rolling_liftoff_fraction"])
print("J =", round(cal.calibration_objective(table), 4))
