"""Loading what labs write (issue 11, item 1): polar columns, title lines, missing="drop", DataFrames,
and loader errors as data (file, column, row, hints) that Python and the command line word in their own terms."""

from __future__ import annotations

import json
import math
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_OK
from bouncelab.core.errors import DataError, DroppedRowsWarning, Hint
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.core.units import state_from_polar
from bouncelab.data.io import load_campaign, save_campaign

R = 0.02135
RPM = 2 * math.pi / 60
DROP = Hint("missing", "drop", "drops incomplete rows")

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
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert exc.value.column == "angle_in" and exc.value.hints == (Hint("units", {"angle": "rad"}),)
    assert "units={'angle': 'rad'}" in str(exc.value)  # how Python words the hint
    check(load_campaign(path, units={"angle": "rad"}))


def test_angle_unit_on_the_command_line(tmp_path, capsys):
    from bouncelab.cli.main import main
    from bouncelab.cli.messages import EXIT_DATA, EXIT_OK

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
    from bouncelab.laws import load_law

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
    assert needle in exc.value.message  # the convention broken, with the cell as written
    assert (exc.value.column, exc.value.row) == cell and exc.value.message.endswith(f"(line {cell[1] + 1})")


def test_ambiguous_polar_and_cartesian_columns_say_how_to_choose(tmp_path):
    table = {"vx_in (m/s)": CART["vx0 (m/s)"], **POLAR}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "amb.csv", table))
    assert "landing: both Cartesian columns ['vx_in (m/s)'] and polar ones" in exc.value.message
    (hint,) = exc.value.hints
    assert hint.option == "columns"
    assert hint.value["liftoff"] == {"speed": "speed_out (m/s)", "angle": "angle_out (deg)", "spin": "spin_out (rpm)"}
    assert "landing_from_speed_angle_spin" not in str(exc.value)


def test_polar_file_without_phases_shows_the_polar_columns_argument(tmp_path):
    table = {"speed (m/s)": SPEED_IN, "angle (deg)": ANGLE_IN, "spin (rpm)": SPIN_IN,
             **{k: POLAR[k] for k in ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)")}}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "nophase.csv", table))
    (hint,) = exc.value.hints
    assert hint.value["landing"] == {"speed": "<landing speed column>", "angle": "<landing angle column>",
                                     "spin": "<landing spin column>"}
    assert "landing_from_speed_angle_spin" not in str(exc.value)


def test_cartesian_file_with_derived_speeds_reads_the_components(tmp_path):
    table = {**CART, "speed_in (m/s)": SPEED_IN, "landing angle (deg)": ANGLE_IN}
    ds = load_campaign(write(tmp_path / "both.csv", table))
    check(ds)
    assert "source_form" not in ds.attrs


def test_polar_columns_mapping_is_validated(tmp_path):
    path = write(tmp_path / "polar.csv", POLAR)
    with pytest.raises(DataError) as exc:
        load_campaign(path, columns={"landing": {"speed": "speed_in", "angle": "angle_in"},
                                     "liftoff": ["speed_out", "angle_out", "spin_out"]})
    assert (exc.value.file, exc.value.column) == (str(path), None)
    assert "{'speed': ..., 'angle': ..., 'spin': ...}" in exc.value.message  # the mapping it must be


MIXED = {**{k: CART[k] for k in ("vx0 (m/s)", "vy0 (m/s)", "w0 (rpm)")},
         **{k: POLAR[k] for k in ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)")}}
LISTS = {"landing": ["vx0", "vy0", "w0"], "liftoff": ["speed_out", "angle_out", "spin_out"]}


@pytest.mark.parametrize("unit_headers", [False, True])
def test_polar_columns_listed_as_xdot_ydot_omega_are_refused(tmp_path, unit_headers):
    # Before: with bare headers and units= this loaded silently, the lift-off speed of 12 m/s as xdot and its
    # angle of 20 degrees as a ydot of 20 m/s; with unit headers it was refused for "a angle unit, not a
    # velocity unit", which did not say that the list was the mistake. (No angle beyond 90 degrees here: read
    # as 105 m/s, that one tripped the plausible ranges, blaming the velocity unit.)
    angles = np.r_[ANGLE_OUT[:3], 75.0, ANGLE_OUT[4:]]
    table = {**MIXED, "angle_out (deg)": angles}
    if not unit_headers:
        table = {k.split(" ")[0]: v for k, v in table.items()}
    path = write(tmp_path / "mixed.csv", table)
    units = None if unit_headers else {"velocity": "m/s", "spin": "rpm"}
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=units, columns=LISTS)
    speed, angle, spin = ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)") if unit_headers else (
        "speed_out", "angle_out", "spin_out")
    assert exc.value.file == str(path) and exc.value.column == speed and exc.value.row is None
    msg = exc.value.message
    assert msg.startswith(f"the column name {speed!r} says it holds the lift-off speed itself, but the list given for "
                          "'liftoff' reads it as the lift-off xdot")
    assert exc.value.hints == (Hint("columns", {"liftoff": {"speed": speed, "angle": angle, "spin": spin}}),)
    assert "unit" not in msg
    # What it says to pass loads the right numbers.
    ds = load_campaign(path, units=units, columns={
        "landing": LISTS["landing"], "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"}})
    np.testing.assert_allclose(ds["landing"].values, EXP_LANDING, rtol=1e-12)
    np.testing.assert_allclose(ds["liftoff"].values, state_from_polar(np.column_stack([SPEED_OUT, angles, SPIN_OUT]),
                                                                      kind="liftoff"), rtol=1e-12, atol=1e-9)


def test_polar_states_listed_as_xdot_ydot_omega_are_refused_for_their_names(tmp_path):
    # Before: refused only by luck, for "landing ydot must be negative" (the angle of 40 read as 40 m/s up).
    path = write(tmp_path / "polar.csv", {k.split(" ")[0]: v for k, v in POLAR.items()})
    lists = {"landing": ["speed_in", "angle_in", "spin_in"], "liftoff": ["speed_out", "angle_out", "spin_out"]}
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s", "spin": "rpm"}, columns=lists)
    assert exc.value.column == "speed_in"
    assert exc.value.hints == (Hint("columns", {"landing": {"speed": "speed_in", "angle": "angle_in",
                                                            "spin": "spin_in"}}),)
    # One column is enough, and a DataFrame is read the same way.
    df = pd.DataFrame({k.split(" ")[0]: v for k, v in MIXED.items()})
    with pytest.raises(DataError) as exc:
        load_campaign(df, units={"velocity": "m/s", "spin": "rpm"},
                      columns={"landing": LISTS["landing"], "liftoff": ["vx0", "angle_out", "spin_out"]})
    assert exc.value.column == "angle_out" and exc.value.file == "<DataFrame>"
    assert exc.value.hints == (Hint("columns", {"liftoff": {"speed": "<liftoff speed column>", "angle": "angle_out",
                                                            "spin": "spin_out"}}),)


