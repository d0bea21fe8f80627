"""Files that used to load wrong values without a word (issue 7, items 3 and 4): each loads exactly
what a person reading it would read, or raises a located DataError."""

from __future__ import annotations

import math
import os
import threading

import numpy as np
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core.errors import DataError, Hint
from bouncelab.core.plausibility import implausibility
from bouncelab.data.campaign import make_campaign, validate_campaign

R = 0.02135
RPM = 2 * math.pi / 60
LAND = np.array([[20.1, -15.2, 3000.0], [12.2, -22.5, -1200.0], [30.0, -20.0, 4500.0]])
LIFT = np.array([[9.5, 5.1, 1500.0], [6.1, 7.7, 600.0], [14.0, 6.0, 2500.0]])
UNITS = {"velocity": "m/s", "spin": "rpm"}
HEAD = ["setting", "vx0", "vy0", "w0", "vxF", "vyF", "wF"]
DROP = Hint("missing", "drop", "drops incomplete rows")


def located(exc: pytest.ExceptionInfo, column: str | None, row: int | None, line: int | None = None) -> bool:
    """The DataError names the column and the 1-based data row (and its message ends with the file's line)."""
    err = exc.value
    return ((err.column, err.row) == (column, row) and err.file is not None
            and (line is None or err.message.endswith(f"(line {line})")))


def scaled(state: np.ndarray) -> np.ndarray:
    return np.column_stack([state[:, 0] / R, state[:, 1] / R, state[:, 2] * RPM])


def rows(settings=("1", "1", "2"), sep=",", fmt=repr) -> list[str]:
    return [sep.join([s, *(fmt(float(v)) for v in (*a, *b))]) for s, a, b in zip(settings, LAND, LIFT, strict=True)]


def write(path, lines, sep=","):
    path.write_text("\n".join([sep.join(HEAD), *lines]) + "\n")
    return path


# --- item 3: "#" rows, blank cells in whitespace files ---------------------------------------------

def test_excel_na_in_the_setting_column_is_a_missing_label_not_a_comment(tmp_path):
    lines = rows()
    lines[1] = "#N/A" + lines[1][1:]
    path = write(tmp_path / "na.csv", ["# measured 2026-11-20", *lines])
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units=UNITS)
    assert located(exc, "setting", 2, line=4) and exc.value.hints == (DROP,)
    assert "missing setting label ('#N/A')" in exc.value.message


def test_a_data_shaped_row_after_the_header_starting_with_hash_is_refused(tmp_path):
    lines = rows()
    path = write(tmp_path / "c.csv", [lines[0], "#" + lines[1], "# just a note", lines[2]])
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units=UNITS)
    assert located(exc, None, 2) and exc.value.message.startswith("line 3 starts with '#' like a comment but holds")
    path = write(tmp_path / "ok.csv", [lines[0], "# just a note, here", lines[1], "% another", lines[2]])
    np.testing.assert_allclose(bl.load_campaign(path, units=UNITS).landing.values, scaled(LAND), rtol=1e-12)


def test_blank_cell_in_a_whitespace_file_is_refused(tmp_path):
    head = "vx0 vy0 w0 vxF vyF wF note"
    good = ["20.1 -15.2 3000 9.5 5.1 1500 a", "12.2 -22.5 -1200 6.1 7.7 600 b"]
    shifted = "30.0 -20.0 4500 14.0 6.0 2500"  # the note is blank: nothing to see
    path = tmp_path / "ws.txt"
    path.write_text("\n".join([head, *good, shifted]) + "\n")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units=UNITS)
    assert located(exc, None, 3) and exc.value.message.startswith("line 4 has 6 values but the header names 7 columns")
    path.write_text("\n".join([head, *good, "30.0 -20.0 4500 14.0 6.0 2500 c"]) + "\n")
    np.testing.assert_allclose(bl.load_campaign(path, units=UNITS).landing.values, scaled(LAND), rtol=1e-12)


# --- item 3: decimal commas ---------------------------------------------------------------------

def test_thousands_dot_in_a_decimal_comma_file_is_refused(tmp_path):
    comma = lambda x: repr(x).replace(".", ",")  # noqa: E731
    lines = rows(sep=";", fmt=comma)
    lines[2] = lines[2].replace("4500,0", "4.500")
    path = write(tmp_path / "eu.csv", lines, sep=";")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units=UNITS)
    assert located(exc, "w0", 3, line=4) and "'4.500' is ambiguous" in exc.value.message
    path = write(tmp_path / "eu_ok.csv", rows(sep=";", fmt=comma), sep=";")
    np.testing.assert_allclose(bl.load_campaign(path, units=UNITS).landing.values, scaled(LAND), rtol=1e-12)


