"""From landing to rest (bouncelab.ground.run): closed forms, an independent integration, the path (issue 25, 2)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import DataError, ParameterError
from bouncelab.ground import PHASES, PRESET_NAMES, Air, BounceLimitWarning, Surface, preset, run

R = 0.02135
G = 9.81
SI = {"velocity": "m/s", "spin": "rad/s"}
Z = np.array([0.0, 0.0, 1.0])


def green(stimp_m: float = 3.0, mu_s: float = 0.4, law=None) -> Surface:
    return Surface(name="test green", law=law or bl.Rigid(r=0.4, mu=0.5), sliding_friction=mu_s, stimp_m=stimp_m)


def rolling_spin(v: np.ndarray, n: np.ndarray = Z) -> np.ndarray:
    """The spin (rad/s) of a ball rolling with velocity v (m/s) on the plane of normal n: n x omega = -v."""
    return np.cross(n, v) / R


def slope(theta_deg: float, phi_deg: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """Unit normal of a plane tilted by theta towards azimuth phi, and its downhill unit vector."""
    th, ph = math.radians(theta_deg), math.radians(phi_deg)
    n = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    down = -(Z - n[2] * n)
    return n, down / np.linalg.norm(down)


# ------------------------------------------------------------------------------ closed forms
@pytest.mark.parametrize("name", ["green-slow", "green-medium", "green-fast"])
def test_the_stimpmeter_ball_stops_at_the_stimpmeter_reading(name):
    """1.83 m/s, rolling, on flat ground, in any direction: it stops at the reading."""
    surface = preset(name)
    heading = np.radians([0.0, 37.0, 200.0])
    v = 1.83 * np.column_stack([np.cos(heading), np.sin(heading), np.zeros(3)])
    r = run(v, rolling_spin(v), surface, units=SI)
    np.testing.assert_allclose(np.linalg.norm(r.rest_position, axis=1), surface.stimp_m, rtol=1e-12)
    assert (r.totals["skid_time"] <= 1e-12).all() and (r.totals["bounces"] == 0).all()  # rolling: no skid
    np.testing.assert_allclose(r.rest_time, 2 * surface.stimp_m / 1.83, rtol=1e-12)


@pytest.mark.parametrize("theta", [0.5, 1.0, 2.0, 3.0])
def test_the_usga_slope_formula_gives_back_the_flat_reading(theta):
    """Up and down the fall line: 2 S_up S_down / (S_up + S_down) = S / cos(theta) (rolling resistance grows
    with the normal load), within 1/cos(theta) - 1 of the flat reading; each run as its closed form."""
    surface = preset("green-medium")
    s = surface.stimp_m
    n, down = slope(theta)
    runs = {}
    for name, d in (("up", -down), ("down", down)):
        v = 1.83 * d
        r = run(v, rolling_spin(v, n), surface, normal=n, units=SI)
        runs[name] = float(np.linalg.norm(r.rest_position))
    th = math.radians(theta)
    a = surface.rolling_resistance * G * math.cos(th)
    assert runs["up"] == pytest.approx(1.83 ** 2 / (2 * (a + 5 / 7 * G * math.sin(th))), rel=1e-12)
    assert runs["down"] == pytest.approx(1.83 ** 2 / (2 * (a - 5 / 7 * G * math.sin(th))), rel=1e-12)
    usga = 2 * runs["up"] * runs["down"] / (runs["up"] + runs["down"])
    assert usga == pytest.approx(s / math.cos(th), rel=1e-12)
    assert abs(usga / s - 1) <= 1 / math.cos(th) - 1 + 1e-12


def test_a_sliding_ball_without_spin_rolls_at_five_sevenths_of_its_speed_after_2v_over_7_mu_g():
    surface = green(stimp_m=3.0, mu_s=0.3)
    v0 = 4.0
    r = run([v0, 0.0, 0.0], [0.0, 0.0, 0.0], surface, units=SI, rate=1000.0)
    ts = 2 * v0 / (7 * 0.3 * G)
    assert r.totals["skid_time"][0] == pytest.approx(ts, rel=1e-12)
    ds = r.path
    skid_end = ds["event_kind"].values[0] == 1
    assert float(ds["event_time"].values[0][skid_end][0]) == pytest.approx(ts, rel=1e-12)
    # the first rolling sample: 5/7 v0 less the rolling deceleration since the skid ended
    k = int(np.argmax(ds["phase"].values[0] == PHASES.index("roll")))
    t = float(ds["time"][k])
    expected = 5 / 7 * v0 - surface.rolling_deceleration * (t - ts)
    assert float(ds["velocity"].values[0, k, 0]) == pytest.approx(expected, rel=1e-12)
    skid = v0 * ts - 0.5 * 0.3 * G * ts ** 2
    roll = (5 / 7 * v0) ** 2 / (2 * surface.rolling_deceleration)
    assert r.rest_position[0, 0] == pytest.approx(skid + roll, rel=1e-12)


def test_a_ball_with_backspin_on_the_ground_spins_back():
    """Velocity change -2/7 of the contact-point slip u0 = v + omega R: strong backspin reverses the ball."""
    surface = green(stimp_m=3.0, mu_s=0.4)
    v0, w = 2.0, 400.0  # rad/s of backspin: omega R = 8.5 m/s
    r = run([v0, 0.0, 0.0], [0.0, -w, 0.0], surface, units=SI)
    u0 = v0 + w * R
    v_end = v0 - 2 / 7 * u0
    ts = 2 * u0 / (7 * 0.4 * G)
    skid = v0 * ts - 0.5 * 0.4 * G * ts ** 2
    roll = -v_end ** 2 / (2 * surface.rolling_deceleration)
    assert v_end < 0
    assert r.rest_position[0, 0] == pytest.approx(skid + roll, rel=1e-12)
    assert r.totals["roll"][0] < 0 and r.totals["bounces"][0] == 0


def test_bounces_without_friction_are_the_closed_form_bouncing_ball():
    """Frictionless rigid law: vz_k = r^k vz, flights 2 vz_k / g, until the apex falls below min_apex_m."""
    r_, vx, vz, h = 0.5, 6.0, 5.0, 0.002
    surface = green(law=bl.Rigid(r=r_, mu=0.0), mu_s=0.4)
    res = run([vx, 0.0, -vz], [0.0, 0.0, 0.0], surface, units=SI, min_apex_m=h)
    ups = []
    k = 1
    while (r_ ** k * vz) ** 2 / (2 * G) > h:
        ups.append(r_ ** k * vz)
        k += 1
    t = res.totals.iloc[0]
    assert t["bounces"] == len(ups) + 1
    carry = sum(vx * 2 * u / G for u in ups)
    assert t["bounce_carry"] == pytest.approx(carry, rel=1e-12)
    assert t["liftoff_speed"] == pytest.approx(math.hypot(vx, r_ * vz), rel=1e-12)
    assert t["liftoff_angle_deg"] == pytest.approx(math.degrees(math.atan2(r_ * vz, vx)), rel=1e-12)
    ts = 2 * vx / (7 * 0.4 * G)  # no spin: skid, then roll at 5/7 vx
    rest = carry + vx * ts - 0.2 * G * ts ** 2 + (5 / 7 * vx) ** 2 / (2 * surface.rolling_deceleration)
    assert res.rest_position[0, 0] == pytest.approx(rest, rel=1e-12)
    assert res.rest_time[0] == pytest.approx(sum(2 * u / G for u in ups) + ts
                                             + 5 / 7 * vx / surface.rolling_deceleration, rel=1e-12)


def test_scaled_and_physical_units_give_the_same_run():
    surface = preset("turf-B")
    v = np.array([[20.0, 2.0, -12.0], [8.0, -1.0, -4.0]])
    w = np.array([[0.0, -500.0, 30.0], [20.0, 100.0, 0.0]])
    phys = run(v, w, surface, units=SI)
    scaled = run(v / R, w, surface)
    np.testing.assert_allclose(phys.rest_position, scaled.rest_position * R, rtol=1e-11, atol=1e-12)
    assert phys.length_unit == "m" and scaled.length_unit == "radius"
    np.testing.assert_allclose(phys.totals["liftoff_speed"], scaled.totals["liftoff_speed"] * R, rtol=1e-12)


# ------------------------------------------------------------------------------ an independent integration
def reference_on_slope(v0: np.ndarray, w0: np.ndarray, n: np.ndarray, mu_s: float, mu_r: float,
                       times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Skid then roll on a plane with scipy's solve_ivp (scaled units): the rest position of the lowest point
    and the positions at ``times`` (s)."""
    from scipy.integrate import solve_ivp

    g = G / R
    gt = -g * (Z - n[2] * n)
    gn = g * n[2]

    def slip(y):
        return y[3:6] + np.cross(n, y[6:9])

    def skid(_t, y):
        u = slip(y)
        f = -mu_s * gn * u / np.linalg.norm(u)
        return np.concatenate([y[3:6], gt + f, -2.5 * np.cross(n, f)])

    def slip_stops(_t, y):
        return np.linalg.norm(slip(y)) - 1e-11 * np.linalg.norm(slip(y0))
    slip_stops.terminal = True

    y0 = np.concatenate([np.zeros(3), v0, w0])
    a = solve_ivp(skid, (0, 1e3), y0, rtol=1e-12, atol=1e-12, events=slip_stops, dense_output=True)
    ts = a.t[-1]

    def roll(_t, y):
        v = y[3:6]
        return np.concatenate([v, 5 / 7 * gt - mu_r * gn * v / np.linalg.norm(v)])

    def stops(_t, y):
        return np.linalg.norm(y[3:6]) - 1e-11 * np.linalg.norm(v0)
    stops.terminal = True

    b = solve_ivp(roll, (ts, 1e4), a.y[:6, -1], rtol=1e-12, atol=1e-12, events=stops, dense_output=True)
    at = np.array([a.sol(t)[:3] if t < ts else b.sol(min(t, b.t[-1]))[:3] for t in times])
    return b.y[:3, -1], at


