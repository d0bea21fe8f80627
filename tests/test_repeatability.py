"""Per-setting means and Student-t confidence intervals (paper: Methods "Repeatability", Appendix Fig. 9)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr
from scipy import stats

import bouncelab as bl
from bouncelab.analysis import repeatability, repeatability_summary
from bouncelab.core.errors import DataError
from bouncelab.data.campaign import make_campaign

# Deviations of the 4 repeats from the setting's centre: mean 0, sum of squares 4+1+0+9 = 14, so
# the sample variance is 14/3 and the std sqrt(14/3) for a unit scale.
DEV = np.array([-2.0, -1.0, 0.0, 3.0])
T975_3 = 3.182446305284263  # Student t, 0.975 quantile, 3 degrees of freedom (tables)

# Spread of each component at landing and at lift-off: lift-off is wider for xdot, equal for
# ydot (lift-off ydot is exactly minus landing ydot plus an offset), narrower for omega.
LAND_SCALE = np.array([1.0, 2.0, 4.0])
LIFT_SCALE = np.array([3.0, 2.0, 1.0])


def _campaign(labels=("b", "a", "c"), *, shuffle=True, with_setting=True):
    """3 settings x 4 repeats; setting i has landing centre [100, -200, 200] * (i + 1)."""
    land, lift, sett = [], [], []
    for i, lab in enumerate(labels):
        c0 = np.array([100.0, -200.0, 200.0]) * (i + 1)
        cf = np.array([60.0, 90.0, -40.0]) * (i + 1)
        for d in DEV:
            p0 = c0 + d * LAND_SCALE
            pf = cf + d * LIFT_SCALE
            pf[1] = cf[1] - d * LAND_SCALE[1]  # same spread as landing ydot, exactly
            land.append(p0)
            lift.append(pf)
            sett.append(lab)
    land, lift, sett = np.array(land), np.array(lift), np.array(sett, dtype=object)
    if shuffle:
        order = np.random.default_rng(3).permutation(len(sett))
        land, lift, sett = land[order], lift[order], sett[order]
    return make_campaign(land, lift, setting=sett if with_setting else None, campaign="hand", surface="test")


def test_mean_std_half_width_by_hand():
    rep = repeatability(_campaign())
    sel = rep.sel(setting="a", state="landing")  # 'a' is the second label: centre [200, -400, 400]
    np.testing.assert_allclose(sel["mean"].values, [200.0, -400.0, 400.0])
    std_unit = np.sqrt(14.0 / 3.0)
    np.testing.assert_allclose(sel["std"].values, std_unit * LAND_SCALE)
    np.testing.assert_allclose(sel["half_width"].values, T975_3 * std_unit * LAND_SCALE / 2.0)
    np.testing.assert_allclose(sel["ci_low"].values, sel["mean"].values - sel["half_width"].values)
    np.testing.assert_allclose(sel["ci_high"].values, sel["mean"].values + sel["half_width"].values)
    lift = rep.sel(setting="c", state="liftoff")
    np.testing.assert_allclose(lift["mean"].values, [180.0, 270.0, -120.0])
    np.testing.assert_allclose(lift["std"].values, std_unit * np.array([3.0, 2.0, 1.0]))


def test_matches_numpy_and_scipy_for_every_cell():
    ds = _campaign()
    rep = repeatability(ds, level=0.9)
    for lab in ("a", "b", "c"):
        members = ds.isel(bounce=np.flatnonzero(ds["setting"].values == lab))
        for state in ("landing", "liftoff"):
            x = members[state].values
            std = x.std(axis=0, ddof=1)
            cell = rep.sel(setting=lab, state=state)
            np.testing.assert_allclose(cell["mean"].values, x.mean(axis=0))
            np.testing.assert_allclose(cell["std"].values, std)
            np.testing.assert_allclose(cell["half_width"].values, stats.t.ppf(0.95, 3) * std / 2.0)


def test_level_scales_half_width_by_the_t_quantile_ratio():
    ds = _campaign()
    r95, r99 = repeatability(ds), repeatability(ds, level=0.99)
    ratio = stats.t.ppf(0.995, 3) / stats.t.ppf(0.975, 3)
    np.testing.assert_allclose(r99["half_width"].values, ratio * r95["half_width"].values)
    np.testing.assert_allclose(r99["mean"].values, r95["mean"].values)
    assert r99.attrs["level"] == 0.99


def test_output_format():
    rep = repeatability(_campaign())
    assert dict(rep.sizes) == {"setting": 3, "state": 2, "component": 3}
    for var in ("mean", "std", "half_width", "ci_low", "ci_high"):
        assert rep[var].dims == ("setting", "state", "component")
    assert rep["n"].dims == ("setting",)
    assert rep["n"].dtype == np.int64
    assert rep["n"].values.tolist() == [4, 4, 4]
    assert rep["state"].values.tolist() == ["landing", "liftoff"]
    assert rep["component"].values.tolist() == ["xdot", "ydot", "omega"]
    assert set(rep.coords) == {"setting", "state", "component"}
    assert set(rep.data_vars) == {"mean", "std", "half_width", "ci_low", "ci_high", "n"}
    assert rep.attrs["level"] == 0.95
    assert rep.attrs["settings_source"] == "data"
    assert rep.attrs["campaign"] == "hand"
    assert rep.attrs["surface"] == "test"


def test_string_settings_are_sorted_labels():
    rep = repeatability(_campaign(("s2", "s1", "s3")))
    assert rep["setting"].values.tolist() == ["s1", "s2", "s3"]
    assert rep["setting"].dtype.kind == "U"
    # 's2' was generated first, so its landing xdot centre is 100
    assert rep["mean"].sel(setting="s2", state="landing", component="xdot") == pytest.approx(100.0)


def test_int_settings_and_the_settings_argument():
    ds = _campaign(shuffle=False)
    ints = np.repeat([30, 10, 20], 4)
    rep = repeatability(ds, settings=ints)  # overrides the string coordinate
    assert rep.attrs["settings_source"] == "argument"
    assert rep["setting"].values.tolist() == [10, 20, 30]
    assert rep["setting"].dtype == np.int64
    assert rep["mean"].sel(setting=30, state="landing", component="xdot") == pytest.approx(100.0)
    from_floats = repeatability(ds, settings=ints.astype(float))
    assert from_floats["setting"].dtype == np.int64
    xr.testing.assert_identical(from_floats, rep)


def test_tuple_input_with_settings():
    ds = _campaign(shuffle=False)
    rep = repeatability((ds["landing"].values, ds["liftoff"].values, np.repeat([1, 2, 3], 4)))
    assert rep.attrs == {"level": 0.95, "settings_source": "data"}
    np.testing.assert_allclose(rep["mean"].sel(setting=1, state="landing").values, [100.0, -200.0, 200.0])


def test_single_bounce_setting_has_nan_interval_and_no_warning():
    ds = _campaign(shuffle=False)
    labels = np.array(["a"] * 4 + ["b"] * 4 + ["c"] * 3 + ["lone"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no "degrees of freedom <= 0" RuntimeWarning
        rep = repeatability(ds, settings=labels)
    lone = rep.sel(setting="lone")
    assert int(lone["n"]) == 1
    np.testing.assert_allclose(lone["mean"].sel(state="landing").values, ds["landing"].values[-1])
    for var in ("std", "half_width", "ci_low", "ci_high"):
        assert np.isnan(lone[var].values).all(), var
    assert np.isfinite(rep["half_width"].sel(setting="c").values).all()
    assert rep["n"].values.tolist() == [4, 4, 3, 1]


def test_inferred_settings_warn_and_say_so():
    ds = _campaign(with_setting=False)
    with pytest.warns(UserWarning, match="inferred"):
        rep = repeatability(ds)
    assert rep.attrs["settings_source"] == "inferred by clustering"
    assert rep["n"].values.tolist() == [4, 4, 4]
    truth = repeatability(_campaign())
    # the clusters are the true settings, so the statistics agree up to the labels' order
    by_xdot = np.argsort(rep["mean"].sel(state="landing", component="xdot").values)
    by_xdot_true = np.argsort(truth["mean"].sel(state="landing", component="xdot").values)
    np.testing.assert_allclose(rep["half_width"].values[by_xdot], truth["half_width"].values[by_xdot_true])


def test_no_settings_and_infer_false_raises():
    ds = _campaign(with_setting=False)
    for data in (ds, (ds["landing"].values, ds["liftoff"].values)):
        with pytest.raises(DataError) as e:
            repeatability(data, infer=False)
        assert (e.value.column, e.value.option) == ("setting", "infer")
        assert [h.option for h in e.value.hints] == ["settings", "infer"] and e.value.hints[1].value is True


@pytest.mark.parametrize("level", [0.0, 1.0, 1.5, -0.1, float("nan"), "high"])
def test_bad_level(level):
    with pytest.raises(DataError) as e:
        repeatability(_campaign(), level=level)
    assert e.value.option == "level"


@pytest.mark.parametrize(("settings", "row"), [
    (np.arange(5), None),  # not one label per bounce
    (np.r_[np.ones(11), np.nan], 12),  # missing
    (["a"] * 11 + [None], 12),
])
def test_bad_settings(settings, row):
    with pytest.raises(DataError) as e:
        repeatability(_campaign(), settings=settings)
    assert (e.value.column, e.value.row) == ("setting", row)


def test_bad_data():
    with pytest.raises(DataError) as e:  # not a campaign Dataset
        repeatability({"landing": [[1.0, -1.0, 0.0]]})
    assert e.value.option == "data"
    with pytest.raises(DataError) as e:
        repeatability(([[1.0, 1.0, 0.0]], [[1.0, 1.0, 0.0]]), settings=[1])
    assert (e.value.column, e.value.row) == ("landing.ydot", 1)
    with pytest.raises(DataError) as e:
        repeatability(_campaign().drop_vars("liftoff"))
    assert e.value.column == "liftoff"


def test_summary_by_hand():
    ds = _campaign(shuffle=False)
    labels = np.array(["a"] * 4 + ["b"] * 4 + ["c"] * 3 + ["lone"])
    rep = repeatability(ds, settings=labels)
    summ = repeatability_summary(rep)
    assert summ.index.tolist() == ["xdot", "ydot", "omega", "all"]
    assert summ["unit"].tolist() == ["radius/s", "radius/s", "rad/s", "mixed"]
    assert summ["n_compared"].tolist() == [3, 3, 3, 9]  # the n=1 setting is not compared
    # lift-off spread is 3x landing for xdot, equal for ydot (a tie is not "wider"), 1/4 for omega
    assert summ["fraction_liftoff_wider"].tolist() == [1.0, 0.0, 0.0, pytest.approx(1 / 3)]
    np.testing.assert_allclose(summ["median_ratio"].values, [3.0, 1.0, 0.25, 1.0])
    hw = rep["half_width"]
    np.testing.assert_allclose(
        summ.loc[["xdot", "ydot", "omega"], "median_half_width_landing"].values,
        [float(hw.sel(state="landing", component=c).median()) for c in ("xdot", "ydot", "omega")],
    )
    # the 4-repeat settings share the half-width T*sqrt(14/3)/2 * scale; the 3-repeat one is larger
    assert summ.loc["xdot", "median_half_width_liftoff"] == pytest.approx(3.0 * T975_3 * np.sqrt(14 / 3) / 2)
    assert np.isnan(summ.loc["all", "median_half_width_landing"])
    assert summ.attrs["level"] == 0.95


def test_summary_rejects_other_input():
    with pytest.raises(DataError) as e:  # not a repeatability() result
        repeatability_summary(_campaign())
    assert (e.value.option, e.value.column) == ("rep", None)
    rep = repeatability(_campaign())
    with pytest.raises(DataError) as e:
        repeatability_summary(rep.assign_coords(state=["in", "out"]))
    assert (e.value.option, e.value.column) == ("rep", "state")


_TURF_B_NARROW = pytest.mark.xfail(strict=True, reason=(
    "a known shortfall of the turf surrogate B (docs/simulation.md, 'do not capture'): its spot-to-spot scatter "
    "widens the lift-off intervals of only 43 % of the settings, against the paper's majority"))


@pytest.mark.parametrize("surrogate", ["published", "turf"])
@pytest.mark.parametrize(("name", "n_settings", "n_bounces"), [("A", 55, 330), ("B", 82, 693)])
def test_embedded_campaigns(name, n_settings, n_bounces, surrogate, request):
    if (name, surrogate) == ("B", "turf"):
        request.applymarker(_TURF_B_NARROW)
    ds = bl.load_campaign(name, surrogate=surrogate)
    rep = repeatability(ds)
    assert dict(rep.sizes) == {"setting": n_settings, "state": 2, "component": 3}
    assert int(rep["n"].sum()) == n_bounces
    assert (rep["n"] >= 2).all()
    assert bool(((rep["ci_low"] <= rep["mean"]) & (rep["mean"] <= rep["ci_high"])).all())
    assert bool((rep["mean"].sel(state="landing", component="ydot") < 0).all())
    summ = repeatability_summary(rep)
    assert summ.loc["all", "n_compared"] == 3 * n_settings
    # the paper's "in the majority of cases" lift-off intervals are wider
    assert summ.loc["all", "fraction_liftoff_wider"] > 0.5


def test_embedded_campaign_inferred_settings():
    ds = bl.load_campaign("A", surrogate="published").drop_vars("setting")
    with pytest.warns(UserWarning, match="55 launcher settings"):
        rep = repeatability(ds)
    assert rep.sizes["setting"] == 55  # infer_settings recovers A's settings exactly (ARI 1.00)
    assert int(rep["n"].sum()) == 330
