import numpy as np
import pandas as pd
import xarray as xr
from dask import array as da
from distributed import Client, LocalCluster

import bouncelab as bl

if __name__ == "__main__":  # worker processes import this file: start the cluster only in the main process
    ds = bl.load_campaign("B", surrogate="published")
    # Here a LocalCluster of two worker processes; on a real cluster, Client("tcp://scheduler:8786") instead.
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=":0") as cluster, Client(cluster) as client:
        print("workers:", len(client.scheduler_info()["workers"]))

        # The same calls as serially, with executor=client: the same numbers, bit for bit.
        boot = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1, executor=client)
        serial = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1)
        print(boot.summary().round(4))
        print("identical to serial:", boot.samples.equals(serial.samples))

        cv = bl.cross_validate(bl.PennerVarying, ds, k=5, executor=client)
        print(cv)
        cmp = bl.compare(ds, ["Rigid", "PennerFixed", "PennerVarying"], split="setting", executor=client)
        print(cmp.table[["train_delta", "test_delta"]].round(4))

        # A parameter sweep: every (r, mu) evaluated, or a profile: beta held, r and mu fitted.
        grid = bl.sweep(bl.Rigid, ds, {"r": [0.1, 0.15, 0.2], "mu": np.linspace(0.2, 0.8, 4)}, executor=client)
        print(grid.pivot(index="r", columns="mu", values="delta").round(4))
        profile = bl.sweep(bl.PennerFixed, ds, {"beta_deg": [0.0, 10.0, 15.0, 20.0]}, executor=client)
        print(profile[["beta_deg", "r", "mu", "delta"]].round(4).to_string(index=False))

        # Lazy prediction of a dask-backed DataArray: one task per chunk, run on the cluster at compute().
        n = 2_000_000
        landings = xr.DataArray(
            da.concatenate([da.from_array(ds.landing.values, chunks=(693, 3))] * (n // 693 + 1))[:n]
            .rechunk((250_000, 3)), dims=("bounce", "component"),
            coords={"component": ["xdot", "ydot", "omega"]})
        law = bl.PennerFixed(r=0.15, mu=0.38, beta_deg=14.5)
        liftoff = law.predict(landings)
        print(type(liftoff.data).__name__, liftoff.data.numblocks, "blocks; computed:",
              np.array_equal(liftoff.compute().values[:693], law.predict(ds.landing.values)))
        print(pd.Series(law.regime(landings).compute().values).value_counts())
