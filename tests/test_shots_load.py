"""Issue 33, item 1: launch-monitor shots in (bouncelab.ground.load_shots).

The files are written here the way the monitors write their exports (TrackMan's header with a units row under it,
FlightScope's and GSPro's units in the headers); the numbers are made up, and every expected SI value is computed
here from the exact unit definitions, not by bouncelab.
"""

from __future__ import annotations

import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bouncelab.ground as ground
from bouncelab.core.errors import DataError, DroppedRowsWarning, Hint
from bouncelab.data.shots import load_shots

MPH, YD, FT, RPM = 1609.344 / 3600, 0.9144, 0.3048, 2 * math.pi / 60

TM_HEAD = ("Date,Player,Club,Club Speed,Ball Speed,Launch Angle,Spin Rate,Spin Axis,Carry Flat - Length,"
           "Carry Flat - Side,Carry Flat - Land. Angle,Carry Flat - Ball Speed,Carry Flat - Time,Total,Side Total")
TM_UNITS = ",,,[mph],[mph],[deg],[rpm],[deg],[yds],[ft],[deg],[mph],[s],[yds],[ft]"
TM_ROWS = [
    "2024-05-01 10:01:02,Sam,Driver,112.4,165.2,12.1,2450,-2.1,262.3,-14.2,38.2,61.5,6.71,284.0,-18.3",
    "2024-05-01 10:02:10,Sam,Driver,111.0,163.0,11.4,2610,3.4,255.8,9.7,39.1,,6.62,,12.1",
    "2024-05-01 10:03:44,Sam,7 Iron,86.2,120.3,17.9,6900,1.2,168.4,3.1,50.2,52.0,6.10,175.2,4.0",
    "2024-05-01 10:04:30,Sam,7 Iron,85.9,119.8,18.3,7020,-0.8,166.9,-2.2,51.0,51.4,6.02,173.0,-3.0",
]


def trackman(path: Path, rows=TM_ROWS, head=TM_HEAD, units=TM_UNITS, pre: str = "") -> Path:
    path.write_text(pre + "\n".join([head, units, *rows]) + "\n", encoding="utf-8")
    return path


def cells(row: str) -> dict[str, str]:
    return dict(zip(TM_HEAD.split(","), row.split(","), strict=True))


def test_a_trackman_export_with_a_units_row_and_blank_cells_loads_with_missing_drop(tmp_path):
    path = trackman(tmp_path / "session.csv")
    with pytest.warns(DroppedRowsWarning, match=r"row 2 \(line 4: 'Carry Flat - Ball Speed' is empty\)"):
        shots = ground.load_shots(path, missing="drop")
    assert shots.sizes["shot"] == 3 and shots["row"].values.tolist() == [1, 3, 4]
    assert shots.attrs["dropped_rows"] == [2] and shots.attrs["format"] == "TrackMan"
    assert shots.attrs["source"] == str(path.resolve()) and shots.attrs["spin_at"] == "launch"
    kept = [cells(TM_ROWS[i]) for i in (0, 2, 3)]

    def column(name: str, factor: float = 1.0) -> np.ndarray:
        return np.array([float(c[name]) * factor for c in kept])

    np.testing.assert_allclose(shots.landing_speed, column("Carry Flat - Ball Speed", MPH), rtol=1e-14)
    np.testing.assert_array_equal(shots.landing_angle, column("Carry Flat - Land. Angle"))
    np.testing.assert_allclose(shots.spin, column("Spin Rate", RPM), rtol=1e-14)
    np.testing.assert_array_equal(shots.spin_axis, column("Spin Axis"))
    np.testing.assert_array_equal(shots.launch_angle, column("Launch Angle"))
    np.testing.assert_allclose(shots.carry, column("Carry Flat - Length", YD), rtol=1e-14)
    np.testing.assert_allclose(shots.total, column("Total", YD), rtol=1e-14)
    np.testing.assert_allclose(shots.side, column("Carry Flat - Side", FT), rtol=1e-14)
    np.testing.assert_allclose(shots.side_total, column("Side Total", FT), rtol=1e-14)
    np.testing.assert_array_equal(shots.flight_time, column("Carry Flat - Time"))
    assert shots.club.values.tolist() == ["Driver", "7 Iron", "7 Iron"]
    units = {v: shots[v].attrs["units"] for v in shots.data_vars if v != "club"}
    assert units == {"landing_speed": "m/s", "landing_angle": "deg", "spin": "rad/s", "spin_axis": "deg",
                     "launch_angle": "deg", "carry": "m", "total": "m", "side": "m", "side_total": "m",
                     "flight_time": "s"}
    assert shots.carry.attrs["source_column"] == "Carry Flat - Length" and shots.carry.attrs["source_units"] == "yd"
    assert shots.spin.attrs["spin_at"] == "launch"
    described = [part.split(": ")[0] for part in shots.attrs["source_units"].split(", ")]
    assert "Ball Speed" not in described and "Club Speed" not in described  # launch and club speeds are not read


