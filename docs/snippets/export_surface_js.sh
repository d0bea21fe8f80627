# The same green as an ES module, used by a web page's script; the script runs under Node as it is.
bouncelab export --surface green-medium --lang js -o green-medium.mjs
cat > rollout.mjs <<'JS'
import { run, bounce3d, SURFACE } from "./green-medium.mjs";

const rpm = 2 * Math.PI / 60;
// SI units, right-handed, z up; backspin for travel in +x is a negative y spin.
const shots = {
  "pitch": { v: [9.0, 0.0, -9.0], w: [0.0, -6000 * rpm, 0.0], n: [0, 0, 1] },
  "bump and run": { v: [7.5, 1.0, -1.8], w: [0.0, -800 * rpm, 0.0], n: [0.0, -0.025, 1.0] },
};
const lines = [`surface ${SURFACE}`];
for (const [name, s] of Object.entries(shots)) {
  const { rest, time, bounces } = run(s.v, s.w, s.n);
  const [vOut] = bounce3d(s.v, s.w, s.n);
  lines.push(`${name}: first lift-off ${vOut.map((x) => x.toFixed(5)).join(" ")} m/s; ${bounces} bounces, rest ` +
             `${rest.map((x) => x.toFixed(5)).join(" ")} m after ${time.toFixed(4)} s`);
}
try {
  run([5, 0, 2], [0, 0, 0], [0, 0, 1]);
} catch (e) {
  lines.push(`${e.name}: ${e.message}`);
}
if (typeof document !== "undefined") document.getElementById("out").textContent = lines.join("\n");
else console.log(lines.join("\n"));
JS
cat > index.html <<'HTML'
<!doctype html>
<meta charset="utf-8">
<title>Roll-out on green-medium</title>
<pre id="out"></pre>
<script type="module" src="rollout.mjs"></script>
HTML
node rollout.mjs
echo "# bouncelab.ground, the same shots:"
python - <<'PY'
import math
from bouncelab.ground import bounce, preset, run
rpm, green, si = 2 * math.pi / 60, preset("green-medium"), {"velocity": "m/s", "spin": "rad/s"}
shots = {"pitch": ([9.0, 0.0, -9.0], [0.0, -6000 * rpm, 0.0], [0, 0, 1]),
         "bump and run": ([7.5, 1.0, -1.8], [0.0, -800 * rpm, 0.0], [0.0, -0.025, 1.0])}
for name, (v, w, n) in shots.items():
    r = run(v, w, green, n, units=si)
    vo, _ = bounce(green, v, w, n, units=si)
    print(f"{name}: first lift-off {' '.join(f'{x:.5f}' for x in vo)} m/s; {int(r.totals['bounces'][0])} bounces, "
          f"rest {' '.join(f'{x:.5f}' for x in r.rest_position[0])} m after {r.rest_time[0]:.4f} s")
PY
