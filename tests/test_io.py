"""Tests of bouncelab.data.io: loading campaigns from files and saving them to netCDF."""

from __future__ import annotations

import errno
import math
import os
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import scipy.io
import xarray as xr

from bouncelab.core.errors import DataError, Hint
from bouncelab.data import io as bio
from bouncelab.data.campaign import make_campaign
from bouncelab.data.io import load as io_load
from bouncelab.data.io import load_campaign, save_campaign
from bouncelab.data.io import names as syn
from bouncelab.data.io import read as io_read

R = 0.02135  # default ball radius, metres
RPM = 2 * math.pi / 60

# Six bounces in physical units: m/s and rpm, two launcher settings.
VX0 = np.array([20.1, 19.8, 20.4, 12.25, 12.0, 11.9])
VY0 = np.array([-15.2, -15.0, -15.4, -22.5, -22.1, -22.8])
W0 = np.array([3000.0, 3050.0, 2980.0, -1200.0, -1150.0, -1250.0])
VXF = np.array([9.5, 9.7, 9.4, 6.1, 6.3, 5.9])
VYF = np.array([5.1, 5.0, 5.3, 7.7, 7.5, 7.9])
WF = np.array([1500.0, 1480.0, 1520.0, 600.0, 620.0, 590.0])
SETTING = np.array([1, 1, 1, 2, 2, 2])
COLS = {"vx0": VX0, "vy0": VY0, "w0": W0, "vxF": VXF, "vyF": VYF, "wF": WF}
PHYS = {"velocity": "m/s", "spin": "rpm"}

# Expected scaled values, computed independently of bouncelab.core.units.
EXP_LANDING = np.column_stack([VX0 / R, VY0 / R, W0 * 2 * np.pi / 60])
EXP_LIFTOFF = np.column_stack([VXF / R, VYF / R, WF * 2 * np.pi / 60])


def write_table(path: Path, header: list[str], columns: list, *, sep: str = ",", pre: str = "") -> Path:
    """Write a text table with ``sep`` between cells (numbers written with repr)."""
    rows = [sep.join(header)]
    for i in range(len(columns[0])):
        rows.append(sep.join(c[i] if isinstance(c[i], str) else repr(float(c[i])) for c in columns))
    path.write_text(pre + "\n".join(rows) + "\n", encoding="utf-8")
    return path


def write_standard_csv(path: Path, **changes) -> Path:
    """The six bounces with columns vx0, vy0, w0, vxF, vyF, wF, setting; ``changes`` sets cells."""
    cols = {k: [repr(float(x)) for x in v] for k, v in COLS.items()}
    cols["setting"] = [str(s) for s in SETTING]
    for key, value in changes.items():
        name, row = key.rsplit("__", 1)  # e.g. w0__3="abc": data row 3 of column w0
        cols[name][int(row) - 1] = value
    return write_table(path, list(cols), list(cols.values()))


def check_physical(ds: xr.Dataset) -> None:
    np.testing.assert_allclose(ds["landing"].values, EXP_LANDING, rtol=1e-12)
    np.testing.assert_allclose(ds["liftoff"].values, EXP_LIFTOFF, rtol=1e-12)


DROP = Hint("missing", "drop", "drops incomplete rows")


def assert_located(exc: pytest.ExceptionInfo, path: Path, column: str | None, row: int | None) -> None:
    """The DataError names the file, the column as in the file and the 1-based data row (None: no column, no row)."""
    err = exc.value
    assert isinstance(err, DataError)
    assert err.file is not None and Path(err.file).name == path.name
    assert (err.column, err.row) == (column, row)


# ---------------------------------------------------------------------------
# Formats
# ---------------------------------------------------------------------------


def test_csv_with_header_units_converts_to_scaled(tmp_path):
    header = ["Vx0 [m/s]", "Vy0 [m/s]", "omega0_rpm", "vxF (m/s)", "vyF (m/s)", "spin_out (rev/min)"]
    path = write_table(tmp_path / "camp.csv", header, [VX0, VY0, W0, VXF, VYF, WF])
    ds = load_campaign(path)
    check_physical(ds)
    assert ds.attrs["campaign"] == "camp"
    assert ds.attrs["surface"] == ""
    assert ds.attrs["source"] == str(path.resolve())
    assert ds.attrs["data_kind"] == "measured"
    assert ds.attrs["source_units"] == "velocity m/s, spin rpm"
    assert ds.attrs["ball_radius_m"] == R
    assert "setting" not in ds.coords


def test_units_argument_and_names(tmp_path):
    path = write_standard_csv(tmp_path / "plain.csv")
    ds = load_campaign(path, units=PHYS, campaign="A", surface="turf")
    check_physical(ds)
    assert (ds.attrs["campaign"], ds.attrs["surface"]) == ("A", "turf")
    np.testing.assert_array_equal(ds["setting"].values, SETTING)
    assert ds["setting"].dtype.kind == "i"


