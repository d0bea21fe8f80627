import bouncelab as bl
from bouncelab.analysis import tangential_crosstab, tangential_summary, tangential_velocities

ds = bl.load_campaign("B", surrogate="published")
tv = tangential_velocities(ds)
print(tv[["vp_landing", "vp_liftoff", "slip_roll", "vp_reversal"]].isel(bounce=slice(0, 4)).to_pandas().round(1))
s = tangential_summary(ds)
print(s.round(3))
print(f"near-zero threshold: {s.attrs['near_zero']:.1f} radii/s ({s.attrs['near_zero_rule']})")
print(tangential_crosstab(ds))
