"""Issue 11 item 5: bouncelab.BounceRegressor, a scikit-learn 3-output regressor."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.model_selection import GridSearchCV, GroupKFold, cross_val_score
from sklearn.utils.estimator_checks import parametrize_with_checks

import bouncelab as bl
from bouncelab.core.errors import DataError

# scikit-learn's generic checks fit on random data of 1 to 10 columns whose second column is mostly positive.
# A bounce law takes exactly three columns [xdot0, ydot0, omega0] with ydot0 < 0 (a landing moves down), so
# these checks cannot apply; the properties they check are tested below on bounces instead.
_WIDTH = "fits random data with 2 to 30 columns; a landing has exactly 3 (xdot0, ydot0, omega0)"
_UPWARD = "fits random 3-column data with ydot0 >= 0, i.e. balls moving up; a landing moves down"
NOT_APPLICABLE = {
    "check_estimators_overwrite_params": _WIDTH, "check_estimators_fit_returns_self": _WIDTH,
    "check_readonly_memmap_input": _WIDTH, "check_n_features_in_after_fitting": _WIDTH,
    "check_estimators_dtypes": _WIDTH, "check_dtype_object": _WIDTH, "check_regressors_train": _WIDTH,
    "check_regressor_data_not_an_array": _WIDTH, "check_regressor_multioutput": _WIDTH,
    "check_regressors_no_decision_function": _WIDTH, "check_regressors_int": _WIDTH,
    "check_fit_idempotent": _WIDTH, "check_fit_check_is_fitted": _WIDTH, "check_n_features_in": _WIDTH,
    "check_fit_score_takes_y": _UPWARD, "check_dont_overwrite_parameters": _UPWARD,
    "check_positive_only_tag_during_fit": _WIDTH, "check_pipeline_consistency": _UPWARD,
    "check_estimators_nan_inf": _UPWARD, "check_estimators_pickle": _UPWARD,
    "check_f_contiguous_array_estimator": _UPWARD, "check_methods_sample_order_invariance": _UPWARD,
    "check_methods_subset_invariance": _UPWARD, "check_dict_unchanged": _UPWARD, "check_fit2d_predict1d": _UPWARD,
    # sample weights: the same properties are tested on bounces in test_sample_weight_properties_on_bounces
    "check_sample_weights_pandas_series": "fits a DataFrame of 2 unnamed columns; a landing has 3 named ones",
    "check_sample_weights_not_an_array": _WIDTH, "check_all_zero_sample_weights_error": _WIDTH,
    "check_sample_weights_shape": _WIDTH, "check_sample_weights_not_overwritten": _WIDTH,
    "check_sample_weight_equivalence_on_dense_data": _WIDTH, "check_sample_weights_list": _UPWARD,
}


_CAUSE = {_WIDTH: "needs 3 columns", _UPWARD: "ydot must be negative",
          NOT_APPLICABLE["check_sample_weights_pandas_series"]: "DataFrame columns must be named"}


@parametrize_with_checks([bl.BounceRegressor("Rigid")], expected_failed_checks=lambda est: NOT_APPLICABLE)
def test_sklearn_estimator_checks(estimator, check) -> None:
    check(estimator)


def test_the_expected_failures_fail_for_their_stated_reason() -> None:
    """Each check marked as not applicable fails on the data its reason names, nothing else."""
    import warnings

    from sklearn.utils.estimator_checks import check_estimator

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = check_estimator(bl.BounceRegressor("Rigid"), on_fail=None, expected_failed_checks=NOT_APPLICABLE)
    seen = set()
    for r in results:
        if r["status"] != "xfail":
            continue
        seen.add(r["check_name"])
        exc, texts = r["exception"], []
        while exc is not None:  # the check's own assertion, and the DataError it reports
            texts.append(str(exc))
            exc = exc.__cause__ or exc.__context__
        assert isinstance(r["exception"], ValueError | AssertionError), r
        assert any(_CAUSE[NOT_APPLICABLE[r["check_name"]]] in t for t in texts), (r["check_name"], texts)
    assert seen == set(NOT_APPLICABLE)  # every listed check still fails (none passes unnoticed)


@pytest.fixture(scope="module")
def bounces():
    ds = bl.load_campaign("A")
    return ds.landing.values, ds.liftoff.values, ds.setting.values


def test_fit_predict_score_match_bouncelab_fit(bounces) -> None:
    X, Y, _ = bounces
    est = bl.BounceRegressor("PennerFixed", seed=3)
    assert est.fit(X, Y) is est
    ref = bl.fit(bl.PennerFixed, (X, Y), seed=3)
    assert est.law_ == ref.model and est.n_features_in_ == 3
    np.testing.assert_array_equal(est.predict(X), ref.model.predict(X))
    assert est.score(X, Y) == pytest.approx(-ref.delta, rel=1e-12)
    assert est.score(X, Y) == pytest.approx(-bl.delta(X, Y, est.predict(X)), rel=1e-12)


def test_properties_of_the_generic_checks_on_bounces(bounces) -> None:
    """What the checks listed in NOT_APPLICABLE verify, on landings and lift-offs."""
    X, Y, _ = bounces
    est = bl.BounceRegressor("Rigid", objective={"delta": 1.0, "omega": 0.5})
    params = est.get_params()
    est.fit(X, Y)
    assert est.get_params() == params  # parameters untouched by fit
    pred = est.predict(X)
    state = dict(est.__dict__)
    est.score(X, Y)
    assert est.__dict__.keys() == state.keys()  # predict/score change nothing
    again = clone(est).fit(X, Y)
    np.testing.assert_array_equal(again.predict(X), pred)  # idempotent, deterministic
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(est)).predict(X), pred)
    perm = np.random.default_rng(0).permutation(len(X))
    np.testing.assert_array_equal(est.predict(X[perm]), pred[perm])  # sample order
    np.testing.assert_array_equal(est.predict(X[:7]), pred[:7])  # subsets
    np.testing.assert_array_equal(est.predict(np.asfortranarray(X)), pred)
    ro = X.copy()
    ro.flags.writeable = False
    np.testing.assert_array_equal(est.predict(ro), pred)
    bad = X.copy()
    bad[4, 2] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        clone(est).fit(bad, Y)
    with pytest.raises(DataError) as e:  # 2 features, not 3
        est.predict(X[:, :2])
    assert e.value.option == "X"
    with pytest.raises(DataError) as e:  # landings moving up
        est.predict(-X)
    assert e.value.column == "landing.ydot"


def test_cross_val_score_with_groupkfold_by_setting(bounces) -> None:
    X, Y, groups = bounces
    cv = GroupKFold(n_splits=4)
    scores = cross_val_score(bl.BounceRegressor("Rigid"), X, Y, groups=groups, cv=cv)
    assert scores.shape == (4,)
    for score, (tr, te) in zip(scores, cv.split(X, Y, groups), strict=True):
        assert not set(groups[tr]) & set(groups[te])  # every fold holds out whole settings
        law = bl.fit(bl.Rigid, (X[tr], Y[tr])).model
        assert score == pytest.approx(-bl.delta(X[te], Y[te], law.predict(X[te])), rel=1e-12)


def test_grid_search_over_laws_and_parameters(bounces) -> None:
    X, Y, groups = bounces
    grid = [{"law": ["Rigid", bl.PennerVarying, bl.PennerFixed()]},
            {"law": [bl.PennerFixed()], "law__fade_xdot": [50.0], "fixed": [{"beta_deg": 0.0}]}]
    search = GridSearchCV(bl.BounceRegressor(), grid, cv=GroupKFold(n_splits=3)).fit(X, Y, groups=groups)
    res = search.cv_results_
    assert len(res["params"]) == 4
    best = int(np.argmax(res["mean_test_score"]))
    assert search.best_index_ == best
    assert isinstance(search.best_estimator_.law_, bl.BounceModel)
    # PennerFixed with beta held at 0 is the rigid bounce: its held-out score equals Rigid's
    rigid, flat = res["mean_test_score"][0], res["mean_test_score"][3]
    assert flat == pytest.approx(rigid, rel=1e-3)
    est = bl.BounceRegressor().set_params(**res["params"][3]).fit(X, Y)
    assert est.law_.fade_xdot == 50.0 and est.law_.beta_deg == 0.0


def test_set_params_on_the_law_and_clone() -> None:
    est = bl.BounceRegressor(bl.Rigid(r=0.5, mu=0.3))
    est.set_params(law__mu=0.7, seed=4)
    assert est.law == bl.Rigid(r=0.5, mu=0.7) and est.seed == 4
    assert clone(est).law is est.law  # laws are immutable values: their own clones
    assert est.get_params(deep=True)["law__mu"] == 0.7


def test_sample_weight_in_fit_and_in_scikit_learn_cross_validation(bounces) -> None:
    X, Y, groups = bounces
    w = np.random.default_rng(1).integers(0, 3, len(X)).astype(float)
    est = bl.BounceRegressor("PennerFixed").fit(X, Y, sample_weight=w)
    assert est.law_ == bl.fit("PennerFixed", (X, Y), sample_weight=w).model
    # scikit-learn splits the weights with the bounces (params are passed to fit).
    scores = cross_val_score(bl.BounceRegressor("Rigid"), X, Y, groups=groups, cv=GroupKFold(3),
                             params={"sample_weight": w})
    plain = cross_val_score(bl.BounceRegressor("Rigid"), X, Y, groups=groups, cv=GroupKFold(3))
    assert scores.shape == (3,) and not np.allclose(scores, plain)
    with pytest.raises(DataError) as e:
        bl.BounceRegressor("Rigid").fit(X, Y, sample_weight=w[:-1])
    assert e.value.option == "sample_weight"


def test_sample_weight_properties_on_bounces(bounces) -> None:
    """scikit-learn's sample-weight checks, on bounces (its own use random data no landing can be)."""
    import pandas as pd

    X, Y, _ = bounces
    w = np.random.default_rng(2).integers(0, 3, len(X)).astype(float)
    kept = w.copy()
    ref = bl.BounceRegressor("PennerFixed").fit(X, Y, sample_weight=w)
    np.testing.assert_array_equal(w, kept)  # not overwritten
    for other in (list(w), pd.Series(w), w.astype(int)):  # list, Series, integers
        assert bl.BounceRegressor("PennerFixed").fit(X, Y, sample_weight=other).law_ == ref.law_
    idx = np.repeat(np.arange(len(X)), w.astype(int))  # equivalence with repeated bounces
    repeated = bl.BounceRegressor("PennerFixed").fit(X[idx], Y[idx]).law_
    np.testing.assert_allclose(list(repeated.flat_parameters().values()), list(ref.law_.flat_parameters().values()),
                               rtol=1e-6)
    for bad in (np.zeros(len(X)), np.ones((len(X), 2))):  # all zero; wrong shape: a ValueError naming weights
        with pytest.raises(ValueError) as e:
            bl.BounceRegressor("PennerFixed").fit(X, Y, sample_weight=bad)
        assert (e.value.option, e.value.row) == ("sample_weight", None)


