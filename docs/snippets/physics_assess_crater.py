"""CraterContact assessed on the embedded campaigns A and B, all eleven parameters free (42 min on 2 shared cores).

SYNTHETIC data: the default "turf" surrogates were simulated with CraterContact itself (its parameters varying
from spot to spot), so this asks which of its parameters bounce data of this design can determine at all, in the
most favourable case (the law is the truth). Reduced counts keep it affordable (each fit takes 30 s to two minutes,
most of it the Nelder-Mead polish): 2 folds, no bootstrap, 2 global starts (DIRECT_L, CRS2_LM), profiles of 3 points
over each parameter's box (its bounds and middle) besides the estimate: 38 fits per campaign. With so coarse a grid
the profile intervals are interpolated between the estimate and the nearest grid point: rough, while the verdicts
rest on the grid points themselves.
"""

import time

from distributed import Client, LocalCluster

import bouncelab as bl

ALL = [s.name for s in bl.CraterContact.parameter_specs]
COUNTS = {"k": 2, "n_bootstrap": 0, "starts": 2, "profile_points": 3, "local_points": 0}

if __name__ == "__main__":
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=":0") as cluster, Client(cluster) as client:
        for campaign in ("A", "B"):
            data = bl.load_campaign(campaign)
            start = time.perf_counter()
            result = bl.assess(bl.CraterContact, data, free=ALL, seed=0, client=client, **COUNTS)
            took = time.perf_counter() - start
            print(f"=== campaign {campaign} (turf surrogate, SYNTHETIC): assess took {took:.0f} s")
            print(result.report())
            print()
            print(result.starts.round(4).to_string())
            print()
            print(result.profiles.round(5).to_string())
            print(flush=True)
