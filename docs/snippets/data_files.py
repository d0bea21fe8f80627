from pathlib import Path

import bouncelab as bl

# A file whose headers say everything: found by the synonym table, units read from the headers.
Path("bounces.csv").write_text(
    "Test condition,Vx0 (m/s),Vy0 (m/s),Spin0 (rpm),VxF (m/s),VyF (m/s),SpinF (rpm)\n"
    "1,20.1,-15.2,3000,9.5,5.1,1500\n"
    "1,19.8,-15.0,3050,9.7,5.0,1480\n"
)
ds = bl.load_campaign("bounces.csv")
print(ds.landing.values.round(1), ds.attrs["source_units"], ds.setting.values)

# Names the synonym table does not know: map them with columns=, give the units with units=.
Path("mine.txt").write_text(
    "# launcher run 7\n"
    "run  a_in   b_in    c_in   a_out  b_out  c_out\n"
    "7    20.1  -15.2   3000    9.5    5.1    1500\n"
    "7    19.8  -15.0   3050    9.7    5.0    1480\n"
)
ds = bl.load_campaign(
    "mine.txt",
    columns={"landing": ["a_in", "b_in", "c_in"], "liftoff": ["a_out", "b_out", "c_out"], "setting": "run"},
    units={"velocity": "m/s", "spin": "rpm"},
)
print(ds.landing.values.round(1), ds.attrs["source_units"])

# Every problem names the file, the column and the row.
for text, kwargs in [
    ("vx0,vy0,w0,vxF,vyF,wF\n20.1,-15.2,3000,9.5,5.1,1500\n", {}),
    ("vx0,vy0,w0,vxF,vyF,wF\n20.1,15.2,314,9.5,5.1,157\n", {"units": {"velocity": "m/s"}}),
    ("x0,y0,z0,xF,yF,zF\n1,2,3,4,5,6\n", {}),
]:
    Path("bad.csv").write_text(text)
    try:
        bl.load_campaign("bad.csv", **kwargs)
    except bl.DataError as exc:
        print("DataError:", str(exc).replace(str(Path.cwd()) + "/", ""))
