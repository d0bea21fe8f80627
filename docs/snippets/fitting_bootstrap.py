import bouncelab as bl

for campaign in "AB":
    ds = bl.load_campaign(campaign, surrogate="published")
    b = bl.bootstrap(bl.PennerFixed, ds, n=100, seed=0)   # resamples whole settings
    table = b.summary()
    table["paper"] = [bl.published.TABLE3.loc[(campaign, "PennerFixed"), k] for k in table.index]
    print(f"campaign {campaign}: {b}")
    print(table.round(3))
