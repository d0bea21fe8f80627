import bouncelab as bl

ds = bl.load_campaign("B", surrogate="published")
print(ds)
print(ds.landing.sel(component="omega").values[:5].round(1))   # rad/s
print(ds.unit.values)
print(ds.attrs["conventions"])
print(ds.landing.isel(bounce=slice(0, 3)).to_pandas().round(1))
