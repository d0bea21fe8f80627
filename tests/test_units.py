"""Units and sign conventions (bouncelab.core.units).

Expected values are computed by hand from the definitions (1 ft = 0.3048 m,
1 mile = 1609.344 m, R = 21.35 mm, 1 rev = 2 pi rad), never from the module's
own constants.
"""

from __future__ import annotations

import doctest
import math
import warnings

import numpy as np
import pytest

from bouncelab.core import published, units
from bouncelab.core.errors import DataError

R = 0.02135  # the paper's ball radius in metres, typed independently of units.BALL_RADIUS_M


# --------------------------------------------------------------------------- velocities
@pytest.mark.parametrize(
    ("unit", "radii_per_s"),
    [
        ("m/s", 1.0 / 0.02135),  # 46.838... radii/s
        ("ft/s", 0.3048 / 0.02135),  # 14.276...
        ("mph", 1609.344 / 3600.0 / 0.02135),  # 20.938...
        ("km/h", 1000.0 / 3600.0 / 0.02135),  # 13.010...
        ("radius/s", 1.0),
    ],
)
def test_one_velocity_unit_in_radii_per_second(unit, radii_per_s):
    assert float(units.velocity_to_scaled(1.0, unit)) == pytest.approx(radii_per_s, rel=1e-12)
    assert float(units.velocity_from_scaled(radii_per_s, unit)) == pytest.approx(1.0, rel=1e-12)


def test_velocity_hand_values():
    # 1 m/s is 46.8384 radii/s; 10 mph = 4.4704 m/s = 209.386 radii/s.
    assert float(units.velocity_to_scaled(1.0)) == pytest.approx(46.83840749, rel=1e-9)
    assert float(units.velocity_to_scaled(10.0, "mph")) == pytest.approx(209.38642, rel=1e-7)
    assert float(units.velocity_from_scaled(2260.0, "m/s")) == pytest.approx(48.251, rel=1e-4)


def test_default_radius_is_the_papers_ball():
    assert units.BALL_RADIUS_M == R


@pytest.mark.parametrize(
    ("unit", "rad_per_s"),
    [
        ("rpm", 2.0 * math.pi / 60.0),
        ("rev/s", 2.0 * math.pi),
        ("deg/s", math.pi / 180.0),
        ("rad/s", 1.0),
    ],
)
def test_one_spin_unit_in_rad_per_second(unit, rad_per_s):
    assert float(units.spin_to_scaled(1.0, unit)) == pytest.approx(rad_per_s, rel=1e-12)
    assert float(units.spin_from_scaled(rad_per_s, unit)) == pytest.approx(1.0, rel=1e-12)


def test_spin_hand_values():
    assert float(units.spin_to_scaled(60.0, "rpm")) == pytest.approx(6.283185307, rel=1e-9)
    assert float(units.spin_to_scaled(9100.0)) == pytest.approx(952.94, abs=0.01)  # default unit rpm
    assert float(units.spin_to_scaled(180.0, "deg/s")) == pytest.approx(3.14159265, rel=1e-8)
    assert float(units.spin_from_scaled(953.0, "rpm")) == pytest.approx(9100.48, abs=0.01)


def _half_ulp_3sf(x: float) -> float:
    """Half a unit in the last place of ``x`` printed to 3 significant figures."""
    return 0.5 * 10.0 ** (math.floor(math.log10(abs(x))) - 2)


@pytest.mark.parametrize(("campaign", "end"), [("A", "min"), ("A", "max"), ("B", "min")])
def test_table1_spin_ranges_agree_with_scaled_omega(campaign, end):
    """Table 1's omega column is its rpm column converted, within the rounding of both (3 s.f.)."""
    rpm = published.TABLE1.loc[(campaign, "spin"), end]
    omega = published.TABLE1.loc[(campaign, "omega"), end]
    converted = float(units.spin_to_scaled(rpm, "rpm"))
    tol = _half_ulp_3sf(rpm) * 2.0 * math.pi / 60.0 + _half_ulp_3sf(omega)
    assert abs(converted - omega) <= tol


