"""The command line: happy paths, and errors a shell user can act on."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_FIT, EXIT_OK, EXIT_USAGE
from bouncelab.core import units


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_info(capsys):
    code, out, _ = run(capsys, "info")
    assert code == EXIT_OK
    assert "campaign A: 330 bounces" in out and "campaign B: 693 bounces" in out
    assert "synthetic surrogate" in out and "launcher settings: 55" in out


def test_fit_and_save(capsys, tmp_path):
    path = tmp_path / "law.json"
    code, out, _ = run(capsys, "fit", "PennerFixed", "B", "--save", str(path), "--seed", "2")
    assert code == EXIT_OK
    assert "[[Fit]] PennerFixed" in out and "beta_deg" in out
    law = bl.load_law(path)
    assert law == bl.fit(bl.PennerFixed, bl.load_campaign("B"), seed=2).model
    code, out, _ = run(capsys, "fit", "Rigid", "A", "--json", "--bounds", '{"mu": [0, 0.2]}')
    assert code == EXIT_OK and '"at_bounds"' in out and '"mu": "upper"' in out


def test_predict_published_in_scaled_units(capsys):
    code, out, _ = run(capsys, "predict", "Rigid", "--published", "A", "--landing", "1000", "-800", "200",
                       "--landing", "500", "-300", "900")
    assert code == EXIT_OK
    rows = [line.split() for line in out.splitlines() if not line.startswith("#")]
    got = np.array([[float(v) for v in r[3:6]] for r in rows])
    want = bl.Rigid.published("A").predict([[1000, -800, 200], [500, -300, 900]])
    np.testing.assert_allclose(got, want, rtol=1e-5)
    assert rows[0][6] in ("roll", "slip_forward", "slip_backward")


def test_predict_physical_units_and_file(capsys, tmp_path):
    law_path = tmp_path / "law.json"
    bl.PennerFixed.published("B").to_json(law_path)
    inp = tmp_path / "landings.csv"
    # A header is read as a table (one separator); a file without header takes any separator a line.
    inp.write_text("vx,vy,spin\n20,-15,3000\n# a comment\n30,-10,-500\n")
    rows_file = tmp_path / "rows.txt"
    rows_file.write_text("20 -15 3000\n# a comment\n30;-10,-500\n")
    code, out, _ = run(capsys, "predict", str(law_path), "--input", str(inp), "--velocity-unit", "m/s",
                       "--spin-unit", "rpm")
    assert code == EXIT_OK
    rows = np.array([[float(v) for v in line.split()[:6]] for line in out.splitlines() if not line.startswith("#")])
    scaled = units.to_scaled([[20, -15, 3000], [30, -10, -500]], velocity="m/s", spin="rpm")
    want = units.from_scaled(bl.PennerFixed.published("B").predict(scaled), velocity="m/s", spin="rpm")
    np.testing.assert_allclose(rows[:, 3:], want, rtol=1e-5)
    np.testing.assert_allclose(rows[:, :3], [[20, -15, 3000], [30, -10, -500]], rtol=1e-5)
    code, out_rows, _ = run(capsys, "predict", str(law_path), "--input", str(rows_file), "--velocity-unit", "m/s",
                            "--spin-unit", "rpm")
    assert code == EXIT_OK and out_rows == out


def test_predict_speed_angle_spin(capsys):
    code, out, _ = run(capsys, "predict", "PiecewiseAffine", "--published", "A", "--speed-angle-spin", "93.6", "37.3",
                       "34.9", "--velocity-unit", "ft/s", "--spin-unit", "rev/s")
    assert code == EXIT_OK
    row = [float(v) for v in out.splitlines()[-1].split()[:6]]
    p0 = units.landing_from_speed_angle_spin(93.6, 37.3, 34.9, speed_unit="ft/s", spin_unit="rev/s")
    want = units.from_scaled(bl.PiecewiseAffine.published("A").predict(p0), velocity="ft/s", spin="rev/s")
    np.testing.assert_allclose(row[3:], want, rtol=1e-5)


@pytest.mark.parametrize(
    ("argv", "code", "needle"),
    [
        (["fit", "Rigid", "nonexistent.csv"], EXIT_DATA, "nonexistent.csv"),
        (["fit", "Bouncy", "A"], EXIT_FIT, "unknown law"),
        (["fit", "Rigid", "A", "--bounds", "{mu: 1"], EXIT_USAGE, "JSON"),
        (["fit", "Rigid", "A", "--bounds", '{"r": [0, 2]}'], EXIT_FIT, "physical range"),
        (["fit", "Rigid", "A", "--method", "svm"], EXIT_FIT, "PiecewiseAffine"),
        (["predict", "Rigid", "--published", "A", "--landing", "1000", "5", "0"], EXIT_DATA, "ydot"),
        (["predict", "Rigid", "--published", "A", "--landing", "1", "-1", "0", "--velocity-unit", "knots"],
         EXIT_DATA, "unknown velocity unit"),
        (["predict", "Rigid", "--published", "A"], EXIT_DATA, "give landings"),
        (["predict", "nolaw.json", "--landing", "1", "-1", "0"], EXIT_DATA, "nolaw.json"),
        (["info", "missing.nc"], EXIT_DATA, "missing.nc"),
    ],
)
def test_errors(capsys, argv, code, needle):
    got, _, err = run(capsys, *argv)
    assert got == code
    assert needle in err
    assert "Traceback" not in err


def test_no_command_prints_help(capsys):
    code, out, _ = run(capsys)
    assert code == EXIT_USAGE and "reproduce" in out


@pytest.mark.parametrize(
    "argv",
    [["fit", "Rigid", "A", "--seed", "many"], ["predict", "Rigid", "--published", "C", "--landing", "1", "-1", "0"]],
)
def test_bad_option_is_usage_error(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == EXIT_USAGE
    assert "usage: bouncelab" in capsys.readouterr().err


def test_closed_pipe_is_not_an_error(tmp_path):
    """`bouncelab predict ... | head` must not end in a BrokenPipeError traceback."""
    rows = tmp_path / "many.txt"
    np.savetxt(rows, np.tile([[1000.0, -800.0, 200.0]], (20000, 1)))  # far more output than a pipe holds
    predict = f"{sys.executable} -m bouncelab predict Rigid --published A --input {rows}"
    cmd = f"{predict} | head -n 3; exit ${{PIPESTATUS[0]}}"
    proc = subprocess.run(["bash", "-c", cmd], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert len(proc.stdout.splitlines()) == 3
    assert "Traceback" not in proc.stderr and "BrokenPipe" not in proc.stderr


def test_module_entry_point():
    proc = subprocess.run([sys.executable, "-m", "bouncelab", "--version"], capture_output=True, text=True, check=True)
    assert proc.stdout.strip() == f"bouncelab {bl.__version__}"


@pytest.mark.slow
def test_reproduce_campaign_a(tmp_path, capsys):
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--out", str(tmp_path / "rep"))
    assert code == EXIT_OK
    rep = tmp_path / "rep"
    index = (rep / "index.html").read_text()
    for name in ("fig3_landing_space", "fig6_pi_widths", "fig7_tangential", "fig8_predictions",
                 "fig9_repeatability", "fig10_slices"):
        png = rep / "figures" / f"A_{name}.png"
        assert png.stat().st_size > 10_000
        assert f"figures/A_{name}.png" in index
    table3 = (rep / "tables" / "A_table3.md").read_text()
    assert "(31.9 %)" in table3 and "TangentialRestitution" in table3
    assert "CompliantImpact" in table3 and "TurfContact" in table3  # the physics-based laws beside the paper's
    lever = (rep / "tables" / "A_lever_arm.md").read_text()
    assert all(name in lever for name in ("data", "Rigid", "TurfContact", "centre_fraction"))
    assert (rep / "figures" / "A_lever_arm.png").stat().st_size > 10_000
    assert "(7.27 %)" in (rep / "tables" / "A_table2.md").read_text()
    for law in ("Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine"):
        bl.load_law(rep / "laws" / f"A_{law}.json")
    assert "SIMULATED CAMPAIGN, NOT MEASURED BOUNCES (surrogate &#x27;turf&#x27;)" in index  # the default surrogate
    assert "[ 1/11] loading A" in err and "done" in err
    assert "ci_high" in (rep / "tables" / "A_bootstrap.md").read_text()
    assert "Values in brackets are the paper's published results on its measured bounces" in index
    assert "a reference, not a validation" in index  # the turf surrogate is synthetic
    repeat = (rep / "tables" / "A_repeatability_summary.md").read_text()
    assert "| all | mixed | – | – |" in repeat and "nan" not in repeat
    # Every file is listed in the manifest that lets a later run replace this report, and nothing else is left.
    listed = set(json.loads((rep / ".bouncelab-report.json").read_text())["files"])
    assert listed | {".bouncelab-report.json"} == {p.relative_to(rep).as_posix() for p in rep.rglob("*") if p.is_file()}
    assert [p.name for p in tmp_path.iterdir()] == ["rep"]


@pytest.mark.slow
def test_reproduce_own_file_without_settings(tmp_path, capsys):
    ds = bl.load_campaign("B")
    p0, pf = ds.landing.values[:300], ds.liftoff.values[:300]
    csv = tmp_path / "my_bounces.csv"
    header = "vx0,vy0,w0,vx1,vy1,w1"
    np.savetxt(csv, np.column_stack([p0, pf]), delimiter=",", header=header, comments="")
    code, _, err = run(capsys, "reproduce", "--data", str(csv), "--spin-unit", "rad/s", "--out", str(tmp_path / "rep"),
                       "--no-figures", "--quiet")
    assert code == EXIT_OK and err == ""
    index = (tmp_path / "rep" / "index.html").read_text()
    assert "inferred by clustering" in index
    table3 = (tmp_path / "rep" / "tables" / "my_bounces_table3.md").read_text()
    table2 = (tmp_path / "rep" / "tables" / "my_bounces_table2.md").read_text()
    # Own data: no published values are shown, so no text may say they are.
    for text in (index, table3, table2):
        assert "bracket" not in text.replace("no published values", "")
        assert "(31.9 %)" not in text and "(7.27 %)" not in text
    assert "no published values are shown" in index


@pytest.mark.slow
def test_reproduce_label_puts_paper_values_beside(tmp_path, capsys):
    ds = bl.load_campaign("A")
    csv = tmp_path / "artificial_turf.csv"
    np.savetxt(csv, np.column_stack([ds.landing.values, ds.liftoff.values]), delimiter=",",
               header="vx0,vy0,w0,vx1,vy1,w1", comments="")
    code, _, _ = run(capsys, "reproduce", "--data", str(csv), "--spin-unit", "rad/s", "--label", "A",
                     "--out", str(tmp_path / "rep"), "--no-figures", "--quiet")
    assert code == EXIT_OK
    assert "(31.9 %)" in (tmp_path / "rep" / "tables" / "A_table3.md").read_text()
    code, _, err = run(capsys, "reproduce", "--data", str(csv), "--label", "A", "B", "--out", str(tmp_path / "r2"))
    assert code == EXIT_USAGE and "one --label per --data file" in err


def test_reproduce_bad_file(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("vx0,vy0,w0,vx1,vy1,w1\n100,-200,30,50,60,10\n100,abc,30,50,60,10\n")
    code, _, err = run(capsys, "reproduce", "--data", str(bad), "--out", str(tmp_path / "rep"), "--quiet")
    assert code == EXIT_DATA
    assert "bad.csv" in err and "row 2" in err


def test_predict_ball_radius(capsys):
    """--radius-mm changes the scaling: the same m/s landing is a different scaled landing."""
    argv = ["predict", "Rigid", "--published", "A", "--landing", "20", "-15", "3000", "--velocity-unit", "m/s",
            "--spin-unit", "rpm"]
    rows = []
    for radius in ("21.35", "30"):
        code, out, _ = run(capsys, *argv, "--radius-mm", radius)
        assert code == EXIT_OK
        rows.append([float(v) for v in out.splitlines()[-1].split()[3:6]])
    scaled = units.to_scaled([[20, -15, 3000]], velocity="m/s", spin="rpm", radius_m=0.030)
    want = units.from_scaled(bl.Rigid.published("A").predict(scaled), velocity="m/s", spin="rpm", radius_m=0.030)
    np.testing.assert_allclose(rows[1], want[0], rtol=1e-5)
    assert rows[0] != rows[1]


def test_library_warnings_are_one_line_messages(capsys):
    import warnings

    before = warnings.showwarning
    code = main(["predict", "PennerFixed", "--published", "B", "--landing", "50", "-100", "2000"])
    _, err = capsys.readouterr()
    assert code == EXIT_OK and warnings.showwarning is before  # restored after the command
    assert err.startswith("bouncelab predict: warning: PennerFixed.published('B') predicts non-physical")
    assert len(err.strip().splitlines()) == 1 and "main.py" not in err
