# The same law as an ES module, called from Node: typed arrays in and out, one bounce without allocating.
bouncelab fit Rigid A --method structured --save rigid_A.json > /dev/null
bouncelab export rigid_A.json --lang js -o rigid_A.mjs 2> /dev/null
cat > main.mjs <<'JS'
import { LAW, PARAMETERS, REGIMES, predict, predictOne } from "./rigid_A.mjs";

console.log(LAW, PARAMETERS);
const landings = new Float64Array([1000, -800, 300, 600, -900, 1500]);  // xdot, ydot, omega a landing
console.log(predict(landings));                     // a Float64Array of lift-offs, three numbers each
const out = new Float64Array(3);
const code = predictOne(600, -900, 1500, out);      // into out: allocates nothing
console.log(Array.from(out), REGIMES[code]);
JS
node main.mjs
