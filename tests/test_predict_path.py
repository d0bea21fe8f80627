"""One path to a law (issue 31): the public methods take the landings once and call the law's hooks; the unit
guard is checked in the pass that predicts, its comparison written once; predicting imports neither pandas
nor scipy.linalg, the command line's help neither pandas nor xarray; a law is checked where it is defined."""

from __future__ import annotations

import math
import subprocess
import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import DataError, LawDefinitionError
from bouncelab.core.landing_checks import FAST, FLAT, SLOW, SPIN
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, landing_faults, landing_limits, landing_status

ROOT = Path(__file__).resolve().parents[1]
COMPILED = [bl.Rigid(r=0.5, mu=0.4), bl.PennerFixed(r=0.42, mu=0.85, beta_deg=12.9),
            bl.PennerVarying(r=0.45, mu=0.97, k_p=1.5e-4, fade_xdot=30.0),
            bl.PiecewiseAffine.published("A").replace(offset=601.0), bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)]


class PathNumpyLaw(bl.BounceModel):
    """A law written in NumPy: its hooks are checked by the default path (a scan before ``_predict``)."""

    e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0))
    regimes = ("bounce",)

    def _predict(self, p, e):
        return p * np.array([1.0, -e, 1.0])

    def _regime(self, p, e):
        return np.zeros(len(p), dtype=np.int8)


