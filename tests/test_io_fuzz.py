"""Hypothesis fuzz test of the CSV loader: hostile edits of a valid file either load the same values or
raise DataError, never another exception and never other numbers.

Default budget: 60 examples (about a second); ``BOUNCELAB_FUZZ_EXAMPLES=5000 pytest tests/test_io_fuzz.py``
runs a larger campaign.
"""

from __future__ import annotations

import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bouncelab as bl
from bouncelab.core.errors import DataError

HEAD = "setting,vx0 [m/s],vy0 [m/s],w0 [rpm],vxF [m/s],vyF [m/s],wF [rpm]"
ROWS = ["1,20.1,-15.2,3000,9.5,5.1,1500", "1,12.2,-22.5,-1200,6.1,7.7,600", "2,30.0,-20.0,4500,14.0,6.0,2500"]
# Cells that are not a number a person would read.
JUNK = ["", "#N/A", "n/a", "NaN", "inf", "-inf", "abc", "1.2.3", "--", "?", "1e400", "#VALUE!", "null", "1_0", "0x10"]
EXAMPLES = int(os.environ.get("BOUNCELAB_FUZZ_EXAMPLES", "60"))

edits = st.one_of(
    st.tuples(st.just("cell"), st.integers(0, 2), st.integers(0, 6), st.sampled_from(JUNK)),
    st.tuples(st.just("drop_comma"), st.integers(0, 2), st.integers(0, 5), st.none()),
    st.tuples(st.just("extra_comma"), st.integers(0, 2), st.integers(0, 6), st.none()),
    st.tuples(st.just("hash_row"), st.integers(0, 2), st.sampled_from(["#", "%", "# "]), st.none()),
    st.tuples(st.just("blank_line"), st.integers(0, 3), st.none(), st.none()),
    st.tuples(st.just("comment_first"), st.none(), st.none(), st.none()),
)


def apply(edit) -> list[str]:
    kind, i, j, junk = edit
    rows = [r.split(",") for r in ROWS]
    lines = [HEAD]
    if kind == "cell":
        rows[i][j] = junk
    elif kind == "drop_comma":
        rows[i][j:j + 2] = [rows[i][j] + rows[i][j + 1]]
    elif kind == "extra_comma":
        rows[i].insert(j, "")
    body = [",".join(r) for r in rows]
    if kind == "hash_row":
        body[i] = j + body[i]
    if kind == "blank_line":
        body.insert(i, "")
    if kind == "comment_first":
        lines.insert(0, "# exported by the launcher")
    return lines + body


@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(edit=edits)
def test_edited_csv_loads_the_same_values_or_raises_data_error(tmp_path, edit):
    good = tmp_path / "good.csv"
    good.write_text("\n".join([HEAD, *ROWS]) + "\n")
    expected = bl.load_campaign(good)
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(apply(edit)) + "\n")
    try:
        got = bl.load_campaign(bad)
    except DataError:
        return
    np.testing.assert_array_equal(got.landing.values, expected.landing.values)
    np.testing.assert_array_equal(got.liftoff.values, expected.liftoff.values)
    if edit[0] != "cell" or edit[2] != 0:  # a text setting ("abc") is a label a reader reads too
        assert got.setting.values.tolist() == expected.setting.values.tolist()
