"""Slip/roll classification from the contact-point velocity v_P = xdot + omega (paper section 2.4.3)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bouncelab.core.errors import DataError
from bouncelab.core.slip_roll import SLIP_ROLL_CLASSES, classify_slip_roll


def _one(landing, liftoff, **kw):
    out = classify_slip_roll([landing], [liftoff], **kw)
    assert out.shape == (1,)
    return out[0]


# landing v_P = 100 + 50 = 150 > 0; each liftoff below gives the v_P in its comment
LAND_POS = [100.0, -200.0, 50.0]


def test_same_positive_sign_is_slip():
    assert _one(LAND_POS, [80.0, 100.0, 30.0]) == "slip"  # v_P 110


def test_sign_change_is_roll():
    assert _one(LAND_POS, [80.0, 100.0, -90.0]) == "roll"  # v_P -10
    assert _one([100.0, -200.0, -250.0], [80.0, 100.0, -60.0]) == "roll"  # -150 -> +20


def test_topspin_negative_at_both_ends_is_slip():
    assert _one([50.0, -200.0, -300.0], [20.0, 100.0, -60.0]) == "slip"  # -250 -> -40


@pytest.mark.parametrize(("landing", "liftoff"), [
    ([100.0, -200.0, -100.0], [80.0, 100.0, 30.0]),  # v_P 0 at touch-down
    (LAND_POS, [80.0, 100.0, -80.0]),  # v_P 0 at lift-off
    ([100.0, -200.0, -100.0], [80.0, 100.0, -80.0]),  # both zero
])
def test_zero_at_either_end_is_roll(landing, liftoff):
    assert _one(landing, liftoff) == "roll"


def test_only_xdot_plus_omega_matters_not_ydot():
    # same v_P at both ends, wildly different ydot
    assert _one([100.0, -5.0, 50.0], [80.0, 1.0, 30.0]) == "slip"
    assert _one([100.0, -5000.0, 50.0], [80.0, 900.0, 30.0]) == "slip"
    # omega alone positive but v_P negative at lift-off: roll
    assert _one(LAND_POS, [-200.0, 100.0, 150.0]) == "roll"  # v_P -50


def test_tol():
    landing, liftoff = LAND_POS, [80.0, 100.0, -75.0]  # v_P 150 -> 5
    assert _one(landing, liftoff) == "slip"
    assert _one(landing, liftoff, tol=4.9) == "slip"
    assert _one(landing, liftoff, tol=5.0) == "roll"  # |v_P| <= tol counts as zero
    assert _one(landing, liftoff, tol=200.0) == "roll"
    # tol applies at touch-down too
    assert _one([100.0, -200.0, -97.0], [80.0, 100.0, 30.0], tol=3.0) == "roll"  # v_P 3 at touch-down
    assert _one([100.0, -200.0, -97.0], [80.0, 100.0, 30.0], tol=2.9) == "slip"


@pytest.mark.parametrize("tol", [-1.0, float("nan"), float("inf")])
def test_bad_tol(tol):
    with pytest.raises(DataError) as e:  # the library's own error type
        classify_slip_roll([LAND_POS], [[80.0, 100.0, 30.0]], tol=tol)
    assert e.value.option == "tol"


def test_many_and_codes():
    landing = np.array([LAND_POS, LAND_POS, [50.0, -200.0, -300.0], [100.0, -200.0, -100.0]])
    liftoff = np.array([[80.0, 100.0, 30.0], [80.0, 100.0, -90.0], [20.0, 100.0, -60.0], [1.0, 1.0, 1.0]])
    names = classify_slip_roll(landing, liftoff)
    assert list(names) == ["slip", "roll", "slip", "roll"]
    codes = classify_slip_roll(landing, liftoff, codes=True)
    assert codes.dtype == np.int8
    np.testing.assert_array_equal(codes, [1, 0, 1, 0])
    assert SLIP_ROLL_CLASSES == ("roll", "slip")
    np.testing.assert_array_equal(np.asarray(SLIP_ROLL_CLASSES)[codes], names)


def test_dataarray_inputs_in_any_component_order():
    landing = np.array([LAND_POS, [100.0, -200.0, -250.0]])
    liftoff = np.array([[80.0, 100.0, 30.0], [80.0, 100.0, -60.0]])
    da0 = xr.DataArray(landing[:, [2, 1, 0]], dims=("bounce", "component"),
                       coords={"component": ["omega", "ydot", "xdot"]})
    daf = xr.DataArray(liftoff.T, dims=("component", "bounce"), coords={"component": ["xdot", "ydot", "omega"]})
    assert list(classify_slip_roll(da0, daf)) == ["slip", "roll"]


def test_bad_inputs():
    with pytest.raises(DataError) as e:
        classify_slip_roll([[100.0, 5.0, 50.0]], [[80.0, 100.0, 30.0]])
    assert (e.value.column, e.value.row) == ("landing.ydot", 1)
    with pytest.raises(DataError) as e:
        classify_slip_roll([LAND_POS, LAND_POS], [[80.0, 100.0, 30.0]])
    assert e.value.option == "liftoff"
    with pytest.raises(DataError) as e:
        classify_slip_roll([LAND_POS], [[80.0, np.nan, 30.0]])
    assert (e.value.column, e.value.row) == ("liftoff.ydot", 1)


def test_inputs_not_modified():
    landing = np.array([LAND_POS])
    liftoff = np.array([[80.0, 100.0, 30.0]])
    classify_slip_roll(landing, liftoff, tol=1.0)
    np.testing.assert_array_equal(landing, [LAND_POS])
    np.testing.assert_array_equal(liftoff, [[80.0, 100.0, 30.0]])
