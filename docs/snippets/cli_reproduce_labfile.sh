# A stand-in for a lab file: 40 launcher shots (m/s, degrees, rpm), a units row, three empty cells.
python - <<'PY'
import numpy as np, bouncelab as bl
from bouncelab.core.units import polar_from_state, state_from_polar
rng = np.random.default_rng(7)
polar = np.column_stack([rng.uniform(15, 30, 40), rng.uniform(25, 60, 40), rng.uniform(500, 5000, 40)])
landing = state_from_polar(polar, kind="landing")
liftoff = bl.Rigid(r=0.5, mu=0.3).predict(landing) * (1 + 0.02 * rng.standard_normal((40, 3)))
rows = np.column_stack([polar, polar_from_state(liftoff, kind="liftoff")]).round(2).astype(str)
rows[[4, 17, 30], [5, 1, 3]] = ""
lines = ["speed_in,angle_in,spin_in,speed_out,angle_out,spin_out", "m/s,deg,rpm,m/s,deg,rpm", *map(",".join, rows)]
open("my_bounces.csv", "w").write("\n".join(lines) + "\n")
PY
bouncelab reproduce --data my_bounces.csv --velocity-unit m/s --spin-unit rpm --laws Rigid PennerFixed \
  --bootstrap 20 --no-figures --quiet --out report
echo "exit code $?"