@pytest.mark.parametrize(("theta", "heading", "spin"), [(2.0, 90.0, (0.0, 0.0, 0.0)),
                                                        (3.0, 40.0, (80.0, -300.0, 20.0)),
                                                        (1.0, 170.0, (-150.0, 60.0, 0.0))])
def test_skid_and_roll_across_a_slope_agree_with_solve_ivp(theta, heading, spin):
    """A curving run (velocity across the fall line: the closed-form curved glide) against scipy, to 1e-9 of its
    length, at rest and along the path."""
    surface = preset("green-fast")
    n, _down = slope(theta, 15.0)
    h = math.radians(heading)
    v = np.array([math.cos(h), math.sin(h), 0.0])
    v = 2.5 / R * (v - (v @ n) * n) / np.linalg.norm(v - (v @ n) * n)  # 2.5 m/s along the plane
    w = np.array(spin)
    r = run(v, w, surface, normal=n, rate=10.0)
    ds = r.path
    expected, along = reference_on_slope(v, w, n, surface.sliding_friction, surface.rolling_resistance,
                                         ds["time"].values)
    length = np.linalg.norm(expected)
    assert np.linalg.norm(r.rest_position[0] - expected) <= 1e-9 * length, (r.rest_position[0], expected)
    assert np.abs(ds["position"].values[0] - along).max() <= 1e-9 * length
    assert abs(r.rest_position[0] @ n) <= 1e-9 * length  # it stays on the plane


