"""A run gives the same bits for a shot whatever the batch, its position in it and the thread count (issue 25, item 6).

As in tests/test_bits.py: the compiled loops of the ground phase allow no floating-point freedom that could
change a finite result (bouncelab.core._jit.ROW_FLAGS), and every shot is its own row.
"""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core import _jit, _parallel
from bouncelab.ground import Air, preset, run
from bouncelab.ground import _kernels as gk
from bouncelab.laws import set_num_threads


def shots(m: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Landings and balls on the ground (any heading, sidespin) on flat ground and gentle slopes."""
    speed = rng.uniform(2.0, 35.0, m)
    angle = rng.uniform(0.2, 1.3, m)
    angle[::5] = 0.0  # on the ground
    heading = rng.uniform(0, 2 * np.pi, m)
    v = np.column_stack([speed * np.cos(angle) * np.cos(heading), speed * np.cos(angle) * np.sin(heading),
                         -speed * np.sin(angle)])
    w = rng.uniform(-600.0, 900.0, (m, 3))
    tilt = rng.uniform(-0.03, 0.03, (m, 3))
    tilt[::3] = 0.0  # flat ground
    n = tilt + np.array([0.0, 0.0, 1.0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    v -= np.einsum("ij,ij->i", v, n)[:, None] * n * (angle == 0)[:, None]  # along the ground exactly
    return v, w, n


def outcome(v, w, n, surface, **kw):
    r = run(v, w, surface, normal=n, units={"velocity": "m/s", "spin": "rad/s"}, **kw)
    ds = r.sample(20.0)
    return r.rest_position, r.totals.to_numpy(dtype=float), ds


def assert_same_shots(a, b, rows):
    np.testing.assert_array_equal(a[0][rows], b[0])
    np.testing.assert_array_equal(a[1][rows], b[1])
    nt = min(a[2].sizes["time"], b[2].sizes["time"])  # a batch samples until its last shot rests
    for name in ("position", "velocity", "spin", "phase"):
        np.testing.assert_array_equal(a[2][name].values[rows, :nt], b[2][name].values[:, :nt])


@pytest.mark.parametrize(("surface", "air"), [pytest.param("turf-A", None, marks=pytest.mark.slow),
                                              ("green-fast", None), ("turf-B", Air())])
def test_a_shot_gives_the_same_bits_alone_in_a_batch_permuted_and_repeated(surface, air):
    rng = np.random.default_rng(len(surface))
    v, w, n = shots(23, rng)  # odd: a scalar tail after any vector width
    s = preset(surface)
    batch = outcome(v, w, n, s, air=air)
    for i in (0, 4, 5, 22):  # a landing, a ball on the ground, on flat ground and on slopes
        assert_same_shots(batch, outcome(v[i:i + 1], w[i:i + 1], n[i:i + 1], s, air=air), [i])
    perm = rng.permutation(23)
    assert_same_shots(batch, outcome(v[perm], w[perm], n[perm], s, air=air), perm)
    rep = np.repeat([7], 9)
    assert_same_shots(batch, outcome(v[rep], w[rep], n[rep], s, air=air), rep)


def test_a_shot_gives_the_same_bits_whatever_the_number_of_threads(monkeypatch):
    """Small parts so that a few hundred shots are shared by the thread pool (law prediction included)."""
    rng = np.random.default_rng(5)
    v, w, n = shots(301, rng)
    s = preset("green-medium").replace(law=bl.CompliantImpact(r=0.4, mu=0.5, kappa=1.3))
    monkeypatch.setattr(_parallel, "PARALLEL_MIN", 64)
    monkeypatch.setattr(_parallel, "CHUNK", 32)
    results = []
    try:
        for threads in (1, 3, 2):
            set_num_threads(threads)
            results.append(outcome(v, w, n, s))
    finally:
        set_num_threads(_parallel._default_threads())
    for other in results[1:]:
        assert_same_shots(results[0], other, np.arange(301))


def test_the_ground_loops_allow_no_floating_point_freedom_beyond_row_flags():
    from bouncelab.ground.bounce3d import compiled_lift

    loops = [getattr(gk, name) for name in dir(gk) if hasattr(getattr(gk, name), "targetoptions")]
    laws = (bl.Rigid(r=0.5, mu=0.4), bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.2), bl.PiecewiseAffine.published("A"))
    for law in laws:
        lift, _ = compiled_lift(law)  # the loops built around a law's lift: own, slip and travel
        loops += [lift, gk.bounce_loop(lift), gk.run_loop(lift)]
    row_loops = [f for f in loops if f.targetoptions.get("nogil")]
    assert {f.py_func.__name__ for f in row_loops} >= {"to_plane_rows", "from_plane_rows", "advance_rows",
                                                       "ground_rows", "sample_rows", "angle_rows", "bounce_rows",
                                                       "run_rows"}
    for f in loops:
        flags = f.targetoptions.get("fastmath", set())
        assert flags is not True and set(flags) <= _jit.ROW_FLAGS, (f.py_func.__name__, flags)


_CROSS = """
import hashlib, json, sys, warnings
sys.path.insert(0, sys.argv[1])
import numpy as np
import bouncelab as bl
from bouncelab.ground import Air, preset, run
from test_ground_bits import shots
warnings.simplefilter("ignore")
v, w, n = shots(61, np.random.default_rng(17))
out = {}
for name, law, air in (("green-fast", None, None), ("turf-A", None, Air()), ("green-medium", bl.CompliantImpact(
        r=0.4, mu=0.5, kappa=1.3), None), ("turf-B", bl.PiecewiseAffine.published("B"), None)):
    s = preset(name) if law is None else preset(name).replace(law=law)
    r = run(v, w, s, normal=n, units={"velocity": "m/s", "spin": "rad/s"}, air=air, max_bounces=20)
    ds = r.sample(25.0)
    parts = [r.rest_position, r.totals.to_numpy(dtype=float)] + [ds[k].values for k in ("position", "velocity", "spin")]
    out[name] = hashlib.sha256(b"".join(np.ascontiguousarray(p).tobytes() for p in parts)).hexdigest()
    vf, wf = bl.ground.bounce(s, v - 2 * np.maximum((v * n).sum(1), 0)[:, None] * n - 0.1 * n, w, n)
    out[name + " bounce"] = hashlib.sha256(vf.tobytes() + wf.tobytes()).hexdigest()
print(json.dumps(out))
"""


@pytest.mark.slow
def test_a_run_gives_the_same_bits_under_a_reduced_instruction_set(tmp_path):
    """As tests/test_bits.py for the laws: the ground's kernels compiled for a generic x86-64 CPU (no AVX2, AVX-512
    or FMA), with a fresh numba cache, give the same bits as natively."""
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    from tests.test_bits import reduced_instruction_set_env

    if os.environ.get("NUMBA_CPU_NAME"):
        pytest.skip("this run is already under a reduced instruction set")
    root = Path(__file__).resolve().parents[1]

    def cross(extra: dict[str, str]) -> dict:
        env = {**os.environ, "PYTHONPATH": str(root), **extra}
        proc = subprocess.run([sys.executable, "-c", _CROSS, str(Path(__file__).parent)], capture_output=True,
                              text=True, env=env, timeout=1200)
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout.splitlines()[-1])

    native = cross({})
    reduced = cross({**reduced_instruction_set_env(), "NUMBA_CACHE_DIR": str(tmp_path), "BOUNCELAB_NO_CACHE": "1"})
    assert native == reduced