def test_table1_campaign_a_max_spin_9100_rpm_is_953_rad_per_s():
    assert round(float(units.spin_to_scaled(9100.0, "rpm"))) == 953


def test_table1_campaign_b_max_spin_is_inconsistent_in_the_paper():
    """The paper prints 16200 rpm but 1670 rad/s (= 15950 rpm): 1.6 % apart, beyond rounding.

    The transcription keeps both numbers as printed; this test documents the
    paper's own inconsistency so nobody "fixes" one of them silently.
    """
    rpm = published.TABLE1.loc[("B", "spin"), "max"]
    omega = published.TABLE1.loc[("B", "omega"), "max"]
    assert (rpm, omega) == (16200.0, 1670.0)
    converted = float(units.spin_to_scaled(rpm, "rpm"))
    assert converted == pytest.approx(1696.5, abs=0.1)
    assert abs(converted - omega) > _half_ulp_3sf(rpm) * 2 * math.pi / 60 + _half_ulp_3sf(omega)


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_table1_scaled_velocity_components_bounded_by_speed(campaign):
    """|xdot| and |ydot| can never exceed the speed: check Table 1's columns against each other."""
    t1 = published.TABLE1.loc[campaign]
    vmax = float(units.velocity_to_scaled(t1.loc["speed", "max"], "m/s"))
    assert t1.loc["xdot", "max"] <= vmax
    assert -t1.loc["ydot", "min"] <= vmax
    # the slowest vertical landing is no faster than the slowest ball (3 s.f. rounding allowed)
    vmin = float(units.velocity_to_scaled(t1.loc["speed", "min"], "m/s"))
    assert -t1.loc["ydot", "max"] <= vmin * 1.01


# --------------------------------------------------------------------------- driver landing
def test_driver_landing_by_hand():
    s = 93.6 * 0.3048 / R  # 1336.25 radii/s
    a = math.radians(37.3)
    expected = [s * math.cos(a), -s * math.sin(a), 34.9 * 2 * math.pi]
    got = units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
    assert got.shape == (3,)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    np.testing.assert_allclose(got, [1062.9, -809.8, 219.3], atol=0.1)


def test_driver_landing_from_published_dict_round_trips():
    d = published.DRIVER_LANDING
    p0 = units.landing_from_speed_angle_spin(
        d["speed"], d["angle_deg"], d["spin"], speed_unit=d["speed_unit"], spin_unit=d["spin_unit"]
    )
    back = units.speed_angle_spin(p0, speed_unit="ft/s", spin_unit="rev/s")
    assert float(back["speed"]) == pytest.approx(93.6, rel=1e-12)
    assert float(back["angle_deg"]) == pytest.approx(37.3, rel=1e-12)
    assert float(back["spin"]) == pytest.approx(34.9, rel=1e-12)
    assert float(units.tangential_velocity(p0)) == pytest.approx(1062.9 + 219.3, abs=0.2)


def test_landing_broadcasts_and_signs():
    p0 = units.landing_from_speed_angle_spin([10.0, 20.0], 30.0, [-1000.0, 2000.0])
    assert p0.shape == (2, 3)
    assert np.all(p0[:, 0] > 0) and np.all(p0[:, 1] < 0)
    np.testing.assert_allclose(p0[:, 0], np.array([10.0, 20.0]) / R * math.cos(math.pi / 6), rtol=1e-12)
    np.testing.assert_allclose(p0[:, 1], -np.array([10.0, 20.0]) / R * 0.5, rtol=1e-12)
    np.testing.assert_allclose(p0[:, 2], np.array([-1000.0, 2000.0]) * math.pi / 30, rtol=1e-12)


