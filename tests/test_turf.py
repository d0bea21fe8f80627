"""TurfContact: physics checks, integrator convergence, agreement with solve_ivp, per-bounce parameters."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.laws._contact_kernels import turf_integrate
from tests.conftest import contact_landings, kinetic_energy

BASE = {"log10_k": 6.8, "c": 1.0, "e_y": 0.3, "mu": 0.6, "log10_kt": 6.0, "lam": 3.0}
LAWS = [bl.TurfContact(**BASE), bl.TurfContact(**{**BASE, "c": 2.5, "e_y": 0.15, "mu": 1.0, "lam": 10.0}),
        bl.TurfContact(**{**BASE, "log10_k": 6.0, "c": 0.3, "mu": 0.3, "log10_kt": 5.0, "lam": 0.0})]


def landings(n: int = 200, seed: int = 0) -> np.ndarray:
    return contact_landings(n, seed)


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_no_energy_gain(law):
    p = landings()
    assert np.all(kinetic_energy(law.predict(p, plausible=None)) <= kinetic_energy(p) * (1 + 1e-9))


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_mirror_symmetry(law):
    p = landings(seed=1)
    m = p * [-1, 1, -1]
    np.testing.assert_allclose(law.predict(m, plausible=None), law.predict(p, plausible=None) * [-1, 1, -1],
                               rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(law.regime(m, plausible=None), law.regime(p, plausible=None))


@pytest.mark.parametrize("law", LAWS[:2], ids=str)
def test_continuous_in_landing_state(law):
    vp = np.linspace(-2000, 2000, 2001)
    p = np.column_stack([0.5 * vp, np.full_like(vp, -600.0), 0.5 * vp])
    out = law.predict(p)
    assert len(set(law.regime(p))) >= 2
    assert np.abs(np.diff(out, axis=0)).max() < 6.0  # neighbours 2 radii/s apart


def run(p, theta, nsteps):
    return np.array([turf_integrate(q[0], q[1], q[2], theta, nsteps)[:3] for q in p])


def test_integrator_converges_within_its_stated_tolerance():
    """Halving the step changes lift-off by less than the stated 1e-4 |p0|, and the error falls."""
    rng = np.random.default_rng(2)
    p = landings(60, seed=2)
    lo = np.array([s.bounds[0] for s in bl.TurfContact.parameter_specs])
    hi = np.array([s.bounds[1] for s in bl.TurfContact.parameter_specs])
    norm = np.linalg.norm(p, axis=1)
    for _ in range(4):
        theta = lo + (hi - lo) * rng.random(6)
        theta[2] = max(theta[2], 0.1)
        a, b, c = run(p, theta, 64), run(p, theta, 128), run(p, theta, 512)
        assert (np.abs(a - b).max(axis=1) / norm).max() < 1e-4
        assert (np.abs(b - c).max(axis=1) / norm).max() < 1e-4
        assert np.median(np.abs(b - c)) <= np.median(np.abs(a - c))  # typical error falls with the step


def test_agrees_with_solve_ivp():
    from benchmarks.contact_reference import turf_reference

    p = landings(4, seed=3)
    theta = np.array(list(BASE.values()))
    ref = np.array([turf_reference(q, theta) for q in p])
    err = np.abs(bl.TurfContact(**BASE).predict(p) - ref).max(axis=1) / np.linalg.norm(p, axis=1)
    assert err.max() < 3e-5


def test_restitution_falls_with_impact_speed():
    for law in LAWS[:2]:
        r = law.restitution(np.linspace(50, 1200, 24))
        assert np.all(np.diff(r) < 0)
        assert r[0] > 0.8 and r[-1] < 0.6


def test_scaling_symmetry_leaves_lift_off_unchanged():
    """(k, e_y, k_t, lam) -> (k s^-5/2, s e_y, k_t s^-2, lam / s): same lift-off (why log10_k is held)."""
    p = landings(40, seed=7)
    s = 1.4
    scaled = bl.TurfContact(**{**BASE, "log10_k": BASE["log10_k"] - 2.5 * np.log10(s), "e_y": BASE["e_y"] * s,
                               "log10_kt": BASE["log10_kt"] - 2 * np.log10(s), "lam": BASE["lam"] / s})
    err = np.abs(scaled.predict(p) - LAWS[0].predict(p)).max(axis=1) / np.linalg.norm(p, axis=1)
    assert err.max() < 1e-4
    assert not bl.TurfContact.parameter_specs[0].vary
    assert bl.TurfContact().log10_k == 6.8


def test_elastic_limit_keeps_energy():
    law = bl.TurfContact(log10_k=6.8, c=0.0, e_y=10.0, mu=0.0, log10_kt=6.0, lam=0.0)
    p = landings(50, seed=4)
    np.testing.assert_allclose(law.predict(p, plausible=None), p * [1, -1, 1], rtol=1e-6)


def test_ploughing_moves_the_lever_arm_below_rigid():
    p = np.array([[1200.0, -700.0, -200.0], [900.0, -500.0, 100.0]])  # slipping forward throughout
    no_plough = bl.TurfContact(**{**BASE, "lam": 0.0, "mu": 0.2})
    out = no_plough.predict(p)
    np.testing.assert_allclose((out[:, 2] - p[:, 2]) / (out[:, 0] - p[:, 0]), 2.5, rtol=1e-9)
    plough = bl.TurfContact(**{**BASE, "lam": 10.0, "mu": 0.2})
    out = plough.predict(p)
    lever = (out[:, 2] - p[:, 2]) / (out[:, 0] - p[:, 0])
    assert np.all((lever > 0) & (lever < 2.0))


def test_gripping_landings_reverse_vp():
    law = LAWS[0]
    vp0 = np.linspace(50, 600, 12)
    p = np.column_stack([vp0, np.full(12, -800.0), np.zeros(12)])
    out = law.predict(p, plausible=None)
    assert np.all(out[:, 0] + out[:, 2] < 0)
    assert set(law.regime(p, plausible=None)) == {"reversed"}
    assert law.regime([2500.0, -200.0, 0.0], plausible=None) == "slip"


def test_predict_varying_matches_one_law_per_row():
    p = landings(30, seed=5)
    rng = np.random.default_rng(5)
    rows = np.array(list(BASE.values())) * (1 + 0.1 * rng.standard_normal((30, 6)))
    out, codes = bl.TurfContact.predict_varying(p, rows, codes=True)
    names = [s.name for s in bl.TurfContact.parameter_specs]
    for i in range(0, 30, 7):
        law = bl.TurfContact(**dict(zip(names, rows[i], strict=True)))
        np.testing.assert_array_equal(out[i], law.predict(p[i:i + 1])[0])
        assert law.regimes[codes[i]] == law.regime(p[i])
    by_name = bl.TurfContact.predict_varying(p, {n: rows[:, j] for j, n in enumerate(names)})
    np.testing.assert_array_equal(by_name, out)
    np.testing.assert_array_equal(bl.TurfContact.predict_varying(p, rows[0]),
                                  bl.TurfContact(**dict(zip(names, rows[0], strict=True))).predict(p))


def test_predict_varying_refuses_bad_rows():
    p = landings(3)
    row = np.array(list(BASE.values()))
    with pytest.raises(bl.ParameterError) as err:  # 2 rows for 3 landings
        bl.TurfContact.predict_varying(p, np.tile(row, (2, 1)))
    assert (err.value.law, err.value.parameter) == ("TurfContact", "params")
    bad = np.tile(row, (3, 1))
    bad[1, 3] = -0.1
    with pytest.raises(bl.ParameterError, match="of row 2") as err:  # the row named
        bl.TurfContact.predict_varying(p, bad)
    assert (err.value.parameter, err.value.value) == ("mu", -0.1)
    with pytest.raises(bl.DataError):
        bl.TurfContact.predict_varying([[1.0, 5.0, 0.0]], row)


def test_fit_json_and_summary(tmp_path):
    law = LAWS[0]
    p = landings(40, seed=6)
    ds = bl.make_campaign(p, law.predict(p, plausible=None))
    res = bl.fit(bl.TurfContact, ds, maxeval=60, local_algorithm=None, seed=0)
    assert np.isfinite(res.delta)
    path = tmp_path / "turf.json"
    res.model.to_json(path)
    assert bl.load_law(path) == res.model
    assert "restitution of vertical landings" in str(res)


@pytest.mark.slow
def test_parameter_recovery_with_one_percent_noise():
    truth = bl.TurfContact(**BASE)
    p = landings(500, seed=11)
    rng = np.random.default_rng(11)
    pf = truth.predict(p, plausible=None)
    pf = pf + 0.01 * np.abs(pf) * rng.standard_normal(pf.shape)
    res = bl.fit(bl.TurfContact, bl.make_campaign(p, pf), seed=0)
    got = res.model.parameters
    # the noise-free law scores delta ~ 0.01 on these data; the fit must do as well and find the parameters
    assert res.delta <= 1.02 * bl.delta(p, pf, truth.predict(p, plausible=None))
    assert got["log10_k"] == BASE["log10_k"]  # held: the scale bounce data cannot see
    for name, tol in {"c": 0.1, "e_y": 0.1, "mu": 0.05, "log10_kt": 0.05, "lam": 0.2}.items():
        assert got[name] == pytest.approx(BASE[name], rel=tol), name


def test_fit_objective_shared_between_threads_is_thread_count_independent():
    p = landings(300, seed=8)
    pf = LAWS[0].predict(p, plausible=None)
    inv = 1.0 / np.linalg.norm(p, axis=1)
    theta = np.array(list(LAWS[1].flat_parameters().values()))
    before = bl.laws.num_threads()
    try:
        values = []
        for threads in (1, 2, 3):
            bl.laws.set_num_threads(threads)
            values.append(LAWS[0]._error_function(p, pf, inv)(theta))
    finally:
        bl.laws.set_num_threads(before)
    assert values[0] == values[1] == values[2]
    direct = np.abs(pf - LAWS[1].predict(p, plausible=None))
    assert values[0][0] == pytest.approx(float((np.linalg.norm(direct, axis=1) * inv).sum()), rel=1e-9)


def test_predict_varying_large_calls_do_not_depend_on_threads():
    from bouncelab.core._parallel import PARALLEL_MIN

    n = PARALLEL_MIN + 1000
    rng = np.random.default_rng(9)
    p = np.column_stack([rng.uniform(0, 1000, n), rng.uniform(-900, -100, n), rng.uniform(-300, 900, n)])
    rows = np.array(list(BASE.values())) * (1 + 0.05 * rng.standard_normal((n, 6)))
    before = bl.laws.num_threads()
    try:
        bl.laws.set_num_threads(1)
        one = bl.TurfContact.predict_varying(p, rows)
        bl.laws.set_num_threads(2)
        two = bl.TurfContact.predict_varying(p, rows)
    finally:
        bl.laws.set_num_threads(before)
    np.testing.assert_array_equal(one, two)
    np.testing.assert_array_equal(one[-5:], bl.TurfContact.predict_varying(p[-5:], rows[-5:]))


def test_stable_and_dissipative_over_the_whole_search_box():
    """Strong damping and ploughing (c, lam at their upper bounds) once made explicit RK4 blow up."""
    rng = np.random.default_rng(10)
    specs = bl.TurfContact.parameter_specs
    p = landings(20, seed=10) * [1.8, 2.0, 1.7]  # up to the paper's fastest landings
    corners = [[6.8, 5.0, 2.0, 1.5, 9.0, 20.0], [6.8, 5.0, 0.05, 0.0, 4.5, 20.0]]
    for theta in [*corners, *(rng.uniform([s.bounds[0] for s in specs], [s.bounds[1] for s in specs])
                             for _ in range(6))]:
        law = bl.TurfContact(**dict(zip([s.name for s in specs], theta, strict=True)))
        out = law.predict(p)
        assert np.all(np.isfinite(out))
        assert np.all(kinetic_energy(out) <= kinetic_energy(p) * (1 + 1e-9))


def test_restitution_refuses_speeds_that_are_not_positive_numbers():
    for bad in ("fast", [0.0], [-300.0], [float("nan")]):
        with pytest.raises(bl.DataError) as err:
            LAWS[0].restitution(bad)
        assert err.value.option == "speed"