def test_a_polar_mapping_is_trusted_whatever_synonym_its_names_are(tmp_path):
    # Regression (c48881e): docs/data.md's own example, columns={"landing": {"speed": "v_in", ...}}, was refused
    # for "the column name 'v_in (m/s)' says it holds the landing ydot" (v is a ydot stem); it loaded before.
    # A mapping says what each column holds, so it is trusted; a list is still checked (next tests).
    names = ["v_in (m/s)", "a_in (deg)", "w_in (rpm)", "v_out (m/s)", "a_out (deg)", "w_out (rpm)"]
    path = write(tmp_path / "v.csv", dict(zip(names, POLAR.values(), strict=True)))
    check(load_campaign(path, columns={"landing": {"speed": "v_in", "angle": "a_in", "spin": "w_in"},
                                       "liftoff": {"speed": "v_out", "angle": "a_out", "spin": "w_out"}}))
    names = ["v0", "theta0", "w0", "vF", "thetaF", "wF"]
    path = write(tmp_path / "v0.csv", dict(zip(names, POLAR.values(), strict=True)))
    check(load_campaign(path, units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": {"speed": "v0", "angle": "theta0", "spin": "w0"},
                                 "liftoff": {"speed": "vF", "angle": "thetaF", "omega": "wF"}}))
    # Even a strong Cartesian name: the caller said it is the speed (c48881e refused this one too).
    names = ["vx_in", "vy_in", "w_in", "speed_out", "angle_out", "spin_out"]
    path = write(tmp_path / "vx.csv", dict(zip(names, POLAR.values(), strict=True)))
    check(load_campaign(path, units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": {"speed": "vx_in", "angle": "vy_in", "spin": "w_in"},
                                 "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"}}))
    # And a Cartesian mapping of polar-sounding names: xdot, ydot, omega as said.
    names = ["speed_in", "angle_in", "spin_in", "vxF", "vyF", "wF"]
    cart = dict(zip(names, [*CART.values()], strict=True))
    check(load_campaign(write(tmp_path / "c.csv", cart), units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": {"xdot": "speed_in", "ydot": "angle_in", "omega": "spin_in"},
                                 "liftoff": ["vxF", "vyF", "wF"]}))


def test_a_list_of_loose_synonyms_is_still_refused(tmp_path):
    # A list is xdot, ydot, omega: v_in is a ydot name, but a_in is no name at all, so only a list naming a
    # recognised speed or angle is refused (the silent mis-read c48881e closed).
    names = ["speed_in", "a_in", "w_in", "speed_out", "a_out", "w_out"]
    path = write(tmp_path / "l.csv", dict(zip(names, POLAR.values(), strict=True)))
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s", "spin": "rpm"},
                      columns={"landing": ["speed_in", "a_in", "w_in"],
                               "liftoff": {"speed": "speed_out", "angle": "a_out", "spin": "w_out"}})
    assert exc.value.column == "speed_in" and [h.option for h in exc.value.hints] == ["columns"]


def test_columns_the_loader_does_not_recognise_are_taken_as_given(tmp_path):
    # Only names the synonym table gives to the other form are refused: any other name may be either.
    cart = dict(zip("abcdef", CART.values(), strict=True))
    check(load_campaign(write(tmp_path / "c.csv", cart), units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": ["a", "b", "c"], "liftoff": ["d", "e", "f"]}))
    polar = dict(zip(["a", "b", "c", "speed", "angle", "spin"], POLAR.values(), strict=True))  # no phase: unknown
    check(load_campaign(write(tmp_path / "p.csv", polar), units={"velocity": "m/s", "spin": "rpm"}, columns={
        "landing": {"speed": "a", "angle": "b", "spin": "c"},
        "liftoff": {"speed": "speed", "angle": "angle", "spin": "spin"}}))


def test_columns_in_the_wrong_form_on_the_command_line(tmp_path, capsys):
    path = str(write(tmp_path / "mixed.csv", MIXED))
    assert main(["info", path, "--columns", json.dumps(LISTS)]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "--columns '{\"liftoff\": {\"speed\": \"speed_out (m/s)\", \"angle\": \"angle_out (deg)\", " \
           "\"spin\": \"spin_out (rpm)\"}}'" in err and "columns=" not in err


@pytest.mark.parametrize(("cell", "value"), [
    (("spin_in (rpm)", 2), "inf"),
    (("spin_out (rpm)", 3), "-inf"),
    (("spin_in (rpm)", 5), "1e999"),
    (("speed_in (m/s)", 2), "inf"),
    (("speed_out (m/s)", 4), "inf"),
    (("angle_in (deg)", 6), "inf"),
    (("angle_out (deg)", 5), "-inf"),
])
def test_non_finite_polar_values_are_refused_naming_the_cell(tmp_path, cell, value):
    # Before: an infinite speed or spin raised "spin must be finite; got inf (element (1,))" from
    # state_from_polar, with no file, column or row; an infinite angle was "not plausible".
    path = write(tmp_path / "inf.csv", POLAR, cells={cell: value})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    state = "landing" if "_in" in cell[0] else "lift-off"
    unit = cell[0].split("(")[1].rstrip(")")
    assert exc.value.message == (f"{state} {cell[0].split('_')[0]} {value} {unit} is not a finite number; every "
                                 f"bounce needs a finite speed, angle and spin (line {cell[1] + 1})")
    assert exc.value.file == str(path) and exc.value.column == cell[0] and exc.value.row == cell[1]


def test_non_finite_polar_values_from_arrays_are_refused_naming_the_cell(tmp_path):
    import scipy.io

    df = pd.DataFrame(POLAR, index=[f"b{i}" for i in range(6)])
    df.loc["b1", "spin_out (rpm)"] = np.inf
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert (exc.value.column, exc.value.row, exc.value.row_label) == ("spin_out (rpm)", 2, "b1")
    assert exc.value.message.startswith("lift-off spin inf rpm is not a finite number")
    for name in ("spin_in", "speed_in", "angle_in"):  # NaN: a .mat file's missing value
        arrays = {k.split(" ")[0]: np.array(v) for k, v in POLAR.items()}
        arrays[name][2] = np.nan
        scipy.io.savemat(tmp_path / "nan.mat", arrays)
        with pytest.raises(DataError) as exc:
            load_campaign(tmp_path / "nan.mat", units={"velocity": "m/s", "spin": "rpm"})
        assert exc.value.column == name and exc.value.row == 3
        assert exc.value.message.startswith(f"landing {name.split('_')[0]} nan")


def test_a_header_unit_of_another_kind_is_named_with_its_article(tmp_path):
    # Before: "the header gives the unit 'deg', a angle unit, not a velocity unit".
    table = dict(zip(["a (m/s)", "b (deg)", "c (rpm)", "d (m/s)", "e (m/s)", "f (rpm)"], POLAR.values(), strict=True))
    path = write(tmp_path / "units.csv", table)
    polar = {"landing": {"speed": "a", "angle": "b", "spin": "c"}}
    for columns, column, said in (
            ({"landing": ["a", "b", "c"], "liftoff": ["d", "e", "f"]}, "b (deg)", "'deg', an angle unit, not a"),
            ({**polar, "liftoff": {"speed": "d", "angle": "e", "spin": "f"}}, "e (m/s)", "'m/s', a velocity unit, not"),
            ({**polar, "liftoff": {"speed": "d", "angle": "f", "spin": "e"}}, "f (rpm)", "'rpm', a spin unit, not an")):
        with pytest.raises(DataError) as exc:
            load_campaign(path, columns=columns)
        assert exc.value.column == column and said in exc.value.message


# ---------------------------------------------------------------------------
# Title lines and header_row
# ---------------------------------------------------------------------------


def test_title_lines_above_the_header(tmp_path):
    pre = "Bounce test 2026-03-14, turf B\nLab: Loughborough sports ground\n\n"
    ds = load_campaign(write(tmp_path / "titled.csv", POLAR, pre=pre))
    check(ds)
    with pytest.raises(DataError) as exc:  # rows are still counted from the header, lines from the top
        load_campaign(write(tmp_path / "titled.csv", POLAR, pre=pre, cells={("spin_in (rpm)", 2): "x"}))
    assert exc.value.row == 2 and exc.value.message.endswith("(line 6)")
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
        with pytest.raises(DataError) as exc:
            load_campaign(path, header_row=bad)
        assert exc.value.file == str(path) and needle in exc.value.message
    for bad in (0, -1, 2.0, True, "4"):
        with pytest.raises(DataError) as exc:
            load_campaign(path, header_row=bad)
        assert repr(bad) in exc.value.message  # the value refused
    for source, file in ((pd.DataFrame(POLAR), "<DataFrame>"), ("A", None)):  # no header row to choose
        with pytest.raises(DataError) as exc:
            load_campaign(source, header_row=1)
        assert exc.value.file == file and "does not apply" in exc.value.message


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
    with pytest.raises(DataError) as exc:
        load_campaign(path, sheet="Bounces", header_row=2)
    assert exc.value.file == str(path) and "row 2 of sheet 'Bounces' is empty" in exc.value.message
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
    assert exc.value.hints == (DROP,)
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
    assert exc.value.row == 6 and exc.value.message.endswith("(line 7)")


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
    with pytest.raises(DataError) as exc:
        load_campaign(path, missing="skip")
    assert "'skip'" in exc.value.message
    everything = {(k, i): "" for k in ("spin_in (rpm)",) for i in range(1, 7)}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "empty.csv", POLAR, cells=everything), missing="drop")
    assert (exc.value.file, exc.value.row) == (str(tmp_path / "empty.csv"), None)
    assert "every row has a missing value" in exc.value.message


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
    assert (exc.value.column, exc.value.row, exc.value.row_label) == ("w0 (rpm)", 4, "b3")
    assert exc.value.hints == (DROP,)
    with pytest.warns(DroppedRowsWarning, match="row 4 \\(row label 'b3': 'w0 \\(rpm\\)' is NaN\\)"):
        assert load_campaign(df, missing="drop").sizes["bounce"] == 5
    df = pd.DataFrame(CART, index=[f"b{i}" for i in range(6)])
    df.loc["b1", "vy0 (m/s)"] = 3.404
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert (exc.value.column, exc.value.row_label) == ("vy0 (m/s)", "b1") and "3.404 m/s" in exc.value.message
    with pytest.raises(DataError) as exc:
        load_campaign(df, sheet=0)
    assert exc.value.file == "<DataFrame>" and "does not apply" in exc.value.message


def test_dataframe_errors_carry_the_row_label_as_an_attribute(tmp_path):
    # Before: DataError.row_label stayed None for load_campaign(DataFrame), the label only at the end of the
    # message ("... (row label 'shot-2')"); now as predict says it: "row 2 (row label 'shot-2'): ...".
    df = pd.DataFrame(CART, index=[f"shot-{i}" for i in range(1, 7)])
    df.loc["shot-2", "vy0 (m/s)"] = 3.404
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert exc.value.row == 2 and exc.value.row_label == "shot-2" and exc.value.column == "vy0 (m/s)"
    assert str(exc.value) == ("file '<DataFrame>', column 'vy0 (m/s)', row 2 (row label 'shot-2'): landing ydot must "
                              "be negative (y points up, a landing moves down); the file gives 3.404 m/s (a file whose "
                              "y points down needs the column negated)")
    # An integer label is the caller's int; after dropped rows, the label of the row as the frame has it.
    df = pd.DataFrame(CART, index=np.arange(10, 16))
    df.loc[11, "w0 (rpm)"] = np.nan
    df.loc[13, "vy0 (m/s)"] = 3.0
    with pytest.warns(DroppedRowsWarning), pytest.raises(DataError) as exc:
        load_campaign(df, missing="drop")
    assert exc.value.row == 4 and exc.value.row_label == 13 and type(exc.value.row_label) is int
    # Found in a cell, before the numbers (missing value) and in a polar half-width.
    df = pd.DataFrame({**POLAR, **POLAR_PI}, index=[f"b{i}" for i in range(6)])
    df.loc["b4", "angle_in_pi (deg)"] = -1.0
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert exc.value.row == 5 and exc.value.row_label == "b4"
    # A file has no row label.
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "up.csv", CART, cells={("vy0 (m/s)", 2): "3.404"}))
    assert exc.value.row == 2 and exc.value.row_label is None and exc.value.message.endswith("(line 3)")