def test_mixed_decimal_marks_and_lone_thousands_comma_are_refused(tmp_path):
    lines = rows(sep=";")
    lines[1] = lines[1].replace("12.2", "12,2")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(write(tmp_path / "mix.csv", lines, sep=";"), units=UNITS)
    assert located(exc, "vx0", 2, line=3)  # 12,2 after the file's 20.1
    assert exc.value.message.startswith("'12,2' writes its decimals differently from '20.1' (column 'vx0', row 1)")
    lines = rows(sep="\t", fmt=lambda x: f"{x:.0f}")
    lines[0] = lines[0].replace("3000", "3,000")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(write(tmp_path / "k.tsv", lines, sep="\t"), units=UNITS)
    assert located(exc, "w0", 1, line=2) and "'3,000' is ambiguous" in exc.value.message


# --- item 3: setting labels ----------------------------------------------------------------------

def test_long_numeric_setting_ids_stay_exact(tmp_path):
    ids17 = ("12345678901234567", "12345678901234568", "12345678901234568")
    ds = bl.load_campaign(write(tmp_path / "id17.csv", rows(ids17)), units=UNITS)
    assert ds.setting.dtype == np.int64 and ds.setting.values.tolist() == [int(i) for i in ids17]
    ids20 = ("12345678901234567890", "12345678901234567891", "1")
    ds = bl.load_campaign(write(tmp_path / "id20.csv", rows(ids20)), units=UNITS)
    assert ds.setting.values.tolist() == list(ids20)


@pytest.mark.parametrize("label", ["n/a", "NaN", "#N/A", "NA", "null"])
def test_missing_setting_labels_are_errors(tmp_path, label):
    with pytest.raises(DataError) as exc:
        bl.load_campaign(write(tmp_path / "m.csv", rows(("1", label, "2"))), units=UNITS)
    assert located(exc, "setting", 2, line=3) and exc.value.hints == (DROP,) and repr(label) in exc.value.message


def test_make_campaign_keeps_huge_whole_float_settings_from_overflowing():
    ds = make_campaign(scaled(LAND), scaled(LIFT), setting=[1e20, 2e20, 1e20])
    assert (ds.setting.values > 0).all()


# --- item 3: units row against header ------------------------------------------------------------

def test_header_unit_contradicted_by_units_row_is_refused(tmp_path):
    head = ["vx0 [m/s]", "vy0 [m/s]", "w0 [rpm]", "vxF [m/s]", "vyF [m/s]", "wF [rpm]"]
    units_row = ["m/s", "m/s", "rad/s", "m/s", "m/s", "rpm"]
    body = [",".join(repr(float(v)) for v in (*a, *b)) for a, b in zip(LAND, LIFT, strict=True)]
    path = tmp_path / "u.csv"
    path.write_text("\n".join([",".join(head), ",".join(units_row), *body]) + "\n")
    with pytest.raises(DataError) as e:
        bl.load_campaign(path)
    assert located(e, "w0 [rpm]", None) and "'rpm'" in e.value.message and "'rad/s'" in e.value.message
    units_row[2] = "rev/min"  # the same unit, spelled differently
    path.write_text("\n".join([",".join(head), ",".join(units_row), *body]) + "\n")
    np.testing.assert_allclose(bl.load_campaign(path).landing.values, scaled(LAND), rtol=1e-12)


# --- item 3: Excel hidden sheets ----------------------------------------------------------------

