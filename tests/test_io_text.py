"""Text tables read by pandas.read_csv: the numbers as Python reads them (to the bit, signed zeros included),
setting labels typed from their text, and every odd cell of a file, short or long, refused at its row and line.

(These tests once kept two CSV parsers in step; the loader now has one, and they check it against Python's own
reading of each cell.)
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bouncelab as bl
from bouncelab.core.errors import DataError, Hint

HEAD = "setting,xdot0 (radii/s),ydot0 (radii/s),omega0 (rad/s),xdotF (radii/s),ydotF (radii/s),omegaF (rad/s)"
ROWS = [
    "1,831.7455984262017,-1197.6512605891739,129.21052091214674,-172.09322224570906,234.17108558579551,-54.38877858",
    "1,900.1,-700.25,300,400,200.5,150",
    "2,1000,-800,200,450.000000000000001,240,160",
    "2,0.9e3,-7.5E2,+310,.4e3,199.,1.55e2",
]
DROP = Hint("missing", "drop", "drops incomplete rows")


def expected(rows: list[str]) -> np.ndarray:
    """The states of ``rows`` as Python's float() reads each cell."""
    return np.array([[float(c) for c in row.split(",")[1:7]] for row in rows])


def load(tmp_path, body: bytes | str, name: str = "f.csv"):
    path = tmp_path / name
    path.write_bytes(body.encode("utf-8") if isinstance(body, str) else body)
    return bl.load_campaign(path)


def states(ds) -> np.ndarray:
    return np.column_stack([ds.landing.values, ds.liftoff.values])


def test_a_plain_file_is_read_to_the_bit(tmp_path):
    ds = load(tmp_path, HEAD + "\n" + "\n".join(ROWS) + "\n")
    np.testing.assert_array_equal(states(ds), expected(ROWS))
    assert ds.setting.dtype == np.int64 and ds.setting.values.tolist() == [1, 1, 2, 2]


@pytest.mark.parametrize("body", [
    pytest.param("\n".join(ROWS), id="no final newline"),
    pytest.param("\r\n".join(ROWS) + "\r\n", id="crlf"),
    pytest.param("\r".join(ROWS) + "\r", id="cr"),
    pytest.param(ROWS[0] + "\n\n  \n" + "\n".join(ROWS[1:]) + "\n\n", id="blank lines"),
    pytest.param("\n".join(r.replace(",150", ",150 ") for r in ROWS) + "\n", id="a space after a number"),
    pytest.param("\n".join('"' + r.replace(",", '",', 1) for r in ROWS) + "\n", id="quoted settings"),
])
def test_line_ends_blank_lines_and_quotes_read_the_same_numbers(tmp_path, body):
    ds = load(tmp_path, HEAD + ("\r" if "\r" in body and "\n" not in body else "\n") + body)
    np.testing.assert_array_equal(states(ds), expected(ROWS))
    assert ds.setting.values.tolist() == [1, 1, 2, 2]


