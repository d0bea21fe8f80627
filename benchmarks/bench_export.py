"""The exported Rigid law in C, JavaScript and C#, each beside what a simulator would otherwise run.

Run: ``python benchmarks/bench_export.py`` (about a minute; needs ``cc``; ``node`` and Mono's ``mcs``/``mono``
for their sections, skipped with a note without them), or ``--quick`` (a few seconds: CI checks that it runs
and that the results agree). The Rigid law with the paper's values for campaign A is exported with
:func:`bouncelab.export.to_c`, ``to_js`` and ``to_cs`` and timed on the same landings (the paper's Table 1
ranges), each side the median of repeats, one thread, the two sides of a comparison alternating in one
process:

* **C**: ``bouncelab_predict`` compiled with ``cc -std=c99 -O2 -ffp-contract=off``, on a large batch
  streamed from memory and a small one that stays in cache; beside it ``law.predict`` (one thread and
  bouncelab's default threads) and the per-bounce Python loops an exported law replaces. Target (issue 25):
  at least 100 M bounces/s on one core.
* **JavaScript** (Node): the module's ``predict(landings, out)`` on a ``Float64Array`` beside a hand-written
  loop over the same typed arrays (the rigid bounce written out, ``Math.min``/``Math.max``), and a loop
  calling ``predictOne(xdot, ydot, omega, out)`` beside one calling a hand-written one-bounce function of the
  same signature; and the old form, ``predictRows`` on arrays of rows. Target (issue 34): the typed-array
  ``predict`` within 2x of the hand-written loop.
* **C#** (Mono): the class's ``Predict(landings, liftoffs)`` beside a hand-written loop over the same arrays.

Every exported result is checked against ``law.predict`` first. Times vary with the machine's load: the
ratios, measured side by side, are what to read.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from benchmarks.bench_predict import best_of as median_time  # the median of repeated timings
from benchmarks.bench_predict import landings  # the paper's Table 1 ranges, capped at 5.5 degrees
from bouncelab.export import to_c, to_cs, to_js
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

# Hand-written in each language as a simulator developer would: the rigid bounce (eq. rigid_bounce) over the
# landings, Math.min/Math.max for the Coulomb cap.
BENCH_JS = r"""
import fs from "fs";
import * as law from "./rigid.mjs";

const [input, n, repeats, output] = [process.argv[2], Number(process.argv[3]), Number(process.argv[4]),
                                     process.argv[5]];
const buf = fs.readFileSync(input);
const p = new Float64Array(buf.buffer.slice(buf.byteOffset, buf.byteOffset + 24 * n));
const R = law.PARAMETERS.r, MU = law.PARAMETERS.mu;

function handPredict(landings, out) {
  for (let i = 0; i < landings.length; i += 3) {
    const xd = landings[i], yd = landings[i + 1], w = landings[i + 2];
    const cap = -MU * (1 + R) * yd, stop = -(xd + w) / 3.5;
    const j = Math.min(Math.max(stop, -cap), cap);
    out[i] = xd + j;
    out[i + 1] = -R * yd;
    out[i + 2] = w + 2.5 * j;
  }
  return out;
}

function handOne(xd, yd, w, out) {
  const cap = -MU * (1 + R) * yd, stop = -(xd + w) / 3.5;
  const j = Math.min(Math.max(stop, -cap), cap);
  out[0] = xd + j;
  out[1] = -R * yd;
  out[2] = w + 2.5 * j;
  return stop < -cap ? 0 : (stop > cap ? 2 : 1);
}

const one = new Float64Array(3), a = new Float64Array(3 * n), b = new Float64Array(3 * n);
const exportedPredict = () => law.predict(p, a);
const handLoop = () => handPredict(p, b);
const predictOne = law.predictOne;
function exportedOne() {  // a simulator's loop: one bounce at a time
  let codes = 0;
  for (let i = 0; i < 3 * n; i += 3) {
    codes += predictOne(p[i], p[i + 1], p[i + 2], one);
    a[i] = one[0]; a[i + 1] = one[1]; a[i + 2] = one[2];
  }
  return codes;
}
function handOneLoop() {
  let codes = 0;
  for (let i = 0; i < 3 * n; i += 3) {
    codes += handOne(p[i], p[i + 1], p[i + 2], one);
    b[i] = one[0]; b[i + 1] = one[1]; b[i + 2] = one[2];
  }
  return codes;
}
const rows = Array.from({length: Math.min(n, 100000)}, (_, i) => [p[3 * i], p[3 * i + 1], p[3 * i + 2]]);
const rowsForm = () => law.predictRows(rows);

