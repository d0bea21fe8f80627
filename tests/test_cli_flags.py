"""Issue 22: a command line that speaks its own flags.

``predict --input`` reads columns by name (Cartesian or speed, angle, spin; units from the header, a
units row or the flags) and ``-`` for standard input; law-name errors tell a missing module from a
missing class and name ``--import``; ``track`` refuses a bad ``--fps`` at parse time naming it, blames
implausible tracked states on the frame rate, refuses an invalid or catastrophic ``--pattern`` (exit
2) and an ``--out`` that cannot be written (exit 2, before tracking and on the final write).
"""

from __future__ import annotations

import io
import json
import signal
import sys
import time
import uuid

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_FIT, EXIT_OK, EXIT_USAGE
from bouncelab.core import units
from bouncelab.core.errors import DataError

PUB = ["predict", "Rigid", "--published", "A"]
LAW = bl.Rigid.published("A")


def run(capsys, *argv):
    try:
        code = main(list(argv))
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def rows_of(out: str) -> np.ndarray:
    return np.array([[float(v) for v in line.split()[:6]] for line in out.splitlines() if not line.startswith("#")])


# ----------------------------------------------------------------------------------------------- predict --input
POLAR = np.array([[28.5, 37.3, 2094.0], [10.0, 60.0, -500.0], [40.0, 20.0, 6000.0]])  # m/s, deg, rpm


def polar_file(path, header="speed,angle,spin", units_row="m/s,deg,rpm", order=(0, 1, 2)):
    lines = [header] + ([units_row] if units_row else [])
    lines += [",".join(f"{r[k]:g}" for k in order) for r in POLAR]
    path.write_text("\n".join(lines) + "\n")
    return path


def expected_polar() -> tuple[np.ndarray, np.ndarray]:
    """The landings and lift-offs of POLAR as speed [m/s], angle [deg], spin [rpm]."""
    landing = units.landing_from_speed_angle_spin(POLAR[:, 0], POLAR[:, 1], POLAR[:, 2])
    liftoff = units.polar_from_state(LAW.predict(landing), kind="liftoff", speed_unit="m/s", spin_unit="rpm")
    return units.polar_from_state(landing, kind="landing", speed_unit="m/s", spin_unit="rpm"), liftoff


def test_a_speed_angle_spin_header_is_read_by_name_and_printed_in_its_units(tmp_path, capsys):
    """The issue's file: a 'speed,angle,spin' header was read as xdot, ydot, omega ('landing ydot must be
    negative ... got 1873.5')."""
    code, out, err = run(capsys, *PUB, "--input", str(polar_file(tmp_path / "shots.csv")))
    assert code == EXIT_OK, err
    assert "# speed0[m/s] angle0[deg] spin0[rpm] -> speedF[m/s] angleF[deg] spinF[rpm] regime" in out
    got = rows_of(out)
    p0, pf = expected_polar()
    np.testing.assert_allclose(got[:, :3], POLAR, rtol=1e-5)  # the landings as given
    np.testing.assert_allclose(got[:, :3], p0, rtol=1e-5)
    np.testing.assert_allclose(got[:, 3:], pf, rtol=1e-5)
    assert (got[:, 4] > 0).all()  # lift-off angles above the horizontal
    regimes = [line.split()[-1] for line in out.splitlines() if not line.startswith("#")]
    assert regimes == list(LAW.regime(units.landing_from_speed_angle_spin(*POLAR.T)))


def test_columns_in_any_order_units_in_the_header_or_from_flags(tmp_path, capsys):
    want = run(capsys, *PUB, "--input", str(polar_file(tmp_path / "a.csv")))[1]
    shuffled = polar_file(tmp_path / "b.csv", header="spin [rpm],speed [m/s],angle [deg]", units_row=None,
                          order=(2, 0, 1))
    assert run(capsys, *PUB, "--input", str(shuffled))[1] == want
    bare = polar_file(tmp_path / "c.csv", units_row=None)
    assert run(capsys, *PUB, "--input", str(bare), "--velocity-unit", "m/s", "--spin-unit", "rpm")[1] == want
    # angles in radians, said by the flag (without it they are refused as looking like radians)
    rad = tmp_path / "d.csv"
    rad.write_text("speed,angle,spin\n" + "".join(f"{s},{float(np.deg2rad(a))!r},{w}\n" for s, a, w in POLAR))
    code, _, err = run(capsys, *PUB, "--input", str(rad), "--velocity-unit", "m/s", "--spin-unit", "rpm")
    assert code == EXIT_DATA and "--angle-unit rad" in err and "'angle'" in err
    code, out, _ = run(capsys, *PUB, "--input", str(rad), "--velocity-unit", "m/s", "--spin-unit", "rpm",
                       "--angle-unit", "rad")
    assert code == EXIT_OK and "angle0[rad]" in out
    got = rows_of(out)
    np.testing.assert_allclose(got[:, 1], np.deg2rad(POLAR[:, 1]), rtol=1e-5)
    np.testing.assert_allclose(got[:, 4], np.deg2rad(rows_of(want)[:, 4]), rtol=1e-5)