def test_a_blank_cell_is_refused_by_default_naming_column_row_and_line(tmp_path):
    path = trackman(tmp_path / "session.csv")
    with pytest.raises(DataError) as exc:
        load_shots(path)
    err = exc.value
    assert (err.file, err.column, err.row) == (str(path), "Carry Flat - Ball Speed", 2)
    assert err.hints == (Hint("missing", "drop", "drops incomplete rows"),)
    assert "empty cell" in err.message and err.message.endswith("(line 4)")


def test_a_bad_cell_is_a_typed_error(tmp_path):
    rows = [*TM_ROWS[:2], TM_ROWS[2].replace(",50.2,", ",fifty,")]
    with pytest.warns(DroppedRowsWarning), pytest.raises(DataError) as exc:
        load_shots(trackman(tmp_path / "s.csv", rows=rows), missing="drop")
    assert (exc.value.column, exc.value.row) == ("Carry Flat - Land. Angle", 3)
    assert "non-numeric value 'fifty'" in exc.value.message and exc.value.message.endswith("(line 5)")


def test_a_title_line_above_the_header_and_an_excel_export(tmp_path):
    csv = trackman(tmp_path / "t.csv", rows=[TM_ROWS[0], TM_ROWS[2]], pre="TrackMan Normalized Report - Sam\n")
    a = load_shots(csv)
    text = ("Date", "Player", "Club")  # a sheet as Excel holds it: numbers as numbers, the units row as text
    grid = [[c if k in text or not c or c.startswith("[") else float(c) for k, c in zip(TM_HEAD.split(","),
             r.split(","), strict=True)] for r in [TM_UNITS, TM_ROWS[0], TM_ROWS[2]]]
    book = tmp_path / "t.xlsx"
    pd.DataFrame(grid, columns=TM_HEAD.split(",")).replace("", None).to_excel(book, index=False)
    b = load_shots(book)
    for var in ("landing_speed", "carry", "total", "spin", "side_total"):
        np.testing.assert_allclose(a[var], b[var], rtol=1e-14)
    assert a.attrs["format"] == b.attrs["format"] == "TrackMan"


def test_flightscope_and_gspro_exports(tmp_path):
    fs = tmp_path / "flightscope.csv"
    fs.write_text("Shot,Club,Ball (mph),Club (mph),Launch V (°),Launch H (°),Spin (rpm),Spin Axis (°),Carry (yds),"
                  "Roll (yds),Total (yds),Lateral (yds),Height (ft),Descent V (°),Flight Time (s)\n"
                  "1,Driver,160.1,110.2,11.8,-1.2,2700,-3.0,250.1,22.0,272.1,-6.5,95.0,37.5,6.4\n"
                  "2,Driver,158.4,109.0,12.4,0.8,2850,2.5,246.0,20.5,266.5,4.1,97.2,38.8,6.5\n")
    shots = load_shots(fs)
    assert shots.attrs["format"] == "FlightScope" and "landing_speed" not in shots
    np.testing.assert_array_equal(shots.landing_angle, [37.5, 38.8])
    np.testing.assert_allclose(shots.side, [-6.5 * YD, 4.1 * YD], rtol=1e-14)
    np.testing.assert_allclose(shots.total, [272.1 * YD, 266.5 * YD], rtol=1e-14)
    gs = tmp_path / "gspro.csv"
    gs.write_text("Shot Key,Club,Ball Speed (mph),VLA (deg),HLA (deg),TotalSpin (rpm),BackSpin (rpm),"
                  "SideSpin (rpm),Spin Axis (deg),Carry (yds),Total (yds),Offline (yds),Peak Height (yds),"
                  "Descent Angle (deg)\n"
                  "a1,DR,150.2,13.0,1.1,2500,2490,-218,-5.0,238.4,262.0,-8.2,30.1,36.9\n")
    shots = load_shots(gs)
    assert shots.attrs["format"] == "GSPro" and shots.club.values.tolist() == ["DR"]
    np.testing.assert_allclose(shots.spin, [2500 * RPM], rtol=1e-14)
    np.testing.assert_array_equal(shots.landing_angle, [36.9])