const sides = {exportedPredict, handLoop, exportedOne, handOneLoop, rowsForm};
const times = Object.fromEntries(Object.keys(sides).map((k) => [k, []]));
for (let r = 0; r < 2; r++) for (const f of Object.values(sides)) f();  // V8 optimises them first
for (let r = 0; r < repeats; r++) {  // the sides alternate: the machine's load falls on all alike
  for (const [k, f] of Object.entries(sides)) {
    const t = process.hrtime.bigint();
    f();
    times[k].push(Number(process.hrtime.bigint() - t) / 1e9);
  }
}
law.predict(p, a);
fs.writeFileSync(output, Buffer.from(a.buffer));
console.log(JSON.stringify({times, rows: rows.length}));
"""

BENCH_CS = r"""
using System;
using System.Diagnostics;
using System.IO;

public static class Bench {
    static double R = BouncelabLaw_R.R, MU = BouncelabLaw_R.MU;

    static void HandPredict(double[] landings, double[] liftoffs) {
        for (int i = 0; i < landings.Length; i += 3) {
            double xd = landings[i], yd = landings[i + 1], w = landings[i + 2];
            double cap = -MU * (1.0 + R) * yd, stop = -(xd + w) / 3.5;
            double j = Math.Min(Math.Max(stop, -cap), cap);
            liftoffs[i] = xd + j;
            liftoffs[i + 1] = -R * yd;
            liftoffs[i + 2] = w + 2.5 * j;
        }
    }