def test_other_units_and_ball_radius(tmp_path):
    path = write_table(tmp_path / "ft.csv", list(COLS), [VX0, VY0, W0 / 60, VXF, VYF, WF / 60])
    ds = load_campaign(path, units={"velocity": "ft/s", "spin": "rev/s"}, ball_radius_m=0.021)
    np.testing.assert_allclose(ds["landing"].values[:, 0], VX0 * 0.3048 / 0.021, rtol=1e-12)
    np.testing.assert_allclose(ds["landing"].values[:, 2], W0 / 60 * 2 * np.pi, rtol=1e-12)
    assert ds.attrs["ball_radius_m"] == 0.021
    assert ds.attrs["source_units"] == "velocity ft/s, spin rev/s"


def test_scaled_units_assumed(tmp_path):
    path = write_table(tmp_path / "scaled.csv", list(COLS), [EXP_LANDING[:, 0], EXP_LANDING[:, 1],
                       EXP_LANDING[:, 2], EXP_LIFTOFF[:, 0], EXP_LIFTOFF[:, 1], EXP_LIFTOFF[:, 2]])
    # Spins of a few hundred with no unit fit rad/s, rpm and rev/s alike: refused, not guessed.
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, None, None)  # two columns: both named in the message
    assert exc.value.hints == tuple(Hint("units", {"spin": u}) for u in ("rad/s", "rpm", "rev/s"))
    assert "'w0', 'wF'" in exc.value.message
    # Velocities of ~1000 fit only radii/s (in m/s they would be faster than any golf ball).
    ds = load_campaign(path, units={"spin": "rad/s"})
    np.testing.assert_array_equal(ds["landing"].values, EXP_LANDING)
    np.testing.assert_array_equal(ds["liftoff"].values, EXP_LIFTOFF)
    assert ds.attrs["source_units"] == "velocity radius/s (assumed), spin rad/s"


@pytest.mark.parametrize(
    ("suffix", "sep"),
    [(".csv", ","), (".tsv", "\t"), (".txt", "\t"), (".txt", ";"), (".txt", "   "), (".csv", " ")],
)
def test_text_delimiters(tmp_path, suffix, sep):
    path = write_table(tmp_path / f"data{suffix}", list(COLS), list(COLS.values()), sep=sep)
    check_physical(load_campaign(path, units=PHYS))


def test_semicolon_file_with_decimal_commas(tmp_path):
    lines = ["vx0;vy0;w0;vxF;vyF;wF"]
    for row in zip(*COLS.values(), strict=True):
        lines.append(";".join(repr(float(x)).replace(".", ",") for x in row))
    path = tmp_path / "euro.csv"
    path.write_text("\n".join(lines), encoding="utf-8")
    check_physical(load_campaign(path, units=PHYS))


def test_whitespace_file_with_bracket_units_and_comments(tmp_path):
    header = ["vx0 [m/s]", "vy0 [m/s]", "w0 [rpm]", "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    path = write_table(tmp_path / "ws.txt", header, list(COLS.values()), sep="  ",
                       pre="% exported by the tracker\n\n")
    check_physical(load_campaign(path))


def test_units_row_under_header(tmp_path):
    path = tmp_path / "units_row.csv"
    lines = ["vx0,vy0,w0,vxF,vyF,wF,setting", "m/s,m/s,rpm,m/s,m/s,rpm,-"]
    lines += [",".join([*(repr(float(x)) for x in row), str(s)])
              for *row, s in zip(*COLS.values(), SETTING, strict=True)]
    path.write_text("\n".join(lines), encoding="utf-8")
    ds = load_campaign(path)
    check_physical(ds)
    write = path.read_text().replace("-15.0", "abc")  # data row 2 is the third line after the header
    path.write_text(write)
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, "vy0", 2)
    assert exc.value.message.endswith("(line 4)")


def test_excel_round_trip_and_sheet(tmp_path):
    path = tmp_path / "book.xlsx"
    frame = pd.DataFrame({"Vx0 (m/s)": VX0, "Vy0 (m/s)": VY0, "Spin0 (rpm)": W0, "VxF (m/s)": VXF,
                          "VyF (m/s)": VYF, "SpinF (rpm)": WF, "Test condition": SETTING})
    with pd.ExcelWriter(path) as writer:
        pd.DataFrame({"note": ["not data"]}).to_excel(writer, sheet_name="Notes", index=False)
        frame.to_excel(writer, sheet_name="Bounces", index=False)
    ds = load_campaign(path, sheet="Bounces")
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, SETTING)
    check_physical(load_campaign(path, sheet=1))
    with pytest.raises(DataError) as exc:
        load_campaign(path, sheet="Nope")
    assert_located(exc, path, None, None)
    assert "'Nope'" in exc.value.message and "['Notes', 'Bounces']" in exc.value.message  # the sheets there are
    with pytest.raises(DataError) as exc:
        load_campaign(path)  # first sheet has no bounce data
    assert [h.option for h in exc.value.hints] == ["columns"]