def test_hidden_first_excel_sheet_is_not_the_default(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    path = tmp_path / "hidden.xlsx"
    wb = openpyxl.Workbook()
    old = wb.active
    old.title = "old"
    old.append(HEAD)
    for a, b in zip(LAND, LIFT, strict=True):
        old.append([9, *(a * 2), *(b * 2)])
    old.sheet_state = "hidden"
    new = wb.create_sheet("bounces")
    new.append(HEAD)
    for s, a, b in zip((1, 1, 2), LAND, LIFT, strict=True):
        new.append([s, *a, *b])
    wb.save(path)
    ds = bl.load_campaign(path, units=UNITS)
    np.testing.assert_allclose(ds.landing.values, scaled(LAND), rtol=1e-12)
    assert bl.load_campaign(path, units=UNITS, sheet="old").setting.values.tolist() == [9, 9, 9]


# --- item 3: netCDF units and settings ----------------------------------------------------------

def test_netcdf_table_honours_cf_units(tmp_path):
    ft, u = 0.3048, {}
    data = {}
    for j, name in enumerate(["vx0", "vy0", "w0"]):
        data[name] = LAND[:, j] / ft if j < 2 else LAND[:, j]
        u[name] = "ft s-1" if j < 2 else "rpm"
    for j, name in enumerate(["vxF", "vyF", "wF"]):
        data[name] = LIFT[:, j] if j < 2 else LIFT[:, j] * RPM
        u[name] = "m s-1" if j < 2 else "rad s-1"
    ds = xr.Dataset({k: ("row", v, {"units": u[k]}) for k, v in data.items()})
    path = tmp_path / "cf.nc"
    ds.to_netcdf(path, engine="scipy")
    out = bl.load_campaign(path)
    np.testing.assert_allclose(out.landing.values, scaled(LAND), rtol=1e-12)
    np.testing.assert_allclose(out.liftoff.values, scaled(LIFT), rtol=1e-12)
    ds["w0"].attrs["units"] = "furlong/fortnight"
    ds.to_netcdf(tmp_path / "bad.nc", engine="scipy")
    with pytest.raises(DataError) as e:
        bl.load_campaign(tmp_path / "bad.nc")
    assert located(e, "w0", None)
    assert e.value.message.startswith("the units attribute gives the unit 'furlong/fortnight'")


def test_netcdf_campaign_in_physical_units_is_refused_and_its_setting_variable_kept(tmp_path):
    ds = make_campaign(scaled(LAND), scaled(LIFT), setting=[1, 1, 2])
    phys = ds.copy(deep=True)
    phys["landing"] = phys["landing"] * R
    phys["landing"].attrs["units"] = "m/s"
    phys.to_netcdf(tmp_path / "phys.nc", engine="scipy")
    with pytest.raises(DataError) as e:
        bl.load_campaign(tmp_path / "phys.nc")
    assert located(e, "landing", None) and "'m/s'" in e.value.message
    as_var = ds.reset_coords("setting")
    assert "setting" in as_var.data_vars
    as_var.to_netcdf(tmp_path / "var.nc", engine="scipy")
    assert bl.load_campaign(tmp_path / "var.nc").setting.values.tolist() == [1, 1, 2]
    huge = ds.copy(deep=True)
    huge["landing"][0, 2] = 5000.0  # rad/s: 47 700 rpm
    huge.to_netcdf(tmp_path / "huge.nc", engine="scipy")
    with pytest.raises(DataError) as e:
        bl.load_campaign(tmp_path / "huge.nc")
    assert located(e, "landing", 1) and e.value.hints[0].option == "plausible"  # 47 700 rpm


# --- item 4: non-regular files ------------------------------------------------------------------

@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_fifo_named_csv_is_refused_without_hanging(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    result: list[BaseException] = []

    def load() -> None:
        try:
            bl.load_campaign(fifo)
        except BaseException as exc:
            result.append(exc)

    t = threading.Thread(target=load, daemon=True)
    t.start()
    t.join(10)
    assert not t.is_alive(), "load_campaign hung on a FIFO"
    assert isinstance(result[0], DataError) and result[0].file == str(fifo) and "named pipe" in result[0].message


def test_symlink_to_dev_zero_is_refused(tmp_path):
    if not os.path.exists("/dev/zero"):
        pytest.skip("no /dev/zero")
    link = tmp_path / "zero.csv"
    link.symlink_to("/dev/zero")
    with pytest.raises(DataError) as e:
        bl.load_campaign(link)
    assert e.value.file == str(link) and "character device" in e.value.message


def test_unreadable_file_is_a_data_error(tmp_path):
    path = write(tmp_path / "locked.csv", rows())
    path.chmod(0)
    if os.access(path, os.R_OK):
        pytest.skip("running as root: permissions are not enforced")
    with pytest.raises(DataError) as e:
        bl.load_campaign(path, units=UNITS)
    assert e.value.file == str(path) and "permission denied" in e.value.message




# --- item 4: a damaged .mat file must not kill the process --------------------------------------

def test_mat_file_that_crashes_scipy_is_a_data_error(tmp_path):
    import scipy.io

    rng = np.random.default_rng(0)
    base = tmp_path / "base.mat"
    scipy.io.savemat(base, {"vx0": rng.normal(size=6), "vy0": -rng.random(6),
                            "setting": np.array(["a", "b", "c", "a", "b", "c"], dtype=object),
                            "S": {"w0": rng.normal(size=6)}}, do_compression=False)
    raw = bytearray(base.read_bytes())
    raw[552] = 63  # found by fuzzing: one byte in a data-type tag; scipy.io.loadmat segfaults
    bad = tmp_path / "bad.mat"
    bad.write_bytes(bytes(raw))
    with pytest.raises(DataError) as e:
        bl.load_campaign(bad)
    assert e.value.file == str(bad) and "(signal SIGSEGV)" in e.value.message


# --- items 6 and 7: save_campaign -----------------------------------------------------------------

def test_save_campaign_keeps_mode_and_symlink(tmp_path):
    ds = make_campaign(scaled(LAND), scaled(LIFT), setting=[1, 1, 2])
    real = tmp_path / "real.nc"
    real.write_bytes(b"old")
    real.chmod(0o644)
    link = tmp_path / "link.nc"
    link.symlink_to(real)
    bl.save_campaign(ds, link, engine="scipy")
    assert link.is_symlink() and (real.stat().st_mode & 0o777) == 0o644
    new = bl.save_campaign(ds, tmp_path / "new.nc", engine="scipy")
    umask = os.umask(0)
    os.umask(umask)
    assert (new.stat().st_mode & 0o777) == 0o666 & ~umask


@pytest.mark.parametrize("engine", ["scipy", None])
def test_save_campaign_round_trips_settings_beyond_int32(tmp_path, engine):
    ids = ("12345678901234567", "3000000000", "12345678901234567")
    ds = bl.load_campaign(write(tmp_path / "ids.csv", rows(ids)), units=UNITS)
    back = bl.load_campaign(bl.save_campaign(ds, tmp_path / "ids.nc", engine=engine))
    assert back.setting.dtype == np.int64 and back.setting.values.tolist() == [int(i) for i in ids]


# --- item 7: damaged files give DataError, never another exception --------------------------------

@pytest.mark.parametrize("suffix", [".xlsx", ".nc", ".csv", pytest.param(".mat", marks=pytest.mark.slow)])
def test_damaged_files_give_data_errors_or_the_same_values(tmp_path, suffix):
    ds = make_campaign(scaled(LAND), scaled(LIFT), setting=[1, 1, 2])
    good = tmp_path / f"good{suffix}"
    kwargs = {}
    if suffix == ".nc":
        bl.save_campaign(ds, good, engine="scipy")
    elif suffix == ".xlsx":
        pytest.importorskip("openpyxl")
        pd_ = pytest.importorskip("pandas")
        pd_.DataFrame(np.column_stack([[1, 1, 2], LAND, LIFT]), columns=HEAD).to_excel(good, index=False)
        kwargs = {"units": UNITS}
    elif suffix == ".mat":  # scipy's reader can segfault on a damaged file: the loader contains that
        from scipy.io import savemat

        savemat(good, dict(zip(HEAD, np.column_stack([[1, 1, 2], LAND, LIFT]).T, strict=True)))
        kwargs = {"units": UNITS}
    else:
        write(good, rows())
        kwargs = {"units": UNITS}
    expected = bl.load_campaign(good, **kwargs)
    raw = good.read_bytes()
    rng = np.random.default_rng(7)
    for k in range(15 if suffix == ".mat" else 40):  # a .mat load runs in a child interpreter (~0.4 s)
        b = bytearray(raw)
        for pos in rng.integers(0, len(b), size=1 + k % 3):
            b[pos] = int(rng.integers(0, 256))
        bad = tmp_path / f"bad{k}{suffix}"
        bad.write_bytes(bytes(b))
        try:
            got = bl.load_campaign(bad, **kwargs)
        except DataError:
            continue
        if suffix == ".xlsx":  # zip members carry CRCs: a damaged workbook cannot load other numbers
            np.testing.assert_array_equal(got.landing.values, expected.landing.values)
            np.testing.assert_array_equal(got.liftoff.values, expected.liftoff.values)
        else:  # a changed digit is a different, readable file: it must still be a plausible campaign
            assert implausibility(got.landing.values, got.liftoff.values) is None
            assert validate_campaign(got).landing.shape == got.landing.shape


# --- arguments of load_campaign: a wrong type or unit is refused, never taken as metres ------------------

@pytest.mark.parametrize("radius", [True, "0.02", b"0.02", None, -0.02, float("nan"), 21.35, 2.135])
def test_ball_radius_that_is_no_ball_radius_in_metres_is_refused(tmp_path, radius):
    good = write(tmp_path / "good.csv", rows())
    with pytest.raises(DataError, match="ball_radius_m"):
        bl.load_campaign(good, units=UNITS, ball_radius_m=radius)
    with pytest.raises(DataError, match="ball_radius_m"):
        bl.load_campaign("A", ball_radius_m=radius)


def test_ball_radius_in_metres_scales_the_velocities(tmp_path):
    good = write(tmp_path / "good.csv", rows())
    golf = bl.load_campaign(good, units=UNITS)
    tennis = bl.load_campaign(good, units=UNITS, ball_radius_m=0.0335)
    np.testing.assert_allclose(tennis.landing.values[:, :2] * 0.0335, golf.landing.values[:, :2] * R)


def test_plausible_must_be_ranges(tmp_path):
    good = write(tmp_path / "good.csv", rows())
    with pytest.raises(bl.ParameterError, match=r"plausible must be a PlausibleRanges.*widened"):
        bl.load_campaign(good, units=UNITS, plausible=None)


# --- fuzz campaign rerun: commented-out rows with trailing separators, thousands dots, Latin-1 "…" ---------

@pytest.mark.parametrize("row", ["#N/A,16,-9,1620,7,3,-750,", "#N/A,16,-9,1620,7,3", "#N/A,16,-9,1620,7,3,-750,1",
                                 "%1,16,-9,1620,7,3"])
def test_commented_out_rows_near_the_header_width_are_refused(tmp_path, row):
    path = tmp_path / "t.csv"
    path.write_text(",".join(HEAD) + ",\n" + "\n".join(r + "," for r in rows()) + "\n" + row + "\n")
    with pytest.raises(DataError) as exc:  # refused as data, never skipped as a comment
        bl.load_campaign(path, units=UNITS)
    assert exc.value.row == 4 and "line 5" in exc.value.message


def test_a_comment_that_is_no_row_is_still_skipped(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text(",".join(HEAD) + "\n" + "\n".join(rows()) + "\n# measured by K. J., 2026\n")
    assert bl.load_campaign(path, units=UNITS).sizes["bounce"] == 3


def test_thousands_dot_in_a_semicolon_file_is_refused(tmp_path):
    path = tmp_path / "t.csv"
    lines = [";".join(HEAD), "1;15;-8;1.500;6;3;-800", "2;18;-10;2500;9;4;300"]
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units=UNITS)
    assert located(exc, "w0", 1, line=2) and "'1.500' is ambiguous" in exc.value.message
    path.write_text("\n".join([";".join(HEAD), "1;15;-8;1500;6;3;-800", "2;18;-10;2500;9.5;4;300"]) + "\n")
    assert bl.load_campaign(path, units=UNITS).sizes["bounce"] == 2


def test_latin1_ellipsis_does_not_split_a_line(tmp_path):
    path = tmp_path / "t.csv"
    body = "\n".join([",".join(HEAD), *rows()]) + "\n"
    path.write_bytes("# notes: wet turf\x85 see log\n".encode("latin-1") + body.encode("latin-1"))
    assert bl.load_campaign(path, units=UNITS).sizes["bounce"] == 3


def test_campaign_file_with_numbers_only_damage_makes_is_refused(tmp_path):
    """A damaged netCDF-3 file can hold spins of 1e-150: a campaign file gets the lower limits too."""
    ds = bl.load_campaign("A")
    tiny = ds.copy(deep=True)
    tiny["landing"].values[:, 2] *= 1e-150
    tiny["liftoff"].values[:, 2] *= 1e-150
    path = bl.save_campaign(tiny, tmp_path / "damaged.nc")
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path)
    assert exc.value.file == str(path) and exc.value.column == "omega0" and exc.value.hints[0].option == "plausible"
    assert bl.load_campaign(bl.save_campaign(ds, tmp_path / "good.nc")).sizes["bounce"] == 330


def test_make_campaign_takes_the_same_ball_radius_check():
    land, lift = scaled(LAND), scaled(LIFT)
    for radius in (21.35, True, "0.02135"):
        with pytest.raises(DataError, match="ball_radius_m"):
            make_campaign(land, lift, ball_radius_m=radius)
    assert make_campaign(land, lift, ball_radius_m=0.0335).attrs["ball_radius_m"] == 0.0335
