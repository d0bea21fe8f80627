"""Held-out evaluation (split, cross-validation, inferred settings) and bouncelab.compare."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import adjusted_rand_score

import bouncelab as bl
from bouncelab.core.errors import DataError, FitError


@pytest.fixture(scope="module")
def campaign_b():
    return bl.load_campaign("B")


def test_split_by_setting(campaign_b):
    train, test = bl.split_by_setting(campaign_b, seed=4)
    settings = campaign_b.setting.values
    counts = pd.Series(test.setting.values).value_counts()
    assert (counts == 1).all()
    assert set(test.setting.values) == {s for s in set(settings) if (settings == s).sum() > 1}
    assert train.sizes["bounce"] + test.sizes["bounce"] == campaign_b.sizes["bounce"]
    assert not set(train.bounce.values) & set(test.bounce.values)
    again = bl.split_by_setting(campaign_b, seed=4)[1]
    np.testing.assert_array_equal(again.bounce.values, test.bounce.values)
    other = bl.split_by_setting(campaign_b, seed=5)[1]
    assert not np.array_equal(other.bounce.values, test.bounce.values)


def test_split_needs_settings(campaign_b):
    with pytest.raises(DataError) as e:
        bl.split_by_setting(campaign_b.drop_vars("setting"))
    assert (e.value.column, e.value.option) == ("setting", None)
    assert "infer_settings" in e.value.message  # says how to make the settings
    with pytest.raises(DataError) as e:
        bl.split_by_setting((campaign_b.landing.values, campaign_b.liftoff.values))
    assert e.value.option == "data"
    single = campaign_b.assign_coords(setting=("bounce", np.arange(campaign_b.sizes["bounce"])))
    with pytest.raises(DataError) as e:  # no setting has two or more bounces
        bl.split_by_setting(single)
    assert (e.value.column, e.value.option) == ("setting", None)


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_infer_settings_recovers_surrogate_settings(campaign):
    ds = bl.load_campaign(campaign, surrogate="published")  # well-separated settings (the turf: below)
    labels = bl.infer_settings(ds)
    assert adjusted_rand_score(ds.setting.values, labels) > 0.97
    known = bl.infer_settings(ds, n_settings=len(np.unique(ds.setting.values)))
    assert adjusted_rand_score(ds.setting.values, known) > 0.97
    assert labels[0] == 1 and set(labels) == set(range(1, labels.max() + 1))


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_infer_settings_on_the_turf_surrogates(campaign):
    # Simulated landings scatter by a paper-like launcher scatter, so neighbouring dials can overlap (A's
    # closest ones): told how many settings there are, the clustering still finds them closely.
    ds = bl.load_campaign(campaign, surrogate="turf")
    known = bl.infer_settings(ds, n_settings=len(np.unique(ds.setting.values)))
    assert adjusted_rand_score(ds.setting.values, known) > 0.9


def test_infer_settings_errors(campaign_b):
    with pytest.raises(DataError) as e:
        bl.infer_settings(campaign_b, n_settings=0)
    assert e.value.option == "n_settings"
    with pytest.raises(DataError) as e:
        bl.infer_settings(campaign_b, threshold=-1)
    assert e.value.option == "threshold"


def test_cross_validate_groups_settings(campaign_b):
    cv = bl.cross_validate(bl.Rigid, campaign_b, k=4, seed=2)
    assert len(cv.folds) == 4
    assert cv.folds["n_test"].sum() == campaign_b.sizes["bounce"]
    assert cv.delta == pytest.approx(cv.folds["test_delta"].mean())
    assert np.isfinite(cv.delta_std) and cv.delta_std > 0
    assert "held-out delta" in repr(cv)
    with pytest.raises(FitError) as e:
        bl.cross_validate(bl.Rigid, campaign_b, k=1)
    assert (e.value.option, e.value.law) == ("k", "Rigid")


def test_cross_validation_folds_never_share_a_setting(campaign_b, monkeypatch):
    import bouncelab.fitting.fitter as fitmod

    seen = []
    real_fit = fitmod.fit

    def spy(model, data, **kw):
        seen.append((set(data.setting.values), set(kw["test"].setting.values)))
        return real_fit(model, data, **kw)

    monkeypatch.setattr(fitmod, "fit", spy)
    bl.cross_validate(bl.Rigid, campaign_b, k=3)
    assert len(seen) == 3
    for train_settings, test_settings in seen:
        assert not train_settings & test_settings


def test_compare_tables(campaign_b):
    cmp = bl.compare(campaign_b, ["Rigid", bl.PennerFixed, bl.PiecewiseAffine()])
    assert list(cmp.table.index) == ["Rigid", "PennerFixed", "PiecewiseAffine"]
    assert cmp.campaign == "B"
    for name, res in cmp.results.items():
        assert cmp.table.loc[name, "train_delta"] == res.delta
    assert cmp.table.loc["PennerFixed", "beta_deg"] == cmp.results["PennerFixed"].model.beta_deg
    paper = cmp.published()
    # Table 3's delta is on the bounces the paper fitted, as ours; Table 2's 7.84 % is a test-set figure,
    # shown only beside held-out errors (compare(..., split="setting")).
    assert paper.loc["Rigid", "delta"] == 0.350 and np.isnan(paper.loc["PiecewiseAffine", "delta"])
    md = cmp.to_markdown()
    assert "| delta |" in md and "(35 %)" in md and campaign_b.attrs["warning"] in md
    assert cmp.notes == [campaign_b.attrs["warning"] + " Agreement with the paper's numbers for its measured "
                         "campaign is expected only roughly."]
    pw = cmp.by_class("PiecewiseAffine")
    assert list(pw.index) == ["overall", "roll", "slip"] and 0 <= pw.loc["overall", "mismatched"] <= 1
    assert cmp.table.loc["PiecewiseAffine", "train_mismatched"] == cmp.results["PiecewiseAffine"].mismatched
    sbs = cmp.side_by_side()
    assert ("delta", "paper") in sbs.columns and sbs.loc["Rigid", ("r", "paper")] == 0.260


def test_compare_with_split(campaign_b):
    cmp = bl.compare(campaign_b, ["Rigid"], split="setting", seed=1)
    assert "test_delta" in cmp.table.columns
    assert cmp.results["Rigid"].n_test == len(np.unique(campaign_b.setting.values))
    assert "held-out" in cmp.to_markdown()


def test_compare_errors(campaign_b):
    with pytest.raises(FitError) as e:
        bl.compare(campaign_b, ["Bouncy"])
    assert (e.value.option, e.value.law) == ("model", "Bouncy")
    with pytest.raises(FitError) as e:  # each law once
        bl.compare(campaign_b, ["Rigid", bl.Rigid])
    assert e.value.option == "laws" and "['Rigid', 'Rigid']" in e.value.message
    with pytest.raises(FitError) as e:
        bl.compare(campaign_b, ["Rigid"], split="random")
    assert e.value.option == "split"
    with pytest.raises(FitError) as e:  # at least one law
        bl.compare(campaign_b, [])
    assert e.value.option == "laws"


def test_compare_and_fit_notes_name_what_made_the_data():
    """A simulated campaign is not called a surrogate of the published laws; a fit report on synthetic data says so."""
    turf = bl.load_campaign("A", surrogate="turf")
    cmp = bl.compare(turf, ["Rigid"])
    law = json.loads(turf.attrs["turf_calibration"])["law"]  # the turf law that made it
    assert law in cmp.notes[0] and "published piecewise" not in cmp.notes[0]
    assert law in cmp.to_markdown()
    assert turf.attrs["warning"] in bl.fit(bl.Rigid, turf).notes
    mine = turf.assign_attrs(data_kind="measured", campaign="mine")
    mine.attrs.pop("warning")
    assert bl.compare(mine, ["Rigid"]).notes == [] and bl.fit(bl.Rigid, mine).notes == []


def test_compare_takes_law_names_in_any_case(campaign_b):
    cmp = bl.compare(campaign_b, ["rigid", "PENNERFIXED"])
    assert list(cmp.table.index) == ["Rigid", "PennerFixed"]
    with pytest.raises(bl.FitError) as e:
        bl.compare(campaign_b, ["rigidd"])
    assert (e.value.option, e.value.law) == ("model", "rigidd")


def _tilt_law(name: str, unit: str, to_rad: float) -> type:
    """A toy law whose one parameter, ``tilt``, is in ``unit`` (to_rad converts it to radians)."""

    def _predict(self, p, tilt):
        c = np.cos(tilt * to_rad)
        return p * np.array([0.5 * c, -0.5 * c, 0.2])

    def _regime(self, p, tilt):
        return np.zeros(len(p), dtype=np.int8)

    hi = 89.0 if unit == "deg" else np.radians(89.0)
    spec = bl.laws.Parameter(bounds=(0.0, hi), physical=(0.0, hi), unit=unit, doc="tilt of the contact")
    return type(name, (bl.BounceModel,), {"tilt": spec, "regimes": ("bounce",), "_predict": _predict,
                                          "_regime": _regime})


def test_compare_keeps_a_shared_parameter_name_apart_by_unit(campaign_b):
    deg, rad = _tilt_law("TiltDeg", "deg", np.pi / 180), _tilt_law("TiltRad", "rad", 1.0)
    cmp = bl.compare(campaign_b, [deg, rad, "Rigid"])
    # The first law keeps the plain name; the other unit gets its own column.
    assert {"tilt", "tilt [rad]"} <= set(cmp.parameter_columns()) and cmp.units["tilt"] == "deg"
    d, r = (bl.laws.base.law_name(law) for law in (deg, rad))  # user laws: "module:Class"
    assert np.isnan(cmp.table.loc[d, "tilt [rad]"]) and np.isnan(cmp.table.loc[r, "tilt"])
    # The same fitted tilt, in its own unit in its own column.
    assert cmp.table.loc[d, "tilt"] == pytest.approx(np.degrees(cmp.table.loc[r, "tilt [rad]"]), rel=1e-3, abs=1e-3)
    md = cmp.to_markdown()
    assert "| tilt [deg] |" in md and "| tilt [rad] |" in md and "[rad] [rad]" not in md
    # One unit per name stays one column, as before.
    assert "mu" in bl.compare(campaign_b, ["Rigid", "PennerFixed"]).parameter_columns()


def test_bouncelab_laws_keep_their_parameter_columns_and_the_papers_values(campaign_b):
    spec = bl.laws.Parameter(bounds=(0.0, 1.5), physical=(0.0, 1.5), unit="rad",
                             doc="a tilt in radians under the same name")

    def _predict(self, p, beta_deg):
        c = np.cos(beta_deg)
        return p * np.array([0.5 * c, -0.5 * c, 0.2])

    radians = type("BetaInRadians", (bl.BounceModel,), {
        "beta_deg": spec, "regimes": ("bounce",), "_predict": _predict,
        "_regime": lambda self, p, beta_deg: np.zeros(len(p), dtype=np.int8)})
    # Whatever the order, PennerFixed keeps "beta_deg" and the paper's 18.4 degrees stay beside it.
    cmp = bl.compare(campaign_b, [radians, "PennerFixed"])
    assert "beta_deg" in cmp.table.columns and "beta_deg [rad]" in cmp.table.columns
    assert cmp.published().loc["PennerFixed", "beta_deg"] == pytest.approx(18.4, abs=0.05)
    assert cmp.side_by_side().loc["PennerFixed", ("beta_deg", "paper")] == pytest.approx(18.4, abs=0.05)


def test_compare_says_when_the_fits_minimised_something_else(campaign_b):
    w = np.ones(campaign_b.sizes["bounce"])
    assert not any("Fitted by minimising" in n for n in bl.compare(campaign_b, ["Rigid"]).notes)
    weighted = bl.compare(campaign_b, ["Rigid"], sample_weight=w, heldout=False)
    assert any("delta, sample-weighted, not the paper's delta" in n for n in weighted.notes)
    assert "sample-weighted" in weighted.to_markdown()


# ------------------------------------------------------------------------------ issue 24: held-out columns
def test_compare_held_out_columns_are_assess_held_out_row(campaign_b):
    """compare's held-out errors are assess's (the same folds, fits and weighting), beside the training ones,
    with the number of free parameters; the paper's values stand beside the training errors only."""
    cmp = bl.compare(campaign_b, ["Rigid", "PennerFixed"], seed=2)
    t = cmp.table
    assert list(t["n_free"]) == [2, 3]
    for law in ("Rigid", "PennerFixed"):
        a = bl.assess(law, campaign_b, seed=2, n_bootstrap=0, starts=0, profile_points=3, local_points=0)
        held = a.scores.loc["held-out"]
        for col in ("delta", "delta_xdot", "delta_ydot", "delta_omega", "delta_sd"):
            assert t.loc[law, f"heldout_{col}"] == held[col]
        assert t.loc[law, "train_delta"] == a.scores.loc["training", "delta"]
        assert cmp.heldout[law].split == "setting" and cmp.heldout[law].k == 5
    # each bounce held out once; a fit that saw none of a bounce's setting predicts it worse than one that did
    assert cmp.heldout["Rigid"].scores["n"] == campaign_b.sizes["bounce"]
    assert (t["heldout_delta"] > t["train_delta"]).all()
    md = cmp.to_markdown()
    assert "| free parameters | 2 | 3 |" in md
    row = next(line for line in md.splitlines() if line.startswith("| delta, held out (5 folds by setting)"))
    assert row.count("+-") == 2 and "(" not in row.split("|", 2)[2]  # no paper value beside a held-out figure
    assert f"{100 * t.loc['Rigid', 'heldout_delta']:.3g} % +- {100 * t.loc['Rigid', 'heldout_delta_sd']:.3g} %" in row
    assert "grouped 5-fold cross-validation" in md
    sbs = cmp.side_by_side()
    assert ("heldout_delta", "bouncelab") in sbs.columns and np.isnan(sbs.loc["Rigid", ("heldout_delta", "paper")])
    assert "n_free" not in cmp.parameter_columns() and "heldout_delta" not in cmp.parameter_columns()