def test_excel_bad_cell_names_cell(tmp_path):
    path = tmp_path / "bad.xlsx"
    frame = pd.DataFrame({k: list(v) for k, v in COLS.items()}, dtype=object)
    frame.loc[3, "vyF"] = None  # data row 4, spreadsheet row 5, column E
    frame.to_excel(path, index=False)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "vyF", 4)
    assert exc.value.hints == (DROP,)
    assert exc.value.message.endswith("(cell E5 of sheet 'Sheet1')")


def test_excel_needs_openpyxl(tmp_path, monkeypatch):
    path = tmp_path / "book.xlsx"
    pd.DataFrame(COLS).to_excel(path, index=False)
    monkeypatch.setattr(io_read, "module_available", lambda name: False)
    with pytest.raises(DataError) as e:
        load_campaign(path)
    assert e.value.file == str(path) and "openpyxl" in e.value.message


def test_mat_vectors(tmp_path):
    path = tmp_path / "vec.mat"
    scipy.io.savemat(path, {**{k: v.reshape(-1, 1) for k, v in COLS.items()}, "setting": SETTING,
                            "fps": 5000.0})
    ds = load_campaign(path, units=PHYS)
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, SETTING)


def test_mat_matrix_columns_are_one_based(tmp_path):
    path = tmp_path / "mat.mat"
    scipy.io.savemat(path, {"IN": np.column_stack([VX0, VY0, W0]), "OUT": np.column_stack([VXF, VYF, WF])})
    ds = load_campaign(path, units=PHYS, columns={"landing": ["IN_1", "IN_2", "IN_3"],
                                                  "liftoff": ["OUT_1", "OUT_2", "OUT_3"]})
    check_physical(ds)


def test_mat_struct_and_struct_array(tmp_path):
    path = tmp_path / "struct.mat"
    labels = np.array([f"S{s}" for s in SETTING], dtype=object)
    scipy.io.savemat(path, {"bounces": {**COLS, "condition": labels}})
    ds = load_campaign(path, units=PHYS)
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, [f"S{s}" for s in SETTING])

    # table2struct(T): a 1 x n struct array with one scalar per field
    rec = np.zeros((1, len(VX0)), dtype=[(k, object) for k in COLS])
    for k, v in COLS.items():
        for i, x in enumerate(v):
            rec[0, i][k] = x
    path2 = tmp_path / "structarray.mat"
    scipy.io.savemat(path2, {"T": rec})
    check_physical(load_campaign(path2, units=PHYS))


def test_mat_nan_is_located(tmp_path):
    path = tmp_path / "nan.mat"
    w0 = W0.copy()
    w0[4] = np.nan
    scipy.io.savemat(path, {**COLS, "w0": w0})
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "w0", 5)


def test_mat_columns_of_different_lengths(tmp_path):
    path = tmp_path / "len.mat"
    scipy.io.savemat(path, {**COLS, "wF": WF[:4]})
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "vx0", None)  # a column of the longest, beside wF's 4 values


def test_netcdf_plain_columns(tmp_path):
    path = tmp_path / "cols.nc"
    xr.Dataset({k: ("row", v) for k, v in COLS.items()} | {"group": ("row", SETTING)}).to_netcdf(
        path, engine="scipy")
    ds = load_campaign(path, units=PHYS)
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, SETTING)
    assert ds.attrs["data_kind"] == "measured"


# ---------------------------------------------------------------------------
# netCDF campaigns: save / load
# ---------------------------------------------------------------------------


def make_full_campaign(setting) -> xr.Dataset:
    rng = np.random.default_rng(1)
    return make_campaign(
        EXP_LANDING + rng.normal(0, 1e-3, EXP_LANDING.shape), EXP_LIFTOFF, setting=setting,
        landing_pi=np.abs(rng.normal(0, 3, EXP_LANDING.shape)),
        liftoff_pi=np.abs(rng.normal(0, 3, EXP_LANDING.shape)),
        campaign="B", surface="tee (fescue)", source="/data/é.csv", data_kind="synthetic surrogate",
        attrs={"source_units": "velocity m/s, spin rpm", "n_settings": 2, "noise": 0.25},
    )


@pytest.mark.parametrize("setting", [SETTING, np.array(["low spin", "héavy", "low spin", "a", "b", "c"]),
                                     None])
def test_save_load_bit_exact(tmp_path, setting):
    ds = make_full_campaign(setting)
    out = save_campaign(ds, tmp_path / "camp.nc", engine="scipy")
    assert out == tmp_path / "camp.nc"
    back = load_campaign(out)
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        np.testing.assert_array_equal(back[var].values, ds[var].values)
        assert back[var].dtype == ds[var].dtype
    if setting is None:
        assert "setting" not in back.coords
    else:
        np.testing.assert_array_equal(back["setting"].values, ds["setting"].values)
        assert back["setting"].dtype == ds["setting"].dtype
    np.testing.assert_array_equal(back["bounce"].values, ds["bounce"].values)
    assert back["bounce"].dtype == ds["bounce"].dtype
    assert back.attrs == ds.attrs
    xr.testing.assert_identical(back, ds)
    assert [p.name for p in tmp_path.iterdir()] == ["camp.nc"]  # no temporary file left
    again = load_campaign(save_campaign(back, tmp_path / "again.nc", engine="scipy"))
    xr.testing.assert_identical(again, ds)


