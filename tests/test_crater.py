"""CraterContact: physics checks, integrator convergence, limits, per-bounce parameters, fitting."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.laws._contact_kernels import CRATER_STEPS, crater_integrate
from tests.conftest import contact_landings, kinetic_energy

BASE = {"r0": 0.6, "v_r": 2000.0, "mu_k": 0.15, "mu_s": 1.0, "v_s": 150.0, "lam": 0.25, "kappa": 0.1,
        "e_t": 0.2, "beta0": 5.0, "beta_n": 4.0, "beta_t": 3.0}
SPECS = bl.CraterContact.parameter_specs
LO = np.array([s.bounds[0] for s in SPECS])
HI = np.array([s.bounds[1] for s in SPECS])
LAWS = [bl.CraterContact(**BASE),
        bl.CraterContact(**{**BASE, "r0": 1.0, "v_r": 1e9, "lam": 0.0, "e_t": 1.0, "mu_s": 2.0, "v_s": 5.0}),
        bl.CraterContact(**{**BASE, "kappa": 1.0, "lam": 1.0, "mu_s": 0.3, "mu_k": 0.8, "beta_t": 30.0})]


def random_laws(n: int, seed: int) -> list[bl.CraterContact]:
    rng = np.random.default_rng(seed)
    return [bl.CraterContact(**dict(zip([s.name for s in SPECS], LO + (HI - LO) * rng.random(len(SPECS)),
                                        strict=True))) for _ in range(n)]


@pytest.mark.parametrize("law", LAWS + random_laws(20, 0), ids=str)
def test_no_energy_gain(law):
    p = contact_landings(400, seed=1)
    assert np.all(kinetic_energy(law.predict(p, plausible=None)) <= kinetic_energy(p) * (1 + 1e-12))


def test_elastic_frictionless_limit_keeps_energy():
    law = bl.CraterContact(**{**BASE, "r0": 1.0, "v_r": 1e9, "mu_k": 0.0, "mu_s": 0.0, "lam": 0.0, "e_t": 0.0})
    p = contact_landings(200, seed=2)
    # v_r = 1e9 radii/s leaves r = 1 - |v_n| / 1e9, a relative loss of about 2e-6
    np.testing.assert_allclose(kinetic_energy(law.predict(p, plausible=None)), kinetic_energy(p), rtol=1e-5)


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_mirror_symmetry(law):
    p = contact_landings(300, seed=3)
    m = p * [-1, 1, -1]
    np.testing.assert_allclose(law.predict(m, plausible=None), law.predict(p, plausible=None) * [-1, 1, -1],
                               rtol=1e-12, atol=1e-9)
    np.testing.assert_array_equal(law.regime(m, plausible=None), law.regime(p, plausible=None))


@pytest.mark.parametrize("law", LAWS, ids=str)
def test_continuous_through_stick_and_at_zero_xdot(law):
    # across the slip/grip threshold: landings 1 radius/s apart in v_P
    w = np.linspace(-1200.0, 1500.0, 2701)
    p = np.column_stack([np.full_like(w, 600.0), np.full_like(w, -700.0), w])
    out = law.predict(p)
    if law.kappa < 1:  # at kappa = 1 ploughing acts at the contact point and never unsticks it: grip only
        assert {"slip", "grip"} <= set(law.regime(p))
    assert np.abs(np.diff(out, axis=0)).max() < 25.0
    # across xdot0 = 0, where the crater wall's tilt fades out
    x = np.linspace(-100.0, 100.0, 2001)
    q = np.column_stack([x, np.full_like(x, -700.0), np.full_like(x, 200.0)])
    assert np.abs(np.diff(law.predict(q), axis=0)).max() < 5.0


def test_velocity_weakening_sharpens_the_slip_grip_transition():
    """With mu_s > mu_k the lift-off v_P climbs steeply out of the grip regime; with mu_s = mu_k at slope 1."""
    w = np.linspace(-600.0, 1500.0, 4201)
    p = np.column_stack([np.full_like(w, 600.0), np.full_like(w, -700.0), w])
    flat = {**BASE, "lam": 0.0, "e_t": 0.0, "beta0": 0.0, "beta_n": 0.0, "beta_t": 0.0}
    slopes = {}
    for mu_s in (0.15, 1.0):
        law = bl.CraterContact(**{**flat, "mu_s": mu_s})
        out = law.predict(p)
        vp = out[:, 0] + out[:, 2]
        slip = np.asarray(law.regime(p)) == "slip"
        first = np.flatnonzero(slip)[0]
        slopes[mu_s] = (vp[first + 5] - vp[first]) / (w[first + 5] - w[first])
    assert slopes[0.15] == pytest.approx(1.0, rel=1e-3)
    assert slopes[1.0] > 4.0


def test_rigid_and_penner_limits():
    """No tilt, ploughing, recoil or weakening, constant restitution: Rigid; with a fixed tilt: PennerFixed."""
    p = contact_landings(500, seed=4)
    p = p[np.abs(p[:, 0]) > 60.0]  # beyond the tilt's fade
    rigid = {**BASE, "v_r": 1e9, "lam": 0.0, "e_t": 0.0, "mu_s": BASE["mu_k"], "beta0": 0.0, "beta_n": 0.0,
             "beta_t": 0.0}
    law = bl.CraterContact(**rigid)
    np.testing.assert_allclose(law.predict(p, plausible=None), bl.Rigid(r=0.6, mu=0.15).predict(p, plausible=None),
                               rtol=1e-5, atol=1e-3)
    tilted = bl.CraterContact(**{**rigid, "beta0": 12.0})
    penner = bl.PennerFixed(r=0.6, mu=0.15, beta_deg=12.0, fade_xdot=50.0)
    np.testing.assert_allclose(tilted.predict(p, plausible=None), penner.predict(p, plausible=None), rtol=1e-5,
                               atol=1e-3)


def test_restitution_falls_with_normal_speed():
    law = LAWS[0]
    r = law.restitution([100.0, 500.0, 1500.0])
    np.testing.assert_allclose(r, 0.6 / (1 + np.array([100.0, 500.0, 1500.0]) / 2000.0), rtol=1e-9)


def test_bristle_recoil_is_walton_for_a_contact_that_sticks_at_once():
    """Without ploughing or tilt, a contact sticking after normal impulse p* leaves with v_P = -e_t v_P0 (1 - p*/P)."""
    flat = {**BASE, "lam": 0.0, "mu_s": BASE["mu_k"], "beta0": 0.0, "beta_n": 0.0, "beta_t": 0.0, "v_r": 1e9}
    law = bl.CraterContact(**flat)
    p = np.array([[300.0, -800.0, -250.0], [300.0, -800.0, -100.0], [300.0, -800.0, 0.0]])
    out = law.predict(p)
    vp0 = p[:, 0] + p[:, 2]
    total = 1.6 * 800.0
    pstar = np.abs(vp0) / (3.5 * 0.15)
    np.testing.assert_allclose(out[:, 0] + out[:, 2], -0.2 * vp0 * (1 - pstar / total), rtol=1e-6, atol=1e-6)
    assert list(law.regime(p)) == ["grip"] * 3
    np.testing.assert_allclose((5 * out[:, 0] - 2 * out[:, 2]), 5 * p[:, 0] - 2 * p[:, 2], rtol=1e-9)


def test_every_regime_occurs():
    law = bl.CraterContact(**{**BASE, "kappa": 0.0, "lam": 1.0, "mu_s": 0.05, "mu_k": 0.05})
    p = np.array([[828.0, -802.0, 124.0], [948.0, -906.0, 20.0], [789.0, -346.0, -585.0]])
    # the third slips forward, then strong ploughing slows the centre until the contact point slips back
    assert list(law.regime(p)) == ["slip", "grip", "reversed"]


def test_integrator_converges_within_its_stated_tolerance():
    """48 steps are within the stated 1e-4 ||p0|| of 1536, in the same regime, and the error falls at fourth order."""
    rng = np.random.default_rng(5)
    p = contact_landings(300, seed=5)
    norm = np.linalg.norm(p, axis=1)
    errs = {48: [], 96: []}
    for i in range(len(p)):
        theta = np.append(LO + (HI - LO) * rng.random(len(SPECS)), 50.0)
        ref = np.array(crater_integrate(*p[i], theta, 1536)[:3])
        for n in errs:
            got = crater_integrate(*p[i], theta, n)
            assert got[3] == crater_integrate(*p[i], theta, 1536)[3]
            errs[n].append(np.abs(np.array(got[:3]) - ref).max() / norm[i])
    e48, e96 = np.array(errs[48]), np.array(errs[96])
    assert CRATER_STEPS == 48
    assert e48.max() < 1e-4
    assert np.median(e96[e48 > 1e-9] / e48[e48 > 1e-9]) < 1 / 8


def test_predict_varying_matches_one_law_per_row_and_refuses_bad_rows():
    p = contact_landings(50, seed=6)
    laws = random_laws(50, 7)
    rows = np.array([list(law.flat_parameters().values()) for law in laws])
    out, codes = bl.CraterContact.predict_varying(p, rows, codes=True)
    for i, law in enumerate(laws):
        np.testing.assert_array_equal(out[i], law.predict(p[i : i + 1], plausible=None)[0])
        assert law.regimes[codes[i]] == law.regime(p[i : i + 1], plausible=None)[0]
    bad = rows.copy()
    bad[3, 0] = 1.5
    with pytest.raises(bl.ParameterError) as err:
        bl.CraterContact.predict_varying(p, bad)
    assert (err.value.parameter, err.value.value) == ("r0", 1.5) and "row 4" in str(err.value)
    # on the class, the options' defaults: the same as a law with the default fade
    np.testing.assert_array_equal(bl.laws.predict_per_bounce(bl.CraterContact, p, rows), out)


def test_simulated_turf_uses_each_spot_s_parameters():
    from bouncelab.simulation import LogNormal, Turf

    turf = Turf(LAWS[0], {"r0": LogNormal(0.2), "lam": LogNormal(0.3)})
    p = contact_landings(40, seed=8)
    theta = turf.spot_parameters(np.random.default_rng(0).standard_normal((len(p), len(SPECS))))
    assert np.unique(theta[:, 0]).size == len(p)  # every spot its own restitution
    out, _ = turf.liftoff(p, theta)
    for i in range(len(p)):
        law = LAWS[0].replace(**dict(zip([s.name for s in SPECS], theta[i], strict=True)))
        np.testing.assert_array_equal(out[i], law.predict(p[i : i + 1])[0])


@pytest.mark.parametrize("value", [0.0, -5.0, "fast", "20", True, None, float("nan")])
def test_fade_option_is_validated(value):
    with pytest.raises(bl.ParameterError) as err:
        bl.CraterContact(**BASE, fade_xdot=value)
    assert (err.value.law, err.value.parameter) == ("CraterContact", "fade_xdot") and err.value.value is value


def test_json_round_trip_keeps_the_option(tmp_path):
    law = bl.CraterContact(**BASE, fade_xdot=80.0)
    path = tmp_path / "crater.json"
    law.to_json(path)
    back = bl.load_law(path)
    assert back == law and back.fade_xdot == 80.0


def test_fit_recovers_its_own_parameters():
    """Fitted to its own noise-free lift-offs (tilt growth and recoil held), the law finds its parameters."""
    truth = LAWS[0]
    p = contact_landings(300, seed=9)
    p = p[p[:, 0] > 100]
    ds = bl.make_campaign(p, truth.predict(p, plausible=None))
    held = {"beta_n": BASE["beta_n"], "beta_t": BASE["beta_t"], "v_r": BASE["v_r"], "kappa": BASE["kappa"]}
    res = bl.fit(bl.CraterContact, ds, fixed=held, seed=0)
    assert res.delta < 2e-3
    got = res.model.parameters
    for name, tol in {"r0": 0.02, "mu_k": 0.05, "lam": 0.05, "e_t": 0.1, "beta0": 0.1}.items():
        assert got[name] == pytest.approx(BASE[name], rel=tol), name


def test_agrees_with_solve_ivp():
    """The compiled law against an independent solve_ivp integration of the docstring's equations.

    ``benchmarks/contact_reference.py`` integrates the tangential ODE over p with DOP853 (rtol 1e-11) and locates
    every stop of the contact point as an event: it is exact to ~1e-10 ||p0||, so the difference is the law's own
    error, stated as about 1e-4 ||p0|| at worst for its 48 RK4 steps (measured here: about 1e-7).
    """
    from benchmarks.contact_reference import crater_reference

    names = [s.name for s in SPECS]
    cases = {
        # velocity weakening (mu_s > mu_k), tilt growing with both landing speeds
        "weakening": (BASE, contact_landings(6, seed=10)),
        # strong ploughing through the centre, no weakening: all three regimes (see test_every_regime_occurs)
        "ploughing": ({**BASE, "kappa": 0.0, "lam": 1.0, "mu_s": 0.05, "mu_k": 0.05},
                      np.vstack([contact_landings(6, seed=11),
                                 [[828.0, -802.0, 124.0], [948.0, -906.0, 20.0], [789.0, -346.0, -585.0]]])),
        # strong ploughing low on the ball, steep crater wall, elastic recoil
        "deep": ({**BASE, "lam": 0.8, "kappa": 0.6, "e_t": 1.0, "beta_t": 30.0, "beta_n": 20.0},
                 contact_landings(6, seed=12)),
    }
    worst = 0.0
    seen = set()
    for params, p in cases.values():
        law = bl.CraterContact(**params)
        theta = np.array([params[n] for n in names])
        ref = [crater_reference(q, theta) for q in p]
        out = law.predict(p)
        err = np.abs(out - np.array([r[:3] for r in ref])).max(axis=1) / np.linalg.norm(p, axis=1)
        worst = max(worst, err.max())
        assert list(law.regime(p)) == [r[3] for r in ref]
        seen.update(r[3] for r in ref)
    assert seen == {"slip", "grip", "reversed"}
    assert worst < 4e-6


# Landings where the first kernel went wrong (found by the independent reference): a stop where the friction needed
# exceeds mu_s by 4e-6 of it (slips back for an instant, then sticks), one where it slips back and sticks again
# later, and steady sliding (friction balancing ploughing; mu_k and lam beyond the search box) that a step too long
# for its stiffness crossed v_P = 0 by mistake.
HARD = [((1033.54, -186.37, 904.7), (0.3862, 3601.7743, 0.7446, 0.0634, 245.4251, 0.8806, 0.3141, 0.7523,
                                      1.2352, 2.9691, 28.4205)),
        ((1286.3, -229.09, 398.38), (0.6261, 6071.4605, 0.5299, 0.0766, 774.3572, 0.8838, 0.198, 0.4901,
                                     23.5525, 26.0737, 10.5427)),
        ((1223.1675355838188, -774.9713101103157, 814.2332724928342),
         (1.0, 1e9, 7.9236850187799, 0.21454334921551022, 43.77363953436731, 10.253169961817093,
          0.5732641256148879, 1.0, 18.19039211606521, 0.0, 0.0))]


@pytest.mark.parametrize(("landing", "theta"), HARD, ids=["marginal-stick", "slip-back-and-stick", "steady-sliding"])
def test_hard_stops_agree_with_solve_ivp(landing, theta):
    from benchmarks.contact_reference import crater_reference

    ref = crater_reference(landing, theta)
    law = bl.CraterContact(**dict(zip([s.name for s in SPECS], theta, strict=True)))
    got = law.predict([landing])[0]
    assert law.regime([landing])[0] == ref[3] == "grip"
    assert np.abs(got - np.array(ref[:3])).max() / np.linalg.norm(landing) < 1e-4


def test_friction_and_fit_report():
    law = LAWS[0]
    np.testing.assert_allclose(law.friction([0.0, 150.0, -1e6]), [1.0, 0.15 + 0.85 / np.e, 0.15])
    p = contact_landings(40, seed=13)
    p = p[p[:, 0] > 100]
    res = bl.fit(bl.CraterContact, bl.make_campaign(p, law.predict(p, plausible=None)), maxeval=80,
                 local_algorithm=None, seed=0)
    text = str(res)
    assert "restitution of vertical landings" in text and "friction at slip speeds" in text


def test_predict_varying_reads_mappings_by_name_and_uses_the_instance_option():
    import pandas as pd

    p = contact_landings(5, seed=14)
    law = LAWS[0].replace(fade_xdot=10.0)
    p[0] = [20.0, -800.0, 0.0]  # inside the fade: the option matters
    rows = pd.DataFrame([law.parameters] * len(p))
    swapped = rows[list(reversed(rows.columns))]
    np.testing.assert_array_equal(law.predict_varying(p, swapped), law.predict(p))
    np.testing.assert_array_equal(law.predict_varying(p, dict(law.parameters)), law.predict(p))
    default = bl.CraterContact.predict_varying(p, rows)  # on the class: the default fade of 50
    np.testing.assert_array_equal(default, law.replace(fade_xdot=50.0).predict(p))
    assert not np.allclose(default[0], law.predict(p)[0])


@pytest.mark.parametrize(("params", "bad"), [
    ({**BASE, "fade_xdot": 20.0}, "fade_xdot"),  # an option, not a parameter per bounce
    ({k: v for k, v in BASE.items() if k != "lam"}, "lam"),  # missing
    ({**BASE, "r0": [0.5, 0.6]}, "r0"),  # neither one value nor one per landing
    ({**BASE, "mu_k": "0.2"}, "mu_k"),  # not numbers
    ({**BASE, "v_s": float("nan")}, "v_s"),  # not finite
    ([[0.5] * 10], "params"),  # not of shape (5, 11)
])
def test_predict_varying_refuses_bad_params_by_name(params, bad):
    with pytest.raises(bl.ParameterError) as err:
        bl.CraterContact.predict_varying(contact_landings(5, seed=15), params)
    assert (err.value.law, err.value.parameter) == ("CraterContact", bad)


def test_helpers_refuse_bad_speeds_and_missing_parameters():
    with pytest.raises(bl.NotFittedError):
        bl.CraterContact().friction([0.0])
    for bad in ("abc", [0.0], [-500.0], [float("inf")]):
        with pytest.raises(bl.DataError) as err:
            LAWS[0].restitution(bad)
        assert err.value.option == "speed"
    with pytest.raises(bl.DataError) as err:
        LAWS[0].friction(["fast"])
    assert err.value.option == "slip_speed"


def test_steep_walls_can_send_a_ball_into_the_ground_and_predict_flags_it():
    """A documented limit: with heavy backspin on a steep wall the ball slides back down it (ydotF <= 0)."""
    law = bl.CraterContact(**{**BASE, "beta_t": 30.0, "beta_n": 30.0})
    p = np.array([[2500.0, -2200.0, 1500.0], [1000.0, -800.0, 0.0]])
    out, flags = law.predict(p, return_flags=True)
    assert out[0, 1] <= 0 < out[1, 1]
    assert list(flags.into_ground) == [True, False]


def test_predict_varying_names_a_dataframe_row_by_its_label():
    import pandas as pd

    p = contact_landings(4, seed=21)
    frame = pd.DataFrame([BASE] * 4, index=["spot-a", "spot-b", "spot-c", "spot-d"])
    frame.loc["spot-c", "r0"] = 1.5
    with pytest.raises(bl.ParameterError, match=r"'r0' of row 3 \(row label 'spot-c'\) is 1.5") as err:  # the label
        bl.CraterContact.predict_varying(p, frame)
    assert (err.value.parameter, err.value.value) == ("r0", 1.5)
