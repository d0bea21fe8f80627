"""The same bits for a bounce wherever it sits in a batch, and on any x86-64 CPU (issue 22).

A fresh clone failed on an AVX-512 machine: the compiled row loops were built with the fast-math
freedoms ``contract`` and ``arcp``, so the vectorised body of a loop and its scalar tail fused
multiply-adds differently and a landing's lift-off changed in the last bit with its row's parity.
The loops now allow no freedom that can change a finite result (:data:`bouncelab.core._jit.ROW_FLAGS`).

CI runs this module twice: natively, and under a reduced instruction set (``NUMBA_CPU_NAME=generic``
and NumPy's SIMD dispatch switched off, see ``.ci/run``); ``test_reduced_instruction_set_gives_the_same_bits``
also compares the two in one run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.laws import registered_laws

ROOT = Path(__file__).resolve().parents[1]

CLOSED_FORM = ["Rigid", "PennerFixed", "PennerVarying", "PiecewiseAffine", "TangentialRestitution"]
INTEGRATED = ["CompliantImpact", "TurfContact", "CraterContact"]


def random_law(name: str, rng: np.random.Generator):
    """A law with every parameter drawn uniformly from its default search box."""
    cls = registered_laws()[name]
    values = {}
    for spec in cls.parameter_specs:
        lo, hi = spec.bound_arrays()
        v = rng.uniform(lo, hi)
        values[spec.name] = v.reshape(spec.shape) if spec.shape else float(v[0])
    return cls(**values)


def random_landings(n: int, rng: np.random.Generator) -> np.ndarray:
    """Landings over the paper's Table 1 and beyond it, both directions of travel, every regime."""
    return np.column_stack([rng.uniform(-2500.0, 2500.0, n), rng.uniform(-1900.0, -60.0, n),
                            rng.uniform(-600.0, 1800.0, n)])


def predict(law, p: np.ndarray) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # published laws warn of non-physical lift-offs on random landings
        return law.predict(p, plausible=None)


def test_the_reported_landing_repeated_gives_one_answer():
    """Issue 22's case: one landing repeated 16 times gave a different last bit at every odd row."""
    law = bl.Rigid(r=0.22215093986386003, mu=0.11738148474341314)
    p = np.repeat([[-2638.060016322687, -630.4673046157602, 25.702529743336296]], 16, axis=0)
    out = predict(law, p)
    assert (out == out[0]).all(), np.flatnonzero((out != out[0]).any(axis=1))


# TurfContact compiles for ~10 s on a cold cache (a fresh clone): slow, and run under the reduced instruction set by CI.
@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "TurfContact" else n
                                  for n in CLOSED_FORM + INTEGRATED])
def test_a_bounce_gives_the_same_bits_anywhere_in_a_batch(name):
    """Row by row, in a batch, permuted, reversed and repeated: every lift-off and regime the same bits."""
    rng = np.random.default_rng(sum(map(ord, name)))
    draws = 25 if name in CLOSED_FORM else 4
    n = 41 if name in CLOSED_FORM else 13  # odd: a scalar tail after any vector width
    for _ in range(draws):
        law = random_law(name, rng)
        p = random_landings(n, rng)
        batch = predict(law, p)
        alone = np.vstack([predict(law, p[i:i + 1]) for i in range(n)])
        np.testing.assert_array_equal(batch, alone, err_msg=repr(law))
        perm = rng.permutation(n)
        np.testing.assert_array_equal(predict(law, p[perm]), batch[perm], err_msg=repr(law))
        np.testing.assert_array_equal(predict(law, p[::-1]), batch[::-1], err_msg=repr(law))
        k = int(rng.integers(n))
        repeated = predict(law, np.repeat(p[k:k + 1], 9, axis=0))
        assert (repeated == batch[k]).all(), repr(law)
        codes = law.regime(p, codes=True, plausible=None)
        np.testing.assert_array_equal(law.regime(p[perm], codes=True, plausible=None), codes[perm])