def test_compare_held_out_can_be_left_out_or_chosen(campaign_b, monkeypatch):
    import bouncelab.fitting.splits as splits

    calls = []
    real = splits.cross_validate

    def spy(model, data, **kw):
        calls.append(bl.laws.law_name(model))
        return real(model, data, **kw)

    monkeypatch.setattr("bouncelab.fitting.assessment.cross_validate", spy)
    quick = bl.compare(campaign_b, ["Rigid", "PennerFixed"], heldout=False)
    assert calls == [] and "heldout_delta" not in quick.table.columns and list(quick.table["n_free"]) == [2, 3]
    assert "held out" not in quick.to_markdown()
    assert quick.heldout_skipped == {} and "held-out" not in quick.to_markdown()  # no note for what was not asked
    some = bl.compare(campaign_b, ["Rigid", "PennerFixed"], heldout=["PennerFixed"], k=3)
    assert calls == ["PennerFixed"]
    assert np.isnan(some.table.loc["Rigid", "heldout_delta"]) and some.heldout["PennerFixed"].k == 3
    assert "Rigid" in some.heldout_skipped
    md = some.to_markdown()
    assert "Rigid: no held-out errors" in md and "(3 folds by setting)" in md


def test_compare_held_out_by_bounce_without_settings(campaign_b):
    pair = (campaign_b.landing.values[:120], campaign_b.liftoff.values[:120])
    cmp = bl.compare(pair, ["Rigid"], k=4)
    assert cmp.heldout["Rigid"].split == "bounce" and cmp.heldout["Rigid"].scores["n"] == 120
    assert "(4 folds by bounce)" in cmp.to_markdown()
    assert "the data have no launcher settings" in cmp.to_markdown()