def landings(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    speed, angle = rng.uniform(200.0, 2500.0, n), np.radians(rng.uniform(10.0, 85.0, n))
    return np.column_stack([speed * np.cos(angle), -speed * np.sin(angle), rng.uniform(-500.0, 1500.0, n)])


#: A landing that breaks each limit of the default guard, and rows that are no landing at all.
FAULTY = {SLOW: [20.0, -15.0, 200.0], FAST: [5000.0, -800.0, 0.0], SPIN: [1000.0, -800.0, 3000.0],
          FLAT: [1000.0, -50.0, 0.0], SLOW | SPIN: [20.0, -15.0, 3000.0]}
INVALID_ROWS = [[math.nan, -800.0, 0.0], [1000.0, -0.0, 0.0], [1000.0, 5.0, 0.0], [math.inf, -800.0, 0.0],
                [1e9, -800.0, 0.0]]


def calls_during(f) -> Counter:
    """``module.function`` of every bouncelab function called while ``f()`` runs."""
    seen: Counter = Counter()

    def profile(frame, event, arg):
        if event == "call" and frame.f_globals.get("__name__", "").startswith("bouncelab"):
            seen[f"{frame.f_globals['__name__']}.{frame.f_code.co_name}"] += 1

    sys.setprofile(profile)
    try:
        f()
    finally:
        sys.setprofile(None)
    return seen


@pytest.mark.parametrize("law", [*COMPILED, PathNumpyLaw(e=0.5)], ids=lambda law: type(law).__name__)
def test_the_verdict_of_the_pass_that_predicts_is_the_guards(law):
    """The compiled loops' verdict (valid, and which limits a landing breaks) is bit for bit the NumPy scan's,
    for every fault, rows that are no landing, and -0.0; one comparison, compiled or not."""
    rng = np.random.default_rng(1)
    limits = landing_limits()
    values = law.params.valuesdict()
    for n in (1, 9, 5000, 70_000):  # one, a few, NumPy's scan, the compiled scan and the threaded loops
        p = landings(n, seed=n)
        for bad in [*FAULTY.values(), *INVALID_ROWS, None]:
            q = p.copy()
            if bad is not None:
                q[rng.integers(n)] = bad
            expected = landing_status(q, limits)
            for hook in (law._evaluate_checked, law._classify_checked):
                assert hook(q, values, limits)[1] == expected, (n, bad, hook.__name__)


@pytest.mark.parametrize("law", [COMPILED[0], COMPILED[3], PathNumpyLaw(e=0.5)], ids=lambda law: type(law).__name__)
def test_every_path_refuses_a_landing_alike(law):
    """predict, regime and predict_one name the same row and limit for the same landing."""
    for bad in FAULTY.values():
        for n, row in ((1, 0), (12, 7), (60_000, 45_000)):
            p = landings(n)
            p[row] = bad
            errors = []
            for f in (law.predict, law.regime):
                with pytest.raises(DataError) as err:
                    f(p)
                errors.append(err.value)
            if n == 1:
                with pytest.raises(DataError) as err:
                    law.predict_one(*bad)
                errors.append(err.value)
            assert {(e.row, e.column, e.hints[-2]) for e in errors} == {(errors[0].row, errors[0].column,
                                                                         errors[0].hints[-2])}
            assert errors[0].row == row + 1
            first = landing_faults(p).first()
            assert first is not None and first[1] == row


@pytest.mark.parametrize("law", COMPILED[:4], ids=lambda law: type(law).__name__)
def test_large_arrays_are_read_once(law):
    """predict and regime of 10^5 landings make one pass over them: the law's, which checks the values and the
    unit guard as it predicts (the guard was a pass of its own before the prediction, 1.8x its time)."""
    p = landings(100_000)
    law.predict(p)
    for f in (lambda: law.predict(p), lambda: law.regime(p, codes=True)):
        seen = calls_during(f)
        assert seen["bouncelab.core._parallel.run_rows"] == 1, seen
        assert not [name for name in seen if name.rsplit(".", 1)[-1] in
                    ("landing_status", "landing_faults", "_check_values", "landing_error")], seen


def test_no_guard_on_purpose_and_limits_without_limit():
    law = COMPILED[0]
    p = np.array([[1e7, -1e7, 1e7], [1.0, -1.5, 0.0]])  # beyond every default limit
    with pytest.raises(DataError):
        law.predict(p)
    unguarded = law.predict(p, plausible=None)
    assert law.predict_one(*p[0], plausible=None) == tuple(unguarded[0])
    no_upper = PLAUSIBLE_RANGES.widened(max_speed=math.inf, max_spin=math.inf, min_landing_speed=0.0)
    np.testing.assert_array_equal(law.predict(p, plausible=no_upper), unguarded)
    with pytest.raises(DataError) as err:  # the lower limits still hold
        law.predict(p, plausible=PLAUSIBLE_RANGES.widened(max_speed=math.inf, max_spin=math.inf))
    assert err.value.row == 2


def test_predict_one_refuses_what_is_not_a_number():
    law = COMPILED[0]
    assert law.predict_one(1000, -800, np.float32(300.0)) == law.predict_one(1000.0, -800.0, 300.0)
    # text is not a number (predict refuses an array of text too): core.checks' rule, also on the fast path
    for bad, words in (((None, -800.0, 0.0), "None is not a number"), ((10**400, -800.0, 0.0), "too large"),
                       (("x", -800.0, 0.0), "text is not a number"), (("1000", -800.0, 0.0), "text is not"),
                       (([1, 2], -800.0, 0.0), "not a number"), ((True, -800.0, 0.0), "a bool is not"),
                       ((1000.0, -0.0, 0.0), "negative"), ((1000.0, -800.0, math.inf), "infinite")):
        with pytest.raises(DataError, match=words):
            law.predict_one(*bad)
    for kwargs in ({"radius_m": -1.0}, {"radius_m": [1.0]}, {"plausible": 3}):
        with pytest.raises(DataError):
            law.predict_one(1000.0, -800.0, 300.0, **kwargs)


def _run(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          cwd=ROOT).stdout.strip()


def test_predicting_an_ndarray_imports_neither_pandas_nor_scipy_linalg():
    """Predicting and classifying arrays (compiled and NumPy laws, a published law's non-physical check) leave
    pandas and scipy.linalg unimported: 0.5 s and 0.6 s that a simulator's process need not pay."""
    code = ("import sys, numpy as np, bouncelab as bl; p = np.array([[1000.0, -800.0, 300.0]] * 5); "
            "[law.predict(p) for law in (bl.Rigid(r=0.5, mu=0.4), bl.Rigid.published('A'), "
            "bl.PennerVarying.published('B'), bl.PiecewiseAffine.published('A'))]; "
            "bl.Rigid.published('B').regime(p); bl.PennerFixed.published('A').predict_one(1000.0, -800.0, 300.0); "
            "print([m for m in ('pandas', 'xarray', 'scipy.linalg') if m in sys.modules])")
    assert _run(code) == "[]"


@pytest.mark.parametrize("flag", ["--help", "--version"])
def test_the_command_lines_help_imports_neither_pandas_nor_xarray(flag):
    proc = subprocess.run([sys.executable, "-X", "importtime", "-m", "bouncelab", flag], capture_output=True,
                          text=True, cwd=ROOT)
    assert proc.returncode == 0 and "bouncelab" in proc.stdout
    imported = {line.rsplit("|", 1)[-1].strip() for line in proc.stderr.splitlines() if "|" in line}
    assert "bouncelab.cli.main" in imported and not imported & {"pandas", "xarray", "bouncelab.data.io"}


def test_a_hook_that_cannot_take_the_parameters_is_refused_where_the_law_is_defined():
    with pytest.raises(LawDefinitionError) as err:
        class Misnamed(bl.BounceModel):
            e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0))
            regimes = ("bounce",)

            def _predict(self, p, r):
                return p

            def _regime(self, p, e):
                return np.zeros(len(p), dtype=np.int8)
    assert (err.value.law, err.value.method) == ("Misnamed", "_predict")
    assert "['e']" in str(err.value) and "['r']" in str(err.value) and "def _predict(self, p, e)" in str(err.value)

    with pytest.raises(LawDefinitionError) as err:
        class NoLandings(bl.BounceModel):
            e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0))
            regimes = ("bounce",)

            def _predict(self, p, e):
                return p

            def _regime(self, *, e):
                return 0
    assert err.value.method == "_regime" and "no landings p" in str(err.value)

    with pytest.raises(LawDefinitionError) as err:  # a subclass that drops a parameter its base's maths needs
        class PathDropped(PathNumpyLaw):
            e = None
    assert err.value.method == "_predict"

    class PathFlexible(PathNumpyLaw):  # any keyword, a default for what is not a parameter, a static method: fine
        def _predict(self, p, scale=1.0, **parameters):
            return super()._predict(p, **parameters) * scale

        @staticmethod
        def _regime(p, e):
            return np.zeros(len(p), dtype=np.int8)

    assert PathFlexible(e=0.5).predict_one(1000.0, -800.0, 300.0) == (1000.0, 400.0, 300.0)


def test_option_is_exported_and_all_names_each_name_once():
    assert bl.Option is bl.laws.Option and "Option" in bl.__all__
    assert not [name for name, n in Counter(bl.__all__).items() if n > 1]
    assert all(hasattr(bl, name) for name in bl.__all__)


def test_params_reads_the_parameters_on_a_law_and_on_its_class():
    law = bl.PiecewiseAffine.published("A")
    assert list(law.params) == [s.name for s in bl.PiecewiseAffine.parameter_specs]
    assert law.params["offset"].value == law.offset and law.params["A1"].shape == (3, 3)
    flat = law.params.flat()
    assert len(flat) == 28 and flat["A1[0,2]"] == law.A1[0, 2]
    assert law.flat_parameters() == flat and law.parameters.keys() == law.params.valuesdict().keys()
    assert bl.Rigid.params["mu"].bounds == (0.0, 1.5) and bl.Rigid.params["mu"].value is None
    assert bl.Rigid().params.flat() == {"r": None, "mu": None}
    with pytest.raises(AttributeError):
        law.params = None