def test_save_default_engine_and_overrides(tmp_path):
    ds = make_full_campaign(SETTING)
    path = save_campaign(ds, str(tmp_path / "c.netcdf"))
    back = load_campaign(path, campaign="renamed", surface="grass")
    assert (back.attrs["campaign"], back.attrs["surface"]) == ("renamed", "grass")
    assert back.attrs["data_kind"] == "synthetic surrogate"
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, None, None)
    assert exc.value.hints == ()


def test_netcdf_campaign_without_kind_is_measured(tmp_path):
    ds = make_campaign(EXP_LANDING, EXP_LIFTOFF)
    del ds.attrs["data_kind"], ds.attrs["source"]
    path = tmp_path / "bare.nc"
    ds.to_netcdf(path, engine="scipy")
    back = load_campaign(path)
    assert back.attrs["data_kind"] == "measured"
    assert back.attrs["source"] == str(path.resolve())


def test_save_refuses_bad_campaign(tmp_path):
    ds = make_full_campaign(SETTING).copy(deep=True)
    ds["landing"].values[2, 1] = 3.0  # moving up at landing
    with pytest.raises(DataError) as exc:
        save_campaign(ds, tmp_path / "bad.nc")
    assert (exc.value.file, exc.value.column, exc.value.row) == (str(tmp_path / "bad.nc"), "landing.ydot", 3)
    assert list(tmp_path.iterdir()) == []


def test_save_refuses_unstorable_attr_and_bad_suffix(tmp_path):
    ds = make_full_campaign(SETTING)
    with pytest.raises(DataError) as exc:
        save_campaign(ds.assign_attrs(flag={"a": 1}), tmp_path / "x.nc")
    assert exc.value.file == str(tmp_path / "x.nc") and "'flag'" in exc.value.message
    with pytest.raises(DataError) as exc:
        save_campaign(ds, tmp_path / "x.csv")
    assert exc.value.file == str(tmp_path / "x.csv")
    assert list(tmp_path.iterdir()) == []


def test_save_missing_directory(tmp_path):
    from bouncelab.core.errors import OutputError

    with pytest.raises(OutputError) as e:
        save_campaign(make_full_campaign(SETTING), tmp_path / "no" / "dir" / "x.nc")
    assert isinstance(e.value, OSError) and e.value.path == str(tmp_path / "no" / "dir" / "x.nc")
    assert e.value.errno == errno.ENOENT
    assert list(tmp_path.iterdir()) == []


def test_save_failure_keeps_existing_file(tmp_path, monkeypatch):
    path = save_campaign(make_full_campaign(SETTING), tmp_path / "keep.nc")
    before = path.read_bytes()

    def boom(self, *args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", boom)
    with pytest.raises(OSError, match="disk full"):
        save_campaign(make_campaign(EXP_LANDING, EXP_LIFTOFF), path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["keep.nc"]


# ---------------------------------------------------------------------------
# Sources
# ---------------------------------------------------------------------------


def test_embedded_names_use_package_file(tmp_path, monkeypatch):
    path = save_campaign(make_full_campaign(SETTING), tmp_path / "campaign_A.nc")
    monkeypatch.setattr(io_load, "_embedded_file", lambda name, surrogate: path if name == "A" else None)
    ds = load_campaign(" a ")
    xr.testing.assert_identical(ds, make_full_campaign(SETTING))


def test_embedded_missing_file_message(monkeypatch, tmp_path):
    monkeypatch.setattr(io_load.resources, "files", lambda pkg: tmp_path)
    with pytest.raises(FileNotFoundError, match=r"campaign_B_turf\.nc"):
        load_campaign("B")
    with pytest.raises(FileNotFoundError, match=r"campaign_B\.nc"):
        load_campaign("B", surrogate="published")


def test_unknown_source_name_and_missing_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError, match=r"'C'.*embedded campaigns are 'A' and 'B'"):
        load_campaign("C")
    with pytest.raises(FileNotFoundError, match=r"nothere\.csv"):
        load_campaign(tmp_path / "nothere.csv")


def test_path_named_a_is_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError, match="'A'"):
        load_campaign(Path("A"))


def test_unknown_suffix(tmp_path):
    path = tmp_path / "data.json"
    path.write_text("{}")
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, None, None)
    assert all(suffix in exc.value.message for suffix in bio.SUPPORTED_SUFFIXES)


