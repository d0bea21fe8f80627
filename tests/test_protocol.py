"""The law protocol (issue 8): laws defined outside the package are first-class everywhere.

The two worked examples of docs/laws.md (a NumPy law and a compiled law with array parameters and its
own fitting method) are imported from their snippet files, as a user's module would be.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import Code, FitError, Hint, NotFittedError, ParameterError, UnknownLawError
from bouncelab.laws import BounceModel, CompiledLaw, FitOutcome, Parameter, fit_method, law_class, law_name

ROOT = Path(__file__).resolve().parents[1]
SNIPPETS = ROOT / "docs" / "snippets"


def _load(name: str):
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, SNIPPETS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def numpy_law():
    return _load("laws_new").SpeedRestitution


@pytest.fixture(scope="module")
def compiled_law():
    return _load("laws_new_compiled").AffineMap


@pytest.fixture(scope="module")
def campaign_b():
    return bl.load_campaign("B")


@pytest.fixture(scope="module")
def campaign_a():
    return bl.load_campaign("A")


# ------------------------------------------------------------------ the two worked examples, everywhere
def test_examples_are_user_laws(numpy_law, compiled_law):
    assert law_name(numpy_law) == "laws_new:SpeedRestitution"
    assert law_name(compiled_law) == "laws_new_compiled:AffineMap"
    assert issubclass(compiled_law, CompiledLaw)
    assert compiled_law.fit_methods().keys() == {"global", "lstsq"}
    assert numpy_law.fit_methods().keys() == {"global"}


def test_numpy_example_fits_and_reports(numpy_law, campaign_b):
    res = bl.fit(numpy_law, campaign_b)
    assert res.method == "global" and res.delta < bl.fit(bl.Rigid, campaign_b).delta  # one more parameter
    text = res.report()
    for name in ("r0", "v_c", "mu", "radius/s", "laws_new:SpeedRestitution"):
        assert name in text
    # the objective the fitter minimised is the law's delta
    p0, pf = campaign_b.landing.values, campaign_b.liftoff.values
    assert res.delta == pytest.approx(bl.delta(p0, pf, res.model.predict(p0)), rel=1e-12)


def test_compiled_example_own_method_with_stderr(compiled_law, campaign_b):
    res = bl.fit(compiled_law, campaign_b)
    assert res.method == "lstsq" and res.algorithm == "linear least squares"
    p0, pf = campaign_b.landing.values, campaign_b.liftoff.values
    coef = np.linalg.lstsq(np.column_stack([p0, np.ones(len(p0))]), pf, rcond=None)[0]
    np.testing.assert_allclose(res.model.A, coef[:3].T, rtol=1e-10)
    assert res.params["A"].stderr.shape == (3, 3) and np.all(res.params["A"].stderr > 0)
    assert "+-" in res.report()
    weighted = bl.fit(compiled_law, campaign_b, weighted=True)
    assert not np.allclose(weighted.model.A, res.model.A)
    with pytest.raises(FitError) as err:  # an option of none of its methods
        bl.fit(compiled_law, campaign_b, svm_C=1.0)
    assert (err.value.law, err.value.option) == (law_name(compiled_law), "svm_C")
    polished = bl.fit(res.model, campaign_b, method="global", maxeval=300)  # generic search from there
    assert polished.delta <= res.delta + 1e-12


def test_compiled_example_matches_numpy(compiled_law, campaign_b):
    law = compiled_law(A=np.arange(9.0).reshape(3, 3) / 10, b=[1.0, 2.0, 3.0])
    p0 = campaign_b.landing.values
    np.testing.assert_allclose(law.predict(p0), p0 @ law.A.T + law.b, rtol=1e-12)
    assert set(law.regime(p0)) == {"affine"}


@pytest.mark.slow  # ~6 s on a cold numba cache
def test_examples_compare_bootstrap_cross_validate(numpy_law, compiled_law, campaign_a):
    cmp = bl.compare(campaign_a, ["Rigid", numpy_law, compiled_law], split="setting")
    names = ["Rigid", "laws_new:SpeedRestitution", "laws_new_compiled:AffineMap"]
    assert list(cmp.table.index) == names
    assert cmp.table.loc[names[1], "v_c"] == cmp.results[names[1]].model.v_c  # its own parameters
    assert cmp.table.loc[names[2], "A"].startswith("[[")  # array parameters summarised, not dropped
    md = cmp.to_markdown()
    assert "| v_c [radius/s] |" in md and "| A |" in md
    boot = bl.bootstrap(numpy_law, campaign_a, n=4)
    assert set(boot.summary().index) == {"r0", "v_c", "mu"}
    boot_arr = bl.bootstrap(compiled_law, campaign_a, n=3)
    assert "A[2,1]" in boot_arr.summary().index and len(boot_arr.samples) == 3
    cv = bl.cross_validate(compiled_law, campaign_a, k=3)
    assert cv.law == names[2] and len(cv.folds) == 3 and np.isfinite(cv.delta)
    cv2 = bl.cross_validate(numpy_law, campaign_a, k=3)
    assert (cv2.folds["test_delta"] > 0).all()


@pytest.mark.parametrize("which", ["numpy_law", "compiled_law"])
def test_examples_round_trip_json(which, request, campaign_a, tmp_path):
    cls = request.getfixturevalue(which)
    law = bl.fit(cls, campaign_a).model
    path = tmp_path / "law.json"
    law.to_json(path)
    d = json.loads(path.read_text())
    assert d["law"] == law_name(cls)
    again = bl.load_law(path)
    assert again == law and type(again) is cls
    p0 = campaign_a.landing.values
    np.testing.assert_array_equal(again.predict(p0), law.predict(p0))


@pytest.mark.slow
def test_examples_in_the_cli(tmp_path):
    env = dict(os.environ, PYTHONPATH=f"{SNIPPETS}{os.pathsep}{ROOT}")
    out = subprocess.run([sys.executable, "-m", "bouncelab.cli.main", "fit", "laws_new:SpeedRestitution", "A",
                          "--save", str(tmp_path / "s.json")], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert "v_c" in out.stdout and "laws_new:SpeedRestitution" in out.stdout
    out = subprocess.run([sys.executable, "-m", "bouncelab.cli.main", "fit", "laws_new_compiled:AffineMap", "B"],
                         capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert "by lstsq" in out.stdout and "+-" in out.stdout
    out = subprocess.run([sys.executable, "-m", "bouncelab.cli.main", "fit", "rIgId", "A"], capture_output=True,
                         text=True, env=env)
    assert out.returncode == 0 and "[[Fit]] Rigid" in out.stdout  # law names are case-insensitive


# ------------------------------------------------------------------ identity
def test_user_class_named_like_a_builtin_does_not_replace_it():
    class Rigid(BounceModel):  # deliberately the built-in's name
        k = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="k")
        regimes = ("one",)

        def _predict(self, p, k):
            return p * k

        def _regime(self, p, k):
            return np.zeros(len(p), np.int8)

    assert law_class("Rigid") is bl.Rigid
    assert bl.BounceModel.from_dict({"law": "Rigid", "parameters": {"r": 0.5, "mu": 0.4}}) == bl.Rigid(r=0.5, mu=0.4)
    mine = Rigid(k=0.5)
    qualified = f"{__name__}:test_user_class_named_like_a_builtin_does_not_replace_it.<locals>.Rigid"
    assert mine.to_dict()["law"] == qualified
    assert bl.BounceModel.from_dict(mine.to_dict()) == mine
    assert bl.laws.registered_laws()["Rigid"] is bl.Rigid


def test_ambiguous_and_unknown_names():
    made = []
    for module in ("lab_one", "lab_two"):
        made.append(type("Twin", (BounceModel,), {"__module__": module, "regimes": ()}))
    with pytest.raises(ParameterError, match=r"ambiguous.*lab_one:Twin.*lab_two:Twin") as err:  # names both
        bl.BounceModel.from_dict({"law": "Twin", "parameters": {}})
    assert err.value.law == "Twin" and not isinstance(err.value, UnknownLawError)
    assert type(bl.BounceModel.from_dict({"law": "lab_two:Twin", "parameters": {}})) is made[1]
    with pytest.raises(UnknownLawError) as err:  # a ParameterError that says to import the module
        bl.BounceModel.from_dict({"law": "nowhere.module:Law", "parameters": {}})
    assert (err.value.module, err.value.qualname, err.value.module_imported) == ("nowhere.module", "Law", False)


@pytest.mark.parametrize("bad", [
    {"law": "Rigid", "parameters": [1, 2]},
    {"law": "Rigid", "parameters": {"r": [1, 2], "mu": 0.3}},
    {"law": "Rigid", "parameters": {"r": 10**400, "mu": 0.3}},
    {"law": "Rigid", "parameters": {"r": {"x": 1}, "mu": 0.3}},
    {"law": "Rigid", "parameters": {"r": "0.5", "mu": 0.3}},
    {"law": 3, "parameters": {}},
    {"law": "PiecewiseAffine", "parameters": {"normal": [[[1]]], "offset": 1, "A1": None, "b1": None,
                                              "A2": None, "b2": None}},
    {"law": "Rigid", "parameters": {"r": 0.5, "mu": 0.3}, "options": [1]},
    [],
])
def test_from_dict_raises_parameter_error_only(bad):
    with pytest.raises(ParameterError):
        bl.BounceModel.from_dict(bad)


def test_deeply_nested_json_is_a_parameter_error(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text('{"law": "Rigid", "parameters": {"r": ' + "[" * 100000 + "]" * 100000 + "}}")
    with pytest.raises(ParameterError):
        bl.load_law(path)


def test_to_json_is_atomic(tmp_path, monkeypatch):
    path = tmp_path / "law.json"
    bl.Rigid(r=0.5, mu=0.4).to_json(path)
    before = path.read_text()

    def fail(*args, **kwargs):
        raise OSError("disk full")

    import bouncelab.core.atomic as atomic

    monkeypatch.setattr(atomic.os, "replace", fail)
    with pytest.raises(OSError) as err:
        bl.Rigid(r=0.9, mu=0.1).to_json(path)
    assert (err.value.path, err.value.reason) == (str(path), "disk full")
    assert path.read_text() == before  # the previous law is intact
    assert [p.name for p in tmp_path.iterdir()] == ["law.json"]  # no temporary file left


# ------------------------------------------------------------------ parameters and fit options
def test_parameters_objects():
    params = bl.PiecewiseAffine.published("A").params
    assert list(params) == ["normal", "offset", "A1", "b1", "A2", "b2"]
    assert params["A1"].shape == (3, 3) and params["A1"].size == 9 and params["A1"].value[0, 2] == -0.205
    assert "doc" in params.pretty() and "A1" in repr(params)
    assert bl.Rigid().params["mu"].value is None and bl.Rigid(r=0.5, mu=0.3).params.valuesdict()["mu"] == 0.3
    law = bl.PennerFixed(r=0.4, mu=0.3, beta_deg=10.0)
    from bouncelab.fitting.vector import ParameterVector

    vec = ParameterVector(law)
    assert vec.law(law, vec.of(law)) == law and vec.names == ["r", "mu", "beta_deg"]
    with pytest.raises(NotFittedError) as err:
        vec.of(bl.Rigid(r=0.5))
    assert err.value.missing == ("mu",) and err.value.law == "Rigid"


def test_fixed_and_free(campaign_a):
    res = bl.fit(bl.PennerFixed(r=0.4, mu=0.3, beta_deg=12.0), campaign_a, fixed=["beta_deg"])
    assert res.model.beta_deg == 12.0 and res.fixed == {"beta_deg": 12.0} and res.model.r != 0.4
    res = bl.fit(bl.PennerFixed, campaign_a, fixed={"r": 0.5, "beta_deg": 5.0})
    assert (res.model.r, res.model.beta_deg) == (0.5, 5.0) and "(fixed)" in res.report()
    assert res.params["r"].vary is False
    with pytest.raises(FitError) as err:  # held, but the law has no value for it
        bl.fit(bl.Rigid, campaign_a, fixed=["r"])
    assert err.value.option == "fixed" and err.value.hints == (Hint("fixed", {"r": Code("value")}),)
    with pytest.raises(ParameterError) as err:
        bl.fit(bl.Rigid, campaign_a, fixed={"nu": 1.0})
    assert (err.value.law, err.value.parameter) == ("Rigid", "nu")
    with pytest.raises(ParameterError) as err:  # outside its physical range
        bl.fit(bl.Rigid, campaign_a, fixed={"r": 2.0})
    assert (err.value.law, err.value.parameter, err.value.value) == ("Rigid", "r", 2.0)

    class Held(_Scaled):  # the same law, its spin parameter held at 1 unless freed
        g = Parameter(bounds=(0.0, 2.0), physical=(0.0, 2.0), doc="spin kept", vary=False, default=1.0)

    held = bl.fit(Held, campaign_a)
    assert held.model.g == 1.0 and "g" in held.fixed
    freed = bl.fit(Held, campaign_a, free=["g"])
    assert freed.model.g != 1.0 and freed.delta < held.delta


def test_piecewise_start_values_and_held_plane(campaign_a):
    published = bl.PiecewiseAffine.published("A")
    res = bl.fit(published, campaign_a, fixed=["normal", "offset"])
    np.testing.assert_array_equal(res.model.normal, published.normal)
    assert res.model.offset == published.offset and res.n_evaluations == 0
    started = bl.fit(published, campaign_a, maxeval=50)  # the search starts from the law's own plane
    assert "started from the plane of the law given" in started.report()
    with pytest.raises(FitError) as err:  # the plane methods hold only the plane
        bl.fit(published, campaign_a, fixed=["A1"])
    assert (err.value.law, err.value.option) == ("PiecewiseAffine", "fixed")
    assert [(h.option, h.value) for h in err.value.hints] == [("method", "global")]


def test_unknown_method_and_options_are_named(campaign_a):
    with pytest.raises(FitError, match=r"'svm' is a method of PiecewiseAffine") as err:  # where it is a method
        bl.fit(bl.Rigid, campaign_a, method="svm")
    assert (err.value.law, err.value.option) == ("Rigid", "method")
    with pytest.raises(FitError) as err:
        bl.fit(bl.Rigid, campaign_a, method="structured", algorithm="CRS2_LM")
    assert (err.value.law, err.value.option) == ("Rigid", "algorithm")
    with pytest.raises(FitError) as err:
        bl.fit(bl.Rigid, campaign_a, svm_C=2.0)  # previously ignored silently
    assert (err.value.law, err.value.option) == ("Rigid", "svm_C")


@pytest.mark.parametrize("seed", [-1, 2**64, 1.5, "1", True])
def test_bad_seed_is_a_fit_error(seed, campaign_a):
    with pytest.raises(FitError) as err:
        bl.fit(bl.Rigid, campaign_a, seed=seed)
    assert err.value.option == "seed"


def test_held_out_must_be_held_out(campaign_a):
    train, test = bl.split_by_setting(campaign_a, seed=0)
    with pytest.raises(FitError) as err:  # held-out bounces must not be fitted
        bl.fit(bl.Rigid, campaign_a, test=test)
    assert err.value.option == "test"
    assert bl.fit(bl.Rigid, train, test=test).n_test == test.sizes["bounce"]


def test_validation_happens_once_per_fit(campaign_b, monkeypatch):
    """Internals call the private hooks: a piecewise fit checks its arrays' values at the entry only.

    (bouncelab 0.1 validated the same arrays 16 times in one piecewise fit.)"""
    import bouncelab.core.validation as validation

    calls = []
    real = validation._check_values

    def counting(arr, name, **kwargs):
        calls.append(name)
        return real(arr, name, **kwargs)

    monkeypatch.setattr(validation, "_check_values", counting)
    train, test = bl.split_by_setting(campaign_b, seed=0)
    calls.clear()
    res = bl.fit(bl.PiecewiseAffine, train, test=test)
    _ = res.errors, res.report(), res.mismatched, res.test_mismatched
    assert sorted(calls) == ["landing", "landing", "liftoff", "liftoff"]  # fitted and held-out, once each


def test_fit_outcome_type_is_checked(campaign_a):
    class Bad(BounceModel):
        e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        regimes = ("one",)

        def _predict(self, p, e):
            return p

        def _regime(self, p, e):
            return np.zeros(len(p), np.int8)

        @fit_method("broken")
        def _broken(self, problem) -> FitOutcome:
            return "nothing"

    with pytest.raises(FitError) as err:  # it returned a str
        bl.fit(Bad, campaign_a, method="broken")
    assert (err.value.law, err.value.option) == (law_name(Bad), "method")


class _Scaled(BounceModel):
    """A two-parameter law whose own methods misbehave on purpose (for the fit contract tests)."""

    e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    g = Parameter(bounds=(0.0, 2.0), physical=(0.0, 2.0), doc="spin kept")
    regimes = ("one",)

    def _predict(self, p, e, g):
        return p * np.array([1.0, -e, g])

    def _regime(self, p, e, g):
        return np.zeros(len(p), np.int8)

    @fit_method("ignores_everything")
    def _ignores(self, problem) -> FitOutcome:
        law = self.replace(e=0.9, g=1.9)
        return FitOutcome(model=law, objective_value=problem.value(law), algorithm="none")

    @fit_method("holds_e")
    def _holds_e(self, problem) -> FitOutcome:
        return problem.run_global(self, hold={"e": 0.2})


def test_a_method_that_ignores_fixed_or_bounds_fails(campaign_a):
    assert bl.fit(_Scaled, campaign_a, method="ignores_everything").model.e == 0.9  # nothing asked: fine
    with pytest.raises(FitError) as err:  # e was fixed, the method did not hold it
        bl.fit(_Scaled, campaign_a, method="ignores_everything", fixed={"e": 0.5})
    assert (err.value.law, err.value.option) == (law_name(_Scaled), "fixed")
    assert [(h.option, h.value) for h in err.value.hints] == [("method", "global")]
    with pytest.raises(FitError) as err:  # outside the bounds given: the hint is the method that keeps them
        bl.fit(_Scaled, campaign_a, method="ignores_everything", bounds={"g": (0.0, 1.0)})
    assert err.value.option == "bounds" and [(h.option, h.value) for h in err.value.hints] == [("method", "global")]
    # the piecewise methods find the plane without a box: explicit bounds they cannot honour are an error
    with pytest.raises(FitError) as err:
        bl.fit(bl.PiecewiseAffine, campaign_a, bounds={"offset": (0.0, 1.0)})
    assert (err.value.law, err.value.option) == ("PiecewiseAffine", "bounds")


def test_callers_fixed_values_win_over_a_methods_hold(campaign_a):
    assert bl.fit(_Scaled, campaign_a, method="holds_e").model.e == 0.2
    assert bl.fit(_Scaled, campaign_a, method="holds_e", fixed={"e": 0.5}).model.e == 0.5


def test_law_definition_errors(campaign_a):
    with pytest.raises(bl.LawDefinitionError) as err:  # a kernel that is not numba.njit
        class NotCompiled(CompiledLaw):
            e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
            regimes = ("one",)
            kernel = staticmethod(lambda xd, yd, w, e: (xd, -yd, w, 0))
    assert (err.value.law, err.value.method) == ("NotCompiled", "kernel")

    class BadCodes(_Scaled):
        def _regime(self, p, e, g):
            return np.full(len(p), 3, np.int8)

    with pytest.raises(bl.LawDefinitionError, match="regime code 3") as err:  # the code named: the point
        BadCodes(e=0.5, g=1.0).regime(campaign_a.landing.values)
    assert (err.value.law, err.value.method) == (law_name(BadCodes), "_regime")


def test_docs_compiled_example_refuses_to_hold(compiled_law, campaign_b):
    with pytest.raises(FitError, match="cannot hold"):
        bl.fit(compiled_law, campaign_b, fixed={"b": [0.0, 0.0, 0.0]})


def test_user_laws_from_the_command_line_without_pythonpath(tmp_path):
    """Run where the law's file lies, as a user would: no PYTHONPATH; --import for a saved user law."""
    import shutil

    shutil.copy(SNIPPETS / "laws_new.py", tmp_path / "mylaws.py")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}

    def cli(*argv):
        return subprocess.run([sys.executable, "-m", "bouncelab.cli.main", *argv], capture_output=True, text=True,
                              env=env, cwd=tmp_path)

    out = cli("fit", "mylaws:speedrestitution", "A", "--save", "s.json", "--method", "global",
              "--option", "maxeval=60", "--option", "local_algorithm=null")
    assert out.returncode == 0, out.stderr
    assert "mylaws:SpeedRestitution" in out.stdout and (tmp_path / "s.json").exists()
    out = cli("predict", "s.json", "--landing", "1000", "-8e2", "200")
    assert out.returncode == 4 and "add --import mylaws" in out.stderr  # a JSON file never imports code by itself
    out = cli("predict", "s.json", "--import", "mylaws", "--landing", "1000", "-8e2", "200")
    assert out.returncode == 0, out.stderr
    assert len(out.stdout.strip().splitlines()[-1].split()) == 7
    out = cli("fit", "Rigid", "A", "--option", "maxeval")
    assert out.returncode == 2 and "KEY=VALUE" in out.stderr
    out = cli("fit", "Rigid", "A", "--import", "no_such_module_here")
    assert out.returncode == 4 and "there is no module 'no_such_module_here'" in out.stderr


