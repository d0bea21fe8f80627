"""Loading what labs write (issue 11, item 1): polar columns, title lines, missing="drop", DataFrames,
and loader messages in the caller's language (Python keywords or the command's flags)."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.cli.main import EXIT_DATA, EXIT_OK, main
from bouncelab.data.io import load_campaign, save_campaign
from bouncelab.data.units import state_from_polar
from bouncelab.errors import DataError, DroppedRowsWarning

R = 0.02135
RPM = 2 * math.pi / 60

# Six bounces as a launch monitor gives them: speed (m/s), angle (deg), spin (rpm).
SPEED_IN = np.array([25.0, 24.6, 25.3, 18.0, 17.7, 18.4])
ANGLE_IN = np.array([40.0, 39.5, 40.8, 55.0, 54.2, 56.1])
SPIN_IN = np.array([3000.0, 3050.0, 2980.0, -1200.0, -1150.0, -1250.0])
SPEED_OUT = np.array([12.0, 11.8, 12.3, 9.8, 9.6, 10.1])
ANGLE_OUT = np.array([20.0, 21.5, 19.4, 105.0, 38.0, 0.0])
SPIN_OUT = np.array([1500.0, 1480.0, 1520.0, 600.0, 620.0, 590.0])
POLAR = {"speed_in (m/s)": SPEED_IN, "angle_in (deg)": ANGLE_IN, "spin_in (rpm)": SPIN_IN,
         "speed_out (m/s)": SPEED_OUT, "angle_out (deg)": ANGLE_OUT, "spin_out (rpm)": SPIN_OUT}
EXP_LANDING = state_from_polar(np.column_stack([SPEED_IN, ANGLE_IN, SPIN_IN]), kind="landing")
EXP_LIFTOFF = state_from_polar(np.column_stack([SPEED_OUT, ANGLE_OUT, SPIN_OUT]), kind="liftoff")

# The same bounces in Cartesian form (m/s, rpm).
CART = {"vx0 (m/s)": EXP_LANDING[:, 0] * R, "vy0 (m/s)": EXP_LANDING[:, 1] * R, "w0 (rpm)": SPIN_IN,
        "vxF (m/s)": EXP_LIFTOFF[:, 0] * R, "vyF (m/s)": EXP_LIFTOFF[:, 1] * R, "wF (rpm)": SPIN_OUT}


def write(path: Path, table: dict, *, pre: str = "", cells: dict | None = None, sep: str = ",") -> Path:
    """A text table of ``table`` (name -> values); ``cells={(name, row): text}`` overrides 1-based data rows."""
    cols = {k: [repr(float(x)) for x in v] for k, v in table.items()}
    for (name, row), text in (cells or {}).items():
        cols[name][row - 1] = text
    lines = [sep.join(cols)] + [sep.join(c[i] for c in cols.values()) for i in range(len(SPEED_IN))]
    path.write_text(pre + "\n".join(lines) + "\n", encoding="utf-8")
    return path


def check(ds) -> None:
    np.testing.assert_allclose(ds["landing"].values, EXP_LANDING, rtol=1e-12)
    np.testing.assert_allclose(ds["liftoff"].values, EXP_LIFTOFF, rtol=1e-12, atol=1e-9)


# ---------------------------------------------------------------------------
# Polar columns
# ---------------------------------------------------------------------------


def test_polar_file_equals_cartesian_file(tmp_path):
    polar = load_campaign(write(tmp_path / "polar.csv", POLAR))
    check(polar)
    cart = load_campaign(write(tmp_path / "cart.csv", CART))
    np.testing.assert_allclose(polar["landing"].values, cart["landing"].values, rtol=1e-12)
    np.testing.assert_allclose(polar["liftoff"].values, cart["liftoff"].values, rtol=1e-12, atol=1e-9)
    assert polar.attrs["source_units"] == "velocity m/s, spin rpm, angle deg"
    assert polar.attrs["source_form"] == "landing polar, liftoff polar"
    assert "source_form" not in cart.attrs


@pytest.mark.parametrize("names", [
    ["inbound speed [m/s]", "landing angle [deg]", "inbound spin [rpm]", "outbound speed [m/s]",
     "launch angle [deg]", "outbound spin [rpm]"],
    ["Speed In (m/s)", "Angle In (deg)", "Spin In (rpm)", "Speed Out (m/s)", "Angle Out (deg)", "Spin Out (rpm)"],
    ["vel_in m/s", "angle0 deg", "w0 rpm", "velocity_out m/s", "theta_out deg", "spin_out rpm"],
])
def test_polar_headers_are_recognised(tmp_path, names):
    check(load_campaign(write(tmp_path / "p.csv", dict(zip(names, POLAR.values(), strict=True)))))


def test_polar_columns_given_explicitly_and_mixed_forms(tmp_path):
    names = ["v_a", "a_a", "w_a", "v_b", "a_b", "w_b"]
    path = write(tmp_path / "odd.csv", dict(zip(names, POLAR.values(), strict=True)))
    ds = load_campaign(path, units={"velocity": "m/s", "spin": "rpm"}, columns={
        "landing": {"speed": "v_a", "angle": "a_a", "spin": "w_a"},
        "liftoff": {"speed": "v_b", "angle": "a_b", "spin": "w_b"}})
    check(ds)
    # A Cartesian landing and a polar lift-off, found from the headers and named explicitly.
    mixed = {**{k: CART[k] for k in ("vx0 (m/s)", "vy0 (m/s)", "w0 (rpm)")},
             **{k: POLAR[k] for k in ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)")}}
    path = write(tmp_path / "mixed.csv", mixed)
    check(load_campaign(path))
    assert load_campaign(path).attrs["source_form"] == "landing cartesian, liftoff polar"
    check(load_campaign(path, columns={"landing": ["vx0", "vy0", "w0"],
                                       "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"}}))


def test_angles_in_radians(tmp_path):
    table = {**POLAR, "angle_in (rad)": np.deg2rad(ANGLE_IN), "angle_out (rad)": np.deg2rad(ANGLE_OUT)}
    del table["angle_in (deg)"], table["angle_out (deg)"]
    check(load_campaign(write(tmp_path / "rad.csv", table)))
    bare = {("angle_in" if k == "angle_in (rad)" else "angle_out" if k == "angle_out (rad)" else k): v
            for k, v in table.items()}
    path = write(tmp_path / "bare.csv", bare)
    with pytest.raises(DataError, match="look like radians") as exc:
        load_campaign(path)
    assert exc.value.column == "angle_in" and "units={'angle': 'rad'}" in str(exc.value)
    check(load_campaign(path, units={"angle": "rad"}))


def test_angle_unit_on_the_command_line(tmp_path, capsys):
    from bouncelab.cli.main import EXIT_DATA, EXIT_OK, main

    table = {("angle_in" if "angle_in" in k else "angle_out" if "angle_out" in k else k): v
             for k, v in POLAR.items()}
    table["angle_in"], table["angle_out"] = np.deg2rad(ANGLE_IN), np.deg2rad(ANGLE_OUT)
    path = str(write(tmp_path / "bare.csv", table))
    assert main(["info", path]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "look like radians" in err and "--angle-unit rad" in err and "units=" not in err
    assert main(["info", path, "--angle-unit", "rad"]) == EXIT_OK
    assert "6 bounces" in capsys.readouterr().out
    out = tmp_path / "fit.json"
    assert main(["fit", "Rigid", path, "--angle-unit", "rad", "--save", str(out)]) == EXIT_OK
    from bouncelab.laws.base import load_law

    assert load_law(out) == bl.fit(bl.Rigid, load_campaign(path, units={"angle": "rad"})).model


def test_flat_angles_declared_in_degrees_are_kept(tmp_path):
    table = dict(POLAR)
    table["angle_out (deg)"] = np.full(6, 2.0)  # skimming lift-offs, said to be degrees
    ds = load_campaign(write(tmp_path / "flat.csv", table))
    np.testing.assert_allclose(np.rad2deg(np.arctan2(ds["liftoff"].values[:, 1], ds["liftoff"].values[:, 0])), 2.0)


@pytest.mark.parametrize(("cell", "value", "needle"), [
    (("angle_in (deg)", 3), "-40.8", "landing angle -40.8 deg is not plausible: a landing angle is positive below"),
    (("angle_in (deg)", 2), "95", "landing angle 95 deg"),
    (("angle_out (deg)", 4), "-5", "lift-off angle -5 deg is not plausible: a lift-off angle is positive above"),
    (("angle_out (deg)", 4), "180", "lift-off angle 180 deg"),
    (("speed_out (m/s)", 5), "-9.6", "lift-off speed -9.6 m/s: a speed must be zero or positive"),
    (("speed_in (m/s)", 1), "0", "landing speed 0 m/s: a speed must be positive"),
])
def test_polar_values_that_are_no_bounce_are_refused(tmp_path, cell, value, needle):
    path = write(tmp_path / "bad.csv", POLAR, cells={cell: value})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert needle in str(exc.value)
    assert exc.value.column == cell[0] and exc.value.row == cell[1] and f"line {cell[1] + 1}" in str(exc.value)


def test_ambiguous_polar_and_cartesian_columns_say_how_to_choose(tmp_path):
    table = {"vx_in (m/s)": CART["vx0 (m/s)"], **POLAR}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "amb.csv", table))
    msg = str(exc.value)
    assert "landing: both Cartesian columns ['vx_in (m/s)'] and polar ones" in msg
    assert "'liftoff': {'speed': 'speed_out (m/s)', 'angle': 'angle_out (deg)', 'spin': 'spin_out (rpm)'}" in msg
    assert "landing_from_speed_angle_spin" not in msg


def test_polar_file_without_phases_shows_the_polar_columns_argument(tmp_path):
    table = {"speed (m/s)": SPEED_IN, "angle (deg)": ANGLE_IN, "spin (rpm)": SPIN_IN,
             **{k: POLAR[k] for k in ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)")}}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "nophase.csv", table))
    msg = str(exc.value)
    assert "'landing': {'speed': '<landing speed column>', 'angle': '<landing angle column>'" in msg
    assert "landing_from_speed_angle_spin" not in msg


def test_cartesian_file_with_derived_speeds_reads_the_components(tmp_path):
    table = {**CART, "speed_in (m/s)": SPEED_IN, "landing angle (deg)": ANGLE_IN}
    ds = load_campaign(write(tmp_path / "both.csv", table))
    check(ds)
    assert "source_form" not in ds.attrs


def test_polar_columns_mapping_is_validated(tmp_path):
    path = write(tmp_path / "polar.csv", POLAR)
    with pytest.raises(DataError, match=r"'speed': \.\.\., 'angle': \.\.\., 'spin'"):
        load_campaign(path, columns={"landing": {"speed": "speed_in", "angle": "angle_in"},
                                     "liftoff": ["speed_out", "angle_out", "spin_out"]})


# ---------------------------------------------------------------------------
# Title lines and header_row
# ---------------------------------------------------------------------------


def test_title_lines_above_the_header(tmp_path):
    pre = "Bounce test 2026-03-14, turf B\nLab: Loughborough sports ground\n\n"
    ds = load_campaign(write(tmp_path / "titled.csv", POLAR, pre=pre))
    check(ds)
    with pytest.raises(DataError) as exc:  # rows are still counted from the header, lines from the top
        load_campaign(write(tmp_path / "titled.csv", POLAR, pre=pre, cells={("spin_in (rpm)", 2): "x"}))
    assert exc.value.row == 2 and "line 6" in str(exc.value)
    ws = write(tmp_path / "titled.txt", {k.split(" ")[0]: v for k, v in POLAR.items()}, sep="  ",
               pre="Bounce test turf B\n")
    check(load_campaign(ws, units={"velocity": "m/s", "spin": "rpm"}))


def test_a_data_row_is_never_taken_for_a_header(tmp_path):
    # A first line of numbers with fewer cells than the header is not a title: the load fails, naming it.
    path = write(tmp_path / "short.csv", POLAR, pre="1,2,3\n")
    with pytest.raises(DataError):
        load_campaign(path)
    # A header without units above data: still the header (not a title), as before.
    plain = {k.split(" ")[0]: v for k, v in POLAR.items()}
    check(load_campaign(write(tmp_path / "plain.csv", plain), units={"velocity": "m/s", "spin": "rpm"}))


def test_header_row(tmp_path):
    pre = "Lab notes\n12.5,3,4\n\n"  # a second line with numbers: no automatic detection
    path = write(tmp_path / "notes.csv", POLAR, pre=pre)
    with pytest.raises(DataError):
        load_campaign(path)
    check(load_campaign(path, header_row=4))
    for bad, needle in ((3, "line 3 is blank"), (99, "the file has 10 lines")):
        with pytest.raises(DataError, match=needle) as exc:
            load_campaign(path, header_row=bad)
        assert f"header_row={bad}" in str(exc.value)
    for bad in (0, -1, 2.0, True, "4"):
        with pytest.raises(DataError, match="header_row= is the 1-based line"):
            load_campaign(path, header_row=bad)
    with pytest.raises(DataError, match="header_row= does not apply to a DataFrame"):
        load_campaign(pd.DataFrame(POLAR), header_row=1)
    with pytest.raises(DataError, match="header_row= does not apply to an embedded campaign"):
        load_campaign("A", header_row=1)


def test_excel_title_rows_header_row_and_sheet(tmp_path):
    pytest.importorskip("openpyxl")
    path = tmp_path / "book.xlsx"
    frame = pd.DataFrame(POLAR)
    with pd.ExcelWriter(path) as writer:
        pd.DataFrame({"x": [1]}).to_excel(writer, sheet_name="Summary", index=False)
        frame.to_excel(writer, sheet_name="Bounces", index=False, startrow=2)
        writer.sheets["Bounces"]["A1"] = "Bounce test 2026-03-14, turf B"
    check(load_campaign(path, sheet="Bounces"))
    check(load_campaign(path, sheet="Bounces", header_row=3))
    with pytest.raises(DataError, match="row 2 of sheet 'Bounces' is empty"):
        load_campaign(path, sheet="Bounces", header_row=2)
    code = main(["info", str(path), "--sheet", "Bounces"])
    assert code == EXIT_OK
    assert main(["info", str(path), "--sheet", "1", "--header-row", "3"]) == EXIT_OK  # no sheet "1": index 1


# ---------------------------------------------------------------------------
# missing="drop"
# ---------------------------------------------------------------------------


def test_missing_drop_drops_exactly_the_incomplete_rows(tmp_path):
    cells = {("spin_in (rpm)", 2): "", ("angle_out (deg)", 4): "NA", ("speed_out (m/s)", 5): "NaN"}
    path = write(tmp_path / "gaps.csv", POLAR, cells=cells, pre="# exported\n")
    with pytest.raises(DataError) as exc:  # default: refused, naming the first cell, and the way out
        load_campaign(path)
    assert exc.value.column == "spin_in (rpm)" and exc.value.row == 2
    assert "missing='drop' drops incomplete rows" in str(exc.value)
    with pytest.warns(DroppedRowsWarning) as rec:
        ds = load_campaign(path, missing="drop")
    msg = str(rec[0].message)
    assert "dropped 3 incomplete row(s) of 6" in msg
    assert "row 2 (line 4: 'spin_in (rpm)' is empty)" in msg
    assert "row 4 (line 6: 'angle_out (deg)' is 'NA')" in msg and "row 5 (line 7: 'speed_out (m/s)' is 'NaN')" in msg
    assert ds.attrs["dropped_rows"] == [2, 4, 5]
    keep = [0, 2, 5]
    np.testing.assert_allclose(ds["landing"].values, EXP_LANDING[keep], rtol=1e-12)
    np.testing.assert_allclose(ds["liftoff"].values, EXP_LIFTOFF[keep], rtol=1e-12, atol=1e-9)
    # A bad cell in a kept row is located in the file, not in the table left after dropping.
    cells[("spin_out (rpm)", 6)] = "abc"
    with pytest.raises(DataError) as exc, warnings.catch_warnings():
        warnings.simplefilter("ignore", DroppedRowsWarning)
        load_campaign(write(tmp_path / "gaps.csv", POLAR, cells=cells), missing="drop")
    assert exc.value.row == 6 and "line 7" in str(exc.value)


def test_missing_drop_with_nothing_missing_and_round_trip(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", DroppedRowsWarning)
        ds = load_campaign(write(tmp_path / "full.csv", POLAR), missing="drop")
    assert ds.attrs["dropped_rows"] == []
    with pytest.warns(DroppedRowsWarning):
        ds = load_campaign(write(tmp_path / "gap.csv", POLAR, cells={("spin_in (rpm)", 3): "n/a"}), missing="drop")
    save_campaign(ds, tmp_path / "gap.nc")
    assert np.atleast_1d(load_campaign(tmp_path / "gap.nc").attrs["dropped_rows"]).tolist() == [3]


def test_missing_argument_is_validated(tmp_path):
    path = write(tmp_path / "p.csv", POLAR)
    with pytest.raises(DataError, match="missing= must be one of 'raise', 'drop'; got 'skip'"):
        load_campaign(path, missing="skip")
    everything = {(k, i): "" for k in ("spin_in (rpm)",) for i in range(1, 7)}
    with pytest.raises(DataError, match="every row has a missing value"):
        load_campaign(write(tmp_path / "empty.csv", POLAR, cells=everything), missing="drop")


# ---------------------------------------------------------------------------
# DataFrames in load_campaign and fit
# ---------------------------------------------------------------------------


def test_dataframe_loads_as_the_same_csv(tmp_path):
    csv = load_campaign(write(tmp_path / "cart.csv", CART))
    df = pd.DataFrame(CART, index=[f"b{i}" for i in range(6)])
    ds = load_campaign(df)
    np.testing.assert_array_equal(ds["landing"].values, csv["landing"].values)
    np.testing.assert_array_equal(ds["liftoff"].values, csv["liftoff"].values)
    assert ds.attrs["campaign"] == "DataFrame" and ds.attrs["source_units"] == csv.attrs["source_units"]
    check(load_campaign(pd.DataFrame(POLAR)))
    # columns=, units= and a setting column of integers, as for a file.
    plain = pd.DataFrame({k.split(" ")[0]: v for k, v in CART.items()}).assign(cond=[1, 1, 1, 2, 2, 2])
    got = load_campaign(plain, units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"], "setting": "cond"})
    np.testing.assert_allclose(got["landing"].values, csv["landing"].values, rtol=1e-15)
    assert got["setting"].values.tolist() == [1, 1, 1, 2, 2, 2]


def test_dataframe_errors_name_column_and_row_label(tmp_path):
    df = pd.DataFrame(CART, index=[f"b{i}" for i in range(6)])
    df.loc["b3", "w0 (rpm)"] = np.nan
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert exc.value.column == "w0 (rpm)" and exc.value.row == 4 and "row label 'b3'" in str(exc.value)
    assert "missing='drop'" in str(exc.value)
    with pytest.warns(DroppedRowsWarning, match="row 4 \\(row label 'b3': 'w0 \\(rpm\\)' is NaN\\)"):
        assert load_campaign(df, missing="drop").sizes["bounce"] == 5
    df = pd.DataFrame(CART, index=[f"b{i}" for i in range(6)])
    df.loc["b1", "vy0 (m/s)"] = 3.404
    with pytest.raises(DataError, match=r"the file gives 3\.404 m/s") as exc:
        load_campaign(df)
    assert "row label 'b1'" in str(exc.value)
    with pytest.raises(DataError, match="sheet= does not apply to a DataFrame"):
        load_campaign(df, sheet=0)


def test_fit_accepts_a_dataframe(tmp_path):
    csv = load_campaign(write(tmp_path / "cart.csv", CART))
    df = pd.DataFrame(CART)
    a = bl.fit(bl.Rigid, df, seed=1)
    b = bl.fit(bl.Rigid, csv, seed=1)
    assert a.model == b.model
    with pytest.raises(DataError, match="no velocity unit"):
        bl.fit(bl.Rigid, pd.DataFrame({k.split(" ")[0]: v for k, v in CART.items()}))


# ---------------------------------------------------------------------------
# Messages: cells as written, and in the caller's language
# ---------------------------------------------------------------------------


def test_errors_quote_the_cell_as_written_with_its_unit(tmp_path):
    path = write(tmp_path / "up.csv", CART, cells={("vy0 (m/s)", 2): "3.404"})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    msg = str(exc.value)
    assert "3.404 m/s" in msg and "159.4" not in msg and exc.value.row == 2
    path = write(tmp_path / "fast.csv", CART, cells={("w0 (rpm)", 3): "30000"})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert str(exc.value).split(": ", 1)[1].startswith("30000 rpm (unit from header)")


def test_cli_messages_name_flags_and_python_messages_keywords(tmp_path, capsys):
    plain = {k.split(" ")[0]: v for k, v in CART.items()}
    path = write(tmp_path / "bare.csv", plain)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s"})
    assert "units={'spin': 'rpm'}" in str(exc.value) and "--spin-unit" not in str(exc.value)
    assert main(["info", str(path), "--velocity-unit", "m/s"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "--spin-unit rpm" in err and "units=" not in err
    # A missing value points to --missing drop; undetectable columns to --columns JSON.
    gap = write(tmp_path / "gap.csv", POLAR, cells={("spin_in (rpm)", 2): "NA"})
    assert main(["info", str(gap)]) == EXIT_DATA
    assert "--missing drop drops incomplete rows" in capsys.readouterr().err
    odd = write(tmp_path / "odd.csv", {f"c{i}": v for i, v in enumerate(POLAR.values())})
    assert main(["info", str(odd)]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "--columns '{\"landing\": [" in err and "load_campaign(" not in err
    assert main(["info", str(gap), "--sheet", "x"]) == EXIT_DATA
    assert "--sheet only applies to Excel files" in capsys.readouterr().err


def test_cli_missing_header_row_and_polar_columns(tmp_path, capsys):
    names = ["v_a", "a_a", "w_a", "v_b", "a_b", "w_b"]
    path = write(tmp_path / "odd.csv", dict(zip(names, POLAR.values(), strict=True)),
                 pre="Lab notes\n1,2\n", cells={("w_a", 3): ""})
    columns = json.dumps({"landing": {"speed": "v_a", "angle": "a_a", "spin": "w_a"},
                          "liftoff": {"speed": "v_b", "angle": "a_b", "spin": "w_b"}})
    argv = ["info", str(path), "--columns", columns, "--velocity-unit", "m/s", "--spin-unit", "rpm",
            "--header-row", "3", "--missing", "drop"]
    assert main(argv) == EXIT_OK
    out, err = capsys.readouterr()
    assert "campaign odd: 5 bounces" in out
    assert "warning: " in err and "row 3 (line 6: 'w_a' is empty)" in err
    assert main(argv[:-2]) == EXIT_DATA  # without --missing drop: refused
    assert main([*argv[:-4], "--missing", "drop"]) == EXIT_DATA  # without --header-row: "Lab notes" is no title
    capsys.readouterr()
    assert main(["fit", "Rigid", str(path), *argv[2:]]) == EXIT_OK
    assert "[[Fit]] Rigid" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["info", str(path), "--header-row", "0"])


def test_title_line_above_a_header_with_a_units_row(tmp_path):
    plain = {k.split(" ")[0]: v for k, v in POLAR.items()}
    path = write(tmp_path / "units_row.csv", plain, pre="Bounce test, turf B\n")
    text = path.read_text().splitlines()
    text.insert(2, "m/s,deg,rpm,m/s,deg,rpm")
    path.write_text("\n".join(text) + "\n")
    check(load_campaign(path))


def test_hint_style_is_validated_and_warnings_point_at_the_caller(tmp_path):
    path = write(tmp_path / "p.csv", POLAR, cells={("spin_in (rpm)", 2): "NA"})
    with pytest.raises(DataError, match="hint_style must be one of 'python', 'cli'; got 'shell'"):
        load_campaign(path, hint_style="shell")
    for source in (path, pd.DataFrame(POLAR).assign(**{"spin_in (rpm)": [1.0, np.nan, 3000, 3000, 3000, 3000]})):
        with pytest.warns(DroppedRowsWarning) as rec:
            load_campaign(source, missing="drop")
        assert rec[0].filename == __file__


def test_reproduce_with_embedded_campaign_and_file_options(tmp_path, capsys, monkeypatch):
    import bouncelab.cli.reproduce as rep

    loaded = {}

    def fake_reproduce(*, campaigns, data, out, load, **_):  # only the loading, not the analysis
        for src in [*campaigns, *data]:
            loaded[src] = load(src)
        return type("Report", (), {"index": Path(out) / "index.html"})()

    monkeypatch.setattr(rep, "reproduce", fake_reproduce)
    path = write(tmp_path / "lab.csv", POLAR, pre="Lab notes\n1,2\n")
    code = main(["reproduce", "--campaign", "A", "--data", str(path), "--header-row", "3", "--no-figures",
                 "--quiet", "--out", str(tmp_path / "report")])
    assert code == EXIT_OK, capsys.readouterr().err
    assert loaded["A"].sizes["bounce"] == 330  # --header-row applies to the file only
    check(loaded[str(path)])
