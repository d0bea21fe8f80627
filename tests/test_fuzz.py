"""Fuzzing ``predict`` (hypothesis): any input gives finite, physical lift-offs or a DataError.

The default budget is small for CI; ``pytest tests/test_fuzz.py --hypothesis-profile=fuzz`` runs 20 times more.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

import bouncelab as bl  # noqa: E402
from bouncelab.core.errors import DataError  # noqa: E402
from bouncelab.core.validation import as_states  # noqa: E402
from tests.conftest import kinetic_energy  # noqa: E402

# Profiles "bouncelab" (the default here, 60 examples per test) and "fuzz" (1200) are registered in conftest.py.

LAWS = [bl.Rigid.published("A"), bl.PennerFixed.published("B"), bl.PennerVarying.published("A"),
        bl.PennerFixed.published("A").replace(fade_xdot=30.0), bl.TangentialRestitution(r=0.6, mu=0.5, e_t=0.8),
        bl.PiecewiseAffine.published("B")]
ENERGY_SAFE = LAWS[:5]  # r <= 1 and e_t <= 1: no energy gain

special = st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 5e-324, 1e-12, -1e-12, 1e8, -1e8, 1.0000001e8, 1e308,
                           -1e308, np.inf, -np.inf, np.nan, 2300.0, -1880.0, 953.0])
values = st.one_of(st.floats(allow_nan=True, allow_infinity=True, width=64), special,
                   st.floats(min_value=-3000, max_value=3000))


def arrays():
    shapes = st.one_of(st.just((1, 3)), st.tuples(st.integers(0, 40), st.just(3)), st.just((3,)),
                       st.tuples(st.integers(1, 3), st.integers(1, 4), st.just(3)),
                       st.tuples(st.integers(1, 5), st.integers(1, 5)))
    return hnp.arrays(np.float64, shapes, elements=values)


def landings():
    """Mostly valid landings (so that the physics is exercised), some invalid."""
    row = st.tuples(st.floats(-3000, 3000), st.floats(-3000, -1e-9), st.floats(-2000, 2000))
    return st.lists(row, min_size=1, max_size=30).map(np.array)


def odd_inputs():
    return st.one_of(
        st.lists(st.lists(values, min_size=0, max_size=4), max_size=4),
        st.builds(lambda a: np.ma.masked_array(a, mask=a > 1000), landings()),
        st.builds(lambda a: a + 1j, landings()),
        st.builds(lambda a: a.astype(bool), landings()),
        st.builds(lambda a: a.astype(str), landings()),
        st.builds(lambda a, cols: pd.DataFrame(a, columns=cols), landings(),
                  st.sampled_from([["xdot", "ydot", "omega"], ["omega", "xdot", "ydot"], ["a", "b", "c"],
                                   ["xdot0", "ydot0", "omega0"], ["ydot", "ydot", "omega"]])),
        st.none(), st.text(max_size=5), st.integers(), st.just([[None, 1, 2]]), st.just(object()),
    )


def check(law, landing) -> None:
    # The unit guard (the default) refuses with a DataError or predicts what the maths predict; the
    # properties below are of the maths (plausible=None), on every valid landing, plausible for golf or not.
    try:
        guarded = law.predict(landing)
    except DataError:
        guarded = None
    try:
        out = law.predict(landing, plausible=None)
    except DataError:
        assert guarded is None  # what the value checks refuse, the guarded call refuses too
        return
    if guarded is not None:
        np.testing.assert_array_equal(np.asarray(guarded), np.asarray(out))
    if isinstance(landing, pd.DataFrame):  # labelled in, labelled out (columns xdot, ydot, omega)
        assert isinstance(out, pd.DataFrame) and list(out.columns) == ["xdot", "ydot", "omega"]
        out = out.to_numpy()
        p = as_states(landing)[0]  # the landings in component order, whatever the columns' order
    else:
        p = np.asarray(landing, dtype=np.float64)
    assert out.shape == p.shape
    assert np.isfinite(out).all(), (landing, out)
    assert np.all(np.abs(out) < 1e15)
    if law in ENERGY_SAFE:
        assert np.all(kinetic_energy(out) <= kinetic_energy(p) * (1 + 1e-12) + 1e-9)
    regimes = np.asarray(law.regime(landing, plausible=None))
    assert regimes.shape == p.shape[:-1] and set(np.ravel(regimes)) <= set(law.regimes)


@pytest.mark.parametrize("law", LAWS, ids=lambda m: type(m).__name__)
@given(landing=st.one_of(arrays(), landings()))
def test_predict_arrays(law, landing):
    check(law, landing)


@pytest.mark.parametrize("law", LAWS[:1] + LAWS[-1:], ids=lambda m: type(m).__name__)
@given(landing=odd_inputs())
def test_predict_odd_inputs(law, landing):
    check(law, landing)


@given(speed=st.floats(0.2, 150.0), angle=st.floats(0.5, 90.0), spin=st.floats(-40_000.0, 40_000.0))
def test_unit_guard_judges_a_landing_alike_in_every_form_and_unit(speed, angle, spin):
    """Issue 22: one guard. Polar or Cartesian, SI, scaled or km/h and rad/s: the same verdict (the same limit)."""
    from tests.test_unit_guard import _forms, _verdicts

    verdicts = _verdicts(speed, angle, spin)
    assert len(set(verdicts.values())) == 1, (speed, angle, spin, verdicts)
    assert len(verdicts) == len(_forms(speed, angle, spin))
