import logging
from concurrent.futures import ThreadPoolExecutor

from distributed import Client, LocalCluster
from joblib.externals.loky import get_reusable_executor

import bouncelab as bl

if __name__ == "__main__":  # worker processes import this file: start the pools only in the main process
    ds = bl.load_campaign("B", surrogate="published")
    serial = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1)

    # 1. Threads of this process: the built-in laws release the GIL in their loops.
    with ThreadPoolExecutor(max_workers=2) as pool:
        threads = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1, executor=pool)
        assessed = bl.assess(bl.Rigid, ds, seed=0, executor=pool)
    print("thread pool, identical to serial:", threads.samples.equals(serial.samples))
    print("assess on the thread pool, identical to serial:",
          assessed.parameters.equals(bl.assess(bl.Rigid, ds, seed=0).parameters))

    # 2. loky's reusable executor (joblib's): worker processes that stay up between calls.
    loky = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1, executor=get_reusable_executor(max_workers=2))
    print("loky, identical to serial:", loky.samples.equals(serial.samples))

    # 3. dask: the Client's concurrent.futures face, or the Client itself; on a real cluster only the Client changes.
    quiet = {"dashboard_address": ":0", "silence_logs": logging.CRITICAL}
    with LocalCluster(n_workers=2, threads_per_worker=1, **quiet) as cluster, Client(cluster) as client:
        futures = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1, executor=client.get_executor())
        direct = bl.bootstrap(bl.PennerFixed, ds, n=40, seed=1, executor=client)
    print("dask client.get_executor(), identical to serial:", futures.samples.equals(serial.samples))
    print("dask Client, identical to serial:", direct.samples.equals(serial.samples))