def test_fit_accepts_a_dataframe(tmp_path):
    csv = load_campaign(write(tmp_path / "cart.csv", CART))
    df = pd.DataFrame(CART)
    a = bl.fit(bl.Rigid, df, seed=1)
    b = bl.fit(bl.Rigid, csv, seed=1)
    assert a.model == b.model
    with pytest.raises(DataError) as exc:
        bl.fit(bl.Rigid, pd.DataFrame({k.split(" ")[0]: v for k, v in CART.items()}))
    assert exc.value.file == "<DataFrame>" and Hint("units", {"velocity": "m/s"}) in exc.value.hints


# ---------------------------------------------------------------------------
# Messages: cells as written, and in the caller's language
# ---------------------------------------------------------------------------


def test_errors_quote_the_cell_as_written_with_its_unit(tmp_path):
    path = write(tmp_path / "up.csv", CART, cells={("vy0 (m/s)", 2): "3.404"})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    msg = exc.value.message
    assert "3.404 m/s" in msg and "159.4" not in msg and exc.value.row == 2
    path = write(tmp_path / "fast.csv", CART, cells={("w0 (rpm)", 3): "30000"})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert exc.value.message.startswith("30000 rpm (unit from header)")


def test_cli_messages_name_flags_and_python_messages_keywords(tmp_path, capsys):
    plain = {k.split(" ")[0]: v for k, v in CART.items()}
    path = write(tmp_path / "bare.csv", plain)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units={"velocity": "m/s"})
    assert exc.value.hints == (Hint("units", {"spin": "rpm"}),)
    assert "pass units={'spin': 'rpm'}" in str(exc.value) and "--spin-unit" not in str(exc.value)
    assert main(["info", str(path), "--velocity-unit", "m/s"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "give --spin-unit rpm" in err and "units=" not in err
    # A missing value points to --missing drop; undetectable columns to --columns JSON.
    gap = write(tmp_path / "gap.csv", POLAR, cells={("spin_in (rpm)", 2): "NA"})
    assert main(["info", str(gap)]) == EXIT_DATA
    assert "give --missing drop (drops incomplete rows)" in capsys.readouterr().err
    odd = write(tmp_path / "odd.csv", {f"c{i}": v for i, v in enumerate(POLAR.values())})
    assert main(["info", str(odd)]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "give --columns '{\"landing\": [" in err and "load_campaign(" not in err and "columns=" not in err
    assert main(["info", str(gap), "--sheet", "x"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "sheet 'x'" in err and "only Excel files have sheets" in err and "sheet=" not in err


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


def test_warnings_point_at_the_caller(tmp_path):
    path = write(tmp_path / "p.csv", POLAR, cells={("spin_in (rpm)", 2): "NA"})
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
        return type("Report", (), {"index": Path(out) / "index.html", "complete": True, "skipped": []})()

    monkeypatch.setattr(rep, "reproduce", fake_reproduce)
    path = write(tmp_path / "lab.csv", POLAR, pre="Lab notes\n1,2\n")
    code = main(["reproduce", "--campaign", "A", "--data", str(path), "--header-row", "3", "--no-figures",
                 "--quiet", "--out", str(tmp_path / "report")])
    assert code == EXIT_OK, capsys.readouterr().err
    assert loaded["A"].sizes["bounce"] == 330  # --header-row applies to the file only
    check(loaded[str(path)])


# ---------------------------------------------------------------------------
# Polar prediction intervals: speed, angle and spin half-widths propagated to xdot, ydot, omega
# ---------------------------------------------------------------------------

# 95 % half-widths of the six bounces above: m/s, degrees, rpm.
SPEED_IN_PI = np.array([0.5, 0.4, 0.6, 0.3, 0.35, 0.45])
ANGLE_IN_PI = np.array([1.0, 0.8, 1.2, 0.5, 0.7, 0.9])
SPIN_IN_PI = np.array([100.0, 120.0, 90.0, 80.0, 60.0, 70.0])
SPEED_OUT_PI = np.array([0.3, 0.25, 0.35, 0.2, 0.3, 0.4])
ANGLE_OUT_PI = np.array([1.5, 2.0, 1.0, 3.0, 2.5, 4.0])
SPIN_OUT_PI = np.array([150.0, 140.0, 160.0, 90.0, 70.0, 80.0])
POLAR_PI = {"speed_in_pi (m/s)": SPEED_IN_PI, "angle_in_pi (deg)": ANGLE_IN_PI, "spin_in_pi (rpm)": SPIN_IN_PI,
            "speed_out_pi (m/s)": SPEED_OUT_PI, "angle_out_pi (deg)": ANGLE_OUT_PI, "spin_out_pi (rpm)": SPIN_OUT_PI}
PROPAGATED = "polar (speed, angle and spin half-widths propagated to first order, speed and angle errors independent)"


def numeric_halfwidths(polar: np.ndarray, hw: np.ndarray, kind: str) -> np.ndarray:
    """Half-widths of xdot, ydot, omega from those of speed (m/s), angle (deg), spin (rpm) of independent
    errors, by differentiating state_from_polar numerically (central differences): sqrt(sum_j (J_ij h_j)^2)."""
    var = np.zeros_like(polar)
    for j, step in enumerate((1e-4, 1e-4, 1e-2)):
        d = np.zeros(3)
        d[j] = step
        jac = (state_from_polar(polar + d, kind=kind) - state_from_polar(polar - d, kind=kind)) / (2 * step)
        var += (jac * hw[:, [j]]) ** 2
    return np.sqrt(var)


EXP_LANDING_PI = numeric_halfwidths(np.column_stack([SPEED_IN, ANGLE_IN, SPIN_IN]),
                                    np.column_stack([SPEED_IN_PI, ANGLE_IN_PI, SPIN_IN_PI]), "landing")
EXP_LIFTOFF_PI = numeric_halfwidths(np.column_stack([SPEED_OUT, ANGLE_OUT, SPIN_OUT]),
                                    np.column_stack([SPEED_OUT_PI, ANGLE_OUT_PI, SPIN_OUT_PI]), "liftoff")


def check_pi(ds, landing=EXP_LANDING_PI, liftoff=EXP_LIFTOFF_PI) -> None:
    check(ds)
    np.testing.assert_allclose(ds["landing_pi"].values, landing, rtol=1e-7)
    np.testing.assert_allclose(ds["liftoff_pi"].values, liftoff, rtol=1e-7)


def test_polar_intervals_are_propagated_to_first_order(tmp_path):
    # Not a tautology: a half-width of the angle in degrees used as radians is 57 times too wide, and cos
    # and sin swapped would change every row (the lift-off angles include 0 and 105 degrees).
    assert not np.allclose(EXP_LIFTOFF_PI[:, 0], EXP_LIFTOFF_PI[:, 1], rtol=0.1)
    ds = load_campaign(write(tmp_path / "pi.csv", {**POLAR, **POLAR_PI}))
    check_pi(ds)
    assert ds.attrs["source_form"] == "landing polar, liftoff polar"
    assert ds.attrs["interval_form"] == f"landing {PROPAGATED}, liftoff {PROPAGATED}"
    # The spin half-width is converted like the spin, never negated (the spins of rows 4-6 are negative).
    np.testing.assert_allclose(ds["landing_pi"].values[:, 2], SPIN_IN_PI * RPM, rtol=1e-15)
    # Saved and loaded back, the intervals and how they were obtained survive.
    save_campaign(ds, tmp_path / "pi.nc")
    again = load_campaign(tmp_path / "pi.nc")
    np.testing.assert_array_equal(again["liftoff_pi"].values, ds["liftoff_pi"].values)
    assert again.attrs["interval_form"] == ds.attrs["interval_form"]


def test_polar_intervals_named_explicitly_and_from_a_dataframe(tmp_path):
    names = ["v_a", "a_a", "w_a", "v_b", "a_b", "w_b", "dv_a", "da_a", "dw_a", "dv_b", "da_b", "dw_b"]
    table = dict(zip(names, [*POLAR.values(), *POLAR_PI.values()], strict=True))
    path = write(tmp_path / "odd.csv", table)
    columns = {"landing": {"speed": "v_a", "angle": "a_a", "spin": "w_a"},
               "liftoff": {"speed": "v_b", "angle": "a_b", "spin": "w_b"},
               "landing_pi": {"speed": "dv_a", "angle": "da_a", "spin": "dw_a"},
               "liftoff_pi": {"speed": "dv_b", "angle": "da_b", "omega": "dw_b"}}
    csv = load_campaign(path, units={"velocity": "m/s", "spin": "rpm"}, columns=columns)
    check_pi(csv)
    assert csv.attrs["interval_form"] == f"landing {PROPAGATED}, liftoff {PROPAGATED}"
    df = load_campaign(pd.DataFrame(table, index=[f"b{i}" for i in range(6)]),
                       units={"velocity": "m/s", "spin": "rpm"}, columns=columns)
    np.testing.assert_array_equal(df["landing_pi"].values, csv["landing_pi"].values)
    np.testing.assert_array_equal(df["liftoff_pi"].values, csv["liftoff_pi"].values)
    check_pi(load_campaign(pd.DataFrame({**POLAR, **POLAR_PI})))  # found from the headers too
    # Only the intervals named are read: without liftoff_pi, no lift-off intervals.
    del columns["liftoff_pi"]
    only = load_campaign(path, units={"velocity": "m/s", "spin": "rpm"}, columns=columns)
    assert "liftoff_pi" not in only and only.attrs["interval_form"] == f"landing {PROPAGATED}"


def test_cartesian_landing_with_polar_liftoff_and_both_intervals(tmp_path):
    cart_pi = {"vx0_pi (m/s)": np.full(6, 0.2), "vy0_pi (m/s)": np.full(6, 0.3), "w0_pi (rpm)": SPIN_IN_PI}
    table = {**{k: CART[k] for k in ("vx0 (m/s)", "vy0 (m/s)", "w0 (rpm)")}, **cart_pi,
             **{k: POLAR[k] for k in ("speed_out (m/s)", "angle_out (deg)", "spin_out (rpm)")},
             **{k: POLAR_PI[k] for k in ("speed_out_pi (m/s)", "angle_out_pi (deg)", "spin_out_pi (rpm)")}}
    landing_pi = np.column_stack([np.full(6, 0.2 / R), np.full(6, 0.3 / R), SPIN_IN_PI * RPM])
    path = write(tmp_path / "mixed.csv", table)
    ds = load_campaign(path)
    check_pi(ds, landing=landing_pi)
    assert ds.attrs["source_form"] == "landing cartesian, liftoff polar"
    assert ds.attrs["interval_form"] == f"landing cartesian, liftoff {PROPAGATED}"
    explicit = load_campaign(path, columns={
        "landing": ["vx0", "vy0", "w0"], "landing_pi": ["vx0_pi", "vy0_pi", "w0_pi"],
        "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"},
        "liftoff_pi": {"speed": "speed_out_pi", "angle": "angle_out_pi", "spin": "spin_out_pi"}})
    check_pi(explicit, landing=landing_pi)


def test_interval_units_from_headers_and_from_the_state_columns(tmp_path):
    ft, rad = 0.3048, math.pi / 180
    table = {**POLAR, "angle_out (rad)": ANGLE_OUT * rad,
             # own units: ft/s, radians, rev/s (rpm / 60)
             "speed_in_pi (ft/s)": SPEED_IN_PI / ft, "angle_in_pi (rad)": ANGLE_IN_PI * rad,
             "spin_in_pi (rev/s)": SPIN_IN_PI / 60,
             # no unit: each has its state column's (m/s; radians, as the lift-off angle says; rpm)
             "speed_out_pi": SPEED_OUT_PI, "angle_out_pi": ANGLE_OUT_PI * rad, "spin_out_pi": SPIN_OUT_PI}
    del table["angle_out (deg)"]
    ds = load_campaign(write(tmp_path / "units.csv", table))
    check_pi(ds)
    assert "speed_in_pi (ft/s): ft/s" in ds.attrs["source_units"]
    # The same half-widths in rpm and degrees read as declared units would be 60 and 57 times off:
    wrong = {**table, "spin_in_pi (rpm)": SPIN_IN_PI / 60}
    del wrong["spin_in_pi (rev/s)"]
    assert not np.allclose(load_campaign(write(tmp_path / "w.csv", wrong))["landing_pi"].values[:, 2],
                           EXP_LANDING_PI[:, 2])


def test_polar_intervals_with_missing_drop(tmp_path):
    path = write(tmp_path / "na.csv", {**POLAR, **POLAR_PI}, cells={("angle_in_pi (deg)", 3): "NA"})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert (exc.value.column, exc.value.row, exc.value.hints) == ("angle_in_pi (deg)", 3, (DROP,))
    with pytest.warns(DroppedRowsWarning, match="'angle_in_pi \\(deg\\)' is 'NA'"):
        ds = load_campaign(path, missing="drop")
    keep = [0, 1, 3, 4, 5]
    np.testing.assert_allclose(ds["landing_pi"].values, EXP_LANDING_PI[keep], rtol=1e-7)


def test_cartesian_half_widths_of_a_polar_state_are_still_read(tmp_path):
    # As before: Cartesian half-widths need no propagation; without a unit they have the speed column's.
    table = {**POLAR, "vx_in_pi": np.full(6, 0.5), "vy_in_pi": np.full(6, 0.4), "spin_in_pi (rpm)": SPIN_IN_PI}
    ds = load_campaign(write(tmp_path / "cart_pi.csv", table))
    np.testing.assert_allclose(ds["landing_pi"].values,
                               np.column_stack([np.full(6, 0.5 / R), np.full(6, 0.4 / R), SPIN_IN_PI * RPM]))
    assert "interval_form" not in ds.attrs


def test_a_lone_spin_half_width_is_ignored_with_a_warning(tmp_path):
    with pytest.warns(UserWarning, match=r"incomplete landing_pi columns \['spin_in_pi \(rpm\)'\]; name all "
                      r"three \(xdot, ydot, omega; or speed, angle, spin\)") as rec:
        ds = load_campaign(write(tmp_path / "spin.csv", {**POLAR, "spin_in_pi (rpm)": SPIN_IN_PI}))
    assert "landing_pi" not in ds and "interval_form" not in ds.attrs
    assert rec[0].filename == __file__


@pytest.mark.parametrize(("cell", "value", "needle"), [
    (("speed_in_pi (m/s)", 2), "-0.4", "prediction-interval half-width -0.4 m/s is negative"),
    (("angle_out_pi (deg)", 5), "-2.5", "prediction-interval half-width -2.5 deg is negative"),
    (("spin_out_pi (rpm)", 1), "-150", "prediction-interval half-width -150 rpm is negative"),
    (("angle_in_pi (deg)", 4), "0.5°", "non-numeric value '0.5°'"),
    (("speed_out_pi (m/s)", 6), "inf", "prediction-interval half-width inf m/s is not a finite number"),
    (("angle_in_pi (deg)", 2), "95", "half-width 95 deg is wider than any plausible angle half-width (90 deg"),
    (("spin_in_pi (rpm)", 3), "25000", "half-width 25000 rpm is wider than any plausible value (20000 rpm)"),
    (("speed_in_pi (m/s)", 2), "200", "the landing xdot half-width propagated from the speed half-width 200 m/s "
     "and the angle half-width 0.8 deg (at speed 24.6 m/s, angle 39.5 deg) is 154.3 m/s, wider than any plausible "
     "value (90 m/s): check the unit of 'speed_in_pi (m/s)'"),
])
def test_bad_polar_half_widths_are_refused_naming_the_cell(tmp_path, cell, value, needle):
    path = write(tmp_path / "bad.csv", {**POLAR, **POLAR_PI}, cells={cell: value})
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert needle in exc.value.message  # the cell as written (x 1.96 for a standard deviation), and why
    assert exc.value.file == str(path) and exc.value.column == cell[0] and exc.value.row == cell[1]
    assert exc.value.message.endswith(f"(line {cell[1] + 1})")


def test_a_propagated_half_width_too_wide_by_its_angle_names_the_angle_column(tmp_path):
    # 80 m/s at 55 degrees is a plausible landing (46 and 66 m/s); an 89 degree half-width of its angle makes
    # the xdot one v sin(a) h_a = 102 m/s, while its speed half-width adds cos(a) * 0.3 m/s.
    table = {**POLAR, **POLAR_PI, "speed_in (m/s)": np.r_[SPEED_IN[:3], 80.0, SPEED_IN[4:]]}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "wide.csv", table, cells={("angle_in_pi (deg)", 4): "89"}))
    assert exc.value.column == "angle_in_pi (deg)" and exc.value.row == 4
    assert "the landing xdot half-width propagated from the speed half-width 0.3 m/s and the angle half-width " \
           "89 deg (at speed 80.0 m/s, angle 55.0 deg) is 101.8 m/s" in exc.value.message
    # The check is the plausible ranges' one: widened on purpose, the same numbers load.
    ds = load_campaign(write(tmp_path / "wide.csv", table, cells={("angle_in_pi (deg)", 4): "89"}),
                       plausible=PLAUSIBLE_RANGES.widened(max_speed=120))
    assert 101.7 < ds["landing_pi"].values[3, 0] * R < 101.9


def test_bad_polar_half_widths_in_a_dataframe_name_the_row_label():
    df = pd.DataFrame({**POLAR, **POLAR_PI}, index=[f"b{i}" for i in range(6)])
    df.loc["b2", "angle_in_pi (deg)"] = -1.0
    with pytest.raises(DataError) as exc:
        load_campaign(df)
    assert (exc.value.column, exc.value.row, exc.value.row_label) == ("angle_in_pi (deg)", 3, "b2")
    assert "half-width -1.0 deg is negative" in exc.value.message


@pytest.mark.parametrize(("drop", "missing"), [
    (["spin_in_pi (rpm)"], "spin"),
    (["angle_in_pi (deg)", "spin_in_pi (rpm)"], "angle and spin"),
    (["speed_in_pi (m/s)"], "speed"),
])
def test_polar_half_widths_for_some_columns_only_are_refused(tmp_path, drop, missing):
    table = {k: v for k, v in {**POLAR, **POLAR_PI}.items() if k not in drop}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "some.csv", table))
    assert f"but none for its {missing}: all three (speed, angle, spin) are needed" in exc.value.message
    (hint,) = exc.value.hints  # the columns= to pass, with a place for each missing column
    for name in drop:
        key = name.split("_")[0]
        assert hint.value["landing_pi"][key] == f"<landing_pi {key} column>"
    assert hint.value["liftoff_pi"] == {"speed": "speed_out_pi (m/s)", "angle": "angle_out_pi (deg)",
                                        "spin": "spin_out_pi (rpm)"}