def test_vertical_landing_allowed():
    p0 = units.landing_from_speed_angle_spin(2.0, 90.0, 0.0)
    assert abs(p0[0]) < 1e-9
    assert p0[1] == pytest.approx(-2.0 / R, rel=1e-12)


@pytest.mark.parametrize("angle", [0.0, -10.0, 90.01, 120.0, float("nan"), float("inf")])
def test_landing_angle_out_of_range(angle):
    with pytest.raises(DataError) as e:
        units.landing_from_speed_angle_spin(10.0, angle, 1000.0)
    assert e.value.column == "angle"


def test_landing_angle_out_of_range_in_an_array():
    with pytest.raises(DataError) as e:
        units.landing_from_speed_angle_spin([10.0, 10.0], [30.0, 95.0], 1000.0)
    assert e.value.column == "angle" and "(element (1,))" in e.value.message


@pytest.mark.parametrize("speed", [0.0, -5.0, float("nan"), float("inf")])
def test_landing_speed_must_be_positive_and_finite(speed):
    with pytest.raises(DataError) as e:
        units.landing_from_speed_angle_spin(speed, 30.0, 1000.0)
    assert e.value.column == "speed"


@pytest.mark.parametrize("spin", [float("nan"), float("inf")])
def test_landing_spin_must_be_finite(spin):
    with pytest.raises(DataError) as e:
        units.landing_from_speed_angle_spin(10.0, 30.0, spin)
    assert e.value.column == "spin"


def test_speed_angle_spin_of_liftoff_has_negative_angle():
    out = units.speed_angle_spin([[300.0, 400.0, 10.0]], speed_unit="radius/s", spin_unit="rad/s")
    assert out["speed"][0] == pytest.approx(500.0)
    assert out["angle_deg"][0] == pytest.approx(-math.degrees(math.atan2(400.0, 300.0)))
    assert out["spin"][0] == pytest.approx(10.0)


# --------------------------------------------------------------------------- whole states
def test_to_scaled_state_by_hand():
    state = np.array([[10.0, -5.0, 3000.0], [1.0, -1.0, -600.0]])
    before = state.copy()
    got = units.to_scaled(state)  # m/s and rpm by default
    expected = np.array([[10.0 / R, -5.0 / R, 100.0 * math.pi], [1.0 / R, -1.0 / R, -20.0 * math.pi]])
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    np.testing.assert_array_equal(state, before)  # input untouched


@pytest.mark.parametrize(("velocity", "spin"), [("m/s", "rpm"), ("ft/s", "rev/s"), ("mph", "deg/s"),
                                                ("km/h", "rad/s"), ("radius/s", "rpm")])
def test_state_round_trip(velocity, spin):
    rng = np.random.default_rng(1)
    state = rng.normal(size=(4, 2, 3)) * [30.0, 20.0, 5000.0]
    scaled = units.to_scaled(state, velocity=velocity, spin=spin)
    assert scaled.shape == state.shape
    back = units.from_scaled(scaled, velocity=velocity, spin=spin)
    np.testing.assert_allclose(back, state, rtol=1e-12)


def test_from_scaled_by_hand():
    got = units.from_scaled([1.0 / R, -2.0 / R, 2 * math.pi], velocity="m/s", spin="rev/s")
    np.testing.assert_allclose(got, [1.0, -2.0, 1.0], rtol=1e-12)


def test_radius_is_settable():
    assert float(units.velocity_to_scaled(1.0, "m/s", radius_m=0.5)) == pytest.approx(2.0)
    assert float(units.velocity_from_scaled(2.0, "m/s", radius_m=0.5)) == pytest.approx(1.0)
    got = units.to_scaled([1.0, -1.0, 60.0], radius_m=0.25)
    np.testing.assert_allclose(got, [4.0, -4.0, 2 * math.pi], rtol=1e-12)
    back = units.from_scaled(got, radius_m=0.25)
    np.testing.assert_allclose(back, [1.0, -1.0, 60.0], rtol=1e-12)
    p0 = units.landing_from_speed_angle_spin(1.0, 90.0, 0.0, radius_m=0.1)
    assert p0[1] == pytest.approx(-10.0)
    assert float(units.speed_angle_spin(p0, radius_m=0.1)["speed"]) == pytest.approx(1.0)


