"""CompliantImpact: physics checks, limits, agreement with solve_ivp, protocol."""

from __future__ import annotations

import math

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.laws.compliant import R_MIN, contact_time, restitution_of_damping
from tests.conftest import contact_landings, kinetic_energy

LAWS = [bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5), bl.CompliantImpact(r=0.25, mu=1.0, kappa=0.8),
        bl.CompliantImpact(r=0.9, mu=0.2, kappa=3.0)]


def landings(n: int = 300, seed: int = 0) -> np.ndarray:
    return contact_landings(n, seed)


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_no_energy_gain(law):
    p = landings()
    assert np.all(kinetic_energy(law.predict(p, plausible=None)) <= kinetic_energy(p) * (1 + 1e-12))


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_mirror_symmetry(law):
    p = landings(seed=1)
    m = p * [-1, 1, -1]
    np.testing.assert_allclose(law.predict(m, plausible=None), law.predict(p, plausible=None) * [-1, 1, -1],
                               rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(law.regime(m, plausible=None), law.regime(p, plausible=None))


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_normal_restitution_exact_and_homogeneous(law):
    p = landings(seed=2)
    out = law.predict(p, plausible=None)
    np.testing.assert_allclose(out[:, 1], -law.r * p[:, 1], rtol=1e-14)
    np.testing.assert_allclose(law.predict(3.0 * p, plausible=None), 3.0 * out, rtol=1e-9, atol=1e-7)


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_continuous_in_landing_state(law):
    # a line of landings crossing every regime: neighbours 1 radius/s apart differ by O(1)
    vp = np.linspace(-3000, 3000, 6001)
    p = np.column_stack([0.5 * vp, np.full_like(vp, -600.0), 0.5 * vp])
    out = law.predict(p)
    assert len(set(law.regime(p))) >= 2
    assert np.abs(np.diff(out, axis=0)).max() < 5.0


def test_restitution_of_damping_and_its_range():
    assert restitution_of_damping(0.0) == pytest.approx(1.0)
    assert restitution_of_damping(0.999) == pytest.approx(math.exp(-2), abs=2e-3)
    z = np.linspace(0, 0.99, 50)
    assert np.all(np.diff([restitution_of_damping(x) for x in z]) < 0)
    assert contact_time(1.0) == pytest.approx(math.pi)
    with pytest.raises(bl.ParameterError):
        bl.CompliantImpact(r=R_MIN / 2, mu=0.4, kappa=1.0)


def test_large_kappa_gives_rigid():
    p = landings(500, seed=3)
    rigid = bl.Rigid(r=0.5, mu=0.4).predict(p, plausible=None)
    err = [np.abs(bl.CompliantImpact(r=0.5, mu=0.4, kappa=k).predict(p, plausible=None) - rigid).max(axis=1)
           / np.linalg.norm(p, axis=1) for k in (10.0, 40.0)]
    assert err[1].max() < err[0].max() / 3  # converges to Rigid as the tangential spring stiffens
    assert err[1].max() < 3e-3


def test_infinite_friction_gives_walton():
    r, kappa = 0.5, 1.2
    et = -math.cos(kappa * contact_time(r))
    assert 0 < et < 1
    p = landings(200, seed=4)
    walton = bl.TangentialRestitution(r=r, mu=1e6, e_t=et).predict(p, plausible=None)
    err = [np.abs(bl.CompliantImpact(r=r, mu=mu, kappa=kappa).predict(p, plausible=None) - walton).max()
           / np.abs(p).max() for mu in (1e2, 1e4)]
    assert err[1] < err[0] / 10  # the slider slips only ever later, as the cap mu N grows
    assert err[1] < 2e-5


def test_frictionless_keeps_tangential_motion():
    p = landings(100, seed=5)
    out = bl.CompliantImpact(r=0.6, mu=0.0, kappa=1.0).predict(p, plausible=None)
    np.testing.assert_array_equal(out[:, [0, 2]], p[:, [0, 2]])


def test_gripping_landings_reverse_vp_and_lift_off_slipping():
    law = bl.CompliantImpact(r=0.5, mu=0.8, kappa=1.2)  # kappa t_c between pi/2 and pi
    vp0 = np.linspace(50, 800, 20)
    p = np.column_stack([vp0, np.full(20, -800.0), np.zeros(20)])
    out = law.predict(p)
    vpf = out[:, 0] + out[:, 2]
    assert np.all(vpf < 0)
    assert set(law.regime(p)) == {"reversed"}
    # a fast-slipping landing keeps its sign and slips throughout, as in the rigid law
    fast = law.predict([[3000.0, -300.0, 0.0]])
    assert fast[0, 0] + fast[0, 2] > 0 and law.regime([3000.0, -300.0, 0.0]) == "slip"


def test_agrees_with_solve_ivp():
    from benchmarks.contact_reference import compliant_reference

    rng = np.random.default_rng(1)  # the whole of the paper's Table 1, where a grazing restick once went wrong
    p = np.column_stack([rng.uniform(1, 2300, 60), -rng.uniform(90, 1900, 60), rng.uniform(-410, 1700, 60)])
    for law in [LAWS[1], bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)]:
        ref = np.array([compliant_reference(q, law.r, law.mu, law.kappa, rtol=1e-11, atol=1e-11) for q in p])
        err = np.abs(law.predict(p, plausible=None) - ref).max(axis=1) / np.linalg.norm(p, axis=1)
        assert err.max() < 1e-8


def test_fit_compare_json_roundtrip(tmp_path):
    law = LAWS[0]
    p = landings(120, seed=7)
    ds = bl.make_campaign(p, law.predict(p, plausible=None))
    res = bl.fit(bl.CompliantImpact, ds, maxeval=300, seed=0)
    assert res.delta < 0.05
    path = tmp_path / "law.json"
    res.model.to_json(path)
    assert bl.load_law(path) == res.model
    assert "CompliantImpact" in str(res)


@pytest.mark.slow
def test_parameter_recovery_with_one_percent_noise():
    truth = bl.CompliantImpact(r=0.5, mu=0.45, kappa=1.3)
    p = landings(500, seed=11)
    rng = np.random.default_rng(11)
    pf = truth.predict(p, plausible=None)
    pf = pf + 0.01 * np.abs(pf) * rng.standard_normal(pf.shape)
    res = bl.fit(bl.CompliantImpact, bl.make_campaign(p, pf), seed=0)
    got = res.model.parameters
    assert got["r"] == pytest.approx(0.5, rel=0.02)
    assert got["mu"] == pytest.approx(0.45, rel=0.05)
    assert got["kappa"] == pytest.approx(1.3, rel=0.05)
