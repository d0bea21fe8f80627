"""Issue 11 item 3: predict in physical units (Cartesian and polar), non-physical lift-offs, regime codes."""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core import published, units
from bouncelab.core.errors import DataError, Hint, LargeResultWarning, NonphysicalLiftoffWarning
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.laws import BounceModel, Parameter

SI = {"velocity": "m/s", "spin": "rpm"}


def table1_polar(campaign: str, n: int, seed: int = 0) -> np.ndarray:
    """Landings drawn uniformly within the paper's Table 1 ranges of speed (m/s), angle (deg) and spin (rpm)."""
    t = published.TABLE1.loc[campaign]
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(t.loc[q, "min"], t.loc[q, "max"], n) for q in ("speed", "angle", "spin")])


def test_cartesian_physical_units_match_manual_conversion() -> None:
    law = bl.PennerFixed.published("A")
    phys = np.array([[20.0, -15.0, 3000.0], [5.0, -8.0, -1000.0]])
    expected = units.from_scaled(law.predict(units.to_scaled(phys, velocity="m/s", spin="rpm")),
                                 velocity="m/s", spin="rpm")
    np.testing.assert_allclose(law.predict(phys, units=SI), expected, rtol=1e-12)
    mph = law.predict(phys * [1 / 0.44704, 1 / 0.44704, 1], units={"velocity": "mph", "spin": "rpm"})
    np.testing.assert_allclose(mph * [0.44704, 0.44704, 1], expected, rtol=1e-9)


def test_polar_liftoff_angle_is_positive_above_horizontal() -> None:
    law = bl.Rigid.published("A")
    polar = np.array([[28.5, 37.3, 2094.0], [10.0, 60.0, -500.0]])  # speed m/s, degrees below horizontal, rpm
    out = law.predict(polar, units=SI, form="polar")
    scaled = law.predict(units.landing_from_speed_angle_spin(polar[:, 0], polar[:, 1], polar[:, 2]))
    assert (scaled[:, 1] > 0).all()  # the ball goes up ...
    assert (out[:, 1] > 0).all()  # ... so its lift-off angle is positive
    np.testing.assert_allclose(out[:, 1], np.degrees(np.arctan2(scaled[:, 1], scaled[:, 0])), rtol=1e-12)
    np.testing.assert_allclose(out[:, 0], np.hypot(scaled[:, 0], scaled[:, 1]) * units.BALL_RADIUS_M, rtol=1e-12)
    np.testing.assert_allclose(out[:, 2], scaled[:, 2] * 60 / (2 * np.pi), rtol=1e-12)


def test_speed_angle_spin_gives_positive_liftoff_angles() -> None:
    law = bl.Rigid.published("A")
    out = law.predict(units.landing_from_speed_angle_spin([28.5, 10.0], [37.3, 60.0], [2094.0, -500.0]))
    up = units.speed_angle_spin(out, kind="liftoff")["angle_deg"]
    assert (up > 0).all()
    np.testing.assert_allclose(up, -units.speed_angle_spin(out)["angle_deg"])  # the landing convention flips it
    with pytest.raises(DataError) as e:
        units.speed_angle_spin(out, kind="up")
    assert e.value.option == "kind"


def test_polar_round_trip_and_mixed_forms() -> None:
    law = bl.PennerVarying.published("A")
    polar = table1_polar("A", 50)
    cart_in = units.physical_to_scaled(polar, units=SI, form="polar", kind="landing")
    np.testing.assert_allclose(units.scaled_to_physical(cart_in, units=SI, form="polar", kind="landing"), polar,
                               rtol=1e-9)
    both = law.predict(polar, units=SI, form=("polar", "cartesian"))
    np.testing.assert_allclose(both, units.from_scaled(law.predict(cart_in), velocity="m/s", spin="rpm"),
                               rtol=1e-12)
    # the leading shape is kept
    assert law.predict(polar.reshape(5, 10, 3), units=SI, form="polar").shape == (5, 10, 3)


def test_dataframe_polar_columns_by_name() -> None:
    law = bl.Rigid.published("B")
    polar = table1_polar("B", 4)
    df = pd.DataFrame(polar[:, [2, 0, 1]], columns=["spin", "speed", "angle"], index=list("abcd"))
    out = law.predict(df, units=SI, form="polar")
    assert list(out.columns) == ["speed", "angle", "spin"] and list(out.index) == list("abcd")
    np.testing.assert_allclose(out.to_numpy(), law.predict(polar, units=SI, form="polar"))


