"""Shared validation of bounce-state arrays (bouncelab.core.validation) and the error types."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bouncelab.core.errors import BouncelabError, DataError, FitError, NotFittedError, ParameterError
from bouncelab.core.validation import as_states, check_same_length

P0 = np.array([
    [100.0, -200.0, 50.0],
    [300.0, -400.0, -20.0],
    [500.0, -600.0, 700.0],
    [50.0, -90.0, 0.0],
])


# --------------------------------------------------------------------------- plain arrays
def test_list_of_lists():
    arr, wrap = as_states(P0.tolist())
    assert arr.dtype == np.float64 and arr.flags.c_contiguous
    np.testing.assert_array_equal(arr, P0)
    assert wrap(arr * 2).shape == (4, 3)


def test_single_state_shape_3():
    arr, wrap = as_states([1.0, -2.0, 3.0])
    assert arr.shape == (1, 3)
    out = wrap(arr + 1)
    assert out.shape == (3,)
    np.testing.assert_array_equal(out, [2.0, -1.0, 4.0])
    # a per-bounce scalar result comes back 0-d
    assert wrap(arr[:, 0]).shape == ()


def test_integer_input_becomes_float64():
    arr, _ = as_states(np.array([[1, -2, 3]], dtype=np.int32))
    assert arr.dtype == np.float64
    np.testing.assert_array_equal(arr, [[1.0, -2.0, 3.0]])


def test_nd_states_flatten_row_major_and_wrap_restores_shape():
    states = np.arange(2 * 5 * 3, dtype=float).reshape(2, 5, 3)
    arr, wrap = as_states(states)
    assert arr.shape == (10, 3)
    np.testing.assert_array_equal(arr[6], states[1, 1])  # row-major order
    out = wrap(arr * 10)
    assert out.shape == (2, 5, 3)
    np.testing.assert_array_equal(out, states * 10)
    assert wrap(arr[:, 0]).shape == (2, 5)  # per-bounce results keep the leading shape


def test_fortran_order_becomes_c_contiguous():
    states = np.asfortranarray(P0)
    arr, _ = as_states(states)
    assert arr.flags.c_contiguous
    np.testing.assert_array_equal(arr, P0)


# --------------------------------------------------------------------------- DataArrays
def _labelled(values, comps=("xdot", "ydot", "omega"), dims=("bounce", "component")):
    coords = {"component": list(comps)}
    if "bounce" in dims:
        coords["bounce"] = np.arange(10, 10 + values.shape[dims.index("bounce")])
    return xr.DataArray(values, dims=dims, coords=coords)


@pytest.mark.parametrize("order", [(0, 1, 2), (2, 0, 1), (1, 2, 0), (2, 1, 0)])
def test_dataarray_any_component_order(order):
    comps = [("xdot", "ydot", "omega")[i] for i in order]
    da = _labelled(P0[:, order], comps)
    arr, _ = as_states(da)
    np.testing.assert_array_equal(arr, P0)  # always xdot, ydot, omega


@pytest.mark.parametrize("order", [(0, 1, 2), (2, 0, 1)])
def test_dataarray_component_first(order):
    comps = [("xdot", "ydot", "omega")[i] for i in order]
    da = _labelled(P0[:, order].T, comps, dims=("component", "bounce"))
    arr, wrap = as_states(da)
    np.testing.assert_array_equal(arr, P0)
    out = wrap(arr)
    assert out.dims == ("bounce", "component")
    assert list(out["component"].values) == ["xdot", "ydot", "omega"]
    assert list(out["unit"].values) == ["radius/s", "radius/s", "rad/s"]
    np.testing.assert_array_equal(out["bounce"].values, np.arange(10, 14))
    np.testing.assert_array_equal(out.values, P0)


def test_dataarray_component_in_the_middle_of_three_dims():
    states = np.random.default_rng(0).normal(size=(2, 4, 3)) * 100
    states[..., 1] = -np.abs(states[..., 1]) - 1
    # stored as (setting, component, repeat) with components omega, xdot, ydot
    stored = states[..., [2, 0, 1]].transpose(0, 2, 1)
    da = xr.DataArray(stored, dims=("setting", "component", "repeat"),
                      coords={"component": ["omega", "xdot", "ydot"], "setting": ["s1", "s2"]})
    arr, wrap = as_states(da, landing=True)
    np.testing.assert_array_equal(arr, states.reshape(-1, 3))
    out = wrap(arr)
    assert out.dims == ("setting", "repeat", "component")
    assert list(out["setting"].values) == ["s1", "s2"]
    np.testing.assert_array_equal(out.values, states)


def test_dataarray_without_labels_is_positional():
    da = xr.DataArray(P0.T, dims=("component", "bounce"))
    arr, _ = as_states(da)
    np.testing.assert_array_equal(arr, P0)


def test_dataarray_without_component_dim():
    da = xr.DataArray(P0, dims=("bounce", "comp"))
    with pytest.raises(DataError) as e:
        as_states(da)
    assert e.value.option == "landing" and "component" in e.value.message


def test_dataarray_wrong_component_size():
    da = xr.DataArray(np.zeros((4, 2)), dims=("bounce", "component"))
    with pytest.raises(DataError) as e:
        as_states(da)
    assert e.value.option == "landing"


@pytest.mark.parametrize("labels", [("xdot", "ydot", "spin"), ("xdot", "xdot", "omega"), ("x", "y", "w")])
def test_dataarray_bad_component_labels(labels):
    with pytest.raises(DataError) as e:
        as_states(_labelled(P0, labels))
    assert e.value.option == "landing"


def test_dataarray_extra_component_label():
    da = xr.DataArray(np.zeros((2, 4)), dims=("bounce", "component"),
                      coords={"component": ["xdot", "ydot", "omega", "vp"]})
    with pytest.raises(DataError):
        as_states(da)


def test_dataarray_nan_row_and_column_follow_the_labels():
    values = P0.T[[2, 0, 1]].copy()  # (component, bounce) with omega, xdot, ydot
    values[0, 2] = np.nan  # omega of the third bounce
    da = _labelled(values, ("omega", "xdot", "ydot"), dims=("component", "bounce"))
    with pytest.raises(DataError) as info:
        as_states(da, "landing")
    assert info.value.row == 3
    assert info.value.column == "landing.omega"


def test_dataarray_input_not_modified():
    da = _labelled(P0[:, [2, 0, 1]].T.copy(), ("omega", "xdot", "ydot"), dims=("component", "bounce"))
    before = da.copy(deep=True)
    as_states(da)
    xr.testing.assert_identical(da, before)


# --------------------------------------------------------------------------- bad values
@pytest.mark.parametrize(("row", "col", "value", "what"), [
    (0, 0, np.nan, "NaN"), (2, 1, np.inf, "infinite"), (3, 2, -np.inf, "infinite"), (1, 2, np.nan, "NaN"),
])
def test_nonfinite_names_row_and_column(row, col, value, what):
    bad = P0.copy()
    bad[row, col] = value
    before = bad.copy()
    with pytest.raises(DataError) as info:
        as_states(bad, "liftoff")
    err = info.value
    assert err.row == row + 1  # 1-based
    assert err.column == f"liftoff.{('xdot', 'ydot', 'omega')[col]}"
    assert what in err.message
    np.testing.assert_array_equal(bad, before)  # nothing changed


def test_nonfinite_first_bad_row_reported_and_count():
    bad = P0.copy()
    bad[1, 2] = np.nan
    bad[3, 0] = np.nan
    with pytest.raises(DataError) as info:
        as_states(bad)
    assert info.value.row == 2
    assert "(2 bounce(s) affected)" in info.value.message  # the count is said, and only in words


def test_nonfinite_row_in_nd_input_is_the_flattened_row():
    bad = np.tile(P0[0], (2, 3, 1))
    bad[1, 0, 1] = np.nan  # flattened row 4
    with pytest.raises(DataError) as info:
        as_states(bad)
    assert info.value.row == 4
    assert info.value.column == "landing.ydot"


@pytest.mark.parametrize("ydot", [0.0, 5.0])
def test_landing_moving_up_is_rejected(ydot):
    bad = P0.copy()
    bad[2, 1] = ydot
    with pytest.raises(DataError) as info:
        as_states(bad, "landing", landing=True)
    assert info.value.row == 3
    assert info.value.column == "landing.ydot"
    # the same values are fine when they are not a landing
    arr, _ = as_states(bad, "liftoff")
    assert arr[2, 1] == ydot


def test_landing_error_carries_the_name():
    bad = P0.copy()
    bad[0, 1] = 1.0
    with pytest.raises(DataError) as info:
        as_states(bad, "p0", landing=True)
    assert info.value.column == "p0.ydot"


@pytest.mark.parametrize("bad", [np.zeros((0, 3)), []])
def test_empty(bad):
    with pytest.raises(DataError):
        as_states(bad)


def test_empty_message():
    with pytest.raises(DataError) as e:
        as_states(np.zeros((0, 3)), "landing")
    assert e.value.option == "landing" and (e.value.row, e.value.column) == (None, None)


@pytest.mark.parametrize("bad", [5.0, [1.0, 2.0], np.zeros((4, 2)), np.zeros((4, 4)), np.zeros((3, 1))])
def test_wrong_shape(bad):
    with pytest.raises(DataError) as e:
        as_states(bad)
    assert e.value.option == "landing"


@pytest.mark.parametrize("bad", [[["a", "b", "c"]], [[1.0, 2.0, 3.0], [1.0, 2.0]], [[1 + 2j, -1, 0]]])
def test_non_numeric(bad):
    with pytest.raises(DataError) as e:
        as_states(bad)
    assert e.value.option == "landing" and "numeric" in e.value.message


def test_file_is_named():
    bad = P0.copy()
    bad[0, 0] = np.nan
    with pytest.raises(DataError) as info:
        as_states(bad, file="bounces.csv")
    assert info.value.file == "bounces.csv"
    assert "bounces.csv" in str(info.value)


def test_check_same_length():
    check_same_length(P0, P0 + 1, "a", "b")
    with pytest.raises(DataError) as e:
        check_same_length(P0, P0[:3], "a", "b")
    assert e.value.option == "b"


# --------------------------------------------------------------------------- errors
def test_error_hierarchy():
    assert issubclass(DataError, BouncelabError) and issubclass(DataError, ValueError)
    assert issubclass(ParameterError, BouncelabError) and issubclass(ParameterError, ValueError)
    assert issubclass(NotFittedError, ParameterError)
    assert issubclass(FitError, BouncelabError) and issubclass(FitError, ValueError)
    assert not issubclass(DataError, ParameterError)


def test_data_error_message_names_where():
    err = DataError("bad value", file="f.csv", column="vx0", row=7)
    assert str(err) == "file 'f.csv', column 'vx0', row 7: bad value"
    assert (err.file, err.column, err.row, err.message) == ("f.csv", "vx0", 7, "bad value")
    assert str(DataError("plain")) == "plain"
    assert str(DataError("x", row=1)) == "row 1: x"


def test_data_error_file_path_is_stringified():
    from pathlib import Path

    err = DataError("m", file=Path("/tmp/a.nc"))
    assert err.file == "/tmp/a.nc"
    assert "'/tmp/a.nc'" in str(err)


# ------------------------------------------------------------------ what predict used to misread (issue 7)
def test_dataframe_columns_are_read_by_name():
    """bouncelab 0.1 read columns omega, ydot, xdot as xdot, ydot, omega."""
    import pandas as pd

    import bouncelab as bl

    law = bl.Rigid.published("A")
    df = pd.DataFrame(P0[:, [2, 1, 0]], columns=["omega", "ydot", "xdot"])
    np.testing.assert_array_equal(law.predict(df), law.predict(P0))
    np.testing.assert_array_equal(as_states(pd.DataFrame(P0, columns=["xdot0", "ydot0", "omega0"]))[0], P0)
    np.testing.assert_array_equal(as_states(pd.DataFrame(P0))[0], P0)  # unnamed (0, 1, 2): by position
    with pytest.raises(DataError) as e:
        law.predict(pd.DataFrame(P0, columns=["vx", "vy", "w"]))
    assert e.value.option == "landing" and "['vx', 'vy', 'w']" in e.value.message
    series = pd.Series(P0[0, [2, 0, 1]], index=["omega", "xdot", "ydot"])
    np.testing.assert_array_equal(as_states(series)[0], P0[:1])


def test_masked_values_are_refused():
    """bouncelab 0.1 predicted from the data under a mask."""
    masked = np.ma.masked_array(P0, mask=np.zeros_like(P0, dtype=bool))
    masked[2, 1] = np.ma.masked
    with pytest.raises(DataError) as err:
        as_states(masked, landing=True)
    assert err.value.row == 3 and err.value.column == "landing.ydot"
    np.testing.assert_array_equal(as_states(np.ma.masked_array(P0), landing=True)[0], P0)  # nothing masked


@pytest.mark.parametrize(("values", "what"), [(P0 + 1j, "complex"), (P0 > 0, "boolean"), (P0.astype(str), "text")])
def test_non_real_values_are_refused(values, what):
    """bouncelab 0.1 dropped the imaginary parts with a warning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DataError) as e:
            as_states(values, landing=True)
        assert e.value.option == "landing" and what in e.value.message


