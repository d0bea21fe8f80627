"""delta and Delta q (eqs. error and error_individual), worked by hand, and their per-class tables."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core.errors import DataError

# Two bounces with landing norms 5 and 13, prediction errors (0, 0, 0.5) and (3, 4, 12).
P0 = np.array([[3.0, -4.0, 0.0], [5.0, -12.0, 0.0]])
PF = np.array([[1.0, 1.0, 0.0], [10.0, 10.0, 10.0]])
PRED = np.array([[1.0, 1.0, 0.5], [7.0, 6.0, -2.0]])


def test_delta_by_hand():
    # (0.5 / 5 + 13 / 13) / 2
    assert bl.delta(P0, PF, PRED) == pytest.approx((0.1 + 1.0) / 2, rel=1e-15)


def test_delta_q_by_hand():
    expected = [(0 / 5 + 3 / 13) / 2, (0 / 5 + 4 / 13) / 2, (0.5 / 5 + 12 / 13) / 2]
    np.testing.assert_allclose(bl.delta_q(P0, PF, PRED), expected, rtol=1e-15)


def test_perfect_prediction_and_symmetry():
    assert bl.delta(P0, PF, PF) == 0.0
    assert bl.delta(P0, PF, PRED) == bl.delta(P0, PRED, PF)  # the norm of the difference is symmetric
    # delta_q never exceeds delta component-wise, and delta <= sum of delta_q (triangle inequality)
    assert bl.delta(P0, PF, PRED) <= bl.delta_q(P0, PF, PRED).sum() + 1e-15
    assert np.all(bl.delta_q(P0, PF, PRED) <= bl.delta(P0, PF, PRED) + 1e-15)


def test_scaling_by_landing_norm():
    """Doubling every landing halves both measures (the errors are relative to ||p0||)."""
    assert bl.delta(2 * P0, PF, PRED) == pytest.approx(bl.delta(P0, PF, PRED) / 2)
    np.testing.assert_allclose(bl.delta_q(2 * P0, PF, PRED), bl.delta_q(P0, PF, PRED) / 2)


def test_accepts_dataarrays():
    da = xr.DataArray(P0.T, dims=("component", "bounce"), coords={"component": ["xdot", "ydot", "omega"]})
    assert bl.delta(da, PF, PRED) == bl.delta(P0, PF, PRED)


def test_error_table_by_class():
    table = bl.error_table(P0, PF, PRED, ["roll", "slip"])
    assert list(table.index) == ["all", "roll", "slip"]
    assert table.loc["roll", "delta"] == pytest.approx(0.1)
    assert table.loc["slip", "delta"] == pytest.approx(1.0)
    assert table.loc["slip", "delta_omega"] == pytest.approx(12 / 13)
    assert table.loc["all", "delta"] == pytest.approx(bl.delta(P0, PF, PRED))
    assert list(table["n"]) == [2, 1, 1]
    assert list(bl.error_table(P0, PF, PRED).index) == ["all"]


def test_score_breakdowns():
    ds = bl.load_campaign("A")
    law = bl.Rigid.published("A")
    by_class = bl.score(law, ds)
    assert set(by_class.index) == {"all", "roll", "slip"}
    assert by_class.loc["roll", "n"] + by_class.loc["slip", "n"] == 330
    by_regime = bl.score(law, ds, by="regime")
    assert set(by_regime.index) - {"all"} <= set(law.regimes)
    overall = bl.score(law, ds, by=None)
    assert overall.loc["all", "delta"] == pytest.approx(
        bl.delta(ds.landing.values, ds.liftoff.values, law.predict(ds.landing.values)))
    with pytest.raises(bl.DataError) as e:  # the library's own error type
        bl.score(law, ds, by="setting")
    assert e.value.option == "by"
    with pytest.raises(bl.ParameterError) as e:  # not a bounce law
        bl.score("Rigid", ds)
    assert e.value.parameter == "model"


def test_underflowing_landing_is_a_data_error():
    """bouncelab 0.1: one landing whose norm underflows made delta NaN and fit return the box centre."""
    p0 = np.array([[1000.0, -800.0, 100.0], [900.0, -700.0, 0.0], [1e-200, -1e-200, 0.0]])
    pf = p0 * 0.5
    with pytest.raises(bl.DataError) as err:  # its norm is below the limit
        bl.delta(p0, pf, pf)
    assert err.value.row == 3
    with pytest.raises(bl.DataError) as err:
        bl.fit(bl.Rigid, (np.vstack([p0] * 3), np.vstack([pf] * 3)))
    assert err.value.row == 3
    tiny = np.array([[3e-170, -4e-170, 0.0]])  # no underflow in the norm: computed exactly, then refused
    with pytest.raises(bl.DataError) as err:
        bl.delta(tiny, tiny, tiny)
    assert err.value.row == 1 and "5e-170" in err.value.message  # the norm, computed exactly


@pytest.mark.parametrize(
    ("args", "fields"),
    [
        ((P0, PF, PRED[:1]), {"option": "predicted", "column": None}),  # not as many rows
        ((P0, PF[:, :2], PRED), {"option": "liftoff", "column": None}),  # not (n, 3)
        ((P0 * np.array([1, -1, 1]), PF, PRED), {"option": None, "column": "landing.ydot"}),  # moving up
        ((P0, np.where(PF == 10.0, np.nan, PF), PRED), {"option": None, "column": "liftoff.xdot"}),
    ],
)
def test_bad_input(args, fields):
    for f in (bl.delta, bl.delta_q):
        with pytest.raises(DataError) as e:
            f(*args)
        assert {k: getattr(e.value, k) for k in fields} == fields


def test_bad_classes():
    with pytest.raises(DataError) as e:  # not one label per bounce
        bl.error_table(P0, PF, PRED, ["roll"])
    assert e.value.option == "classes"
