"""Compiled prediction under fork, spawn and threads, bit-identical results, and kernel caches (issue 7)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core._parallel import PARALLEL_MIN, num_threads, set_num_threads

ROOT = Path(__file__).resolve().parents[1]

LAWS = [
    bl.Rigid.published("A"),
    bl.PennerFixed.published("A"),
    bl.PennerVarying.published("B"),
    bl.PennerFixed.published("B").replace(fade_xdot=40.0),
    bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3),
    bl.PiecewiseAffine.published("B"),
]


def _run(code: str, *, env: dict | None = None, timeout: float = 240, script: Path | None = None
         ) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter (from a file when ``script`` is given: spawn needs one)."""
    if script is not None:
        script.write_text(textwrap.dedent(code))
    args = [str(script)] if script is not None else ["-c", textwrap.dedent(code)]
    return subprocess.run([sys.executable, *args], capture_output=True, text=True,
                          timeout=timeout, env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})})


@pytest.fixture
def threads():
    before = num_threads()
    yield set_num_threads
    set_num_threads(before)


@pytest.mark.parametrize("law", LAWS, ids=lambda m: type(m).__name__)
def test_results_do_not_depend_on_batch_size_or_threads(law, threads):
    """bouncelab 0.1: 143 of campaign B's 693 lift-offs changed bits inside a 30,000-row call."""
    p = bl.load_campaign("B").landing.values
    alone = law.predict(p, plausible=None)
    rng = np.random.default_rng(0)
    filler = np.abs(rng.normal(500.0, 300.0, (200_000, 3))) * np.array([1.0, -1.0, 1.0]) + [0.0, -1.0, 0.0]
    for size, at in ((30_000, 0), (30_000, 12_345), (PARALLEL_MIN + 1, 40_000), (200_000, 150_001)):
        big = filler[:size].copy()
        big[at:at + len(p)] = p
        for n_threads in (1, 2, 3):
            threads(n_threads)
            np.testing.assert_array_equal(law.predict(big, plausible=None)[at:at + len(p)], alone)
            np.testing.assert_array_equal(law.regime(big, codes=True, plausible=None)[at:at + len(p)],
                                          law.regime(p, codes=True, plausible=None))
    for row in (0, 17, len(p) - 1):
        np.testing.assert_array_equal(law.predict(p[row], plausible=None), alone[row])


def test_error_sums_do_not_depend_on_threads(threads):
    rng = np.random.default_rng(1)
    p0 = np.abs(rng.normal(600.0, 300.0, (3 * PARALLEL_MIN, 3))) * np.array([1.0, -1.0, 1.0]) + [0.0, -1.0, 0.0]
    pf = bl.Rigid(r=0.4, mu=0.3).predict(p0, plausible=None) + rng.normal(0.0, 20.0, p0.shape)
    inv = 1.0 / np.linalg.norm(p0, axis=1)
    values = []
    for n_threads in (1, 2, 4):
        threads(n_threads)
        for law in (bl.Rigid(), bl.PennerVarying()):
            f = law._error_function(p0, pf, inv)
            values.append((n_threads, type(law).__name__, tuple(f([0.4, 0.3, 1e-4][:len(law.parameter_specs)]))))
    for name in ("Rigid", "PennerVarying"):
        got = {v[2] for v in values if v[1] == name}
        assert len(got) == 1, got


def test_threads_calling_predict_at_once():
    law = bl.PennerVarying.published("A")
    rng = np.random.default_rng(2)
    arrays = [np.abs(rng.normal(500.0, 300.0, (150_000, 3))) * np.array([1.0, -1.0, 1.0]) + [0.0, -1.0, 0.0]
              for _ in range(6)]
    expected = [law.predict(a, plausible=None) for a in arrays]
    results: dict[int, np.ndarray] = {}

    def work(i: int) -> None:
        for _ in range(3):
            results[i] = law.predict(arrays[i], plausible=None)

    workers = [threading.Thread(target=work, args=(i,)) for i in range(6)]
    for t in workers:
        t.start()
    for t in workers:
        t.join(timeout=120)
    for i in range(6):
        np.testing.assert_array_equal(results[i], expected[i])