def test_compare_held_out_errors_and_options(campaign_b):
    w = np.ones(campaign_b.sizes["bounce"])
    with pytest.raises(FitError) as e:  # the folds could not carry the weights
        bl.compare(campaign_b, ["Rigid"], sample_weight=w, heldout=True)
    assert e.value.option == "sample_weight" and e.value.hints[0] == bl.errors.Hint("heldout", False)
    # by default (heldout=None) a weighted comparison still works, and says why it has no held-out errors
    weighted = bl.compare(campaign_b, ["Rigid"], sample_weight=w)
    assert weighted.heldout == {} and "sample-weighted" in weighted.heldout_skipped["Rigid"]
    assert np.isnan(weighted.table.loc["Rigid", "heldout_delta"])
    assert "Rigid: no held-out errors (sample-weighted fits" in weighted.to_markdown()
    with pytest.raises(FitError) as e:
        bl.compare(campaign_b, ["Rigid"], heldout=["PennerFixed"])
    assert e.value.option == "heldout"
    for bad in (1, 2.5, True):
        with pytest.raises(FitError) as e:
            bl.compare(campaign_b, ["Rigid"], k=bad)
        assert e.value.option == "k"
    one = campaign_b.isel(bounce=slice(0, 40)).assign_coords(setting=("bounce", np.zeros(40, int)))
    with pytest.raises(FitError) as e:  # one launcher setting: no fold of settings can be held out
        bl.compare(one, ["Rigid"], heldout=True)
    assert e.value.option == "heldout" and e.value.hints[0] == bl.errors.Hint("heldout", False)
    for skipped in (bl.compare(one, ["Rigid"], heldout=True, errors="skip"), bl.compare(one, ["Rigid"])):
        assert "one launcher setting only" in skipped.heldout_skipped["Rigid"] and skipped.heldout == {}
        assert np.isnan(skipped.table.loc["Rigid", "heldout_delta"]) and "Rigid" in skipped.results