def test_a_generic_dataframe_with_units_and_a_landing_spin():
    frame = pd.DataFrame({"landing speed": [27.6, 25.1], "landing angle": [37.7, 41.0], "landing spin": [2100, 2300],
                          "carry": [230.0, 221.5], "total": [248.0, 240.0]}, index=["s1", "s2"])
    shots = load_shots(frame, units={"velocity": "m/s", "spin": "rpm", "distance": "m"})
    assert shots.attrs["source"] == "pandas.DataFrame" and shots.attrs["format"] == "generic"
    assert shots.attrs["spin_at"] == "landing" == shots.spin.attrs["spin_at"]
    np.testing.assert_array_equal(shots.landing_speed, [27.6, 25.1])
    np.testing.assert_allclose(shots.spin, [2100 * RPM, 2300 * RPM], rtol=1e-14)
    renamed = frame.rename(columns={"landing angle": "Land V"})
    # not a name it knows: the landing angle is not read...
    assert "landing_angle" not in load_shots(renamed, units={"velocity": "m/s", "spin": "rpm", "distance": "m"})
    named = load_shots(renamed, units={"velocity": "m/s", "spin": "rpm", "distance": "m"},
                       columns={"landing_angle": "Land V"})  # ...unless columns= names it
    np.testing.assert_array_equal(named.landing_angle, [37.7, 41.0])


@pytest.mark.parametrize(("head", "units_row", "row", "column", "said"), [
    # spins in rpm said to be rad/s: 2450 rad/s is 23 396 rpm, which no golf ball reaches
    ("Spin Rate,Carry Flat - Land. Angle", "[rad/s],[deg]", "2450,38.2", "Spin Rate",
     "2450 rad/s is 23396 rpm, beyond 20000 rpm"),
    # a landing speed said to be m/s that only km/h makes (99 m/s)
    ("Carry Flat - Ball Speed,Total", "[m/s],[yds]", "99.0,284", "Carry Flat - Ball Speed", "90 m/s"),
    # carry in feet said to be yards: 860 yd is 786 m
    ("Carry Flat - Length,Total", "[yds],[yds]", "860.5,284", "Carry Flat - Length", "550 m"),
    # a flight time in milliseconds said to be seconds
    ("Carry Flat - Time,Total", "[s],[yds]", "6710,284", "Carry Flat - Time", "20 s"),
    # a launch angle beyond 90 degrees: no shot has it (another column taken for it, or another unit)
    ("Launch Angle,Total", "[deg],[yds]", "210,284", "Launch Angle", "beyond 90 deg"),
])
def test_the_unit_guard_refuses_numbers_only_another_unit_makes(tmp_path, head, units_row, row, column, said):
    path = tmp_path / "g.csv"
    path.write_text(f"{head}\n{units_row}\n{row}\n")
    with pytest.raises(DataError) as exc:
        load_shots(path)
    assert (exc.value.column, exc.value.row) == (column, 1) and said in exc.value.message
    assert exc.value.message.endswith("(line 3)")