def test_polar_half_widths_of_a_cartesian_state_are_ignored_with_a_warning(tmp_path):
    # Regression (c48881e): a Cartesian file with a stray polar uncertainty column loaded before and was then
    # refused ("half-widths of the landing speed or angle, but the landing is read from its Cartesian
    # columns"). Nothing to propagate them through: they are left out, with a warning naming them.
    stray = {**{k.split(" ")[0]: v for k, v in CART.items()}, "speed_in_unc": np.full(6, 0.3)}
    names = list(stray)
    stray = {k: stray[k] for k in [*names[:3], "speed_in_unc", *names[3:6]]}  # vx0, vy0, w0, speed_in_unc, ...
    with pytest.warns(UserWarning, match=r"ignoring the landing_pi columns \['speed_in_unc'\]: the landing is read "
                      r"from its Cartesian columns \(xdot, ydot, omega\), and half-widths of its speed or angle "
                      r"\(speed_in_unc\) are propagated only through a polar state; loaded without landing "
                      r"intervals") as rec:
        ds = load_campaign(write(tmp_path / "stray.csv", stray), units={"velocity": "m/s", "spin": "rpm"})
    assert rec[0].filename == __file__  # the caller's line
    check(ds)
    assert "landing_pi" not in ds and "interval_form" not in ds.attrs
    with pytest.warns(UserWarning, match="ignoring the landing_pi columns") as rec:
        check(load_campaign(pd.DataFrame(stray), units={"velocity": "m/s", "spin": "rpm"}))
    assert rec[0].filename == __file__
    # All three of them, with the spin's, are ignored the same way (naming them all).
    table = {**CART, **{k: POLAR_PI[k] for k in ("speed_in_pi (m/s)", "angle_in_pi (deg)", "spin_in_pi (rpm)")}}
    path = write(tmp_path / "cart.csv", table)
    with pytest.warns(UserWarning, match=r"ignoring the landing_pi columns \['speed_in_pi \(m/s\)', 'angle_in_pi "
                      r"\(deg\)', 'spin_in_pi \(rpm\)'\]"):
        ds = load_campaign(path)
    check(ds)
    assert "landing_pi" not in ds
    # Named explicitly, they are still refused: the caller asked for intervals that cannot be had.
    with pytest.raises(DataError) as exc:
        load_campaign(path, columns={"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"],
                                     "landing_pi": {"speed": "speed_in_pi", "angle": "angle_in_pi",
                                                    "spin": "spin_in_pi"}})
    assert (exc.value.file, exc.value.column) == (str(path), None) and exc.value.hints[0].option == "columns"
    assert "the landing is read from Cartesian columns" in exc.value.message
    # Complete Cartesian half-widths of a Cartesian state are read beside polar ones (derived columns, sharing
    # the spin's), as the state is read beside derived speeds and angles.
    cart_pi = {"vx0_pi (m/s)": np.full(6, 0.2), "vy0_pi (m/s)": np.full(6, 0.3)}
    ds = load_campaign(write(tmp_path / "both.csv", {**table, **cart_pi, "speed_in (m/s)": SPEED_IN,
                                                     "angle_in (deg)": ANGLE_IN}))
    np.testing.assert_allclose(ds["landing_pi"].values[:, 0], 0.2 / R)
    assert "interval_form" not in ds.attrs


