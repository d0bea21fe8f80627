"""A surface's ground phase outside Python (bouncelab.export.ground): exported C, JavaScript and C# agree with
``bouncelab.ground.bounce`` and ``run``, and refuse what they refuse.

The C headers (one prefix a surface) are compiled into one program with ``cc -std=c99 -O2 -ffp-contract=off
-Wall -Wextra -pedantic -Werror``; the ES modules run under Node; the C# classes are compiled by Mono's ``mcs``
as C# 2.0 with warnings as errors and run by ``mono``. Each program reads shots (v m/s, w rad/s, n) from a
binary file and writes the lift-off of ``bounce3d`` and the rest position, time and bounces of ``run``.
Skipped with a reason where ``cc``, ``node`` or ``mcs``/``mono`` is missing.

The issue's check (three surfaces: a preset, a Rigid surface, a PennerFixed surface with ``fade_xdot``; 2,000
landings each on slopes up to 2.5 degrees) is ``slow``; the default run checks 200 landings on the Rigid
surface in each language.
"""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_FIT, EXIT_OK, EXIT_USAGE
from bouncelab.core.errors import DataError, ParameterError
from bouncelab.export import REFUSALS, ExportError, export_surface
from bouncelab.export import ground as eg
from bouncelab.ground import Surface, bounce, preset, run

CC, CXX, NODE, MCS, MONO = (shutil.which(x) for x in ("cc", "c++", "node", "mcs", "mono"))
NO_MONO = ("no Mono C# compiler and runtime: `mcs` and `mono` are not on PATH (Debian: apt-get install mono-mcs "
           "mono-runtime)")
CFLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-pedantic", "-Werror"]
MCS_FLAGS = ["-langversion:ISO-2", "-warnaserror+", "-optimize+"]
SI = {"velocity": "m/s", "spin": "rad/s"}
BOUNCE_RTOL = 1e-12  # of the lift-off vector's norm
REST_ATOL = 1e-9  # metres (and seconds for the time to rest)

SURFACES = {
    "preset": lambda: preset("green-medium"),
    "rigid": lambda: Surface("rigid green", bl.Rigid(r=0.45, mu=0.35), sliding_friction=0.35, stimp_ft=10.0,
                             pivot_retention=0.7),
    "penner_fixed": lambda: Surface("tilted turf", bl.PennerFixed.published("A").replace(fade_xdot=40.0),
                                    sliding_friction=0.45, stimp_ft=8.5, pivot_retention=0.9),
}
#: Laws lifted in the plane of travel (a law with arrays among its values) and of the slip (sin, cos: the JavaScript
#: and C# math libraries' last bits).
OTHER_LIFTS = {
    "piecewise": lambda: Surface("affine turf", bl.PiecewiseAffine.published("B"), sliding_friction=0.4, stimp_ft=9.0),
    "compliant": lambda: Surface("springy", bl.CompliantImpact(r=0.5, mu=0.4, kappa=3.0), sliding_friction=0.4,
                                 stimp_ft=9.0, pivot_retention=0.5),
}


