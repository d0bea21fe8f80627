"""The unit guard beyond files (issue 11 item 2): make_campaign, fit on bare arrays and the command line
refuse numbers that only a unit mistake makes, naming the column, the likely unit and how to widen."""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_OK
from bouncelab.core import units
from bouncelab.core.errors import Hint
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, check_scaled, widen_hints

RPM = 60 / (2 * np.pi)  # rpm per rad/s


@pytest.fixture(scope="module")
def campaign_a():
    return bl.load_campaign("A")


@pytest.fixture(scope="module")
def lab_sheet(campaign_a):
    """Campaign A as a lab sheet holds it: m/s and rpm."""
    return (units.from_scaled(campaign_a.landing.values, velocity="m/s", spin="rpm"),
            units.from_scaled(campaign_a.liftoff.values, velocity="m/s", spin="rpm"))


def test_make_campaign_refuses_m_per_s_and_rpm(lab_sheet):
    landing, liftoff = lab_sheet
    before = landing.copy()
    with pytest.raises(bl.DataError) as exc:
        bl.make_campaign(landing, liftoff)
    msg = str(exc.value)
    assert exc.value.column == "ydot0"
    assert "median landing speed" in msg and "look like m/s" in msg
    assert "they look like rpm" in msg and "spin='rpm'" in msg and "velocity='m/s'" in msg
    assert "plausible=PLAUSIBLE_RANGES.widened(" in msg and "plausible=None" in msg
    np.testing.assert_array_equal(landing, before)  # changes nothing


def test_make_campaign_refuses_rpm_spins_naming_column_and_bounce(campaign_a):
    landing = campaign_a.landing.values * [1, 1, RPM]
    with pytest.raises(bl.DataError) as exc:
        bl.make_campaign(landing, campaign_a.liftoff.values)
    err = exc.value
    first = int(np.argmax(np.abs(landing[:, 2]) / RPM > 20_000))
    assert err.column == "omega0" and err.row == first + 1
    assert "look like rpm" in err.message
    assert err.hints == (Hint("plausible", "PLAUSIBLE_RANGES.widened(max_spin=...)"), Hint("plausible", "None"))


def test_make_campaign_refuses_rpm_lift_off_spins(campaign_a):
    with pytest.raises(bl.DataError) as exc:
        bl.make_campaign(campaign_a.landing.values, campaign_a.liftoff.values * [1, 1, 60])
    assert exc.value.column == "omegaF"


def test_make_campaign_refuses_m_per_s_alone(lab_sheet, campaign_a):
    landing = lab_sheet[0].copy()
    liftoff = lab_sheet[1].copy()
    landing[:, 2], liftoff[:, 2] = campaign_a.landing.values[:, 2], campaign_a.liftoff.values[:, 2]
    with pytest.raises(bl.DataError, match="look like m/s") as exc:
        bl.make_campaign(landing, liftoff)
    assert "spins too" not in str(exc.value) and "widened(min_median_landing_speed=" in str(exc.value)


def test_make_campaign_refuses_spins_that_fit_no_unit(campaign_a):
    with pytest.raises(bl.DataError, match="not plausible in rpm, rev/s either") as exc:
        bl.make_campaign(campaign_a.landing.values * [1, 1, 1e-3], campaign_a.liftoff.values * [1, 1, 1e-3])
    assert "min_peak_spin" in str(exc.value)