@pytest.mark.parametrize(("kwargs", "option"), [
    ({"units": {"velocity": "m/s"}}, "units"),  # no spin unit
    ({"units": {"velocity": "rpm", "spin": "rpm"}}, "velocity"),  # not a velocity unit
    ({"units": "m/s"}, "units"),  # not a mapping
    ({"units": SI, "form": "spherical"}, "form"),
])
def test_bad_units_or_form_refused(kwargs: dict, option: str) -> None:
    with pytest.raises(DataError) as e:
        bl.Rigid.published("A").predict([[20.0, 30.0, 100.0]], **kwargs)
    assert e.value.option == option
    if option == "units":  # an example of the mapping
        assert e.value.hints == (Hint("units", {"velocity": "m/s", "spin": "rpm"}),)


def test_polar_landing_angle_out_of_range_refused() -> None:
    law = bl.Rigid.published("A")
    with pytest.raises(DataError) as e:  # a landing angle outside (0, 180)
        law.predict([[20.0, 30.0, 100.0], [20.0, -5.0, 100.0]], units=SI, form="polar")
    assert e.value.column == "angle" and "(element (1,))" in e.value.message
    with pytest.raises(DataError) as e:  # a negative speed
        law.predict([[-20.0, 30.0, 100.0]], units=SI, form="polar")
    assert e.value.column == "speed"
    with pytest.raises(DataError) as e:  # a DataArray states its own units
        law.predict(xr.DataArray([[20.0, -30.0, 100.0]], dims=("bounce", "component")), units=SI)
    assert e.value.option == "units" and e.value.hints[0][:2] == ("landing", "landing.values")


@pytest.mark.parametrize("landing, kw, column, row, hint", [
    # 2000 "m/s": radii/s given as m/s (the first landing is plausible in both units; the speed of a Cartesian
    # landing involves two columns, so the error names none: the message names xdot0 and ydot0)
    ([[50.0, -30.0, 2000.0], [2000.0, -800.0, 2000.0]], {}, None, 2,
     Hint("units", {"velocity": "radius/s", "spin": "rpm"})),
    # 30 000 "rpm" is beyond what any golf ball spins, in any unit
    ([[20.0, -8.0, 30_000.0]], {}, "omega0", 1, Hint("plausible", "PLAUSIBLE_RANGES.widened(max_spin=...)")),
    # an angle in radians given as degrees
    ([[20.0, 0.6, 2000.0]], {"form": "polar"}, "angle", 1,
     Hint("plausible", "PLAUSIBLE_RANGES.widened(min_landing_angle=...)")),
])
def test_physical_landings_that_only_a_unit_mistake_makes_are_refused(landing, kw, column, row, hint) -> None:
    law = bl.Rigid.published("A")
    for method in (law.predict, law.regime):
        with pytest.raises(DataError) as err:
            method(np.array(landing), units=SI, **kw)
        assert (err.value.column, err.value.row) == (column, row)
        assert err.value.hints[0] == hint
        if column == "angle":
            assert "if it is in radians" in err.value.message  # what the numbers look like
        method(np.array(landing), units=SI, plausible=None, **kw)  # accepted on purpose
    wide = bl.plausibility.PLAUSIBLE_RANGES.widened(max_speed=1e4, max_spin=1e5, min_landing_angle=0.1)
    assert np.isfinite(law.predict(np.array(landing), units=SI, plausible=wide, **kw)).all()


def test_scaled_landings_are_guarded_too_and_a_bad_guard_is_refused() -> None:
    law = bl.Rigid.published("A")
    # Issue 22: scaled Cartesian landings get the same guard (46 m/s and 19 100 rpm are golf landings) ...
    assert np.isfinite(law.predict([[2000.0, -800.0, 2000.0]])).all()
    with pytest.raises(DataError) as e:  # ... and m/s given as radii/s are refused
        law.predict([[20.0, -8.0, 200.0]])
    assert e.value.hints[1] == Hint("plausible", "PLAUSIBLE_RANGES.widened(min_landing_speed=...)")
    for units_ in (SI, None):
        for call in (law.predict, law.regime):  # plausible must be a PlausibleRanges or None
            with pytest.raises(DataError) as e:
                call([[20.0, -8.0, 200.0]], units=units_, plausible={"max_speed": 90})
            assert e.value.option == "plausible"


class Booster(BounceModel):
    """Not a physical law: bounces up with ``g`` times the landing speed (energy gain for g > 1)."""

    g = Parameter(bounds=(0.0, 3.0), physical=(0.0, 10.0), unit="1", doc="gain")
    regimes = ("bounce",)

    def _predict(self, p, g):
        return p * np.array([g, -g, g])

    def _regime(self, p, g):
        return np.zeros(len(p), dtype=np.int8)


