"""Errors as data (issue 23, item 5) for the laws: the facts of a law's errors are fields, the advice on the
options of the call is hints, and the edges word them (Python keywords, or the command line's flags)."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.messages import message
from bouncelab.core.errors import Code, DataError, FitError, Hint, NotFittedError, ParameterError
from bouncelab.laws import Parameter, fit_method, law_class


@pytest.fixture(scope="module")
def campaign_a():
    return bl.load_campaign("A")


def test_a_law_file_names_the_file_and_keeps_the_fields_of_the_fault(tmp_path):
    path = tmp_path / "law.json"
    path.write_text(json.dumps({"law": "Rigid", "parameters": {"r": 2.0, "mu": 0.3}}))
    with pytest.raises(ParameterError) as err:
        bl.load_law(path)
    assert (err.value.law, err.value.parameter, err.value.value) == ("Rigid", "r", 2.0)
    assert err.value.message.startswith(f"{path}: ")  # the file is named; ParameterError has no file field
    path.write_text(json.dumps({"law": "Rigid", "parameters": {"r": 0.5, "mu": 0.3}, "format_version": 0}))
    with pytest.raises(ParameterError) as err:
        bl.load_law(path)
    assert (err.value.parameter, err.value.value) == ("format_version", 0)


def test_a_law_error_keeps_its_fields_through_pickling():
    with pytest.raises(ParameterError) as err:
        bl.PennerFixed(r=0.5, mu=0.5, beta_deg=95.0)
    back = pickle.loads(pickle.dumps(err.value))  # errors cross process boundaries (parallel fits)
    assert type(back) is ParameterError and str(back) == str(err.value)
    assert (back.law, back.parameter, back.value) == ("PennerFixed", "beta_deg", 95.0)


def test_the_svm_method_cannot_hold_the_plane_and_hints_the_plane_method(campaign_a):
    plane = bl.PiecewiseAffine.published("A")
    with pytest.raises(FitError) as err:
        bl.fit(bl.PiecewiseAffine, campaign_a, method="svm", fixed={"normal": plane.normal, "offset": plane.offset})
    assert (err.value.law, err.value.option) == ("PiecewiseAffine", "fixed")
    assert err.value.hints == (Hint("method", "plane", "with fixed=['normal', 'offset']"),)
    assert "method=" not in err.value.message  # the advice is in the hints, not the facts
    assert str(err.value).endswith("; pass method='plane' (with fixed=['normal', 'offset'])")
    assert message(err.value).endswith("; give --method plane (with fixed=['normal', 'offset'])")


def test_a_piecewise_fit_that_needs_the_generic_search_says_so_in_flags_too(campaign_a):
    with pytest.raises(FitError) as err:
        bl.fit(bl.PiecewiseAffine, campaign_a, objective="omega")
    assert err.value.option == "objective" and "method=" not in err.value.message
    assert "; give --method global (" in message(err.value) and "; pass method='global' (" in str(err.value)
    with pytest.raises(FitError) as err:  # one of the plane's two numbers held
        bl.fit(bl.PiecewiseAffine, campaign_a, fixed={"offset": 0.0})
    assert err.value.option == "fixed" and err.value.hints == (Hint("fixed", ["normal", "offset"]),)


def test_the_plane_methods_svm_start_passes_its_own_svm_c_error_on(campaign_a):
    """The plane method starts from an SVM; a bad svm_C is the caller's, told by the error's field."""
    with pytest.raises(FitError) as err:
        bl.fit(bl.PiecewiseAffine, campaign_a, method="plane", svm_C=-1.0, maxeval=20)
    assert (err.value.law, err.value.option) == ("PiecewiseAffine", "svm_C")


def test_a_law_without_its_plane_names_what_is_missing():
    with pytest.raises(NotFittedError) as err:
        bl.PiecewiseAffine().plane_unit_form()
    assert (err.value.law, err.value.missing) == ("PiecewiseAffine", ("normal", "offset"))


def test_a_dataarray_with_units_hints_its_values():
    import xarray as xr

    with pytest.raises(DataError) as err:
        bl.Rigid.published("A").predict(xr.DataArray([[20.0, -30.0, 100.0]], dims=("bounce", "component")),
                                        form="polar")
    assert err.value.option == "form"  # the option that asks for a conversion
    assert err.value.hints == (Hint("landing", Code("landing.values"), "its numbers, in the units and form given"),)
    assert str(err.value).endswith("; pass landing=landing.values (its numbers, in the units and form given)")


def test_declaration_mistakes_name_the_value_refused():
    with pytest.raises(ParameterError) as err:
        Parameter(bounds=(0, 1), name="2e")
    assert err.value.value == "2e"
    with pytest.raises(ParameterError) as err:
        fit_method("not a name")
    assert err.value.value == "not a name"
    with pytest.raises(ParameterError) as err:
        law_class("")
    assert err.value.value == ""
    with pytest.raises(ParameterError) as err:  # bounds that are not a (low, high) pair
        Parameter(bounds=("low", 1), name="e").bound_arrays()
    assert (err.value.parameter, err.value.value) == ("e", ("low", 1))
    assert np.isfinite(Parameter(bounds=(0, 1), name="e").bound_arrays()[1]).all()
