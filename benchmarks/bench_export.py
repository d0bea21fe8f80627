"""The exported C Rigid law (``law.to_c()``) on one core, beside ``law.predict`` and a Python per-bounce loop.

Run: ``python benchmarks/bench_export.py`` (about 30 s; needs ``cc``). The Rigid law with the paper's
values for campaign A is exported, compiled with ``cc -std=c99 -O2 -ffp-contract=off`` and timed calling
``bouncelab_predict`` on the same landings as the Python side: a large batch (streamed from memory) and a
small one that stays in cache, each the median of repeats, single-threaded by construction. Beside it:
``law.predict`` on the whole batch (one thread, and bouncelab's default threads), and the per-bounce loop
an exported law replaces in a simulator written in Python: ``law.predict`` on one landing at a time, and
the same formula in plain Python floats (the kernel's Python source, ``rigid_kernel.py_func``). The C
results are checked against ``law.predict`` first. Target (issue 25, item 6): at least 100 M bounces/s
for the exported Rigid law on one core. Times vary with the machine's load: indicative unless quiet.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from bouncelab.laws import num_threads, set_num_threads
from bouncelab.laws._kernels import rigid_kernel

BENCH_C = r"""
#define _POSIX_C_SOURCE 199309L  /* clock_gettime under -std=c99 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "rigid.h"

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* usage: bench IN N OUT SMALL REPEATS: prints the median seconds of a call on all N and on the first SMALL */
int main(int argc, char **argv) {
    if (argc != 6) return 2;
    long n = atol(argv[2]), small = atol(argv[4]);
    int repeats = atoi(argv[5]);
    double *p = malloc(24 * n), *out = malloc(24 * n), *times = malloc(sizeof(double) * repeats);
    FILE *f = fopen(argv[1], "rb");
    if (!f || fread(p, 8, 3 * n, f) != (size_t)(3 * n)) return 3;
    fclose(f);
    bouncelab_predict(p, out, n);  /* warm up, and the results Python checks */
    f = fopen(argv[3], "wb");
    fwrite(out, 8, 3 * n, f);
    fclose(f);
    for (int r = 0; r < repeats; r++) {
        double t = now();
        bouncelab_predict(p, out, n);
        times[r] = now() - t;
    }
    qsort(times, repeats, sizeof(double), cmp);
    printf("%.9g\n", times[repeats / 2]);
    long loops = (long)(20 * n / small);  /* the same bounces in all, a batch that stays in cache */
    for (int r = 0; r < repeats; r++) {
        double t = now();
        for (long k = 0; k < loops; k++) bouncelab_predict(p, out, small);
        times[r] = (now() - t) / loops;
    }
    qsort(times, repeats, sizeof(double), cmp);
    printf("%.9g\n", times[repeats / 2]);
    double check = 0;
    for (long i = 0; i < 3 * small; i++) check += out[i];
    fprintf(stderr, "checksum %g\n", check);
    return 0;
}
"""


def landings(n: int, seed: int = 0) -> np.ndarray:
    """Landings over the paper's Table 1 ranges (scaled units), as benchmarks/bench_predict.py draws them."""
    rng = np.random.default_rng(seed)
    xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
    return np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])


def median_time(f, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=2_000_000, help="landings of the large batch (default 2e6)")
    ap.add_argument("--small", type=int, default=10_000, help="landings of the in-cache batch (default 1e4)")
    ap.add_argument("--loop", type=int, default=20_000, help="landings of the per-bounce loops (default 2e4)")
    ap.add_argument("--repeats", type=int, default=9)
    args = ap.parse_args()
    cc = shutil.which("cc")
    if cc is None:
        raise SystemExit("no C compiler: `cc` is not on PATH")

    law = bl.Rigid.published("A")
    p = landings(args.n)
    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-") as tmp:
        folder = Path(tmp)
        law.to_c(folder / "rigid.h")
        (folder / "bench.c").write_text(BENCH_C)
        flags = ["-std=c99", "-O2", "-ffp-contract=off"]
        subprocess.run([cc, *flags, "-o", "bench", "bench.c", "-lm"], cwd=folder, check=True)
        p.tofile(folder / "in.bin")
        proc = subprocess.run([str(folder / "bench"), str(folder / "in.bin"), str(args.n), str(folder / "out.bin"),
                               str(args.small), str(args.repeats)], capture_output=True, text=True, check=True)
        t_c_big, t_c_small = (float(x) for x in proc.stdout.split())
        out_c = np.fromfile(folder / "out.bin").reshape(-1, 3)

    ref = law.predict(p)
    worst = float((np.abs(out_c - ref).max(axis=1) / np.linalg.norm(p, axis=1)).max())

    threads = num_threads()
    t_py_default = median_time(lambda: law.predict(p), args.repeats)
    set_num_threads(1)
    t_py_one = median_time(lambda: law.predict(p), args.repeats)
    set_num_threads(threads)

    rows = p[: args.loop].tolist()
    t_loop_predict = median_time(lambda: [law.predict([row]) for row in rows], 3) / len(rows)
    formula = rigid_kernel.py_func
    r, mu = law.r, law.mu
    t_loop_py = median_time(lambda: [formula(x, y, w, r, mu) for x, y, w in rows], 3) / len(rows)

    c_rate = args.n / t_c_big
    print(f"exported C Rigid law vs Python ({platform.processor() or platform.machine()}, load average "
          f"{os.getloadavg()[0]:.2f}; C: cc {' '.join(flags)}, one thread)")
    print(f"C results vs law.predict on {args.n:.0e} landings: worst difference {worst:.3g} of the landing's norm")
    print(f"{'':58s} {'M bounces/s':>12s} {'C is x faster':>14s}")
    table = [
        (f"C bouncelab_predict, {args.n:.0e} landings (from memory)", args.n / t_c_big),
        (f"C bouncelab_predict, {args.small:.0e} landings (in cache)", args.small / t_c_small),
        (f"law.predict, {args.n:.0e} landings, 1 thread", args.n / t_py_one),
        (f"law.predict, {args.n:.0e} landings, {threads} threads", args.n / t_py_default),
        ("Python loop: law.predict([landing]) per bounce", 1.0 / t_loop_predict),
        ("Python loop: the kernel's formula in Python floats", 1.0 / t_loop_py),
    ]
    for label, rate in table:
        print(f"{label:58s} {rate / 1e6:12.3f} {c_rate / rate:14.3g}")
    print(f"target: >= 100 M bounces/s for the exported Rigid law on one core: "
          f"{'met' if c_rate >= 1e8 else 'NOT met'} ({c_rate / 1e6:.0f} M/s from memory)")


if __name__ == "__main__":
    main()