def test_score_checks_its_sample_weights_as_fit_does(bounces) -> None:
    X, Y, _ = bounces
    est = bl.BounceRegressor("Rigid").fit(X, Y)
    w = np.ones(len(X))
    assert est.score(X, Y, sample_weight=w * 3) == pytest.approx(est.score(X, Y))
    for bad, row in ((-w, 1), (np.r_[np.nan, w[1:]], 1), (w[:-1], None), (0 * w, None)):
        with pytest.raises(DataError) as e:
            est.score(X, Y, sample_weight=bad)
        assert (e.value.option, e.value.row) == ("sample_weight", row)


def test_the_law_parameter_is_read_as_fit_reads_it(bounces) -> None:
    X, Y, _ = bounces
    assert isinstance(bl.BounceRegressor("pennerfixed").fit(X, Y).law_, bl.PennerFixed)  # any case, as bl.fit
    for bad in ("Nope", 3):  # a bad estimator parameter stays a ParameterError
        with pytest.raises(bl.errors.ParameterError) as e:
            bl.BounceRegressor(bad).fit(X, Y)
        assert (e.value.parameter, e.value.value) == ("law", bad)


def test_bad_arrays_are_data_errors_naming_x_or_y_and_the_row(bounces) -> None:
    """Issue 22: scikit-learn's ValueErrors came through for these; bl.fit names the row with a DataError."""
    X, Y, _ = bounces
    nan, inf = X.copy(), X.copy()
    nan[4, 2], inf[6, 0] = np.nan, np.inf
    fitted = bl.BounceRegressor("Rigid").fit(X, Y)
    # (call, the argument, (row, column) of a bad value, scikit-learn's own wording where its checks look for it)
    cases = [
        (lambda: bl.BounceRegressor().fit(nan, Y), None, (5, "landing.omega"), None),
        (lambda: bl.BounceRegressor().fit(X, np.where(np.arange(3) == 1, Y, np.inf)), None, (1, "liftoff.xdot"), None),
        (lambda: fitted.predict(inf), None, (7, "landing.xdot"), None),
        (lambda: bl.BounceRegressor().fit(X, Y[:, 0]), "y", (None, None), None),  # 1-D
        (lambda: bl.BounceRegressor().fit(X[:1], Y[:1]), "X", (None, None), "Found array with 1 sample(s)"),
        (lambda: bl.BounceRegressor().fit(X + 0j, Y), "X", (None, None), "Complex data not supported"),
        (lambda: bl.BounceRegressor().fit(X[None], Y), "X", (None, None), None),  # 3-D
        (lambda: fitted.predict(X[0]), "X", (None, None), None),  # one bounce, 1-D
        (lambda: fitted.predict(X[None]), "X", (None, None), None),
        (lambda: fitted.predict(X + 0j), "X", (None, None), "Complex data not supported"),
        (lambda: fitted.predict(X[:0]), "X", (None, None), "0 sample"),
    ]
    for call, option, where, sklearn_words in cases:
        with pytest.raises(DataError) as e:
            call()
        assert isinstance(e.value, ValueError)  # scikit-learn's convention holds
        assert (e.value.option, (e.value.row, e.value.column)) == (option, where)
        if sklearn_words is not None:
            assert sklearn_words in e.value.message


def test_predict_before_fit_is_scikit_learns_not_fitted_error() -> None:
    from sklearn.exceptions import NotFittedError as SklearnNotFittedError

    X = bl.load_campaign("A").landing.values
    for call in (lambda est: est.predict(X), lambda est: est.score(X, X)):
        with pytest.raises(SklearnNotFittedError, match="not fitted yet") as e:
            call(bl.BounceRegressor("Rigid"))
        assert isinstance(e.value, bl.errors.NotFittedError)  # and bouncelab's, a ValueError
        assert isinstance(e.value, bl.errors.BouncelabError)
