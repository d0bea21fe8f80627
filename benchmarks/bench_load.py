"""Loading a large CSV file: ``bouncelab.load_campaign`` against ``pandas.read_csv`` + the same checks.

Run: ``python benchmarks/bench_load.py`` (10^6 rows, about 20 s) or ``--rows N``. The file is
written in a temporary folder from campaign B's bounces (repeated), with a header such as
``xdot0 (radii/s)``; both sides read the same file in the same run, each the best of
``--repeats`` (default 3). The peer is what a script would do by hand: ``pandas.read_csv``, then
check there are seven columns, that the six state columns are numbers, all finite, with every
landing moving down, and build the (n, 3) landing and lift-off arrays. bouncelab does more
(finds the columns and their units, checks the plausible ranges, types the settings, builds the
campaign Dataset). Targets (issue 7 item 8): 10^6 rows in under 3 s, and within 3x the peer.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl

HEADER = ("setting,xdot0 (radii/s),ydot0 (radii/s),omega0 (rad/s),"
          "xdotF (radii/s),ydotF (radii/s),omegaF (rad/s)")


def write_file(path: Path, rows: int) -> None:
    """``rows`` bounces of campaign B, repeated, full precision (17 significant digits)."""
    ds = bl.load_campaign("B")
    idx = np.arange(rows) % ds.sizes["bounce"]
    table = np.column_stack([ds.setting.values[idx], ds.landing.values[idx], ds.liftoff.values[idx]])
    with open(path, "w") as f:
        f.write(HEADER + "\n")
        np.savetxt(f, table, delimiter=",", fmt=["%d"] + ["%.17g"] * 6)


def pandas_with_checks(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The peer: ``pandas.read_csv`` and the checks a careful script would make."""
    frame = pd.read_csv(path)
    if frame.shape[1] != 7:
        raise ValueError(f"expected 7 columns, got {frame.shape[1]}")
    states = frame.iloc[:, 1:].to_numpy()
    if states.dtype.kind != "f" or not np.isfinite(states).all():
        raise ValueError("non-numeric or non-finite state values")
    if frame.iloc[:, 0].isna().any():
        raise ValueError("missing setting")
    landing, liftoff = states[:, :3].copy(), states[:, 3:].copy()
    if (landing[:, 1] >= 0).any():
        raise ValueError("a landing moving up")
    return landing, liftoff, frame.iloc[:, 0].to_numpy()


def best_of(f, repeats: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeats):
        t = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-load-") as tmp:
        path = Path(tmp) / "bounces.csv"
        write_file(path, args.rows)
        size = path.stat().st_size / 1e6
        bl.load_campaign(path)  # imports and first-call costs out of the timing
        ours, ds = best_of(lambda: bl.load_campaign(path), args.repeats)
        peer, (landing, liftoff, _) = best_of(lambda: pandas_with_checks(path), args.repeats)
    agree = bool(np.array_equal(ds.landing.values, landing) and np.array_equal(ds.liftoff.values, liftoff))
    ratio = ours / peer
    print(f"load a {args.rows:,}-row CSV file ({size:.0f} MB), {os.cpu_count()} cores, best of {args.repeats}")
    print(f"{'bouncelab.load_campaign':<34}{ours:>8.2f} s   target < 3 s: {'met' if ours < 3 else 'NOT MET'}")
    print(f"{'pandas.read_csv + checks':<34}{peer:>8.2f} s")
    print(f"{'ratio':<34}{ratio:>8.2f} x   target <= 3x: {'met' if ratio <= 3 else 'NOT MET'}")
    print(f"same numbers: {agree}")
    return {"rows": args.rows, "bouncelab_s": ours, "pandas_s": peer, "ratio": ratio, "agree": agree}


if __name__ == "__main__":
    main()
