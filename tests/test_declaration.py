"""A law is declared once: parameters as class attributes named by the attribute, options, no __init__ (issue 23)."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
from numba import njit

import bouncelab as bl
from bouncelab.core.errors import Code, Hint, LawDefinitionError, ParameterError
from bouncelab.laws import Option, Parameter

P0 = np.array([[1000.0, -800.0, 300.0], [400.0, -600.0, -200.0]])


class Scaled(bl.BounceModel):
    """pF = [g xdot0, -e ydot0, g omega0]."""

    e = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="restitution")
    g = Parameter(bounds=(0.0, 2.0), physical=(0.0, 5.0), unit="1", doc="gain", default=1.0, vary=False)
    note = Option(default="", doc="a label, not fitted")
    regimes = ("bounce",)

    def _predict(self, p, e, g):
        return p * np.array([g, -e, g])

    def _regime(self, p, e, g):
        return np.zeros(len(p), dtype=np.int8)


def test_parameters_take_their_names_from_the_attributes_and_keep_their_order():
    assert [s.name for s in Scaled.parameter_specs] == ["e", "g"]
    assert Scaled.e is Scaled.parameter_specs[0] and Scaled.e.doc == "restitution" and Scaled.g.vary is False
    assert str(inspect.signature(Scaled)) == "(e=None, g=1.0, *, note='')"
    law = Scaled(e=0.5)
    assert (law.e, law.g, law.note) == (0.5, 1.0, "")  # on a law, the attribute is the value
    assert law.parameters == {"e": 0.5, "g": 1.0} and law.options == {"note": ""}
    np.testing.assert_array_equal(law.predict(P0), P0 * [1.0, -0.5, 1.0])
    assert repr(Scaled(e=0.25, g=2.0, note="x")) == "Scaled(e=0.25, g=2, note='x')"


def test_the_constructor_takes_keywords_and_validates_them():
    with pytest.raises(ParameterError) as err:
        Scaled(e=2.0)
    assert (err.value.law, err.value.parameter, err.value.value) == (bl.laws.law_name(Scaled), "e", 2.0)
    with pytest.raises(ParameterError) as err:
        Scaled(e=0.5, nu=1.0)
    assert err.value.parameter == "nu"
    assert Scaled(0.5, 2.0) == Scaled(e=0.5, g=2.0)  # parameters also in declaration order
    with pytest.raises(ParameterError):
        Scaled(0.5, 2.0, "label")  # options by keyword only
    with pytest.raises(ParameterError) as err:
        Scaled(0.5, e=0.4)
    assert err.value.parameter == "e"
    law = Scaled(e=0.5)
    with pytest.raises(AttributeError, match="immutable"):
        law.e = 0.3
    with pytest.raises(AttributeError, match="immutable"):
        law.anything = 1
    assert law.replace(e=0.3).e == 0.3 and law.e == 0.5


def test_held_parameters_and_options_in_a_fit_and_a_law_file(tmp_path):
    ds = bl.load_campaign("A")
    res = bl.fit(Scaled(e=0.5, note="lab 3"), ds, maxeval=60)
    assert res.model.g == 1.0 and "g" in res.fixed and res.model.note == "lab 3"  # vary=False holds g
    res.model.to_json(tmp_path / "law.json")
    again = bl.load_law(tmp_path / "law.json")
    assert again == res.model and again.note == "lab 3"


def test_a_law_in_the_old_form_says_how_to_write_it():
    with pytest.raises(LawDefinitionError) as err:
        class Old(bl.BounceModel):
            parameter_specs = ()
            regimes = ("bounce",)

            def __init__(self, e=None):
                self.e = e
                super().__init__()
    assert err.value.law == "Old" and err.value.method in ("__init__", "parameter_specs")
    assert "bl.Parameter(bounds=" in str(err.value)  # the message shows the new form
    with pytest.raises(LawDefinitionError) as err:
        Parameter("e", (0.0, 1.0), (0.0, 1.0), "1", "restitution")
    assert err.value.method == "Parameter" and "bounds=" in str(err.value)
    with pytest.raises(LawDefinitionError) as err:
        Parameter(physical=(0, 1))  # no search box
    assert err.value.method == "Parameter" and err.value.hints == (Hint("bounds", Code("(low, high)")),)


def test_one_parameter_object_cannot_take_two_names():
    shared = Parameter(bounds=(0.0, 1.0))
    with pytest.raises((LawDefinitionError, RuntimeError)):  # Python wraps errors of __set_name__ before 3.12
        type("Twice", (bl.BounceModel,), {"a": shared, "b": shared, "regimes": ("one",)})


def test_a_subclass_inherits_and_redeclares_parameters():
    class Stiffer(Scaled):
        g = Parameter(bounds=(0.5, 1.5), physical=(0.0, 5.0), doc="gain", default=1.2)

    assert [s.name for s in Stiffer.parameter_specs] == ["e", "g"] and Stiffer().g == 1.2


@njit
def _echo_kernel(xd, yd, w, a, b, extra):
    return a, -yd * b, extra, 0


class Echo(bl.CompiledLaw):
    """A compiled law whose kernel shows what it receives: its parameters by name, then the extra argument."""

    a = Parameter(bounds=(0.0, 10.0))
    b = Parameter(bounds=(0.0, 1.0))
    regimes = ("one",)
    kernel = _echo_kernel
    calls = 0

    def _kernel_args(self, *, a, b):
        type(self).calls += 1
        return a, b, 7.0


def test_a_kernel_receives_the_parameters_by_name_and_the_extra_args_once_per_law():
    law = Echo(a=3.0, b=0.5)
    Echo.calls = 0
    for _ in range(3):
        out = law.predict(P0)
    np.testing.assert_array_equal(out, [[3.0, 400.0, 7.0], [3.0, 300.0, 7.0]])
    assert Echo.calls == 1  # an immutable law's constants are computed once
    res = bl.fit(Echo, bl.load_campaign("A"), maxeval=30)  # the objective receives them by name too
    assert 0 <= res.model.a <= 10 and np.isfinite(res.delta)


def test_predict_varying_is_every_laws_and_agrees_with_one_law_per_row():
    rows = np.array([[0.4, 1.0], [0.8, 1.5]])
    out = Scaled.predict_varying(P0, rows)
    for i in range(2):
        np.testing.assert_array_equal(out[i], Scaled(e=rows[i, 0], g=rows[i, 1]).predict(P0[i:i + 1])[0])
    compiled = bl.Rigid.predict_varying(P0, {"r": [0.3, 0.6], "mu": 0.4})
    np.testing.assert_array_equal(compiled[1], bl.Rigid(r=0.6, mu=0.4).predict(P0[1:2])[0])
