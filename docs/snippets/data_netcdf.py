import numpy as np

import bouncelab as bl
from bouncelab.data.io import save_campaign

ds = bl.load_campaign("A", surrogate="published")
path = save_campaign(ds, "campaign_A_copy.nc")
again = bl.load_campaign(path)
print(path, again.sizes["bounce"], again.attrs["data_kind"])
print(all(np.array_equal(ds[v].values, again[v].values) for v in ("landing", "liftoff", "landing_pi", "liftoff_pi")))
print(np.array_equal(ds.setting.values, again.setting.values), ds.attrs == {k: again.attrs[k] for k in ds.attrs})
