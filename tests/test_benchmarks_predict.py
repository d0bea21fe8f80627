"""The prediction benchmarks run (``--quick``: a small run that must exit 0), so that none rots silently (issue 30).

They measure nothing here: the figures come from full runs on a quiet machine (see the README)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow  # seconds each once compiled; bench_contact compiles the contact laws' kernels on a cold cache
@pytest.mark.parametrize(("script", "says"), [
    ("bench_predict.py", "hand-written numba loop"),
    ("bench_predict_one.py", "hand-written Python rigid bounce"),
    ("bench_contact.py", "TurfContact.predict"),
])
def test_the_benchmark_runs_quickly(script, says):
    proc = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), "--quick"], capture_output=True,
                          text=True, cwd=ROOT, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert says in proc.stdout and "Traceback" not in proc.stderr
