"""One bounce at a time, as a simulator's loop calls a law: ``law.predict_one`` against hand-written Python.

Run: ``python benchmarks/bench_predict_one.py`` (about 10 s; ``--quick``, a second or two, for CI). In the
same run, with the same harness (``timeit`` of a statement that calls the function directly, no wrapper):
a hand-written pure-Python rigid bounce (the reference: plain arithmetic and comparisons, no builtins),
``law.predict_one`` of every closed-form law, and ``law.predict`` of one row (the array path). Targets:
Rigid's ``predict_one`` within 3x of the hand-written bounce (issue 34), with the same numbers, and no more
than 3 us for any closed-form law (issue 25), on a quiet machine. Medians of repeated timings, alternating
between the functions.

``--baseline PATH`` instead times ``law.predict`` of one row and ``law.predict_one`` (where the other version
has it), and CompliantImpact's (the integrated law whose per-call constant issue 23 moved out of the call),
in this checkout and in the bouncelab at PATH, alternating ``--rounds`` times, each in a fresh interpreter,
and prints the ratios.
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


def python_rigid(xd: float, yd: float, w: float, r: float, mu: float) -> tuple[float, float, float]:
    """The rigid bounce of eq. (rigid_bounce), written by hand for one landing: the tangential impulse that
    stops the contact point, capped by Coulomb friction mu (1 + r) |ydot0|."""
    cap = -mu * (1.0 + r) * yd
    j = -(xd + w) / 3.5
    if j > cap:
        j = cap
    elif j < -cap:
        j = -cap
    return xd + j, -r * yd, w + 2.5 * j


def per_call(statements: dict[str, str], names: dict, number: int, repeat: int) -> dict[str, float]:
    """Median seconds per call of each statement, timed in turn (``repeat`` rounds of ``number`` calls)."""
    times: dict[str, list[float]] = {k: [] for k in statements}
    for _ in range(repeat):
        for key, stmt in statements.items():
            times[key].append(timeit.timeit(stmt, globals=names, number=number) / number)
    return {k: float(np.median(v)) for k, v in times.items()}


_ONE_ROW = """
import json, sys, timeit
sys.path.insert(0, sys.argv[1])
import numpy as np
import bouncelab as bl
landing = [[1000.0, -800.0, 300.0]]
number = int(sys.argv[2])
laws = {"Rigid": bl.Rigid(r=0.5, mu=0.4), "PennerVarying": bl.PennerVarying(r=0.448, mu=0.969, k_p=1.543e-4),
        "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3),
        "PiecewiseAffine": bl.PiecewiseAffine.published("A").replace(offset=601.0),
        "CompliantImpact": bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)}
out = {}
for name, law in laws.items():
    law.predict(landing)
    out[name] = float(np.median(timeit.repeat(lambda: law.predict(landing), number=number, repeat=7))) / number
    if hasattr(law, "predict_one"):
        law.predict_one(*landing[0])
        one = timeit.repeat("law.predict_one(1000.0, -800.0, 300.0)", globals={"law": law}, number=10 * number,
                            repeat=7)
        out[name + " predict_one"] = float(np.median(one)) / (10 * number)
print(json.dumps({"module": bl.__file__, "us": {k: v * 1e6 for k, v in out.items()}}))
"""


def one_row(path: str, number: int) -> dict:
    """``predict`` of one row (and ``predict_one``) per law, microseconds, for the bouncelab at ``path``."""
    proc = subprocess.run([sys.executable, "-c", _ONE_ROW, os.path.abspath(path), str(number)], capture_output=True,
                          text=True, check=True)
    return json.loads(proc.stdout.splitlines()[-1])


def side_by_side(baseline: str, rounds: int, number: int) -> None:
    """``predict`` of one row here and at ``baseline``, alternating; medians over the rounds and the ratio."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ours: dict[str, list[float]] = {}
    theirs: dict[str, list[float]] = {}
    for _ in range(rounds):
        for path, into in ((here, ours), (baseline, theirs)):
            result = one_row(path, number)
            assert os.path.dirname(os.path.dirname(result["module"])) == os.path.abspath(path), result["module"]
            for name, us in result["us"].items():
                into.setdefault(name, []).append(us)
    print(f"one landing, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}: this bouncelab "
          f"against {baseline} ({rounds} alternating rounds, medians)")
    print(f"{'law and call':<36}{'this us':>10}{'baseline us':>13}{'speed-up':>10}")
    for name in ours:
        if name in theirs:
            a, b = float(np.median(ours[name])), float(np.median(theirs[name]))
            label = name if name.endswith("predict_one") else f"{name} predict(1 row)"
            print(f"{label:<36}{a:>10.2f}{b:>13.2f}{b / a:>9.2f}x")


def main(argv: list[str] | None = None) -> dict[str, dict[str, float]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a short run that checks the benchmark works (CI)")
    ap.add_argument("--baseline", help="path of another bouncelab checkout: time predict of one row side by side")
    ap.add_argument("--rounds", type=int, default=3, help="alternations with the baseline")
    args = ap.parse_args(argv)
    number, repeat = (2_000, 3) if args.quick else (50_000, 9)
    if args.baseline:
        side_by_side(args.baseline, 1 if args.quick else args.rounds, 200 if args.quick else 2000)
        return {}
    laws = {"Rigid": bl.Rigid(r=0.5, mu=0.4), "PennerFixed": bl.PennerFixed.published("A"),
            "PennerVarying": bl.PennerVarying.published("A"), "PiecewiseAffine": bl.PiecewiseAffine.published("A"),
            "TangentialRestitution": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3)}
    for law in laws.values():
        law.predict_one(*LANDING)  # compile / load outside the timing
        law.predict([LANDING])
    rigid = laws["Rigid"]
    same = rigid.predict_one(*LANDING) == python_rigid(*LANDING, 0.5, 0.4)
    names = {"python_rigid": python_rigid, **{f"law_{k}": v for k, v in laws.items()}}
    statements = {"python": "python_rigid(1000.0, -800.0, 300.0, 0.5, 0.4)"}
    statements |= {name: f"law_{name}.predict_one(1000.0, -800.0, 300.0)" for name in laws}
    times = per_call(statements, names, number, repeat)
    rows = per_call({name: f"law_{name}.predict([(1000.0, -800.0, 300.0)])" for name in laws}, names,
                    max(number // 20, 100), repeat)
    ref = times["python"]
    print(f"one bounce, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} (medians of {repeat} rounds of "
          f"{number:,} calls)")
    print(f"hand-written Python rigid bounce, called directly: {ref * 1e6:.3f} us; Rigid's predict_one gives the "
          f"same numbers: {same}")
    print(f"{'law':<24}{'predict_one us':>16}{'x Python':>10}{'predict(1 row) us':>20}  <=3 us  Rigid <= 3x")
    for name in laws:
        one = times[name]
        target = ("met" if one / ref <= 3 else "NOT") if name == "Rigid" else ""
        print(f"{name:<24}{one * 1e6:>16.3f}{one / ref:>10.2f}{rows[name] * 1e6:>20.1f}  "
              f"{'met' if one <= 3e-6 else 'NOT':<6}  {target}")
    return {"predict_one": times, "predict_row": rows}


if __name__ == "__main__":
    main()