@pytest.mark.parametrize("value", [1e308, -1e308, 1.5e8, 1e20])
def test_magnitudes_beyond_any_bounce_are_refused(value):
    """bouncelab 0.1 turned 1e308 into an infinite lift-off."""
    import bouncelab as bl
    from bouncelab.core.validation import STATE_LIMIT

    bad = P0.copy()
    bad[1, 0] = value
    with pytest.raises(DataError) as err:
        bl.Rigid.published("A").predict(bad)
    assert err.value.row == 2 and err.value.column == "landing.xdot"
    big = np.tile(P0, (20_000, 1))  # the compiled check of large arrays too
    big[-1, 2] = value
    with pytest.raises(DataError) as err:
        as_states(big)
    assert (err.value.row, err.value.column) == (len(big), "landing.omega")
    edge = P0.copy()
    edge[0, 2] = STATE_LIMIT
    assert as_states(edge)[0][0, 2] == STATE_LIMIT


def test_labelled_input_gives_labelled_output():
    """The docs promise a result of the same kind as the input (bouncelab 0.1 returned a bare array)."""
    import pandas as pd

    import bouncelab as bl

    law = bl.Rigid.published("A")
    df = pd.DataFrame(P0[:, [2, 1, 0]], columns=["omega", "ydot", "xdot"], index=[f"b{i}" for i in range(len(P0))])
    out = law.predict(df)
    assert isinstance(out, pd.DataFrame) and list(out.columns) == ["xdot", "ydot", "omega"]
    assert list(out.index) == list(df.index)
    np.testing.assert_array_equal(out.to_numpy(), law.predict(P0))
    codes = law.regime(df, codes=True)
    assert isinstance(codes, pd.Series) and list(codes.index) == list(df.index)
    one = law.predict(pd.Series(P0[0], index=["xdot", "ydot", "omega"], name="shot 1"))
    assert isinstance(one, pd.Series) and one.name == "shot 1" and list(one.index) == ["xdot", "ydot", "omega"]