def test_negative_zeros_keep_their_sign(tmp_path):
    rows = [ROWS[1], "2,900,-700,-0,400,200,-0.0", "2,900,-700,0,400,200,0"]
    ds = load(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n")
    got = states(ds)
    np.testing.assert_array_equal(np.signbit(got), np.signbit(expected(rows)))
    assert np.signbit(got[1, 2]) and np.signbit(got[1, 5]) and not np.signbit(got[2, 2])


@pytest.mark.parametrize(("row", "column", "what", "hints"), [
    ("2,900,-700,300,400,200", "omegaF (rad/s)", "empty cell", (DROP,)),  # a short row: its cell is empty
    ("2,900,,300,400,200,150", "ydot0 (radii/s)", "empty cell", (DROP,)),
    ("2,900,-700,300,400,200,1.5.0", "omegaF (rad/s)", "'1.5.0'", ()),
    ("2,900,-700,300,400,200,--5", "omegaF (rad/s)", "'--5'", ()),
    ("2,900,-700,300,400,200,1_50", "omegaF (rad/s)", "'1_50'", ()),  # Python reads 150; a person may not
    ("2,900,-700,300,400,200,NA", "omegaF (rad/s)", "'NA'", (DROP,)),
    ("2,900,-700,300,400,200,1e999", "omegaF (rad/s)", "infinite", ()),
    ("2,900,700,300,400,200,150", "ydot0 (radii/s)", "700 radius/s", ()),  # a landing moving up
    (",,,,,,", "xdot0 (radii/s)", "empty cell", (DROP,)),  # a row of empty cells: its first state cell
])
def test_an_odd_cell_is_refused_at_its_row_and_line(tmp_path, row, column, what, hints):
    with pytest.raises(DataError) as exc:
        load(tmp_path, HEAD + "\n" + ROWS[0] + "\n" + row + "\n")
    assert (exc.value.column, exc.value.row, exc.value.hints) == (column, 2, hints)
    assert what in exc.value.message and exc.value.message.endswith("(line 3)")


def test_a_long_row_and_an_implausible_value_are_refused(tmp_path):
    with pytest.raises(DataError) as exc:
        load(tmp_path, HEAD + "\n" + ROWS[0] + "\n" + ROWS[1] + ",7\n")
    assert (exc.value.column, exc.value.row) == (None, 2) and exc.value.message.endswith("(line 3)")
    with pytest.raises(DataError) as exc:
        load(tmp_path, HEAD + "\n" + ROWS[0] + "\n2,90000,-700,300,400,200,150\n")  # 1900 m/s
    assert (exc.value.column, exc.value.row) == ("xdot0 (radii/s)", 2)
    assert exc.value.hints[-1].option == "plausible"


@pytest.mark.parametrize(("labels", "want"), [
    (["1", "2"], [1, 2]), (["007", "+8"], [7, 8]), (["1.0", "2.0"], [1, 2]), (["1e3", "2"], [1000, 2]),
    (["1.5", "2.5"], [1.5, 2.5]),
    (["0.10000000000000001", "0.2"], ["0.10000000000000001", "0.2"]),  # more digits than a float keeps: text
    (["99999999999999999999", "1"], ["99999999999999999999", "1"]),  # beyond 64 bits: text, exact
    (["-99999999999999999999", "1"], ["-99999999999999999999", "1"]),
])
def test_setting_labels_are_typed_from_their_text(tmp_path, labels, want):
    rows = [f"{s},900,-700,300,400,200,150" for s in labels]
    ds = load(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n")
    assert ds.setting.values.tolist() == want


@pytest.mark.parametrize(("late", "labels"), [
    ("3,900,-700,300,400,200,1.5", (1, 3)), ("-0,900,-700,-0,400,200,150", (1, 0)),
    ("3,900,-700,300,400,200,x1", None), ("3.5,900,-700,300,400,200,150", ("1", "3.5")),  # labels of two kinds: text
    ("99999999999999999999,900,-700,300,400,200,150", ("1", "99999999999999999999")),
])
def test_late_rows_of_a_long_file_are_read_as_written(tmp_path, late, labels):
    """pandas types a long file chunk by chunk: a row far down that changes a column's type changes nothing."""
    rows = ["1,900,-700,300,400,200,150", "2,901,-701,301,401,201,151"] * 40_000 + [late]
    if labels is None:
        with pytest.raises(DataError) as exc:
            load(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n")
        assert (exc.value.column, exc.value.row) == ("omegaF (rad/s)", 80_001)
        assert exc.value.message.endswith("(line 80002)")
        return
    ds = load(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n")
    got = states(ds)
    np.testing.assert_array_equal(got[-3:], expected(rows[-3:]))
    np.testing.assert_array_equal(np.signbit(got[-1]), np.signbit(expected(rows[-1:])[0]))
    assert (ds.setting.values[0].item(), ds.setting.values[-1].item()) == labels


@pytest.mark.parametrize("head", [
    "# measured 2024\n% by KJ\n\n" + HEAD,
    HEAD + ",",  # a trailing empty name: the rows' trailing separators are no data
    "setting,,xdot0 (radii/s),ydot0 (radii/s),omega0 (rad/s),xdotF (radii/s),ydotF (radii/s),omegaF (rad/s)",
])
def test_headers(tmp_path, head):
    rows = ["1,900,-700,300,400,200,150" + ("," if head.endswith(",") else "")] * 3
    if ",," in head:  # an unnamed column is not read
        rows = ["1,junk,900,-700,300,400,200,150"] * 3
    ds = load(tmp_path, head + "\n" + "\n".join(rows) + "\n")
    np.testing.assert_array_equal(states(ds), [[900, -700, 300, 400, 200, 150]] * 3)


def test_a_duplicate_name_and_a_semicolon_file(tmp_path):
    with pytest.raises(DataError) as exc:
        load(tmp_path, "xdot0,xdot0,ydot0,omega0,xdotF,ydotF,omegaF\n" + "900,900,-700,300,400,200,150\n" * 3)
    assert exc.value.column == "xdot0" and "columns 1 and 2" in exc.value.message
    ds = load(tmp_path, HEAD.replace(",", ";") + "\n" + "1;900,5;-700;300;400;200;150\n" * 3, "s.csv")
    assert ds.landing.values[0, 0] == 900.5  # a decimal comma


@pytest.mark.parametrize(("head", "ok"), [
    (b"\xef\xbb\xbf" + HEAD.encode(), True),  # byte-order mark
    ("# vitesse mesur\u00e9e\n".encode() + HEAD.encode(), True),  # UTF-8 above the header
    ("# vitesse mesur\u00e9e\n".encode("latin-1") + HEAD.encode(), True),  # Latin-1
    (b"# a\x0bb\n" + HEAD.encode(), True),  # a line break only str.splitlines knows: not one here
    (b"# note\x00\n" + HEAD.encode(), False),  # NUL byte: not a text table
])
def test_the_lines_above_the_header(tmp_path, head, ok):
    body = head + b"\n" + "\n".join(ROWS).encode() + b"\n"
    if ok:
        np.testing.assert_array_equal(states(load(tmp_path, body)), expected(ROWS))
    else:
        with pytest.raises(DataError) as exc:
            load(tmp_path, body)
        assert exc.value.file == str(tmp_path / "f.csv") and "NUL" in exc.value.message


def test_a_value_after_its_row_is_refused(tmp_path):
    rows = ["1,900,-700,300,400,200,150,"] * 2 + ["1,900,-700,300,400,200,150,5"]  # under no name
    with pytest.raises(DataError) as exc:
        load(tmp_path, HEAD + ",\n" + "\n".join(rows) + "\n")
    assert exc.value.row == 3 and exc.value.message.startswith("the row has 8 values but the header names 7 columns")


def test_a_line_beyond_the_csv_field_limit_is_refused(tmp_path):
    long_one = "0" * 140_000 + "1"  # the delimiter is told by the csv module, which refuses such a cell
    with pytest.raises(DataError) as exc:
        load(tmp_path, HEAD + "\n" + ROWS[0] + f"\n2,900,-700,300,400,200,{long_one}\n")
    assert exc.value.file == str(tmp_path / "f.csv")


@pytest.mark.parametrize("blank", ["", "\r\n", "\n\n"])
def test_comments_above_and_blank_lines_within(tmp_path, blank):
    body = "# campaign\n\n% notes\n" + HEAD + "\n" + ROWS[0] + "\n" + blank + ROWS[1] + "\n" + blank
    assert load(tmp_path, body).sizes["bounce"] == 2
    bad = body.replace(ROWS[1], "2,900,700,300,400,200,150")  # a landing moving up: its line is named
    with pytest.raises(DataError) as exc:
        load(tmp_path, bad, "bad.csv")
    line = 6 + blank.count("\n")
    assert exc.value.row == 2 and exc.value.message.endswith(f"(line {line})")


_NUMBER = st.one_of(
    st.floats(-3000, 3000, allow_nan=False).map(repr),
    st.integers(-3000, 3000).map(str),
    st.sampled_from(["", "-", ".", "e", "1e5", "-0", "0", "1.", ".5", "+7", "1e-3", "00012", "1e999", "--1", "1.2.3"]),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(cells=st.lists(st.lists(_NUMBER, min_size=6, max_size=6), min_size=1, max_size=6),
       setting=st.lists(st.sampled_from(["1", "2", "1.5", "0.10000000000000001", "", "12345678901234567890"]),
                        min_size=6, max_size=6),
       breaks=st.sampled_from(["\n", "\r\n"]))
def test_random_files_load_the_numbers_written_or_raise_a_data_error(tmp_path_factory, cells, setting, breaks):
    rows = [",".join([s, *r]) for s, r in zip(setting, cells, strict=False)]
    path = tmp_path_factory.mktemp("fuzz") / "f.csv"
    path.write_bytes(breaks.join([HEAD, *rows]).encode() + breaks.encode())
    try:
        ds = bl.load_campaign(path)
    except DataError as exc:
        assert exc.file == str(path)
        return
    want = np.array([[float(c) for c in r] for r in cells[: len(rows)]])
    np.testing.assert_array_equal(states(ds), want)
    np.testing.assert_array_equal(np.signbit(states(ds)), np.signbit(want))