def test_cartesian_names_with_a_units_row(tmp_path, capsys):
    f = tmp_path / "lab.csv"
    f.write_text("Landings 2026-03-14\nshot,vx0,vy0,w0,club\n,m/s,m/s,rpm,\n1,20,-15,3000,7i\n2,12,-6,-500,PW\n")
    code, out, err = run(capsys, *PUB, "--input", str(f))
    assert code == EXIT_OK, err
    assert "# xdot0[m/s] ydot0[m/s] omega0[rpm] -> xdotF[m/s] ydotF[m/s] omegaF[rpm] regime" in out
    got = rows_of(out)
    landing = units.to_scaled([[20, -15, 3000], [12, -6, -500]], velocity="m/s", spin="rpm")
    np.testing.assert_allclose(got[:, :3], [[20, -15, 3000], [12, -6, -500]], rtol=1e-5)
    np.testing.assert_allclose(got[:, 3:], units.from_scaled(LAW.predict(landing), velocity="m/s", spin="rpm"),
                               rtol=1e-5)


def test_input_dash_reads_standard_input(tmp_path, capsys, monkeypatch):
    text = polar_file(tmp_path / "shots.csv").read_bytes()
    want = run(capsys, *PUB, "--input", str(tmp_path / "shots.csv"))[1]
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text)))
    code, out, err = run(capsys, *PUB, "--input", "-")
    assert code == EXIT_OK, err
    assert out == want
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"speed,angle,spin\nm/s,deg,rpm\n28.5,x,2094\n")))
    code, _, err = run(capsys, *PUB, "--input", "-")
    assert code == EXIT_DATA and "'<stdin>'" in err and "column 'angle'" in err and "line 3" in err


@pytest.mark.parametrize(
    ("text", "argv", "code", "needles"),
    [
        # a bad cell: the file, the column and the line
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,37.3,2094\n10,sixty,-500\n", [], EXIT_DATA,
         ["column 'angle'", "line 4", "'sixty'"]),
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,,2094\n", [], EXIT_DATA, ["column 'angle'", "line 3", "empty cell"]),
        # a landing that does not come down
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,120,2094\n", [], EXIT_DATA, ["column 'angle'", "line 3", "120"]),
        ("vx0,vy0,w0\n1000,800,200\n", [], EXIT_DATA, ["column 'vy0'", "line 2", "negative"]),
        # a grazing angle that looks like radians, refused as for --speed-angle-spin
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,37.3,2094\n10,3,-500\n", [], EXIT_DATA,
         ["column 'angle'", "row 2", "3 degrees"]),
        # names that say nothing, lift-offs only, a form half given, two columns for one thing
        ("a,b,c\n1,2,3\n", [], EXIT_DATA, ["['a', 'b', 'c']", "speed, angle, spin"]),
        ("xdotF,ydotF,omegaF\n1,2,3\n", [], EXIT_DATA, ["lift-off", "only landings"]),
        ("speed,ydot,spin\n10,-5,100\n", [], EXIT_DATA, ["xdot", "angle"]),
        ("vx,xdot0,vy,spin\n1,1,-1,1\n", [], EXIT_DATA, ["'vx'", "'xdot0'"]),
        # a unit given twice, differently
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,37.3,2094\n", ["--velocity-unit", "ft/s"], EXIT_DATA,
         ["the velocity unit given is ft/s", "give --velocity-unit m/s"]),
        # typed landings beside a file in other units: one unit for all, said with the flag
        ("speed,angle,spin\nm/s,deg,rpm\n28.5,37.3,2094\n", ["--landing", "1000", "-800", "200"], EXIT_USAGE,
         ["--velocity-unit m/s"]),
        # separators mixed under a header
        ("vx,vy,spin\n20,-15,3000\n30;-10;-500\n", ["--velocity-unit", "m/s", "--spin-unit", "rpm"], EXIT_DATA,
         ["line 3", "';'"]),
        # no header: three numbers a line, as before; a positive ydot0 says a header would help
        ("28.5 37.3 2094\n", [], EXIT_DATA, ["line 1", "ydot0", "speed,angle,spin"]),
    ],
)
def test_input_errors_name_the_file_column_and_line(tmp_path, capsys, text, argv, code, needles):
    f = tmp_path / "in.csv"
    f.write_text(text)
    got, _, err = run(capsys, *PUB, "--input", str(f), *argv)
    assert got == code, err
    assert len([line for line in err.splitlines() if line.startswith("bouncelab predict:")]) == 1, err
    for needle in [*needles, "in.csv"] if code == EXIT_DATA else needles:
        assert needle in err, (needle, err)


