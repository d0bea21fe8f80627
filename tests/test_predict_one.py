"""The single-bounce fast path: law.predict_one gives exactly what predict gives for one landing (issue 25)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import DataError, NotFittedError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES

LANDING = (1000.0, -800.0, 300.0)
LAWS = [bl.Rigid(r=0.5, mu=0.4), bl.PennerFixed.published("A"), bl.PennerVarying.published("B"),
        bl.PennerFixed.published("B").replace(fade_xdot=40.0), bl.PiecewiseAffine.published("A"),
        bl.TangentialRestitution(r=0.5, mu=0.4, e_t=0.3), bl.CompliantImpact(r=0.5, mu=0.6, kappa=1.2),
        bl.TurfContact(c=1.0, e_y=0.3, mu=0.6, log10_kt=6.0, lam=3.0),
        bl.CraterContact(r0=0.6, v_r=2000.0, mu_k=0.15, mu_s=1.0, v_s=150.0, lam=0.25, kappa=0.1, e_t=0.2,
                         beta0=5.0, beta_n=0.0, beta_t=0.0)]


def golf_landings(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    speed, angle = rng.uniform(200.0, 2500.0, n), np.radians(rng.uniform(10.0, 85.0, n))
    sign = np.where(rng.random(n) < 0.2, -1.0, 1.0)
    return np.column_stack([sign * speed * np.cos(angle), -speed * np.sin(angle), rng.uniform(-500.0, 1500.0, n)])


@pytest.mark.parametrize("law", LAWS, ids=lambda law: type(law).__name__)
def test_predict_one_is_predict_of_one_landing(law):
    import warnings

    p = golf_landings(60, seed=sum(map(ord, type(law).__name__)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the published piecewise law warns of its non-physical lift-offs
        batch = law.predict(p)
    for row, expected in zip(p, batch, strict=True):
        got = law.predict_one(*row)
        assert all(type(v) is float for v in got)
        np.testing.assert_array_equal(got, expected)


def test_predict_one_checks_what_predict_checks():
    law = LAWS[0]
    for bad in ((math.nan, -800.0, 300.0), (1000.0, 800.0, 300.0), (1000.0, 0.0, 0.0), ("fast", -800.0, 0.0)):
        with pytest.raises(DataError):
            law.predict_one(*bad)
    with pytest.raises(DataError) as err:  # m/s given as radii/s: the unit guard, as in predict
        law.predict_one(20.0, -15.0, 200.0)
    assert err.value.row == 1 and any(h.option == "units" for h in err.value.hints)
    assert law.predict_one(20.0, -15.0, 200.0, plausible=None) == tuple(law.predict([[20.0, -15.0, 200.0]],
                                                                                      plausible=None)[0])
    with pytest.raises(NotFittedError):
        bl.Rigid(r=0.5).predict_one(1000.0, -800.0, 300.0)


def test_a_numpy_law_has_it_too():
    class OneFastPath(bl.BounceModel):
        e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0))
        regimes = ("bounce",)

        def _predict(self, p, e):
            return p * np.array([1.0, -e, 1.0])

        def _regime(self, p, e):
            return np.zeros(len(p), dtype=np.int8)

    assert OneFastPath(e=0.5).predict_one(1000.0, -800.0, 300.0) == (1000.0, 400.0, 300.0)


@pytest.mark.parametrize("law", [bl.Rigid(r=0.5, mu=0.4), bl.CompliantImpact(r=0.5, mu=0.4, kappa=1.5)],
                         ids=["Rigid", "CompliantImpact"])
def test_a_law_that_ran_predict_one_still_pickles_and_copies(law):
    """The compiled entry point predict_one keeps is a cache, not state: pickling and copies leave it out."""
    import copy
    import pickle

    before = law.predict_one(*LANDING)
    again = pickle.loads(pickle.dumps(law))
    assert again == law and again.predict_one(*LANDING) == before
    twin = copy.copy(law)
    assert "_one_entry" not in twin.__dict__ and twin.predict_one(*LANDING) == before


def test_equal_ranges_in_a_new_object_are_not_confused_with_freed_ones():
    law = bl.Rigid(r=0.5, mu=0.4)
    slow = (1.0, -1.5, 0.0)  # about 0.04 m/s: refused by the default guard
    with pytest.raises(bl.errors.DataError):
        law.predict_one(*slow)
    for _ in range(3):  # a fresh, wider ranges object each time (ids of freed objects may be reused)
        assert law.predict_one(*slow, plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=0.01))[1] > 0
        with pytest.raises(bl.errors.DataError):
            law.predict_one(*slow, plausible=PLAUSIBLE_RANGES.widened(min_landing_speed=0.5))