# ---------------------------------------------------------------------------
# Column matching
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("header", "unit"),
    [("vx0 [m/s]", "m/s"), ("Vx0 (m/s)", "m/s"), ("vx0_mps", "m/s"), ("VX_0 {ft/s}", "ft/s"),
     ("vx0 m/s", "m/s"), ("x_dot_0 [m s^-1]", "m/s"), ("vx0 (mph)", "mph")],
)
def test_velocity_header_unit_suffixes(tmp_path, header, unit):
    factor = {"m/s": 1.0, "ft/s": 0.3048, "mph": 1609.344 / 3600}[unit]
    names = [header, "vy0 [m/s]", "w0 [rpm]", "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    path = write_table(tmp_path / "h.csv", names, list(COLS.values()))
    ds = load_campaign(path)
    np.testing.assert_allclose(ds["landing"].values[:, 0], VX0 * factor / R, rtol=1e-12)


@pytest.mark.parametrize(
    ("header", "factor"),
    [("omega0_rpm", RPM), ("spin (rev/min)", RPM), ("Spin0 [rot per min]", RPM), ("w0 (rad/s)", 1.0),
     ("ω0 [Hz]", 2 * math.pi), ("omega_in [deg/s]", math.pi / 180), ("w0 [1/s]", 1.0)],
)
def test_spin_header_unit_suffixes(tmp_path, header, factor):
    names = ["vx0 [m/s]", "vy0 [m/s]", header, "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    in_unit = W0 * RPM / factor  # the landing spin written in the header's unit
    path = write_table(tmp_path / "s.csv", names, [VX0, VY0, in_unit, VXF, VYF, WF])
    columns = None
    if header.startswith("spin ("):  # no phase in the name: name it
        columns = {"landing": ["vx0", "vy0", "spin"], "liftoff": ["vxF", "vyF", "wF"]}
    ds = load_campaign(path, columns=columns)
    np.testing.assert_allclose(ds["landing"].values[:, 2], in_unit * factor, rtol=1e-12)
    np.testing.assert_allclose(ds["landing"].values[:, 2], EXP_LANDING[:, 2], rtol=1e-12)


def test_explicit_columns_are_matched_tolerantly(tmp_path):
    names = ["X_Dot 0 [m/s]", "y-dot-0 (m/s)", "SPIN IN rpm", "Out Vx", "Out Vy", "Out Spin", "Test #"]
    path = write_table(tmp_path / "odd.csv", names, [*COLS.values(), [str(s) for s in SETTING]])
    ds = load_campaign(
        path, units={"velocity": "m/s", "spin": "rpm"},
        columns={"landing": ["xdot0", "YDOT_0", "spin_in"], "liftoff": ["out vx", "outvy", "out-spin"],
                 "setting": "test"},
    )
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, SETTING)


def test_ambiguous_requested_name(tmp_path):
    names = ["Vx0", "vx_0 [m/s]", "vy0", "w0", "vxF", "vyF", "wF"]
    path = write_table(tmp_path / "amb.csv", names, [VX0, VX0, VY0, W0, VXF, VYF, WF])
    columns = {"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"]}
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS, columns=columns)
    assert_located(exc, path, "vx0", None)
    assert "['Vx0', 'vx_0 [m/s]']" in exc.value.message  # the columns it matches
    # the exact spelling picks one
    ds = load_campaign(path, units=PHYS, columns={**columns, "landing": ["Vx0", "vy0", "w0"]})
    check_physical(ds)


def test_missing_requested_column(tmp_path):
    path = write_standard_csv(tmp_path / "miss.csv")
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS, columns={"landing": ["vx0", "vy0", "omega_0"],
                                                 "liftoff": ["vxF", "vyF", "wF"]})
    assert_located(exc, path, "omega_0", None)
    assert "['vx0', 'vy0', 'w0', 'vxF', 'vyF', 'wF', 'setting']" in exc.value.message  # lists the file's columns


def test_bad_columns_argument(tmp_path):
    path = write_standard_csv(tmp_path / "arg.csv")
    for columns, said in (({"landing": ["vx0", "vy0", "w0"]}, "liftoff"),
                          ({"landing": ["vx0", "vy0", "w0"], "lift": ["vxF", "vyF", "wF"]}, "'lift'"),
                          ({"landing": "vx0", "liftoff": ["vxF", "vyF", "wF"]}, "'vx0'")):
        with pytest.raises(DataError) as exc:
            load_campaign(path, columns=columns)
        assert_located(exc, path, None, None)
        assert said in exc.value.message  # what is wrong with the argument
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS, columns={"landing": ["vx0", "vy0", "w0"],
                                                 "liftoff": ["vxF", "vyF", "w0"]})
    assert_located(exc, path, "w0", None)
    assert "landing.omega" in exc.value.message and "liftoff.omega" in exc.value.message


