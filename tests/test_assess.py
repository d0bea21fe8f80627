"""Issue 24 item 1: bouncelab.assess - held-out scores beside training ones, and per-parameter identifiability
(bootstrap by setting, independent starts, profiles, Jacobian null directions, verdicts)."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.core.errors import FitError
from bouncelab.fitting.assessment import VERDICTS, Assessment, SmallBootstrapWarning, assess, min_bootstrap
from bouncelab.laws import BounceModel, Parameter

# small bootstrap counts keep these tests quick; test_too_few_resamples_for_the_level_warn checks the warning
pytestmark = pytest.mark.filterwarnings("ignore::bouncelab.fitting.assessment.SmallBootstrapWarning")

_RIGID = bl.Rigid(r=0.5, mu=0.5)


def _rigid(p: np.ndarray, r: float, mu: float) -> np.ndarray:
    return _RIGID._predict(p, r=r, mu=mu)


class RedundantRigid(BounceModel):
    """Rigid bounce whose restitution is the product r1 * r2: a deliberately redundant pair."""

    r1 = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution factor 1")
    r2 = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution factor 2")
    mu = Parameter(bounds=(0.0, 1.5), physical=(0.0, float("inf")), doc="friction")
    regimes = bl.Rigid.regimes

    def _predict(self, p, r1, r2, mu):
        return _rigid(p, r1 * r2, mu)

    def _regime(self, p, r1, r2, mu):
        return _RIGID._regime(p, r=r1 * r2, mu=mu)


class IdleRigid(BounceModel):
    """Rigid bounce with a parameter that changes nothing."""

    r = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    mu = Parameter(bounds=(0.0, 1.5), physical=(0.0, float("inf")), doc="friction")
    idle = Parameter(bounds=(0.0, 5.0), physical=(0.0, 10.0), doc="does nothing")
    regimes = bl.Rigid.regimes

    def _predict(self, p, r, mu, idle):
        return _rigid(p, r, mu)

    def _regime(self, p, r, mu, idle):
        return _RIGID._regime(p, r=r, mu=mu)


class VectorRigid(BounceModel):
    """Rigid bounce with its two parameters in one array parameter ``rm = [r, mu]``."""

    rm = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), shape=(2,), doc="[restitution, friction]")
    regimes = bl.Rigid.regimes

    def _predict(self, p, rm):
        return _rigid(p, rm[0], rm[1])

    def _regime(self, p, rm):
        return _RIGID._regime(p, r=rm[0], mu=rm[1])


def campaign(law: BounceModel, n_settings: int = 40, repeats: int = 6, noise=(8.0, 8.0, 30.0), seed: int = 1):
    """Launcher settings with repeats (landings jittered), lift-offs from ``law`` plus normal noise."""
    rng = np.random.default_rng(seed)
    base = np.column_stack([rng.uniform(200, 1200, n_settings), rng.uniform(-900, -200, n_settings),
                            rng.uniform(-500, 800, n_settings)])
    land = np.repeat(base, repeats, axis=0) + rng.normal(0, [10, 10, 20], (n_settings * repeats, 3))
    lift = law.predict(land) + rng.normal(0, noise, land.shape)
    return bl.make_campaign(land, lift, setting=np.repeat(np.arange(n_settings), repeats))


@pytest.fixture(scope="module")
def rigid_data():
    return campaign(bl.Rigid(r=0.5, mu=0.4), n_settings=20, repeats=5)


@pytest.fixture(scope="module")
def rigid_assessment(rigid_data):
    return assess(bl.Rigid, rigid_data, n_bootstrap=30, seed=3)


# ------------------------------------------------------------------------------ done-when: a redundant pair
@pytest.mark.slow  # 4-7 s: the law is plain NumPy, fitted some 150 times
def test_redundant_pair_is_not_identifiable_and_the_rest_is() -> None:
    truth = RedundantRigid(r1=0.9, r2=0.6, mu=0.35)
    data = campaign(truth)
    result = assess(RedundantRigid, data, n_bootstrap=30)
    v = result.verdicts
    assert v == {"r1": "not identifiable", "r2": "not identifiable", "mu": "identifiable"}
    params = result.parameters
    assert params.loc["r1", "correlated"] == "r2" and params.loc["r2", "correlated"] == "r1"
    assert params.loc["mu", "correlated"] == ""
    # the null direction is the pair's, and the data fix their product
    [null] = result.null_directions
    assert set(null["parts"]) == {"r1", "r2"} and null["ratio"] < 1e-6
    product = params.loc["r1", "estimate"] * params.loc["r2", "estimate"]
    assert product == pytest.approx(0.54, abs=0.01)
    assert params.loc["mu", "profile_low"] < 0.35 < params.loc["mu", "profile_high"]
    # the profile of r1 is flat from r1 = product (r2 at its bound 1) to 1 and rises below: its lower end lies
    # between the product and the first grid point above it (0.6 on the grid 0, 0.1, ..., 1)
    assert product - 0.01 < params.loc["r1", "profile_low"] <= 0.6
    assert params.loc["r1", "profile_high"] == 1.0
    assert result.correlation.loc["r1", "r2"] < -0.9


def test_parameter_without_effect_is_flat_everywhere(rigid_data) -> None:
    result = assess(IdleRigid(r=0.5, mu=0.4, idle=1.0), rigid_data, n_bootstrap=0, starts=2, profile_points=5)
    row = result.parameters.loc["idle"]
    assert row["verdict"] == "not identifiable"
    assert "whole search box" in row["reason"]
    assert result.verdicts["r"] == result.verdicts["mu"] == "identifiable"
    assert np.isnan(row["ci_low"])  # no bootstrap asked
    assert result.bootstrap is None and result.correlation.empty


def test_bounded_on_one_side_only_is_weakly_identifiable() -> None:
    data = campaign(bl.Rigid(r=0.5, mu=0.4), n_settings=12, repeats=4, noise=(30.0, 30.0, 120.0), seed=3)
    wide = assess(bl.Rigid, data, n_bootstrap=20)
    narrow = assess(bl.Rigid, data, n_bootstrap=20, bounds={"mu": (0.2, 0.42)})
    assert wide.verdicts["mu"] == "identifiable"
    assert narrow.verdicts["mu"] == "weakly identifiable"  # the data cannot exclude mu up to 0.42
    assert narrow.parameters.loc["mu", "profile_high"] == 0.42
    assert narrow.parameters.loc["mu", "at_bound"] == ""  # the estimate itself is inside the box


def test_rigid_on_its_own_data_scores_and_report(rigid_assessment, rigid_data) -> None:
    result = rigid_assessment
    assert isinstance(result, Assessment)
    assert result.verdicts == {"r": "identifiable", "mu": "identifiable"}
    assert set(result.parameters["verdict"]) <= {*VERDICTS, "fixed"}
    p = result.parameters
    for name, true in (("r", 0.5), ("mu", 0.4)):
        assert p.loc[name, "ci_low"] < p.loc[name, "estimate"] < p.loc[name, "ci_high"]
        assert p.loc[name, "profile_low"] < p.loc[name, "estimate"] < p.loc[name, "profile_high"]
        assert p.loc[name, "estimate"] == pytest.approx(true, abs=0.01)
        # the profile interval and the bootstrap interval measure the same uncertainty: they overlap
        assert p.loc[name, "profile_low"] < p.loc[name, "ci_high"]
        assert p.loc[name, "ci_low"] < p.loc[name, "profile_high"]
        assert p.loc[name, "starts_spread"] < 1e-3  # every global start finds the same minimum
    # training and held-out rows: the training delta is the full fit's, the held-out one each bounce held out once
    scores = result.scores
    assert list(scores.index) == ["training", "held-out"]
    assert scores.loc["training", "delta"] == pytest.approx(result.fit.delta, rel=1e-12)
    assert scores.loc["held-out", "n"] == scores.loc["training", "n"] == 100
    folds = result.cross_validation.folds
    assert scores.loc["held-out", "delta"] == pytest.approx(
        (folds["test_delta"] * folds["n_test"]).sum() / folds["n_test"].sum(), rel=1e-12)
    assert scores.loc["held-out", "delta"] >= scores.loc["training", "delta"] * 0.95
    summary = result.summary()
    assert summary["n_free"] == 2 and summary["n_identifiable"] == 2
    assert summary["heldout_delta"] == scores.loc["held-out", "delta"]
    text = str(result)
    for part in ("[[Assessment]] Rigid on 100 bounces (20 launcher settings)", "[[Errors]]", "[[Parameters]]",
                 "[[Verdicts]]", "held-out"):
        assert part in text
    md = result.to_markdown()
    assert md.startswith("**Rigid**: 2 free parameter(s)")
    assert md.count("| identifiable |") == 2
    frame = result.to_frame()
    assert frame.attrs["law"] == "Rigid" and frame.attrs["summary"]["n_free"] == 2
    frame.loc["r", "verdict"] = "changed"
    assert result.parameters.loc["r", "verdict"] == "identifiable"  # a copy
    # the profile table: the estimate is one of its points, with no change
    prof = result.profiles[result.profiles["parameter"] == "r"]
    est = prof[prof["estimate"]]
    assert len(est) == 1 and est["change"].iloc[0] == 0.0 and bool(est["within_noise"].iloc[0])
    assert prof["value"].is_monotonic_increasing
    assert "r" in repr(result) and "identifiable" in repr(result)


def test_profile_change_is_the_paired_objective_change(rigid_assessment, rigid_data) -> None:
    """Each profile point's change is the mean per-bounce delta change from the estimate, refitted with the parameter
    held (checked here against an independent refit), and its threshold the clustered standard error times z."""
    result = rigid_assessment
    row = result.profiles[(result.profiles["parameter"] == "mu") & ~result.profiles["estimate"]].iloc[2]
    refit = bl.fit(bl.Rigid, rigid_data, fixed={"mu": row["value"]}, method="global")
    assert row["delta"] == pytest.approx(refit.delta, rel=1e-9)
    assert row["change"] == pytest.approx(refit.delta - result.fit.delta, rel=1e-9, abs=1e-15)
    assert row["threshold"] > 0


def test_array_parameters_by_element(rigid_data) -> None:
    result = assess(VectorRigid(rm=np.array([0.5, 0.5])), rigid_data, n_bootstrap=10, starts=1, profile_points=5)
    assert list(result.parameters.index) == ["rm[0]", "rm[1]"]
    assert result.verdicts == {"rm[0]": "identifiable", "rm[1]": "identifiable"}
    assert result.parameters.loc["rm[0]", "estimate"] == pytest.approx(0.5, abs=0.03)


def test_held_parameters_are_listed_as_fixed(rigid_data) -> None:
    result = assess(bl.Rigid(r=0.5, mu=0.4), rigid_data, fixed=["r"], n_bootstrap=10, starts=1, profile_points=5)
    assert result.parameters.loc["r", "verdict"] == "fixed"
    assert result.parameters.loc["r", "estimate"] == 0.5
    assert result.n_free == 1 and list(result.verdicts) == ["mu"]
    assert "| r | 0.5 |  |  |  | fixed |  |" in result.to_markdown()  # the same cells as reproduce's table


def test_without_settings_folds_and_resamples_bounces(rigid_data) -> None:
    pair = (rigid_data.landing.values, rigid_data.liftoff.values)
    result = assess(bl.Rigid, pair, n_bootstrap=10, starts=1, profile_points=5)
    assert result.split == "bounce"
    assert result.scores.loc["held-out", "n"] == 100
    assert "no launcher settings" in result.report()
    assert result.bootstrap.by == "setting"  # each bounce its own group
    assert len(result.bootstrap.samples) == 10


def test_synthetic_campaign_says_so() -> None:
    data = bl.load_campaign("A", surrogate="published").isel(bounce=slice(0, 60))
    result = assess(bl.Rigid, data, k=3, n_bootstrap=0, starts=0, profile_points=3, local_points=0)
    assert result.notes and "SYNTHETIC" in result.notes[0].upper()
    assert result.starts.empty
    assert np.isnan(result.parameters.loc["r", "starts_spread"])


@pytest.mark.parametrize("kwargs", [
    {"k": 1}, {"k": 500},  # too few folds; more folds than launcher settings
    {"n_bootstrap": 1}, {"starts": -1}, {"profile_points": 2}, {"level": 1.5}, {"correlation": 0},
    {"null_tol": 0}, {"null_tol": True}, {"null_tol": 10**400}, {"tol": -1}, {"tol": "0.1"}, {"tol": float("nan")},
    {"seed": -1}, {"sample_weight": np.ones(100)},
])
def test_bad_options_are_refused(rigid_data, kwargs) -> None:
    with pytest.raises(FitError) as e:
        assess(bl.Rigid, rigid_data, **kwargs)
    assert e.value.option == next(iter(kwargs))


# ------------------------------------------------------------------------------ on an executor
_EXECUTOR_KWARGS = {"n_bootstrap": 8, "starts": 3, "profile_points": 5, "seed": 4}


@pytest.fixture(scope="module")
def serial_assessment(rigid_data) -> Assessment:
    return assess(bl.Rigid, rigid_data, **_EXECUTOR_KWARGS)


def _same(a: Assessment, b: Assessment) -> None:
    for name in ("parameters", "profiles", "starts", "scores", "correlation"):
        pd.testing.assert_frame_equal(getattr(a, name), getattr(b, name), check_exact=True)
    pd.testing.assert_frame_equal(a.bootstrap.samples, b.bootstrap.samples, check_exact=True)


def test_assess_on_a_thread_pool_equals_serial(rigid_data, serial_assessment) -> None:
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=2) as pool:
        _same(assess(bl.Rigid, rigid_data, executor=pool, **_EXECUTOR_KWARGS), serial_assessment)
    other = assess(bl.Rigid, rigid_data, **{**_EXECUTOR_KWARGS, "seed": 5})
    assert not other.starts.equals(serial_assessment.starts)  # the seed matters: the comparison above could fail


def test_client_is_a_deprecated_alias_of_executor(rigid_data, serial_assessment) -> None:
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=2) as pool:
        with pytest.warns(DeprecationWarning, match=r"assess\(client=...\) is deprecated"):
            _same(assess(bl.Rigid, rigid_data, client=pool, **_EXECUTOR_KWARGS), serial_assessment)
        with ThreadPoolExecutor(max_workers=1) as other, pytest.warns(DeprecationWarning), \
                pytest.raises(FitError) as e:
            assess(bl.Rigid, rigid_data, executor=pool, client=other, **_EXECUTOR_KWARGS)
        assert e.value.option == "client"


def test_assess_on_dask_equals_serial(rigid_data, serial_assessment) -> None:
    """A dask Client itself and its concurrent.futures face (client.get_executor()) both give the serial result."""
    distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cl, \
            distributed.Client(cl) as client:
        _same(assess(bl.Rigid, rigid_data, executor=client, **_EXECUTOR_KWARGS), serial_assessment)
        _same(assess(bl.Rigid, rigid_data, executor=client.get_executor(), **_EXECUTOR_KWARGS), serial_assessment)


def test_too_few_resamples_for_the_level_warn(rigid_data) -> None:
    """assess(n_bootstrap=2) reported a 95 % interval excluding its own estimate without a word: fewer resamples than
    put one in each tail of the interval (2 / (1 - level)) now warn, and the notes say so."""
    assert [min_bootstrap(x) for x in (0.95, 0.9, 0.5, 0.99)] == [40, 20, 4, 200]
    kwargs = {"starts": 0, "profile_points": 3, "local_points": 0, "seed": 1}
    with pytest.warns(SmallBootstrapWarning, match="2 bootstrap resamples are too few for 95 % intervals") as rec:
        result = assess(bl.Rigid, rigid_data, n_bootstrap=2, **kwargs)
    assert len([w for w in rec if issubclass(w.category, SmallBootstrapWarning)]) == 1
    assert any("too few for 95 % intervals" in note for note in result.notes)
    assert "too few" in str(result)
    table = result.parameters
    excluded = ~((table["ci_low"] <= table["estimate"]) & (table["estimate"] <= table["ci_high"]))
    assert excluded.any()  # what the warning is about: here the "interval" misses the estimate
    with warnings.catch_warnings():
        warnings.simplefilter("error", SmallBootstrapWarning)
        assess(bl.Rigid, rigid_data, n_bootstrap=4, level=0.5, **kwargs)  # enough for a 50 % interval: silent
        assess(bl.Rigid, rigid_data, n_bootstrap=0, **kwargs)  # no bootstrap, no interval: silent
    with pytest.warns(SmallBootstrapWarning):
        assess(bl.Rigid, rigid_data, n_bootstrap=39, **kwargs)


def test_prediction_interval_weighted_objective() -> None:
    """objective='delta_pi' weighs bounces by their intervals everywhere: full fit, folds, bootstrap, profiles."""
    data = bl.load_campaign("A", surrogate="published").isel(bounce=slice(0, 90))
    result = assess(bl.Rigid, data, k=3, n_bootstrap=2, starts=1, profile_points=4, local_points=1,
                    objective="delta_pi", maxeval=100)
    assert result.options["objective"].startswith("delta") and "pi" in result.fit.objective
    est = result.profiles[result.profiles["estimate"]]
    assert (est["change"] == 0).all()
    # the profile's change is the pi-weighted objective's: a refit with r held gives the same objective value
    row = result.profiles[(result.profiles["parameter"] == "r") & ~result.profiles["estimate"]].iloc[1]
    refit = bl.fit(bl.Rigid, data, fixed={"r": row["value"]}, method="global", objective="delta_pi", maxeval=100)
    assert row["change"] == pytest.approx(refit.objective_value - result.fit.objective_value, rel=1e-9, abs=1e-12)