def test_polar_and_cartesian_half_widths_of_a_polar_state_are_refused(tmp_path):
    table = {**POLAR, **POLAR_PI, "vx_in_pi (m/s)": np.full(6, 0.2)}
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "two.csv", table))
    assert "the landing has both Cartesian half-widths ['vx_in_pi (m/s)'] and polar ones " \
           "['speed_in_pi (m/s)', 'angle_in_pi (deg)']" in exc.value.message
    assert [h.option for h in exc.value.hints] == ["columns"]


def test_half_widths_named_in_the_wrong_form_are_refused(tmp_path):
    # Before: a list of polar half-widths was read as xdot, ydot, omega, a 1 degree half-width as 1 m/s.
    plain = {k.split(" ")[0]: v for k, v in {**POLAR, **POLAR_PI}.items()}
    path = write(tmp_path / "plain.csv", plain)
    states = {"landing": {"speed": "speed_in", "angle": "angle_in", "spin": "spin_in"},
              "liftoff": {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"}}
    units = {"velocity": "m/s", "spin": "rpm"}
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=units, columns={**states, "landing_pi": ["speed_in_pi", "angle_in_pi", "spin_in_pi"]})
    assert exc.value.column == "speed_in_pi"
    assert exc.value.message.startswith(
        "the column name 'speed_in_pi' says it holds a half-width of the landing speed (a prediction interval), but "
        "the list given for 'landing_pi' reads it as the landing xdot half-width")
    assert exc.value.hints == (Hint("columns", {"landing_pi": {"speed": "speed_in_pi", "angle": "angle_in_pi",
                                                               "spin": "spin_in_pi"}}),)
    # A mapping says what its columns hold: Cartesian-sounding names given as speed and angle half-widths are
    # read as such (c48881e refused them; the caller said so explicitly).
    table = {**POLAR, "vx_out_pi (m/s)": SPEED_OUT_PI, "vy_out_pi (deg)": ANGLE_OUT_PI,
             "spin_out_pi (rpm)": SPIN_OUT_PI}
    ds = load_campaign(write(tmp_path / "c.csv", table), columns={
        **states, "liftoff_pi": {"speed": "vx_out_pi", "angle": "vy_out_pi", "spin": "spin_out_pi"}})
    np.testing.assert_allclose(ds["liftoff_pi"].values, EXP_LIFTOFF_PI, rtol=1e-7)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=units, columns={**states, "landing_pi": {"speed": "speed_in_pi"}})
    assert exc.value.column is None and "'landing_pi'" in exc.value.message


