# A preset green's whole ground phase as a C header, dropped into a C++ simulator's loop.
bouncelab export --surface green-medium --lang c -o green.h
cat > sim.cpp <<'CPP'
#include <cmath>
#include <cstdio>
#include <vector>
#include "green.h"

// SI units, right-handed, z up; spin is the angular-velocity vector (backspin in +x: negative y).
struct Shot { const char *name; double v[3], w[3], n[3]; };

int main() {
    const double rpm = 2.0 * M_PI / 60.0, a = 37.3 * M_PI / 180.0;
    std::vector<Shot> shots = {
        {"driver", {28.53 * std::cos(a), 0.0, -28.53 * std::sin(a)}, {0.0, -2094.0 * rpm, 0.0}, {0.0, 0.0, 1.0}},
        // 11 m/s at 52 degrees heading 30 degrees left, 8500 rpm backspin, 500 rpm sidespin, down a 2 % slope
        {"wedge", {5.87, 3.39, -8.67}, {4250.0 * rpm, -7360.0 * rpm, 500.0 * rpm}, {0.0, 0.02, 1.0}},
        {"chip", {6.5, 0.0, -2.4}, {0.0, -1500.0 * rpm, 0.0}, {-0.03, 0.0, 1.0}},  // into a 3 % upslope
        {"putt", {1.83, 0.0, 0.0}, {0.0, 1.83 / 0.02135, 0.0}, {0.0, 0.0, 1.0}},  // rolling off the Stimpmeter
    };
    for (const Shot &s : shots) {
        double rest[3], t;
        int bounces = bouncelab_run(s.v, s.w, s.n, rest, &t);
        std::printf("%-6s %2d bounces, rest at (%9.5f, %8.5f, %8.5f) m after %.4f s\n", s.name, bounces, rest[0],
                    rest[1], rest[2], t);
    }
    double v_out[3], w_out[3];  // one bounce: the driver's first lift-off
    bouncelab_bounce3d(shots[0].v, shots[0].w, shots[0].n, v_out, w_out);
    std::printf("driver lifts off at (%.5f, %.5f, %.5f) m/s, spin (%.4f, %.4f, %.4f) rad/s\n", v_out[0], v_out[1],
                v_out[2], w_out[0], w_out[1], w_out[2]);
    const double steep[3] = {0.0, std::sin(0.1), std::cos(0.1)};  // 5.7 degrees: steeper than a ball rests on
    double rest[3], t;
    int code = bouncelab_run(shots[0].v, shots[0].w, steep, rest, &t);
    std::printf("refused: %d (%s)\n", code, bouncelab_refusal(code));
    return 0;
}
CPP
c++ -std=c++11 -O2 -ffp-contract=off -Wall -Wextra -Werror sim.cpp -o sim && ./sim
echo "# bouncelab.ground, the same shots:"
python - <<'PY'
import math
from bouncelab.ground import bounce, preset, run
rpm, a, green = 2 * math.pi / 60, math.radians(37.3), preset("green-medium")
shots = [("driver", [28.53 * math.cos(a), 0, -28.53 * math.sin(a)], [0, -2094 * rpm, 0], [0, 0, 1]),
         ("wedge", [5.87, 3.39, -8.67], [4250 * rpm, -7360 * rpm, 500 * rpm], [0, 0.02, 1]),
         ("chip", [6.5, 0, -2.4], [0, -1500 * rpm, 0], [-0.03, 0, 1]),
         ("putt", [1.83, 0, 0], [0, 1.83 / 0.02135, 0], [0, 0, 1])]
si = {"velocity": "m/s", "spin": "rad/s"}
for name, v, w, n in shots:
    r = run(v, w, green, n, units=si)
    x, y, z = r.rest_position[0]
    print(f"{name:<6} {int(r.totals['bounces'][0]):2d} bounces, rest at ({x:9.5f}, {y:8.5f}, {z:8.5f}) m after "
          f"{r.rest_time[0]:.4f} s")
vo, wo = bounce(green, shots[0][1], shots[0][2], units=si)
print("driver lifts off at ({:.5f}, {:.5f}, {:.5f}) m/s, spin ({:.4f}, {:.4f}, {:.4f}) rad/s".format(*vo, *wo))
PY
