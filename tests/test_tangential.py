"""Contact-point velocity v_P = xdot + omega at landing and lift-off (paper: Fig. 7 and Discussion)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
import bouncelab.analysis as analysis
from bouncelab.analysis import tangential_crosstab, tangential_summary, tangential_velocities
from bouncelab.analysis.contact_velocity import NEAR_ZERO_FRACTION, SUMMARY_ROWS
from bouncelab.core.errors import DataError
from bouncelab.data.campaign import make_campaign

# One bounce per behaviour; comments give v_P0 -> v_PF and omega0 -> omegaF.
BOUNCES = [
    # name,               landing,                 liftoff
    ("backspin_slip",     [100.0, -200.0, 50.0],   [80.0, 100.0, 30.0]),    # 150 -> 110, 50 -> 30
    ("topspin_slip",      [50.0, -200.0, -300.0],  [20.0, 100.0, -60.0]),   # -250 -> -40, no spin reversal
    ("reversal_pos_neg",  [100.0, -200.0, 50.0],   [80.0, 100.0, -90.0]),   # 150 -> -10, spin reversal
    ("reversal_neg_pos",  [100.0, -200.0, -250.0], [80.0, 100.0, -60.0]),   # -150 -> 20, no spin reversal
    ("zero_landing",      [100.0, -200.0, -100.0], [80.0, 100.0, 30.0]),    # 0 -> 110, spin reversal
    ("zero_liftoff",      [100.0, -200.0, 50.0],   [80.0, 100.0, -80.0]),   # 150 -> 0, spin reversal
    ("zero_both",         [100.0, -200.0, -100.0], [80.0, 100.0, -80.0]),   # 0 -> 0, no spin reversal
    ("zero_spin",         [100.0, -200.0, 0.0],    [80.0, 100.0, -20.0]),   # 100 -> 60, omega 0 is no reversal
    ("near_zero_liftoff", [100.0, -200.0, 50.0],   [80.0, 100.0, -79.5]),   # 150 -> 0.5, spin reversal
]
NAMES = [b[0] for b in BOUNCES]
LANDING = np.array([b[1] for b in BOUNCES])
LIFTOFF = np.array([b[2] for b in BOUNCES])
VP0 = [150.0, -250.0, 150.0, -150.0, 0.0, 150.0, 0.0, 100.0, 150.0]
VPF = [110.0, -40.0, -10.0, 20.0, 110.0, 0.0, 0.0, 60.0, 0.5]
MEAN_ABS_VP0 = 1100.0 / 9.0

EXPECTED = {
    "n_bounces": 9,
    "slip": 4,  # backspin_slip, topspin_slip, zero_spin, near_zero_liftoff
    "roll": 5,
    "landing_positive": 5,
    "landing_negative": 2,
    "landing_zero": 2,
    "liftoff_positive": 5,
    "liftoff_negative": 2,
    "liftoff_zero": 2,
    "backspin_slip": 3,
    "topspin_slip": 1,
    "vp_reversal": 2,
    "vp_reversal_pos_to_neg": 1,
    "vp_reversal_neg_to_pos": 1,
    "vp_zero": 3,
    "spin_reversal": 4,  # reversal_pos_neg, zero_landing, zero_liftoff, near_zero_liftoff
    "near_zero_liftoff": 3,  # |v_PF| <= 2 % of 1100/9 = 2.44: zero_liftoff, zero_both, near_zero_liftoff
}


@pytest.fixture
def campaign():
    return make_campaign(LANDING, LIFTOFF, setting=NAMES, campaign="hand")


def test_velocities_per_bounce(campaign):
    tv = tangential_velocities(campaign)
    assert tv.sizes == {"bounce": 9}
    np.testing.assert_array_equal(tv["vp_landing"].values, VP0)
    np.testing.assert_array_equal(tv["vp_liftoff"].values, VPF)
    assert tv["sign_landing"].values.tolist() == [1, -1, 1, -1, 0, 1, 0, 1, 1]
    assert tv["sign_liftoff"].values.tolist() == [1, -1, -1, 1, 1, 0, 0, 1, 1]
    assert tv["slip_roll"].values.tolist() == ["slip", "slip", "roll", "roll", "roll", "roll", "roll", "slip", "slip"]
    np.testing.assert_array_equal(tv["slip_roll"].values, bl.classify_slip_roll(LANDING, LIFTOFF))
    assert tv["vp_reversal"].values.tolist() == [False, False, True, True, False, False, False, False, False]
    assert tv["spin_reversal"].values.tolist() == [False, False, True, False, True, True, False, False, True]
    assert tv["setting"].values.tolist() == NAMES
    assert tv["bounce"].values.tolist() == list(range(9))
    assert tv.attrs["campaign"] == "hand"


def test_velocities_keep_bounce_labels_and_accept_pairs(campaign):
    sub = campaign.isel(bounce=[2, 5, 7])
    tv = tangential_velocities(sub)
    assert tv["bounce"].values.tolist() == [2, 5, 7]
    np.testing.assert_array_equal(tv["vp_liftoff"].values, [-10.0, 0.0, 60.0])
    pair = tangential_velocities((LANDING, LIFTOFF))
    assert "setting" not in pair.coords
    assert pair.attrs == {}
    np.testing.assert_array_equal(pair["vp_landing"].values, VP0)


def test_summary_counts_every_category(campaign):
    summ = tangential_summary(campaign)
    assert summ.index.tolist() == list(SUMMARY_ROWS)
    assert summ["count"].to_dict() == EXPECTED
    assert summ["count"].dtype == np.int64
    np.testing.assert_allclose(summ["fraction"].values, summ["count"].values / 9.0)
    assert summ.loc["near_zero_liftoff", "fraction"] == pytest.approx(3 / 9)
    assert summ.attrs["near_zero"] == pytest.approx(NEAR_ZERO_FRACTION * MEAN_ABS_VP0)
    assert summ.attrs["campaign"] == "hand"


def test_summary_identities(campaign):
    c = tangential_summary(campaign)["count"]
    assert c["slip"] == c["backspin_slip"] + c["topspin_slip"]
    assert c["roll"] == c["vp_reversal"] + c["vp_zero"]
    assert c["vp_reversal"] == c["vp_reversal_pos_to_neg"] + c["vp_reversal_neg_to_pos"]


@pytest.mark.parametrize(("near_zero", "expected"), [
    (0.0, 2),     # exact zeros only (inclusive threshold)
    (0.5, 3),     # |v_PF| = 0.5 is at the threshold: counted
    (0.49, 2),
    (10.0, 4),    # adds the -10
    (1000.0, 9),
])
def test_near_zero_threshold(campaign, near_zero, expected):
    summ = tangential_summary(campaign, near_zero=near_zero)
    assert summ.loc["near_zero_liftoff", "count"] == expected
    assert summ.attrs["near_zero"] == near_zero
    assert summ.attrs["near_zero_rule"] == "given"


def test_default_threshold_scales_with_the_campaign():
    # scaling every velocity by 10 scales the default threshold by 10, so the count is unchanged
    summ = tangential_summary((10.0 * LANDING, 10.0 * LIFTOFF))
    assert summ.attrs["near_zero"] == pytest.approx(10.0 * NEAR_ZERO_FRACTION * MEAN_ABS_VP0)
    assert summ.loc["near_zero_liftoff", "count"] == 3
    assert "campaign" not in summ.attrs


@pytest.mark.parametrize("near_zero", [-1.0, float("nan"), float("inf"), "small"])
def test_bad_near_zero(campaign, near_zero):
    with pytest.raises(DataError) as err:
        tangential_summary(campaign, near_zero=near_zero)
    assert err.value.option == "near_zero"


def test_bad_data():
    with pytest.raises(DataError) as err:  # a file name, not a campaign Dataset
        tangential_velocities("data.csv")
    assert err.value.option == "data"
    with pytest.raises(DataError) as err:  # a landing moving up
        tangential_summary(([[1.0, 5.0, 0.0]], [[1.0, 5.0, 0.0]]))
    assert (err.value.column, err.value.row) == ("landing.ydot", 1)
    with pytest.raises(DataError):
        tangential_crosstab((LANDING, LIFTOFF[:3]))


def test_crosstab(campaign):
    table = tangential_crosstab(campaign)
    expected = pd.DataFrame(
        [[1, 0, 1, 2], [0, 1, 1, 2], [1, 1, 3, 5], [2, 2, 5, 9]],
        index=pd.Index(["negative", "zero", "positive", "total"], name="sign_vp_landing"),
        columns=pd.Index(["negative", "zero", "positive", "total"], name="sign_vp_liftoff"),
    )
    pd.testing.assert_frame_equal(table, expected, check_dtype=False)
    assert (table.dtypes == np.int64).all()
    bare = tangential_crosstab(campaign.isel(bounce=[0, 7]), margins=False)
    assert bare.shape == (3, 3)  # all signs present even when unseen
    assert bare.loc["positive", "positive"] == 2
    assert bare.values.sum() == 2


@pytest.mark.parametrize("name", ["A", "B"])
def test_embedded_campaigns(name):
    ds = bl.load_campaign(name)
    n = ds.sizes["bounce"]
    tv = tangential_velocities(ds)
    assert tv.sizes == {"bounce": n}
    np.testing.assert_array_equal(tv["setting"].values, ds["setting"].values)
    c = tangential_summary(ds)["count"]
    assert c["n_bounces"] == n
    assert c["slip"] + c["roll"] == n
    assert c["landing_positive"] + c["landing_negative"] + c["landing_zero"] == n
    assert c["liftoff_positive"] + c["liftoff_negative"] + c["liftoff_zero"] == n
    assert c["slip"] == c["backspin_slip"] + c["topspin_slip"]
    assert c["roll"] == c["vp_reversal"] + c["vp_zero"]
    assert 0 <= c["near_zero_liftoff"] < c["liftoff_positive"] + c["liftoff_negative"]
    table = tangential_crosstab(ds)
    assert table.loc["total", "total"] == n
    assert table.loc["positive", "negative"] == c["vp_reversal_pos_to_neg"]
    assert table.loc["negative", "negative"] == c["topspin_slip"]
    # the paper: rolling bounces are the majority of reversals, from v_P0 > 0 to v_PF < 0
    assert c["vp_reversal_pos_to_neg"] > c["vp_reversal_neg_to_pos"]


def test_analysis_package_exports():
    expected = {
        "simulate_tracked_bounce", "measure_bounce", "estimate_velocity", "estimate_spin", "detect_contact",
        "interval_coverage", "VelocityEstimate", "SpinEstimate", "ContactDetection", "repeatability",
        "repeatability_summary", "tangential_velocities", "tangential_summary", "tangential_crosstab",
        "impulse_lever_arm", "lever_arm_summary",
    }
    assert set(analysis.__all__) == expected
    for name in analysis.__all__:
        assert callable(getattr(analysis, name)), name
