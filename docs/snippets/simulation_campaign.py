import json

import bouncelab as bl
from bouncelab.simulation import Camera, LauncherDesign, LogNormal, Normal, Turf

# A stand-in turf: Walton's law with spot-to-spot scatter of its three parameters.
turf = Turf(
    bl.TangentialRestitution(r=0.3, mu=0.6, e_t=0.3),
    {"r": LogNormal(0.15), "mu": LogNormal(0.2), "e_t": Normal(0.1)},
    name="stand-in",
)
design = LauncherDesign.for_campaign("B")  # 35 settings x 12 + 47 x 6, 9 lost
ds = bl.simulate_campaign(design, turf, Camera(fps=5000), seed=1)
print(ds.sizes["bounce"], "bounces,", len(set(ds["setting"].values.tolist())), "settings")
print(ds.attrs["warning"])
print(json.loads(ds.attrs["simulation_json"])["turf"]["scatter"])
print(ds[["landing", "liftoff"]].isel(bounce=0).to_pandas().round(1))
print("measured - true, first bounce:")
print((ds["liftoff"] - ds["true_liftoff"]).isel(bounce=0).to_pandas().round(2))
print("its 95 % intervals:")
print(ds["liftoff_pi"].isel(bounce=0).to_pandas().round(2))
print("spot parameters of the first 3 bounces:")
print(ds["spot_parameters"].isel(bounce=slice(0, 3)).to_pandas().round(3))