def test_units_that_are_not_given_are_not_guessed(tmp_path):
    path = tmp_path / "plain.csv"
    path.write_text("landing speed,landing angle,spin,carry,total\n27.6,37.7,2440,230,248\n")
    with pytest.raises(DataError) as exc:
        load_shots(path)
    assert exc.value.column == "landing speed" and "does not guess" in exc.value.message
    assert Hint("units", {"velocity": "mph"}) in exc.value.hints
    with pytest.raises(DataError) as exc:
        load_shots(path, units={"velocity": "m/s", "spin": "rpm"})
    assert exc.value.column == "carry" and "yards or metres" in exc.value.message
    shots = load_shots(path, units={"velocity": "m/s", "spin": "rpm", "distance": "m"})
    assert shots.landing_angle.values.tolist() == [37.7]  # angles without a unit are degrees
    with pytest.raises(DataError) as exc:  # a header unit the units= contradicts
        path.write_text("landing speed (mph),landing angle,spin,carry,total\n61.7,37.7,2440,230,248\n")
        load_shots(path, units={"velocity": "m/s", "spin": "rpm", "distance": "m"})
    assert exc.value.column == "landing speed (mph)" and exc.value.hints[0] == Hint("units", {"velocity": "mph"},
                                                                                    "as the header says")
    with pytest.raises(DataError, match="unknown distance unit 'furlong'"):
        load_shots(path, units={"distance": "furlong"})


@pytest.mark.parametrize("angle", ["0", "-38.2", "120"])
def test_a_landing_angle_that_is_no_landing_is_refused(tmp_path, angle):
    path = tmp_path / "a.csv"
    path.write_text(f"Carry Flat - Land. Angle,Total\n[deg],[yds]\n38.2,280\n{angle},281\n")
    with pytest.raises(DataError) as exc:
        load_shots(path)
    assert (exc.value.column, exc.value.row) == ("Carry Flat - Land. Angle", 2)


def test_no_shot_column_and_a_column_left_blank(tmp_path):
    path = tmp_path / "none.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(DataError) as exc:
        load_shots(path)
    assert "['a', 'b']" in exc.value.message and exc.value.hints[0].option == "columns"
    rows = [",".join(c if k != 11 else "" for k, c in enumerate(r.split(","))) for r in TM_ROWS]  # no landing speeds
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing dropped: the blank column is not read
        shots = load_shots(trackman(tmp_path / "blank.csv", rows=[r for i, r in enumerate(rows) if i != 1]))
    assert "landing_speed" not in shots and shots.attrs["empty_columns"] == ["Carry Flat - Ball Speed"]


def test_ground_re_exports_it_without_loading_pandas_on_import():
    assert ground.load_shots is load_shots and "load_shots" in ground.__all__
    code = "import sys, bouncelab.ground; print([m for m in ('pandas', 'xarray') if m in sys.modules])"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip() == "[]"


def test_options_that_do_not_apply_are_refused(tmp_path):
    path = trackman(tmp_path / "s.csv")
    with pytest.raises(DataError, match="only Excel files have sheets"):
        load_shots(path, sheet="Shots")
    with pytest.raises(DataError, match="missing must be one of"):
        load_shots(path, missing="skip")
    with pytest.raises(DataError, match="DataFrame"):
        load_shots(pd.DataFrame({"Total (yds)": [250.0]}), header_row=2)
    with pytest.raises(DataError, match=r"a shot export is a \.csv"):
        load_shots(tmp_path)


def test_a_wide_trackman_export_reads_total_before_the_flat_estimate(tmp_path):
    head = TM_HEAD + ",Est. Total Flat - Length,Est. Total Flat - Side,Smash Factor"
    units = TM_UNITS + ",[yds],[ft],[]"
    rows = [TM_ROWS[0] + ",276.9,-15.0,1.47", TM_ROWS[2] + ",171.0,3.5,1.40"]
    shots = load_shots(trackman(tmp_path / "wide.csv", rows=rows, head=head, units=units))
    np.testing.assert_allclose(shots.total, [284.0 * YD, 175.2 * YD], rtol=1e-14)
    assert shots.total.attrs["source_column"] == "Total" and shots.side_total.attrs["source_column"] == "Side Total"
    twice = tmp_path / "twice.csv"
    twice.write_text("Total (yds),Total (m),Carry (yds)\n250,228.6,230\n")
    with pytest.raises(DataError) as exc:
        load_shots(twice)
    assert "['Total (yds)', 'Total (m)']" in exc.value.message and exc.value.hints[0].option == "columns"