# ------------------------------------------------------------------------------ the path
def test_the_path_is_consistent_with_the_events_and_the_rest():
    v = np.array([[25.0, 1.0, -18.0], [12.0, 0.0, -10.0], [3.0, 0.0, 0.0]])
    w = np.array([[0.0, -250.0, 10.0], [0.0, -900.0, 0.0], [0.0, 0.0, 0.0]])
    r = run(v, w, preset("green-medium"), units=SI, rate=200.0)
    ds = r.path
    assert ds["position"].dims == ("shot", "time", "axis") and ds.sizes["shot"] == 3
    np.testing.assert_array_equal(ds["position"].values[:, 0], 0.0)
    np.testing.assert_allclose(ds["position"].values[:, -1], r.rest_position, rtol=1e-12, atol=1e-12)
    assert (np.diff(ds["phase"].values.astype(int), axis=1) >= 0).all()  # flight, skid, roll, rest in order
    assert (ds["phase"].values[:, -1] == PHASES.index("rest")).all()
    assert (ds["position"].sel(axis="z").values >= -1e-9).all()  # never below flat ground
    kinds = ds["event_kind"].values
    for i in range(3):
        k = kinds[i][kinds[i] >= 0]
        assert list(k) == [0] * int(r.totals["bounces"][i]) + [1, 2]
        times = ds["event_time"].values[i][kinds[i] >= 0]
        assert (np.diff(times) >= 0).all() and times[-1] == pytest.approx(r.rest_time[i], rel=1e-15)
    bounces = ds["event_position"].values[kinds == 0]
    assert np.abs(bounces[:, 2]).max() <= 1e-9
    # velocity in flight is the derivative of the position (central differences at 200 Hz, within one flight)
    t = ds["time"].values
    bounce_times = ds["event_time"].values[0][kinds[0] == 0]
    one_flight = (np.searchsorted(bounce_times, t[:-2], side="right")
                  == np.searchsorted(bounce_times, t[2:], side="right")) & (ds["phase"].values[0, 2:] == 0)
    assert one_flight.sum() > 100
    x = ds["position"].values[0, :, 0]
    dx = (x[2:] - x[:-2]) * 100.0
    np.testing.assert_allclose(dx[one_flight], ds["velocity"].values[0, 1:-1, 0][one_flight], rtol=1e-9)
    z = ds["position"].values[0, :, 2]
    dz = (z[2:] - z[:-2]) * 100.0
    np.testing.assert_allclose(dz[one_flight], ds["velocity"].values[0, 1:-1, 2][one_flight], rtol=1e-6, atol=1e-9)
    assert ds.attrs["ball_radius_m"] == R and "lowest point" in ds.attrs["conventions"]
    assert r.sample(10.0).sizes["time"] < ds.sizes["time"]