@pytest.mark.parametrize("radius", [0.0, -0.02, float("nan"), float("inf")])
def test_bad_radius(radius):
    for call in (lambda: units.velocity_to_scaled(1.0, radius_m=radius),
                 lambda: units.to_scaled([1.0, -1.0, 0.0], radius_m=radius)):
        with pytest.raises(DataError) as e:
            call()
        assert e.value.option == "radius_m"


def test_scaled_velocity_is_a_copy():
    v = np.array([1.0, 2.0])
    out = units.velocity_to_scaled(v, "radius/s")
    out[0] = 99.0
    assert v[0] == 1.0


# --------------------------------------------------------------------------- unit spellings
@pytest.mark.parametrize(
    ("alias", "canon"),
    [("m/s", "m/s"), ("M/S", "m/s"), ("mps", "m/s"), ("m s-1", "m/s"), (" m s^-1 ", "m/s"),
     ("fps", "ft/s"), ("FT/SEC", "ft/s"), ("mi/h", "mph"), ("MPH", "mph"),
     ("kph", "km/h"), ("km/h", "km/h"), ("KMH", "km/h"),
     ("radii/s", "radius/s"), ("scaled", "radius/s"), ("1/s", "radius/s"), ("s^-1", "radius/s")],
)
def test_velocity_aliases(alias, canon):
    assert units.canonical_unit(alias, "velocity") == canon
    assert float(units.velocity_to_scaled(3.0, alias)) == float(units.velocity_to_scaled(3.0, canon))


@pytest.mark.parametrize(
    ("alias", "canon"),
    [("rpm", "rpm"), ("RPM", "rpm"), ("rev/min", "rpm"), ("rot per min", "rpm"), ("r/min", "rpm"),
     ("rps", "rev/s"), ("Hz", "rev/s"), ("rev/s", "rev/s"), ("deg/s", "deg/s"), ("°/s", "deg/s"),
     ("rad/s", "rad/s"), ("rad/sec", "rad/s"), ("rad s^-1", "rad/s")],
)
def test_spin_aliases(alias, canon):
    assert units.canonical_unit(alias, "spin") == canon
    assert float(units.spin_to_scaled(7.0, alias)) == float(units.spin_to_scaled(7.0, canon))


@pytest.mark.parametrize("unit", ["furlong/fortnight", "", "m", "knots"])
def test_unknown_velocity_unit(unit):
    with pytest.raises(DataError) as e:
        units.velocity_to_scaled(1.0, unit)
    assert e.value.option == "velocity"
    with pytest.raises(DataError):
        units.to_scaled([1.0, -1.0, 1.0], velocity=unit)


@pytest.mark.parametrize("unit", ["rad", "rpms", "cycles", ""])
def test_unknown_spin_unit(unit):
    with pytest.raises(DataError) as e:
        units.spin_to_scaled(1.0, unit)
    assert e.value.option == "spin"
    with pytest.raises(DataError):
        units.from_scaled([1.0, -1.0, 1.0], spin=unit)


def test_unit_of_the_wrong_kind():
    with pytest.raises(DataError) as e:
        units.velocity_to_scaled(1.0, "rpm")
    assert e.value.option == "velocity"
    with pytest.raises(DataError) as e:
        units.spin_to_scaled(1.0, "m/s")
    assert e.value.option == "spin"
    with pytest.raises(DataError):
        units.spin_to_scaled(1.0, "radius/s")


def test_unknown_unit_error_lists_the_known_units():
    with pytest.raises(DataError) as info:
        units.spin_to_scaled(1.0, "bogus")
    for known in ("rpm", "rev/s", "deg/s", "rad/s"):
        assert known in str(info.value)


