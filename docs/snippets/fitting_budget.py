import bouncelab as bl
from bouncelab.fitting.fitter import default_maxeval

sizes = (20, 30, 60, 150, 275, 300, 700)
print("bounces          " + "".join(f"{n:>7}" for n in sizes))
for d in (2, 3):
    print(f"{d} free parameters" + "".join(f"{default_maxeval(d, n):>7}" for n in sizes))

ds = bl.load_campaign("A", surrogate="published")
train, test = bl.split_by_setting(ds, seed=0)              # 275 of the 330 bounces
for data in (ds, train, ds.isel(bounce=slice(0, 60))):
    res = bl.fit(bl.Rigid, data)
    print(f"{res.n_train:>3} bounces: {res.n_global} global + {res.n_local} local evaluations ({res.stop_reason})")
print(bl.fit(bl.Rigid, ds, maxeval=50).n_global, "global evaluations with maxeval=50")