@pytest.mark.parametrize(
    "names",
    [
        ["xdot0", "ydot0", "omega0", "xdotF", "ydotF", "omegaF"],
        ["x_dot_0", "y_dot_0", "w0", "x_dot_F", "y_dot_F", "wF"],
        ["vx_in", "vy_in", "spin_in", "vx_out", "vy_out", "spin_out"],
        ["u0", "v0", "w0", "u1", "v1", "w1"],
        ["inbound_vx", "inbound_vy", "inbound_spin", "outbound_vx", "outbound_vy", "outbound_spin"],
        ["Landing Vx [m/s]", "Landing Vy [m/s]", "Landing spin (rpm)", "Rebound Vx [m/s]",
         "Rebound Vy [m/s]", "Rebound spin (rpm)"],
        ["Inbound horizontal velocity (m/s)", "Inbound vertical velocity (m/s)", "Inbound spin (rpm)",
         "Outbound horizontal velocity (m/s)", "Outbound vertical velocity (m/s)", "Outbound spin (rpm)"],
        ["ẋ0", "ẏ0", "ω0", "ẋF", "ẏF", "ωF"],
    ],
)
@pytest.mark.parametrize("setting_name", ["setting", "Condition", "launcher_setting", "group", "Test condition"])
def test_auto_detection(tmp_path, names, setting_name):
    order = [2, 0, 5, 1, 4, 3]  # columns in a shuffled order
    header = [setting_name] + [names[i] for i in order]
    data = [[f"S{s}" for s in SETTING]] + [list(COLS.values())[i] for i in order]
    path = write_table(tmp_path / "auto.csv", header, data)
    units = None if "[m/s]" in names[0] or "(m/s)" in names[0] else PHYS
    ds = load_campaign(path, units=units)
    check_physical(ds)
    np.testing.assert_array_equal(ds["setting"].values, [f"S{s}" for s in SETTING])


def test_spec_synonyms_are_recognised():
    expect = {
        "landing.xdot": ["xdot0", "x_dot_0", "vx0", "vx_in", "u0", "xdot_in", "inbound_vx"],
        "liftoff.xdot": ["xdotF", "vxF", "vx_out", "vx1"],
        "landing.omega": ["omega0", "w0", "spin0", "spin_in"],
        "liftoff.omega": ["omegaF", "wF", "spin_out"],
        "landing_pi.ydot": ["vy0_pi", "ydot0 err", "PI vy0"],
        "setting": ["setting", "condition", "launcher_setting", "group", "test_condition"],
    }
    for role, names in expect.items():
        for name in names:
            assert syn.role_of(syn.normalize(name)) == role, name


def test_synonym_table_has_no_collisions():
    seen: dict[str, str] = {}
    for state, phases in syn._PHASES.items():
        for comp, stems in syn._STEMS.items():
            for stem in stems:
                for ph in phases:
                    for key in (stem + ph, ph + stem):
                        assert seen.setdefault(key, f"{state}.{comp}") == f"{state}.{comp}", key
    assert not set(syn._SETTING_NAMES) & set(seen)
    assert syn._build_state_keys() == syn._STATE_KEYS


@pytest.mark.parametrize(
    "name",
    ["idx", "index", "indx", "id", "trial", "time", "speed", "angle", "landing angle", "low", "prev",
     "ivy", "iv", "speed0", "notes", "x0", "y0", "frame rate", "wheel speed", "vx", "spin", "in", "out"],
)
def test_common_column_names_are_not_bounce_data(name):
    assert syn.role_of(syn.normalize(name)) is None


def test_auto_detection_failure_shows_columns_argument(tmp_path):
    names = ["vx0", "vx_in", "vy0", "speed", "vxF", "vyF", "wF"]
    path = write_table(tmp_path / "undecided.csv", names, [VX0, VX0, VY0, W0, VXF, VYF, WF])
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, None, None)
    msg = exc.value.message
    assert "['vx0', 'vx_in', 'vy0', 'speed', 'vxF', 'vyF', 'wF']" in msg
    assert "landing.xdot: several candidates ['vx0', 'vx_in']" in msg
    assert "landing.omega: no column found" in msg
    assert exc.value.hints == (Hint("columns", {"landing": ["<one of vx0, vx_in>", "vy0", "<landing omega column>"],
                                                "liftoff": ["vxF", "vyF", "wF"]}, "replace each <...>"),)
    # what str() says to pass is that argument, with each <...> to replace
    assert ("pass columns={'landing': ['<one of vx0, vx_in>', 'vy0', '<landing omega column>'], "
            "'liftoff': ['vxF', 'vyF', 'wF']} (replace each <...>)") in str(exc.value)


def test_prediction_intervals(tmp_path):
    pis = {f"{k}_pi": np.full(6, 0.1 if k.startswith("v") else 20.0) for k in COLS}
    path = write_table(tmp_path / "pi.csv", [*COLS, *pis], [*COLS.values(), *pis.values()])
    ds = load_campaign(path, units=PHYS)
    check_physical(ds)
    np.testing.assert_allclose(ds["landing_pi"].values[:, 0], 0.1 / R, rtol=1e-12)
    np.testing.assert_allclose(ds["liftoff_pi"].values[:, 2], 20 * RPM, rtol=1e-12)

    explicit = load_campaign(path, units=PHYS, columns={
        "landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"],
        "landing_pi": ["vx0_pi", "vy0_pi", "w0_pi"]})
    assert "liftoff_pi" not in explicit and "landing_pi" in explicit

    pis["vyF_pi"][4] = -0.5
    write_table(path, [*COLS, *pis], [*COLS.values(), *pis.values()])
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "vyF_pi", 5)
    assert "-0.5 is negative" in exc.value.message

    pis["vyF_pi"][4] = 0.5
    pis["w0_pi"][2] = 1e6  # an interval no spin measurement has: a unit mistake
    write_table(path, [*COLS, *pis], [*COLS.values(), *pis.values()])
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "w0_pi", 3)
    assert "1000000.0 rpm is wider than any plausible value" in exc.value.message  # the cell as written


