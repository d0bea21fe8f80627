"""Every benchmark script runs (``python benchmarks/NAME.py --quick``), so that none rots silently (issue 30).

A benchmark script is any ``benchmarks/*.py`` with an ``if __name__ == "__main__"`` block (``contact_reference.py``
and ``numpy_reference.py`` are modules the benchmarks import). Each must take ``--quick`` (small sizes, the same
code paths as its full run), exit 0 without a traceback and print its table, the peer beside bouncelab, and
where it checks that the two sides agree, that they do. A new script fails here until it has ``--quick`` and its
phrase below.

The quick runs measure nothing: the figures come from full runs on a quiet machine (see the README). Together
they take about 3 minutes from a cold numba cache on a 2-core machine, hence ``slow``.
"""

from __future__ import annotations

import ast
import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCHMARKS = ROOT / "benchmarks"

#: What each script's output must contain once it ran: its table (bouncelab beside the peer) and, where the script
#: compares the two sides' results, the verdict that they agree.
PHRASES: dict[str, tuple[str, ...]] = {
    "bench_algorithms.py": ("random fitting problems", "median evals"),
    "bench_assess.py": ("| task | time, s |",),
    "bench_cluster.py": ("identical resamples",),
    "bench_contact.py": ("CompliantImpact vs solve_ivp", "CraterContact vs solve_ivp", "TurfContact.predict",
                         "TurfContact global fit to campaign B"),
    "bench_export.py": ("Python loop: the kernel's formula in Python floats", "target: >= 100 M bounces/s"),
    "bench_fit.py": ("DE+NumPy ms", "TangentialRestitution"),
    "bench_fit_surface.py": ("fit_surface, ProcessPoolExecutor(2)", "identical: True", "held-out median"),
    "bench_ground.py": ("predict_one loop / ground.run", "they agree to"),
    "bench_load.py": ("pandas.read_csv + checks", "same numbers: True"),
    "bench_piecewise.py": ("speed-up", "campaign B (693 bounces): delta"),
    "bench_predict.py": ("hand-written numba loop", "identical results: True"),
    "bench_predict_one.py": ("hand-written Python rigid bounce", "gives the same numbers: True"),
    "bench_simulation.py": ("measure_bounce per bounce", "measured by both"),
    "bench_tracking.py": ("frames/s", "OpenCV HoughCircles"),
    "bench_tracking_camera.py": ("12-bit .cine (no drop)", "rounded to 8 bits (no drop)", "frames/s"),
    "bench_tracking_memory.py": ("peak RSS", "the clip decoded into memory"),
    "calibrate_surrogates.py": ("paper  simulated", "max |dev|"),
    "surrogate_limits.py": ("delta (floor)", "CompliantImpact"),
}

#: What it must print besides where a peer is installed: (script, what is needed, phrase).
WHERE_INSTALLED = [
    ("bench_ground.py", lambda: shutil.which("cc") or shutil.which("gcc"),
     "exported C gives the same bits as run: flat True, slope True"),
    ("bench_export.py", lambda: shutil.which("node"), "JavaScript (Node"),
    ("bench_tracking_camera.py", lambda: importlib.util.find_spec("pims"), "the same pixels: True"),
]

def scripts() -> list[str]:
    """The benchmark scripts: every benchmarks/*.py run as a program."""
    return sorted(p.name for p in BENCHMARKS.glob("*.py") if 'if __name__ == "__main__"' in p.read_text())


def cases() -> list:
    return scripts()


def takes_quick(source: str) -> bool:
    """Whether the source declares ``--quick`` to argparse (an ``add_argument("--quick", ...)`` call)."""
    return any(isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
               and node.func.attr == "add_argument" and node.args and isinstance(node.args[0], ast.Constant)
               and node.args[0].value == "--quick" for node in ast.walk(ast.parse(source)))


def test_the_benchmark_scripts_are_found():
    found = scripts()
    assert {"bench_predict.py", "bench_contact.py", "calibrate_surrogates.py"} <= set(found)
    assert "numpy_reference.py" not in found and "contact_reference.py" not in found  # modules, not scripts
    assert set(PHRASES) == set(found), "every benchmark script needs its phrase in PHRASES, and only those"


def test_takes_quick_reads_argparse_not_text():
    assert takes_quick('ap.add_argument("--quick", action="store_true")')
    assert not takes_quick('"""Run with --quick."""\nap.add_argument("--quickly")')


@pytest.mark.parametrize("script", cases())
def test_every_benchmark_declares_quick(script):
    assert takes_quick((BENCHMARKS / script).read_text()), f"{script} has no --quick argument"


@pytest.mark.slow  # 3 to 30 s each from a cold numba cache; about 3 minutes in all
@pytest.mark.parametrize("script", cases())
def test_the_benchmark_runs_quickly(script):
    proc = subprocess.run([sys.executable, str(BENCHMARKS / script), "--quick"], capture_output=True, text=True,
                          cwd=ROOT, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr, proc.stderr[-3000:]
    missing = [p for p in PHRASES[script] if p not in proc.stdout]
    assert not missing, f"{script} --quick did not print {missing}:\n{proc.stdout[-3000:]}"
    for name, available, phrase in WHERE_INSTALLED:
        if name == script and available():
            assert phrase in proc.stdout, f"{script} --quick did not print {phrase!r}:\n{proc.stdout[-3000:]}"
    if script == "bench_tracking_memory.py":
        assert proc.stdout.count("peak RSS") == 2  # the AVI and the .cine


@pytest.mark.slow  # about 10 s
def test_the_coverage_benchmark_runs_quickly():
    """bench_assess.py's --coverage mode (issue 30's done-when, with the likelihood profile) runs too: its tables
    per campaign, over the campaigns and of the profile."""
    proc = subprocess.run([sys.executable, str(BENCHMARKS / "bench_assess.py"), "--coverage", "--profile", "--quick",
                           "--seeds", "1"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-3000:]
    for phrase in ("likelihood's peak of mu's median", "per fresh campaign", "median intervals hold truth"):
        assert phrase in proc.stdout, phrase
