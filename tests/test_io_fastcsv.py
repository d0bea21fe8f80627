"""The bulk reader of plain comma-separated files makes the table the cell-by-cell reader makes:
same numbers (to the bit), same setting labels, same refusals with the same row and line."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import bouncelab as bl
from bouncelab.data.io import fastcsv, text

HEAD = "setting,xdot0 (radii/s),ydot0 (radii/s),omega0 (rad/s),xdotF (radii/s),ydotF (radii/s),omegaF (rad/s)"
ROWS = [
    "1,831.7455984262017,-1197.6512605891739,129.21052091214674,-172.09322224570906,234.17108558579551,-54.38877858",
    "1,900.1,-700.25,300,400,200.5,150",
    "2,1000,-800,200,450.000000000000001,240,160",
    "2,0.9e3,-7.5E2,+310,.4e3,199.,1.55e2",
]


def _load(path, monkeypatch, *, fast: bool, **kw):
    """Load ``path`` through the bulk reader, or with it switched off; (dataset or error text, used bulk?)."""
    used = []

    def spy(*args):
        table = fastcsv.read_plain_csv(*args)
        used.append(table is not None)
        return table

    monkeypatch.setattr(text, "read_plain_csv", spy if fast else (lambda *args: None))
    try:
        return bl.load_campaign(path, **kw), bool(used and used[0])
    except bl.DataError as exc:
        return f"DataError: {exc}", bool(used and used[0])


def _same(path, monkeypatch, **kw):
    got, used = _load(path, monkeypatch, fast=True, **kw)
    want, _ = _load(path, monkeypatch, fast=False, **kw)
    if isinstance(want, str) or isinstance(got, str):
        assert got == want
        return used, got
    xr.testing.assert_identical(got, want)
    for var in ("landing", "liftoff"):  # to the bit, signed zeros included
        np.testing.assert_array_equal(np.signbit(got[var].values), np.signbit(want[var].values))
    assert got.setting.dtype == want.setting.dtype
    return used, got


def _write(tmp_path, body: str, name: str = "f.csv") -> str:
    path = tmp_path / name
    path.write_bytes(body.encode("utf-8"))
    return str(path)


def test_plain_file_is_read_in_bulk(tmp_path, monkeypatch):
    used, ds = _same(_write(tmp_path, HEAD + "\n" + "\n".join(ROWS) + "\n"), monkeypatch)
    assert used and ds.sizes["bounce"] == 4 and ds.setting.dtype == np.int64


@pytest.mark.parametrize(
    ("body", "bulk"),
    [
        pytest.param("\n".join(ROWS), True, id="no final newline"),
        pytest.param("\r\n".join(ROWS) + "\r\n", True, id="crlf"),
        pytest.param(ROWS[0] + "\n\n\n" + ROWS[1] + "\n", True, id="blank lines"),
        pytest.param(ROWS[0] + "\n-0,900,-700,-0,400,200,-0.0\n", False, id="negative zero"),
        pytest.param(ROWS[0] + "\n0,900,-700,0,400,200,0\n", True, id="zeros"),
        pytest.param(ROWS[0] + "\n" + ROWS[1] + ",7\n", False, id="long row"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200\n", True, id="short row"),  # its empty cell reported
        pytest.param(ROWS[0] + "\n2,900,,300,400,200,150\n", True, id="empty cell"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,1.5.0\n", True, id="two dots"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,--5\n", True, id="two minus"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,1e999\n", False, id="overflow"),
        pytest.param(ROWS[0] + "\n2,900,700,300,400,200,150\n", True, id="landing moving up"),
        pytest.param(ROWS[0] + "\n2,90000,-700,300,400,200,150\n", True, id="implausible"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,150\n,,,,,,\n", True, id="row of empty cells"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,150\n#N/A,1,-1,1,1,1,1\n", False, id="hash cell"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,150 \n", False, id="space"),
        pytest.param(ROWS[0] + "\n2,900,-700,300,400,200,1_50\n", False, id="underscore"),
        pytest.param(ROWS[0] + "\r2,900,-700,300,400,200,150\n", False, id="lone cr"),
        pytest.param(ROWS[0] + '\n"2",900,-700,300,400,200,150\n', False, id="quotes"),
    ],
)
def test_bulk_and_cell_by_cell_agree(tmp_path, monkeypatch, body, bulk):
    used, _ = _same(_write(tmp_path, HEAD + "\n" + body), monkeypatch)
    assert used == bulk


@pytest.mark.parametrize(
    ("settings_", "bulk"),
    [(["1", "2"], True), (["007", "+8"], True), (["1.0", "2.0"], True), (["1.5", "2.5"], True),
     (["0.10000000000000001", "0.2"], True), (["1e3", "2"], True),
     (["99999999999999999999", "1"], False), (["-99999999999999999999", "1"], False)],  # beyond 64 bits
)
def test_setting_labels_typed_from_their_text(tmp_path, monkeypatch, settings_, bulk):
    rows = [f"{s},900,-700,300,400,200,150" for s in settings_]
    used, _ = _same(_write(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n"), monkeypatch)
    assert used == bulk


@pytest.mark.parametrize(
    "head",
    [
        "# measured 2024\n% by KJ\n\n" + HEAD,
        HEAD + ",",  # trailing empty name
        "setting,,xdot0 (radii/s),ydot0 (radii/s),omega0 (rad/s),xdotF (radii/s),ydotF (radii/s),omegaF (rad/s)",
        "xdot0,xdot0,ydot0,omega0,xdotF,ydotF,omegaF",  # duplicate name
        "setting;xdot0;ydot0;omega0;xdotF;ydotF;omegaF",  # not comma-separated
    ],
)
def test_headers_agree(tmp_path, monkeypatch, head):
    width = len(head.splitlines()[-1].replace(";", ",").split(","))
    rows = [",".join((["1", "900", "-700", "300", "400", "200", "150", "5"])[:width])] * 3
    _same(_write(tmp_path, head + "\n" + "\n".join(rows) + "\n"), monkeypatch)


def test_units_and_columns_arguments_agree(tmp_path, monkeypatch):
    path = _write(tmp_path, "cond,a,b,c,d,e,f\n1,20,-15,3000,9,5,1500\n2,21,-14,2900,9.5,5.5,1400\n")
    cols = {"landing": ["a", "b", "c"], "liftoff": ["d", "e", "f"], "setting": "cond"}
    used, ds = _same(path, monkeypatch, columns=cols, units={"velocity": "m/s", "spin": "rpm"})
    assert used and not isinstance(ds, str)
    used, err = _same(path, monkeypatch, columns=cols, units={"velocity": "m/s"})
    assert used and "rpm" in err


_NUMBER = st.one_of(
    st.floats(-3000, 3000, allow_nan=False).map(repr),
    st.integers(-3000, 3000).map(str),
    st.sampled_from(["", "-", ".", "e", "1e5", "-0", "0", "1.", ".5", "+7", "1e-3", "00012", "1e999", "--1", "1.2.3"]),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    cells=st.lists(st.lists(_NUMBER, min_size=6, max_size=6), min_size=1, max_size=6),
    setting=st.lists(st.sampled_from(["1", "2", "1.5", "0.10000000000000001", "", "12345678901234567890"]),
                     min_size=6, max_size=6),
    breaks=st.sampled_from(["\n", "\r\n"]),
)
def test_random_plain_files_agree(tmp_path_factory, monkeypatch, cells, setting, breaks):
    rows = [",".join([s, *r]) for s, r in zip(setting, cells, strict=False)]
    path = _write(tmp_path_factory.mktemp("fuzz"), breaks.join([HEAD, *rows]) + breaks)
    _same(path, monkeypatch)


@pytest.mark.parametrize(
    ("head", "bulk"),
    [
        (b"\xef\xbb\xbf" + HEAD.encode(), True),  # byte-order mark
        ("# vitesse mesur\u00e9e\n".encode() + HEAD.encode(), True),  # UTF-8 above the header
        ("# vitesse mesur\u00e9e\n".encode("latin-1") + HEAD.encode(), False),  # Latin-1: read cell by cell
        (b"# note\x00\n" + HEAD.encode(), False),  # NUL byte: refused by the text reader
        (b"# a\x0bb\n" + HEAD.encode(), False),  # a line break only str.splitlines knows
    ],
)
def test_header_region_agrees(tmp_path, monkeypatch, head, bulk):
    path = tmp_path / "f.csv"
    path.write_bytes(head + b"\n" + "\n".join(ROWS).encode() + b"\n")
    used, _ = _same(str(path), monkeypatch)
    assert used == bulk


def test_line_beyond_the_csv_field_limit_agrees(tmp_path, monkeypatch):
    long_zero = "0" * 140_000 + "1"  # "000...01" is 1, but the csv module refuses the oversized cell
    used, got = _same(_write(tmp_path, HEAD + "\n" + ROWS[0] + f"\n2,900,-700,300,400,200,{long_zero}\n"), monkeypatch)
    assert not used and got.startswith("DataError")


@pytest.mark.parametrize(
    "late",
    ["3,900,-700,300,400,200,1.5", "-0,900,-700,-0,400,200,150", "3,900,-700,300,400,200,x1",
     "3.5,900,-700,300,400,200,150", "99999999999999999999,900,-700,300,400,200,150"],
)
def test_late_rows_of_a_long_file_agree(tmp_path, monkeypatch, late):
    """pandas types a long file chunk by chunk: a row far down that changes a column's type changes nothing."""
    rows = ["1,900,-700,300,400,200,150", "2,901,-701,301,401,201,151"] * 40_000 + [late]
    _same(_write(tmp_path, HEAD + "\n" + "\n".join(rows) + "\n"), monkeypatch)


@pytest.mark.parametrize("blank", ["", "\r\n", "\n\n"])
def test_comments_above_and_blank_lines_within_agree(tmp_path, monkeypatch, blank):
    """pandas reads the file from the header down (the lines above skipped), or from memory if data lines are blank."""
    body = "# campaign\n\n% notes\n" + HEAD + "\n" + ROWS[0] + "\n" + blank + ROWS[1] + "\n" + blank
    used, ds = _same(_write(tmp_path, body), monkeypatch)
    assert used and ds.sizes["bounce"] == 2
    bad = body.replace(ROWS[1], "2,900,700,300,400,200,150")  # a landing moving up: its line is named
    used, err = _same(_write(tmp_path, bad, "bad.csv"), monkeypatch)
    assert used and "line" in err