def test_half_widths_named_as_states_and_states_as_half_widths_are_refused(tmp_path):
    # Before: the landing read from the half-width columns loaded (the half-widths as a 0.3 m/s landing), and
    # a state named as the half-widths was refused only when its column was also named as the state.
    plain = {k.split(" ")[0]: v for k, v in {**POLAR, **POLAR_PI}.items()}
    path = write(tmp_path / "plain.csv", plain)
    units = {"velocity": "m/s", "spin": "rpm"}
    liftoff = {"speed": "speed_out", "angle": "angle_out", "spin": "spin_out"}
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=units, columns={
            "landing": {"speed": "speed_in_pi", "angle": "angle_in_pi", "spin": "spin_in_pi"}, "liftoff": liftoff})
    assert exc.value.column == "speed_in_pi" and exc.value.file == str(path)
    msg = exc.value.message
    assert "'speed_in_pi' says it holds a half-width of the landing speed (a prediction interval), not the landing " \
           "speed" in msg  # the first of them
    assert [h.option for h in exc.value.hints] == ["columns"]
    # One column is enough, in a list or a mapping, of either form; and the other way round.
    cart = {**{k.split(" ")[0]: v for k, v in CART.items()}, "vx0_err": np.full(6, 0.2), "vy0_err": np.full(6, 0.2),
            "w0_err": SPIN_IN_PI}
    cpath = write(tmp_path / "cart.csv", cart)
    with pytest.raises(DataError) as exc:
        load_campaign(cpath, units=units,
                      columns={"landing": ["vx0", "vy0", "w0_err"], "liftoff": ["vxF", "vyF", "wF"]})
    assert exc.value.column == "w0_err"
    assert "'w0_err' says it holds a half-width of the landing spin (a prediction interval), not the landing " \
           "omega" in exc.value.message
    with pytest.raises(DataError) as exc:
        load_campaign(cpath, units=units, columns={"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"],
                                                   "landing_pi": ["vx0_err", "vy0_err", "w0"]})
    assert exc.value.column == "w0"
    assert "'w0' says it holds the landing spin itself, not the landing omega half-width" in exc.value.message
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=units, columns={
            "landing": {"speed": "speed_in", "angle": "angle_in", "spin": "spin_in"}, "liftoff": liftoff,
            "liftoff_pi": {"speed": "speed_out_pi", "angle": "angle_out_pi", "spin": "spin_out"}})
    assert exc.value.column == "spin_out"
    assert "'spin_out' says it holds the lift-off spin itself, not the lift-off spin half-width" in exc.value.message


@pytest.mark.parametrize(("header", "unit"), [
    ("speed_in_pi (%)", "%"), ("speed_in_pi [%]", "%"), ("speed_in_pi_%", "%"), ("speed_in_pi (percent)", "percent"),
    ("speed_in_pi [pct]", "pct"), ("angle_in_pi (%)", "%"), ("spin_in_pi_%", "%"), ("spin_in_pi (rel)", "rel"),
])
def test_relative_half_widths_are_refused(tmp_path, header, unit):
    # Before: '(%)', '[%]' and '_%' were dropped with the rest of the name's punctuation, and the half-width of
    # 2 (per cent) read as 2 m/s (2 deg, 2 rpm), in the unit of its value.
    polar_pi = {k: v for k, v in POLAR_PI.items() if not k.startswith(header.split("_")[0] + "_in_pi")}
    table = {**POLAR, header: np.full(6, 2.0), **polar_pi}
    path = write(tmp_path / "rel.csv", table)
    with pytest.raises(DataError) as exc:
        load_campaign(path)
    assert exc.value.file == str(path) and exc.value.column == header and exc.value.row is None
    what = header.split("_")[0]
    assert exc.value.message.startswith(f"the header gives the landing {what} half-width in {unit!r}, a relative "
                                        "unit: bouncelab reads half-widths only in an absolute unit")
    assert "multiplying each half-width in per cent by its value / 100 (2 % of 25 m/s is 0.5 m/s)" in exc.value.message
    # A DataFrame too.
    with pytest.raises(DataError) as exc:
        load_campaign(pd.DataFrame(table))
    assert (exc.value.file, exc.value.column) == ("<DataFrame>", header) and "a relative unit" in exc.value.message