    public static void Main(string[] argv) {
        int n = int.Parse(argv[1]), repeats = int.Parse(argv[2]);
        double[] p = new double[3 * n], a = new double[3 * n], b = new double[3 * n];
        Buffer.BlockCopy(File.ReadAllBytes(argv[0]), 0, p, 0, 24 * n);
        double[] te = new double[repeats], th = new double[repeats];
        BouncelabLaw.Predict(p, a);  // compiled by the JIT first
        HandPredict(p, b);
        for (int r = 0; r < repeats; r++) {
            Stopwatch s = Stopwatch.StartNew();
            BouncelabLaw.Predict(p, a);
            te[r] = s.Elapsed.TotalSeconds;
            s = Stopwatch.StartNew();
            HandPredict(p, b);
            th[r] = s.Elapsed.TotalSeconds;
        }
        Array.Sort(te);
        Array.Sort(th);
        byte[] raw = new byte[24 * n];
        Buffer.BlockCopy(a, 0, raw, 0, raw.Length);
        File.WriteAllBytes(argv[3], raw);
        Console.WriteLine(te[repeats / 2].ToString("R") + " " + th[repeats / 2].ToString("R"));
    }
}
"""


def _worst(out: np.ndarray, ref: np.ndarray, p: np.ndarray) -> float:
    return float((np.abs(out - ref).max(axis=1) / np.linalg.norm(p, axis=1)).max())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=2_000_000, help="landings of the large batch (default 2e6)")
    ap.add_argument("--small", type=int, default=10_000, help="landings of the in-cache batch (default 1e4)")
    ap.add_argument("--loop", type=int, default=20_000, help="landings of the Python per-bounce loops (default 2e4)")
    ap.add_argument("--js-n", type=int, default=1_000_000, help="landings of the JavaScript and C# runs (1e6)")
    ap.add_argument("--repeats", type=int, default=9, help="repeats of each timing (JavaScript: 3x as many rounds)")
    ap.add_argument("--quick", action="store_true",
                    help="small sizes and few repeats (a few seconds: checks that it runs and agrees, for CI)")
    args = ap.parse_args()
    if args.quick:
        args.n, args.small, args.loop, args.js_n, args.repeats = 200_000, 10_000, 2_000, 100_000, 3
    args.js_n = min(args.js_n, args.n)
    cc, node, mcs, mono = (shutil.which(x) for x in ("cc", "node", "mcs", "mono"))
    if cc is None:
        raise SystemExit("no C compiler: `cc` is not on PATH")

    law = bl.Rigid.published("A")
    p = landings(args.n)
    pj = np.ascontiguousarray(p[: args.js_n])
    ref = law.predict(p)
    flags = ["-std=c99", "-O2", "-ffp-contract=off"]
    js = cs = None
    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-") as tmp:
        folder = Path(tmp)
        to_c(law, folder / "rigid.h")
        (folder / "bench.c").write_text(BENCH_C)
        subprocess.run([cc, *flags, "-o", "bench", "bench.c", "-lm"], cwd=folder, check=True)
        p.tofile(folder / "in.bin")
        pj.tofile(folder / "in_js.bin")
        proc = subprocess.run([str(folder / "bench"), str(folder / "in.bin"), str(args.n), str(folder / "out.bin"),
                               str(args.small), str(args.repeats)], capture_output=True, text=True, check=True)
        t_c_big, t_c_small = (float(x) for x in proc.stdout.split())
        worst_c = _worst(np.fromfile(folder / "out.bin").reshape(-1, 3), ref, p)
        if node is not None:
            to_js(law, folder / "rigid.mjs")
            (folder / "bench.mjs").write_text(BENCH_JS)
            proc = subprocess.run([node, "bench.mjs", "in_js.bin", str(args.js_n), str(3 * args.repeats), "out_js.bin"],
                                  cwd=folder, capture_output=True, text=True, check=True)
            js = json.loads(proc.stdout)
            js["times"] = {k: np.array(v) for k, v in js["times"].items()}
            js["worst"] = _worst(np.fromfile(folder / "out_js.bin").reshape(-1, 3), ref[: args.js_n], pj)
        if mcs is not None and mono is not None:
            # the parameters, for the hand-written side, from a class of their own
            (folder / "params.cs").write_text(f"public static class BouncelabLaw_R {{ public const double R = "
                                              f"{law.r!r}; public const double MU = {law.mu!r}; }}\n")
            to_cs(law, folder / "Law.cs")
            (folder / "bench.cs").write_text(BENCH_CS)
            subprocess.run([mcs, "-optimize+", "-out:bench.exe", "bench.cs", "Law.cs", "params.cs"], cwd=folder,
                           check=True, capture_output=True)
            proc = subprocess.run([mono, "bench.exe", "in_js.bin", str(args.js_n), str(args.repeats), "out_cs.bin"],
                                  cwd=folder, capture_output=True, text=True, check=True)
            cs = [float(x) for x in proc.stdout.split()]
            worst_cs = _worst(np.fromfile(folder / "out_cs.bin").reshape(-1, 3), ref[: args.js_n], pj)

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

    print(f"exported Rigid law ({platform.processor() or platform.machine()}, load average {os.getloadavg()[0]:.2f}"
          f"{', --quick: indicative of nothing' if args.quick else ''})")
    c_rate = args.n / t_c_big
    print(f"\nC (cc {' '.join(flags)}, one thread); results vs law.predict on {args.n:.0e} landings: worst "
          f"difference {worst_c:.3g} of the landing's norm")
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

    if js is None:
        print("\nJavaScript: skipped (no `node` on PATH)")
    else:
        n = args.js_n
        print(f"\nJavaScript (Node {subprocess.run([node, '--version'], capture_output=True, text=True).stdout.strip()}"
              f"), {n:.0e} landings in a Float64Array; results vs law.predict: worst difference {js['worst']:.3g}")
        # Under load a run's times spread: the ratio of each round's two adjacent timings (they share the load)
        # is what is compared, its median over the rounds, and beside it the ratio of the two sides' best times.
        t = js["times"]
        print(f"{'':58s} {'M bounces/s':>12s} {'x the hand-written (median of rounds; of best)':>48s}")
        for label, key, peer, count in [
                ("exported predict(landings, out)", "exportedPredict", "handLoop", n),
                ("hand-written typed-array loop", "handLoop", "handLoop", n),
                ("loop of exported predictOne(xdot, ydot, omega, out)", "exportedOne", "handOneLoop", n),
                ("loop of a hand-written one-bounce function", "handOneLoop", "handOneLoop", n),
                ("exported predictRows(rows) (arrays of rows)", "rowsForm", "handLoop", js["rows"])]:
            per_round = np.median((t[key] / count) / (t[peer] / n))
            best = (t[key].min() / count) / (t[peer].min() / n)
            print(f"{label:58s} {count / np.median(t[key]) / 1e6:12.3f} {per_round:27.2f}x {best:18.2f}x")
        ratio = float(np.median(t["exportedPredict"] / t["handLoop"]))
        print(f"target: exported predict within 2x of the hand-written typed-array loop: "
              f"{'met' if ratio <= 2 else 'NOT met'} ({ratio:.2f}x, the median of {len(t['handLoop'])} rounds)")

    if cs is None:
        print("\nC#: skipped (no Mono `mcs` and `mono` on PATH)")
    else:
        n = args.js_n
        print(f"\nC# (Mono, mcs -optimize+), {n:.0e} landings; results vs law.predict: worst difference {worst_cs:.3g}")
        print(f"{'exported BouncelabLaw.Predict(landings, liftoffs)':58s} {n / cs[0] / 1e6:12.3f} "
              f"{cs[0] / cs[1]:18.2f}x")
        print(f"{'hand-written loop over the same arrays':58s} {n / cs[1] / 1e6:12.3f} {1.0:18.2f}x")


if __name__ == "__main__":
    main()
