"""Issue 22 item 5: mistakes in writing a law raise LawDefinitionError naming the class, the method and the shape.

Before, a law without ``_regime`` gave a bare ``NotImplementedError``, and a ``_predict`` returning (3, n) made
``bl.fit`` fail with ``FitError: NLopt failed: operands could not be broadcast together with shapes (330,3) (3,330)``.
"""

from __future__ import annotations

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import FitError, LawDefinitionError
from bouncelab.laws import BounceModel, CompiledLaw, FitOutcome, Parameter, fit_method, law_name

LANDINGS = np.array([[1000.0, -800.0, 300.0], [600.0, -900.0, -100.0], [1500.0, -400.0, 50.0],
                     [200.0, -1200.0, 600.0], [900.0, -700.0, 0.0]])


def _base(name: str, **methods) -> type[BounceModel]:
    return type(name, (BounceModel,), {"__module__": "lawdefs", "regimes": ("bounce",),
                                       "e": Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="e"), **methods})


def good_predict(self, p, e):
    return np.column_stack([p[:, 0], -e * p[:, 1], p[:, 2]])


def one_regime(self, p, e):
    return np.zeros(len(p), dtype=np.int8)


NoRegime = _base("NoRegime", _predict=good_predict)
NoPredict = _base("NoPredict", _regime=one_regime)
Transposed = _base("Transposed", _predict=lambda self, p, e: np.array([p[:, 0], -e * p[:, 1], p[:, 2]]),
                   _regime=one_regime)
TransposedOwnMethod = _base(
    "TransposedOwnMethod", _predict=Transposed._predict, _regime=one_regime,
    _fit_closed=fit_method("closed")(lambda self, problem: FitOutcome(model=self.replace(e=0.5), objective_value=0.0,
                                                                      algorithm="none")))
FlatCodes = _base("FlatCodes", _predict=good_predict, _regime=lambda self, p, e: np.zeros((len(p), 1), np.int8))
FloatCodes = _base("FloatCodes", _predict=good_predict, _regime=lambda self, p, e: np.zeros(len(p)))
ComplexOut = _base("ComplexOut", _predict=lambda self, p, e: good_predict(self, p, e) + 0j,
                   _regime=one_regime)
ListOut = _base("ListOut", _predict=lambda self, p, e: good_predict(self, p, e).tolist(),
                _regime=lambda self, p, e: [0] * len(p))


def test_missing_regime_names_the_method_to_write():
    law = NoRegime(e=0.5)
    np.testing.assert_allclose(law.predict(LANDINGS)[:, 1], 0.5 * -LANDINGS[:, 1])  # predict needs no _regime
    with pytest.raises(LawDefinitionError) as err:
        law.regime(LANDINGS)
    assert (err.value.law, err.value.method) == ("lawdefs:NoRegime", "_regime")
    assert "_regime(self, p, e)" in str(err.value) and "['bounce']" in str(err.value)  # how to write it


def test_missing_predict_fails_at_first_use_in_predict_and_fit():
    law = NoPredict(e=0.5)  # the class and the law can be made: an abstract base may lack _predict
    for call in (lambda: law.predict(LANDINGS), lambda: bl.fit(NoPredict, bl.load_campaign("A"), maxeval=20)):
        with pytest.raises(LawDefinitionError) as err:
            call()
        assert (err.value.law, err.value.method) == ("lawdefs:NoPredict", "_predict")
        assert "_predict(self, p, e)" in str(err.value)  # the words say how to write it


def test_predict_returning_3_by_n_names_the_shapes_in_predict():
    with pytest.raises(LawDefinitionError) as err:
        Transposed(e=0.5).predict(LANDINGS)
    msg = str(err.value)
    assert "lawdefs:Transposed._predict returned an array of shape (3, 5)" in msg
    assert "(here n = 5: shape (5, 3))" in msg and "transposed" in msg and "np.column_stack" in msg


def test_fit_of_a_law_returning_3_by_n_is_a_law_definition_error_not_an_nlopt_failure():
    ds = bl.load_campaign("A")
    with pytest.raises(LawDefinitionError) as err:  # _predict returned (3, 330)
        bl.fit(Transposed, ds, maxeval=20)
    assert (err.value.law, err.value.method) == ("lawdefs:Transposed", "_predict")
    # a law's own method that never evaluates the objective: checked where the result is built
    with pytest.raises(LawDefinitionError) as err:
        bl.fit(TransposedOwnMethod, ds, method="closed")
    assert (err.value.law, err.value.method) == ("lawdefs:TransposedOwnMethod", "_predict")


def test_fit_error_is_not_raised_for_a_definition_mistake():
    with pytest.raises(LawDefinitionError) as err:
        bl.fit(Transposed, bl.load_campaign("A"), maxeval=20)
    assert not isinstance(err.value, FitError) and "NLopt" not in str(err.value)


@pytest.mark.parametrize("cls", [FlatCodes, FloatCodes])  # codes of shape (5, 1); float64 codes
def test_regime_codes_of_the_wrong_shape_or_type(cls):
    with pytest.raises(LawDefinitionError) as err:
        cls(e=0.5).regime(LANDINGS)
    assert (err.value.law, err.value.method) == (f"lawdefs:{cls.__name__}", "_regime")


def test_complex_lift_offs_are_refused():
    with pytest.raises(LawDefinitionError) as err:  # lift-offs of dtype complex128
        ComplexOut(e=0.5).predict(LANDINGS)
    assert (err.value.law, err.value.method) == ("lawdefs:ComplexOut", "_predict")


def test_array_likes_of_the_right_shape_are_accepted():
    law = ListOut(e=0.5)
    out = law.predict(LANDINGS)
    assert out.dtype == np.float64 and out.shape == (5, 3)
    codes = law.regime(LANDINGS, codes=True)
    assert codes.dtype == np.int8 and list(law.regime(LANDINGS)) == ["bounce"] * 5


def test_int64_codes_come_back_as_documented_int8():
    law = _base("WideCodes", _predict=good_predict,
                _regime=lambda self, p, e: np.zeros(len(p), dtype=np.int64))(e=0.5)
    assert law.regime(LANDINGS, codes=True).dtype == np.int8


def test_compiled_law_without_kernel_says_to_set_it():
    class NoKernel(CompiledLaw):
        e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="e")
        regimes = ("bounce",)

    for call in (lambda: NoKernel(e=0.5).predict(LANDINGS), lambda: NoKernel(e=0.5).regime(LANDINGS),
                 lambda: bl.fit(NoKernel, bl.load_campaign("A"), maxeval=20)):
        with pytest.raises(LawDefinitionError, match=r"NoKernel sets no kernel: a CompiledLaw needs the class "
                                                     r"attribute kernel = a numba.njit function") as err:  # says how
            call()
        assert (err.value.law, err.value.method) == (law_name(NoKernel), "kernel")


def test_a_correct_numpy_law_is_unaffected():
    law = _base("Fine", _predict=good_predict, _regime=one_regime)(e=0.5)
    res = bl.fit(type(law), bl.load_campaign("A"), maxeval=40)
    assert 0.0 <= res.model.e <= 1.0 and np.isfinite(res.delta)


def test_score_names_a_definition_mistake_too():
    ds = bl.load_campaign("A")
    with pytest.raises(LawDefinitionError) as err:
        bl.score(Transposed(e=0.5), ds)
    assert (err.value.law, err.value.method) == ("lawdefs:Transposed", "_predict")
    with pytest.raises(LawDefinitionError) as err:
        bl.score(FloatCodes(e=0.5), ds, by="regime")
    assert (err.value.law, err.value.method) == ("lawdefs:FloatCodes", "_regime")
