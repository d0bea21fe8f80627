"""The bounce laws against the paper's equations, worked by hand and by an independent reference."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

import bouncelab as bl
from benchmarks import numpy_reference
from bouncelab.core.errors import DataError, NotFittedError, ParameterError, UnknownLawError
from bouncelab.laws import Parameter
from bouncelab.laws.base import BounceModel
from tests.conftest import kinetic_energy, random_landings

RIGID_FAMILY = [
    bl.Rigid(r=0.54, mu=0.4),
    bl.PennerFixed(r=0.42, mu=0.85, beta_deg=12.9),
    bl.PennerVarying(r=0.45, mu=0.97, k_p=1.543e-4),
    bl.TangentialRestitution(r=0.5, mu=0.3, e_t=0.4),
]


# The independent reference: plain NumPy written from the paper's equations (also the benchmarks' peer).
rigid_reference = numpy_reference.rigid
penner_reference = numpy_reference.penner


def mirror(p: np.ndarray) -> np.ndarray:
    return p * np.array([-1.0, 1.0, -1.0])


# --------------------------------------------------------------------------- rigid, worked by hand
class TestRigidByHand:
    law = bl.Rigid(r=0.5, mu=0.2)  # k = mu (1 + r) = 0.3; slip limit 7/2 k |ydot0| = 1.05 |ydot0|

    def test_slip_forward(self):
        # v_P = 1000 + 900 = 1900 > 1.05 * 1000 = 1050
        out = self.law.predict([1000.0, -1000.0, 900.0])
        np.testing.assert_allclose(out, [1000 - 300, 500, 900 - 750], rtol=1e-13)
        assert self.law.regime([1000.0, -1000.0, 900.0]) == "slip_forward"

    def test_roll(self):
        # v_P = 1000 - 500 = 500 < 1050: xF = 5/7*1000 + 2/7*500, omegaF = -5/7*1000 - 2/7*500... sign:
        # omegaF = -5/7 xdot0 + 2/7 omega0
        out = self.law.predict([1000.0, -1000.0, -500.0])
        np.testing.assert_allclose(out, [(5000 + 1000) / 7, 500, (-5000 - 1000) / 7], rtol=1e-13)
        assert out[0] + out[2] == pytest.approx(0.0, abs=1e-10)
        assert self.law.regime([1000.0, -1000.0, -500.0]) == "roll"

    def test_slip_backward(self):
        # v_P = 200 - 1500 = -1300 < -1050
        out = self.law.predict([200.0, -1000.0, -1500.0])
        np.testing.assert_allclose(out, [200 + 300, 500, -1500 + 750], rtol=1e-13)
        assert self.law.regime([200.0, -1000.0, -1500.0]) == "slip_backward"

    def test_published_driver_landing(self):
        p0 = bl.units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
        law = bl.Rigid.published("A")
        k = 0.997 * 1.544
        vp = p0[0] + p0[2]
        assert abs(vp) < 3.5 * k * abs(p0[1])  # the driver landing grips under this law
        out = law.predict(p0)
        np.testing.assert_allclose(out, [(5 * p0[0] - 2 * p0[2]) / 7, -0.544 * p0[1], (2 * p0[2] - 5 * p0[0]) / 7])


@pytest.mark.parametrize("law", RIGID_FAMILY[:1] + RIGID_FAMILY[3:], ids=lambda m: type(m).__name__)
def test_rigid_and_tangential_match_reference(law, landings):
    e_t = getattr(law, "e_t", 0.0)
    np.testing.assert_allclose(law.predict(landings, plausible=None), rigid_reference(landings, law.r, law.mu, e_t),
                               rtol=1e-12, atol=1e-9)


def test_penner_fixed_matches_reference(landings):
    law = bl.PennerFixed(r=0.42, mu=0.85, beta_deg=12.9)
    beta = np.full(len(landings), math.radians(12.9))
    np.testing.assert_allclose(law.predict(landings, plausible=None), penner_reference(landings, 0.42, 0.85, beta),
                               rtol=1e-11, atol=1e-8)


def test_penner_varying_matches_reference(landings):
    law = bl.PennerVarying(r=0.45, mu=0.97, k_p=1.543e-4)
    s = np.hypot(landings[:, 0], landings[:, 1])
    phi = np.arctan(-landings[:, 1] / np.abs(landings[:, 0]))
    beta = np.minimum(1.543e-4 * s * phi, np.pi / 2)
    np.testing.assert_allclose(law.predict(landings, plausible=None), penner_reference(landings, 0.45, 0.97, beta),
                               rtol=1e-11, atol=1e-8)
    np.testing.assert_allclose(law.beta_deg(landings), np.degrees(beta), rtol=1e-12)


def test_penner_beta_cap_at_vertical():
    law = bl.PennerVarying(r=0.5, mu=0.5, k_p=1.0)  # absurdly large: beta capped at 90 degrees
    assert law.beta_deg([[100.0, -100.0, 0.0]]) == pytest.approx([90.0])
    out = law.predict([[100.0, -100.0, 0.0]])
    ref = penner_reference(np.array([[100.0, -100.0, 0.0]]), 0.5, 0.5, np.array([np.pi / 2]))
    np.testing.assert_allclose(out, ref, atol=1e-9)


def test_penner_with_zero_tilt_is_rigid(landings):
    rigid = bl.Rigid(r=0.3, mu=0.6).predict(landings, plausible=None)
    np.testing.assert_allclose(bl.PennerFixed(r=0.3, mu=0.6, beta_deg=0.0).predict(landings, plausible=None), rigid,
                               rtol=1e-13, atol=1e-10)
    np.testing.assert_allclose(bl.PennerVarying(r=0.3, mu=0.6, k_p=0.0).predict(landings, plausible=None), rigid,
                               rtol=1e-13, atol=1e-10)


def test_penner_tilt_against_travel_reduces_forward_speed():
    # A frictionless ball on a surface rising towards +x is pushed back: xdotF < xdot0 (mu=0, r=1 is a mirror).
    p0 = np.array([[1000.0, -500.0, 0.0]])
    flat = bl.PennerFixed(r=1.0, mu=0.0, beta_deg=0.0).predict(p0)
    tilted = bl.PennerFixed(r=1.0, mu=0.0, beta_deg=10.0).predict(p0)
    assert tilted[0, 0] < flat[0, 0]
    assert np.hypot(*tilted[0, :2]) == pytest.approx(np.hypot(*p0[0, :2]))  # elastic, frictionless: speed kept


def test_tangential_restitution():
    law = bl.TangentialRestitution(r=0.5, mu=0.5, e_t=0.6)
    p0 = np.array([[500.0, -1000.0, 200.0]])  # v_P = 700, limit 3.5*0.75*1000/1.6 = 1640.6: grips
    out = law.predict(p0)
    assert out[0, 0] + out[0, 2] == pytest.approx(-0.6 * 700.0)
    np.testing.assert_allclose(bl.TangentialRestitution(r=0.5, mu=0.5, e_t=0.0).predict(p0),
                               bl.Rigid(r=0.5, mu=0.5).predict(p0))


# ------------------------------------------------------------------------------- general properties
@pytest.mark.parametrize("law", RIGID_FAMILY, ids=lambda m: type(m).__name__)
def test_continuity_across_regime_boundaries(law, rng):
    """Walk omega0 through every regime change: the lift-off never jumps."""
    n_changes = 0
    for _ in range(30):
        xd, yd = rng.uniform(50, 2000) * rng.choice([-1, 1]), -rng.uniform(100, 1800)
        w = np.linspace(-6000, 6000, 400001)
        p = np.column_stack([np.full_like(w, xd), np.full_like(w, yd), w])
        out = law.predict(p, plausible=None)
        codes = law.regime(p, plausible=None)
        changes = np.flatnonzero(codes[1:] != codes[:-1])
        n_changes += len(changes)
        step = np.abs(np.diff(out, axis=0)).max(axis=1)
        # the step at a regime change is as small as a step inside a regime (0.03 rad/s grid)
        if len(changes):
            assert step[changes].max() < 0.1
    assert n_changes >= 30


@pytest.mark.parametrize("law", RIGID_FAMILY[:1], ids=lambda m: type(m).__name__)
def test_rigid_rolling_lifts_off_with_zero_contact_velocity(law, landings):
    roll = law.regime(landings, plausible=None) == "roll"
    assert roll.sum() > 100
    out = law.predict(landings[roll], plausible=None)
    np.testing.assert_allclose(out[:, 0] + out[:, 2], 0.0, atol=1e-9)
    slip = ~roll
    v0 = landings[slip, 0] + landings[slip, 2]
    vf = law.predict(landings[slip], plausible=None)
    assert np.all(np.sign(vf[:, 0] + vf[:, 2]) == np.sign(v0))  # slipping balls keep slipping the same way


@pytest.mark.parametrize("cls", [bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.TangentialRestitution])
def test_no_energy_gain(cls, rng):
    p = random_landings(rng, 5000)
    for _ in range(20):
        params = {s.name: rng.uniform(*s.bounds) for s in cls.parameter_specs}
        out = cls(**params).predict(p, plausible=None)
        assert np.all(kinetic_energy(out) <= kinetic_energy(p) * (1 + 1e-12)), params


def test_elastic_frictionless_keeps_energy(landings):
    out = bl.Rigid(r=1.0, mu=0.0).predict(landings, plausible=None)
    np.testing.assert_allclose(kinetic_energy(out), kinetic_energy(landings), rtol=1e-12)


@pytest.mark.parametrize("law", RIGID_FAMILY, ids=lambda m: type(m).__name__)
def test_mirror_symmetry(law, landings):
    np.testing.assert_allclose(law.predict(mirror(landings), plausible=None),
                               mirror(law.predict(landings, plausible=None)), rtol=1e-12, atol=1e-9)
    swap = {"slip_forward": "slip_backward", "slip_backward": "slip_forward", "roll": "roll"}
    assert [swap[c] for c in law.regime(landings, plausible=None)] == list(law.regime(mirror(landings), plausible=None))


# ---------------------------------------------------------------------------------- piecewise affine
def test_piecewise_sides_and_maps():
    law = bl.PiecewiseAffine.published("A")
    a = np.array(bl.published.PIECEWISE["A"]["A1"])
    b = np.array(bl.published.PIECEWISE["A"]["b1"])
    p_roll = np.array([1000.0, -800.0, 0.0])  # 891 - 610.4 + 0 = 280.6 < 600
    p_slip = np.array([1000.0, -800.0, 600.0])  # 880.6 > 600
    np.testing.assert_allclose(law.predict(p_roll, plausible=None), a @ p_roll + b)
    a2 = np.array(bl.published.PIECEWISE["A"]["A2"])
    b2 = np.array(bl.published.PIECEWISE["A"]["b2"])
    np.testing.assert_allclose(law.predict(p_slip, plausible=None), a2 @ p_slip + b2)
    assert list(law.regime(np.array([p_roll, p_slip]), plausible=None)) == ["roll", "slip"]
    on_plane = np.array([0.0, 0.0, 600.0])  # exactly on the plane belongs to side 2
    assert law.regime(np.array([[1e-12, -1e-9, 600.0]]), plausible=None)[0] in ("roll", "slip")
    np.testing.assert_allclose(law.predict(np.array([[0.0, -1e-300, 600.0]]), plausible=None), [a2 @ on_plane + b2])


def test_piecewise_printed_plane_b():
    law = bl.PiecewiseAffine.published("B")
    assert law.printed_plane() == pytest.approx((0.377, 2.25, -485.0))
    scaled = law.replace(normal=2 * law.normal, offset=2 * law.offset)
    assert scaled.printed_plane() == pytest.approx(law.printed_plane())
    assert scaled.plane_equation() == law.plane_equation()


def test_piecewise_validation():
    partial = bl.PiecewiseAffine(normal=[1, 0, 0], offset=0.0)  # a plane without maps: not fitted yet
    assert not partial.is_fitted
    with pytest.raises(NotFittedError) as err:
        partial.predict([[1000.0, -800.0, 0.0]])
    assert err.value.missing == ("A1", "b1", "A2", "b2")
    good = bl.published.piecewise_parameters("A")
    with pytest.raises(ParameterError) as err:  # a 2 x 2 map
        bl.PiecewiseAffine(**{**good, "A1": np.eye(2)})
    assert (err.value.law, err.value.parameter) == ("PiecewiseAffine", "A1") and err.value.value.shape == (2, 2)
    with pytest.raises(ParameterError) as err:
        bl.PiecewiseAffine(**{**good, "b2": [1.0, np.nan, 0.0]})
    assert err.value.parameter == "b2[1]" and np.isnan(err.value.value)  # the element named
    with pytest.raises(ParameterError) as err:
        bl.PiecewiseAffine(**{**good, "normal": [0.0, 0.0, 0.0]})
    assert err.value.parameter == "normal" and not np.any(err.value.value)
    law = bl.PiecewiseAffine(**good)
    with pytest.raises(ValueError):
        law.A1[0, 0] = 5.0  # stored arrays are read-only
    assert len(law.parameters) == 6 and law.parameters["A1"][0, 2] == -0.205 and law.parameters["b2"][2] == -267.0
    flat = law.flat_parameters()
    assert len(flat) == 28 and flat["A1[0,2]"] == -0.205 and flat["b2[2]"] == -267.0


# -------------------------------------------------------------------------------- shapes and kinds
@pytest.mark.parametrize("law", [*RIGID_FAMILY, bl.PiecewiseAffine.published("B")], ids=lambda m: type(m).__name__)
def test_predict_shapes_and_dataarray(law, landings):
    p = np.abs(landings[:12]) * np.array([1.0, -1.0, 1.0])
    flat = law.predict(p, plausible=None)
    assert flat.shape == (12, 3)
    np.testing.assert_array_equal(law.predict(p[0], plausible=None), flat[0])
    np.testing.assert_array_equal(law.predict(p.reshape(3, 4, 3), plausible=None), flat.reshape(3, 4, 3))
    np.testing.assert_array_equal(law.predict(p.tolist(), plausible=None), flat)
    da = xr.DataArray(p.T[[2, 0, 1]], dims=("component", "bounce"),
                      coords={"component": ["omega", "xdot", "ydot"], "bounce": np.arange(12) + 100})
    out = law.predict(da, plausible=None)
    assert isinstance(out, xr.DataArray)
    assert out.dims == ("bounce", "component")
    assert list(out.component.values) == ["xdot", "ydot", "omega"]
    np.testing.assert_array_equal(out.bounce.values, np.arange(12) + 100)
    np.testing.assert_array_equal(out.values, flat)
    reg = law.regime(da, plausible=None)
    assert isinstance(reg, xr.DataArray) and reg.dims == ("bounce",)
    assert list(reg.values) == list(law.regime(p, plausible=None))
    assert law.regime(p[0], plausible=None).shape == ()


@pytest.mark.parametrize("law", [RIGID_FAMILY[0], bl.PiecewiseAffine.published("A")], ids=lambda m: type(m).__name__)
def test_predict_rejects_bad_arrays(law):
    good = np.array([[1000.0, -800.0, 100.0], [900.0, -700.0, 0.0]])
    with pytest.raises(DataError) as err:
        law.predict(np.array([[1000.0, -800.0, 100.0], [np.nan, -700.0, 0.0]]))
    assert (err.value.column, err.value.row) == ("landing.xdot", 2)
    with pytest.raises(DataError) as err:
        law.predict(np.array([[1000.0, -800.0, 100.0], [900.0, 5.0, 0.0]]))
    assert err.value.column == "landing.ydot" and err.value.row == 2
    with pytest.raises(DataError) as err:
        law.predict(np.array([[np.inf, -800.0, 100.0]]))
    assert (err.value.column, err.value.row) == ("landing.xdot", 1)
    # the argument is at fault as a whole: the option names it, the wording tells the faults apart
    for bad, words in ((np.ones((4, 2)), r"shape \(n, 3\)"), ([["a", "b", "c"]], "numeric"),
                       (np.empty((0, 3)), "no bounces"), (xr.DataArray(good, dims=("bounce", "xyz")), "component")):
        with pytest.raises(DataError, match=words) as err:
            law.predict(bad)
        assert err.value.option == "landing" and err.value.row is None
    before = good.copy()
    law.predict(good)
    np.testing.assert_array_equal(good, before)  # input untouched


# ------------------------------------------------------------------------------- parameters and state
def test_unfitted_laws():
    for cls in (bl.Rigid, bl.PennerFixed, bl.PennerVarying, bl.PiecewiseAffine, bl.TangentialRestitution):
        law = cls()
        assert not law.is_fitted
        assert all(v is None for v in law.parameters.values())
        with pytest.raises(NotFittedError) as err:
            law.predict([[1000.0, -800.0, 0.0]])
        assert err.value.law == cls.__name__ and err.value.missing == tuple(law.parameters)


@pytest.mark.parametrize(
    ("kwargs", "bad"),
    [
        ({"r": 1.5, "mu": 0.3}, "r"),  # outside its physical range
        ({"r": -0.1, "mu": 0.3}, "r"),
        ({"r": 0.5, "mu": -0.3}, "mu"),
        ({"r": 0.5, "mu": np.nan}, "mu"),
        ({"r": "abc", "mu": 0.3}, "r"),  # not a number
    ],
)
def test_bad_parameters(kwargs, bad):
    with pytest.raises(ParameterError) as err:
        bl.Rigid(**kwargs)
    assert (err.value.law, err.value.parameter) == ("Rigid", bad)
    assert err.value.value is kwargs[bad] or (np.isnan(err.value.value) and np.isnan(kwargs[bad]))


@pytest.mark.parametrize(("cls", "kwargs", "bad"), [
    (bl.PennerFixed, {"r": 0.5, "mu": 0.5, "beta_deg": 95.0}, "beta_deg"),
    (bl.PennerVarying, {"r": 0.5, "mu": 0.5, "k_p": -1e-4}, "k_p"),
    (bl.TangentialRestitution, {"r": 0.5, "mu": 0.5, "e_t": 1.2}, "e_t"),
])
def test_bad_penner_parameters(cls, kwargs, bad):
    with pytest.raises(ParameterError) as err:
        cls(**kwargs)
    assert (err.value.law, err.value.parameter, err.value.value) == (cls.__name__, bad, kwargs[bad])


def test_immutable_and_replace():
    law = bl.Rigid(r=0.5, mu=0.4)
    with pytest.raises(AttributeError, match="replace"):
        law.r = 0.6
    other = law.replace(mu=0.2)
    assert other == bl.Rigid(r=0.5, mu=0.2) and law.mu == 0.4
    with pytest.raises(ParameterError) as err:
        law.replace(nu=1.0)
    assert (err.value.law, err.value.parameter) == ("Rigid", "nu")
    with pytest.raises(ParameterError):
        law.replace(r=2.0)


def test_repr_and_equality():
    assert repr(bl.Rigid.published("A")) == "Rigid(r=0.544, mu=0.997)"
    assert repr(bl.Rigid()) == "Rigid(r=None, mu=None)"
    assert bl.PennerVarying.published("B") == bl.PennerVarying(r=0.222, mu=0.999, k_p=2.973e-4)
    assert bl.Rigid(r=0.5, mu=0.4) != bl.Rigid(r=0.5, mu=0.41)
    assert len({bl.Rigid(r=0.5, mu=0.4), bl.Rigid(r=0.5, mu=0.4)}) == 1
    assert "0.891" in repr(bl.PiecewiseAffine.published("A"))


@pytest.mark.parametrize("law", [*RIGID_FAMILY, bl.PiecewiseAffine.published("B"), bl.Rigid()],
                         ids=lambda m: type(m).__name__)
def test_json_round_trip(law, tmp_path, landings):
    text = law.to_json(tmp_path / "law.json")
    again = bl.BounceModel.from_dict(json.loads(text))
    assert again == law and type(again) is type(law)
    assert bl.load_law(tmp_path / "law.json") == law
    if law.is_fitted:
        p = np.abs(landings) * np.array([1, -1, 1])
        np.testing.assert_array_equal(again.predict(p, plausible=None), law.predict(p, plausible=None))


def test_from_dict_errors(tmp_path):
    with pytest.raises(UnknownLawError) as err:  # a ParameterError
        bl.BounceModel.from_dict({"law": "Nope", "parameters": {}})
    assert err.value.law_name == "Nope"
    with pytest.raises(ParameterError) as err:
        bl.BounceModel.from_dict({"parameters": {}})
    assert err.value.parameter == "law"  # the key missing
    with pytest.raises(ParameterError) as err:
        bl.PennerFixed.from_dict(bl.Rigid(r=0.5, mu=0.5).to_dict())
    assert (err.value.parameter, err.value.value) == ("law", "Rigid")
    with pytest.raises(ParameterError) as err:
        bl.BounceModel.from_dict({"law": "Rigid", "parameters": {"r": 0.5, "q": 1}})
    assert (err.value.law, err.value.parameter) == ("Rigid", "q")
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(ParameterError) as err:
        bl.load_law(tmp_path / "bad.json")
    assert (err.value.parameter, err.value.value) == ("path", str(tmp_path / "bad.json"))


@pytest.mark.parametrize("campaign", ["A", "B", "a"])
def test_published_constructors(campaign):
    key = campaign.upper()
    t3 = bl.published.TABLE3
    assert bl.Rigid.published(campaign).parameters == {"r": t3.loc[(key, "Rigid"), "r"],
                                                       "mu": t3.loc[(key, "Rigid"), "mu"]}
    assert bl.PennerFixed.published(campaign).beta_deg == t3.loc[(key, "PennerFixed"), "beta_deg"]
    assert bl.PennerVarying.published(campaign).k_p == t3.loc[(key, "PennerVarying"), "k_p"]
    pw = bl.PiecewiseAffine.published(campaign)
    np.testing.assert_array_equal(pw.A2, bl.published.PIECEWISE[key]["A2"])
    with pytest.raises(ValueError) as err:
        bl.Rigid.published("C")
    assert err.value.option == "campaign"


def test_default_bounds():
    assert bl.Rigid.default_bounds() == {"r": (0.0, 1.0), "mu": (0.0, 1.5)}
    assert bl.PennerFixed.default_bounds()["beta_deg"] == (0.0, 45.0)
    assert bl.PennerVarying.default_bounds()["k_p"] == (0.0, bl.laws.K_P_MAX)


# ------------------------------------------------------------------------------------ a user's law
class Frictionless(BounceModel):
    """pF = [xdot0, -e ydot0, omega0]: the one-small-class extension point."""

    e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="restitution")
    regimes = ("bounce",)

    def _predict(self, p, e):
        return p * np.array([1.0, -e, 1.0])

    def _regime(self, p, e):
        return np.zeros(len(p), dtype=np.int8)


def test_user_defined_law(landings, tmp_path):
    law = Frictionless(e=0.5)
    out = law.predict(landings, plausible=None)
    np.testing.assert_array_equal(out[:, 1], -0.5 * landings[:, 1])
    assert "Frictionless" in bl.laws.registered_laws()
    law.to_json(tmp_path / "f.json")
    assert bl.load_law(tmp_path / "f.json") == law
    with pytest.raises(ParameterError):
        Frictionless(e=2.0)


# ------------------------------------------------------------------------------- numeric helpers
def test_fast_atan_and_sincos_accuracy():
    from numba import njit

    from bouncelab.laws import _kernels

    @njit
    def run(num, den, x, out):
        for i in range(num.size):
            out[i, 0] = _kernels.atan_ratio(num[i], den[i])
            out[i, 1], out[i, 2] = _kernels.sincos_quadrant(x[i])

    rng = np.random.default_rng(0)
    num = 10 ** rng.uniform(-4, 4, 100000)
    den = 10 ** rng.uniform(-4, 4, 100000)
    den[:5] = 0.0
    x = rng.uniform(0, np.pi / 2, 100000)
    x[:3] = [0.0, np.pi / 4, np.pi / 2]
    out = np.empty((100000, 3))
    run(num, den, x, out)
    np.testing.assert_allclose(out[:, 0], np.arctan2(num, den), rtol=5e-16)
    np.testing.assert_allclose(out[:, 1], np.sin(x), rtol=5e-16, atol=1e-300)
    np.testing.assert_allclose(out[:, 2], np.cos(x), rtol=5e-16, atol=2e-16)


@pytest.mark.parametrize(("row", "col", "value"), [(77777, 2, np.nan), (88888, 1, 3.0), (99999, 0, np.inf)])
def test_large_arrays_are_checked_too(row, col, value):
    """Past FAST_CHECK_MIN bounces a compiled pass checks the values; errors still name the row."""
    from bouncelab.core.validation import FAST_CHECK_MIN

    p = np.random.default_rng(0).uniform(1, 100, (2 * FAST_CHECK_MIN, 3)) * np.array([1, -1, 1])
    p[row, col] = value
    with pytest.raises(DataError) as err:
        bl.Rigid(r=0.5, mu=0.5).predict(p)
    assert (err.value.column, err.value.row) == (f"landing.{('xdot', 'ydot', 'omega')[col]}", row + 1)


# ------------------------------------------------------------------------- review fixes (issue 8)
def test_tangential_regimes_agree_with_its_own_liftoff(landings):
    """The paper's rule on the law's own lift-off: slip only if v_P keeps its sign (0.1 said slip_forward here)."""
    law = bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.5)
    out = law.predict([1000.0, -800.0, 400.0], plausible=None)
    assert out[0] + out[2] == pytest.approx(-280.0)
    assert law.regime([1000.0, -800.0, 400.0], plausible=None) == "roll"
    for e_t in (0.0, 0.3, 0.9):
        law = bl.TangentialRestitution(r=0.5, mu=0.3, e_t=e_t)
        v0 = landings[:, 0] + landings[:, 2]
        out = law.predict(landings, plausible=None)
        vf = out[:, 0] + out[:, 2]
        measured = bl.classify_slip_roll(landings, out, tol=1e-6)  # a rigid roll leaves with v_P ~ 1e-13
        regime = law.regime(landings, plausible=None)
        slipping = regime != "roll"
        assert slipping.sum() > 100 and (~slipping).sum() > 100
        np.testing.assert_array_equal(np.where(slipping, "slip", "roll"), measured)
        assert np.all(np.sign(vf[slipping]) == np.sign(v0[slipping]))
        assert np.all((regime == "slip_forward") == (slipping & (v0 > 0)))


def test_penner_jump_at_vertical_impact_and_its_continuous_variant():
    law = bl.PennerFixed.published("B")
    p = np.array([[1.0, -1000.0, 0.0], [-1.0, -1000.0, 0.0]])
    np.testing.assert_allclose(law.predict(p)[:, 0], [-257.0, 257.0], atol=0.5)  # the documented jump
    assert law.predict(p)[0, 0] == pytest.approx(-257.34, abs=0.01)
    smooth = law.replace(fade_xdot=50.0)
    assert np.abs(smooth.predict(p)[:, 0]).max() < 10.0
    # published behaviour unchanged where |xdot0| >= the fade scale, and the option round-trips
    far = np.array([[60.0, -1000.0, 10.0], [800.0, -300.0, 100.0], [-75.0, -500.0, -20.0]])
    np.testing.assert_allclose(smooth.predict(far), law.predict(far), rtol=1e-14, atol=1e-12)
    assert bl.BounceModel.from_dict(json.loads(smooth.to_json())) == smooth
    # continuous through xdot0 = 0, for both laws
    for faded in (smooth, bl.PennerVarying.published("A").replace(fade_xdot=30.0)):
        x = np.linspace(-2.0, 2.0, 4001)
        q = np.column_stack([x, np.full_like(x, -900.0), np.full_like(x, 200.0)])
        assert np.abs(np.diff(faded.predict(q), axis=0)).max() < 1.0
        assert faded.predict(q[2000:2001])[0, 0] == pytest.approx(bl.Rigid(r=faded.r, mu=faded.mu).predict(
            q[2000:2001])[0, 0])
    with pytest.raises(ParameterError) as err:
        law.replace(fade_xdot=-1.0)
    assert (err.value.law, err.value.parameter, err.value.value) == ("PennerFixed", "fade_xdot", -1.0)
    for not_a_speed in ("50", True, np.nan, [50.0]):  # the tilted-surface laws share one check with CraterContact
        with pytest.raises(ParameterError) as err:
            law.replace(fade_xdot=not_a_speed)
        assert err.value.parameter == "fade_xdot"
    assert law.replace(fade_xdot=None).fade_xdot is None and law.replace(fade_xdot=40).fade_xdot == 40.0
    beta = bl.PennerVarying.published("A").replace(fade_xdot=30.0).beta_deg([[15.0, -900.0, 0.0], [0.0, -900.0, 0.0]])
    assert beta[1] == 0.0 and 0 < beta[0] < bl.PennerVarying.published("A").beta_deg([[15.0, -900.0, 0.0]])[0]


def test_plane_prints_finite_when_nearly_parallel_to_omega():
    good = bl.published.piecewise_parameters("A")
    law = bl.PiecewiseAffine(**{**good, "normal": [-0.98, 0.2, 1.5e-15], "offset": 430.0})
    text = law.plane_equation()
    assert "e+" not in text and "inf" not in text and "nan" not in text
    assert text.startswith("-0.98·xdot0 + 0.2·ydot0")
    u, d = law.plane_unit_form()
    assert np.linalg.norm(u) == pytest.approx(1.0) and np.isfinite(d)
    with pytest.raises(ParameterError) as err:  # no 'omega0 = ...' form
        law.printed_plane()
    assert (err.value.law, err.value.parameter) == ("PiecewiseAffine", "normal")
    lines = "\n".join(law._summary_lines())
    assert "paper's form" not in lines and "unit normal" in lines
    assert "(paper's form): 0.891·xdot0" in "\n".join(bl.PiecewiseAffine.published("A")._summary_lines())


def test_published_campaign_error_is_typed():
    with pytest.raises(DataError) as err:
        bl.Rigid.published("C")
    assert err.value.option == "campaign"
    with pytest.raises(ParameterError) as err:  # not a law of Table 3
        bl.published.rigid_family_parameters("A", "PiecewiseAffine")
    assert err.value.law == "PiecewiseAffine"
