# The same law as an ES module, called from Node.
bouncelab fit Rigid A --method structured --save rigid_A.json > /dev/null
bouncelab export rigid_A.json --lang js -o rigid_A.mjs 2> /dev/null
cat > main.mjs <<'JS'
import { LAW, PARAMETERS, REGIMES, predict, predictOne } from "./rigid_A.mjs";

console.log(LAW, PARAMETERS);
console.log(predict([[1000, -800, 300], [600, -900, 1500]]));  // rows [xdot, ydot, omega], radii/s and rad/s
const [xdot, ydot, omega, code] = predictOne(600, -900, 1500);
console.log(xdot, ydot, omega, REGIMES[code]);
JS
node main.mjs
