"""Use a bounce law inside a simple golf-ball trajectory simulation: fly, bounce, fly, bounce...

What it shows
    * a flight model in SI units: gravity plus quadratic air drag,
      ``a = -g y_hat - K |v| v`` with ``K = rho C_d pi R^2 / (2 m)``, using the constants of
      :mod:`bouncelab.analysis.trajectories` (air density 1.2 kg/m^3, drag coefficient 0.25,
      ball mass 45.9 g, radius 21.35 mm, so K = 4.68e-3 1/m). Spin is held constant in flight
      and the Magnus lift is ignored, so the ball is started on its way down (4 m up,
      26 m/s at 33 degrees below the horizontal, 34.9 rev/s of backspin) rather than from a tee;
    * touch-down found as an event of the ODE solver (the ball's centre one radius above the
      ground);
    * the bounce law applied at touch-down, converting the state to the paper's scaled units
      with :mod:`bouncelab.core.units` on the way in and back to m/s and rad/s on the way out;
    * several bounces in a row, until the ball hops less than ``--min-hop`` (then it rolls)
      or ``--max-bounces`` is reached.

By default the law is Penner's fixed-angle law fitted to campaign B (the embedded synthetic
surrogate of the paper's natural-turf campaign, simulated from turf physics). ``--published`` uses the paper's published
values instead, and ``--law`` picks another law. Try ``--law PiecewiseAffine --published``:
its offset ``b`` gives every lift-off an upward velocity of at least about 0.5 m/s, so the
ball never settles -- the paper's own caution about that law.

Run it from the repository root (a few seconds)::

    python examples/trajectory_with_bounce.py [--law PennerFixed] [--campaign B] [--published]
                                              [--max-bounces 20] [--min-hop 0.01] [--plot]

``--plot`` draws the path to a PNG in a new temporary directory (Agg backend) and prints its path.
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

from scipy.integrate import solve_ivp

import bouncelab as bl
from bouncelab.analysis.trajectories import AIR_DENSITY, BALL_MASS_KG, DRAG_COEFFICIENT, GRAVITY
from bouncelab.core import units

RADIUS = units.BALL_RADIUS_M  # m
#: Quadratic-drag coefficient K in a = -K |v| v, 1/m.
K_DRAG = AIR_DENSITY * DRAG_COEFFICIENT * math.pi * RADIUS**2 / (2.0 * BALL_MASS_KG)

START = {"x": 0.0, "y": 4.0, "speed": 26.0, "angle_deg": 33.0, "spin_rev_s": 34.9}


def fly(x: float, y: float, vx: float, vy: float, t_max: float = 30.0):
    """Integrate the flight until the ball's centre comes down to one radius above the ground.

    Returns the path (t, x, y) and the velocity (vx, vy) at touch-down, SI units.
    """

    def rhs(_t, s):
        speed = math.hypot(s[2], s[3])
        return [s[2], s[3], -K_DRAG * speed * s[2], -GRAVITY - K_DRAG * speed * s[3]]

    def touchdown(_t, s):
        return s[1] - RADIUS

    touchdown.terminal = True
    touchdown.direction = -1
    sol = solve_ivp(rhs, (0.0, t_max), [x, y + 1e-9, vx, vy], events=touchdown, max_step=0.01,
                    rtol=1e-9, atol=1e-12)
    if not sol.t_events[0].size:
        raise RuntimeError("the ball did not come down within t_max")
    end = sol.y_events[0][0]
    return (sol.t, sol.y[0], sol.y[1]), (end[0], end[2], end[3])


def bounce(law: bl.BounceModel, vx: float, vy: float, omega: float):
    """Lift-off velocity (m/s) and spin (rad/s) from the landing ones, through the law in scaled units."""
    landing = units.to_scaled([vx, vy, omega], velocity="m/s", spin="rad/s")  # radii/s, radii/s, rad/s
    # plausible=None: the simulation's own states, not numbers typed by a person. The unit guard would refuse
    # the last hops of a ball coming to rest (slower than 1 m/s or flatter than 5 degrees: no measured bounce).
    liftoff = law.predict(landing, plausible=None)
    regime = str(law.regime(landing, plausible=None))
    vx_f, vy_f, omega_f = units.from_scaled(liftoff, velocity="m/s", spin="rad/s")
    return float(vx_f), float(vy_f), float(omega_f), regime


def choose_law(name: str, campaign: str, published: bool) -> bl.BounceModel:
    cls = bl.laws.registered_laws()[name]
    if published:
        return cls.published(campaign)
    return bl.fit(cls, bl.load_campaign(campaign), seed=0).model


def describe(vx: float, vy: float, omega: float) -> str:
    """Speed, angle below the horizontal and spin of a state in m/s and rad/s (via the scaled state)."""
    scaled = units.to_scaled([vx, vy, omega], velocity="m/s", spin="rad/s")
    s = units.speed_angle_spin(scaled, speed_unit="m/s", spin_unit="rpm")
    return f"{float(s['speed']):5.2f} m/s {float(s['angle_deg']):6.1f} deg {float(s['spin']):7.0f} rpm"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--law", default="PennerFixed", choices=sorted(bl.laws.registered_laws()))
    parser.add_argument("--campaign", default="B", choices=["A", "B"], help="campaign to fit (or published values of)")
    parser.add_argument("--published", action="store_true", help="use the paper's published values")
    parser.add_argument("--max-bounces", type=int, default=20)
    parser.add_argument("--min-hop", type=float, default=0.01, help="stop when a hop is lower than this (m)")
    parser.add_argument("--plot", action="store_true", help="draw the path to a PNG in a temporary directory")
    args = parser.parse_args(argv)

    law = choose_law(args.law, args.campaign, args.published)
    source = "published" if args.published else "fitted to"
    print(f"law: {law!r} ({source} campaign {args.campaign})")
    print(f"flight: gravity {GRAVITY} m/s^2, quadratic drag K = {K_DRAG:.3e} 1/m "
          f"(rho {AIR_DENSITY} kg/m^3, C_d {DRAG_COEFFICIENT}, m {BALL_MASS_KG} kg, R {RADIUS} m); "
          "no Magnus lift, constant spin in flight")

    angle = math.radians(START["angle_deg"])
    x, y = START["x"], START["y"]
    vx, vy = START["speed"] * math.cos(angle), -START["speed"] * math.sin(angle)
    omega = units.spin_to_scaled(START["spin_rev_s"], "rev/s")  # rad/s, positive = backspin
    print(f"start: x {x} m, height {y} m, {describe(vx, vy, omega)} (angle below the horizontal)\n")
    print(f"{'#':>2} {'x [m]':>7}  {'landing: speed, angle below horizontal, spin':<45} "
          f"{'lift-off: speed, angle above horizontal, spin':<45} {'regime':<13} {'hop [m]':>7}")

    paths = []
    for k in range(1, args.max_bounces + 1):
        path, (x, vx, vy) = fly(x, y, vx, vy)
        paths.append(path)
        y = RADIUS
        land = describe(vx, vy, omega)
        vx, vy, omega, regime = bounce(law, vx, vy, omega)
        hop = vy**2 / (2.0 * GRAVITY) if vy > 0 else 0.0  # apex height without drag
        print(f"{k:>2} {x:>7.2f}  {land:<45} {describe(vx, -vy, omega):<45} {regime:<13} {hop:>7.3f}")
        if vy <= 0 or hop < args.min_hop:
            print(f"\nthe ball no longer leaves the ground (hop below {args.min_hop} m): it rolls on "
                  f"from x = {x:.2f} m at {vx:.2f} m/s with {units.spin_from_scaled(omega, 'rpm'):.0f} rpm")
            break
    else:
        print(f"\nstill hopping after {args.max_bounces} bounces (x = {x:.2f} m)")

    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 3), layout="constrained")
        for _t, px, py in paths:
            ax.plot(px, py, color="tab:blue")
        ax.axhline(0.0, color="tab:green")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("height of the centre [m]")
        ax.set_title(f"{type(law).__name__} bounces ({source} campaign {args.campaign})")
        out = Path(tempfile.mkdtemp(prefix="bouncelab-trajectory-")) / "trajectory.png"
        fig.savefig(out, dpi=100)
        plt.close(fig)
        print(f"path drawn to {out}")


if __name__ == "__main__":
    main()
