"""The campaign container (bouncelab.data.campaign)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bouncelab.core.errors import DataError
from bouncelab.data.campaign import CONVENTIONS, make_campaign, validate_campaign
from bouncelab.data.inputs import campaign_arrays

P0 = np.array([
    [100.0, -200.0, 50.0],
    [300.0, -400.0, -20.0],
    [500.0, -600.0, 700.0],
    [50.0, -90.0, 0.0],
])
PF = np.array([
    [60.0, 80.0, 10.0],
    [150.0, 160.0, -90.0],
    [200.0, 250.0, 400.0],
    [20.0, 30.0, -5.0],
])
PI0 = np.full((4, 3), 2.5)
PIF = np.full((4, 3), 4.0)


def _campaign(**kw):
    args = {"setting": [1, 1, 2, 2], "landing_pi": PI0, "liftoff_pi": PIF, "campaign": "X",
            "surface": "lab floor", "source": "unit test", "data_kind": "measured"}
    args.update(kw)
    return make_campaign(P0, PF, **args)


# --------------------------------------------------------------------------- make_campaign
def test_layout():
    ds = _campaign()
    assert dict(ds.sizes) == {"bounce": 4, "component": 3}
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        assert ds[var].dims == ("bounce", "component")
        assert ds[var].dtype == np.float64
    np.testing.assert_array_equal(ds["landing"].values, P0)
    np.testing.assert_array_equal(ds["liftoff"].values, PF)
    np.testing.assert_array_equal(ds["landing_pi"].values, PI0)
    np.testing.assert_array_equal(ds["liftoff_pi"].values, PIF)
    np.testing.assert_array_equal(ds["bounce"].values, [0, 1, 2, 3])
    assert list(ds["component"].values) == ["xdot", "ydot", "omega"]
    assert ds["unit"].dims == ("component",)
    assert list(ds["unit"].values) == ["radius/s", "radius/s", "rad/s"]
    assert ds["setting"].dims == ("bounce",)
    assert "setting" in ds.coords


def test_attrs():
    ds = _campaign(ball_radius_m=0.021, attrs={"operator": "KJ", "note": 3})
    assert ds.attrs["campaign"] == "X"
    assert ds.attrs["surface"] == "lab floor"
    assert ds.attrs["source"] == "unit test"
    assert ds.attrs["data_kind"] == "measured"
    assert ds.attrs["ball_radius_m"] == 0.021 and isinstance(ds.attrs["ball_radius_m"], float)
    assert ds.attrs["operator"] == "KJ" and ds.attrs["note"] == 3
    assert ds.attrs["conventions"] == CONVENTIONS
    for phrase in ("radii per second", "rad/s", "y up", "ydot < 0", "backspin", "v_P = xdot + omega"):
        assert phrase in CONVENTIONS


def test_defaults():
    ds = make_campaign(P0, PF)
    assert set(ds.data_vars) == {"landing", "liftoff"}
    assert "setting" not in ds.coords
    assert ds.attrs["data_kind"] == "unknown"
    assert ds.attrs["ball_radius_m"] == 0.02135
    assert ds.attrs["campaign"] == ""


def test_attrs_cannot_replace_conventions():
    ds = _campaign(attrs={"conventions": "y down"})
    assert ds.attrs["conventions"] == CONVENTIONS


def test_data_kind_in_attrs_is_checked():
    assert _campaign(attrs={"data_kind": "synthetic surrogate"}).attrs["data_kind"] == "synthetic surrogate"
    with pytest.raises(DataError, match="data_kind"):
        _campaign(attrs={"data_kind": "made up"})


@pytest.mark.parametrize("kind", ["measured", "synthetic surrogate", "unknown"])
def test_data_kinds(kind):
    assert _campaign(data_kind=kind).attrs["data_kind"] == kind


@pytest.mark.parametrize("kind", ["synthetic", "Measured", ""])
def test_bad_data_kind(kind):
    with pytest.raises(DataError, match="data_kind"):
        _campaign(data_kind=kind)


def test_labelled_inputs_are_put_in_canonical_order():
    da = xr.DataArray(P0[:, [2, 0, 1]].T, dims=("component", "bounce"),
                      coords={"component": ["omega", "xdot", "ydot"]})
    ds = make_campaign(da, PF)
    np.testing.assert_array_equal(ds["landing"].values, P0)


# settings
def test_setting_ints_become_int64():
    ds = _campaign(setting=np.array([3, 3, 4, 4], dtype=np.int16))
    assert ds["setting"].dtype == np.int64
    np.testing.assert_array_equal(ds["setting"].values, [3, 3, 4, 4])


def test_setting_integer_valued_floats_become_int64():
    ds = _campaign(setting=[1.0, 1.0, 2.0, 7.0])
    assert ds["setting"].dtype == np.int64
    np.testing.assert_array_equal(ds["setting"].values, [1, 1, 2, 7])


def test_setting_fractional_floats_stay_float():
    ds = _campaign(setting=[1.5, 1.5, 2.0, 2.0])
    assert ds["setting"].dtype.kind == "f"
    np.testing.assert_array_equal(ds["setting"].values, [1.5, 1.5, 2.0, 2.0])


def test_setting_strings():
    ds = _campaign(setting=["a", "a", "b", "long name"])
    assert ds["setting"].dtype.kind == "U"
    assert list(ds["setting"].values) == ["a", "a", "b", "long name"]
    ds = _campaign(setting=np.array([b"a", b"a", b"b", b"b"]))
    assert ds["setting"].dtype.kind == "U"
    assert list(ds["setting"].values) == ["a", "a", "b", "b"]
    ds = _campaign(setting=np.array(["a", 2, "b", 3], dtype=object))
    assert list(ds["setting"].values) == ["a", "2", "b", "3"]


@pytest.mark.parametrize("bad", [[1.0, np.nan, 2.0, 2.0], [1.0, 1.0, 2.0, np.inf]])
def test_setting_nan(bad):
    with pytest.raises(DataError) as info:
        _campaign(setting=bad)
    assert info.value.column == "setting"
    assert info.value.row == 2 if np.isnan(bad[1]) else info.value.row == 4


@pytest.mark.parametrize("bad", [["a", None, "b", "b"], np.array([1, 2, float("nan"), 3], dtype=object)])
def test_setting_missing_in_object_array(bad):
    with pytest.raises(DataError) as info:
        _campaign(setting=bad)
    assert (info.value.column, info.value.row) == ("setting", 2 if bad[1] is None else 3)


@pytest.mark.parametrize("bad", [[1, 2, 3], [[1, 2], [3, 4]], 5])
def test_setting_shape(bad):
    with pytest.raises(DataError, match="one label per bounce"):
        _campaign(setting=bad)


# prediction intervals
def test_negative_pi():
    bad = PI0.copy()
    bad[2, 1] = -0.1
    with pytest.raises(DataError) as info:
        _campaign(landing_pi=bad)
    assert info.value.column == "landing_pi"
    assert info.value.row == 3
    assert bad[2, 1] == -0.1


def test_nan_pi():
    bad = PIF.copy()
    bad[1, 2] = np.nan
    with pytest.raises(DataError) as info:
        _campaign(liftoff_pi=bad)
    assert info.value.column == "liftoff_pi.omega"
    assert info.value.row == 2


def test_pi_shape_mismatch():
    with pytest.raises(DataError, match="landing_pi"):
        _campaign(landing_pi=PI0[:3])


def test_zero_pi_allowed():
    assert float(_campaign(liftoff_pi=np.zeros((4, 3)))["liftoff_pi"].sum()) == 0.0


# states
def test_length_mismatch():
    with pytest.raises(DataError, match="shape"):
        make_campaign(P0, PF[:3])


def test_landing_moving_up():
    bad = P0.copy()
    bad[3, 1] = 10.0
    with pytest.raises(DataError) as info:
        make_campaign(bad, PF)
    assert (info.value.row, info.value.column) == (4, "landing.ydot")


def test_liftoff_nan():
    bad = PF.copy()
    bad[0, 0] = np.nan
    with pytest.raises(DataError) as info:
        make_campaign(P0, bad)
    assert (info.value.row, info.value.column) == (1, "liftoff.xdot")


def test_campaign_does_not_share_memory_with_inputs():
    p0, pf, pi = P0.copy(), PF.copy(), PI0.copy()
    ds = make_campaign(p0, pf, landing_pi=pi)
    p0[0, 1] = 99.0  # would make the stored landing move up
    pf[:] = 0.0
    pi[:] = -1.0
    np.testing.assert_array_equal(ds["landing"].values, P0)
    np.testing.assert_array_equal(ds["liftoff"].values, PF)
    np.testing.assert_array_equal(ds["landing_pi"].values, PI0)


def test_failed_call_changes_nothing():
    p0, pf = P0.copy(), PF.copy()
    setting = np.array([1.0, np.nan, 2.0, 2.0])
    with pytest.raises(DataError):
        make_campaign(p0, pf, setting=setting)
    np.testing.assert_array_equal(p0, P0)
    np.testing.assert_array_equal(pf, PF)
    assert np.isnan(setting[1]) and setting[0] == 1.0


# --------------------------------------------------------------------------- validate_campaign
def test_validate_is_identity_on_a_good_campaign():
    ds = _campaign(attrs={"extra": "kept"})
    xr.testing.assert_identical(validate_campaign(ds), ds)


def test_validate_canonicalises_a_transposed_reordered_dataset():
    ds = _campaign(attrs={"extra": "kept"})
    messy = ds.transpose("component", "bounce").isel(component=[2, 0, 1])
    messy = messy.assign_coords(bounce=[10, 11, 12, 13])
    assert messy["landing"].dims == ("component", "bounce")
    out = validate_campaign(messy)
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        assert out[var].dims == ("bounce", "component")
    assert list(out["component"].values) == ["xdot", "ydot", "omega"]
    np.testing.assert_array_equal(out["landing"].values, P0)
    np.testing.assert_array_equal(out["liftoff"].values, PF)
    np.testing.assert_array_equal(out["bounce"].values, [10, 11, 12, 13])
    np.testing.assert_array_equal(out["setting"].values, [1, 1, 2, 2])
    assert out.attrs["extra"] == "kept"
    assert out.attrs["campaign"] == "X" and out.attrs["data_kind"] == "measured"
    assert list(out["unit"].values) == ["radius/s", "radius/s", "rad/s"]


def test_validate_restores_conventions():
    ds = _campaign()
    ds.attrs["conventions"] = "something else"
    assert validate_campaign(ds).attrs["conventions"] == CONVENTIONS


@pytest.mark.parametrize("var", ["landing", "liftoff"])
def test_validate_missing_variable(var):
    ds = _campaign().drop_vars(var)
    with pytest.raises(DataError, match=f"no '{var}' variable"):
        validate_campaign(ds, file="c.nc")


def test_validate_not_a_dataset():
    with pytest.raises(DataError, match=r"xarray\.Dataset"):
        validate_campaign(P0)


def test_validate_wrong_dims():
    ds = _campaign().rename({"bounce": "shot"})
    with pytest.raises(DataError, match="dimensions"):
        validate_campaign(ds)


def test_validate_pi_with_wrong_dims():
    ds = _campaign()
    ds["landing_pi"] = xr.DataArray(np.ones(4), dims=("bounce",))
    with pytest.raises(DataError, match="landing_pi"):
        validate_campaign(ds)


def test_validate_rejects_physical_units():
    ds = _campaign().assign_coords(unit=("component", ["m/s", "m/s", "rpm"]))
    with pytest.raises(DataError) as info:
        validate_campaign(ds)
    assert info.value.column == "unit"


def test_validate_accepts_unit_aliases_of_scaled_units():
    ds = _campaign().assign_coords(unit=("component", ["radii/s", "1/s", "rad/s"]))
    out = validate_campaign(ds)
    assert list(out["unit"].values) == ["radius/s", "radius/s", "rad/s"]


def test_validate_bad_values_and_kind():
    ds = _campaign()
    ds["landing"][1, 1] = 3.0
    with pytest.raises(DataError) as info:
        validate_campaign(ds, file="c.nc")
    assert (info.value.file, info.value.row, info.value.column) == ("c.nc", 2, "landing.ydot")
    ds = _campaign()
    ds.attrs["data_kind"] = "guess"
    with pytest.raises(DataError, match="data_kind"):
        validate_campaign(ds)


def test_validate_does_not_modify_its_input():
    ds = _campaign().transpose("component", "bounce")
    before = ds.copy(deep=True)
    validate_campaign(ds)
    xr.testing.assert_identical(ds, before)


# --------------------------------------------------------------------------- campaign_arrays
def test_arrays_from_dataset():
    p0, pf, setting = campaign_arrays(_campaign())
    np.testing.assert_array_equal(p0, P0)
    np.testing.assert_array_equal(pf, PF)
    np.testing.assert_array_equal(setting, [1, 1, 2, 2])
    assert campaign_arrays(make_campaign(P0, PF))[2] is None


def test_arrays_from_transposed_dataset():
    ds = _campaign().transpose("component", "bounce").isel(component=[1, 2, 0])
    p0, pf, _ = campaign_arrays(ds)
    np.testing.assert_array_equal(p0, P0)
    np.testing.assert_array_equal(pf, PF)


@pytest.mark.parametrize("pair", [(P0, PF), [P0, PF], (P0.tolist(), PF.tolist()), (P0, PF, None)])
def test_arrays_from_pairs(pair):
    p0, pf, setting = campaign_arrays(pair)
    np.testing.assert_array_equal(p0, P0)
    np.testing.assert_array_equal(pf, PF)
    assert setting is None


def test_arrays_from_triple():
    _, _, setting = campaign_arrays((P0, PF, ["a", "a", "b", "b"]))
    assert list(setting) == ["a", "a", "b", "b"]
    with pytest.raises(DataError, match="one label per bounce"):
        campaign_arrays((P0, PF, [1, 2]))


@pytest.mark.parametrize("bad", [P0, {"landing": P0, "liftoff": PF}, (P0,), (P0, PF, None, None), "A", None])
def test_arrays_bad_types(bad):
    with pytest.raises(DataError, match="campaign Dataset or a"):
        campaign_arrays(bad, name="data")


def test_arrays_checks_values():
    bad = P0.copy()
    bad[0, 1] = 1.0
    with pytest.raises(DataError) as info:
        campaign_arrays((bad, PF))
    assert (info.value.column, info.value.row) == ("landing.ydot", 1)
    with pytest.raises(DataError, match="shape"):
        campaign_arrays((P0, PF[:2]))
    with pytest.raises(DataError, match="no 'liftoff'"):
        campaign_arrays(_campaign().drop_vars("liftoff"))
