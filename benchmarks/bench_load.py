"""Loading a large CSV file: ``bouncelab.load_campaign`` against ``pandas.read_csv`` + the same checks.

Run: ``python benchmarks/bench_load.py`` (10^6 rows, about 20 s) or ``--rows N`` (``--quick``: 60,000 rows, above
the size where the compiled checks start, best of 2, for CI). The file is
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
    ds = bl.load_campaign("B", surrogate="published")
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


_PEAK_CHILD = """
import sys
def vm(key):
    for line in open('/proc/self/status'):
        if line.startswith(key):
            return int(line.split()[1]) * 1024
import bouncelab as bl, pandas as pd, numpy as np
sys.path.insert(0, sys.argv[3])
from bench_load import pandas_with_checks, write_file
import tempfile, pathlib
small = pathlib.Path(tempfile.mkdtemp()) / 'small.csv'
write_file(small, 50_000)  # above the size where compiled checks start
warm = bl.load_campaign(small) if sys.argv[1] == 'bouncelab' else pandas_with_checks(small)  # first-call costs
del warm
before = vm('VmRSS:')
out = bl.load_campaign(sys.argv[2]) if sys.argv[1] == 'bouncelab' else pandas_with_checks(sys.argv[2])
print(vm('VmHWM:') - before)
"""


def peak_memory(which: str, path: Path) -> int | None:
    """Peak resident memory a load adds, in bytes, measured in a fresh interpreter after one small load (the
    imports and first-call costs, as in the timings, are not the file's); Linux /proc, else None."""
    import subprocess

    if not Path("/proc/self/status").exists():
        return None
    proc = subprocess.run([sys.executable, "-c", _PEAK_CHILD, which, str(path), os.path.dirname(__file__)],
                          capture_output=True, text=True, check=True)
    return int(proc.stdout.split()[-1])


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=None, help="rows of the file (default 10^6; 60,000 with --quick)")
    ap.add_argument("--repeats", type=int, default=None, help="timings of each side (default 3; 2 with --quick)")
    ap.add_argument("--quick", action="store_true", help="a small file: checks the benchmark runs (CI)")
    args = ap.parse_args(argv)
    args.rows = args.rows or (60_000 if args.quick else 1_000_000)
    args.repeats = args.repeats or (2 if args.quick else 3)
    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-load-") as tmp:
        path = Path(tmp) / "bounces.csv"
        write_file(path, args.rows)
        size = path.stat().st_size / 1e6
        bl.load_campaign(path)  # imports and first-call costs out of the timing
        ours, ds = best_of(lambda: bl.load_campaign(path), args.repeats)
        peer, (landing, liftoff, _) = best_of(lambda: pandas_with_checks(path), args.repeats)
        mem = {which: peak_memory(which, path) for which in ("bouncelab", "pandas")}
        file_bytes = path.stat().st_size
    agree = bool(np.array_equal(ds.landing.values, landing) and np.array_equal(ds.liftoff.values, liftoff))
    ratio = ours / peer
    print(f"load a {args.rows:,}-row CSV file ({size:.0f} MB), {os.cpu_count()} cores, best of {args.repeats}")
    at_size = ("met" if ours < 3 else "NOT MET") if args.rows == 1_000_000 else "(it is set for 10^6 rows)"
    print(f"{'bouncelab.load_campaign':<34}{ours:>8.2f} s   target < 3 s: {at_size}")
    print(f"{'pandas.read_csv + checks':<34}{peer:>8.2f} s")
    print(f"{'ratio':<34}{ratio:>8.2f} x   target <= 3x: {'met' if ratio <= 3 else 'NOT MET'}")
    if mem["bouncelab"] is not None:
        ours_x, peer_x = mem["bouncelab"] / file_bytes, mem["pandas"] / file_bytes
        print(f"{'peak memory added, bouncelab':<34}{mem['bouncelab'] / 1e6:>8.0f} MB = {ours_x:.2f}x the file   "
              f"target < 3x: {'met' if ours_x < 3 else 'NOT MET'}")
        print(f"{'peak memory added, pandas + checks':<34}{mem['pandas'] / 1e6:>8.0f} MB = {peer_x:.2f}x the file")
    print(f"same numbers: {agree}")
    return {"rows": args.rows, "bouncelab_s": ours, "pandas_s": peer, "ratio": ratio, "agree": agree,
            "bouncelab_peak_bytes": mem["bouncelab"], "pandas_peak_bytes": mem["pandas"], "file_bytes": file_bytes}


if __name__ == "__main__":
    main()
