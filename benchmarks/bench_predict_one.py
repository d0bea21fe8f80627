"""One bounce at a time, as a simulator's loop calls a law: ``law.predict_one`` against hand-written Python.

Run: ``python benchmarks/bench_predict_one.py`` (about 10 s). In the same run: a hand-written pure-Python
rigid bounce (the reference), ``law.predict_one`` of every closed-form law, and ``law.predict`` of one row
(the array path). Targets (issue 25): Rigid's ``predict_one`` within 5x of the hand-written bounce, and no
more than 3 us for any closed-form law, on a quiet machine. Medians of repeated timings.
"""

from __future__ import annotations

import os
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


def main() -> None:
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
