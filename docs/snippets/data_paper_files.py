from pathlib import Path

import bouncelab as bl

# A stand-in for a file of measured bounces in physical units (here made from surrogate A,
# so the numbers are NOT measurements): one row per bounce, m/s and rpm, a setting column.
ds = bl.load_campaign("A", surrogate="published")
physical = {s: bl.units.from_scaled(ds[s].values, velocity="m/s", spin="rpm") for s in ("landing", "liftoff")}
rows = ["Setting,Vx in,Vy in,Spin in,Vx out,Vy out,Spin out"]
for k in range(ds.sizes["bounce"]):
    cells = [*physical["landing"][k], *physical["liftoff"][k]]
    rows.append(f"{ds.setting.values[k]}," + ",".join(f"{v:.4f}" for v in cells))
Path("campaign_A_measured.csv").write_text("\n".join(rows) + "\n")

# Loading such a file: name the campaign "A" (or "B") and bouncelab.compare sets the paper's values beside yours.
mine = bl.load_campaign(
    "campaign_A_measured.csv",
    columns={"landing": ["Vx in", "Vy in", "Spin in"], "liftoff": ["Vx out", "Vy out", "Spin out"],
             "setting": "Setting"},
    units={"velocity": "m/s", "spin": "rpm"},
    campaign="A",
    surface="artificial turf",
)
print(mine.attrs["campaign"], mine.attrs["data_kind"], mine.attrs["source_units"])
cmp = bl.compare(mine, ["Rigid", "PennerFixed"])
print(cmp.to_markdown())