def test_read_landings_in_python(tmp_path):
    from bouncelab.data.io.landings import read_landings

    got = read_landings(polar_file(tmp_path / "s.csv"))
    assert got.form == "polar" and got.units == {"velocity": "m/s", "angle": "deg", "spin": "rpm"}
    assert got.unit_origins == {"velocity": "header", "angle": "header", "spin": "header"}
    assert got.columns == ("speed", "angle", "spin")
    np.testing.assert_allclose(got.values, POLAR)
    np.testing.assert_allclose(got.states, units.landing_from_speed_angle_spin(*POLAR.T), rtol=1e-12)
    rows = tmp_path / "r.txt"
    rows.write_text("1000 -800 200\n# note\n900,-700;100\n")
    got = read_landings(rows, units={"spin": "rpm"})
    assert got.form == "rows" and got.units == {"velocity": "radius/s", "spin": "rpm"}
    np.testing.assert_allclose(got.states, units.to_scaled([[1000, -800, 200], [900, -700, 100]],
                                                           velocity="radius/s", spin="rpm"))
    bad = tmp_path / "b.csv"
    bad.write_text("speed,angle,spin\n28.5,37.3,2094\n10,60,x\n")
    with pytest.raises(DataError) as e:
        read_landings(bad)
    assert (e.value.file, e.value.column, e.value.row) == (str(bad), "spin", 2)
    assert "non-numeric value 'x'" in str(e.value) and "line 3" in str(e.value)


def test_polar_output_only_for_polar_input(tmp_path, capsys):
    """The output format of Cartesian input and of --speed-angle-spin is unchanged."""
    code, out, _ = run(capsys, *PUB, "--speed-angle-spin", "28.5", "37.3", "2094", "--velocity-unit", "m/s",
                       "--spin-unit", "rpm")
    assert code == EXIT_OK and "# xdot0[m/s] ydot0[m/s] omega0[rpm] ->" in out
    f = polar_file(tmp_path / "s.csv")
    code, out, _ = run(capsys, *PUB, "--input", str(f), "--landing", "20", "-15", "3000", "--velocity-unit", "m/s",
                       "--spin-unit", "rpm")
    assert code == EXIT_OK and "# xdot0[m/s] ydot0[m/s] omega0[rpm] ->" in out  # mixed: Cartesian, as the typed
    got = rows_of(out)
    assert len(got) == 4
    np.testing.assert_allclose(got[1:, :3], units.from_scaled(units.landing_from_speed_angle_spin(*POLAR.T),
                                                              velocity="m/s", spin="rpm"), rtol=1e-5)


# ----------------------------------------------------------------------------------------------------- law names
LAW_MODULE = """
import bouncelab as bl


class {cls}(bl.Rigid):
    pass
"""


@pytest.fixture
def law_module(tmp_path, monkeypatch):
    """A module of the user's, defining one law, in the current folder (a fresh name each test)."""
    name = f"cli_laws_{uuid.uuid4().hex[:8]}"
    (tmp_path / f"{name}.py").write_text(LAW_MODULE.format(cls="SpeedRestitution"))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", list(sys.path))
    yield name
    sys.modules.pop(name, None)