def test_held_out_errors_is_what_compare_and_assess_report():
    """bouncelab.fitting.assessment.held_out_errors, the public form of the held-out figures, gives compare's."""
    from bouncelab.fitting.assessment import held_out_errors

    data = bl.load_campaign("B", surrogate="published")
    alone = held_out_errors(bl.Rigid, data, k=3, seed=0)
    assert alone.split == "setting" and alone.k == 3 and alone.scores["n"] == data.sizes["bounce"]
    cmp = bl.compare(data, ["Rigid"], k=3, seed=0, heldout=True)
    assert cmp.heldout["Rigid"].scores == alone.scores
    pair = held_out_errors(bl.Rigid, (data.landing.values[:60], data.liftoff.values[:60]), k=4, seed=0)
    assert pair.split == "bounce" and pair.scores["n"] == 60


# ------------------------------------------------------------------------------ one parallel interface: executor=
def _thread_pool():
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(max_workers=2)


def test_compare_bootstrap_and_cross_validate_on_a_thread_pool_equal_serial(campaign_b):
    """Issue 31: executor= takes any concurrent.futures.Executor; the results are the serial ones, bit for bit."""
    data = campaign_b.isel(bounce=slice(0, 300))
    with _thread_pool() as pool:
        laws = ["Rigid", "PennerFixed"]
        pd.testing.assert_frame_equal(bl.compare(data, laws, seed=5, executor=pool).table,
                                      bl.compare(data, laws, seed=5).table, check_exact=True)
        serial = bl.bootstrap(bl.PennerFixed, data, n=6, seed=11)
        pooled = bl.bootstrap(bl.PennerFixed, data, n=6, seed=11, executor=pool)
        pd.testing.assert_frame_equal(pooled.samples, serial.samples, check_exact=True)
        assert not bl.bootstrap(bl.PennerFixed, data, n=6, seed=12, executor=pool).samples.equals(serial.samples)
        pd.testing.assert_frame_equal(bl.cross_validate(bl.Rigid, data, k=3, seed=2, executor=pool).folds,
                                      bl.cross_validate(bl.Rigid, data, k=3, seed=2).folds, check_exact=True)