def test_incomplete_prediction_intervals_are_ignored_with_warning(tmp_path):
    path = write_table(tmp_path / "pi2.csv", [*COLS, "vx0_err"], [*COLS.values(), np.ones(6)])
    with pytest.warns(UserWarning, match="incomplete landing_pi"):
        ds = load_campaign(path, units=PHYS)
    assert "landing_pi" not in ds


# ---------------------------------------------------------------------------
# Units
# ---------------------------------------------------------------------------


def test_physical_units_guard(tmp_path):
    path = write_standard_csv(tmp_path / "phys.csv")
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"spin": "rpm"})
    assert_located(exc, path, None, None)
    assert exc.value.hints == tuple(Hint("units", {"velocity": u}) for u in ("m/s", "ft/s", "km/h", "mph"))
    assert "the median landing speed would be 0.5" in exc.value.message  # why not radii/s
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_physical(load_campaign(path, units=PHYS))


def test_spin_in_rpm_read_as_rad_per_s_is_refused(tmp_path):
    names = ["vx0 [m/s]", "vy0 [m/s]", "w0", "vxF [m/s]", "vyF [m/s]", "wF"]
    w0 = W0.copy()
    w0[2] = 9100.0
    path = write_table(tmp_path / "rpm.csv", names, [VX0, VY0, w0, VXF, VYF, WF])
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, "w0", 1)  # 3000 read as rad/s is 28 648 rpm
    assert exc.value.hints == (Hint("units", {"spin": "rpm"}),)
    assert load_campaign(path, units={"spin": "rpm"}).attrs["source_units"] == "velocity m/s, spin rpm"


def test_scaled_file_declared_in_m_per_s_is_refused(tmp_path):
    path = write_table(tmp_path / "twice.csv", list(COLS), [EXP_LANDING[:, 0], EXP_LANDING[:, 1],
                       EXP_LANDING[:, 2], EXP_LIFTOFF[:, 0], EXP_LIFTOFF[:, 1], EXP_LIFTOFF[:, 2]])
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s", "spin": "rad/s"})
    assert_located(exc, path, "vx0", 1)
    assert Hint("units", {"velocity": "radius/s"}) in exc.value.hints and exc.value.hints[-1].option == "plausible"


def test_header_and_units_argument_disagree(tmp_path):
    names = ["vx0 [m/s]", "vy0 [ft/s]", "w0 [rpm]", "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    path = write_table(tmp_path / "clash.csv", names, list(COLS.values()))
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s"})
    assert_located(exc, path, "vy0 [ft/s]", None)
    assert exc.value.hints == (Hint("units", {"velocity": "ft/s"}, "as the header says"),)
    ds = load_campaign(path, units={"spin": "rpm"})  # agrees with the header
    np.testing.assert_allclose(ds["landing"].values[:, 1], VY0 * 0.3048 / R, rtol=1e-12)
    assert ds.attrs["source_units"].startswith("velocity vx0 [m/s]: m/s, vy0 [ft/s]: ft/s")


def test_unknown_units(tmp_path):
    path = write_standard_csv(tmp_path / "u.csv")
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "furlong/s"})
    assert_located(exc, path, None, None)
    assert "'furlong/s'" in exc.value.message
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"speed": "m/s"})
    assert_located(exc, path, None, None)
    assert "{'speed': 'm/s'}" in exc.value.message
    names = ["vx0 [px/frame]", "vy0 [m/s]", "w0 [rpm]", "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    path2 = write_table(tmp_path / "u2.csv", names, list(COLS.values()))
    with pytest.raises(DataError) as exc:
        load_campaign(path2)
    assert_located(exc, path2, "vx0 [px/frame]", None)
    assert "'px/frame', not a known unit" in exc.value.message
    names[2] = "w0 [m/s]"
    names[0] = "vx0 [m/s]"
    write_table(path2, names, list(COLS.values()))
    with pytest.raises(DataError) as exc:
        load_campaign(path2)
    assert_located(exc, path2, "w0 [m/s]", None)
    assert "a velocity unit, not a spin unit" in exc.value.message


# ---------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("changes", "column", "row", "cell", "hints"),
    [
        ({"w0__3": "abc"}, "w0", 3, "'abc'", ()),  # non-numeric
        ({"vyF__6": ""}, "vyF", 6, "empty", (DROP,)),
        ({"vxF__2": "NA"}, "vxF", 2, "'NA'", (DROP,)),  # a missing value
        ({"vx0__4": "nan"}, "vx0", 4, "'nan'", (DROP,)),
        ({"wF__5": "-inf"}, "wF", 5, "infinite", ()),
        ({"vy0__2": "0.0"}, "vy0", 2, "0.0 m/s", ()),  # a landing must come down
        ({"vy0__5": "3.5"}, "vy0", 5, "3.5 m/s", ()),
        ({"setting__1": ""}, "setting", 1, "(empty)", (DROP,)),  # a missing setting label
        ({"w0__5": "1.2.3", "vxF__2": "x"}, "vxF", 2, "'x'", ()),  # first bad row wins
    ],
)
def test_bad_cells_are_located(tmp_path, changes, column, row, cell, hints):
    path = write_standard_csv(tmp_path / "bad.csv", **changes)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, column, row)
    assert exc.value.hints == hints
    assert cell in exc.value.message and exc.value.message.endswith(f"(line {row + 1})")  # as written; where
    assert [p.name for p in tmp_path.iterdir()] == ["bad.csv"]  # nothing written