def test_fit_tells_a_missing_module_from_a_missing_class(tmp_path, capsys, law_module):
    missing = f"nomodule_{uuid.uuid4().hex[:8]}"
    code, _, err = run(capsys, "fit", f"{missing}:Nope", "A")
    assert code == EXIT_FIT
    assert f"cannot import {missing}" in err and f"--import {missing}" in err and str(tmp_path) in err
    code, _, err = run(capsys, "fit", f"{law_module}:Nope", "A")
    assert code == EXIT_FIT
    assert f"module '{law_module}' was imported, but it defines no bounce law 'Nope'" in err
    assert f"it defines {law_module}:SpeedRestitution" in err
    assert "cannot import" not in err


def test_a_module_that_fails_to_import_is_not_called_missing(tmp_path, capsys, law_module):
    broken = f"cli_broken_{uuid.uuid4().hex[:8]}"
    (tmp_path / f"{broken}.py").write_text("import no_such_package_xyz\n")
    code, _, err = run(capsys, "fit", f"{broken}:Law", "A")
    assert code == EXIT_FIT and "was found, but importing it failed" in err and "no_such_package_xyz" in err
    syntax = f"cli_syntax_{uuid.uuid4().hex[:8]}"
    (tmp_path / f"{syntax}.py").write_text("def (:\n")
    code, _, err = run(capsys, "fit", "Rigid", "A", "--import", syntax)  # a traceback before
    assert code == EXIT_FIT and f"--import {syntax}" in err and "SyntaxError" in err
    code, _, err = run(capsys, "fit", "Rigid", "A", "--import", f"{law_module}.py")
    assert code == EXIT_FIT and "not a module name" in err
    for name in (broken, syntax):
        sys.modules.pop(name, None)


def test_predict_law_file_of_a_user_law_names_import(tmp_path, capsys, law_module):
    law_file = tmp_path / "law.json"
    law_file.write_text(json.dumps({"law": f"{law_module}:SpeedRestitution",
                                    "parameters": {"r": 0.5, "mu": 0.3}}))
    code, _, err = run(capsys, "predict", str(law_file), "--landing", "1000", "-800", "200")
    assert code == EXIT_FIT and f"add --import {law_module}" in err
    code, out, err = run(capsys, "predict", str(law_file), "--landing", "1000", "-800", "200", "--import", law_module)
    assert code == EXIT_OK, err
    want = (1000, -800, 200, *bl.Rigid(r=0.5, mu=0.3).predict([[1000, -800, 200]])[0])
    assert out.splitlines()[-1].split()[:6] == [f"{v:.6g}" for v in want]
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"law": f"{law_module}:Gone", "parameters": {"r": 0.5, "mu": 0.3}}))
    code, _, err = run(capsys, "predict", str(other), "--landing", "1000", "-800", "200", "--import", law_module)
    assert code == EXIT_FIT and "defines no bounce law 'Gone'" in err and "SpeedRestitution" in err
    script = tmp_path / "script.json"  # a law fitted in a script run as the main program
    script.write_text(json.dumps({"law": "__main__:Simple", "parameters": {"r": 0.5, "mu": 0.3}}))
    code, _, err = run(capsys, "predict", str(script), "--landing", "1000", "-800", "200")
    assert code == EXIT_FIT and "--import" in err and "Simple" in err and "script's file name" in err


def test_export_law_file_of_a_user_law_takes_import_as_predict_does(tmp_path, capsys, law_module):
    """export shares predict's law argument: a file naming a user's law says to add --import, and with it exports."""
    law_file = tmp_path / "law.json"
    law_file.write_text(json.dumps({"law": f"{law_module}:SpeedRestitution", "parameters": {"r": 0.5, "mu": 0.3}}))
    code, out, err = run(capsys, "export", str(law_file), "--lang", "js")
    assert code == EXIT_FIT and f"add --import {law_module}" in err and out == ""
    code, out, err = run(capsys, "export", str(law_file), "--lang", "js", "--import", law_module)
    assert code == EXIT_OK, err
    assert "export function predictOne" in out and "SpeedRestitution" in out
    code, _, err = run(capsys, "export", "Rigid", "--lang", "c")  # neither a file nor --published
    assert code == EXIT_USAGE and "bouncelab export Rigid --published A --lang c -o law.h" in err


# ------------------------------------------------------------------------------------------------------- track
@pytest.mark.parametrize("value", ["inf", "nan", "-inf", "1e300", "-5", "0", "30", "1e-300", "fast"])
def test_track_refuses_a_bad_fps_naming_it(tmp_path, capsys, value):
    """`--fps inf` was blamed on "fps from the file name" (exit 3 after reading the clip)."""
    code, _, err = run(capsys, "track", str(tmp_path / "clip.avi"), "--fps", value, "--out", str(tmp_path / "c.nc"))
    assert code == EXIT_USAGE
    assert "argument --fps" in err and "file name" not in err


