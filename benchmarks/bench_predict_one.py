"""One bounce at a time, as a simulator's loop calls a law: ``law.predict_one`` against hand-written Python.

Run: ``python benchmarks/bench_predict_one.py`` (about 10 s). In the same run: a hand-written pure-Python
rigid bounce (the reference), ``law.predict_one`` of every closed-form law, and ``law.predict`` of one row
(the array path). Targets (issue 25): Rigid's ``predict_one`` within 5x of the hand-written bounce, and no
more than 3 us for any closed-form law, on a quiet machine. Medians of repeated timings.

``--baseline PATH`` instead times ``law.predict`` of one row (and CompliantImpact's, the integrated law
whose per-call constant issue 23 moved out of the call) in this checkout and in the bouncelab at PATH (a
checkout of another version, which may have no ``predict_one``), alternating ``--rounds`` times, each in a
fresh interpreter, and prints the ratios.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import timeit

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl

LANDING = (1000.0, -800.0, 300.0)


def python_rigid(xd: float, yd: float, w: float, r: float = 0.5, mu: float = 0.4) -> tuple[float, float, float]:
    """The rigid bounce of eq. (rigid_bounce), written by hand for one landing."""
    cap = -mu * (1.0 + r) * yd
    j = min(max(-(xd + w) / 3.5, -cap), cap)
    return xd + j, -r * yd, w + 2.5 * j


def per_call(f, number: int = 20_000, repeat: int = 7) -> float:
    """Median seconds per call."""
    return float(np.median(timeit.repeat(f, number=number, repeat=repeat))) / number


_ONE_ROW = """
import json, sys, timeit
sys.path.insert(0, sys.argv[1])
import numpy as np
import bouncelab as bl
landing = [[1000.0, -800.0, 300.0]]
laws = {"Rigid": bl.Rigid(r=0.5, mu=0.4), "PennerVarying": bl.PennerVarying(r=0.448, mu=0.969, k_p=1.543e-4),
        "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3),
        "CompliantImpact": bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)}
out = {}
for name, law in laws.items():
    law.predict(landing)
    out[name] = float(np.median(timeit.repeat(lambda: law.predict(landing), number=2000, repeat=7))) / 2000
print(json.dumps({"module": bl.__file__, "us": {k: v * 1e6 for k, v in out.items()}}))
"""


def one_row(path: str) -> dict:
    """``predict`` of one row per law, microseconds, for the bouncelab at ``path`` (a fresh interpreter)."""
    proc = subprocess.run([sys.executable, "-c", _ONE_ROW, os.path.abspath(path)], capture_output=True, text=True,
                          check=True)
    return json.loads(proc.stdout.splitlines()[-1])


def side_by_side(baseline: str, rounds: int) -> None:
    """``predict`` of one row here and at ``baseline``, alternating; medians over the rounds and the ratio."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ours: dict[str, list[float]] = {}
    theirs: dict[str, list[float]] = {}
    for _ in range(rounds):
        for path, into in ((here, ours), (baseline, theirs)):
            result = one_row(path)
            assert os.path.dirname(os.path.dirname(result["module"])) == os.path.abspath(path), result["module"]
            for name, us in result["us"].items():
                into.setdefault(name, []).append(us)
    print(f"predict of one row, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}: this bouncelab "
          f"against {baseline} ({rounds} alternating rounds, medians)")
    print(f"{'law':<24}{'this us':>10}{'baseline us':>13}{'speed-up':>10}")
    for name in ours:
        a, b = float(np.median(ours[name])), float(np.median(theirs[name]))
        print(f"{name:<24}{a:>10.1f}{b:>13.1f}{b / a:>9.2f}x")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", help="path of another bouncelab checkout: time predict of one row side by side")
    ap.add_argument("--rounds", type=int, default=3, help="alternations with the baseline")
    args = ap.parse_args(argv)
    if args.baseline:
        side_by_side(args.baseline, args.rounds)
        return
    laws = {"Rigid": bl.Rigid(r=0.5, mu=0.4), "PennerFixed": bl.PennerFixed.published("A"),
            "PennerVarying": bl.PennerVarying.published("A"), "PiecewiseAffine": bl.PiecewiseAffine.published("A"),
            "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3)}
    for law in laws.values():
        law.predict_one(*LANDING)  # compile / load outside the timing
        law.predict([LANDING])
    ref = per_call(lambda: python_rigid(*LANDING))
    print(f"one bounce, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}")
    print(f"hand-written Python rigid bounce: {ref * 1e6:.2f} us")
    print(f"{'law':<24}{'predict_one us':>16}{'x Python':>10}{'predict(1 row) us':>20}  <=3 us")
    for name, law in laws.items():
        one = per_call(lambda law=law: law.predict_one(*LANDING))
        row = per_call(lambda law=law: law.predict([LANDING]), number=2000)
        print(f"{name:<24}{one * 1e6:>16.2f}{one / ref:>10.1f}{row * 1e6:>20.1f}  {'met' if one <= 3e-6 else 'NOT'}")


if __name__ == "__main__":
    main()
