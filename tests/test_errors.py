"""Errors carry their facts as fields and their hints as data; they survive pickling (issue 23)."""

from __future__ import annotations

import pickle

import pytest

from bouncelab.cli.messages import flag_hint, message
from bouncelab.core import errors as E


@pytest.mark.parametrize("error", [
    E.DataError("spins look like rpm", file="f.csv", column="w0", row=3, row_label="shot-2",
                hints=[E.Hint("units", {"spin": "rpm"})]),
    E.ParameterError("outside its physical range", law="Rigid", parameter="r", value=2.0),
    E.NotFittedError("no value", law="Rigid", missing=["r", "mu"]),
    E.FitError("too few bounces", law="PiecewiseAffine", option="min_side"),
    E.LawDefinitionError("returned shape (3, 5)", law="mylaws:Simple", method="_predict"),
    E.UnknownLawError("unknown", law_name="mylaws:Nope", module="mylaws", qualname="Nope", module_imported=True),
    E.OutputError("cannot write", path="/x/y.json", reason="Permission denied", errno=13),
], ids=lambda e: type(e).__name__)
def test_fields_and_words_survive_pickling(error):
    again = pickle.loads(pickle.dumps(error))
    assert type(again) is type(error) and str(again) == str(error)
    fields = {k: v for k, v in vars(error).items()}
    assert {k: v for k, v in vars(again).items()} == fields


def test_a_hint_is_worded_by_the_edge():
    e = E.DataError("spins look like rpm", file="f.csv", column="w0", hints=[E.Hint("units", {"spin": "rpm"}),
                                                                           E.Hint("missing", "drop")])
    assert str(e) == "file 'f.csv', column 'w0': spins look like rpm; pass units={'spin': 'rpm'} or missing='drop'"
    assert message(e) == "file 'f.csv', column 'w0': spins look like rpm; give --spin-unit rpm or --missing drop"
    assert e.message == "spins look like rpm" and e.hints[0].option == "units"


@pytest.mark.parametrize(("hint", "words"), [
    (E.Hint("units", {"velocity": "m/s", "spin": "rpm"}), "--velocity-unit m/s --spin-unit rpm"),
    (E.Hint("columns", {"landing": ["a", "b", "c"]}), """--columns '{"landing": ["a", "b", "c"]}'"""),
    (E.Hint("header_row", 3), "--header-row 3"),
    (E.Hint("intervals", "sd", "standard deviations"), "--intervals sd (standard deviations)"),
    (E.Hint("plausible", None), "plausible=... (in Python)"),
])
def test_flags_for_hints(hint, words):
    assert flag_hint(hint) == words
