import time

import bouncelab as bl

# SYNTHETIC data: the default 'turf' surrogate of campaign B, simulated with the CraterContact law.
data = bl.load_campaign("B")
start = time.perf_counter()
result = bl.assess(bl.PennerFixed, data, seed=0)
print(f"assess: {time.perf_counter() - start:.1f} s on {data.sizes['bounce']} bounces")
print(result)
print()
print(result.to_markdown())