def test_rows_count_data_rows_not_lines(tmp_path):
    path = write_standard_csv(tmp_path / "gaps.csv", w0__4="abc")
    lines = path.read_text().splitlines()
    lines = ["# bounce data", "", lines[0], "", lines[1], "# repeat", *lines[2:]]
    path.write_text("\n".join(lines))
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "w0", 4)
    assert exc.value.message.endswith("(line 9)")


def test_empty_file(tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text("\n  \n")
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, None, None)
    assert "empty" in exc.value.message


def test_header_without_rows(tmp_path):
    path = tmp_path / "header.csv"
    path.write_text("vx0,vy0,w0,vxF,vyF,wF\n")
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert_located(exc, path, None, None)
    assert "no data rows" in exc.value.message


def test_duplicate_column_names(tmp_path):
    path = write_table(tmp_path / "dup.csv", [*COLS, "w0"], [*COLS.values(), W0])
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, "w0", None)
    assert "columns 3 and 7" in exc.value.message


def test_row_with_too_many_values(tmp_path):
    path = write_standard_csv(tmp_path / "wide.csv")
    lines = path.read_text().splitlines()
    lines[3] += ",99"
    path.write_text("\n".join(lines))
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS)
    assert_located(exc, path, None, 3)
    assert "8 values but the header names 7" in exc.value.message and exc.value.message.endswith("(line 4)")


def test_bad_ball_radius_and_sheet_on_csv(tmp_path):
    path = write_standard_csv(tmp_path / "r.csv")
    with pytest.raises(DataError, match="ball_radius_m"):
        load_campaign(path, units=PHYS, ball_radius_m=-1)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=PHYS, sheet="x")
    assert_located(exc, path, None, None)
    assert "'x'" in exc.value.message


def test_not_a_mat_or_netcdf_file(tmp_path):
    for name in ("junk.mat", "junk.nc", "junk.xlsx"):
        path = tmp_path / name
        path.write_bytes(b"this is not binary data at all" * 10)
        with pytest.raises(DataError) as exc:
            load_campaign(path)
        assert_located(exc, path, None, None)


def test_save_campaign_keeps_mode_and_symlinks(tmp_path):
    """bouncelab 0.1 made files mode 0600 and replaced a symlink by a file (issue 7, item 6)."""
    import stat

    import bouncelab as bl

    ds = bl.load_campaign("A")
    old = os.umask(0o022)
    try:
        new = bl.save_campaign(ds, tmp_path / "new.nc")
        assert stat.S_IMODE(new.stat().st_mode) == 0o644  # the umask's mode, not mkstemp's 0600
        shared = tmp_path / "shared.nc"
        bl.save_campaign(ds, shared)
        shared.chmod(0o664)
        bl.save_campaign(ds, shared)
        assert stat.S_IMODE(shared.stat().st_mode) == 0o664
        target = tmp_path / "real.nc"
        bl.save_campaign(ds, target)
        link = tmp_path / "link.nc"
        link.symlink_to(target)
        bl.save_campaign(ds.isel(bounce=slice(0, 10)), link)
        assert link.is_symlink() and bl.load_campaign(target).sizes["bounce"] == 10
    finally:
        os.umask(old)


def test_plain_number_fast_path_agrees_with_cell_by_cell_parsing(tmp_path):
    """A large CSV goes through pandas' one-call parse: the same floats as Python's reading of each cell."""
    import bouncelab as bl

    ds = bl.load_campaign("A")
    rng = np.random.default_rng(3)
    cols = ["xdot0", "ydot0", "omega0", "xdotF", "ydotF", "omegaF"]
    state = np.column_stack([ds.landing.values, ds.liftoff.values])
    state = state * (1 + 1e-9 * rng.standard_normal(state.shape))
    cells = [[f"{v:.17g}" for v in row] for row in state]
    text = "setting," + ",".join(c + " (radii/s)" if "dot" in c else c + " (rad/s)" for c in cols) + "\n"
    text += "".join(f"{s}," + ",".join(r) + "\n" for s, r in zip(ds.setting.values, cells, strict=True))
    (tmp_path / "big.csv").write_text(text)
    back = bl.load_campaign(tmp_path / "big.csv")
    got = np.column_stack([back.landing.values, back.liftoff.values])
    np.testing.assert_array_equal(got, [[float(c) for c in r] for r in cells])