@pytest.mark.parametrize("start", ["fork", "spawn"])
def test_processes_after_a_large_predict(start, tmp_path):
    """bouncelab 0.1: after a large predict (GNU OpenMP), a forked child was killed and Pool(fork).map hung."""
    proc = _run(f"""
        import multiprocessing as mp
        import numpy as np
        import bouncelab as bl

        def child(n):
            law = bl.PennerFixed.published("A")
            p = np.tile([[900.0, -700.0, 150.0]], (n, 1))
            return float(law.predict(p)[-1, 0])

        if __name__ == "__main__":
            law = bl.PennerFixed.published("A")
            big = np.tile([[900.0, -700.0, 150.0]], (300_000, 1))
            ref = float(law.predict(big)[-1, 0])
            ctx = mp.get_context("{start}")
            with ctx.Pool(2) as pool:
                got = pool.map(child, [10, 300_000, 100_000])
            assert got == [ref] * 3, (got, ref)
            p = ctx.Process(target=child, args=(300_000,))
            p.start(); p.join(60)
            assert p.exitcode == 0, p.exitcode
            print("ok")
    """, script=tmp_path / "procs.py")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "ok"
    assert "fork() called from a process already using" not in proc.stderr


# ------------------------------------------------------------------------------ caches
PREDICT = """
import warnings
import bouncelab as bl
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    out = bl.PennerVarying.published("A").predict([[900.0, -700.0, 150.0]])
print(repr(float(out[0, 0])))
for w in caught:
    print("WARNING", w.message)
"""


@pytest.mark.slow
def test_damaged_cache_recovers(tmp_path):
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    first = _run(PREDICT, env=env)
    assert first.returncode == 0, first.stderr
    files = [p for p in (tmp_path / "cache").rglob("*") if p.suffix in (".nbi", ".nbc")]
    assert len(files) >= 2
    for p in files:  # damage every entry: truncated and garbage
        p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 3] if p.suffix == ".nbc" else b"\x80garbage")
    second = _run(PREDICT, env=env)
    assert second.returncode == 0, second.stderr
    assert second.stdout.splitlines()[0] == first.stdout.splitlines()[0]
    assert sum("damaged numba cache" in line for line in second.stdout.splitlines()) == 1  # one line
    third = _run(PREDICT, env=env)  # the entries were rewritten
    assert third.returncode == 0 and "WARNING" not in third.stdout


@pytest.mark.slow
def test_no_cache_location_falls_back(tmp_path):
    """No locator at all (a read-only install, no writable home): a private temporary folder, else no cache."""
    no_locators = "import numba.core.caching as c; c.CompileResultCacheImpl._locator_classes = ()\n"
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    run = _run(no_locators + PREDICT, env={"TMPDIR": str(tmp), "NUMBA_CACHE_DIR": ""})
    assert run.returncode == 0, run.stderr
    assert "WARNING" not in run.stdout
    assert list(tmp.glob("bouncelab-numba-*/**/*.nbi"))  # cached in the private folder
    no_folder = "import bouncelab.core._jit as j; j.cache_directory = lambda: None\n"
    run = _run(no_locators + no_folder + PREDICT, env={"NUMBA_CACHE_DIR": ""})
    assert run.returncode == 0, run.stderr
    warnings = [line for line in run.stdout.splitlines() if line.startswith("WARNING")]
    assert len(warnings) == 1 and "cannot cache" in warnings[0]


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0 or shutil.which("setpriv") is None,
                    reason="needs root and setpriv to run as another user")