# --------------------------------------------------------------------------- shapes
@pytest.mark.parametrize("bad", [[1.0, 2.0], np.zeros((5, 2)), np.zeros((2, 4)), 3.0, np.zeros((3, 3, 1))])
def test_wrong_shape(bad):
    for fn in (units.to_scaled, units.from_scaled, units.tangential_velocity, units.speed_angle_spin):
        with pytest.raises(DataError):  # numpy would raise IndexError or broadcast the shape
            fn(bad)


def test_non_numeric_state():
    with pytest.raises(DataError):  # numpy's own ValueError before
        units.to_scaled(["a", "b", "c"])
    with pytest.raises(DataError):
        units.velocity_to_scaled("fast")


def test_tangential_velocity_is_xdot_plus_omega():
    assert float(units.tangential_velocity([10.0, -5.0, 3.0])) == 13.0
    got = units.tangential_velocity([[100.0, -50.0, -130.0], [-20.0, -1.0, 20.0], [0.0, -1.0, 7.0]])
    np.testing.assert_array_equal(got, [-30.0, 0.0, 7.0])
    assert units.tangential_velocity(np.ones((2, 4, 3))).shape == (2, 4)


def test_components_and_units_constants():
    assert units.COMPONENTS == ("xdot", "ydot", "omega")
    assert units.COMPONENT_UNITS == ("radius/s", "radius/s", "rad/s")