def test_clip_settings_says_where_a_bad_fps_came_from(tmp_path):
    from bouncelab.tracking import FrameRateError, clip_settings

    with pytest.raises(FrameRateError) as e:
        clip_settings(["s1_r1.avi"], fps=float("inf"))
    assert e.value.source == "argument" and "file name" not in str(e.value)
    with pytest.raises(FrameRateError) as e:
        clip_settings(["s1_r1_0fps.avi"], fps=5000, pattern=r"_(?P<fps>\d+)fps")
    assert e.value.source == "file name"
    got = clip_settings(["s1_r1_300fps.avi", "s2.avi"], fps=5000, pattern=r"_(?P<fps>\d+)fps")
    assert [(s.fps, s.fps_source) for s in got.values()] == [(300.0, "file name"), (5000.0, "argument")]


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    pytest.importorskip("cv2")
    from bouncelab.tracking import render_clip

    d = tmp_path_factory.mktemp("clips")
    path = d / "bounce.npz"
    render_clip((1063.0, -810.0, 219.0), (696.7, 440.6, -696.7), size=(144, 288), radius_px=18.0, n_before=14,
                n_after=14, contact_frames=6.0, seed=3).save(path)
    return path


@pytest.mark.parametrize(("fps", "direction"), [("100", "low"), ("1e6", "high")])
def test_a_wrong_frame_rate_is_blamed_on_fps_not_on_units(tmp_path, capsys, clip, fps, direction):
    """A clip filmed at 5000 frames/s tracked with --fps 100 (or 10^6): the speeds are 50 times too slow (200
    times too fast). The unit guard's message ended with a Python call (bouncelab.core.units.to_scaled). The clip
    is saved without its own frame rate (a disagreeing --fps would be refused against it before tracking)."""
    with np.load(clip) as data:
        entries = {k: data[k] for k in data.files if k != "fps"}
    bare = tmp_path / "bounce.npz"
    np.savez(bare, **entries)
    out = tmp_path / "c.nc"
    code, _, err = run(capsys, "track", str(bare), "--fps", fps, "--out", str(out), "--quiet")
    assert code == EXIT_DATA
    assert f"--fps {float(fps):g}" in err and f"likely too {direction}" in err and "e.g. --fps 5000" in err
    assert "to_scaled" not in err and "plausible=" not in err
    assert not out.exists()


def test_a_frame_rate_from_the_manifest_is_checked_before_tracking(tmp_path, capsys, clip, monkeypatch):
    from bouncelab.tracking import campaign as tracking_campaign

    monkeypatch.setattr(tracking_campaign, "_process_clip", lambda job: pytest.fail("tracked a clip"))
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"clip,fps\n{clip.name},1e300\n")
    code, _, err = run(capsys, "track", str(clip), "--manifest", str(manifest), "--out", str(tmp_path / "c.nc"),
                       "--quiet")
    assert code == EXIT_DATA and "from the manifest (--manifest)" in err and "--fps 5000" in err


@pytest.mark.parametrize(
    ("pattern", "needle"),
    [("(?P<fps", "not a regular expression"), (r"(?P<rate>\d+)fps", "['rate']"), ("bounce", "no named group")],
)
def test_track_refuses_a_pattern_that_cannot_work(tmp_path, capsys, clip, pattern, needle, monkeypatch):
    from bouncelab.tracking import campaign as tracking_campaign

    monkeypatch.setattr(tracking_campaign, "_process_clip", lambda job: pytest.fail("tracked a clip"))
    code, _, err = run(capsys, "track", str(clip), "--pattern", pattern, "--out", str(tmp_path / "c.nc"))
    assert code == EXIT_USAGE and "--pattern" in err and needle in err


