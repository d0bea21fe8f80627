import pandas as pd

import bouncelab as bl

rows = []
for campaign in ("A", "B"):
    ds = bl.load_campaign(campaign, surrogate="published")
    for law in (bl.Rigid, bl.PennerFixed, bl.PennerVarying):
        for objective in ("delta", "delta_pi"):
            res = bl.fit(law, ds, objective=objective)
            pi = bl.fit(res.model, ds, objective="delta_pi", fixed=list(res.model.parameters))  # delta_pi only
            cv = bl.cross_validate(law, ds, k=5, objective=objective)
            rows.append({"campaign": campaign, "law": law.__name__, "objective": objective,
                         **{k: f"{v:.4g}" for k, v in res.model.parameters.items()},
                         "delta": res.delta, "delta_pi": pi.objective_value, "held-out delta": cv.delta})
table = pd.DataFrame(rows).set_index(["campaign", "law", "objective"]).fillna("")
table = table[["r", "mu", "beta_deg", "k_p", "delta", "delta_pi", "held-out delta"]]
print(table.to_string(float_format=lambda v: f"{v:.4f}"))