def test_widened_or_no_ranges_accept_on_purpose(campaign_a):
    landing = campaign_a.landing.values * [1, 1, 2.5]  # campaign A spins up to ~10 000 rpm: now 25 000
    assert np.abs(landing[:, 2]).max() * RPM > 20_000
    with pytest.raises(bl.DataError):
        bl.make_campaign(landing, campaign_a.liftoff.values)
    ds = bl.make_campaign(landing, campaign_a.liftoff.values, plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
    np.testing.assert_array_equal(ds.landing.values, landing)
    assert bl.make_campaign(landing, campaign_a.liftoff.values, plausible=None).sizes["bounce"] == len(landing)
    # a widened campaign stays valid: validation checks the form, not the ranges
    assert bl.validate_campaign(ds).sizes["bounce"] == len(landing)


def test_guard_uses_the_ball_radius(campaign_a):
    # a median landing of 26 radii/s is 0.56 m/s for a 21.35 mm ball, 5.2 m/s for a 0.2 m one
    slow, slow_f = campaign_a.landing.values * [0.02, 0.02, 1], campaign_a.liftoff.values * [0.02, 0.02, 1]
    with pytest.raises(bl.DataError) as exc:
        bl.make_campaign(slow, slow_f)
    assert (exc.value.column, exc.value.row) == ("ydot0", None)  # the median landing speed
    assert bl.make_campaign(slow, slow_f, ball_radius_m=0.2).sizes["bounce"] == len(slow)
    with pytest.raises(bl.DataError, match="ball_radius_m"):
        bl.make_campaign(slow, slow_f, ball_radius_m=-1)


@pytest.mark.parametrize("name", ["A", "B"])
@pytest.mark.parametrize("surrogate", ["published", "turf"])
def test_embedded_campaigns_pass_the_guard(name, surrogate):
    ds = bl.load_campaign(name, surrogate=surrogate)
    check_scaled(ds.landing.values, ds.liftoff.values)
    assert bl.make_campaign(ds.landing.values, ds.liftoff.values).sizes["bounce"] == ds.sizes["bounce"]


def test_fit_refuses_bare_arrays_in_lab_units(lab_sheet):
    with pytest.raises(bl.DataError) as exc:
        bl.fit(bl.Rigid, lab_sheet)
    assert "look like m/s" in exc.value.message and exc.value.column == "ydot0"
    assert {h.option for h in exc.value.hints} == {"plausible"}  # fit(..., plausible=) accepts them on purpose


def test_fit_refuses_bare_rpm_spins_and_held_out_arrays(campaign_a):
    p0, pf = campaign_a.landing.values, campaign_a.liftoff.values
    with pytest.raises(bl.DataError) as exc:
        bl.fit(bl.Rigid, (p0 * [1, 1, RPM], pf), method="structured")
    assert exc.value.column == "omega0" and "look like rpm" in str(exc.value)
    with pytest.raises(bl.DataError) as exc:
        bl.fit(bl.Rigid, (p0[:200], pf[:200]), test=(p0[200:], pf[200:] * [1, 1, 60]), method="structured")
    assert exc.value.column == "omegaF"


def test_fit_accepts_bare_arrays_on_purpose(campaign_a):
    p0, pf = campaign_a.landing.values * [1, 1, 2.5], campaign_a.liftoff.values
    res = bl.fit(bl.Rigid, (p0, pf), method="structured", plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
    assert res.n_train == len(p0)
    wide = bl.make_campaign(p0, pf, plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
    assert bl.fit(bl.Rigid, wide, method="structured").n_train == len(p0)  # a Dataset is checked when made
    assert bl.fit(bl.Rigid, (p0, pf), method="structured", plausible=None).n_train == len(p0)


def test_bootstrap_and_estimator_guard_bare_arrays(lab_sheet, campaign_a):
    with pytest.raises(bl.DataError, match="look like m/s"):
        bl.bootstrap(bl.Rigid, lab_sheet, n=2, by="bounce", method="structured")
    with pytest.raises(bl.DataError, match="look like m/s"):
        bl.BounceRegressor("Rigid", method="structured").fit(*lab_sheet)
    # resamples of checked data are not refused (a bootstrap of a widened campaign runs)
    wide = bl.make_campaign(campaign_a.landing.values * [1, 1, 2.5], campaign_a.liftoff.values,
                            plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
    assert len(bl.bootstrap(bl.Rigid, wide, n=2, by="bounce", method="structured").samples) == 2


# ----------------------------------------------------------------------------- command line
@pytest.fixture(scope="module")
def sheet_b(tmp_path_factory):
    """The issue's file: campaign B's bounces with spins below 4800 rpm, in m/s and rpm, no units in the header."""
    b = bl.load_campaign("B")
    p0 = units.from_scaled(b.landing.values, velocity="m/s", spin="rpm")
    pf = units.from_scaled(b.liftoff.values, velocity="m/s", spin="rpm")
    keep = (np.abs(p0[:, 2]) < 4800) & (np.abs(pf[:, 2]) < 4800)
    path = tmp_path_factory.mktemp("guard") / "sheet.csv"
    rows = np.column_stack([p0[keep], pf[keep]])
    np.savetxt(path, rows, delimiter=",", fmt="%.4f", header="xdot0,ydot0,omega0,xdotF,ydotF,omegaF", comments="")
    return path


def test_cli_fit_names_spin_column_and_flag(sheet_b, capsys):
    code = main(["fit", "PennerFixed", str(sheet_b), "--velocity-unit", "m/s"])
    err = capsys.readouterr().err
    assert code == EXIT_DATA
    assert "column 'omega0'" in err and "--spin-unit rpm" in err and "units=" not in err


@pytest.mark.parametrize("command", [["info"], ["fit", "Rigid"]])
def test_cli_wrong_declared_spin_unit_names_flag(sheet_b, capsys, command):
    argv = [command[0], *command[1:], str(sheet_b), "--velocity-unit", "m/s", "--spin-unit", "rad/s"]
    code = main(argv)
    err = capsys.readouterr().err
    assert code == EXIT_DATA and "omega0" in err and "--spin-unit rpm" in err


def test_cli_reproduce_refuses_lab_units(sheet_b, tmp_path, capsys):
    code = main(["reproduce", "--data", str(sheet_b), "--velocity-unit", "m/s", "--out", str(tmp_path / "r"),
                 "--quiet", "--no-figures"])
    err = capsys.readouterr().err
    assert code == EXIT_DATA and "--spin-unit rpm" in err
    assert not (tmp_path / "r").exists()


PUB = ["predict", "Rigid", "--published", "A"]


def test_cli_predict_refuses_lab_units_typed_as_scaled(capsys):
    code = main([*PUB, "--landing", "20", "-15", "3000"])
    err = capsys.readouterr().err
    assert code == EXIT_DATA
    assert "--velocity-unit m/s" in err and "--spin-unit rpm" in err and "ydot0" in err


def test_cli_predict_refuses_rpm_declared_as_rad_per_s(capsys):
    code = main([*PUB, "--landing", "20", "-15", "3000", "--velocity-unit", "m/s"])
    err = capsys.readouterr().err
    assert code == EXIT_DATA and "landing 1, omega0" in err and "--spin-unit rpm" in err
    assert "--velocity-unit" not in err.split("give the unit with")[1].split(";")[0]


def test_cli_predict_input_file_is_guarded(tmp_path, capsys):
    rows = tmp_path / "landings.csv"
    rows.write_text("vx,vy,spin\n20,-15,3000\n30,-10,-500\n")
    assert main([*PUB, "--input", str(rows)]) == EXIT_DATA
    assert "--velocity-unit m/s" in capsys.readouterr().err
    assert main([*PUB, "--input", str(rows), "--velocity-unit", "m/s", "--spin-unit", "rpm"]) == EXIT_OK


def test_cli_predict_refuses_radians_for_degrees(capsys):
    argv = [*PUB, "--speed-angle-spin", "20", "0.65", "3000", "--velocity-unit", "m/s", "--spin-unit", "rpm"]
    assert main(argv) == EXIT_DATA
    assert "radians" in capsys.readouterr().err
    argv[6] = "37.2"
    assert main(argv) == EXIT_OK


def test_cli_predict_landing_without_spin_is_plausible(capsys):
    """A landing alone may have no spin: the peak-spin limit applies to campaigns, not to landings."""
    assert main([*PUB, "--landing", "900", "-700", "0"]) == EXIT_OK
    capsys.readouterr()


# ----------------------------------------------------------------------------- one guard for every landing (issue 22)
SI = {"velocity": "m/s", "spin": "rpm"}
LAW = bl.Rigid.published("A")


def _forms(speed_mps: float, angle_deg: float, spin_rpm: float) -> dict[str, tuple[np.ndarray, dict]]:
    """One landing in every form and unit: (landing, predict keywords)."""
    polar = np.array([[speed_mps, angle_deg, spin_rpm]])
    cart_si = units.state_from_polar(polar, kind="landing", speed_unit="m/s", spin_unit="rpm")
    cart_si = units.from_scaled(cart_si, velocity="m/s", spin="rpm")
    scaled = units.to_scaled(cart_si, velocity="m/s", spin="rpm")
    kmh = units.from_scaled(scaled, velocity="km/h", spin="rad/s")
    return {
        "polar SI": (polar, {"units": SI, "form": "polar"}),
        "Cartesian SI": (cart_si, {"units": SI}),
        "Cartesian scaled": (scaled, {}),
        "Cartesian km/h, rad/s": (kmh, {"units": {"velocity": "km/h", "spin": "rad/s"}}),
    }


def _verdicts(speed_mps: float, angle_deg: float, spin_rpm: float) -> dict[str, str | None]:
    out = {}
    for name, (landing, kw) in _forms(speed_mps, angle_deg, spin_rpm).items():
        try:
            LAW.predict(landing, **kw)
            out[name] = None
        except bl.DataError as exc:
            out[name] = next(limit for limit in ("min_landing_speed", "max_speed", "max_spin", "min_landing_angle")
                             if f"widened({limit}=" in str(exc))
    return out


@pytest.mark.parametrize("landing, limit", [
    ((20.0, 4.9, 2000.0), "min_landing_angle"),   # grazing: refused in polar form before, accepted as Cartesian
    ((20.0, 30.0, 30_000.0), "max_spin"),          # 30 000 rpm: refused in SI before, 3141 rad/s accepted scaled
    ((0.5, 30.0, 2000.0), "min_landing_speed"),    # slower than any golf landing: accepted everywhere before
    ((95.0, 40.0, 2000.0), "max_speed"),           # 95 m/s at 40 degrees: 73 m/s per component, accepted before
    ((20.0, 30.0, 2000.0), None),                  # a golf landing, accepted in every form
])
def test_one_landing_is_judged_alike_in_every_form_and_unit(landing, limit):
    assert _verdicts(*landing) == dict.fromkeys(_forms(*landing), limit)


@pytest.mark.parametrize("landing", [(1.0, 30.0, 2000.0), (20.0, 5.0, 2000.0), (90.0, 60.0, 2000.0),
                                     (20.0, 30.0, 20_000.0), (20.0, 30.0, -20_000.0)])
def test_landings_at_the_limits_are_accepted_in_every_form(landing):
    """The limits hold to a relative 1e-9, so a conversion's last bits do not decide."""
    assert set(_verdicts(*landing).values()) == {None}


def test_m_per_s_given_as_scaled_units_are_refused_naming_the_unit():
    for method in (LAW.predict, LAW.regime):
        with pytest.raises(bl.DataError) as exc:
            method([[20.0, -15.0, 200.0]])
        msg = str(exc.value)
        assert exc.value.row == 1 and exc.value.column is None
        assert "25 radii/s = 0.5338 m/s is slower than any golf landing (min_landing_speed 1 m/s" in msg
        assert "the numbers look like m/s" in msg
        assert exc.value.hints == (Hint("units", {"velocity": "m/s", "spin": "rad/s"}),
                                   Hint("plausible", "PLAUSIBLE_RANGES.widened(min_landing_speed=...)"),
                                   Hint("plausible", "None"))
    # ... and declaring the unit, as the message says, predicts the landing
    out = LAW.predict([[20.0, -15.0, 200.0]], units={"velocity": "m/s", "spin": "rad/s"})
    np.testing.assert_allclose(out, units.from_scaled(LAW.predict(units.to_scaled(
        [[20.0, -15.0, 200.0]], velocity="m/s", spin="rad/s")), velocity="m/s", spin="rad/s"))


def test_rad_per_s_that_are_rpm_are_refused_in_scaled_units():
    with pytest.raises(bl.DataError) as exc:  # 100000 rad/s is 954930 rpm, beyond 20000 rpm: no unit fits
        LAW.predict([[1000.0, -800.0, 1e5]])
    assert (exc.value.column, exc.value.row) == ("omega0", 1) and exc.value.hints == widen_hints("max_spin")
    with pytest.raises(bl.DataError) as exc:  # the numbers look like rpm
        LAW.predict([[1000.0, -800.0, 3000.0]])
    assert (exc.value.column, exc.value.row) == ("omega0", 1)
    assert exc.value.hints == (Hint("units", {"velocity": "radius/s", "spin": "rpm"}), *widen_hints("max_spin"))


def test_the_guard_can_be_widened_or_dropped_on_purpose():
    slow = [[20.0, -15.0, 200.0]]
    expected = LAW.predict(slow, plausible=None)
    np.testing.assert_array_equal(LAW.predict(slow, plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=0.1)),
                                  expected)
    assert list(LAW.regime(slow, plausible=None)) == list(LAW.regime(
        slow, plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=0.1)))
    grazing = [[1000.0, -50.0, 200.0]]
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(grazing)
    assert exc.value.row == 1 and exc.value.hints == widen_hints("min_landing_angle")
    assert np.isfinite(LAW.predict(grazing, plausible=PLAUSIBLE_RANGES.widened(min_landing_angle=1.0))).all()
    with pytest.raises(bl.ParameterError) as exc:  # a finite number >= 0
        PLAUSIBLE_RANGES.widened(min_landing_speed=-1.0)
    assert (exc.value.parameter, exc.value.value) == ("min_landing_speed", -1.0)


def test_the_scaled_guard_uses_the_ball_radius():
    landing = [[20.0, -15.0, 200.0]]  # 25 radii/s: 0.53 m/s for a golf ball, 5 m/s for a 0.2 m ball
    with pytest.raises(bl.DataError):
        LAW.predict(landing)
    assert np.isfinite(LAW.predict(landing, radius_m=0.2)).all()
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(landing, radius_m=21.35)  # millimetres
    assert exc.value.option == "ball_radius_m"


def test_a_dataframe_landing_is_named_by_its_row_label():
    import pandas as pd

    frame = pd.DataFrame([[1000.0, -800.0, 300.0], [20.0, -15.0, 200.0]], columns=["xdot", "ydot", "omega"],
                         index=["shot-1", "shot-2"])
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(frame)
    assert (exc.value.row, exc.value.row_label) == (2, "shot-2")


@pytest.mark.parametrize("n", [1, 8, 9, 500, 3 * 4096])  # plain Python, NumPy and the compiled pass
def test_each_limit_is_found_whatever_the_number_of_landings(n):
    from bouncelab.core.plausibility import LandingFaults, landing_faults

    base = np.tile([[1000.0, -800.0, 300.0]], (n, 1))
    assert landing_faults(base) == LandingFaults()
    row = n - 1
    for kind, landing in {"slow": [20.0, -15.0, 200.0], "fast": [5000.0, -800.0, 0.0],
                          "spin": [1000.0, -800.0, 3000.0], "flat": [1000.0, -50.0, 0.0]}.items():
        p = base.copy()
        p[row] = landing
        assert landing_faults(p) == LandingFaults(**{kind: row}), kind
    p = base.copy()
    p[row, 1] = np.nan  # not a landing: left to the value check, which names it
    assert landing_faults(p) == LandingFaults(invalid=True)


def test_a_large_array_names_its_first_implausible_landing_and_its_bad_values_first():
    p = np.tile([[1000.0, -800.0, 300.0]], (60_000, 1))
    p[45_000] = [20.0, -15.0, 200.0]
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(p)
    assert exc.value.row == 45_001 and exc.value.hints[-2:] == widen_hints("min_landing_speed")
    p[50_000, 1] = np.nan  # a value no landing has: the value check names it, as without the guard
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(p)
    assert (exc.value.column, exc.value.row) == ("landing.ydot", 50_001)


def test_lazy_predictions_are_guarded_chunk_by_chunk():
    pytest.importorskip("dask")
    import xarray as xr

    p = np.tile([[1000.0, -800.0, 300.0]], (10, 1))
    p[7] = [20.0, -15.0, 200.0]
    da = xr.DataArray(p, dims=("bounce", "component"), coords={"component": ["xdot", "ydot", "omega"]}).chunk(
        {"bounce": 5})
    with pytest.raises(bl.DataError) as exc:
        LAW.predict(da).compute()
    assert exc.value.hints[-2:] == widen_hints("min_landing_speed")
    np.testing.assert_array_equal(LAW.predict(da, plausible=None).compute().values, LAW.predict(p, plausible=None))


def test_cli_refuses_a_grazing_landing_alike_in_both_forms(capsys):
    for landing in (["--landing", "1000", "-80", "300"], ["--speed-angle-spin", "20", "4.9", "2000",
                                                          "--velocity-unit", "m/s", "--spin-unit", "rpm"]):
        assert main([*PUB, *landing]) == EXIT_DATA
        err = capsys.readouterr().err
        assert "min_landing_angle" in err or "flatter than any golf landing" in err


def test_cli_refuses_m_per_s_typed_as_scaled_and_keeps_the_ball_radius(capsys):
    assert main([*PUB, "--landing", "20", "-15", "200"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "landing 1: the landing speed" in err and "--velocity-unit m/s" in err
    # with a 0.2 m ball the same numbers are a 5 m/s landing: the CLI's check and the law's agree
    assert main([*PUB, "--landing", "20", "-15", "200", "--radius-mm", "200"]) == EXIT_OK
    capsys.readouterr()
