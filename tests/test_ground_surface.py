"""Surfaces: named, serialisable (law as its JSON description), validated; presets (issue 25, item 2)."""

from __future__ import annotations

import json
import math

import pytest

import bouncelab as bl
from bouncelab.core.errors import DataError, NotFittedError, ParameterError
from bouncelab.ground import PRESET_NAMES, STIMP_SPEED_M_S, Surface, load_surface, preset


def test_a_surface_holds_its_law_friction_and_green_speed():
    law = bl.Rigid(r=0.3, mu=0.5)
    s = Surface(name="my green", law=law, sliding_friction=0.35, stimp_m=3.0)
    assert s.law is law and s.sliding_friction == 0.35 and s.stimp_m == 3.0 and s.pivot_retention == 1.0
    assert s.rolling_deceleration == pytest.approx(1.83 ** 2 / 6.0, rel=1e-15)
    assert s.rolling_resistance == pytest.approx(1.83 ** 2 / 6.0 / 9.81, rel=1e-15)
    assert STIMP_SPEED_M_S == 1.83


def test_feet_are_accepted_by_keyword():
    s = Surface(name="g", law=bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_ft=10)
    assert s.stimp_m == pytest.approx(3.048, rel=1e-15)
    assert s.stimp_ft == pytest.approx(10.0, rel=1e-15)
    assert s.replace(stimp_ft=12).stimp_m == pytest.approx(12 * 0.3048, rel=1e-15)


def test_the_steepest_slope_a_ball_rests_on():
    s = Surface(name="g", law=bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_ft=10)
    assert math.tan(math.radians(s.max_slope_deg())) == pytest.approx(1.4 * s.rolling_resistance, rel=1e-12)


@pytest.mark.parametrize("law", [bl.Rigid(r=0.3, mu=0.5), bl.PennerVarying.published("A"),
                                 bl.PiecewiseAffine.published("B"),
                                 bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.2)])
def test_round_trip_through_dict_json_and_file(law, tmp_path):
    s = Surface(name="x", law=law, sliding_friction=0.3, stimp_m=2.5, pivot_retention=0.7, description="test")
    d = s.to_dict()
    assert d["law"] == law.to_dict()  # the law stored as its own JSON description
    assert json.loads(json.dumps(d)) == d
    assert Surface.from_dict(d) == s
    assert Surface.from_json(s.to_json()) == s
    path = tmp_path / "s.json"
    s.to_json(path)
    back = load_surface(path)
    assert back == s and back.law == law
    assert back != s.replace(stimp_m=2.6)


@pytest.mark.parametrize("name", PRESET_NAMES)
def test_presets_load_and_round_trip(name):
    s = preset(name)
    assert s.name == name and s.description
    assert Surface.from_json(s.to_json()) == s
    assert s.sliding_friction == 0.4


def test_preset_green_speeds_and_laws():
    assert preset("green-slow").stimp_ft == pytest.approx(7.5)
    assert preset("green-medium").stimp_ft == pytest.approx(9.0)
    assert preset("green-fast").stimp_ft == pytest.approx(11.0)
    # the published laws, their tilt faded at small speeds along the ground (issue 30: a vertical drop stays put)
    from bouncelab.ground.surface import PRESET_FADE_XDOT

    assert PRESET_FADE_XDOT == 50.0
    assert preset("turf-A").law == bl.PennerVarying.published("A").replace(fade_xdot=50.0)
    for name in ("turf-B", "green-slow", "green-medium", "green-fast"):
        assert preset(name).law == bl.PennerVarying.published("B").replace(fade_xdot=50.0)
        assert "fades below 50 radii/s" in preset(name).description


@pytest.mark.parametrize(("kwargs", "parameter"), [
    ({"name": ""}, "name"),
    ({"law": "Rigid"}, "law"),
    ({"sliding_friction": -0.1}, "sliding_friction"),
    ({"sliding_friction": float("nan")}, "sliding_friction"),
    ({"stimp_m": 0.0}, "stimp_m"),
    ({"stimp_ft": 9.0}, "stimp_m"),  # both stimp_m and stimp_ft: exactly one of them
    ({"stimp_m": None}, "stimp_m"),  # neither
    ({"pivot_retention": 2.0}, "pivot_retention"),
    ({"description": 3}, "description"),
])
def test_bad_values_are_refused_naming_them(kwargs, parameter):
    args = {"name": "g", "law": bl.Rigid(r=0.3, mu=0.5), "sliding_friction": 0.4, "stimp_m": 3.0} | kwargs
    with pytest.raises(ParameterError) as e:
        Surface(**args)
    assert e.value.parameter == parameter
    if "stimp_ft" in kwargs or kwargs.get("stimp_m", 1) is None:
        assert [h.option for h in e.value.hints] == ["stimp_m", "stimp_ft"]


def test_an_unfitted_law_is_refused():
    with pytest.raises(NotFittedError):
        Surface(name="g", law=bl.Rigid(r=0.3), sliding_friction=0.4, stimp_m=3.0)


def test_bad_descriptions_and_names_are_refused(tmp_path):
    d = preset("turf-A").to_dict()
    for bad, key in (({k: v for k, v in d.items() if k != "stimp_m"}, "stimp_m"), (d | {"colour": "green"}, "colour")):
        with pytest.raises(ParameterError) as e:  # a missing or an unknown key
            Surface.from_dict(bad)
        assert e.value.parameter == key
    with pytest.raises(ParameterError) as e:  # not JSON
        Surface.from_json("{nope")
    assert e.value.parameter == "text"
    with pytest.raises(ParameterError) as e:
        preset("green-glass")
    assert (e.value.parameter, e.value.value) == ("surface", "green-glass")
    with pytest.raises(DataError) as e:  # cannot read the file: a DataError naming it (also a FileNotFoundError)
        load_surface(tmp_path / "missing.json")
    assert e.value.file == str(tmp_path / "missing.json") and isinstance(e.value, FileNotFoundError)
    with pytest.raises(ParameterError) as e:  # no such field
        preset("turf-A").replace(colour="green")
    assert e.value.parameter == "colour"
