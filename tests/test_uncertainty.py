"""Bootstrap parameter uncertainty."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import FitError, Hint


@pytest.fixture(scope="module")
def synthetic():
    """Bounces from a known Rigid law, 40 settings x 5 repeats, 3 % noise."""
    rng = np.random.default_rng(3)
    centres = np.column_stack([rng.uniform(200, 2000, 40), -rng.uniform(200, 1500, 40), rng.uniform(-300, 1500, 40)])
    p0 = np.repeat(centres, 5, axis=0) * (1 + 0.02 * rng.standard_normal((200, 3)))
    truth = bl.Rigid(r=0.45, mu=0.3)
    pf = truth.predict(p0) + 0.03 * np.linalg.norm(p0, axis=1, keepdims=True) * rng.standard_normal((200, 3))
    ds = bl.make_campaign(p0, pf, setting=np.repeat(np.arange(40), 5))
    return truth, ds


def test_bootstrap_covers_truth_and_is_repeatable(synthetic):
    truth, ds = synthetic
    boot = bl.bootstrap(bl.Rigid, ds, n=60, seed=1)
    summary = boot.summary()
    assert list(summary.index) == ["r", "mu"] and len(boot.samples) == 60
    for name in ("r", "mu"):
        lo, hi = summary.loc[name, ["ci_low", "ci_high"]]
        assert lo <= getattr(truth, name) <= hi
        assert 0 < summary.loc[name, "std_error"] < 0.05
    assert summary.attrs["by"] == "setting" and summary.attrs["n_resamples"] == 60
    again = bl.bootstrap(bl.Rigid, ds, n=60, seed=1)
    np.testing.assert_array_equal(again.samples.to_numpy(), boot.samples.to_numpy())
    other = bl.bootstrap(bl.Rigid, ds, n=60, seed=2)
    assert not np.array_equal(other.samples.to_numpy(), boot.samples.to_numpy())
    assert "resamples by setting" in repr(boot)


def test_bootstrap_by_bounce_and_fit_options(synthetic):
    _, ds = synthetic
    boot = bl.bootstrap(bl.PennerFixed, (ds.landing.values, ds.liftoff.values), n=10, by="bounce",
                        bounds={"beta_deg": (5.0, 5.0)})
    assert (boot.samples["beta_deg"] == 5.0).all()


def test_settings_resampling_is_wider_than_bounce_resampling_for_clustered_noise():
    """When repeats share a setting-level error, resampling bounces understates the uncertainty."""
    rng = np.random.default_rng(5)
    centres = np.column_stack([rng.uniform(200, 2000, 30), -rng.uniform(200, 1500, 30), rng.uniform(-300, 1500, 30)])
    p0 = np.repeat(centres, 8, axis=0)
    shared = np.repeat(0.06 * rng.standard_normal((30, 3)), 8, axis=0)  # one turf error per setting
    pf = bl.Rigid(r=0.45, mu=0.3).predict(p0) + shared * np.linalg.norm(p0, axis=1, keepdims=True)
    ds = bl.make_campaign(p0, pf, setting=np.repeat(np.arange(30), 8))
    by_setting = bl.bootstrap(bl.Rigid, ds, n=60).summary()
    by_bounce = bl.bootstrap(bl.Rigid, ds, n=60, by="bounce").summary()
    assert by_setting.loc["r", "std_error"] > 1.5 * by_bounce.loc["r", "std_error"]


@pytest.mark.parametrize("kwargs", [{"by": "campaign"}, {"n": 1}, {"level": 1.5}])
def test_bootstrap_errors(synthetic, kwargs):
    _, ds = synthetic
    with pytest.raises(FitError) as e:
        bl.bootstrap(bl.Rigid, ds, **kwargs)
    assert e.value.option == next(iter(kwargs))


def test_bootstrap_needs_settings(synthetic):
    _, ds = synthetic
    with pytest.raises(FitError) as e:
        bl.bootstrap(bl.Rigid, (ds.landing.values, ds.liftoff.values))
    assert e.value.option == "by" and e.value.hints == (Hint("by", "bounce"),)
    assert "infer_settings" in e.value.message  # says how to give the data settings
    with pytest.raises(FitError) as e:
        bl.bootstrap(bl.Rigid, ds, seed=-1)
    assert e.value.option == "seed"