def test_relative_units_of_cartesian_columns_units_rows_and_units_are_refused(tmp_path):
    cart = {k.split(" ")[0]: v for k, v in CART.items()}
    table = {**cart, "vx0_pi (%)": np.full(6, 2.0), "vy0_pi": np.full(6, 0.1), "w0_pi": np.full(6, 50.0)}
    path = write(tmp_path / "c.csv", table)
    with pytest.raises(DataError) as e:
        load_campaign(path, units={"velocity": "m/s", "spin": "rpm"})
    assert e.value.column == "vx0_pi (%)"
    assert e.value.message.startswith("the header gives the landing xdot half-width in '%', a relative unit")
    with pytest.raises(DataError) as e:
        load_campaign(write(tmp_path / "s.csv", {("vx0 (%)" if k == "vx0" else k): v for k, v in cart.items()}),
                      units={"velocity": "m/s", "spin": "rpm"})
    assert e.value.column == "vx0 (%)"
    assert e.value.message.startswith("the header gives the landing xdot in '%', a relative unit: a measured landing "
                                      "xdot needs an absolute unit")
    # Named explicitly, a relative unit as the last word of the name is refused too.
    named = {**cart, "dvx0_pct": np.full(6, 2.0), "dvy0": np.full(6, 0.1), "dw0": np.full(6, 50.0)}
    with pytest.raises(DataError) as e:
        load_campaign(write(tmp_path / "n.csv", named), units={"velocity": "m/s", "spin": "rpm"},
                      columns={"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"],
                               "landing_pi": ["dvx0_pct", "dvy0", "dw0"]})
    assert e.value.column == "dvx0_pct"
    assert e.value.message.startswith("the header gives the landing xdot half-width in 'pct', a relative unit")
    # A units row saying '%' under a half-width (it was "not a known unit", which did not say why).
    lines = (tmp_path / "c.csv").read_text().splitlines()
    header = lines[0].replace("vx0_pi (%)", "vx0_pi")
    units_row = ",".join(["m/s", "m/s", "rpm", "m/s", "m/s", "rpm", "%", "m/s", "rpm"])
    (tmp_path / "u.csv").write_text("\n".join([header, units_row, *lines[1:]]) + "\n")
    with pytest.raises(DataError) as e:
        load_campaign(tmp_path / "u.csv")
    assert e.value.column == "vx0_pi"
    assert e.value.message.startswith("the units row gives the landing xdot half-width in '%', a relative unit")
    # units= cannot say per cent either.
    with pytest.raises(DataError) as e:
        load_campaign(path, units={"velocity": "percent", "spin": "rpm"})
    assert (e.value.file, e.value.column) == (str(path), None) and "'percent', is a relative unit" in e.value.message
    # 'rel' inside a name is not a unit: such a column is taken as named.
    ok = {("v_rel_x" if k == "vx0" else k): v for k, v in cart.items()}
    check(load_campaign(write(tmp_path / "ok.csv", ok), units={"velocity": "m/s", "spin": "rpm"},
                        columns={"landing": ["v_rel_x", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"]}))


def test_polar_interval_names_are_recognised():
    import bouncelab.data.io.names as names

    expect = {"landing_pi.speed": ["speed_in_pi", "PI speed in", "Speed In CI95", "vel_in_err"],
              "landing_pi.angle": ["angle_in_pi", "descent angle hw", "theta0_unc"],
              "liftoff_pi.angle": ["launch angle uncertainty", "angle_out_err"],
              "liftoff_pi.speed": ["launch speed pi", "ballspeed_out_halfwidth"],
              "liftoff_pi.omega": ["launch spin ci"]}
    for role, spellings in expect.items():
        for name in spellings:
            key = names.normalize(name)
            assert (names.role_of(key) or names.role_of(key, polar=True)) == role, name
    # No polar interval name is a Cartesian name of any kind (role_of is asked first).
    for key in names._POLAR_KEYS:
        for m in names._PI_MARKERS:
            assert names.role_of(key + m) is None and names.role_of(m + key) is None, key + m


def test_polar_interval_errors_on_the_command_line(tmp_path, capsys):
    table = {k: v for k, v in {**POLAR, **POLAR_PI}.items() if k != "spin_out_pi (rpm)"}
    path = str(write(tmp_path / "some.csv", table))
    assert main(["info", path]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "but none for its spin" in err and "give --columns '{" in err and "columns=" not in err
    assert '"liftoff_pi": {"speed": "speed_out_pi (m/s)", "angle": "angle_out_pi (deg)", "spin": ' \
           '"<liftoff_pi spin column>"}' in err
    full = str(write(tmp_path / "full.csv", {**POLAR, **POLAR_PI}))
    assert main(["info", full]) == EXIT_OK


# ---------------------------------------------------------------------------
# What an interval column holds: a 95 % half-width, a standard deviation, or a name that does not say
# ---------------------------------------------------------------------------

Z95 = 1.959963984540054
CART_PLAIN = {k.split(" ")[0]: v for k, v in CART.items()}  # vx0, ..., no units in the header
CART_UNITS = {"velocity": "m/s", "spin": "rpm"}
LANDING_HW = {"vx0": np.full(6, 0.2), "vy0": np.full(6, 0.3), "w0": SPIN_IN_PI}
EXP_CART_PI = np.column_stack([np.full(6, 0.2 / R), np.full(6, 0.3 / R), SPIN_IN_PI * RPM])


def with_marker(marker: str, *, before: bool = False) -> dict:
    return {**CART_PLAIN, **{(f"{marker}_{k}" if before else f"{k}_{marker}"): v for k, v in LANDING_HW.items()}}


@pytest.mark.parametrize("marker", ["err", "error", "unc", "uncertainty"])
def test_an_uncertainty_that_could_be_either_kind_is_refused_until_intervals_says(tmp_path, marker):
    path = write(tmp_path / "u.csv", with_marker(marker))
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=CART_UNITS)
    assert exc.value.column == f"vx0_{marker}" and exc.value.file == str(path)
    assert [(h.option, h.value) for h in exc.value.hints] == [("intervals", "sd"), ("intervals", "pi95")]
    as_hw = load_campaign(path, units=CART_UNITS, intervals="pi95")
    as_sd = load_campaign(path, units=CART_UNITS, intervals="sd")
    np.testing.assert_allclose(as_hw["landing_pi"].values, EXP_CART_PI, rtol=1e-12)
    np.testing.assert_allclose(as_sd["landing_pi"].values, Z95 * EXP_CART_PI, rtol=1e-12)
    assert as_hw.attrs["interval_source"] == "landing 95 % half-widths"
    assert as_sd.attrs["interval_source"] == "landing standard deviations x 1.96"
    check(as_sd)  # the states themselves are not scaled


@pytest.mark.parametrize(("marker", "factor"), [("pi", 1.0), ("hw", 1.0), ("ci95", 1.0), ("sd", Z95),
                                                ("std", Z95), ("stdev", Z95), ("sigma", Z95)])
@pytest.mark.parametrize("before", [False, True])
def test_names_that_say_what_they_hold_are_read_so(tmp_path, marker, factor, before):
    ds = load_campaign(write(tmp_path / "n.csv", with_marker(marker, before=before)), units=CART_UNITS)
    np.testing.assert_allclose(ds["landing_pi"].values, factor * EXP_CART_PI, rtol=1e-12)
    assert "standard deviations" in ds.attrs["interval_source"] if factor != 1.0 else \
        ds.attrs["interval_source"] == "landing 95 % half-widths"
    # intervals= agreeing with the name changes nothing; contradicting it is an error naming the column
    same, other = ("sd", "pi95") if factor != 1.0 else ("pi95", "sd")
    again = load_campaign(write(tmp_path / "n.csv", with_marker(marker, before=before)), units=CART_UNITS,
                          intervals=same)
    np.testing.assert_array_equal(again["landing_pi"].values, ds["landing_pi"].values)
    with pytest.raises(DataError) as exc:
        load_campaign(tmp_path / "n.csv", units=CART_UNITS, intervals=other)
    assert exc.value.column in (f"vx0_{marker}", f"{marker}_vx0") and f"({marker!r})" in exc.value.message
    assert exc.value.hints == (Hint("intervals", same, "as the name says"),)


def test_columns_named_in_columns_without_a_marker_follow_intervals(tmp_path):
    table = {**CART_PLAIN, "a": LANDING_HW["vx0"], "b": LANDING_HW["vy0"], "c": LANDING_HW["w0"]}
    path = write(tmp_path / "m.csv", table)
    cols = {"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"], "landing_pi": ["a", "b", "c"]}
    plain = load_campaign(path, units=CART_UNITS, columns=cols)
    np.testing.assert_allclose(plain["landing_pi"].values, EXP_CART_PI, rtol=1e-12)
    sd = load_campaign(path, units=CART_UNITS, columns=cols, intervals="sd")
    np.testing.assert_allclose(sd["landing_pi"].values, Z95 * EXP_CART_PI, rtol=1e-12)
    # an explicit mapping does not make an ambiguous name unambiguous
    table = {**CART_PLAIN, **{f"{k}_err": v for k, v in LANDING_HW.items()}}
    cols["landing_pi"] = ["vx0_err", "vy0_err", "w0_err"]
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "e.csv", table), units=CART_UNITS, columns=cols)
    assert exc.value.column == "vx0_err" and {h.option for h in exc.value.hints} == {"intervals"}


def test_polar_standard_deviations_give_1_96_times_the_propagated_half_widths(tmp_path):
    sds = {k.replace("_pi", "_sd"): v for k, v in POLAR_PI.items()}
    ds = load_campaign(write(tmp_path / "sd.csv", {**POLAR, **sds}))
    check_pi(ds, landing=Z95 * EXP_LANDING_PI, liftoff=Z95 * EXP_LIFTOFF_PI)
    assert ds.attrs["interval_source"] == "landing standard deviations x 1.96, liftoff standard deviations x 1.96"
    assert ds.attrs["interval_form"] == f"landing {PROPAGATED}, liftoff {PROPAGATED}"


def test_intervals_is_validated_and_applies_to_tables_only(tmp_path):
    df = pd.DataFrame(with_marker("err"))
    before = df.copy()
    with pytest.raises(DataError) as exc:
        load_campaign(df, units=CART_UNITS, intervals="95")
    assert "'95'" in exc.value.message
    with pytest.raises(DataError) as exc:
        load_campaign(df, units=CART_UNITS)
    assert exc.value.column == "vx0_err" and {h.option for h in exc.value.hints} == {"intervals"}
    pd.testing.assert_frame_equal(df, before)  # nothing changed by a refused load
    ds = load_campaign(df, units=CART_UNITS, intervals="sd")
    np.testing.assert_allclose(ds["landing_pi"].values, Z95 * EXP_CART_PI, rtol=1e-12)
    with pytest.raises(DataError) as exc:
        load_campaign("A", intervals="sd")
    assert "does not apply to an embedded campaign" in exc.value.message
    save_campaign(ds, tmp_path / "c.nc")
    with pytest.raises(DataError) as exc:
        load_campaign(tmp_path / "c.nc", intervals="pi95")
    assert exc.value.file == str(tmp_path / "c.nc") and "campaign file" in exc.value.message
    np.testing.assert_array_equal(load_campaign(tmp_path / "c.nc")["landing_pi"].values, ds["landing_pi"].values)


def test_intervals_on_the_command_line(tmp_path, capsys):
    path = str(write(tmp_path / "u.csv", with_marker("unc")))
    assert main(["info", path, "--velocity-unit", "m/s", "--spin-unit", "rpm"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "give --intervals sd (standard deviations" in err and "--intervals pi95 (95 % half-widths" in err
    assert "intervals=" not in err
    assert main(["info", path, "--velocity-unit", "m/s", "--spin-unit", "rpm", "--intervals", "sd"]) == EXIT_OK
    out = capsys.readouterr().out
    assert "read from: landing standard deviations x 1.96" in out and "source units: velocity m/s, spin rpm" in out


def test_columns_named_in_columns_say_what_they_hold_by_their_last_or_first_word(tmp_path):
    # Review (stop 19): "a_sd" named in columns= was read as a 95 % half-width, 1.96 times too narrow.
    table = {**CART_PLAIN, "a_sd": LANDING_HW["vx0"], "b_sd": LANDING_HW["vy0"], "sigma c": LANDING_HW["w0"],
             "a_err": LANDING_HW["vx0"], "b_err": LANDING_HW["vy0"], "c_err": LANDING_HW["w0"]}
    path = write(tmp_path / "w.csv", table)
    cols = {"landing": ["vx0", "vy0", "w0"], "liftoff": ["vxF", "vyF", "wF"]}
    ds = load_campaign(path, units=CART_UNITS, columns={**cols, "landing_pi": ["a_sd", "b_sd", "sigma c"]})
    np.testing.assert_allclose(ds["landing_pi"].values, Z95 * EXP_CART_PI, rtol=1e-12)
    with pytest.raises(DataError) as exc:
        load_campaign(path, units=CART_UNITS, columns={**cols, "landing_pi": ["a_err", "b_err", "c_err"]})
    assert exc.value.column == "a_err" and {h.option for h in exc.value.hints} == {"intervals"}


def test_a_standard_deviation_too_wide_is_quoted_with_what_was_checked(tmp_path):
    sds = {**CART_PLAIN, **{f"{k}_sd": v for k, v in LANDING_HW.items()}}
    sds["w0_sd"] = np.full(6, 15000.0)  # rpm: x 1.96 is beyond the plausible 20000 rpm
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "s.csv", sds), units=CART_UNITS)
    assert exc.value.column == "w0_sd" and exc.value.row == 1
    assert exc.value.message.startswith("standard deviation 15000.0 rpm (x 1.96: 29399.5 rpm as a 95 % half-width) "
                                        "is wider than any plausible value (20000 rpm)")  # the number checked
    polar = {**POLAR, **{k.replace("_pi", "_sd"): v for k, v in POLAR_PI.items()}}
    polar["angle_in_sd (deg)"] = np.full(6, 50.0)
    with pytest.raises(DataError) as exc:
        load_campaign(write(tmp_path / "p.csv", polar))
    assert exc.value.column == "angle_in_sd (deg)" and exc.value.row == 1
    assert exc.value.message.startswith("standard deviation 50.0 deg (x 1.96: 97.9982 deg as a 95 % half-width) is "
                                        "wider than any plausible angle half-width")


def test_surrogate_and_intervals_on_the_command_line_of_reproduce(tmp_path, capsys):
    path = str(write(tmp_path / "u.csv", with_marker("unc")))
    units = ["--velocity-unit", "m/s", "--spin-unit", "rpm"]
    # a surrogate with only data files is a usage error, not silently ignored; its message speaks flags
    assert main(["reproduce", "--data", path, *units, "--surrogate", "turf", "--no-figures", "--quiet",
                 "--out", str(tmp_path / "r")]) == 2
    assert "--surrogate turf names which embedded campaigns" in capsys.readouterr().err
    assert main(["info", path, *units, "--surrogate", "turf"]) == EXIT_DATA
    err = capsys.readouterr().err
    assert "surrogate 'turf' names which of the embedded campaigns" in err and "surrogate=" not in err