@pytest.mark.slow
def test_reproduce_compares_a_user_law(tmp_path, monkeypatch):
    import bouncelab as rp
    from bouncelab.report import steps

    monkeypatch.setattr(steps, "BOOTSTRAP_RESAMPLES", 5)
    law = _load("laws_new").SpeedRestitution
    report = rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=False, laws=[law])
    table3 = (tmp_path / "rep" / "tables" / "A_table3.md").read_text()
    assert "SpeedRestitution" in table3 and "v_c" in table3
    assert "SpeedRestitution" in (tmp_path / "rep" / "tables" / "A_crossvalidation.md").read_text()
    assert report.index.exists()
    with pytest.raises(FitError):
        rp.reproduce(["A"], out=tmp_path / "rep2", figures=False, progress=False, laws=["NoSuchLaw"])
    assert not (tmp_path / "rep2").exists()


def test_load_law_given_json_text_says_what_it_takes():
    text = bl.Rigid(r=0.5, mu=0.3).to_dict()
    import json

    with pytest.raises(bl.ParameterError, match=r"path of a law JSON file.*law_from_dict") as err:  # what it takes
        bl.load_law(json.dumps(text))
    assert err.value.parameter == "path"
    assert bl.laws.law_from_dict(json.loads(json.dumps(text))) == bl.Rigid(r=0.5, mu=0.3)


