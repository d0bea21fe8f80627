"""bouncelab.fit: recovery, optimality against brute force, the paper's procedures, errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import differential_evolution

import bouncelab as bl
from bouncelab.core.errors import DataError, FitError, ParameterError
from bouncelab.fitting.objective import ErrorMeasure
from tests.conftest import random_landings
from tests.test_laws import Frictionless


def landings_plus_x(rng, n):
    return np.abs(random_landings(rng, n)) * np.array([1.0, -1.0, 1.0])


def noisy(law, p0, rng, level=0.01):
    """Lift-off from ``law`` plus Gaussian noise of ``level`` times |p0| per component (the law's maths on any
    landing: random landings include grazing ones that the unit guard of predict refuses)."""
    scale = level * np.linalg.norm(p0, axis=1, keepdims=True)
    return law.predict(p0, plausible=None) + scale * rng.standard_normal(p0.shape)


@pytest.fixture(scope="module")
def campaign_a():
    return bl.load_campaign("A")


# ----------------------------------------------------------------------------------- recovery
@pytest.mark.parametrize(
    ("truth", "tol"),
    [
        (bl.Rigid(r=0.55, mu=0.35), {"r": 0.01, "mu": 0.01}),
        (bl.PennerFixed(r=0.42, mu=0.3, beta_deg=12.9), {"r": 0.02, "mu": 0.02, "beta_deg": 0.5}),
        (bl.PennerVarying(r=0.45, mu=0.3, k_p=1.5e-4), {"r": 0.02, "mu": 0.02, "k_p": 1e-5}),
        (bl.TangentialRestitution(r=0.5, mu=0.3, e_t=0.4), {"r": 0.01, "mu": 0.02, "e_t": 0.05}),
    ],
    ids=lambda v: type(v).__name__ if isinstance(v, bl.BounceModel) else "",
)
def test_parameter_recovery(truth, tol, rng):
    p0 = landings_plus_x(rng, 600)
    res = bl.fit(type(truth), (p0, noisy(truth, p0, rng)))
    for name, t in tol.items():
        assert res.model.parameters[name] == pytest.approx(getattr(truth, name), abs=t), name
    assert res.delta < 0.03


def test_piecewise_recovery(rng):
    truth = bl.PiecewiseAffine.published("A")
    p0 = landings_plus_x(rng, 800) * np.array([0.5, 0.5, 0.5])
    pf = noisy(truth, p0, rng, 0.003)
    res = bl.fit(bl.PiecewiseAffine, (p0, pf))
    # the plane may move within the gap between bounces, but the maps must come back
    np.testing.assert_allclose(res.model.A1, truth.A1, atol=0.03)
    np.testing.assert_allclose(res.model.A2, truth.A2, atol=0.03)
    assert np.mean(res.model.regime(p0, plausible=None) == truth.regime(p0, plausible=None)) > 0.98
    assert res.delta < 0.01


# --------------------------------------------------------------------- optimality vs brute force
def test_rigid_no_worse_than_dense_grid(rng):
    p0 = landings_plus_x(rng, 60)
    pf = noisy(bl.Rigid(r=0.4, mu=0.5), p0, rng, 0.08)
    res = bl.fit(bl.Rigid, (p0, pf))
    measure = ErrorMeasure(bl.Rigid(), p0, pf)
    r, mu = np.meshgrid(np.linspace(0, 1, 301), np.linspace(0, 1.5, 451))
    grid = min(measure.errors(np.array([a, b]))[0] for a, b in zip(r.ravel(), mu.ravel(), strict=True))
    assert res.delta <= grid + 1e-12


@pytest.mark.parametrize("cls", [bl.PennerFixed, bl.PennerVarying, bl.TangentialRestitution])
def test_no_worse_than_differential_evolution(cls, rng):
    p0 = landings_plus_x(rng, 40)
    truth = cls(**{s.name: 0.5 * (s.bounds[0] + s.bounds[1]) for s in cls.parameter_specs})
    pf = noisy(truth, p0, rng, 0.1)
    res = bl.fit(cls, (p0, pf), plausible=None)  # mid-bounds laws may spin a ball off beyond golf's 20 000 rpm
    measure = ErrorMeasure(cls(), p0, pf)
    bounds = [s.bounds for s in cls.parameter_specs]
    best = min(differential_evolution(lambda t: measure.errors(t)[0], bounds, tol=1e-12, seed=s).fun
               for s in range(3))
    assert res.delta <= best + 1e-9


def test_result_delta_is_metric_of_model(campaign_a):
    res = bl.fit(bl.PennerFixed, campaign_a)
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    assert res.delta == pytest.approx(bl.delta(p0, pf, res.model.predict(p0)), rel=1e-12)
    np.testing.assert_allclose(res.delta_q, bl.delta_q(p0, pf, res.model.predict(p0)), rtol=1e-12)
    assert res.objective == "delta" and res.objective_value == pytest.approx(res.delta, rel=1e-12)
    assert res.n_evaluations == res.n_global + res.n_local > 0
    assert res.elapsed > 0 and res.stop_reason


# ------------------------------------------------------------------------------ reproducibility
@pytest.mark.parametrize("algorithm", ["DIRECT_L", "CRS2_LM", "ISRES", "ESCH", "MLSL"])
def test_same_seed_same_result(algorithm, campaign_a):
    a = bl.fit(bl.Rigid, campaign_a, algorithm=algorithm, seed=3)
    b = bl.fit(bl.Rigid, campaign_a, algorithm=algorithm, seed=3)
    assert a.model == b.model and a.n_evaluations == b.n_evaluations
    assert a.algorithm.startswith(algorithm)


def test_input_law_is_not_changed(campaign_a):
    start = bl.Rigid(r=0.3, mu=0.3)
    res = bl.fit(start, campaign_a)
    assert start == bl.Rigid(r=0.3, mu=0.3)
    assert res.model != start


# ------------------------------------------------------------------------------ objectives
def test_component_objective_minimises_that_component(campaign_a):
    by_delta = bl.fit(bl.Rigid, campaign_a)
    by_omega = bl.fit(bl.Rigid, campaign_a, objective="omega")
    assert by_omega.objective == "delta_omega"
    assert by_omega.delta_q[2] <= by_delta.delta_q[2] + 1e-12
    assert by_omega.delta >= by_delta.delta - 1e-12
    mixed = bl.fit(bl.Rigid, campaign_a, objective={"delta": 1.0, "omega": 2.0})
    assert mixed.objective_value == pytest.approx(mixed.delta + 2 * mixed.delta_q[2], rel=1e-10)


@pytest.mark.parametrize("bad", ["energy", {}, {"delta": -1.0}, {"spin": 1.0}, 3])
def test_bad_objective(bad, campaign_a):
    with pytest.raises(FitError):
        bl.fit(bl.Rigid, campaign_a, objective=bad)


# ------------------------------------------------------------------------------- bounds
def test_fixed_parameter_and_bounds(campaign_a):
    res = bl.fit(bl.PennerFixed, campaign_a, bounds={"beta_deg": (15.0, 15.0)})
    assert res.model.beta_deg == 15.0
    res2 = bl.fit(bl.Rigid, campaign_a, bounds={"mu": (0.0, 0.1)})
    assert res2.model.mu == pytest.approx(0.1)
    assert res2.at_bounds == {"mu": "upper"}
    assert any("upper bound" in n for n in res2.notes)
    assert "at upper bound" in res2.report()


def test_flat_objective_is_reported(rng):
    """When every bounce grips above some mu, mu is not determined beyond it: the fit says so and where."""
    p0 = landings_plus_x(rng, 200)
    p0[:, 2] = -p0[:, 0] + rng.uniform(-300, 300, len(p0))
    pf = bl.Rigid(r=0.5, mu=1.0).predict(p0, plausible=None)
    pf[:, 1] += 5.0 * rng.standard_normal(len(p0))  # noise in ydot only: rolling predicts xdot, omega exactly
    res = bl.fit(bl.Rigid, (p0, pf), plausible=None)  # spins up to ~2300 rad/s: beyond golf's ranges on purpose
    lo, hi = res.insensitive["mu"]
    r = res.model.r
    grip = np.max(np.abs(p0[:, 0] + p0[:, 2]) / (3.5 * (1 + r) * np.abs(p0[:, 1])))  # smallest mu where all grip
    assert lo == pytest.approx(grip, rel=1e-4) and hi == 1.5  # to the 1e-9 tolerance on delta
    assert lo <= res.model.mu <= hi
    assert any("do not determine" in n for n in res.notes)
    assert "not determined by the data" in res.report()


@pytest.mark.parametrize(
    "bounds",
    [{"r": (0.0, 1.2)}, {"mu": (-0.5, 1.0)}, {"mu": (1.0, 0.5)}, {"r": (0.0, np.nan)}, {"r": "abc"}],
    ids=["beyond physical", "below physical", "reversed", "not finite", "not a pair"],
)
def test_bad_bounds(bounds, campaign_a):
    with pytest.raises(ParameterError) as e:
        bl.fit(bl.Rigid, campaign_a, bounds=bounds)
    (name, value), = bounds.items()
    assert (e.value.law, e.value.parameter, e.value.value) == ("Rigid", name, value)


def test_bounds_of_an_unknown_parameter(campaign_a):
    with pytest.raises(ParameterError) as e:
        bl.fit(bl.Rigid, campaign_a, bounds={"nu": (0.0, 1.0)})
    assert (e.value.law, e.value.parameter) == ("Rigid", "nu")


def test_start_outside_bounds(campaign_a):
    with pytest.raises(ParameterError) as e:
        bl.fit(bl.Rigid(r=0.9, mu=0.5), campaign_a, bounds={"r": (0.0, 0.5)})
    assert (e.value.law, e.value.parameter, e.value.value) == ("Rigid", "r", 0.9)


# ------------------------------------------------------------------------------ bad input
def test_bad_data():
    p0 = np.array([[1000.0, -800.0, 100.0]] * 5)
    with pytest.raises(FitError) as e:  # too few bounces
        bl.fit(bl.PennerFixed, (p0[:3], p0[:3] * 0.5))
    assert (e.value.law, e.value.option) == ("PennerFixed", None)
    bad = p0.copy()
    bad[2, 1] = np.nan
    with pytest.raises(DataError) as e:
        bl.fit(bl.Rigid, (bad, p0))
    assert (e.value.row, e.value.column) == (3, "landing.ydot")
    with pytest.raises(DataError) as e:
        bl.fit(bl.Rigid, (p0, p0[:4]))
    assert e.value.option == "liftoff"
    with pytest.raises(DataError) as e:
        bl.fit(bl.Rigid, "not data")
    assert e.value.option == "data"
    with pytest.raises(FitError) as e:
        bl.fit(42, (p0, p0))
    assert e.value.option == "model"


def test_bad_methods_and_algorithms(campaign_a):
    for law, method in ((bl.Rigid, "annealing"), (bl.PennerFixed, "structured"), (bl.Rigid, "svm")):
        with pytest.raises(FitError) as e:
            bl.fit(law, campaign_a, method=method)
        assert (e.value.law, e.value.option) == (law.__name__, "method")
    assert "PiecewiseAffine" in e.value.message  # the law that has method 'svm' is named
    with pytest.raises(FitError) as e:
        bl.fit(bl.Rigid, campaign_a, algorithm="GN_MAGIC")
    assert e.value.option == "algorithm"
    with pytest.raises(FitError) as e:
        bl.fit(bl.Rigid, campaign_a, local_algorithm="LBFGS")
    assert e.value.option == "local_algorithm"
    with pytest.raises(FitError) as e:  # the piecewise fit minimises delta only
        bl.fit(bl.PiecewiseAffine, campaign_a, objective="omega")
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", "objective")
    assert [(h.option, h.value) for h in e.value.hints] == [("method", "global")]


def test_piecewise_class_too_small(rng):
    p0 = landings_plus_x(rng, 40)
    p0[:, 2] = 3000.0  # every bounce backspins hard: all slip
    pf = bl.Rigid(r=0.5, mu=0.1).predict(p0, plausible=None)
    with pytest.raises(FitError, match="both classes") as e:  # 3000 rad/s: beyond golf's ranges on purpose
        bl.fit(bl.PiecewiseAffine, (p0, pf), method="svm", plausible=None)
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", None)  # the data, not an option, are at fault
    with pytest.raises(FitError, match="too few") as e:
        bl.fit(bl.PiecewiseAffine, (p0[:10], pf[:10]), plausible=None)
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", None)


# ------------------------------------------------------------------------- paper's procedures
def test_structured_rigid(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    res = bl.fit(bl.Rigid, campaign_a, method="structured")
    r_ls = -(pf[:, 1] @ p0[:, 1]) / (p0[:, 1] @ p0[:, 1])
    assert res.model.r == pytest.approx(r_ls, rel=1e-12)
    # mu is the best for that r: no other mu on a fine grid does better
    measure = ErrorMeasure(bl.Rigid(), p0, pf)
    grid = min(measure.errors(np.array([r_ls, m]))[0] for m in np.linspace(0, 1.5, 3001))
    assert res.delta <= grid + 1e-12
    # and the global fit, free in r too, is at least as good
    assert bl.fit(bl.Rigid, campaign_a).delta <= res.delta + 1e-12
    lsq = bl.fit(bl.Rigid, campaign_a, method="structured", mu_objective="lstsq")
    assert lsq.model.r == res.model.r and lsq.model.mu != res.model.mu
    with pytest.raises(FitError) as e:
        bl.fit(bl.Rigid, campaign_a, method="structured", mu_objective="l1")
    assert (e.value.law, e.value.option) == ("Rigid", "mu_objective")


def test_svm_procedure(campaign_a):
    res = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm")
    law = res.model
    assert law.normal[2] in (1.0, -1.0)  # the paper's printed form: omega coefficient 1
    assert "omega0 =" in law.plane_equation()
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    labels = bl.classify_slip_roll(p0, pf)
    assert res.mismatched == pytest.approx(np.mean(law.regime(p0) != labels))
    assert np.mean(law.regime(p0)[labels == "slip"] == "slip") > 0.5  # side 2 is the slip side
    # each side's map is the least-squares fit on that side
    side = law.regime(p0) == "slip"
    X = np.column_stack([p0[side], np.ones(side.sum())])
    coef = np.linalg.lstsq(X, pf[side], rcond=None)[0]
    np.testing.assert_allclose(law.A2, coef[:3].T, rtol=1e-9, atol=1e-12)


def test_plane_search_beats_svm(campaign_a):
    svm = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm")
    plane = bl.fit(bl.PiecewiseAffine, campaign_a)
    assert plane.method == "plane"
    assert plane.delta < svm.delta
    assert plane.mismatched is not None


# ------------------------------------------------------------------------------- held out
def test_held_out_errors(campaign_a):
    train, test = bl.split_by_setting(campaign_a, seed=1)
    res = bl.fit(bl.PennerFixed, train, test=test)
    assert res.n_test == test.sizes["bounce"] and res.n_train == train.sizes["bounce"]
    p0, pf = test.landing.values, test.liftoff.values
    assert res.test_delta == pytest.approx(bl.delta(p0, pf, res.model.predict(p0)), rel=1e-12)
    assert set(res.errors.index.get_level_values("data")) == {"train", "test"}
    assert "held out" in res.report()


def test_user_defined_law_is_fitted(rng):
    p0 = landings_plus_x(rng, 100)
    pf = Frictionless(e=0.37).predict(p0) + rng.normal(0, 1.0, p0.shape)
    res = bl.fit(Frictionless, (p0, pf))
    assert res.model.e == pytest.approx(0.37, abs=0.005)


def test_report_and_dict(campaign_a):
    res = bl.fit(bl.Rigid, campaign_a)
    text = res.report()
    for piece in ("[[Fit]] Rigid", "evaluations", "r ", "mu ", "delta", "roll", "slip", "DIRECT_L"):
        assert piece in text
    d = res.to_dict()
    assert d["law"]["law"] == "Rigid" and d["delta"] == res.delta
    assert "FitResult(Rigid(" in repr(res)


def test_svm_plane_readings(campaign_a):
    default = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm")
    hyper = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", svm_plane="hyperplane")
    sv = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", svm_plane="support_vectors")
    margin = bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", svm_plane="margin_support_vectors")
    assert default.model == hyper.model and "decision boundary" in hyper.notes[0]
    assert "all" in sv.notes[0] and "support vectors by least squares" in sv.notes[0]
    assert "on-margin" in margin.notes[0]
    assert len(margin.extras["margin_support"]) < len(sv.extras["svm_support"])
    assert not np.allclose(hyper.model.normal, sv.model.normal)
    with pytest.raises(FitError) as e:
        bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", svm_plane="median")
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", "svm_plane")


def test_plane_search_recovers_the_surrogates_true_plane():
    """The surrogates are made from the published laws, so their true plane is known."""
    for campaign in ("A", "B"):
        ds = bl.load_campaign(campaign, surrogate="published")
        fitted = bl.fit(bl.PiecewiseAffine, ds).model
        truth = bl.PiecewiseAffine.published(campaign)
        p0 = ds.landing.values
        agree = np.mean(fitted.regime(p0) == truth.regime(p0))
        svm_agree = np.mean(bl.fit(bl.PiecewiseAffine, ds, method="svm").model.regime(p0) == truth.regime(p0))
        assert agree > 0.97 and agree > svm_agree


def test_search_options_are_honoured(campaign_a):
    no_polish = bl.fit(bl.Rigid, campaign_a, local_algorithm=None, maxeval=150)
    assert no_polish.n_global <= 151 and "no polish" in no_polish.algorithm
    assert no_polish.delta >= bl.fit(bl.Rigid, campaign_a).delta - 1e-12
    with pytest.raises(FitError) as e:
        bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", svm_C=0.0)
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", "svm_C")


def test_fit_takes_a_law_name_in_any_case(campaign_a):
    by_class = bl.fit(bl.Rigid, campaign_a, seed=3)
    by_name = bl.fit("rigid", campaign_a, seed=3)
    assert isinstance(by_name.model, bl.Rigid)
    assert by_name.delta == pytest.approx(by_class.delta, rel=1e-12)
    assert bl.cross_validate("PennerFixed", campaign_a, k=2, seed=0).law == "PennerFixed"


@pytest.mark.parametrize("bad, law", [("Rigidd", "Rigidd"), (3.0, None), (None, None)])
def test_fit_refuses_what_is_not_a_law(bad, law, campaign_a):
    with pytest.raises(FitError) as e:
        bl.fit(bad, campaign_a)
    assert (e.value.option, e.value.law) == ("model", law)


# ------------------------------------------------------------------------------ sample weights
@pytest.mark.parametrize("law, method", [("Rigid", "structured"), ("Rigid", "global"), ("PennerFixed", "global"),
                                         ("PiecewiseAffine", "plane"), ("PiecewiseAffine", "svm")])
def test_integer_sample_weights_are_repeated_bounces(law, method, campaign_a):
    # Weight k on a bounce is the bounce k times (0: dropped), in every stage of every method.
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    w = np.random.default_rng(0).integers(0, 3, len(p0))
    idx = np.repeat(np.arange(len(p0)), w)
    weighted = bl.fit(law, (p0, pf), method=method, sample_weight=w, seed=1)
    repeated = bl.fit(law, (p0[idx], pf[idx]), method=method, seed=1)
    assert weighted.objective_value == pytest.approx(repeated.objective_value, rel=1e-6)
    assert weighted.objective.endswith("sample-weighted")
    if law != "PiecewiseAffine":  # a piecewise plane is one of many with the same delta
        np.testing.assert_allclose(_numbers(weighted.model), _numbers(repeated.model), rtol=1e-6)
    # The reported delta stays the paper's unweighted mean over the fitted bounces (weight 0: left out).
    kept = w > 0
    assert weighted.n_train == kept.sum() and any("sample_weight 0 left out" in n for n in weighted.notes)
    assert weighted.delta == pytest.approx(bl.delta(p0[kept], pf[kept], weighted.model.predict(p0[kept])), rel=1e-12)


def test_sample_weights_change_the_fit_and_equal_weights_do_not(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    plain = bl.fit("PennerFixed", (p0, pf))
    assert bl.fit("PennerFixed", (p0, pf), sample_weight=np.full(len(p0), 7.0)).model == plain.model
    skew = np.where(p0[:, 0] > np.median(p0[:, 0]), 10.0, 1.0)
    assert bl.fit("PennerFixed", (p0, pf), sample_weight=skew).model != plain.model


@pytest.mark.parametrize("weights, row", [
    (np.ones(5), None), (["a"] * 330, None),
    (np.r_[np.ones(3), -1.0, np.ones(326)], 4), (np.r_[np.nan, np.ones(329)], 1),
    (np.zeros(330), None),
], ids=["length", "text", "negative", "NaN", "all zero"])
def test_bad_sample_weights_are_refused(weights, row, campaign_a):
    with pytest.raises(DataError) as err:
        bl.fit("Rigid", campaign_a, sample_weight=weights)
    assert (err.value.option, err.value.column, err.value.row) == ("sample_weight", "sample_weight", row)


def test_functions_that_split_or_resample_refuse_sample_weights(campaign_a):
    w = np.ones(campaign_a.sizes["bounce"])
    for call in (lambda: bl.cross_validate("Rigid", campaign_a, k=2, sample_weight=w),
                 lambda: bl.bootstrap("Rigid", campaign_a, n=2, sample_weight=w),
                 lambda: bl.sweep("Rigid", campaign_a, {"mu": [0.3]}, sample_weight=w),
                 lambda: bl.compare(campaign_a, ["Rigid"], split="setting", sample_weight=w)):
        with pytest.raises(FitError) as e:
            call()
        assert e.value.option == "sample_weight"
    # Without a split, compare fits all bounces and passes the weights on.
    cmp = bl.compare(campaign_a, ["Rigid"], sample_weight=w * 2)
    assert cmp.results["Rigid"].objective.endswith("sample-weighted")


def test_only_the_ratios_of_sample_weights_matter_even_at_extreme_scales(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    w = np.random.default_rng(4).uniform(0.5, 2.0, len(p0))
    ref = bl.fit("Rigid", (p0, pf), method="structured", sample_weight=w)
    for scale in (1e-300, 1e300):
        res = bl.fit("Rigid", (p0, pf), method="structured", sample_weight=w * scale)
        # (rounding in the rescaled weights may move the search's last steps: agreement to its tolerance)
        np.testing.assert_allclose(_numbers(res.model), _numbers(ref.model), rtol=1e-6)
        assert res.objective_value == pytest.approx(ref.objective_value, rel=1e-9)


def test_zero_weights_leave_bounces_out_of_every_count(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    one = np.zeros(len(p0))
    one[0] = 1.0
    with pytest.raises(FitError) as e:  # too few: one bounce left, as if only it were given
        bl.fit("PennerFixed", (p0, pf), sample_weight=one)
    assert (e.value.law, e.value.option) == ("PennerFixed", None) and "1 bounce(s)" in e.value.message
    twelve = np.zeros(len(p0))
    twelve[:12] = 1.0
    with pytest.raises(FitError):
        bl.fit("PiecewiseAffine", (p0, pf), sample_weight=twelve)


def test_structured_least_squares_mu_is_weighted(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    k = np.random.default_rng(1).integers(0, 4, len(p0))
    rep = np.repeat(np.arange(len(p0)), k)
    a = bl.fit("Rigid", (p0, pf), method="structured", mu_objective="lstsq", sample_weight=k)
    b = bl.fit("Rigid", (p0[rep], pf[rep]), method="structured", mu_objective="lstsq")
    np.testing.assert_allclose(_numbers(a.model), _numbers(b.model), rtol=1e-6)


def _numbers(law) -> list[float]:
    """Every number of a law's parameters, in declaration order."""
    return list(law.flat_parameters().values())
