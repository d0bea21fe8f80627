import pandas as pd

import bouncelab as bl
from bouncelab.simulation import calibration as cal

# The 28 calibration numbers on the SHIPPED campaigns of both surrogates, against the paper.
cols, verdicts = {}, {}
for surrogate in ("published", "turf"):
    tables = [cal.calibration_table(bl.load_campaign(key, surrogate=surrogate)) for key in "AB"]
    both = pd.concat(tables)
    cols["paper"] = both["paper"]
    cols[surrogate] = both["simulated"]
    cols[f"dev {surrogate}"] = both["deviation"]
    verdicts[surrogate] = cal.meets_target(tables)
with pd.option_context("display.width", 120, "display.max_rows", 40):
    print(pd.DataFrame(cols).round(3).to_string())
for surrogate, v in verdicts.items():
    print(f"{surrogate:9s}: median |dev| {v['median_abs_deviation']:.1%}, max |dev| {v['max_abs_deviation']:.1%}, "
          f"rolling lift-offs {v['rolling_liftoff_fraction']:.1%}, target {'met' if v['met'] else 'NOT met'}")
