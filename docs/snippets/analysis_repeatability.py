import bouncelab as bl
from bouncelab.analysis import repeatability_summary
from bouncelab.analysis.repeats import repeatability

rep = repeatability(bl.load_campaign("A", surrogate="published"))
print(dict(rep.sizes), rep.attrs["settings_source"])
print(rep["mean"].sel(setting=1).to_pandas().round(1))
print(rep["half_width"].sel(setting=1).to_pandas().round(1))
for campaign in "AB":
    print(f"campaign {campaign}:")
    print(repeatability_summary(repeatability(bl.load_campaign(campaign, surrogate="published"))).round(3).to_string())