def test_map_tasks_batches_on_an_executor_and_keeps_the_order():
    """map_tasks sends an Executor a few batches per worker (submit) and returns the results in task order; any
    object with map() works too; anything else is refused."""
    from concurrent.futures import Executor

    from bouncelab.fitting.tasks import BATCHES_PER_WORKER, map_tasks

    class CountingExecutor(Executor):
        def __init__(self):
            self._inner = _thread_pool()
            self._max_workers = 2
            self.submitted = 0

        def submit(self, fn, /, *args, **kwargs):
            self.submitted += 1
            return self._inner.submit(fn, *args, **kwargs)

        def shutdown(self, wait=True, **kwargs):
            self._inner.shutdown(wait=wait)

    with CountingExecutor() as ex:
        out = map_tasks(abs, range(-50, 50), ex)
    assert out == [abs(i) for i in range(-50, 50)]
    assert ex.submitted == 2 * BATCHES_PER_WORKER  # 100 tasks in 8 batches of 13 (the last short)
    assert map_tasks(abs, [], ex) == []

    class Mapper:  # multiprocessing.Pool-like
        def map(self, fn, items):
            return [fn(i) for i in items]

    assert map_tasks(abs, [-1, 2, -3], Mapper()) == [1, 2, 3]
    with pytest.raises(FitError) as e:
        map_tasks(abs, [1], object())
    assert e.value.option == "executor"


@pytest.mark.slow  # worker processes start and compile the laws: 10-30 s
def test_loky_reusable_executor_equals_serial(campaign_b):
    """loky's reusable executor (joblib's, processes): the same bootstrap as serially."""
    loky = pytest.importorskip("joblib.externals.loky", reason="joblib is not installed")
    data = campaign_b.isel(bounce=slice(0, 200))
    serial = bl.bootstrap(bl.Rigid, data, n=6, seed=3)
    pooled = bl.bootstrap(bl.Rigid, data, n=6, seed=3, executor=loky.get_reusable_executor(max_workers=2))
    pd.testing.assert_frame_equal(pooled.samples, serial.samples, check_exact=True)
