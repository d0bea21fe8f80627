"""The impulse diagnostic: lever arm Δω/Δẋ of data and laws."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.analysis import impulse_lever_arm, lever_arm_summary


def landings(n=200, seed=0):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0, 1300, n), rng.uniform(-900, -100, n), rng.uniform(-300, 900, n)])


@pytest.mark.parametrize("law", [bl.Rigid(r=0.5, mu=0.4), bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.4),
                                 bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)], ids=str)
def test_contact_point_laws_sit_at_two_and_a_half(law):
    p = landings()
    ds = impulse_lever_arm((p, law.predict(p)))
    ok = np.isfinite(ds["lever_arm"].values)
    assert ok.sum() > 150
    np.testing.assert_allclose(ds["lever_arm"].values[ok], 2.5, rtol=1e-9)
    np.testing.assert_allclose(ds["centre_fraction"].values[ok], 0.0, atol=1e-9)


def test_impulse_through_centre_has_zero_lever_arm_and_mixtures_interpolate():
    p = landings(50)
    j = -0.3 * np.linalg.norm(p, axis=1)
    centre = p + np.column_stack([j, -1.5 * p[:, 1], 0 * j])      # all through the centre
    half = p + np.column_stack([j, -1.5 * p[:, 1], 1.25 * j])     # half at the contact point
    np.testing.assert_allclose(impulse_lever_arm((p, centre))["lever_arm"], 0.0, atol=1e-12)
    np.testing.assert_allclose(impulse_lever_arm((p, half))["centre_fraction"], 0.5, rtol=1e-12)


def test_small_dxdot_is_undefined():
    p = np.array([[100.0, -500.0, 0.0]])
    pf = np.array([[100.5, 250.0, 3.0]])
    assert np.isnan(impulse_lever_arm((p, pf))["lever_arm"][0])
    assert impulse_lever_arm((p, pf), min_fraction=0.0)["lever_arm"][0] == pytest.approx(6.0)
    with pytest.raises(bl.DataError):
        impulse_lever_arm((p, pf), min_fraction=1.5)


def test_summary_on_campaign_separates_data_from_rigid():
    ds = bl.load_campaign("A")
    table = lever_arm_summary(ds, [bl.Rigid.published("A"), bl.PiecewiseAffine.published("A")])
    assert list(table.index) == ["data", "Rigid", "PiecewiseAffine"]
    assert table.loc["Rigid", "median"] == pytest.approx(2.5)
    assert table.loc["data", "median"] < 2.0
    assert abs(table.loc["PiecewiseAffine", "median"] - table.loc["data", "median"]) < 0.5


def test_plot_lever_arm(tmp_path):
    pytest.importorskip("matplotlib")
    from bouncelab.plots import plot_lever_arm, save_figure

    fig = plot_lever_arm(bl.load_campaign("B"), [bl.Rigid.published("B")])
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels[0].startswith("data (median") and labels[1] == "Rigid (median 2.50)"
    save_figure(fig, tmp_path / "lever.png")
    assert (tmp_path / "lever.png").stat().st_size > 0
