"""Surfaces fitted to launch-monitor shots (issue 33, items 2-4): recovery, held-out errors, errors, provenance.

The shots are simulated here from known surfaces with :func:`bouncelab.ground.run`, with their own
geometry (scipy's rotations, not the fit's formulas): driver-like landings at the medians of the
issue's public export (27.6 m/s, 37.7 degrees, 2,440 rpm at launch). They are synthetic: they test
that the fit recovers what made them, and say nothing about real turf.
"""

from __future__ import annotations

import json
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from scipy.spatial.transform import Rotation

import bouncelab as bl
from bouncelab.core.errors import DataError, FitError, ParameterError
from bouncelab.ground import PRESET_NAMES, Surface, SurfaceFit, fit_surface, load_surface, predict_shots, preset, run
from bouncelab.ground.fit import _shot_arrays

RPM = 2.0 * math.pi / 60.0
#: The known surfaces: a PennerFixed one that stops the ball in its bounces, a PennerVarying one that rolls.
FIXED = Surface("known-fixed", bl.PennerFixed(r=0.3, mu=0.6, beta_deg=19.0), sliding_friction=0.35, stimp_m=1.2)
VARYING = Surface("known-varying", bl.PennerVarying(r=0.1, mu=0.6, k_p=4e-4), sliding_friction=0.3, stimp_m=0.35)
DECAY, GAIN = 0.04, 1.5


def simulate(n: int, surface: Surface, *, seed: int = 0, noise: float = 0.0, decay: float = DECAY,
             gain: float = GAIN, sessions: int = 0) -> tuple[pd.DataFrame, np.ndarray]:
    """Driver-like shots rolled out on ``surface``: a DataFrame in SI units (launch spin), and the noise added."""
    rng = np.random.default_rng(seed)
    speed = rng.normal(27.6, 2.0, n)
    angle = np.radians(rng.normal(37.7, 3.0, n))
    spin = rng.normal(2440.0, 500.0, n) * RPM
    flight = rng.normal(6.5, 0.4, n)
    axis = np.radians(rng.normal(0.0, 8.0, n))
    launch = np.radians(rng.normal(12.0, 2.0, n))
    carry = rng.normal(230.0, 20.0, n)
    side = rng.normal(0.0, 15.0, n)
    heading = np.arctan(gain * side / carry)  # to the right
    v = speed[:, None] * np.column_stack([np.cos(angle), np.zeros(n), -np.sin(angle)])
    back = np.column_stack([np.zeros(n), -spin * np.exp(-decay * flight), np.zeros(n)])
    # the spin axis: perpendicular to the launch direction, tilted about it by the spin axis, kept in flight
    d0 = np.column_stack([np.cos(launch), np.zeros(n), np.sin(launch)])
    w = Rotation.from_rotvec(axis[:, None] * d0).apply(back)
    turn = Rotation.from_rotvec(np.column_stack([np.zeros(n), np.zeros(n), -heading]))
    rest = run(turn.apply(v), turn.apply(w), surface, units={"velocity": "m/s", "spin": "rad/s"}).rest_position
    added = rng.normal(0.0, noise, n) if noise else np.zeros(n)
    frame = pd.DataFrame({"landing_speed": speed, "landing_angle": angle, "spin": spin, "spin_axis": axis,
                          "launch_angle": launch, "carry": carry, "total": carry + rest[:, 0] + added, "side": side,
                          "side_total": side - rest[:, 1], "flight_time": flight,
                          "club": np.where(rng.random(n) < 0.5, "Driver", "3 Wood")},
                         index=pd.Index([f"s{i}" for i in range(n)], name="shot"))
    if sessions:
        frame["session"] = rng.integers(0, sessions, n).astype(str)
    frame.attrs["spin_at"] = "launch"
    return frame, added


def test_the_simulated_spin_axis_curves_right_and_kicks_right():
    """The shots' convention: a positive spin axis makes the Magnus force at launch (omega x v) point right (-y);
    at landing, its component along the travel makes the contact point slip left, so friction kicks the ball right."""
    d0 = np.array([np.cos(0.2), 0.0, np.sin(0.2)])
    w = Rotation.from_rotvec(0.2 * d0).apply([0.0, -1.0, 0.0])
    assert np.cross(w, d0)[1] < 0
    assert np.cross(w, [0.0, 0.0, -1.0])[1] > 0  # contact-point velocity omega x (-R z) points left (+y)
    v = np.array([[20.0, 0.0, -15.0]])
    out, _ = bl.ground.bounce(bl.Rigid(r=0.3, mu=0.5), v, w[None, :] * 250.0, units={"velocity": "m/s",
                                                                                     "spin": "rad/s"})
    assert out[0, 1] < 0  # lift-off to the right


