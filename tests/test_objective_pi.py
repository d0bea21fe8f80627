"""Issue 11 item 7: a fit objective weighting each bounce by its prediction intervals."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import FitError


def two_law_campaign(pi_first: float, pi_second: float) -> tuple:
    """Bounces of two different rigid laws, noise-free, with the given PI half-widths per half."""
    ds = bl.load_campaign("A")
    p0 = ds.landing.values
    half = len(p0) // 2
    laws = bl.Rigid(r=0.5, mu=0.25), bl.Rigid(r=0.3, mu=0.6)
    pf = np.vstack([laws[0].predict(p0[:half]), laws[1].predict(p0[half:])])
    pi = np.vstack([np.full((half, 3), pi_first), np.full((len(p0) - half, 3), pi_second)])
    return bl.make_campaign(p0, pf, liftoff_pi=pi, landing_pi=pi), laws


def test_precise_bounces_dominate_the_fit() -> None:
    plain = []
    for precise in (0, 1):
        widths = (0.01, 100.0) if precise == 0 else (100.0, 0.01)
        ds, laws = two_law_campaign(*widths)
        plain.append(bl.fit(bl.Rigid, ds).model)
        weighted = bl.fit(bl.Rigid, ds, objective="delta_pi").model
        target = laws[precise]  # the law of the precisely measured half
        assert abs(weighted.r - target.r) < 0.01 and abs(weighted.mu - target.mu) < 0.02
    assert plain[0] == plain[1]  # the paper's delta does not see the intervals: one of the two is missed


def test_value_is_the_mean_residual_in_pi_units_and_scale_free() -> None:
    ds = bl.load_campaign("B")
    res = bl.fit(bl.PennerFixed, ds, objective="delta_pi")
    assert res.objective == "delta_pi"
    e = ds.liftoff.values - res.model.predict(ds.landing.values)
    h = np.sqrt((ds.liftoff_pi.values ** 2).sum(axis=1) + (ds.landing_pi.values ** 2).sum(axis=1))
    assert res.objective_value == pytest.approx(np.mean(np.linalg.norm(e, axis=1) / h), rel=1e-9)
    assert res.delta == pytest.approx(bl.delta(ds.landing, ds.liftoff, res.model.predict(ds.landing.values)))
    doubled = ds.assign(liftoff_pi=2 * ds.liftoff_pi, landing_pi=2 * ds.landing_pi)
    res2 = bl.fit(bl.PennerFixed, doubled, objective="delta_pi")
    assert res2.model == res.model  # a common scale of the intervals changes nothing but the value
    assert res2.objective_value == pytest.approx(res.objective_value / 2, rel=1e-12)


def test_pi_weighting_in_a_mapping_and_with_bootstrap_and_cross_validation() -> None:
    ds = bl.load_campaign("A")
    res = bl.fit(bl.Rigid, ds, objective={"delta": 1.0, "omega": 0.5, "weighting": "pi"})
    assert res.objective == "1*delta + 0.5*delta_omega (weighted by prediction intervals)"
    boot = bl.bootstrap(bl.Rigid, ds, n=2, objective="delta_pi", method="structured")
    assert boot.estimate == bl.fit(bl.Rigid, ds, objective="delta_pi", method="structured").model.flat_parameters()
    cv = bl.cross_validate(bl.Rigid, ds, k=2, objective="delta_pi", method="structured")
    assert len(cv.folds) == 2


def test_refused_without_intervals() -> None:
    ds = bl.load_campaign("A")
    for data in ((ds.landing.values, ds.liftoff.values), ds.drop_vars(["liftoff_pi", "landing_pi"])):
        with pytest.raises(FitError) as e:  # the data do not carry intervals
            bl.fit(bl.Rigid, data, objective="delta_pi")
        assert e.value.option == "objective" and "liftoff_pi" in e.value.message
    zero = ds.copy(deep=True)
    zero["liftoff_pi"][4] = 0.0
    zero["landing_pi"][4] = 0.0
    with pytest.raises(FitError) as e:
        bl.fit(bl.Rigid, zero, objective="delta_pi")
    assert e.value.option == "objective" and e.value.message.startswith("bounce 5 ")  # the bounce is named
    for objective in ({"delta": 1.0, "weighting": "variance"}, "delta_sigma"):
        with pytest.raises(FitError) as e:
            bl.fit(bl.Rigid, ds, objective=objective)
        assert e.value.option == "objective"