def test_read_only_install_run_by_another_user(tmp_path):
    """Installed root-owned, run by 'nobody' without a writable home: bouncelab 0.1 failed at the first predict."""
    import pwd

    try:
        nobody = pwd.getpwnam("nobody")
    except KeyError:
        pytest.skip("no user 'nobody'")
    # The test needs an interpreter and packages that 'nobody' can read; a checkout whose virtual environment
    # lies in a private (0700) folder has neither, and the test would measure the folder, not bouncelab.
    probe = subprocess.run(["setpriv", f"--reuid={nobody.pw_uid}", f"--regid={nobody.pw_gid}", "--clear-groups",
                            sys.executable, "-c", "import numpy, numba, scipy, pandas, xarray, nlopt, sklearn"],
                           capture_output=True, text=True, env={"PATH": "/usr/bin:/bin", "HOME": "/nonexistent"},
                           cwd="/", timeout=240)
    if probe.returncode != 0:
        last = (probe.stderr.strip().splitlines() or ["(no message)"])[-1]
        pytest.skip(f"'nobody' cannot run this interpreter with its packages ({sys.executable}: {last}); "
                    "the virtual environment is in a folder other users cannot read")
    install = tmp_path / "site"
    shutil.copytree(ROOT / "bouncelab", install / "bouncelab", ignore=shutil.ignore_patterns("__pycache__"))
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    os.chmod(tmp, 0o1777)
    os.chmod(tmp_path, 0o755)
    for p in [install, *install.rglob("*")]:
        os.chmod(p, 0o555 if p.is_dir() else 0o444)
    env = {"PATH": "/usr/bin:/bin", "HOME": "/nonexistent", "TMPDIR": str(tmp), "PYTHONPATH": str(install)}
    proc = subprocess.run(["setpriv", f"--reuid={nobody.pw_uid}", f"--regid={nobody.pw_gid}", "--clear-groups",
                           sys.executable, "-c", PREDICT], capture_output=True, text=True, env=env, cwd="/",
                          timeout=240)
    assert proc.returncode == 0, proc.stderr
    assert float(proc.stdout.splitlines()[0]) == pytest.approx(
        float(bl.PennerVarying.published("A").predict([[900.0, -700.0, 150.0]])[0, 0]), rel=1e-15)


def test_run_rows_from_few_rows_keeps_order_and_runs_inner_loops_serially(threads):
    """run_rows with a low min_rows (calibrate's batched law calls, whose rows may each cost an integration):
    every part in order, the same bits for any number of threads; a prediction inside a part, on a pool thread or
    on the calling thread, runs serially (no nested sharing); the calling thread is released afterwards."""
    from bouncelab.core import _parallel
    from bouncelab.core._parallel import run_rows

    law = bl.PennerVarying.published("A")
    rng = np.random.default_rng(3)
    p = np.abs(rng.normal(500.0, 300.0, (PARALLEL_MIN + 700, 3))) * np.array([1.0, -1.0, 1.0]) + [0.0, -1.0, 0.0]
    expected = law.predict(p, plausible=None)
    for n_threads in (1, 2, 3):
        threads(n_threads)
        out = np.empty_like(p)
        seen: list[bool] = []

        def part(out: np.ndarray, seen: list[bool], start: int, stop: int) -> tuple[int, int]:
            seen.append(getattr(_parallel._local, "in_pool", False))
            out[start:stop] = law.predict(p[start:stop], plausible=None)  # a large part shares unless inside one
            return start, stop

        parts = run_rows(part, len(p), out, seen, min_rows=512, min_part=len(p) // 3)
        np.testing.assert_array_equal(out, expected)
        assert [a for a, _ in parts] == sorted(a for a, _ in parts) and parts[0][0] == 0 and parts[-1][1] == len(p)
        assert len(parts) == (1 if n_threads == 1 else 4)  # parts of len(p) // 3 rows, the last one short
        assert all(seen) == (n_threads > 1)
        assert not getattr(_parallel._local, "in_pool", False)
    threads(2)
    assert run_rows(lambda a, b: (a, b), 300, min_rows=512) == [(0, 300)]  # below min_rows: one serial call