def test_dataframe_errors_name_its_own_row_label_and_column():
    """A DataFrame's bad value is named by the frame's index label and column, not only by position."""
    import pandas as pd

    import bouncelab as bl

    law = bl.Rigid.published("A")
    df = pd.DataFrame(P0, columns=["xdot0", "ydot0", "omega0"], index=[10 * i + 7 for i in range(len(P0))])
    df.iloc[1, 1] = 5.0  # a landing moving up
    with pytest.raises(DataError) as err:
        law.predict(df)
    assert (err.value.row, err.value.row_label, err.value.column) == (2, 17, "landing.ydot0")
    labels = [f"s{i}" for i in range(len(P0))]
    shuffled = pd.DataFrame(P0[:, [2, 1, 0]], columns=["omega", "ydot", "xdot"], index=labels)
    shuffled.iloc[2, 0] = np.nan  # omega of row 3
    with pytest.raises(DataError) as err:
        law.predict(shuffled)
    assert (err.value.row, err.value.row_label, err.value.column) == (3, "s2", "landing.omega")
    with pytest.raises(DataError) as err:
        bl.make_campaign(shuffled, P0)
    assert (err.value.row, err.value.row_label) == (3, "s2")
    with pytest.raises(DataError) as err:  # plain arrays keep their position only
        law.predict(np.where(np.isnan(shuffled.to_numpy()[:, [2, 1, 0]]), np.nan, P0))
    assert err.value.row == 3 and err.value.row_label is None and "label" not in str(err.value)


def test_error_rows_name_a_numpy_index_label_as_a_plain_value():
    from bouncelab.core.errors import DataError, plain_label, row_text

    assert row_text(3) == "row 3" and row_text(3, np.int64(7)) == "row 3 (row label 7)"
    assert row_text(2, np.str_("shot-2")) == "row 2 (row label 'shot-2')"
    assert type(plain_label(np.float64(1.5))) is float and plain_label("b") == "b"
    exc = DataError("bad", file="f.csv", column="vy0", row=3, row_label=np.int64(7))
    assert exc.row_label == 7 and type(exc.row_label) is int
    assert str(exc) == "file 'f.csv', column 'vy0', row 3 (row label 7): bad"
