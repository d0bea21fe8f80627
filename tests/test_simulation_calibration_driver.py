"""benchmarks/calibrate_surrogates.py: the search space, one evaluation, and a tiny run on dask."""

from __future__ import annotations

import json

import numpy as np
import pytest

from benchmarks import calibrate_surrogates as drv
from bouncelab.simulation import LogNormal


def test_parametrisation_covers_every_parameter_and_its_scatter():
    par = drv.Parametrisation("TangentialRestitution", max_sigma=0.4)
    assert par.names == ["r", "mu", "e_t", "sigma_r", "sigma_mu", "sigma_e_t"]
    assert par.bounds()[:3] == [(0.0, 1.0), (0.0, 1.5), (0.0, 1.0)] and par.bounds()[3:] == [(0.0, 0.4)] * 3
    turf = par.turf([0.4, 0.5, 0.2, 0.1, 0.0, 0.3])
    assert turf.law.parameters == {"r": 0.4, "mu": 0.5, "e_t": 0.2}
    assert turf.scatter == {"r": LogNormal(0.1), "e_t": LogNormal(0.3)}  # sigma 0: no scatter


def test_evaluate_averages_the_replicates():
    x = [0.4, 0.5, 0.2, 0.1, 0.1, 0.1]
    one = [drv.evaluate(x, "A", "TangentialRestitution", [s]) for s in (1, 2)]
    both = drv.evaluate(x, "A", "TangentialRestitution", [1, 2])
    mean = (one[0]["table"]["simulated"] + one[1]["table"]["simulated"]) / 2
    np.testing.assert_allclose(both["table"]["simulated"], mean, rtol=1e-12)
    assert both["objective"] == pytest.approx(
        drv.cal.calibration_objective(both["table"]), rel=1e-12
    ) and both["objective"] > 0


@pytest.mark.slow
def test_tiny_calibration_run_on_dask(tmp_path):
    out = tmp_path / "calib.json"
    results = drv.main(["--campaign", "A", "--law", "TangentialRestitution", "--maxiter", "1", "--popsize", "1",
                        "--replicates", "1",
                        "--final-seeds", "1", "--scheduler", "synchronous", "--output", str(out)])
    (res,) = results
    # (maxiter + 1) generations of popsize x 6 candidates, rounded up to a power of 2 by the Sobol start
    assert res["evaluations"] == 2 * 8
    assert res["objective_search"] <= drv.objective(np.array(res["x"]), "A", "TangentialRestitution", [1000],
                                                    0.5) + 1e-12
    saved = json.loads(out.read_text())
    assert saved[0]["campaign"] == "A" and len(saved[0]["table"]) == 14


def test_refine_stays_in_the_box_and_stops_at_its_budget():
    """The time-boxed Nelder-Mead: returns its best candidate, clipped into the search box, within budget."""
    law = "TangentialRestitution"
    par = drv.Parametrisation(law, 0.5)
    lo, hi = np.array(par.bounds()).T
    start = hi + 1.0  # outside the box on purpose
    res = drv.refine("A", law=law, start=start, budget=1.0, replicates=1, seed=0, max_sigma=0.5, final_seeds=1)
    x = np.array(res["x"])
    assert ((x >= lo) & (x <= hi)).all()
    assert res["evaluations"] >= 1
    assert np.isfinite(res["objective_fresh_seeds"])


def test_surrogate_limits_measures_the_floor_the_jump_and_rolling_liftoffs():
    import bouncelab as bl
    from benchmarks import surrogate_limits as lim

    out = lim.main(["--campaign", "A", "--laws", "PennerFixed", "Rigid"])["A"]
    pw = out["PiecewiseAffine (published)"]
    # The published law's two maps differ at its plane (a continuous law would give ~0 there).
    assert pw["n_near_plane"] > 10 and pw["jump_near_plane"] > 0.05
    # PennerFixed contains Rigid (beta = 0), so its floor cannot be higher; neither reaches 0.
    assert 0.05 < out["PennerFixed"]["delta_floor"] < out["Rigid"]["delta_floor"]
    p0 = bl.load_campaign("A", surrogate="published")["landing"].values
    noise_free = np.asarray(bl.PiecewiseAffine.published("A").predict(p0))
    assert pw["rolling_liftoff_fraction"] == pytest.approx(lim.rolling_fraction(p0, noise_free))
    assert 0 <= out["Rigid"]["rolling_liftoff_fraction"] <= 1


