"""Laws outside Python (bouncelab.export): exported C, JavaScript and C# agree with bouncelab, bad input is refused.

The C headers are compiled once per module with the system C compiler (``cc``) and run as one program
holding every law (each with its own prefix); the ES modules run under Node; the C# classes are compiled
with Mono's ``mcs`` as C# 2.0 with warnings as errors (what Unity, Godot and every .NET compile) into one
program run by ``mono``. All are compared with ``law.predict(..., plausible=None)`` on landings drawn so
that every regime of each law occurs (checked with ``law.regime``). Skipped with a reason where ``cc``,
``node`` or ``mcs``/``mono`` is missing (Debian: apt-get install mono-mcs mono-runtime).
"""

from __future__ import annotations

import functools
import inspect
import math
import re
import shutil
import subprocess
import warnings
from math import sqrt as msqrt
from pathlib import Path

import numpy as np
import pytest
from numba import njit

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_FIT, EXIT_OK, EXIT_USAGE
from bouncelab.core.errors import LawDefinitionError, NotFittedError, OutputError, ParameterError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.core.units import BALL_RADIUS_M, CONVENTIONS
from bouncelab.export import ExportError, export_law, to_c, to_cs, to_js
from bouncelab.laws.provenance import Provenance
from bouncelab.simulation.surrogate import TURF_CALIBRATION

CC = shutil.which("cc")
NODE = shutil.which("node")
CXX = shutil.which("c++")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler: `cc` is not on PATH")
needs_node = pytest.mark.skipif(NODE is None, reason="no Node.js: `node` is not on PATH")
MCS, MONO = shutil.which("mcs"), shutil.which("mono")
NO_MONO = ("no Mono C# compiler and runtime: `mcs` and `mono` are not on PATH (Debian: apt-get install mono-mcs "
           "mono-runtime)")
needs_mono = pytest.mark.skipif(MCS is None or MONO is None, reason=NO_MONO)
MCS_FLAGS = ["-langversion:ISO-2", "-warnaserror+", "-optimize+"]  # C# 2.0: older than anything Unity or Godot uses
CFLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-pedantic", "-Werror"]
TOL = 1e-12  # relative to the landing's norm


# ------------------------------------------------------------------------------ a user's kernel that uses much of
# the subset: helpers with tuples, keywords and defaults, loops, simultaneous assignment, a variable tuple index
OFFSETS = (0.25, -0.5, 0.75)


@njit(inline="always")
def _spin_pair(a, b, scale=1.0):
    return a * scale, (b, -a)


@njit
def _settle(x, n):
    total = 0
    y = x
    for k in range(n, 0, -2):
        if k == 3:
            continue
        y = y * 0.5 + math.sqrt(abs(y) + 1.0)
        total += k
    while True:
        y = y / 3.0
        if not (-1e300 < y < 1e-3):
            continue
        break
    return y + total / 7


@njit
def _widen(k):
    k = k / 2  # an integer parameter that becomes a float
    return k


@njit
def semantics_kernel(xd, yd, w, a, table):
    u, (v, s) = _spin_pair(xd, w, scale=a)
    u, v = v, u
    unused = xd * 2.0  # set and never used: left out of the output (no compiler warning)
    dead = unused + _widen(3)  # noqa: F841
    i = 0 if xd > 0.0 else -1
    off = OFFSETS[i]
    lift = -a * yd + table[1, 0] * off
    q = min(u, v, w + s) + max(abs(xd), 1.0) ** 0.5 + math.atan2(yd, xd) + math.hypot(a, off)
    q += math.copysign(math.exp(-abs(w) / 1e4), xd) + _settle(a, 6) + msqrt(_widen(5))
    code = 1 if (u < v) and not (w == 0.0) else 0
    return xd - q * 1e-3, lift, w * table[0, 1], code


class ExportSemanticsLaw(bl.CompiledLaw):
    """A made-up law exercising the translator (not physics)."""

    a = bl.Parameter(bounds=(0.1, 1.0), physical=(0.0, 10.0), doc="a number")
    table = bl.Parameter(bounds=(-1.0, 1.0), physical=(-10.0, 10.0), shape=(2, 2), doc="a table")
    regimes = ("high", "low")
    kernel = semantics_kernel


@njit
def frictionless(xd, yd, w, e):
    return xd, -e * yd, w, 0


class ExportFrictionless(bl.CompiledLaw):
    """The example of bouncelab.laws.compiled: pF = [xdot0, -e ydot0, omega0]."""

    e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    regimes = ("bounce",)
    kernel = frictionless


LAWS = {
    "rigid_a": bl.Rigid.published("A"),
    "rigid_b": bl.Rigid.published("B"),
    "penner_fixed": bl.PennerFixed.published("B"),
    "penner_fixed_fade": bl.PennerFixed.published("B").replace(fade_xdot=50.0),
    "penner_varying": bl.PennerVarying.published("A"),
    "penner_varying_fade": bl.PennerVarying.published("A").replace(fade_xdot=80.0),
    "piecewise": bl.PiecewiseAffine.published("A"),
    "tangential": bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3),
    "compliant": bl.CompliantImpact(r=0.5, mu=0.8, kappa=3.0),
    "turf": bl.TurfContact(c=1.0, e_y=0.5, mu=0.5, log10_kt=7.0, lam=2.0),
    "crater": bl.CraterContact(**TURF_CALIBRATION["A"]["nominal"]),
    "semantics": ExportSemanticsLaw(a=0.7, table=np.array([[0.5, -0.25], [2.0, 1.5]])),
    "frictionless": ExportFrictionless(e=0.6),
}
INTEGRATED = ("turf", "crater")  # seconds per 10^5 bounces in each language: 10^5 in the slow run
N = 100_000
N_FAST = 10_000


def _pool(rng: np.random.Generator, n: int) -> np.ndarray:
    """Landings (scaled units, ydot < 0) from four families: broad; contact-point velocity near zero (grip,
    roll); grazing with v_P near zero (contact laws' reversal); the paper's Table 1 ranges."""
    m = n // 4
    xd = rng.uniform(-3000, 3000, n)
    yd = -rng.uniform(20, 3000, n)
    w = rng.uniform(-2500, 2500, n)
    near = slice(m, 2 * m)
    w[near] = -xd[near] + rng.uniform(-4, 4, m) * -yd[near]
    graze = slice(2 * m, 3 * m)
    xd[graze] = rng.choice([-1.0, 1.0], m) * rng.uniform(1500, 3000, m)
    yd[graze] = -rng.uniform(15, 60, m)
    w[graze] = -xd[graze] + rng.uniform(-4, 4, m) * -yd[graze]
    table = slice(3 * m, n)
    k = n - 3 * m
    xd[table] = rng.uniform(1, 2300, k) * rng.choice([-1.0, 1.0], k)
    yd[table] = -rng.uniform(90, 1900, k)
    w[table] = rng.uniform(-1700, 1700, k)
    return np.column_stack([xd, yd, w])


