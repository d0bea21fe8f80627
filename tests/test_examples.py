"""Every script in examples/ runs to completion and prints what it promises.

Each script runs in a subprocess with the interpreter running the tests (the project's
venv), from a temporary working directory, with the Agg matplotlib backend.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

# script name -> (extra arguments, texts its standard output must contain)
EXPECTED: dict[str, list[tuple[list[str], list[str]]]] = {
    "fit_campaign.py": [([], [
        "[[Fit]] Rigid by global",
        "[[Fit]] PiecewiseAffine by plane",
        "[[Fit]] TangentialRestitution",
        "in brackets the paper's Table 3 on its measured bounces (a reference, not a validation)",
        "(the paper's figure is held-out",
        "identical: True",
        "same prediction: True",
    ])],
    "compare_laws.py": [([], [
        "### Laws fitted to campaign B (errors on the held-out bounces",
        "| quantity | Rigid | PennerVarying | PennerFixed | PiecewiseAffine |",
        "### PiecewiseAffine by class",
        "611 bounces fitted, 82 held out",
        "SIMULATED CAMPAIGN, NOT MEASURED BOUNCES (surrogate 'turf')",
    ])],
    "trajectory_with_bounce.py": [
        ([], ["law: PennerFixed(", "quadratic drag K = 4.680e-03 1/m", " 1    5.61", "it rolls on from x ="]),
        (["--law", "PiecewiseAffine", "--published", "--max-bounces", "3", "--plot"],
         ["(published campaign B)", "still hopping after 3 bounces", "path drawn to "]),
    ],
    "track_clip.py": [([], [
        "39 frames of 256 x 128 px at 5000 fps",
        "frames where it was lost: []",
        "touch-down at frame 16",
        "liftoff      omega",
    ])],
    "load_your_own_file.py": [([], [
        "without units=: DataError:",
        "loaded 40 bounces, 8 settings (velocity m/s, spin rpm; data kind measured)",
        "Rigid(r=0.3",
        "CrossValidation(PennerFixed, k=4",
    ])],
}


def test_every_example_is_covered() -> None:
    scripts = sorted(p.name for p in EXAMPLES.glob("*.py"))
    assert scripts == sorted(EXPECTED), "add new example scripts to EXPECTED in tests/test_examples.py"


def _cases():
    for name, runs in EXPECTED.items():
        for k, (args, texts) in enumerate(runs):
            yield pytest.param(name, args, texts, id=f"{name}-{k}")


@pytest.mark.parametrize(("name", "args", "texts"), list(_cases()))
def test_example_runs(name: str, args: list[str], texts: list[str], tmp_path: Path) -> None:
    script = EXAMPLES / name
    text = script.read_text()
    assert text.startswith('"""'), f"{name} needs a module docstring saying what it shows and how to run it"
    assert f"python examples/{name}" in text, f"{name}'s docstring should say how to run it"
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(script), *args], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"{name} {args} failed:\n{proc.stdout}\n{proc.stderr}"
    for expected in texts:
        assert expected in proc.stdout, f"{name} {args}: {expected!r} not in output:\n{proc.stdout}"
    assert not any(tmp_path.iterdir()), f"{name} wrote files to its working directory"
    drawn = re.search(r"path drawn to (\S+)", proc.stdout)
    if drawn:
        png = Path(drawn.group(1))
        assert png.is_file() and png.stat().st_size > 1000
        shutil.rmtree(png.parent)