def test_surrogate_limits_on_the_turf_surrogates_landings():
    import bouncelab as bl
    from benchmarks import surrogate_limits as lim
    from bouncelab.simulation.surrogate import generate_turf_surrogate

    out = lim.main(["--campaign", "A", "--laws", "Rigid", "--landings", "turf"])["A"]
    p0 = generate_turf_surrogate("A")["true_landing"].values
    noise_free = np.asarray(bl.PiecewiseAffine.published("A").predict(p0))
    assert out["PiecewiseAffine (published)"]["rolling_liftoff_fraction"] == pytest.approx(
        lim.rolling_fraction(p0, noise_free))
    published = lim.main(["--campaign", "A", "--laws", "Rigid"])["A"]
    assert out["Rigid"]["delta_floor"] != published["Rigid"]["delta_floor"]  # other landings, another floor


def test_plane_jump_is_zero_for_a_continuous_piecewise_law():
    import bouncelab as bl
    from benchmarks import surrogate_limits as lim

    rng = np.random.default_rng(0)
    a = rng.normal(size=(3, 3))
    law = bl.PiecewiseAffine(normal=[0.2, 1.0, 0.1], offset=-100.0, A1=a, b1=[1.0, 2.0, 3.0], A2=a, b2=[1.0, 2.0, 3.0])
    p0 = bl.load_campaign("A", surrogate="published")["landing"].values
    n, near, overall = lim.plane_jump(law, p0, 0.5)
    assert n > 0 and near == pytest.approx(0.0, abs=1e-12) and overall == pytest.approx(0.0, abs=1e-12)


def test_scatter_option_searches_only_the_named_sds():
    par = drv.Parametrisation("TangentialRestitution", max_sigma=0.4, scatter=("mu",))
    assert par.names == ["r", "mu", "e_t", "sigma_mu"]
    assert par.bounds()[3:] == [(0.0, 0.4)]
    turf = par.turf([0.4, 0.5, 0.2, 0.3])
    assert turf.scatter == {"mu": LogNormal(0.3)}
    with pytest.raises(SystemExit, match=r"--scatter names \['beta'\]"):
        drv.Parametrisation("TangentialRestitution", scatter=("beta",)).bounds()


def test_json_start_reads_a_previous_output_or_a_mapping(tmp_path):
    law, scatter = "TangentialRestitution", ("r", "mu")
    previous = tmp_path / "run.json"
    previous.write_text(json.dumps([
        {"campaign": "B", "names": ["r", "mu", "e_t", "sigma_r", "sigma_mu"], "x": [0.1, 0.2, 0.3, 0.4, 0.5]},
        {"campaign": "A", "names": ["r", "mu", "e_t", "sigma_r", "sigma_mu"], "x": [0.6, 0.7, 0.8, 0.05, 0.06]},
    ]))
    np.testing.assert_array_equal(drv.json_start(str(previous), "A", law, scatter), [0.6, 0.7, 0.8, 0.05, 0.06])
    mapping = tmp_path / "start.json"
    mapping.write_text(json.dumps({"r": 0.5, "mu": 0.4, "e_t": 0.1, "sigma_mu": 0.2}))
    # a log-sd the file does not give starts at 0.1
    np.testing.assert_array_equal(drv.json_start(str(mapping), "A", law, scatter), [0.5, 0.4, 0.1, 0.1, 0.2])
    mapping.write_text(json.dumps({"r": 0.5, "mu": 0.4}))
    with pytest.raises(SystemExit, match=r"gives no value for \['e_t'\]"):
        drv.json_start(str(mapping), "A", law, scatter)
    with pytest.raises(SystemExit, match="no result for campaign"):
        drv.json_start(str(previous), "C", law, scatter)


def test_shipped_start_is_the_shipped_turf():
    from bouncelab.simulation.surrogate import TURF_CALIBRATION, turf_for_campaign

    scatter = ("r0", "mu_k", "lam", "e_t", "beta0", "kappa")  # kappa does not scatter in the shipped turf
    x = drv.shipped_start("B", "CraterContact", scatter)
    turf = drv.Parametrisation("CraterContact", 0.8, scatter).turf(x)
    assert turf.law.parameters == turf_for_campaign("B").law.parameters
    assert dict(zip(drv.Parametrisation("CraterContact", 0.8, scatter).names, x, strict=True))["sigma_kappa"] == 0
    assert x[-2] == TURF_CALIBRATION["B"]["log_sd"]["beta0"]
    with pytest.raises(SystemExit, match="is CraterContact, not TangentialRestitution"):
        drv.shipped_start("A", "TangentialRestitution", None)