@functools.cache
def case(name: str, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """n landings covering every regime of the law (stratified from a pool of 2n, classified by law.regime),
    bouncelab's lift-offs and regime codes."""
    law = LAWS[name]
    rng = np.random.default_rng(sum(map(ord, name)))
    pool = _pool(rng, 2 * n)
    codes = law.regime(pool, codes=True, plausible=None)
    picks = []
    for code in range(len(law.regimes)):
        idx = np.flatnonzero(codes == code)
        assert len(idx) >= 20, f"{name}: the pool has {len(idx)} landings in regime {law.regimes[code]}"
        picks.append(rng.choice(idx, min(len(idx), n // (2 * len(law.regimes))), replace=False))
    chosen = np.concatenate(picks)
    rest = np.setdiff1d(np.arange(len(pool)), chosen)
    chosen = np.concatenate([chosen, rng.choice(rest, n - len(chosen), replace=False)])
    rng.shuffle(chosen)
    p = np.ascontiguousarray(pool[chosen])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bl.errors.NonphysicalLiftoffWarning)
        ref = law.predict(p, plausible=None)
    return p, ref, law.regime(p, codes=True, plausible=None)


# ------------------------------------------------------------------------------ the C program and the JS driver
DRIVER_C = r"""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
%(includes)s

/* usage: driver LAW IN OUT N. OUT: predict (3n doubles), regime (n ints), predict_one (3n doubles, n ints). */
int main(int argc, char **argv) {
    if (argc != 5) return 2;
    long n = atol(argv[4]);
    double *p = malloc(24 * n), *a = malloc(24 * n), *b = malloc(24 * n);
    int *ca = malloc(4 * n), *cb = malloc(4 * n);
    FILE *f = fopen(argv[2], "rb");
    if (!f || fread(p, 8, 3 * n, f) != (size_t)(3 * n)) return 3;
    fclose(f);
    int found = 0;
%(dispatch)s
    if (!found) return 4;
    f = fopen(argv[3], "wb");
    fwrite(a, 8, 3 * n, f);
    fwrite(ca, 4, n, f);
    fwrite(b, 8, 3 * n, f);
    fwrite(cb, 4, n, f);
    fclose(f);
    return 0;
}
"""

DRIVER_JS = """
import fs from 'fs';
%(imports)s
const [name, inp, out, count] = process.argv.slice(2);
const n = Number(count);
const law = {%(names)s}[name];
const buf = fs.readFileSync(inp);
const flat = new Float64Array(buf.buffer.slice(buf.byteOffset, buf.byteOffset + 24 * n));
const a = law.predict(flat), ca = law.regime(flat);
if (!(a instanceof Float64Array) || !(ca instanceof Int32Array)) process.exit(5);
const b = new Float64Array(3 * n), cb = new Int32Array(n), one = new Float64Array(3);
for (let i = 0; i < n; i++) {
  cb[i] = law.predictOne(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2], one);
  for (let k = 0; k < 3; k++) b[3 * i + k] = one[k];
}
const rows = [];
for (let i = 0; i < Math.min(n, 100); i++) rows.push([flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]]);
const r = law.predictRows(rows);  // the arrays-of-rows form gives the same numbers
for (let i = 0; i < rows.length; i++) {
  for (let k = 0; k < 3; k++) if (!Object.is(r[i][k], a[3 * i + k])) process.exit(6);
}
fs.writeFileSync(out, Buffer.concat([a, ca, b, cb].map((x) => Buffer.from(x.buffer))));
"""

DRIVER_CS = """
using System;
using System.IO;

public static class Driver {
    /* usage: driver LAW IN OUT N. OUT: Predict (3n doubles), Regime (n ints), PredictOne (3n doubles, n ints). */
    public static int Main(string[] argv) {
        int n = int.Parse(argv[3]);
        double[] p = new double[3 * n], a = new double[3 * n], b = new double[3 * n], one = new double[3];
        int[] ca = new int[n], cb = new int[n];
        Buffer.BlockCopy(File.ReadAllBytes(argv[1]), 0, p, 0, 24 * n);
        switch (argv[0]) {
%(cases)s
            default: return 4;
        }
        byte[] raw = new byte[56 * n];
        Buffer.BlockCopy(a, 0, raw, 0, 24 * n);
        Buffer.BlockCopy(ca, 0, raw, 24 * n, 4 * n);
        Buffer.BlockCopy(b, 0, raw, 28 * n, 24 * n);
        Buffer.BlockCopy(cb, 0, raw, 52 * n, 4 * n);
        File.WriteAllBytes(argv[2], raw);
        return 0;
    }
}
"""

# The C# case of one law: Predict, Regime, and PredictOne, its array form for even rows, its out form for odd ones.
CASE_CS = """            case "%(name)s": {
                %(cls)s.Predict(p, a);
                %(cls)s.Regime(p, ca);
                for (int i = 0; i < n; i++) {
                    if (i %% 2 == 0) {
                        cb[i] = %(cls)s.PredictOne(p[3 * i], p[3 * i + 1], p[3 * i + 2], one);
                    } else {
                        cb[i] = %(cls)s.PredictOne(p[3 * i], p[3 * i + 1], p[3 * i + 2], out one[0], out one[1],
                                                  out one[2]);
                    }
                    b[3 * i] = one[0];
                    b[3 * i + 1] = one[1];
                    b[3 * i + 2] = one[2];
                }
                break;
            }"""


def cs_class_of(name: str) -> str:
    """The C# class of law NAME in the test program (one of them in a namespace, to test --namespace)."""
    return "Golf.Bounce.Semantics" if name == "semantics" else "Law_" + name


@pytest.fixture(scope="module")
def c_program(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Every law's header (prefix NAME_) in one C program, compiled once with warnings as errors."""
    if CC is None:
        pytest.skip("no C compiler: `cc` is not on PATH")
    folder = tmp_path_factory.mktemp("c")
    for name, law in LAWS.items():
        to_c(law, folder / f"{name}.h", prefix=f"{name}_")
    dispatch = "\n".join(
        f'    if (!strcmp(argv[1], "{n}")) {{ found = 1; {n}_predict(p, a, n); {n}_regime(p, ca, n);\n'
        f"        for (long i = 0; i < n; i++)\n"
        f"            cb[i] = {n}_predict_one(p[3 * i], p[3 * i + 1], p[3 * i + 2], b + 3 * i); }}"
        for n in LAWS)
    includes = "\n".join(f'#include "{n}.h"' for n in LAWS) + '\n#include "rigid_a.h"  /* twice: read once */'
    (folder / "driver.c").write_text(DRIVER_C % {"includes": includes, "dispatch": dispatch})
    proc = subprocess.run([CC, *CFLAGS, "-o", "driver", "driver.c", "-lm"], cwd=folder, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return folder / "driver"


@pytest.fixture(scope="module")
def js_driver(tmp_path_factory: pytest.TempPathFactory) -> Path:
    if NODE is None:
        pytest.skip("no Node.js: `node` is not on PATH")
    folder = tmp_path_factory.mktemp("js")
    for name, law in LAWS.items():
        to_js(law, folder / f"{name}.mjs")
    imports = "\n".join(f"import * as {n} from './{n}.mjs';" for n in LAWS)
    (folder / "driver.mjs").write_text(DRIVER_JS % {"imports": imports, "names": ", ".join(LAWS)})
    return folder / "driver.mjs"


@pytest.fixture(scope="module")
def cs_program(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Every law's C# class in one program, compiled by Mono's mcs as C# 2.0 with warnings as errors."""
    if MCS is None or MONO is None:
        pytest.skip(NO_MONO)
    folder = tmp_path_factory.mktemp("cs")
    for name, law in LAWS.items():
        cls = cs_class_of(name)
        namespace, _, short = cls.rpartition(".")
        to_cs(law, folder / f"{name}.cs", class_name=short, namespace=namespace or None)
    cases = "\n".join(CASE_CS % {"name": n, "cls": cs_class_of(n)} for n in LAWS)
    (folder / "driver.cs").write_text(DRIVER_CS % {"cases": cases})
    proc = subprocess.run([MCS, *MCS_FLAGS, "-out:driver.exe", *(f"{n}.cs" for n in LAWS), "driver.cs"],
                          cwd=folder, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return folder / "driver.exe"


def run_exported(command: list[str], p: np.ndarray, folder: Path) -> tuple[np.ndarray, ...]:
    n = len(p)
    p.tofile(folder / "in.bin")
    proc = subprocess.run([*command, str(folder / "in.bin"), str(folder / "out.bin"), str(n)], capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    raw = (folder / "out.bin").read_bytes()
    a = np.frombuffer(raw, np.float64, 3 * n).reshape(n, 3)
    ca = np.frombuffer(raw, np.int32, n, 24 * n)
    b = np.frombuffer(raw, np.float64, 3 * n, 28 * n).reshape(n, 3)
    cb = np.frombuffer(raw, np.int32, n, 52 * n)
    return a, ca, b, cb


def check_agreement(name: str, n: int, command: list[str], folder: Path) -> None:
    """Lift-offs within TOL of the landing's norm, the same regime codes, and predict_one as predict."""
    law = LAWS[name]
    p, ref, codes = case(name, n)
    assert set(codes.tolist()) == set(range(len(law.regimes))), "every regime occurs"
    a, ca, b, cb = run_exported(command, p, folder)
    scale = np.linalg.norm(p, axis=1)
    err = np.abs(a - ref).max(axis=1) / scale
    assert err.max() <= TOL, f"{name}: worst {err.max():.3g} at landing {p[err.argmax()].tolist()}"
    np.testing.assert_array_equal(ca, codes)
    np.testing.assert_array_equal(b, a)  # one bounce at a time: the same numbers
    np.testing.assert_array_equal(cb, ca)


#: Laws whose numba kernel takes long to compile with a cold cache (TurfContact: about 25 s on the 2-core machine,
#: measured): every test comparing with their law.predict runs with -m slow only.
COLD = ("turf",)


def _params(n: int, slow_ones: tuple[str, ...], fast: bool) -> list:
    out = []
    for name in LAWS:
        if name in slow_ones:
            slow = not fast or name in COLD
            out.append(pytest.param(name, n if not fast else N_FAST, marks=[pytest.mark.slow] if slow else []))
        elif not fast:
            out.append(pytest.param(name, n))
    return out


AGREEMENT = [*_params(N, INTEGRATED, fast=False), *_params(N, INTEGRATED, fast=True)]


@needs_cc
@pytest.mark.parametrize(("name", "n"), AGREEMENT)
def test_c_agrees_with_python(c_program, name, n):
    check_agreement(name, n, [str(c_program), name], c_program.parent)


@needs_node
@pytest.mark.parametrize(("name", "n"), AGREEMENT)
def test_js_agrees_with_python(js_driver, name, n):
    check_agreement(name, n, [NODE, str(js_driver), name], js_driver.parent)


@needs_mono
@pytest.mark.parametrize(("name", "n"), AGREEMENT)
def test_cs_agrees_with_python(cs_program, name, n):
    check_agreement(name, n, [MONO, str(cs_program), name], cs_program.parent)


POW_JS = """
import fs from 'fs';
const $D = new Float64Array(4);
%s
const b = fs.readFileSync(process.argv[2]);
const v = new Float64Array(b.buffer, b.byteOffset, b.length / 8);
const out = new Float64Array(v.length / 2);
for (let i = 0; i < out.length; i++) {
  $D[0] = v[2 * i];
  $D[1] = v[2 * i + 1];
  $pow();
  out[i] = $D[0];
}
fs.writeFileSync(process.argv[3], Buffer.from(out.buffer));
"""

POW_CS = """
using System;
using System.IO;

public static class Pow {
%s

    public static void Main(string[] argv) {
        byte[] raw = File.ReadAllBytes(argv[0]);
        double[] v = new double[raw.Length / 8], o = new double[raw.Length / 16];
        Buffer.BlockCopy(raw, 0, v, 0, raw.Length);
        for (int i = 0; i < o.Length; i++) o[i] = h_pow(v[2 * i], v[2 * i + 1]);
        byte[] w = new byte[o.Length * 8];
        Buffer.BlockCopy(o, 0, w, 0, w.Length);
        File.WriteAllBytes(argv[1], w);
    }
}
"""


def run_pow(lang: str, folder: Path, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``$pow`` (JavaScript) or ``h_pow`` (C#) of the exported code at x, y."""
    from bouncelab.export.emit.cs import cs_pow
    from bouncelab.export.emit.js import js_pow

    np.column_stack([x, y]).tofile(folder / "in.bin")
    if lang == "js":
        (folder / "pow.mjs").write_text(POW_JS % js_pow())
        subprocess.run([NODE, "pow.mjs", "in.bin", "out.bin"], cwd=folder, check=True, timeout=120)
    else:
        (folder / "pow.cs").write_text(POW_CS % cs_pow())
        subprocess.run([MCS, *MCS_FLAGS, "-out:pow.exe", "pow.cs"], cwd=folder, check=True, timeout=120)
        subprocess.run([MONO, "pow.exe", "in.bin", "out.bin"], cwd=folder, check=True, timeout=120)
    return np.fromfile(folder / "out.bin")


@pytest.mark.parametrize("lang", [pytest.param("js", marks=needs_node), pytest.param("cs", marks=needs_mono)])
def test_pow_is_correctly_rounded_with_c_special_values(tmp_path, lang):
    """The exported JavaScript's and C#'s ** is correctly rounded (Node's Math.pow is not: it differs from the C
    library's pow in the last bit for about 8 % of arguments, which TurfContact's event location amplified to 1e-6
    for rare landings; .NET's Math.Pow is the platform's), and gives C's values for the special cases."""
    from decimal import Decimal, localcontext

    rng = np.random.default_rng(7)
    n = 1000
    x = np.concatenate([rng.uniform(1e-8, 1e-2, n), np.full(n, 10.0), np.exp(rng.uniform(-300, 300, n))])
    y = np.concatenate([np.full(n, 0.4), rng.uniform(2, 11, n), rng.uniform(-2, 2, n)])
    with localcontext() as ctx:
        ctx.prec = 50
        exact = np.array([float(Decimal(float(a)) ** Decimal(float(b))) for a, b in zip(x, y, strict=True)])
    inf, nan = math.inf, math.nan
    special = [(1.0, nan, 1.0), (nan, 0.0, 1.0), (-1.0, inf, 1.0), (-1.0, -inf, 1.0), (0.0, -1.0, inf),
               (-0.0, -1.0, -inf), (-8.0, 1 / 3, nan), (-2.0, 3.0, -8.0), (2.0, 0.5, math.sqrt(2.0)),
               (0.5, inf, 0.0), (2.0, -inf, 0.0), (inf, -2.0, 0.0), (4.0, 0.5, 2.0),
               (1e-310, 1.0, 1e-310), (1e-310, 0.5, 1e-155)]  # subnormal bases last
    x = np.concatenate([x, [s[0] for s in special]])
    y = np.concatenate([y, [s[1] for s in special]])
    out = run_pow(lang, tmp_path, x, y)
    np.testing.assert_array_equal(out[:3 * n], exact)
    want = np.array([s[2] for s in special])
    got = out[3 * n:]
    assert all((a == b and math.copysign(1, a) == math.copysign(1, b)) or (math.isnan(a) and math.isnan(b))
               for a, b in zip(got[:-2], want[:-2], strict=True))
    assert got[-2] == want[-2]  # x^1 of a subnormal x, through the fall-back for |y ln x| > 700
    assert got[-1] == pytest.approx(want[-1], rel=1e-15)


@needs_cc
def test_c_is_bit_identical_for_the_closed_form_laws(c_program):
    """With the same C library and no contraction the translation is numba's arithmetic, operation for operation."""
    for name in ("rigid_a", "penner_fixed", "penner_varying", "piecewise", "tangential", "compliant"):
        p, ref, _ = case(name, N)
        a, *_ = run_exported([str(c_program), name], p, c_program.parent)
        np.testing.assert_array_equal(a, ref, err_msg=name)


# ------------------------------------------------------------------------------ the header comment
def comment_text(source: str) -> str:
    """The top comment, unwrapped: its lines without the comment marks, whitespace collapsed."""
    head = source[source.index("/*") + 2:source.index("*/")]
    return " ".join(" ".join(line.strip().lstrip("*").strip() for line in head.splitlines()).split())


@pytest.mark.parametrize("lang", ["c", "js", "cs"])
def test_comment_carries_conventions_units_parameters_and_domain(lang):
    law = bl.PennerFixed.published("B").replace(fade_xdot=50.0)
    text = comment_text(export_law(law, lang))
    assert " ".join(CONVENTIONS.split()) in text
    assert "radius/s" in text and "rad/s" in text and f"R = {BALL_RADIUS_M} m" in text
    for name, value in law.parameters.items():
        assert f"{name} = {float(value)!r}" in text
    assert "option fade_xdot = 50.0" in text
    assert "Regime codes: 0 slip_forward, 1 roll, 2 slip_backward" in text
    r, g = BALL_RADIUS_M, PLAUSIBLE_RANGES
    for number in (g.min_landing_speed / r, g.max_speed / r, g.max_spin * 2 * math.pi / 60):
        assert f"{number:.6g}" in text
    assert f"at least {g.min_landing_angle:g} degrees" in text
    assert "no record of the landings it was fitted on" in text and "extrapolates" in text
    if lang == "c":
        assert "-ffp-contract=off" in text and "-ffast-math" in text
    elif lang == "js":
        assert "Math.exp" in text and "allocated" in text
    else:
        assert "Math.Exp" in text and "h_pow" in text and "Unity, Godot and Mono" in text


def test_comment_gives_the_fitted_ranges_and_says_synthetic():
    ranges = {"xdot0": (120.5, 1830.25), "ydot0": (-1500.0, -95.5), "omega0": (-300.0, 1600.0),
              "speed": (150.0, 2100.0), "angle_deg": (16.5, 80.0)}
    prov = Provenance(n_bounces=330, data_kind="synthetic surrogate", campaign="A", surrogate="turf",
                      generator="CraterContact", landing_ranges=ranges)
    law = bl.Rigid(r=0.5, mu=0.4)._with_provenance(prov)
    for lang in ("c", "js", "cs"):
        text = comment_text(export_law(law, lang))
        for name, (lo, hi) in ranges.items():
            assert f"{name} from {lo:.6g} to {hi:.6g}" in text
        assert "SYNTHETIC" in text and "not real turf" in text


def test_comment_lists_derived_constants():
    law = LAWS["compliant"]
    args = law._kernel_args(**law.parameters)
    text = comment_text(to_c(law))
    assert f"z = {args[3]!r}, wd = {args[4]!r}, tc = {args[5]!r}" in text


# ------------------------------------------------------------------------------ several laws in one program
TWO_LAWS = r"""
#include <stdio.h>
#include "a.h"
#include "b.h"
int main(void) {
    double out[3];
    int code = a_predict_one(1000.0, -800.0, 300.0, out);
    printf("%.17g %.17g %.17g %d\n", out[0], out[1], out[2], code);
    code = b_predict_one(1000.0, -800.0, 300.0, out);
    printf("%.17g %.17g %.17g %d %s\n", out[0], out[1], out[2], code, b_regime_name(code));
    return 0;
}
"""


@needs_cc
def test_prefix_lets_two_laws_share_a_program(tmp_path):
    law_a, law_b = bl.Rigid.published("A"), bl.PennerVarying.published("B")
    to_c(law_a, tmp_path / "a.h", prefix="a_")
    to_c(law_b, tmp_path / "b.h", prefix="b_")
    (tmp_path / "main.c").write_text(TWO_LAWS)
    subprocess.run([CC, *CFLAGS, "-o", "two", "main.c", "-lm"], cwd=tmp_path, check=True, timeout=120)
    lines = subprocess.run([str(tmp_path / "two")], capture_output=True, text=True, check=True).stdout.splitlines()
    p = [[1000.0, -800.0, 300.0]]
    for line, law in zip(lines, (law_a, law_b), strict=True):
        values = line.split()
        np.testing.assert_array_equal(np.array(values[:3], dtype=float), law.predict(p)[0])
        assert int(values[3]) == law.regime(p, codes=True)[0]
    assert lines[1].split()[4] == str(law_b.regime(p)[0])


@needs_cc
def test_two_laws_with_one_prefix_do_not_compile(tmp_path):
    """Two different laws under the same prefix collide loudly (the include guard names the content)."""
    to_c(bl.Rigid.published("A"), tmp_path / "a.h")
    to_c(bl.Rigid.published("B"), tmp_path / "b.h")
    (tmp_path / "main.c").write_text('#include "a.h"\n#include "b.h"\nint main(void) { return 0; }\n')
    proc = subprocess.run([CC, "-std=c99", "-c", "main.c"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode != 0 and "redefinition" in proc.stderr


@pytest.mark.skipif(CXX is None, reason="no C++ compiler: `c++` is not on PATH")
def test_header_compiles_as_cpp(tmp_path):
    for name in ("compliant", "crater", "piecewise", "semantics"):
        to_c(LAWS[name], tmp_path / f"{name}.h", prefix=f"{name}_")
    (tmp_path / "main.cpp").write_text("".join(f'#include "{n}.h"\n' for n in ("compliant", "crater", "piecewise",
                                                                               "semantics"))
                                       + "int main() { double o[3]; return crater_predict_one(1, -2, 3, o) < 0; }\n")
    proc = subprocess.run([CXX, "-std=c++11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only", "main.cpp"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr


# ------------------------------------------------------------------------------ bad input
def test_law_without_values_is_refused():
    with pytest.raises(NotFittedError) as exc:
        to_c(bl.Rigid(r=0.5))
    assert list(exc.value.missing) == ["mu"]
    with pytest.raises(NotFittedError):
        to_js(bl.CraterContact())


def test_unknown_language_and_bad_prefix():
    law = bl.Rigid(r=0.5, mu=0.3)
    with pytest.raises(ParameterError) as exc:
        export_law(law, "rust")
    assert exc.value.parameter == "lang" and exc.value.value == "rust"
    for prefix in ("9x", "a-b", "", "a b"):
        with pytest.raises(ParameterError) as exc:
            to_c(law, prefix=prefix)
        assert exc.value.parameter == "prefix"
    with pytest.raises(ParameterError) as exc:
        export_law(law, "js", prefix="x_")
    assert exc.value.parameter == "prefix"


def test_unwritable_file_is_refused_and_nothing_written(tmp_path):
    law = bl.Rigid(r=0.5, mu=0.3)
    with pytest.raises(OutputError) as exc:
        to_c(law, tmp_path / "missing" / "law.h")
    assert exc.value.path == str(tmp_path / "missing" / "law.h") and exc.value.reason == "no such folder"
    assert not (tmp_path / "missing").exists()
    with pytest.raises(OutputError) as exc:
        to_js(law, tmp_path)
    assert exc.value.reason == "a folder"
    target = tmp_path / "law.h"
    target.write_text("old")
    to_c(law, target)
    assert target.read_text() == to_c(law)


class ExportNumpyLaw(bl.BounceModel):
    """A law written with NumPy (no kernel)."""

    e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    regimes = ("bounce",)

    def _predict(self, p, e):
        return p * np.array([1.0, -e, 1.0])

    def _regime(self, p, e):
        return np.zeros(len(p), dtype=np.int8)


def test_law_without_kernel_is_refused():
    with pytest.raises(ExportError) as exc:
        to_c(ExportNumpyLaw(e=0.5))
    assert exc.value.law == "ExportNumpyLaw" and isinstance(exc.value, LawDefinitionError)


# Kernels outside the subset: each is refused naming the function, its line and the construct.
def _floor_div(xd, yd, w, e):
    k = xd // 2.0  # REFUSED
    return k, -e * yd, w, 0


def _a_list(xd, yd, w, e):
    v = [xd, yd]  # REFUSED
    return v[0], -e * yd, w, 0


def _numpy_call(xd, yd, w, e):
    return np.sqrt(xd), -e * yd, w, 0  # REFUSED


def _truthiness(xd, yd, w, e):
    if xd:  # REFUSED
        return xd, -e * yd, w, 0
    return -xd, -e * yd, w, 0


def _integer_power(xd, yd, w, e):
    return xd ** 2, -e * yd, w, 0  # REFUSED


def _while_else(xd, yd, w, e):
    while xd > 1.0:  # REFUSED
        xd = xd / 2.0
    else:
        xd = 0.0
    return xd, -e * yd, w, 0


def _python_helper(x):
    return x


def _plain_call(xd, yd, w, e):
    return _python_helper(xd), -e * yd, w, 0  # REFUSED


@njit
def _recurse(x):
    return x if x < 1.0 else _recurse(x / 2.0)  # REFUSED


def _recursive(xd, yd, w, e):
    return _recurse(xd), -e * yd, w, 0


def _array_global(xd, yd, w, e):
    return xd * OFFSET_ARRAY[0], -e * yd, w, 0  # REFUSED


OFFSET_ARRAY = np.array([1.0, 2.0])


def _no_regime(xd, yd, w, e):
    return xd, -e * yd, w  # REFUSED


REFUSALS = [(_floor_div, "the operator //"), (_a_list, "a list"), (_numpy_call, "an attribute"),
            (_truthiness, "a condition of type double"), (_integer_power, "** with an integer exponent"),
            (_while_else, "a while loop with an else clause"), (_plain_call, "the module-level name '_python_helper'"),
            (_recursive, "a recursive call"), (_array_global, "the module-level name 'OFFSET_ARRAY'"),
            (_no_regime, None)]


@pytest.mark.parametrize(("func", "construct"), REFUSALS, ids=[f.__name__ for f, _ in REFUSALS])
@pytest.mark.parametrize("lang", ["c", "js"])
def test_kernel_outside_the_subset_is_refused(func, construct, lang):
    kernel = njit(func)

    class Bad(bl.CompiledLaw):
        _abstract_law = True  # not registered
        e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        regimes = ("bounce",)

    Bad.kernel = kernel
    with pytest.raises(ExportError) as exc:
        export_law(Bad(e=0.5), lang)
    assert exc.value.law == "Bad"
    if construct is None:  # a kernel that does not return (xdotF, ydotF, omegaF, code)
        assert "not (xdotF, ydotF, omegaF, regime code)" in exc.value.message
        return
    assert exc.value.construct.startswith(construct), exc.value.message
    source, first = inspect.getsourcelines(func if func is not _recursive else _recurse.py_func)
    line = first + next(k for k, text in enumerate(source) if "REFUSED" in text)
    assert exc.value.line == line and exc.value.file.endswith("test_export.py")
    assert "nothing was written" in exc.value.message


def test_fastmath_kernel_is_refused():
    """A kernel compiled with fastmath freedoms that change finite results cannot be matched by IEEE code."""

    class Fast(bl.CompiledLaw):
        _abstract_law = True
        e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        regimes = ("bounce",)
        kernel = njit(fastmath=True)(frictionless.py_func)

    with pytest.raises(ExportError) as exc:
        to_c(Fast(e=0.5))
    assert exc.value.construct == "a function compiled with fastmath=True"
    Fast.kernel = njit(fastmath={"nnan", "ninf", "nsz"})(frictionless.py_func)  # bouncelab's ROW_FLAGS: allowed
    assert "static inline" in to_c(Fast(e=0.5))


def test_lambda_kernel_is_refused():
    class Lam(bl.CompiledLaw):
        _abstract_law = True
        e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        regimes = ("bounce",)
        kernel = njit(lambda xd, yd, w, e: (xd, -e * yd, w, 0))

    with pytest.raises(ExportError) as exc:
        to_js(Lam(e=0.5))
    assert exc.value.construct == "a function that is not a plain def"


# ------------------------------------------------------------------------------ the JavaScript API
ALLOC_JS = """
const law = await import(process.argv[2]);
const [warm, count] = [Number(process.argv[3]), Number(process.argv[4])];
const out = new Float64Array(3), acc = new Float64Array(1);
const P = new Float64Array([1000.5, -800.25, 300.125, 600.5, -900.75, 1500.5, -1200.5, -300.25, -50.5,
                            40.5, -1500.5, 900.5]);
function loop(n) {
  for (let i = 0; i < n; i++) {
    const k = 3 * (i & 3);
    acc[0] += law.predictOne(P[k], P[k + 1], P[k + 2], out) + out[0];
  }
}
loop(warm);
console.log("MEASURE");
loop(count);
console.log("DONE", acc[0]);
"""


@needs_node
@pytest.mark.parametrize("name", list(LAWS))
def test_js_predict_one_allocates_nothing(js_driver, name):
    """After warming up (V8 compiles it), predictOne runs 10^6 times (10^4 for the integrated laws) without a single
    garbage collection: it allocates nothing (the module's predictOne allocated two arrays a call before)."""
    folder = js_driver.parent
    (folder / "alloc.mjs").write_text(ALLOC_JS)
    warm, count = (3_000, 10_000) if name in (*INTEGRATED, "compliant") else (100_000, 1_000_000)
    # --no-concurrent-recompilation: V8 optimises on the main thread when it decides to, so the measured loop runs
    # optimised code even on a loaded machine (unoptimised code boxes doubles)
    proc = subprocess.run([NODE, "--no-concurrent-recompilation", "--trace-gc", "alloc.mjs", f"./{name}.mjs", str(warm),
                           str(count)], cwd=folder, capture_output=True, text=True, timeout=300, check=True)
    measured = proc.stdout.split("MEASURE", 1)[1].split("DONE", 1)[0]
    assert "Scavenge" not in measured and "Mark" not in measured, measured[:500]
    assert math.isfinite(float(proc.stdout.split("DONE", 1)[1].split()[0]))


JS_API = """
import * as law from './rigid_a.mjs';
const fails = (f) => { try { f(); return "no error"; } catch (e) { return `${e.name}: ${e.message}`; } };
const landings = new Float64Array([1000, -800, 300, 600, -900, 1500]);
const lift = law.predict(landings);
const same = new Float64Array(landings);
law.predict(same, same);  // in place
const code = law.predictOne(600, -900, 1500);  // into LIFTOFF
console.log(JSON.stringify({
  lift: Array.from(lift), inPlace: Array.from(same), liftoff: Array.from(law.LIFTOFF), code,
  codes: Array.from(law.regime(landings)), plain: Array.from(law.predict([1000, -800, 300])),
  rows: law.predictRows([[1000, -800, 300], [600, -900, 1500]]),
  nested: fails(() => law.predict([[1000, -800, 300]])), length: fails(() => law.predict(new Float64Array(4))),
  short: fails(() => law.predict(landings, new Float64Array(3))), notArray: fails(() => law.predict(3)),
  badRow: fails(() => law.predictRows([[1, 2]])),
}));
"""


@needs_node
def test_js_api_on_typed_arrays(js_driver):
    import json

    folder = js_driver.parent
    (folder / "api.mjs").write_text(JS_API)
    out = json.loads(subprocess.run([NODE, "api.mjs"], cwd=folder, capture_output=True, text=True, check=True,
                                    timeout=60).stdout)
    law = LAWS["rigid_a"]
    p = np.array([[1000.0, -800.0, 300.0], [600.0, -900.0, 1500.0]])
    ref = law.predict(p)
    assert out["lift"] == ref.ravel().tolist() == out["inPlace"]
    assert out["liftoff"] == ref[1].tolist() and out["code"] == law.regime(p, codes=True)[1]
    assert out["codes"] == law.regime(p, codes=True).tolist() and out["plain"] == ref[0].tolist()
    assert out["rows"] == ref.tolist()
    assert out["nested"].startswith("TypeError") and "predictRows" in out["nested"]
    assert out["length"].startswith("RangeError") and "4 numbers" in out["length"]
    assert out["short"].startswith("RangeError") and "fewer than the 6" in out["short"]
    assert out["notArray"].startswith("TypeError")
    assert out["badRow"].startswith("RangeError") and "landing 0" in out["badRow"]


# ------------------------------------------------------------------------------ C#
LITERALS_CS = """
using System;
using System.IO;

public static class Literals {
    static readonly double[] Values = { %s };

    public static void Main(string[] argv) {
        byte[] raw = new byte[8 * Values.Length];
        Buffer.BlockCopy(Values, 0, raw, 0, raw.Length);
        File.WriteAllBytes(argv[0], raw);
    }
}
"""


@needs_mono
def test_cs_literals_are_exact(tmp_path):
    """Every double is written so that the C# compiler reads it back to the same bits (shortest repr)."""
    from bouncelab.export.emit.cs import cs_literal

    rng = np.random.default_rng(3)
    special = [5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 0.1, 1 / 3, -0.0, 0.0, math.inf, -math.inf,
               1e23, 9007199254740993.0]
    values = np.concatenate([rng.standard_normal(2000) * 10.0 ** rng.integers(-300, 300, 2000),
                             rng.uniform(0, 1, 2000), special])
    (tmp_path / "lit.cs").write_text(LITERALS_CS % ", ".join(cs_literal(float(v)) for v in values))
    subprocess.run([MCS, *MCS_FLAGS, "lit.cs"], cwd=tmp_path, check=True, timeout=120, capture_output=True)
    subprocess.run([MONO, "lit.exe", "out.bin"], cwd=tmp_path, check=True, timeout=60)
    got = np.fromfile(tmp_path / "out.bin")
    np.testing.assert_array_equal(got.view(np.int64), values.view(np.int64))


HELPERS_CS = """
using System;
using System.IO;

public static class Helpers {
%s

    public static void Main(string[] argv) {
        byte[] raw = File.ReadAllBytes(argv[0]);
        double[] v = new double[raw.Length / 8];
        Buffer.BlockCopy(raw, 0, v, 0, raw.Length);
        int n = v.Length / 2;
        double[] o = new double[7 * n];
        for (int i = 0; i < n; i++) {
            double x = v[2 * i], y = v[2 * i + 1];
            o[7 * i] = h_hypot(x, y);
            o[7 * i + 1] = h_log1p(x);
            o[7 * i + 2] = h_expm1(y);
            o[7 * i + 3] = h_asinh(x);
            o[7 * i + 4] = h_acosh(Math.Abs(x) + 1.0);
            o[7 * i + 5] = h_atanh(y / 1000.0);
            o[7 * i + 6] = h_copysign(x, y);
        }
        byte[] w = new byte[8 * o.Length];
        Buffer.BlockCopy(o, 0, w, 0, w.Length);
        File.WriteAllBytes(argv[1], w);
    }
}
"""


def ulps(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance in units in the last place of b (0 where both are equal, NaN-aware)."""
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    return np.where(same, 0.0, np.abs(a - b) / np.spacing(np.abs(b)))


@needs_mono
def test_cs_math_helpers_are_within_a_few_ulps_of_the_c_library(tmp_path):
    """System.Math (of .NET Framework, Unity's) lacks hypot, log1p, expm1, asinh, acosh, atanh and copysign: the C#
    output writes them out. Measured against Python's math (the C library's) on values of every magnitude."""
    from bouncelab.export.emit.cs import _HELPERS

    rng = np.random.default_rng(11)
    n = 20_000
    x = rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-12, 12, n)
    y = rng.uniform(-700, 700, n)
    x[:6] = [0.0, -0.0, 1e-310, 1e200, -1e-200, 5.0]
    y[:6] = [0.0, -0.0, 1e-300, 3.0, 1e-20, -1e-300]
    code = "\n\n".join(_HELPERS[h] for h in ("copysign", "hypot", "log1p", "expm1", "asinh", "acosh", "atanh"))
    (tmp_path / "h.cs").write_text(HELPERS_CS % code)
    np.column_stack([x, y]).tofile(tmp_path / "in.bin")
    subprocess.run([MCS, *MCS_FLAGS, "h.cs"], cwd=tmp_path, check=True, timeout=120, capture_output=True)
    subprocess.run([MONO, "h.exe", "in.bin", "out.bin"], cwd=tmp_path, check=True, timeout=60)
    got = np.fromfile(tmp_path / "out.bin").reshape(n, 7)
    want = np.array([[math.hypot(a, b), math.log1p(a) if a > -1 else math.nan, math.expm1(b), math.asinh(a),
                      math.acosh(abs(a) + 1.0), math.atanh(b / 1000.0), math.copysign(a, b)]
                     for a, b in zip(x, y, strict=True)])
    worst = [ulps(got[:, k], want[:, k]).max() for k in range(7)]
    assert worst[6] == 0 and np.array_equal(np.signbit(got[:, 6]), np.signbit(want[:, 6]))
    assert max(worst[:6]) <= 4, dict(zip(("hypot", "log1p", "expm1", "asinh", "acosh", "atanh"), worst, strict=False))


API_CS = """
using System;

public static class Api {
    static string Fails(Action a) {
        try {
            a();
            return "no error";
        } catch (ArgumentException e) {
            return e.GetType().Name + ": " + e.Message.Replace("\\n", " ");
        }
    }

    public static void Main() {
        double[] landings = { 1000.0, -800.0, 300.0, 600.0, -900.0, 1500.0 };
        double[] lift = new double[6];
        Law.Predict(landings, lift);
        int[] codes = new int[2];
        Law.Regime(landings, codes);
        double xf, yf, wf;
        int code = Law.PredictOne(600.0, -900.0, 1500.0, out xf, out yf, out wf);
        Console.WriteLine(lift[0].ToString("R") + " " + lift[5].ToString("R") + " " + codes[1] + " " + code + " "
                          + wf.ToString("R") + " " + Law.RegimeName(code) + " " + Law.RegimeName(7) + " "
                          + Law.LawName);
        Console.WriteLine(Fails(delegate { Law.Predict(new double[4], new double[4]); }));
        Console.WriteLine(Fails(delegate { Law.Predict(landings, new double[3]); }));
        Console.WriteLine(Fails(delegate { Law.Predict(null, lift); }));
        Console.WriteLine(Fails(delegate { Law.PredictOne(1.0, -1.0, 0.0, new double[2]); }));
    }
}
"""


@needs_mono
def test_cs_api_checks_its_arrays(tmp_path):
    law = LAWS["rigid_a"]
    to_cs(law, tmp_path / "Law.cs", class_name="Law")
    (tmp_path / "api.cs").write_text(API_CS)
    subprocess.run([MCS, *MCS_FLAGS, "-out:api.exe", "api.cs", "Law.cs"], cwd=tmp_path, check=True, timeout=120)
    lines = subprocess.run([MONO, "api.exe"], cwd=tmp_path, capture_output=True, text=True, check=True,
                           timeout=60).stdout.splitlines()
    p = np.array([[1000.0, -800.0, 300.0], [600.0, -900.0, 1500.0]])
    ref, codes = law.predict(p), law.regime(p, codes=True)
    first = lines[0].split()
    assert [float(first[0]), float(first[1])] == [ref[0, 0], ref[1, 2]] and int(first[2]) == codes[1]
    assert int(first[3]) == codes[1] and float(first[4]) == ref[1, 2]
    assert first[5:] == [law.regimes[codes[1]], "?", "Rigid"]
    assert "ArgumentException" in lines[1] and "not three a landing" in lines[1]
    assert "fewer than the 6" in lines[2] and "liftoffs" in lines[2]
    assert lines[3].startswith("ArgumentNullException") and "landings" in lines[3]
    assert "liftoff must hold 3 numbers" in lines[4]


def test_cs_names_are_checked():
    law = bl.Rigid(r=0.5, mu=0.3)
    for bad in ("9Law", "class", "Predict", "LawName", "a-b", ""):
        with pytest.raises(ParameterError) as exc:
            to_cs(law, class_name=bad)
        assert exc.value.parameter == "class_name"
    for bad in ("Golf..Bounce", "Golf.class", "1x", "Golf.Bounce."):
        with pytest.raises(ParameterError) as exc:
            to_cs(law, namespace=bad)
        assert exc.value.parameter == "namespace"
    text = to_cs(law, class_name="TurfA", namespace="Golf.Bounce")
    assert "namespace Golf.Bounce {" in text and "public static class TurfA {" in text
    assert "namespace" not in to_cs(law).split("*/", 1)[1]  # the global namespace unless told
    with pytest.raises(ParameterError) as exc:
        export_law(law, "c", class_name="X")
    assert exc.value.parameter == "class_name"
    with pytest.raises(ParameterError) as exc:
        export_law(law, "cs", prefix="x_")
    assert exc.value.parameter == "prefix"
    with pytest.raises(ParameterError) as exc:
        export_law("Rigid", "c")
    assert exc.value.parameter == "law"


# ------------------------------------------------------------------------------ the command line
def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_exports_a_law_file(capsys, tmp_path):
    law = bl.PennerVarying.published("A")
    law.to_json(tmp_path / "law.json")
    code, out, _ = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "c", "-o", str(tmp_path / "law.h"),
                       "--prefix", "pv_")
    assert code == EXIT_OK and "law.h" in out
    assert (tmp_path / "law.h").read_text() == to_c(law, prefix="pv_")
    code, out, _ = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "js", "-o", str(tmp_path / "law.mjs"))
    assert code == EXIT_OK and (tmp_path / "law.mjs").read_text() == to_js(law)
    code, out, _ = run(capsys, "export", "rigid", "--published", "B", "--lang", "js")
    assert code == EXIT_OK and out == to_js(bl.Rigid.published("B"))
    code, out, _ = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "cs", "-o", str(tmp_path / "Law.cs"),
                       "--class-name", "PennerA", "--namespace", "Golf.Bounce")
    assert code == EXIT_OK and "Law.cs (C# class)" in out
    assert (tmp_path / "Law.cs").read_text() == to_cs(law, class_name="PennerA", namespace="Golf.Bounce")


def test_cli_errors(capsys, tmp_path):
    law = bl.Rigid(r=0.5, mu=0.3)
    law.to_json(tmp_path / "law.json")
    bl.Rigid(r=0.5).to_json(tmp_path / "unfitted.json")
    with pytest.raises(SystemExit) as exc:  # argparse: an unknown language
        main(["export", str(tmp_path / "law.json"), "--lang", "rust"])
    assert exc.value.code == EXIT_USAGE
    assert "invalid choice: 'rust'" in capsys.readouterr().err
    code, _, err = run(capsys, "export", str(tmp_path / "nothere.json"), "--lang", "c")
    assert code == EXIT_DATA and "nothere.json" in err
    code, _, err = run(capsys, "export", str(tmp_path / "unfitted.json"), "--lang", "c")
    assert code == EXIT_FIT and "no value for ['mu']" in err
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "c", "-o", str(tmp_path / "no" / "l.h"))
    assert code == EXIT_USAGE and "does not exist" in err and not (tmp_path / "no").exists()
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "js", "--prefix", "x_")
    assert code == EXIT_USAGE and "--prefix is for --lang c" in err
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "c", "--class-name", "X")
    assert code == EXIT_USAGE and "--class-name is for --lang cs" in err and "--prefix" in err
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "cs", "--class-name", "9X")
    assert code == EXIT_FIT and "class_name must be a C# identifier" in err
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "c", "--prefix", "1x")
    assert code == EXIT_FIT and "prefix must be a C identifier" in err
    code, _, err = run(capsys, "export", "Rigid", "--lang", "c")
    assert code == EXIT_USAGE and "--published" in err


class ExportUntranslatable(bl.CompiledLaw):
    """A registered law whose kernel the translator refuses (for the command line's exit code)."""

    e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    regimes = ("bounce",)
    kernel = njit(_floor_div)


def test_cli_untranslatable_kernel(capsys, tmp_path):
    ExportUntranslatable(e=0.5).to_json(tmp_path / "law.json")
    code, _, err = run(capsys, "export", str(tmp_path / "law.json"), "--lang", "c", "-o", str(tmp_path / "law.h"))
    assert code == EXIT_FIT and "_floor_div" in err and "the operator //" in err
    assert not (tmp_path / "law.h").exists()


def test_translator_subset_is_documented():
    """The module documentation lists what the translator reads (the docs page points to it)."""
    from bouncelab.export import frontend

    doc = frontend.__doc__
    for word in ("Functions", "Values", "Statements", "Expressions", "refused with"):
        assert word in doc
    assert re.search(r"math\.sqrt", doc)