@pytest.mark.slow
def test_a_compiled_user_law_gives_the_same_bits_anywhere_in_a_batch():
    """The fix is in the loops every compiled law gets, not per law: a user kernel full of a*b + c."""
    from numba import njit

    @njit
    def kernel(xd, yd, w, r, mu, g):
        j = mu * yd * (1.0 + r) + 0.1 * (xd + w)
        return xd * g + j, -r * yd + 1e-3 * xd * w, w * g + 2.5 * j, 0

    class MultiplyAdd(bl.CompiledLaw):
        r = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        mu = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="friction")
        g = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="gain")
        regimes = ("bounce",)

    MultiplyAdd.kernel = kernel
    rng = np.random.default_rng(3)
    for _ in range(20):
        law = MultiplyAdd(r=rng.uniform(), mu=rng.uniform(), g=rng.uniform())
        p = random_landings(37, rng)
        batch = predict(law, p)
        np.testing.assert_array_equal(batch, np.vstack([predict(law, row[None]) for row in p]))


def test_changed_floating_point_flags_are_not_served_from_the_cache(tmp_path):
    """numba's cache key leaves out the compile options: loops compiled with fused multiply-adds were still
    loaded after the flags changed. bouncelab's key holds them."""
    module = tmp_path / "flagged.py"
    module.write_text(textwrap.dedent("""
        import os
        from bouncelab.core._jit import jit
        flags = {"contract"} if os.environ["FLAGS"] == "contract" else {"nnan"}

        @jit(fastmath=flags)
        def f(a, b, c):
            return a * b + c
    """))
    code = ("import flagged; flagged.f(1.5, 2.0, 3.0); "
            "print(sum(flagged.f.stats.cache_hits.values()), sum(flagged.f.stats.cache_misses.values()))")

    def run(flags: str) -> tuple[int, int]:
        env = {**os.environ, "FLAGS": flags, "PYTHONPATH": f"{tmp_path}{os.pathsep}{ROOT}"}
        env.pop("BOUNCELAB_NO_CACHE", None)
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
        assert proc.returncode == 0, proc.stderr
        hits, misses = map(int, proc.stdout.split())
        return hits, misses

    assert run("contract") == (0, 1)  # compiled and cached
    assert run("contract") == (1, 0)  # served from the cache
    assert run("plain") == (0, 1)  # other flags: compiled afresh, not the cached fused code


# ------------------------------------------------------------------------------ across CPUs
_CROSS = r"""
import hashlib, json, sys, warnings
import numpy as np
import bouncelab as bl
sys.path.insert(0, sys.argv[1])
from test_bits import CLOSED_FORM, INTEGRATED, random_landings, random_law, predict
warnings.simplefilter("ignore")
rng = np.random.default_rng(11)
out = {}
for name in CLOSED_FORM + INTEGRATED:
    law = random_law(name, rng)
    p = random_landings(301, rng)
    out[name] = hashlib.sha256(predict(law, p).tobytes()).hexdigest()
ds = bl.load_campaign("B", surrogate="published")
for name in ("Rigid", "PennerVarying"):
    fitted = bl.fit(getattr(bl, name), ds, seed=0)
    out["fit " + name] = [float(v) for v in fitted.model.flat_parameters().values()] + [fitted.delta]
print(json.dumps(out))
"""


def reduced_instruction_set_env() -> dict[str, str]:
    """numba compiling for a generic x86-64 CPU and NumPy's dispatched SIMD code (AVX2, AVX-512) switched off."""
    from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__

    disabled = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    return {"NUMBA_CPU_NAME": "generic", "NPY_DISABLE_CPU_FEATURES": " ".join(disabled)}


def _cross(extra_env: dict[str, str]) -> dict:
    env = {**os.environ, "PYTHONPATH": str(ROOT), **extra_env}
    proc = subprocess.run([sys.executable, "-c", _CROSS, str(Path(__file__).parent)], capture_output=True,
                          text=True, env=env, timeout=900)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.splitlines()[-1])


@pytest.mark.slow
def test_reduced_instruction_set_gives_the_same_bits():
    """Compiled prediction and the fits built on it are the same bits with and without AVX2/AVX-512 and FMA.

    The compiled loops use only IEEE arithmetic in a fixed order, so they do not depend on the vector
    units. (What may differ between CPUs is NumPy's own vectorised maths and BLAS; see docs/fitting.md.)
    """
    if os.environ.get("NUMBA_CPU_NAME"):
        pytest.skip("this run is already under a reduced instruction set")
    native = _cross({})
    reduced = _cross(reduced_instruction_set_env())
    assert native.keys() == reduced.keys()
    different = [k for k in native if native[k] != reduced[k]]
    assert not different, {k: (native[k], reduced[k]) for k in different}