def shots(n: int, seed: int = 0, max_slope_deg: float = 2.5) -> np.ndarray:
    """(n, 9) rows v (m/s), w (rad/s), n: landings over the paper's Table 1 speeds and angles in any heading, spins
    of any direction up to 1700 rad/s (16,000 rpm), on planes tilted up to ``max_slope_deg`` in any direction
    (normals of several lengths); the last rows a vertical drop and balls rolling or skidding on the ground."""
    rng = np.random.default_rng(seed)
    speed = rng.uniform(2.0, 38.7, n)
    angle = np.radians(rng.uniform(16.4, 89.5, n))
    heading = rng.uniform(0.0, 2 * np.pi, n)
    slope = np.radians(rng.uniform(0.0, max_slope_deg, n))
    slope[: n // 10] = 0.0  # flat ground too
    azimuth = rng.uniform(0.0, 2 * np.pi, n)
    normal = np.column_stack([np.sin(slope) * np.cos(azimuth), np.sin(slope) * np.sin(azimuth), np.cos(slope)])
    # the landing in the plane's frame: along the plane in the heading, into it at the angle
    e1 = np.cross(normal, [0.0, 0.0, 1.0] * np.ones((n, 1)))
    e1[np.linalg.norm(e1, axis=1) < 1e-12] = [1.0, 0.0, 0.0]
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(normal, e1)
    along = np.cos(heading)[:, None] * e1 + np.sin(heading)[:, None] * e2
    v = speed[:, None] * (np.cos(angle)[:, None] * along - np.sin(angle)[:, None] * normal)
    w = rng.normal(size=(n, 3))
    w *= (rng.uniform(0.0, 1700.0, n) / np.linalg.norm(w, axis=1))[:, None]
    normal *= rng.choice([1.0, 0.5, 3.7], n)[:, None]
    k = n - 3  # the last three: a vertical drop, a ball rolling and one skidding along the ground
    v[k], w[k], normal[k] = [0.0, 0.0, -6.0], [0.0, 0.0, 40.0], [0.0, 0.0, 1.0]
    v[k + 1], w[k + 1], normal[k + 1] = [2.0, 0.0, 0.0], [0.0, 2.0 / 0.02135, 0.0], [0.0, 0.0, 1.0]
    v[k + 2], w[k + 2], normal[k + 2] = [3.0, 1.0, 0.0], [20.0, -300.0, 5.0], [0.0, 0.0, 2.0]
    return np.column_stack([v, w, normal])


def reference(surface: Surface, rows: np.ndarray) -> dict[str, np.ndarray]:
    """bouncelab's own numbers: the bounce of the landings (rows into the ground) and the run of every row."""
    v, w, n = rows[:, 0:3], rows[:, 3:6], rows[:, 6:9]
    landing = np.einsum("ij,ij->i", v, n) < 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vf, wf = bounce(surface, v[landing], w[landing], n[landing], units=SI)
        r = run(v, w, surface, n, units=SI)
    return {"landing": landing, "vf": vf, "wf": wf, "rest": r.rest_position, "time": r.rest_time,
            "bounces": r.totals["bounces"].to_numpy()}


# ------------------------------------------------------------------------------ the programs
DRIVER_C = r"""#include <math.h>
#include <stdio.h>
#include <string.h>
%(includes)s

/* argv: surface, shots in (n x 9 doubles), results out (n x 12: vOut, wOut, rest, time, run code, bounce ok) */
int main(int argc, char **argv) {
    double row[9], out[12];
    int found = 0;
    FILE *f, *g;
    if (argc != 4) return 2;
    f = fopen(argv[2], "rb");
    g = fopen(argv[3], "wb");
    if (!f || !g) return 3;
    while (fread(row, sizeof(double), 9, f) == 9) {
        double t = 0.0;
        int code = 0;
%(dispatch)s
        out[9] = t;
        out[10] = code;
        out[11] = isnan(out[0]) ? -1.0 : 0.0;
        fwrite(out, sizeof(double), 12, g);
    }
    fclose(f);
    fclose(g);
    return found ? 0 : 4;
}
"""

DRIVER_JS = r"""import { readFileSync, writeFileSync } from "node:fs";
import { pathToFileURL } from "node:url";
const mod = await import(pathToFileURL(process.argv[2]).href);
const buf = readFileSync(process.argv[3]);
const rows = new Float64Array(buf.buffer, buf.byteOffset, buf.length / 8);
const n = rows.length / 9, out = new Float64Array(12 * n);
for (let i = 0; i < n; i++) {
  const r = rows.subarray(9 * i, 9 * i + 9);
  const v = [r[0], r[1], r[2]], w = [r[3], r[4], r[5]], nn = [r[6], r[7], r[8]];
  const o = out.subarray(12 * i, 12 * i + 12);
  try {
    const [vo, wo] = mod.bounce3d(v, w, nn);
    o.set([...vo, ...wo]);
  } catch (e) {
    if (!(e instanceof RangeError)) throw e;
    o.set([NaN, NaN, NaN, NaN, NaN, NaN]);
    o[11] = e.code;
  }
  try {
    const res = mod.run(v, w, nn);
    o.set([...res.rest, res.time, res.bounces], 6);
  } catch (e) {
    if (!(e instanceof RangeError) || !(e.code in mod.REFUSALS)) throw e;
    o.set([NaN, NaN, NaN, NaN, e.code], 6);
  }
}
writeFileSync(process.argv[4], Buffer.from(out.buffer));
"""

DRIVER_CS = r"""using System;
using System.IO;

public static class Driver {
    public static void Main(string[] args) {
        byte[] b = File.ReadAllBytes(args[1]);
        int n = b.Length / 72;
        double[] o = new double[12 * n];
        double[] v = new double[3], w = new double[3], nn = new double[3];
        double[] vo = new double[3], wo = new double[3], rest = new double[3];
        for (int i = 0; i < n; i++) {
            for (int k = 0; k < 3; k++) {
                v[k] = BitConverter.ToDouble(b, 72 * i + 8 * k);
                w[k] = BitConverter.ToDouble(b, 72 * i + 24 + 8 * k);
                nn[k] = BitConverter.ToDouble(b, 72 * i + 48 + 8 * k);
            }
            double t = 0.0;
            int code = 0;
            bool refused = false;
            switch (args[0]) {
%(dispatch)s
                default: throw new ArgumentException("no surface " + args[0]);
            }
            for (int k = 0; k < 3; k++) {
                o[12 * i + k] = refused ? double.NaN : vo[k];
                o[12 * i + 3 + k] = refused ? double.NaN : wo[k];
                o[12 * i + 6 + k] = rest[k];
            }
            o[12 * i + 9] = t;
            o[12 * i + 10] = code;
            o[12 * i + 11] = refused ? -1.0 : 0.0;
        }
        byte[] ob = new byte[o.Length * 8];
        Buffer.BlockCopy(o, 0, ob, 0, ob.Length);
        File.WriteAllBytes(args[2], ob);
    }
}
"""


def _cs_case(name: str) -> str:
    cls = f"Golf.Greens.S_{name}"
    return (f'                case "{name}":\n'
            f"                    try {{ {cls}.Bounce3D(v, w, nn, vo, wo); }} catch (ArgumentException) "
            f"{{ refused = true; }}\n"
            f"                    code = {cls}.Run(v, w, nn, rest, out t);\n"
            f"                    break;")


def build(lang: str, names: tuple[str, ...], folder: Path) -> list[str]:
    """The command (before its arguments) that runs the exported surfaces ``names`` in ``lang``."""
    if lang == "c":
        if CC is None:
            pytest.skip("no C compiler: `cc` is not on PATH")
        for name in names:
            export_surface(SURFACES[name](), "c", folder / f"{name}.h", prefix=f"{name}_")
        dispatch = "\n".join(
            f'        if (!strcmp(argv[1], "{n}")) {{ found = 1; {n}_bounce3d(row, row + 3, row + 6, out, out + 3);\n'
            f"            code = {n}_run(row, row + 3, row + 6, out + 6, &t); }}" for n in names)
        includes = "\n".join(f'#include "{n}.h"' for n in names)
        (folder / "driver.c").write_text(DRIVER_C % {"includes": includes, "dispatch": dispatch})
        proc = subprocess.run([CC, *CFLAGS, "-o", "driver", "driver.c", "-lm"], cwd=folder, capture_output=True,
                              text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr
        return [str(folder / "driver")]
    if lang == "js":
        if NODE is None:
            pytest.skip("no Node.js: `node` is not on PATH")
        for name in names:
            export_surface(SURFACES[name](), "js", folder / f"{name}.mjs")
        (folder / "driver.mjs").write_text(DRIVER_JS)
        return [NODE, str(folder / "driver.mjs")]
    if MCS is None or MONO is None:
        pytest.skip(NO_MONO)
    for name in names:
        export_surface(SURFACES[name](), "cs", folder / f"S_{name}.cs", class_name=f"S_{name}",
                       namespace="Golf.Greens")
    (folder / "Driver.cs").write_text(DRIVER_CS % {"dispatch": "\n".join(_cs_case(n) for n in names)})
    sources = [f"S_{n}.cs" for n in names] + ["Driver.cs"]
    proc = subprocess.run([MCS, *MCS_FLAGS, "-out:driver.exe", *sources], cwd=folder, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return [MONO, str(folder / "driver.exe")]


def run_exported(cmd: list[str], name: str, rows: np.ndarray, folder: Path) -> np.ndarray:
    """(n, 12) results of the exported program for surface ``name`` (see the drivers)."""
    src, dst = folder / f"{name}_in.bin", folder / f"{name}_out.bin"
    np.ascontiguousarray(rows, dtype="<f8").tofile(src)
    which = str(folder / f"{name}.mjs") if cmd[0] == NODE else name  # the module, or the surface's name
    subprocess.run([*cmd, which, str(src), str(dst)], check=True, timeout=600, capture_output=True)
    return np.fromfile(dst, dtype="<f8").reshape(-1, 12)


def check(out: np.ndarray, ref: dict[str, np.ndarray]) -> dict[str, float]:
    """Assert the issue's tolerances; return the worst differences (and the share of identical bits)."""
    landing = ref["landing"]
    vo, wo = out[landing, 0:3], out[landing, 3:6]
    assert (out[~landing, 11] < 0).all(), "a ball on the ground bounced"  # bounce refuses v . n >= 0
    assert (out[landing, 11] == 0).all()
    dv = np.abs(vo - ref["vf"]).max(axis=1) / np.linalg.norm(ref["vf"], axis=1)
    dw = np.abs(wo - ref["wf"]).max(axis=1) / np.maximum(np.linalg.norm(ref["wf"], axis=1), 1e-300)
    assert (dv <= BOUNCE_RTOL).all(), f"bounce velocity off by {dv.max():.3g} of its norm"
    assert (dw <= BOUNCE_RTOL).all(), f"bounce spin off by {dw.max():.3g} of its norm"
    np.testing.assert_array_equal(out[:, 10], ref["bounces"])  # the number of bounces (no refusal here)
    drest = np.abs(out[:, 6:9] - ref["rest"]).max()
    dtime = np.abs(out[:, 9] - ref["time"]).max()
    assert drest <= REST_ATOL, f"rest position off by {drest:.3g} m"
    assert dtime <= REST_ATOL, f"time to rest off by {dtime:.3g} s"
    same = np.all(out[:, 6:10] == np.column_stack([ref["rest"], ref["time"]]), axis=1).mean()
    return {"bounce": float(max(dv.max(), dw.max())), "rest_m": float(drest), "time_s": float(dtime),
            "identical": float(same)}


# ------------------------------------------------------------------------------ agreement
@pytest.mark.parametrize("lang", ["c", "js", "cs"])
def test_a_surface_exported_agrees_with_bounce_and_run(tmp_path, lang):
    """200 landings on slopes up to 2.5 degrees and balls on the ground, the Rigid surface: the issue's tolerances
    (the C is bouncelab's arithmetic to the bit)."""
    cmd = build(lang, ("rigid",), tmp_path)
    rows = shots(200, seed=1)
    ref = reference(SURFACES["rigid"](), rows)
    figures = check(run_exported(cmd, "rigid", rows, tmp_path), ref)
    if lang == "c":
        assert figures["bounce"] == figures["rest_m"] == 0.0 and figures["identical"] == 1.0


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["c", "js", "cs"])
def test_three_surfaces_2000_landings_on_slopes(tmp_path, lang):
    """The issue's check: a preset, a Rigid and a PennerFixed surface with fade_xdot, 2,000 landings each on
    slopes up to 2.5 degrees: bounce within 1e-12, rest within 1e-9 m, the same number of bounces."""
    names = tuple(SURFACES)
    cmd = build(lang, names, tmp_path)
    for k, name in enumerate(names):
        rows = shots(2000, seed=10 + k)
        ref = reference(SURFACES[name](), rows)
        assert ref["bounces"].max() > 2 and (ref["bounces"] == 0).sum() == 2  # bouncing shots, two on the ground
        check(run_exported(cmd, name, rows, tmp_path), ref)


@pytest.mark.slow
@pytest.mark.parametrize("lang", ["c", "js", "cs"])
def test_laws_lifted_in_the_plane_of_travel_and_of_the_slip(tmp_path, lang):
    """PiecewiseAffine (its 2-D kernel in the plane of travel, arrays baked in) and CompliantImpact (in the plane of
    the slip; sin and cos) on 500 landings each: the same tolerances."""
    SURFACES.update(OTHER_LIFTS)
    try:
        cmd = build(lang, tuple(OTHER_LIFTS), tmp_path)
        for k, name in enumerate(OTHER_LIFTS):
            rows = shots(500, seed=20 + k)
            figures = check(run_exported(cmd, name, rows, tmp_path), reference(SURFACES[name](), rows))
            if lang == "c":
                assert figures["bounce"] == figures["rest_m"] == 0.0
    finally:
        for name in OTHER_LIFTS:
            SURFACES.pop(name)


# ------------------------------------------------------------------------------ refusals
# (row v, w, n; the code; whether bouncelab.ground.bounce refuses it too)
BAD = [
    (([np.nan, 0.0, -5.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), eg.NOT_FINITE, True),
    (([5.0, 0.0, -5.0], [0.0, np.inf, 0.0], [0.0, 0.0, 1.0]), eg.NOT_FINITE, True),
    (([5.0, 0.0, -5.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]), eg.ZERO_NORMAL, True),
    (([5.0, 0.0, 5.0], [0.0, 0.0, 0.0], [0.0, 0.0, -1.0]), eg.NOT_UP, False),
    (([5.0, 0.0, -3.0e6], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), eg.TOO_FAST, True),
    (([5.0, 0.0, -5.0], [0.0, -2.0e8, 0.0], [0.0, 0.0, 1.0]), eg.TOO_MUCH_SPIN, True),
    (([5.0, 0.0, -5.0], [0.0, 0.0, 0.0], [math.sin(0.2), 0.0, math.cos(0.2)]), eg.TOO_STEEP, False),
    (([5.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), eg.NOT_LANDING, True),
]


def test_bouncelab_refuses_the_bad_rows_too():
    """Every bad row is one bouncelab.ground refuses with a DataError (so the codes mirror its checks)."""
    s = SURFACES["rigid"]()
    for (v, w, n), code, by_bounce in BAD:
        with pytest.raises(DataError):
            run(v, w, s, n, units=SI)
        if by_bounce:
            with pytest.raises(DataError):
                bounce(s, v, w, n, units=SI)
        assert code in REFUSALS


@pytest.mark.parametrize("lang", ["c", "js", "cs"])
def test_refused_shots_give_their_code(tmp_path, lang):
    cmd = build(lang, ("rigid",), tmp_path)
    rows = np.array([np.concatenate(r) for r, _, _ in BAD])
    out = run_exported(cmd, "rigid", rows, tmp_path)
    np.testing.assert_array_equal(out[:, 10], [code for _, code, _ in BAD])
    assert np.isnan(out[:, 6:10]).all()  # rest and time NaN (C, C#) or the error thrown (JavaScript)
    by_bounce = np.array([b for _, _, b in BAD])
    np.testing.assert_array_equal(out[:, 11] < 0, by_bounce)  # bounce refuses what ground.bounce refuses
    if lang == "js":  # the RangeError's code is the refusal's
        np.testing.assert_array_equal(out[by_bounce, 11], [c for _, c, b in BAD if b])


def test_the_input_kernels_match_the_ground_phase_input_checks():
    """prepare_run (numba, the Python the exports translate) gives the scaled states, unit normal and landing
    test of ground.run, to the bit, on normals of every magnitude."""
    from bouncelab.core.units import BALL_RADIUS_M
    from bouncelab.ground._inputs import unit_normals

    rows = shots(300, seed=3)
    rows[:50, 6:9] *= 1e-160
    rows[50:100, 6:9] *= 1e150
    s = SURFACES["rigid"]()
    V, W, N = np.empty((1, 3)), np.empty((1, 3)), np.empty((1, 3))
    landing = np.empty(1, dtype=np.int64)
    for row in rows:
        code = eg.prepare_run(row[0:3], row[3:6], row[6:9], 1.0 / BALL_RADIUS_M, 1e8, 1.4 * s.rolling_resistance,
                              3.5 * s.sliding_friction, V, W, N, landing)
        assert code == 0
        n_ref, _ = unit_normals(row[6:9], upward=True)
        np.testing.assert_array_equal(N[0], n_ref[0])
        np.testing.assert_array_equal(V[0], row[0:3] * (1.0 / BALL_RADIUS_M))
        vn = V[0, 0] * N[0, 0] + V[0, 1] * N[0, 1] + V[0, 2] * N[0, 2]
        assert landing[0] == (vn < -1e-9 * math.sqrt(V[0, 0] ** 2 + V[0, 1] ** 2 + V[0, 2] ** 2))


# ------------------------------------------------------------------------------ the files
def test_the_c_header_says_what_it_bakes_in_and_compiles_as_cpp(tmp_path):
    s = preset("green-fast")
    text = export_surface(s, "c")
    assert "void bouncelab_bounce3d(const double v[3], const double w[3], const double n[3], double v_out[3]," in text
    assert "BOUNCELAB_API int bouncelab_run(const double v[3], const double w[3], const double n[3], double rest[3]," \
           in text
    for fact in ("min_apex_m = 0.002", "max_bounces = 100", "air=None", repr(s.rolling_resistance),
                 "Provenance: " + s.description[:40], "-ffp-contract=off"):
        assert fact in text, fact
    if CXX is None:
        pytest.skip("no C++ compiler: `c++` is not on PATH")
    (tmp_path / "s.h").write_text(text)
    (tmp_path / "main.cpp").write_text('#include "s.h"\nint main() { double v[3] = {10, 0, -5}, w[3] = {0, -200, 0},'
                                       ' n[3] = {0, 0, 1}, r[3], t; return bouncelab_run(v, w, n, r, &t) > 0 ? 0 : 1;'
                                       ' }\n')
    subprocess.run([CXX, "-std=c++11", "-O2", "-Wall", "-Wextra", "-Werror", "main.cpp", "-o", "main"], cwd=tmp_path,
                   check=True, timeout=300)
    subprocess.run([str(tmp_path / "main")], check=True)


def test_no_air_no_samples_no_pow_in_the_output():
    """The run's optional paths (air, the path's samples and its recorded bounces) are empty arrays in the
    translation: none of their code is in the output (no RK4 step, no curved-glide sampling with pow)."""
    text = export_surface(SURFACES["rigid"](), "c")
    for name in ("air_step", "air_flight", "curve_r", "curve_at", "pow(", "BT[", "tsample"):
        assert name not in text, name
    assert "(void)OFFSETS;" in text  # read only where bounces are recorded: never
    assert "bouncelab_f_run_rows(" in text and "bouncelab_f_rigid_kernel_3d(" in text


def test_options_are_baked_and_checked():
    text = export_surface("turf-A", "js", min_apex_m=0.01, max_bounces=7)
    assert "min_apex_m = 0.01" in text and "max_bounces = 7" in text
    with pytest.raises(ParameterError, match="max_bounces"):
        export_surface("turf-A", "js", max_bounces=0)
    with pytest.raises(ParameterError, match="min_apex_m"):
        export_surface("turf-A", "js", min_apex_m=-1.0)
    with pytest.raises(ParameterError, match="no preset surface"):
        export_surface("green-nowhere", "c")
    with pytest.raises(ParameterError, match="prefix is for C headers"):
        export_surface("turf-A", "js", prefix="x_")
    with pytest.raises(ParameterError, match="class_name"):
        export_surface("turf-A", "cs", class_name="Run")
    with pytest.raises(ParameterError, match="languages"):
        export_surface("turf-A", "rust")


def test_a_law_without_a_kernel_is_refused():
    class NumpyRigid(bl.Rigid):
        kernel = None

    with pytest.raises(ExportError, match="no compiled kernel"):
        export_surface(Surface("np", NumpyRigid(r=0.5, mu=0.4), sliding_friction=0.4, stimp_ft=9), "c")


# ------------------------------------------------------------------------------ the command line
def test_cli_exports_a_surface_file_and_a_preset(tmp_path, capsys):
    path = tmp_path / "rigid.json"
    SURFACES["rigid"]().to_json(path)
    assert main(["export", str(path), "--lang", "c", "-o", str(tmp_path / "s.h")]) == EXIT_OK
    assert "int bouncelab_run(" in (tmp_path / "s.h").read_text()
    assert "surface 'rigid green'" in capsys.readouterr().out
    assert main(["export", "--surface", "green-fast", "--lang", "cs", "--namespace", "Golf", "--class-name",
                 "GreenFast"]) == EXIT_OK
    out = capsys.readouterr().out
    assert "namespace Golf {" in out and "public static class GreenFast {" in out
    assert main(["export", "--surface", "green-fast", "--lang", "js", "-o", str(tmp_path / "g.mjs")]) == EXIT_OK
    assert "export function run(v, w, n)" in (tmp_path / "g.mjs").read_text()
    # a law file still exports the law
    law = tmp_path / "law.json"
    bl.Rigid(r=0.5, mu=0.4).to_json(law)
    assert main(["export", str(law), "--lang", "c"]) == EXIT_OK
    assert "bouncelab_predict_one" in capsys.readouterr().out


def test_cli_surface_errors(tmp_path, capsys):
    assert main(["export", "--lang", "c"]) == EXIT_USAGE
    assert "--surface NAME" in capsys.readouterr().err
    assert main(["export", "--surface", "green-fast", "Rigid", "--lang", "c"]) == EXIT_USAGE
    capsys.readouterr()
    assert main(["export", "--surface", "green-nowhere", "--lang", "c"]) == EXIT_FIT
    assert "no preset surface 'green-nowhere'" in capsys.readouterr().err
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"surface": "x", "law": {"law": "Rigid"}, "sliding_friction": 0.4}))
    assert main(["export", str(bad), "--lang", "c"]) == EXIT_FIT
    assert "stimp_m" in capsys.readouterr().err


# ------------------------------------------------------------------------------ the examples of docs/simulators.md
SNIPPETS = Path(__file__).resolve().parents[1] / "docs" / "snippets"


@pytest.mark.parametrize("name", [
    "export_surface_cpp",
    pytest.param("export_surface_cs", marks=pytest.mark.slow),
    pytest.param("export_surface_js", marks=pytest.mark.slow),
])
def test_the_docs_examples_print_bouncelab_s_numbers(tmp_path, name):
    """The pages' examples (a C++ loop compiled with c++, a Unity-shaped C# script compiled by mcs, a web page's
    script run by Node) run, and every line of bouncelab.ground's numbers they print after them is one the exported
    code printed."""
    import os
    import sys

    need = {"export_surface_cpp": [CXX], "export_surface_cs": [MCS, MONO], "export_surface_js": [NODE]}[name]
    if None in need:
        pytest.skip(f"{name} needs c++, mcs/mono or node, which are not on PATH")
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}")
    proc = subprocess.run(["bash", str(SNIPPETS / f"{name}.sh")], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    exported, _, ours = proc.stdout.partition("# bouncelab.ground, the same")
    ours = ours.splitlines()[1:]
    assert len(ours) >= 1 and all(line in exported.splitlines() for line in ours), proc.stdout