def test_a_ball_on_the_ground_starts_skidding_or_rolling():
    v = np.array([[2.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    w = np.vstack([rolling_spin(v[0]), [0.0, 0.0, 0.0], [0.0, 0.0, 5.0]])
    r = run(v, w, green(), units=SI)
    t = r.totals
    assert (t["bounces"] == 0).all() and t["liftoff_speed"].isna().all()
    assert t["skid_time"][0] == 0 and t["skid_time"][1] > 0
    assert r.rest_time[2] == 0 and (r.rest_position[2] == 0).all()


def test_air_without_drag_or_lift_is_the_vacuum_flight_and_drag_shortens_the_run():
    v = np.array([[20.0, 0.0, -15.0], [10.0, 3.0, -12.0]])
    w = np.array([[0.0, -300.0, 0.0], [0.0, -600.0, 40.0]])
    surface = preset("turf-A")
    vac = run(v, w, surface, units=SI)
    still = run(v, w, surface, units=SI, air=Air(drag_coefficient=0.0, lift_slope=0.0))
    np.testing.assert_allclose(still.rest_position, vac.rest_position, rtol=1e-9)
    assert (still.totals["bounces"] == vac.totals["bounces"]).all()
    drag = run(v, w, surface, units=SI, air=Air(lift_slope=0.0))
    assert (drag.totals["bounce_carry"] < vac.totals["bounce_carry"]).all()
    # lift alone (a frictionless bounce keeps the spin): backspin holds the ball up longer, topspin pulls it down
    slick = surface.replace(law=bl.Rigid(r=0.5, mu=0.0))
    for sign in (1.0, -1.0):
        spin = [0.0, -sign * 500.0, 0.0]  # backspin for travel in +x, then topspin
        lifted = run([15.0, 0.0, -10.0], spin, slick, units=SI, air=Air(drag_coefficient=0.0)).path
        plain = run([15.0, 0.0, -10.0], spin, slick, units=SI).path
        longer = lifted["event_time"].values[0, 1] > plain["event_time"].values[0, 1]
        assert longer == (sign > 0)
    ds = drag.sample(100.0)
    assert (ds["position"].sel(axis="z").values >= -1e-9).all()


def test_a_law_that_never_lets_the_ball_settle_hits_the_bounce_limit():
    """The published piecewise-affine law lifts a ball off with ydotF > 0 even for ydot0 -> 0 (its offsets)."""
    surface = preset("turf-A").replace(law=bl.PiecewiseAffine.published("A"))
    with pytest.warns(BounceLimitWarning, match="still bouncing after max_bounces=30"):
        r = run([10.0, 0.0, -8.0], [0.0, -200.0, 0.0], surface, units=SI, max_bounces=30)
    assert bool(r.totals["bounce_limit"][0]) and r.totals["bounces"][0] == 30


def test_liftoffs_into_the_ground_end_the_bounces_and_are_counted():
    """The published PennerFixed law of campaign B sends a steep landing with heavy backspin into the ground."""
    surface = preset("turf-B").replace(law=bl.PennerFixed.published("B"))
    rpm = 2 * np.pi / 60
    v = 5.0 * np.array([math.cos(math.radians(80)), 0.0, -math.sin(math.radians(80))])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the run handles it: no NonphysicalLiftoffWarning escapes
        r = run(v, [0.0, -10000.0 * rpm, 0.0], surface, units=SI)
    assert r.totals["into_ground"][0] == 1 and r.totals["bounces"][0] == 1
    assert r.totals["liftoff_angle_deg"][0] < 0


# ------------------------------------------------------------------------------ refusals
def test_bad_runs_are_refused_with_typed_errors_naming_the_row():
    s = green()
    with pytest.raises(DataError) as err:  # moves away from the ground
        run([[3.0, 0.0, -1.0], [3.0, 0.0, 1.0]], [0.0, 0.0, 0.0], s, units=SI)
    assert (err.value.column, err.value.row) == ("velocity", 2)
    n, _ = slope(10.0)
    with pytest.raises(DataError) as err:  # too steep: the ball comes to rest only on gentler slopes
        run([3.0, 0.0, 0.0], [0.0, 0.0, 0.0], s, normal=[[0, 0, 1], n], units=SI)
    assert (err.value.column, err.value.row, err.value.option) == ("normal", 2, None)
    assert "comes to rest only on slopes under" in err.value.message  # the limit is said
    with pytest.raises(DataError) as err:
        run(np.empty((0, 3)), np.empty((0, 3)), s)
    assert (err.value.option, err.value.row) == ("velocity", None)  # no rows
    with pytest.raises(DataError) as err:  # does not point up
        run([3.0, 0.0, 0.0], [0.0, 0.0, 0.0], s, normal=(0, 0, -1))
    assert (err.value.column, err.value.row, err.value.option) == ("normal", 1, None)
    with pytest.raises(ParameterError) as err:
        run([3.0, 0.0, 0.0], [0.0, 0.0, 0.0], bl.Rigid(r=0.5, mu=0.5))
    assert err.value.parameter == "surface"
    with pytest.raises(ParameterError) as err:  # no such preset
        run([3.0, 0.0, 0.0], [0.0, 0.0, 0.0], "carpet")
    assert (err.value.parameter, err.value.value) == ("surface", "carpet")
    for kw in ({"rate": 0}, {"min_apex_m": -1}, {"max_bounces": 0}, {"air": "thin"}):
        with pytest.raises(ParameterError) as err:
            run([3.0, 0.0, 0.0], [0.0, 0.0, 0.0], s, **kw)
        assert err.value.parameter == next(iter(kw))
    with pytest.raises(ParameterError) as err:
        Air(drag_coefficient=-1)
    assert err.value.parameter == "drag_coefficient"


# ------------------------------------------------------------------------------ issue 30: honest defaults
@pytest.mark.parametrize("name", PRESET_NAMES)
def test_a_vertical_drop_on_a_preset_stays_put(name):
    """Straight down, no spin: the presets' tilt fades at small speeds along the ground (fade_xdot), so the ball rests
    where it landed, within 5 cm; near-vertical drops too. The published laws bounced it 0.3-5.3 m away."""
    speeds = np.array([2.0, 8.0, 20.0, 35.0])
    rng = np.random.default_rng(3)
    heading = rng.uniform(0, 2 * np.pi, 4)
    down = np.column_stack([np.zeros(4), np.zeros(4), -speeds])
    near = down + 1e-9 * np.column_stack([np.cos(heading), np.sin(heading), np.zeros(4)])
    r = run(np.vstack([down, near]), [0.0, 0.0, 0.0], name, units=SI)
    assert np.linalg.norm(r.rest_position, axis=1).max() <= 0.05, r.rest_position
    assert (r.rest_position[:4] == 0).all()  # exactly vertical: exactly where it landed


@pytest.mark.parametrize(("argument", "value"), [("velocity", [1e154, 0.0, -1e154]), ("velocity", [3.0, 0.0, -2e8]),
                                                 ("spin", [0.0, 1e9, 0.0])])
def test_absurd_magnitudes_are_refused_naming_the_argument(argument, value):
    """A landing of 1e154 radii/s was taken for a ball on the ground (1e-9 |v| overflowed) and rested at NaN."""
    kw = {"velocity": [3.0, 0.0, -2.0], "spin": [0.0, 0.0, 0.0], argument: value}
    with pytest.raises(DataError) as err:
        run(kw["velocity"], kw["spin"], green())
    assert err.value.option == argument and err.value.row == 1 and err.value.column.startswith(argument + "_")
    with pytest.raises(DataError) as err:
        bl.ground.bounce(bl.Rigid(r=0.5, mu=0.4), kw["velocity"], kw["spin"])
    assert err.value.option == argument
    with pytest.raises(DataError) as err:  # finite as given, infinite in scaled units
        run([1e307, 0.0, -1.0], [0.0, 0.0, 0.0], green(), units=SI)
    assert (err.value.option, err.value.column) == ("velocity", "velocity_x")


def test_tiny_and_huge_normals_normalise_exactly():
    """A normal is scaled by its largest component before its length is taken: [1e-160, 0, 1e-160] is [1, 0, 1]
    (its square underflowed: the rest position moved by 0.8 m)."""
    law = bl.Rigid(r=0.4, mu=0.5)
    v, w = [1000.0, 200.0, -1500.0], [30.0, -400.0, 20.0]
    ref = bl.ground.bounce(law, v, w, normal=[1.0, 0.0, 1.0])
    for n in ([1e-160, 0.0, 1e-160], [3e-300, 0.0, 3e-300], [1e300, 0.0, 1e300]):
        got = bl.ground.bounce(law, v, w, normal=n)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
    s = green()
    ref = run([2.0, 0.5, -3.0], [0.0, -100.0, 0.0], s, normal=[0.01, 0.0, 1.0], units=SI).rest_position
    for scale in (2.0 ** -600, 2.0 ** 600):
        got = run([2.0, 0.5, -3.0], [0.0, -100.0, 0.0], s, normal=[0.01 * scale, 0.0, scale], units=SI)
        np.testing.assert_array_equal(got.rest_position, ref)
    got = run([2.0, 0.5, -3.0], [0.0, -100.0, 0.0], s, normal=[1e-162, 0.0, 1e-160], units=SI)
    np.testing.assert_allclose(got.rest_position, ref, rtol=1e-12, atol=1e-14)


def mechanical_energy(ds, n: np.ndarray) -> np.ndarray:
    """Kinetic (translation and spin, a solid sphere) plus potential energy per unit mass, scaled units."""
    v, w, p = (ds[k].values[0] for k in ("velocity", "spin", "position"))
    return 0.5 * (v * v).sum(1) + 0.2 * (w * w).sum(1) + G / R * p[:, 2]


@pytest.mark.parametrize(("fraction", "heading", "spin"), [(0.9, 60.0, (0.0, 0.0, 0.0)),
                                                           (0.99, 120.0, (40.0, -90.0, 10.0)),
                                                           (0.999, 60.0, (0.0, 0.0, 0.0))])
def test_the_path_agrees_with_solve_ivp_down_to_the_steepest_slope_a_ball_rests_on(fraction, heading, spin):
    """Near the steepest slope (5/7 tan(theta) -> mu_r) the curved roll's x = tan(psi/2) falls by hundreds of orders
    of magnitude while the speed falls: sampled by x, the path was off by up to 0.49 radii and gained energy between
    samples; by r = (x/x0)^(Qk-1) it agrees with scipy and loses energy at every step."""
    surface = preset("green-fast")
    theta = math.degrees(math.atan(fraction * 1.4 * surface.rolling_resistance))
    n, _down = slope(theta, 15.0)
    h = math.radians(heading)
    v = np.array([math.cos(h), math.sin(h), 0.0])
    v = 2.0 / R * (v - (v @ n) * n) / np.linalg.norm(v - (v @ n) * n)
    w = np.array(spin)
    r = run(v, w, surface, normal=n, rate=10.0)
    ds = r.path
    expected, along = reference_on_slope(v, w, n, surface.sliding_friction, surface.rolling_resistance,
                                         ds["time"].values)
    length = np.linalg.norm(expected)
    assert np.linalg.norm(r.rest_position[0] - expected) <= 1e-9 * length
    assert np.abs(ds["position"].values[0] - along).max() <= 1e-9 * length
    e = mechanical_energy(ds, n)
    scale = 0.5 * v @ v + 0.2 * w @ w + G / R * np.abs(ds["position"].values[0, :, 2]).max()
    assert (np.diff(e) <= 1e-12 * scale).all(), np.diff(e).max() / scale


# ------------------------------------------------------------------------------ laws without a compiled kernel
class _PyRigid(bl.BounceModel):
    """The rigid bounce in NumPy: a law without a compiled kernel (run bounces it in rounds of law.predict)."""

    r = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
    mu = bl.Parameter(bounds=(0.0, 1.5), physical=(0.0, 10.0), doc="friction")
    regimes = ("bounce",)
    lift_plane = "slip"

    def _predict(self, p, r, mu):
        cap = -mu * (1.0 + r) * p[:, 1]
        j = np.minimum(np.maximum(-(p[:, 0] + p[:, 2]) / 3.5, -cap), cap)
        return np.column_stack([p[:, 0] + j, -r * p[:, 1], p[:, 2] + 2.5 * j])

    def _regime(self, p, r, mu):
        return np.zeros(len(p), dtype=np.int8)


def test_a_law_written_in_numpy_runs_in_rounds_to_the_same_rest():
    """Same maths, compiled (per shot) or in NumPy (in rounds of predict): the same runs, totals and paths."""
    from tests.test_ground_bits import shots

    v, w, n = shots(40, np.random.default_rng(9))
    s = green()
    a = run(v, w, s, normal=n, units=SI)
    b = run(v, w, s.replace(law=_PyRigid(r=0.4, mu=0.5)), normal=n, units=SI)
    np.testing.assert_allclose(b.rest_position, a.rest_position, rtol=1e-12, atol=1e-12)
    cols = ["bounces", "into_ground", "energy_gain", "bounce_limit"]
    assert (a.totals[cols] == b.totals[cols]).all().all()
    np.testing.assert_allclose(b.sample(20.0)["position"].values, a.sample(20.0)["position"].values, atol=1e-9)


def test_a_law_naming_an_unknown_lift_plane_is_refused():
    from bouncelab.core.errors import LawDefinitionError

    class Odd(_PyRigid):
        lift_plane = "diagonal"

    with pytest.raises(LawDefinitionError) as err:
        bl.ground.bounce(Odd(r=0.5, mu=0.4), [3.0, 0.0, -2.0], [0.0, 0.0, 0.0])
    assert err.value.law.endswith("Odd") and err.value.method == "lift_plane"
