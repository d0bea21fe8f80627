# a lab sheet in m/s and rpm (spins all below 4800 rpm), whose spin columns give no unit
python - <<'PY'
import bouncelab as bl
from bouncelab.core import units
b = bl.load_campaign("B", surrogate="published")
p0 = units.from_scaled(b.landing.values, velocity="m/s", spin="rpm")
pf = units.from_scaled(b.liftoff.values, velocity="m/s", spin="rpm")
keep = (abs(p0[:, 2]) < 4800) & (abs(pf[:, 2]) < 4800)
with open("sheet.csv", "w") as f:
    f.write("xdot0,ydot0,omega0,xdotF,ydotF,omegaF\n")
    for row in zip(*p0[keep].T, *pf[keep].T):
        f.write(",".join(f"{x:.2f}" for x in row) + "\n")
PY
head -n 2 sheet.csv
bouncelab fit PennerFixed sheet.csv --velocity-unit m/s;                  echo "exit code $?"
bouncelab fit PennerFixed sheet.csv --velocity-unit m/s --spin-unit rpm | grep -E "^\[\[Fit|mu  |train all"
bouncelab predict Rigid --published A --landing 20 -15 3000;              echo "exit code $?"
bouncelab predict Rigid --published A --landing 20 -15 3000 --velocity-unit m/s --spin-unit rpm
bouncelab predict Rigid --published A --speed-angle-spin 20 0.65 3000 --velocity-unit m/s --spin-unit rpm; echo "exit code $?"