@pytest.fixture(scope="module")
def fixed_fit() -> tuple[SurfaceFit, pd.DataFrame]:
    """The default fit (every parameter, 3 folds) of 600 shots: about 15 s on a 2-core machine."""
    shots, _ = simulate(600, FIXED, seed=1)
    return fit_surface(shots, folds=3, seed=0), shots


@pytest.fixture(scope="module")
def quick_fit() -> tuple[SurfaceFit, pd.DataFrame]:
    """A short fit (small budgets, 2 folds) for what does not depend on how well it converged."""
    shots, _ = simulate(200, FIXED, seed=1)
    return fit_surface(shots, folds=2, seed=0, maxeval=150, local_maxeval=100), shots


def test_a_short_fit_recovers_the_tilt_spin_decay_and_heading():
    shots, _ = simulate(300, FIXED, seed=10)
    law = bl.PennerFixed(r=0.3, mu=0.6, beta_deg=10.0)
    res = fit_surface(shots, law=law, vary=["beta_deg", "spin_decay", "heading_gain"], folds=0, maxeval=120,
                      local_maxeval=150, start={"sliding_friction": 0.35, "stimp_m": 1.2})
    v = res.params.valuesdict()
    assert abs(v["beta_deg"] - 19.0) < 0.5 and abs(v["spin_decay"] - DECAY) < 0.005
    assert abs(v["heading_gain"] - GAIN) < 0.03
    assert res.fitted_errors.loc["all", "median_abs_error"] < 0.3


@pytest.mark.slow
def test_fit_recovers_a_known_surface_and_predicts_held_out_roll(fixed_fit):
    res, shots = fixed_fit
    roll = shots["total"] - shots["carry"]
    assert 15.0 < roll.median() < 22.0  # driver-like: the export has a median roll of 18.0 m
    truth = {"r": 0.3, "mu": 0.6, "beta_deg": 19.0, "sliding_friction": 0.35, "stimp_m": 1.2, "spin_decay": DECAY,
             "heading_gain": GAIN}
    ident = res.identifiable
    assert {"beta_deg", "spin_decay", "heading_gain"} <= {k for k, v in ident.items() if v}, res
    for name, determined in ident.items():
        row = res.parameters.loc[name]
        assert row["low"] <= row["value"] <= row["high"]
        if determined:  # within 5 % of its box of the truth
            assert abs(row["value"] - truth[name]) <= 0.05 * (row["high"] - row["low"]), (name, row["value"])
    # the ball stops in its bounces on this surface: its rolling and skidding are not seen, and the fit says so
    assert not ident["stimp_m"] and not ident["sliding_friction"]
    assert "NOT determined" in str(res)
    e = res.errors.loc["all"]
    assert e["median_abs_error"] < 0.5 < 3.0  # the issue asks for 3 m; noise-free shots do much better
    assert e["median_abs_error"] < 0.2 * e["baseline_median_abs_error"]
    assert set(res.errors.index) == {"all", "club 3 Wood", "club Driver"}
    assert res.heldout["fold"].between(1, 3).all() and len(res.heldout) == len(shots)


def test_every_parameter_stays_in_its_bounds_and_the_report_reads(quick_fit):
    res, _ = quick_fit
    for name, p in res.params.items():
        lo, hi = p.bounds
        assert lo <= p.value <= hi, name
        assert res.parameters.loc[name, "low"] == lo and res.parameters.loc[name, "value"] == p.value
    text = str(res)
    for word in ("beta_deg", "stimp_m", "spin_decay", "held out (2 folds over shots)", "median |err|",
                 "its own estimate"):
        assert word in text
    assert "SurfaceFit(PennerFixed on 200 shots" in repr(res)
    assert list(res.folds.index) == [1, 2] and (res.folds["evaluations"] > 0).all()