def test_flags_mark_energy_gain_and_into_ground_without_warning_for_unpublished_laws() -> None:
    landing = np.array([[100.0, -200.0, 30.0], [50.0, -10.0, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a user's law is never warned about
        _out, flags = Booster(g=1.5).predict(landing, return_flags=True)
        np.testing.assert_array_equal(flags.energy_gain, [True, True])
        np.testing.assert_array_equal(flags.into_ground, [False, False])
        _, flags = Booster(g=0.5).predict(landing, return_flags=True)
        assert not flags.nonphysical.any()
        _, flags = Booster(g=0.0).predict(landing, return_flags=True)  # ydotF = 0: stays on the ground
        np.testing.assert_array_equal(flags.into_ground, [True, True])
    assert flags.counts() == {"into_ground": 2, "energy_gain": 0, "nonphysical": 2, "n": 2}


def test_flags_come_from_the_same_prediction() -> None:
    calls = []

    class Counted(Booster):
        def _predict(self, p, g):
            calls.append(len(p))
            return super()._predict(p, g)

    out, flags = Counted(g=1.5).predict(table1_polar("A", 10), units=SI, form="polar", return_flags=True)
    assert calls == [10]  # one prediction, no second pass for the flags
    assert flags.energy_gain.all() and out.shape == (10, 3)


def test_masked_physical_landings_refused() -> None:
    m = np.ma.masked_array([[20.0, 30.0, 100.0], [20.0, 30.0, 100.0]], mask=[[0, 0, 0], [0, 1, 0]])
    with pytest.raises(DataError, match="masked") as e:  # the option names the argument, the words the fault
        bl.Rigid.published("A").predict(m, units=SI, form="polar")
    assert e.value.option == "landing"


def test_flags_match_an_independent_check_and_keep_the_shape() -> None:
    law = bl.PennerFixed.published("B")
    polar = table1_polar("B", 2000, seed=3)
    with pytest.warns(NonphysicalLiftoffWarning):
        out, flags = law.predict(polar.reshape(40, 50, 3), units=SI, form="polar", return_flags=True)
    with pytest.warns(NonphysicalLiftoffWarning):
        scaled_out = law.predict(units.physical_to_scaled(polar, units=SI, form="polar"))
    assert flags.into_ground.shape == (40, 50)
    np.testing.assert_array_equal(flags.into_ground.ravel(), scaled_out[:, 1] <= 0)
    # a lift-off into the ground has a lift-off angle at or below zero
    assert (out[..., 1][flags.into_ground] <= 0).all() and (out[..., 1][~flags.into_ground] > 0).all()


def test_published_penner_b_warns_on_table1_landings() -> None:
    polar = table1_polar("B", 20_000)
    for cls in (bl.PennerFixed, bl.PennerVarying):
        with pytest.warns(NonphysicalLiftoffWarning, match=r"published\('B'\).*into the ground"):
            _, flags = cls.published("B").predict(polar, units=SI, form="polar", return_flags=True)
        assert flags.into_ground.mean() > 0.05  # a large share, not a rounding accident
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bl.Rigid.published("B").predict(polar, units=SI, form="polar")  # never into the ground: r > 0
        bl.PennerFixed.published("A").predict(units.physical_to_scaled(table1_polar("A", 20_000), units=SI,
                                                                       form="polar"))
        # the same law with other values is the user's own choice: flags, but no warning
        bl.PennerFixed.published("B").replace(r=0.2).predict(polar, units=SI, form="polar")


def test_regime_in_physical_units_and_large_name_arrays_warn() -> None:
    law = bl.Rigid.published("A")
    polar = table1_polar("A", 30)
    np.testing.assert_array_equal(
        law.regime(polar, units=SI, form="polar", codes=True),
        law.regime(units.physical_to_scaled(polar, units=SI, form="polar"), codes=True))
    big = np.tile(units.physical_to_scaled(polar, units=SI, form="polar"), (bl.laws.base.REGIME_NAMES_WARN // 30 + 1,
                                                                               1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        codes = law.regime(big, codes=True)
    assert codes.dtype == np.int8
    with pytest.warns(LargeResultWarning, match="codes=True"):
        names = law.regime(big)
    np.testing.assert_array_equal(names, np.asarray(law.regimes)[codes])


def test_compiled_gate_agrees_with_the_flags() -> None:
    """Published laws check every prediction with one compiled pass; it must flag exactly when the flags do."""
    from bouncelab.laws.nonphysical import any_flagged, liftoff_flags

    rng = np.random.default_rng(5)
    n = 120_000  # above the size where the pass runs in parallel chunks
    p = np.column_stack([rng.uniform(-1500, 1500, n), -rng.uniform(50, 1200, n), rng.uniform(-900, 1500, n)])
    out = p * [0.6, -0.5, 0.3]
    assert not any_flagged(p, out)
    for row, change in ((0, (1, -1.0)), (n - 1, (1, 0.0)), (77_777, (0, 1e4))):  # first, last, mid-chunk row
        bad = out.copy()
        bad[row, change[0]] = change[1]
        g, e = liftoff_flags(p, bad)
        assert any_flagged(p, bad) and (g.any() or e.any())
    edge = out.copy()  # exactly the landing's energy: not a gain, in both
    edge[5] = p[5] * [1, -1, 1]
    assert any_flagged(p, edge) == bool(np.logical_or(*liftoff_flags(p, edge)).any())


def test_polar_landings_are_guarded_by_their_speed_as_given() -> None:
    law = bl.Rigid.published("A")
    with pytest.raises(DataError) as err:
        law.predict([[120.0, 45.0, 2000.0]], units=SI, form="polar")  # 85 m/s in each component
    assert (err.value.column, err.value.row) == ("speed", 1)
    assert err.value.message.startswith("120 m/s")  # the speed as given
    with pytest.raises(DataError) as err:
        law.predict([[60.0, 30.0, 2000.0], [2000.0, 30.0, 2000.0]], units=SI, form="polar")
    assert (err.value.column, err.value.row) == ("speed", 2)
    assert err.value.hints[0] == Hint("units", {"velocity": "radius/s", "spin": "rpm"})  # it looks like radii/s
    with pytest.raises(DataError) as err:
        law.predict([[20.0, 30.0, 30_000.0]], units=SI, form="polar")
    assert (err.value.column, err.value.row) == ("spin", 1)


def test_declared_units_are_held_to_the_lower_limits_too() -> None:
    """Issue 22: one guard for every landing. A landing slower than any golf landing is refused even when its
    unit is declared (it was accepted before as 'a slow landing, not a unit mistake'), and can be accepted on
    purpose."""
    law = bl.Rigid.published("A")
    with pytest.raises(DataError) as err:  # 0.5 m/s is slower than any golf landing
        law.predict([[0.5, 30.0, 100.0]], units=SI, form="polar")
    assert (err.value.column, err.value.row) == ("speed", 1)
    assert Hint("plausible", "PLAUSIBLE_RANGES.widened(min_landing_speed=...)") in err.value.hints
    slow = law.predict([[0.5, 30.0, 100.0]], units=SI, form="polar",
                       plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=0.1))
    both = law.predict([[0.5, 30.0, 100.0], [20.0, 30.0, 2000.0]], units=SI, form="polar", plausible=None)
    np.testing.assert_allclose(slow[0], both[0])
    assert np.isfinite(law.predict([[3.0, -2.0, 50.0]], units={"velocity": "km/h", "spin": "rpm"})).all()  # 1.0 m/s


def test_scaled_units_spelled_out_are_guarded_alike() -> None:
    law = bl.Rigid.published("A")
    landing = [[20_000.0, -1000.0, 30_000.0]]  # 427 m/s, 286 000 rpm: no golf landing
    for given in (None, "scaled"):
        with pytest.raises(DataError) as err:  # faster than 90 m/s
            law.predict(landing, units=given)
        assert err.value.row == 1
        assert Hint("plausible", "PLAUSIBLE_RANGES.widened(max_speed=...)") in err.value.hints
    np.testing.assert_array_equal(law.predict(landing, units="scaled", plausible=None),
                                  law.predict(landing, plausible=None))


@pytest.mark.parametrize("radius", [21.35, 0.0, -0.02, "0.02135", True])
def test_a_ball_radius_that_is_not_metres_is_refused(radius) -> None:
    law = bl.Rigid.published("A")
    for method in (law.predict, law.regime):
        with pytest.raises(DataError) as e:
            method([[20.0, -8.0, 2000.0]], units=SI, radius_m=radius)
        assert e.value.option == "ball_radius_m"


@pytest.mark.parametrize("change", [
    {"max_spin": None}, {"max_spin": "40000"}, {"max_speed": -1.0}, {"min_landing_angle": float("inf")},
    {"max_spn": 3.0},  # no such limit
])
def test_plausible_ranges_refuse_limits_that_are_not_limits(change) -> None:
    from bouncelab.core.plausibility import PLAUSIBLE_RANGES

    with pytest.raises(bl.errors.ParameterError) as e:
        PLAUSIBLE_RANGES.widened(**change)
    assert {e.value.parameter: e.value.value} == change
    assert PLAUSIBLE_RANGES.widened(max_spin=np.int64(30_000), min_peak_spin=0).max_spin == 30_000


def test_an_upward_physical_landing_is_named_in_the_units_given() -> None:
    law = bl.Rigid.published("A")
    with pytest.raises(DataError, match=r"got 10.0 m/s \(1 bounce") as err:
        law.predict([[20.0, -8.0, 2000.0], [20.0, 10.0, 2000.0]], units=SI)
    assert (err.value.column, err.value.row) == ("landing.ydot", 2)