def test_docstring_examples():
    result = doctest.testmod(units, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 1
    assert result.failed == 0


def test_conversion_overflow_is_silent_inf_for_the_state_checks_to_refuse():
    import warnings

    from bouncelab.core.units import velocity_from_scaled, velocity_to_scaled

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no NumPy RuntimeWarning reaches the user
        assert np.isinf(velocity_to_scaled(np.array([1e308]), "m/s")).all()
        assert np.isinf(velocity_from_scaled(np.array([1e308]), "mph", radius_m=10.0)).all()


# ---------------------------------------------------------------------------
# polar_halfwidths_to_cartesian
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(("kind", "polar"), [
    ("landing", [25.0, 40.0, 3000.0]), ("landing", [18.0, 88.0, -1200.0]),
    ("liftoff", [12.0, 20.0, 1500.0]), ("liftoff", [9.8, 105.0, 600.0]), ("liftoff", [10.1, 0.0, 590.0]),
])
def test_polar_halfwidths_match_a_monte_carlo_of_small_independent_errors(kind, polar):
    # 95 % half-widths of Gaussian errors (sd = h / 1.96): the propagated half-width of each component is
    # the 95 % quantile of its error, which a Monte Carlo through state_from_polar measures independently.
    hw = np.array([0.2, 0.5, 50.0])  # m/s, degrees, rpm: small enough for the first order to hold
    rng = np.random.default_rng(11)
    draws = np.asarray(polar) + rng.standard_normal((400_000, 3)) * hw / 1.96
    errors = units.state_from_polar(draws, kind=kind) - units.state_from_polar(polar, kind=kind)
    empirical = np.quantile(np.abs(errors), 0.95, axis=0)
    got = units.polar_halfwidths_to_cartesian(polar, hw, kind=kind)
    np.testing.assert_allclose(got, empirical, rtol=0.01)


def test_polar_halfwidths_units_broadcasting_and_degrees():
    polar = np.array([[25.0, 40.0, 3000.0], [18.0, 55.0, -1200.0]])
    got = units.polar_halfwidths_to_cartesian(polar, [0.5, 1.0, 100.0])
    # The same in ft/s and rev/s, with another ball: scaled by the radius, spin half-width as rad/s.
    ft = units.polar_halfwidths_to_cartesian(polar / [0.3048, 1, 60], [0.5 / 0.3048, 1.0, 100 / 60],
                                             speed_unit="ft/s", spin_unit="rev/s")
    np.testing.assert_allclose(ft, got, rtol=1e-12)
    big = units.polar_halfwidths_to_cartesian(polar, [0.5, 1.0, 100.0], radius_m=2 * units.BALL_RADIUS_M)
    np.testing.assert_allclose(big[:, :2], got[:, :2] / 2, rtol=1e-12)
    np.testing.assert_allclose(got[:, 2], 100 * 2 * math.pi / 60, rtol=1e-15)  # never negated
    # Only an angle error, at 90 degrees: all of it in xdot, v * h_a with h_a in radians.
    only_angle = units.polar_halfwidths_to_cartesian([25.0, 90.0, 0.0], [0.0, 1.0, 0.0])
    np.testing.assert_allclose(only_angle, [25.0 / units.BALL_RADIUS_M * math.pi / 180, 0.0, 0.0], atol=1e-9)
    assert got.shape == (2, 3)


@pytest.mark.parametrize(("polar", "hw", "kind", "field"), [
    ([25.0, 40.0, 3000.0], [-0.5, 1.0, 100.0], "landing", {"option": "halfwidths"}),
    ([25.0, 40.0, 3000.0], [0.5, np.nan, 100.0], "landing", {"option": "halfwidths"}),
    ([25.0, 40.0, 3000.0], [0.5, 1.0, np.inf], "landing", {"option": "halfwidths"}),
    ([25.0, -40.0, 3000.0], [0.5, 1.0, 100.0], "landing", {"column": "angle"}),
    ([-2.0, 40.0, 3000.0], [0.5, 1.0, 100.0], "liftoff", {"column": "speed"}),
    ([25.0, 40.0, 3000.0], [0.5, 1.0], "landing", {"option": "halfwidths"}),
    ([25.0, 40.0, 3000.0], [0.5, "x", 1.0], "landing", {"option": "halfwidths"}),
])
def test_polar_halfwidths_refuse_bad_input(polar, hw, kind, field):
    with pytest.raises(DataError) as exc:
        units.polar_halfwidths_to_cartesian(polar, hw, kind=kind)
    assert {k: getattr(exc.value, k) for k in field} == field


def test_polar_halfwidths_refuse_shapes_overflow_and_booleans():
    # Before: shapes that do not broadcast raised numpy's ValueError (the docstring promises DataError), an
    # overflow came back as inf, and True was a half-width of 1.
    polar = np.array([[25.0, 40.0, 3000.0], [18.0, 55.0, -1200.0]])
    with pytest.raises(DataError) as e:
        units.polar_halfwidths_to_cartesian(polar, np.ones((3, 3)))
    assert e.value.option == "halfwidths"
    assert units.polar_halfwidths_to_cartesian(polar, np.ones((1, 3))).shape == (2, 3)  # broadcasts: fine
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # and no NumPy RuntimeWarning on the way
        with pytest.raises(DataError) as e:
            units.polar_halfwidths_to_cartesian([25.0, 40.0, 3000.0], [1e308, 1.0, 1.0])
        assert (e.value.column, e.value.row) == ("xdot", None)
        with pytest.raises(DataError) as e:
            units.polar_halfwidths_to_cartesian([[25.0, 40.0, 3000.0], [1e300, 0.0, 0.0]], [0.5, 1e10, 1.0],
                                              kind="liftoff")
        assert (e.value.column, e.value.row) == ("ydot", 2)
    for hw in (np.array([True, True, True]), [0.5, True, 100.0], [[0.5, 1.0, 100.0], [False, 1.0, 1.0]]):
        with pytest.raises(DataError) as e:
            units.polar_halfwidths_to_cartesian([25.0, 40.0, 3000.0], hw)
        assert e.value.option == "halfwidths" and "boolean" in e.value.message
    with pytest.raises(DataError) as e:
        units.polar_halfwidths_to_cartesian(np.array([True, True, True]), [0.5, 1.0, 100.0])
    assert e.value.option == "polar"