def test_a_law_name_in_its_exact_case_wins_over_one_differing_in_case():
    from bouncelab.core.errors import FitError, ParameterError
    from bouncelab.laws import law_class

    def make(name):
        return type(name, (bl.BounceModel,), {
            "__module__": "caselaws", "g": bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="g"),
            "regimes": ("bounce",), "_predict": lambda self, p, g: p * np.array([g, -g, 0.0]),
            "_regime": lambda self, p, g: np.zeros(len(p), dtype=np.int8)})

    upper, lower = make("CaseLaw"), make("caselaw")
    for name, cls in (("CaseLaw", upper), ("caselaw", lower), ("caselaws:CaseLaw", upper), ("caselaws:caselaw", lower)):
        assert law_class(name, case_sensitive=False) is cls
        assert type(bl.fit(name, bl.load_campaign("A"))).__name__ == "FitResult"
    with pytest.raises(FitError) as err:  # ambiguous: two laws differ from it only in case
        bl.fit("CASELAW", bl.load_campaign("A"))
    assert (err.value.law, err.value.option) == ("CASELAW", "model")
    with pytest.raises(ParameterError) as err:  # numpy is imported but defines no bounce law 'ndarray'
        law_class("numpy:ndarray")
    assert (err.value.module, err.value.qualname, err.value.module_imported) == ("numpy", "ndarray", True)


def test_the_documented_compiled_law_weighs_its_least_squares_by_the_sample_weights(compiled_law):
    ds = bl.load_campaign("B")
    p0, pf = ds.landing.values, ds.liftoff.values
    w = np.random.default_rng(3).integers(0, 3, len(p0))
    idx = np.repeat(np.arange(len(p0)), w)
    for weighted in (False, True):
        a = bl.fit(compiled_law, (p0, pf), sample_weight=w, weighted=weighted)
        b = bl.fit(compiled_law, (p0[idx], pf[idx]), weighted=weighted)
        np.testing.assert_allclose(list(a.model.flat_parameters().values()),
                                   list(b.model.flat_parameters().values()), rtol=1e-9, atol=1e-9)
