"""How close can a continuous contact law come to the paper's piecewise-affine law? (issue 10)

The calibration (``benchmarks/calibrate_surrogates.py``) asks a turf model to give back, through a
simulated camera, the errors the paper reports for its published laws. Its best turf misses the
target; this script measures why, without any simulation or noise:

1. **Floor.** Each candidate law (``--laws``; default the physical and rigid-family laws) is fitted
   by ``bouncelab.fit`` to the *noise-free* predictions of the published piecewise-affine law on
   the embedded landings. Its delta is how far the best law of that family stays from the paper's
   fitted map. A surrogate made from that law cannot make the published piecewise law look much
   better than that: the paper's own 6.56 % (A) and 7.84 % (B) include its measurement noise, so
   a surrogate whose floor is above them cannot give them back.
2. **Jump.** The published piecewise law is discontinuous at its slip/roll plane: for the
   landings near the plane (within ``--near`` of ||p0||) the script prints the median size of
   the jump between its two affine maps, relative to ||p0||.
3. **Rolling lift-offs.** For the noise-free published law and each fitted law, the fraction of
   bounces lifting off with |v_P| = |xdot_F + omega_F| < 0.02 ||p0||. A continuous law that maps
   the slip side to v_P > 0 and the roll side to v_P < 0 must pass through v_P = 0 in between;
   the jump is what lets the paper's law (and the paper's balls) avoid it.

The landings are those of the published surrogate (``--landings published``, the default) or the true
landings of the shipped turf surrogate's simulation (``--landings turf``:
``bouncelab.simulation.surrogate.generate_turf_surrogate(key)["true_landing"]``), to see how much the
launcher's landings move the floor.

Run: ``python benchmarks/surrogate_limits.py`` (about 3 min on 2 cores, most of it fitting CraterContact).
``--quick`` (CI): campaign A and three of the laws (Rigid, PennerFixed, CompliantImpact), a few seconds;
options given beside it win.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.simulation.calibration import ROLLING_THRESHOLD

DEFAULT_LAWS = ("Rigid", "PennerFixed", "TangentialRestitution", "CompliantImpact", "TurfContact", "CraterContact")
QUICK_LAWS = ("Rigid", "PennerFixed", "CompliantImpact")


def rolling_fraction(p0: np.ndarray, pf: np.ndarray) -> float:
    """Fraction of bounces with |xdot_F + omega_F| < ROLLING_THRESHOLD * ||p0||."""
    return float(np.mean(np.abs(pf[:, 0] + pf[:, 2]) < ROLLING_THRESHOLD * np.linalg.norm(p0, axis=1)))


def plane_jump(law: bl.PiecewiseAffine, p0: np.ndarray, near: float) -> tuple[int, float, float]:
    """(number of landings near the plane, median jump there, median jump over all), relative to ||p0||."""
    u, d = law.plane_unit_form()
    norm = np.linalg.norm(p0, axis=1)
    jump = p0 @ (law.A1 - law.A2).T + (law.b1 - law.b2)
    rel = np.linalg.norm(jump, axis=1) / norm
    close = np.abs(p0 @ u - d) < near * norm
    return int(close.sum()), float(np.median(rel[close])) if close.any() else float("nan"), float(np.median(rel))


def main(argv: list[str] | None = None) -> dict[str, dict[str, dict[str, float]]]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--campaign", choices=("A", "B"), action="append", help="default: both")
    parser.add_argument("--laws", nargs="+", default=None,
                        help="laws to fit (names or module:Class; default: six laws, three with --quick)")
    parser.add_argument("--near", type=float, default=0.05, help="'near the plane' as a fraction of ||p0||")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--landings", choices=("published", "turf"), default="published",
                        help="the published surrogate's landings, or the turf surrogate's true (simulated) ones")
    parser.add_argument("--quick", action="store_true", help="campaign A, three laws: checks the script runs (CI)")
    args = parser.parse_args(argv)
    laws = args.laws or list(QUICK_LAWS if args.quick else DEFAULT_LAWS)
    out: dict[str, dict[str, dict[str, float]]] = {}
    for key in args.campaign or (["A"] if args.quick else ["A", "B"]):
        if args.landings == "turf":
            from bouncelab.simulation.surrogate import generate_turf_surrogate

            p0 = generate_turf_surrogate(key)["true_landing"].values
        else:
            p0 = bl.load_campaign(key, surrogate="published")["landing"].values
        published = bl.PiecewiseAffine.published(key)
        target = np.asarray(published.predict(p0))
        n_near, jump_near, jump_all = plane_jump(published, p0, args.near)
        print(f"\ncampaign {key}: {len(p0)} {args.landings} landings; published piecewise law, noise-free")
        print(f"  jump between its two maps: median {jump_all:.3f} ||p0|| over all landings, "
              f"{jump_near:.3f} ||p0|| over the {n_near} within {args.near:g} ||p0|| of its plane")
        print(f"  rolling lift-offs (|v_P| < {ROLLING_THRESHOLD:g} ||p0||): {rolling_fraction(p0, target):.1%}")
        rows = {"PiecewiseAffine (published)": {"rolling_liftoff_fraction": rolling_fraction(p0, target),
                                                "jump_near_plane": jump_near, "n_near_plane": n_near}}
        print(f"  {'law fitted to it':<24} {'delta (floor)':>13} {'rolling lift-offs':>18} {'fit time':>9}")
        for name in laws:
            start = time.perf_counter()
            result = bl.fit(name, (p0, target), seed=args.seed)
            elapsed = time.perf_counter() - start
            rolling = rolling_fraction(p0, np.asarray(result.model.predict(p0)))
            rows[name] = {"delta_floor": float(result.delta), "rolling_liftoff_fraction": rolling}
            print(f"  {name:<24} {result.delta:>13.4f} {rolling:>18.1%} {elapsed:>8.1f}s")
        out[key] = rows
    return out


if __name__ == "__main__":
    main()