def test_the_fitted_surface_is_a_surface_like_the_presets(quick_fit, tmp_path):
    res, shots = quick_fit
    s = res.surface
    assert isinstance(s, Surface) and isinstance(s.law, bl.PennerFixed)
    path = tmp_path / "fitted.json"
    s.to_json(path)
    back = load_surface(path)
    assert back == s and "fit_surface" in back.description and "not a measurement of the turf" in back.description
    assert "provenance: Fitted by bouncelab.ground.fit_surface" in str(s)
    # predict is ground.run on the landings: the same rest points as the simulation on the fitted values
    pred = res.predict(shots)
    assert list(pred.columns) == ["roll", "total", "side_roll", "side_total", "bounce_limit"]
    assert pred.index.equals(shots.index)
    np.testing.assert_allclose(pred["total"] - shots["carry"], pred["roll"], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(pred["roll"].to_numpy(), res.fitted_predictions["predicted_roll"].to_numpy())
    v = res.params.valuesdict()
    again, _ = simulate(200, back, seed=1, decay=v["spin_decay"], gain=v["heading_gain"])
    np.testing.assert_allclose(pred["total"], again["total"], rtol=0, atol=1e-6)
    np.testing.assert_allclose(pred["side_total"], again["side_total"], rtol=0, atol=1e-6)


def test_predict_needs_no_total_and_refuses_the_other_spin_kind(quick_fit):
    res, shots = quick_fit
    pred = res.predict(shots.drop(columns=["total", "side_total"]).head(5))
    np.testing.assert_array_equal(pred["roll"], res.predict(shots.head(5))["roll"])
    with pytest.raises(DataError) as err:
        res.predict(shots.head(5), spin_kind="landing")
    assert err.value.option == "spin_kind"


@pytest.mark.slow
def test_noise_on_the_totals_shows_as_the_held_out_error():
    """Noise of 2 m on the totals: the held-out error is that noise, not less (no overfit) and not much more."""
    shots, noise = simulate(600, FIXED, seed=2, noise=2.0)
    res = fit_surface(shots, folds=3, seed=0)
    e = res.errors.loc["all"]
    floor = float(np.median(np.abs(noise)))  # the best any prediction can do
    assert 0.85 * floor < e["median_abs_error"] < 1.25 * floor, (e["median_abs_error"], floor)
    assert e["median_abs_error"] < 3.0


@pytest.mark.slow
def test_a_rolling_surface_gives_its_green_speed():
    """On a surface where the ball rolls 7 m after its bounces, the Stimpmeter speed comes back when the bounce law
    is known (say, fitted to launcher bounces on that turf) and the rolling, skid, spin decay and heading are fitted."""
    shots, _ = simulate(500, VARYING, seed=3)
    assert 15.0 < (shots["total"] - shots["carry"]).median() < 22.0
    res = fit_surface(shots, law=VARYING.law, vary=["sliding_friction", "stimp_m", "spin_decay", "heading_gain"],
                      folds=0, seed=0)
    assert res.identifiable["stimp_m"]
    assert abs(res.params["stimp_m"].value - 0.35) < 0.01, res
    assert abs(res.params["spin_decay"].value - DECAY) < 0.002, res
    assert res.fitted_errors.loc["all", "median_abs_error"] < 0.05
    assert len(res.heldout) == 0 and "no held-out errors" in str(res)


def test_vary_holds_the_others_at_their_start():
    shots, _ = simulate(120, FIXED, seed=4)
    law = bl.PennerFixed(r=0.3, mu=0.6, beta_deg=19.0)
    res = fit_surface(shots, law=law, vary=["stimp_m", "spin_decay"], folds=0, maxeval=40, local_maxeval=40,
                      start={"heading_gain": GAIN, "sliding_friction": 0.35})
    t = res.parameters
    assert list(t.index[t["vary"]]) == ["stimp_m", "spin_decay"]
    assert t.loc["r", "value"] == 0.3 and t.loc["beta_deg", "value"] == 19.0 and t.loc["heading_gain", "value"] == 1.5
    assert abs(t.loc["spin_decay", "value"] - DECAY) < 0.01
    # a mapping changes the default set: everything but mu
    res2 = fit_surface(shots, law=law, vary={"mu": False}, folds=0, maxeval=20, local_maxeval=10)
    assert not res2.parameters.loc["mu", "vary"] and res2.parameters.loc["r", "vary"]


def test_executors_give_the_serial_result():
    shots, _ = simulate(90, FIXED, seed=5)
    kw = dict(folds=3, maxeval=40, local_maxeval=20, seed=7)
    serial = fit_surface(shots, **kw)
    with ThreadPoolExecutor(2) as ex:
        threaded = fit_surface(shots, executor=ex, **kw)
    assert threaded.params.valuesdict() == serial.params.valuesdict()
    pd.testing.assert_frame_equal(threaded.heldout, serial.heldout)
    pd.testing.assert_frame_equal(threaded.folds.drop(columns="elapsed_s"), serial.folds.drop(columns="elapsed_s"))


def test_sessions_and_clubs_are_held_out_whole():
    shots, _ = simulate(150, FIXED, seed=6, sessions=4)
    kw = dict(folds=2, maxeval=20, local_maxeval=10)
    res = fit_surface(shots, **kw)
    assert res.groups == "session"
    fold_of = res.heldout["fold"]
    assert (shots.groupby("session").apply(lambda g: fold_of[g.index].nunique(), include_groups=False) == 1).all()
    res = fit_surface(shots, groups="club", **kw)
    assert res.groups == "club"
    assert (res.heldout.groupby("club")["fold"].nunique() == 1).all()
    with pytest.raises(FitError) as err:
        fit_surface(shots, groups="club", folds=3)
    assert err.value.option == "groups"


# ------------------------------------------------------------------------------------------ inputs
def _dataset(frame: pd.DataFrame) -> xr.Dataset:
    """The shots as load_shots returns them: a Dataset with dimension shot, angles in degrees, spin in rpm."""
    ds = xr.Dataset({c: ("shot", frame[c].to_numpy()) for c in frame.columns},
                    coords={"shot": frame.index.to_numpy()})
    ds["landing_angle"] = ("shot", np.degrees(frame["landing_angle"].to_numpy()), {"units": "deg"})
    ds["spin_axis"] = ("shot", np.degrees(frame["spin_axis"].to_numpy()), {"units": "deg"})
    ds["launch_angle"] = ("shot", np.degrees(frame["launch_angle"].to_numpy()), {"units": "deg"})
    ds["spin"] = ("shot", frame["spin"].to_numpy() / RPM, {"units": "rpm", "spin_at": "launch"})
    ds["landing_speed"].attrs["units"] = "m/s"
    return ds


def test_a_dataset_in_degrees_and_rpm_reads_as_the_si_frame():
    frame, _ = simulate(20, FIXED, seed=8)
    a, b = _shot_arrays(frame), _shot_arrays(_dataset(frame))
    for name in ("landing_speed", "landing_angle", "spin", "spin_axis", "launch_angle", "carry", "total", "side",
                 "side_total", "flight_time"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-14, err_msg=name)
    assert b.spin_kind == "launch" and list(b.labels) == list(frame.index) and list(b.club) == list(frame["club"])
    ds = _dataset(frame)
    ds["landing_angle"] = ("shot", frame["landing_angle"].to_numpy(), {"units": "rad"})
    ds["spin"].attrs.pop("spin_at")
    ds.attrs["spin_at"] = "launch"
    np.testing.assert_allclose(_shot_arrays(ds).landing_angle, a.landing_angle, rtol=1e-15)
    units = frame.copy()
    units["landing_angle"] = np.degrees(units["landing_angle"])
    units.attrs = {"spin_at": "launch", "units": {"landing_angle": "deg"}}
    np.testing.assert_allclose(_shot_arrays(units).landing_angle, a.landing_angle, rtol=1e-15)


def test_distances_and_times_in_other_units_read_by_load_shots_table():
    """fit_surface reads distances and times by load_shots' one table of units (yards, feet, centimetres, ms)."""
    frame, _ = simulate(10, FIXED, seed=8)
    a = _shot_arrays(frame)
    other = frame.copy()
    other["carry"], other["side"], other["flight_time"] = frame["carry"] / 0.9144, frame["side"] / 0.3048, \
        frame["flight_time"] * 1000.0
    other.attrs = {"spin_at": "launch", "units": {"carry": "yds", "side": "feet", "flight_time": "ms"}}
    b = _shot_arrays(other)
    for name in ("carry", "side", "flight_time"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-14, err_msg=name)
    other.attrs["units"] = {"carry": "furlong"}
    with pytest.raises(DataError, match="unknown distance unit 'furlong'") as e:
        _shot_arrays(other)
    assert (e.value.column, e.value.option) == ("carry", "units")


def _refusal(exc_type, shots, **kw):
    with pytest.raises(exc_type) as err:
        fit_surface(shots, **kw)
    return err.value


@pytest.fixture(scope="module")
def few() -> pd.DataFrame:
    return simulate(40, FIXED, seed=9)[0]


def test_missing_variables_are_named(few):
    e = _refusal(DataError, few.drop(columns="carry"))
    assert e.column == "carry"
    e = _refusal(DataError, few.drop(columns="flight_time"))  # launch spin cannot decay without a flight time
    assert e.column == "flight_time"
    e = _refusal(DataError, _dataset(few).drop_vars("total"))
    assert e.column == "total"


def test_nans_are_named_by_column_and_shot(few):
    bad = few.copy()
    bad.iloc[6, bad.columns.get_loc("spin")] = np.nan
    e = _refusal(DataError, bad)
    assert (e.column, e.row, e.row_label) == ("spin", 7, "s6")
    assert "missing='drop'" in str(e)


def test_text_and_bools_are_refused_not_read_as_numbers(few):
    """A column of numbers written as text, or of bools, is a DataError naming the column (astype(float) took them)."""
    text = few.assign(carry=few["carry"].map(lambda v: f"{v:.1f}"))
    e = _refusal(DataError, text)
    assert e.column == "carry" and "text" in str(e)
    flags = few.assign(total=few["total"] > 0)
    assert _refusal(DataError, flags).column == "total"
    # a missing cell in a column of objects is a missing value, named with its shot, not a refused element
    holed = few.assign(carry=few["carry"].astype(object))
    holed.iloc[3, holed.columns.get_loc("carry")] = None
    e = _refusal(DataError, holed)
    assert (e.column, e.row, e.row_label) == ("carry", 4, "s3") and "missing='drop'" in str(e)


def test_values_in_another_unit_are_refused(few):
    deg = few.copy()
    deg["landing_angle"] = np.degrees(deg["landing_angle"])  # degrees in a column said to be radians
    assert _refusal(DataError, deg).column == "landing_angle"
    ds = _dataset(few)
    ds["landing_angle"].attrs["units"] = "rad"  # degrees said to be radians
    assert _refusal(DataError, ds).column == "landing_angle"
    ds = _dataset(few)
    ds["landing_angle"] = ("shot", few["landing_angle"].to_numpy(), {"units": "deg"})  # radians said to be degrees
    assert _refusal(DataError, ds).column == "landing_angle"
    ds = _dataset(few)
    del ds["landing_angle"].attrs["units"]
    e = _refusal(DataError, ds)
    assert e.column == "landing_angle" and e.option == "units"
    rpm = few.copy()
    rpm["spin"] = rpm["spin"] / RPM  # rpm in a column said to be rad/s
    assert _refusal(DataError, rpm).column == "spin"
    slow = few.copy()
    slow["spin"] = 1600.0 + 0.1 * (slow["spin"] - slow["spin"].mean()) / RPM  # about 1,600 rpm read as rad/s:
    # each row possible (15,000 rpm), not as the median of a file
    e = _refusal(DataError, slow)
    assert e.column == "spin" and e.row is None and "median" in str(e)
    fast = few.copy()
    fast["landing_speed"] = fast["landing_speed"] * 2.237  # mph read as m/s
    assert _refusal(DataError, fast).column == "landing_speed"
    ms = few.copy()
    ms["flight_time"] = ms["flight_time"] * 1000.0
    assert _refusal(DataError, ms).column == "flight_time"
    mph = few.copy()
    mph.attrs["units"] = {"landing_speed": "furlong/s"}
    e = _refusal(DataError, mph)
    assert e.column == "landing_speed" and "unknown velocity unit" in str(e)


def test_bad_arguments_are_typed_errors_naming_them(few):
    assert _refusal(FitError, few, law="NoSuchLaw").option == "law"
    assert _refusal(FitError, few.head(12)).option == "shots"  # 12 shots, 5 folds: each fits 9
    assert _refusal(FitError, few, vary=["tilt"]).option == "vary"
    assert _refusal(FitError, few, folds=1).option == "folds"
    assert _refusal(FitError, few, folds=41).option == "folds"
    assert _refusal(FitError, few, groups="weekday").option == "groups"
    assert _refusal(FitError, few, groups="session").option == "groups"  # the shots have no sessions
    assert _refusal(FitError, few, bounds={"stimp_m": (-1.0, 2.0)}).option == "bounds"
    assert _refusal(FitError, few, start={"stimp_m": 9.0}).option == "start"
    assert _refusal(FitError, few, seed=-1).option == "seed"
    landing = few.copy()
    landing.attrs["spin_at"] = "landing"
    assert _refusal(FitError, landing, vary=["spin_decay"]).option == "vary"
    assert _refusal(FitError, few.drop(columns=["side", "side_total"]), vary=["heading_gain"]).option == "vary"
    no_kind = few.copy()
    no_kind.attrs = {}
    assert _refusal(DataError, no_kind).option == "spin_kind"
    assert _refusal(DataError, few.to_numpy()).option == "shots"


def test_landing_spin_fits_without_flight_time_or_decay(few):
    landing = few.drop(columns="flight_time")
    res = fit_surface(landing, spin_kind="landing", folds=0, maxeval=20, local_maxeval=10)
    assert not res.parameters.loc["spin_decay", "vary"] and res.parameters.loc["spin_decay", "value"] == 0.0
    assert res.spin_kind == "landing"


# ------------------------------------------------------------------------------------------ presets
def test_every_preset_states_its_provenance_in_str_and_json():
    for name in PRESET_NAMES:
        s = preset(name)
        assert "provenance: " in str(s) and s.description in str(s)
        assert json.loads(s.to_json())["description"] == s.description
        assert "not a fairway" in s.description if name.startswith("turf") else "general guidance" in s.description
        assert "assumption" in s.description
    assert str(Surface("bare", bl.Rigid(r=0.3, mu=0.5), 0.4, stimp_m=2.0)) == repr(
        Surface("bare", bl.Rigid(r=0.3, mu=0.5), 0.4, stimp_m=2.0))


# ------------------------------------------------------------------------------------------ plot
def test_plot_roll_fit(quick_fit):
    pytest.importorskip("matplotlib")
    from bouncelab.plots import plot_roll_fit

    res, _ = quick_fit
    fig = plot_roll_fit(res)
    ax = fig.axes[0]
    assert len(ax.collections) == 2  # one scatter per club
    assert "held out" in ax.get_title()
    assert any("median |error|" in t.get_text() for t in ax.get_legend().get_texts())
    fig = plot_roll_fit(res, heldout=False)
    assert "in-sample" in fig.axes[0].get_title()
    with pytest.raises(ParameterError):
        plot_roll_fit(res.surface)


# ------------------------------------------------------------------------------------------ predict_shots
def test_predict_shots_on_a_preset_is_ground_run_on_the_landings():
    shots, _ = simulate(30, FIXED, seed=11)
    again, _ = simulate(30, preset("turf-B"), seed=11, decay=0.03, gain=1.2)
    pred = predict_shots(shots, "turf-B", spin_decay=0.03, heading_gain=1.2)
    np.testing.assert_allclose(pred["total"], again["total"], rtol=0, atol=1e-6)
    np.testing.assert_allclose(pred["side_total"], again["side_total"], rtol=0, atol=1e-6)
    assert not pred["bounce_limit"].any()
    with pytest.raises(ParameterError) as err:
        predict_shots(shots, "turf-B")  # launch spin: how fast it decays must be said
    assert err.value.parameter == "spin_decay"
    with pytest.raises(ParameterError) as err:
        predict_shots(shots, "turf-B", spin_decay=0.03, heading_gain=-1.0)
    assert err.value.parameter == "heading_gain"
    with pytest.raises(ParameterError) as err:
        predict_shots(shots, "fairway", spin_decay=0.03)
    assert err.value.parameter == "surface"
    landing = predict_shots(shots.drop(columns=["flight_time", "side", "side_total"]), "turf-B", spin_kind="landing")
    assert list(landing.columns) == ["roll", "total", "bounce_limit"]


# ------------------------------------------------------------------------------------------ across CPUs
_CROSS = r"""
import hashlib, json, sys
import pandas as pd
from bouncelab.ground import fit_surface
shots = pd.read_pickle(sys.argv[1])
res = fit_surface(shots, folds=2, maxeval=60, local_maxeval=30, seed=3)
roll = res.heldout["predicted_roll"].to_numpy()
print(json.dumps({"params": res.params.valuesdict(), "heldout": hashlib.sha256(roll.tobytes()).hexdigest()}))
"""


@pytest.mark.slow
def test_a_fit_gives_the_same_bits_under_a_reduced_instruction_set(tmp_path):
    """The same shots fitted with and without AVX2/AVX-512 and FMA (numba and NumPy): the same bits."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    from tests.test_bits import reduced_instruction_set_env

    if os.environ.get("NUMBA_CPU_NAME"):
        pytest.skip("this run is already under a reduced instruction set")
    root = Path(__file__).resolve().parents[1]
    shots, _ = simulate(80, FIXED, seed=12, noise=1.0)  # made once here: the fits read the same numbers
    shots.to_pickle(tmp_path / "shots.pkl")

    def cross(extra: dict[str, str]) -> dict:
        env = {**os.environ, "PYTHONPATH": str(root), **extra}
        proc = subprocess.run([sys.executable, "-c", _CROSS, str(tmp_path / "shots.pkl")], capture_output=True,
                              text=True, env=env, timeout=1800)
        assert proc.returncode == 0, proc.stderr
        return json.loads(proc.stdout.splitlines()[-1])

    assert cross({}) == cross(reduced_instruction_set_env())


# ------------------------------------------------------------------------------------------ the documented path
def test_a_trackman_export_loads_and_fits_end_to_end(tmp_path):
    """docs/simulators.md's path: a TrackMan-style export (units row, a blank cell) -> load_shots(missing="drop")
    -> fit_surface -> predict. The shots load as the frame they were written from (the spin's kind included, under
    the name load_shots gives it) and the fit runs on them."""
    from bouncelab.core.errors import DroppedRowsWarning

    frame, _ = simulate(40, FIXED, seed=21)
    mph, yd, ft = 1609.344 / 3600, 0.9144, 0.3048
    head = ("Club,Spin Rate,Spin Axis,Launch Angle,Carry Flat - Length,Carry Flat - Side,Carry Flat - Land. Angle,"
            "Carry Flat - Ball Speed,Carry Flat - Time,Total,Side Total")
    units = ",[rpm],[deg],[deg],[yds],[ft],[deg],[mph],[s],[yds],[ft]"
    rows = [",".join([f.club, repr(f.spin / RPM), repr(math.degrees(f.spin_axis)), repr(math.degrees(f.launch_angle)),
                      repr(f.carry / yd), repr(f.side / ft), repr(math.degrees(f.landing_angle)),
                      repr(f.landing_speed / mph), repr(f.flight_time), repr(f.total / yd), repr(f.side_total / ft)])
            for f in frame.itertuples()]
    rows[5] = rows[5].replace(rows[5].split(",")[9], "")  # the monitor lost this shot's total
    path = tmp_path / "session.csv"
    path.write_text("\n".join([head, units, *rows]) + "\n", encoding="utf-8")
    with pytest.warns(DroppedRowsWarning, match="row 6"):
        shots = bl.ground.load_shots(path, missing="drop")
    kept = frame.drop(index=frame.index[5])
    a, b = _shot_arrays(kept), _shot_arrays(shots)
    assert b.spin_kind == "launch"
    for name in ("landing_speed", "landing_angle", "spin", "spin_axis", "launch_angle", "carry", "total", "side",
                 "side_total", "flight_time"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-13, err_msg=name)
    res = fit_surface(shots, folds=2, maxeval=60, local_maxeval=30, final_maxeval=20, seed=1)
    predicted = res.predict(shots)
    assert len(predicted) == 39 and np.isfinite(predicted[["roll", "total", "side_total"]].to_numpy()).all()
    # each search's time is a number of seconds (the polish loop once overwrote its start time with a point)
    assert len(res.folds) >= 1
    assert all(isinstance(v, float) and 0.0 <= v < 600.0 for v in res.folds["elapsed_s"])
