import numpy as np

import bouncelab as bl

landing = np.array([[941.5, -711.9, 314.2], [927.4, -702.6, 319.4]])      # scaled units
liftoff = np.array([[445.0, 238.9, 157.1], [454.3, 234.2, 155.0]])
ds = bl.make_campaign(landing, liftoff, setting=[1, 1], campaign="mine", surface="test mat",
                      data_kind="measured")
print(dict(ds.sizes), ds.attrs["data_kind"], ds.setting.values)
try:
    bl.make_campaign(landing * [1, -1, 1], liftoff)                      # a landing moving up
except bl.DataError as exc:
    print("DataError:", exc)