def test_a_catastrophic_pattern_is_stopped_not_hung(tmp_path, capsys, monkeypatch):
    """'(a+)+$' on a name of 40 a's backtracks for days; it is refused once it takes PATTERN_SECONDS."""
    from bouncelab.cli import track
    from bouncelab.tracking import campaign as tracking_campaign

    monkeypatch.setattr(track, "PATTERN_SECONDS", 0.2)
    monkeypatch.setattr(tracking_campaign, "_process_clip", lambda job: pytest.fail("tracked a clip"))
    name = tmp_path / ("a" * 40 + ".npz")
    name.write_bytes(b"")  # it exists: the pattern is checked before the clip is read
    start = time.monotonic()
    code, _, err = run(capsys, "track", str(name), "--pattern", r"(?P<setting>(a+)+)$", "--out",
                       str(tmp_path / "c.nc"))
    assert time.monotonic() - start < 5
    assert code == EXIT_USAGE and "takes longer than 0.2 s" in err and name.name in err


def test_the_pattern_time_bound_in_a_child_process_and_with_a_timer_of_the_callers(monkeypatch):
    """Off the main thread or without SIGALRM, the names are searched in a child process that is stopped; on
    the main thread, a timer the caller had set keeps running."""
    import re

    from bouncelab.cli import track
    from bouncelab.cli.main import UsageError

    track._check_pattern_time(re.compile(r"(?P<setting>s\d)"), ["s1.npz", "s2.npz"], seconds=0.2, in_process=False)
    monkeypatch.setattr(track, "CHILD_START_SECONDS", 1.0)
    slow = re.compile(r"(?P<setting>(a+)+)$")
    start = time.monotonic()
    with pytest.raises(UsageError, match=r"takes longer than 0\.2 s on the file name 'a{40}b'"):
        track._check_pattern_time(slow, ["a" * 40 + "b"], seconds=0.2, in_process=False)
    assert time.monotonic() - start < 5
    if not hasattr(signal, "setitimer"):
        return
    previous = signal.signal(signal.SIGALRM, lambda *a: None)
    try:
        signal.setitimer(signal.ITIMER_REAL, 100.0)
        track._check_pattern_time(re.compile(r"(?P<setting>s\d)"), ["s1.npz"], seconds=0.2)
        left = signal.getitimer(signal.ITIMER_REAL)[0]
        assert 90 < left <= 100
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc is Linux's")
def test_track_out_in_a_read_only_folder_is_refused_before_tracking(tmp_path, capsys, clip, monkeypatch):
    """/proc takes no new files, even from root. It was tracked first, then 'data error', exit 3."""
    from bouncelab.tracking import campaign as tracking_campaign

    monkeypatch.setattr(tracking_campaign, "_process_clip", lambda job: pytest.fail("tracked a clip"))
    code, _, err = run(capsys, "track", str(clip), "--out", "/proc/bouncelab-campaign.nc", "--quiet")
    assert code == EXIT_USAGE and "--out" in err and "cannot create a file" in err and "data error" not in err
    code, _, err = run(capsys, "track", str(clip), "--out", str(tmp_path / "c.nc"), "--figures", "/proc", "--quiet")
    assert code == EXIT_USAGE and "--figures" in err


def test_track_out_that_fails_on_the_final_write_is_an_output_error(tmp_path, capsys, clip, monkeypatch):
    import bouncelab.data.io

    def refuse(ds, path, **kwargs):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(bouncelab.data.io, "save_campaign", refuse)
    code, _, err = run(capsys, "track", str(clip), "--out", str(tmp_path / "c.nc"), "--quiet")
    assert code == EXIT_USAGE
    assert "--out" in err and "not saved" in err and "Permission denied" in err and "data error" not in err


def test_fit_save_that_cannot_be_written_keeps_the_writers_reason(tmp_path, capsys, monkeypatch):
    """fit --save words the OutputError the law's to_json raises (path, reason, errno), not a re-read OSError."""
    import errno

    from bouncelab.core.errors import OutputError
    from bouncelab.laws.base import BounceModel

    target = tmp_path / "law.json"
    raised = []

    def full_disk(self, path=None):
        raise OutputError("cannot write", path=path, reason="No space left on device", errno=errno.ENOSPC)

    real = OutputError.__init__

    def spy(self, message, **fields):
        raised.append(fields)
        real(self, message, **fields)

    monkeypatch.setattr(BounceModel, "to_json", full_disk)
    monkeypatch.setattr(OutputError, "__init__", spy)
    code, _, err = run(capsys, "fit", "Rigid", "A", "--save", str(target))
    assert code == EXIT_USAGE and "not saved" in err and "No space left on device" in err
    assert raised[-1] == {"path": str(target), "reason": "No space left on device", "errno": errno.ENOSPC}
