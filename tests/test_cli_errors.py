"""A table of bad command lines: each exits 2, 3 or 4 with a one-line message and no traceback.

2 = bad command line (argparse errors, malformed or ill-shaped JSON options, an --out or --save
that cannot be written), 3 = bad or missing data file, 4 = a law or fit that cannot be done.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_FIT, EXIT_USAGE

LANDING = ["--landing", "1000", "-800", "200"]
PUB = ["predict", "Rigid", "--published", "A"]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("fuzz")
    (d / "numeric_first_bad.txt").write_text("1 x 3\n1000 -800 200\n")  # was silently skipped as a "header"
    (d / "bad_later.txt").write_text("xdot ydot omega\n1000 -800 200\nfoo bar baz\n")
    (d / "two_headers.txt").write_text("xdot ydot omega\nunits: m/s m/s rpm\n1000 -800 200\n")
    (d / "nan.txt").write_text("1000 -800 nan\n")
    (d / "arity.txt").write_text("1000 -800\n")
    (d / "empty.txt").write_text("# only a comment\n")
    (d / "binary.txt").write_bytes(b"\xff\xfe\x00\x81" * 10)
    (d / "bad.json").write_text('{"law": "Rigid", ')
    (d / "two.csv").write_text("a,b\n1,2\n")
    (d / "notes").mkdir()
    (d / "notes" / "mine.txt").write_text("keep me")
    return d


# (argv with {d} for the fixture folder, expected exit code, a piece of the message)
CASES = [
    # malformed or ill-shaped JSON options
    (["fit", "Rigid", "A", "--bounds", "{mu: 1"], EXIT_USAGE, "malformed JSON"),
    (["fit", "Rigid", "A", "--bounds", "[1, 2]"], EXIT_USAGE, "JSON object"),
    (["fit", "Rigid", "A", "--bounds", '{"mu": 5}'], EXIT_USAGE, "[low, high] pair"),
    (["fit", "Rigid", "A", "--bounds", '{"mu": [0, 1, 2]}'], EXIT_USAGE, "[low, high] pair"),
    (["fit", "Rigid", "A", "--bounds", '{"mu": [1, 0]}'], EXIT_FIT, "reversed"),
    (["fit", "Rigid", "A", "--bounds", '{"zz": [0, 1]}'], EXIT_FIT, "no parameter 'zz'"),
    (["fit", "Rigid", "A", "--bounds", '{"mu": [0, NaN]}'], EXIT_FIT, "finite"),
    (["fit", "Rigid", "A", "--columns", "[1]"], EXIT_USAGE, "JSON object"),
    (["info", "{d}/two.csv", "--columns", "{"], EXIT_USAGE, "malformed JSON"),
    # unknown laws, methods, options
    (["fit", "Bouncy", "A"], EXIT_FIT, "unknown law"),
    (["fit", "no_such_module:Law", "A"], EXIT_FIT, "cannot import"),
    (["fit", "Rigid", "A", "--method", "nope"], EXIT_FIT, "unknown method"),
    (["fit", "Rigid", "A", "--objective", "nope"], EXIT_FIT, "unknown objective"),
    (["fit", "Rigid", "A", "--seed", "-1"], EXIT_FIT, "seed"),
    (["fit", "Rigid", "A", "--seed", "many"], EXIT_USAGE, "invalid int"),
    (["predict", "TangentialRestitution", "--published", "A", *LANDING], EXIT_FIT, "publishes no values"),
    (["predict", "Rigid", "--published", "C", *LANDING], EXIT_USAGE, "invalid choice"),
    (["bogus"], EXIT_USAGE, "invalid choice"),
    # missing or bad files
    (["fit", "Rigid", "{d}/missing.csv"], EXIT_DATA, "missing.csv"),
    (["fit", "Rigid", "{d}"], EXIT_DATA, "directory"),
    (["info", "{d}/two.csv"], EXIT_DATA, "two.csv"),
    (["info", "C"], EXIT_DATA, "embedded campaigns"),
    (["predict", "{d}/missing.json", *LANDING], EXIT_DATA, "missing.json"),
    (["predict", "{d}/bad.json", *LANDING], EXIT_FIT, "not a JSON law"),
    (["predict", "{d}", *LANDING], EXIT_DATA, "directory"),
    (["reproduce", "--data", "{d}/missing.nc", "--out", "{d}/r1", "--quiet", "--no-figures"], EXIT_DATA, "missing.nc"),
    (["reproduce", "--campaign", "C", "--out", "{d}/r2", "--quiet", "--no-figures"], EXIT_DATA, "embedded campaigns"),
    # non-numeric, non-finite or wrongly shaped predict input
    ([*PUB, "--input", "{d}/numeric_first_bad.txt"], EXIT_DATA, "line 1"),
    ([*PUB, "--input", "{d}/bad_later.txt"], EXIT_DATA, "line 3"),
    ([*PUB, "--input", "{d}/two_headers.txt"], EXIT_DATA, "line 2"),
    ([*PUB, "--input", "{d}/nan.txt"], EXIT_DATA, "finite"),
    ([*PUB, "--input", "{d}/arity.txt"], EXIT_DATA, "needs 3"),
    ([*PUB, "--input", "{d}/empty.txt"], EXIT_DATA, "no landing rows"),
    ([*PUB, "--input", "{d}/binary.txt"], EXIT_DATA, "binary.txt"),
    ([*PUB, "--input", "{d}/missing.txt"], EXIT_DATA, "missing.txt"),
    ([*PUB, "--landing", "1000", "abc", "200"], EXIT_USAGE, "not a number"),
    ([*PUB, "--landing", "1000", "-800", "nan"], EXIT_USAGE, "finite"),
    ([*PUB, "--landing", "1e400", "-800", "200"], EXIT_USAGE, "finite"),
    ([*PUB, "--landing", "1000", "-800"], EXIT_USAGE, "expected 3"),
    ([*PUB, "--landing", "1000", "-800", "200", "7"], EXIT_USAGE, "unrecognized"),
    ([*PUB, "--landing", "1e300", "-800", "200"], EXIT_DATA, "landing"),
    ([*PUB, "--landing", "1000", "5", "0"], EXIT_DATA, "ydot"),
    ([*PUB], EXIT_DATA, "give landings"),
    (["predict", "Rigid", *LANDING], EXIT_USAGE, "--published"),
    ([*PUB, "--speed-angle-spin", "30", "95", "100"], EXIT_DATA, "angle"),
    ([*PUB, "--speed-angle-spin", "-30", "40", "100"], EXIT_DATA, "speed"),
    ([*PUB, *LANDING, "--radius-mm", "-5"], EXIT_USAGE, "positive"),
    ([*PUB, *LANDING, "--radius-mm", "0"], EXIT_USAGE, "positive"),
    ([*PUB, *LANDING, "--radius-mm", "inf"], EXIT_USAGE, "finite"),
    # unknown units
    ([*PUB, *LANDING, "--velocity-unit", "knots"], EXIT_DATA, "unknown velocity unit"),
    ([*PUB, *LANDING, "--spin-unit", "m/s"], EXIT_DATA, "unknown spin unit"),
    # outputs that cannot be written
    (["reproduce", "--campaign", "A", "--out", "{d}/notes", "--quiet", "--no-figures"], EXIT_USAGE,
     "not a bouncelab report"),
    (["reproduce", "--campaign", "A", "--out", "{d}/two.csv", "--quiet", "--no-figures"], EXIT_USAGE,
     "not a folder"),
    (["reproduce", "--campaign", "A", "--out", "{d}/missing/rep", "--quiet", "--no-figures"], EXIT_USAGE,
     "does not exist"),
    (["reproduce", "--data", "{d}/two.csv", "--label", "x", "y", "--quiet"], EXIT_USAGE, "one --label per"),
    (["reproduce", "--campaign", "A", "--figure-units", "metric", "--out", "{d}/r3", "--quiet"], EXIT_USAGE,
     "unknown figure units"),
    (["reproduce", "--campaign", "A", "--figure-units", "knots,rpm", "--out", "{d}/r3", "--quiet"], EXIT_USAGE,
     "unknown velocity unit"),
    (["reproduce", "--campaign", "A", "--figure-units", "m/s,rpm,x", "--out", "{d}/r3", "--quiet"], EXIT_USAGE,
     "VELOCITY,SPIN"),
    (["fit", "Rigid", "A", "--save", "{d}"], EXIT_USAGE, "folder"),
    (["fit", "Rigid", "A", "--save", "{d}/missing/law.json"], EXIT_USAGE, "does not exist"),
]
if sys.platform.startswith("linux"):
    # /proc takes no new files, even from root: a read-only --out and --save on any machine.
    CASES += [
        (["reproduce", "--campaign", "A", "--out", "/proc/bouncelab-report", "--quiet", "--no-figures"], EXIT_USAGE,
         "cannot write"),
        (["fit", "Rigid", "A", "--method", "structured", "--save", "/proc/bouncelab-law.json"], EXIT_USAGE,
         "not saved"),
    ]


def run(argv):
    try:
        return main(argv)
    except SystemExit as exc:  # argparse's own errors
        return exc.code


def check(code, err, expected, needle):
    assert code == expected, err
    assert "Traceback" not in err
    messages = [line for line in err.splitlines() if re.match(r"bouncelab( \w+)?: ", line)]
    assert len(messages) == 1, err  # one message line (argparse adds its usage lines; the loader a hint)
    assert needle in err


@pytest.mark.parametrize(("argv", "expected", "needle"), CASES, ids=[" ".join(c[0])[:60] for c in CASES])
def test_bad_command_line(files, capsys, argv, expected, needle):
    argv = [a.replace("{d}", str(files)) for a in argv]
    code = run(argv)
    _, err = capsys.readouterr()
    check(code, err, expected, needle)
    assert (files / "notes" / "mine.txt").read_text() == "keep me"


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes to read-only folders")
def test_read_only_out(tmp_path, capsys):
    ro = tmp_path / "ro"
    ro.mkdir()
    os.chmod(ro, 0o555)
    try:
        code = run(["reproduce", "--campaign", "A", "--out", str(ro / "rep"), "--quiet", "--no-figures"])
        check(code, capsys.readouterr()[1], EXIT_USAGE, "not writable")
        code = run(["fit", "Rigid", "A", "--method", "structured", "--save", str(ro / "law.json")])
        check(code, capsys.readouterr()[1], EXIT_USAGE, "not saved")
    finally:
        os.chmod(ro, 0o755)


@pytest.mark.parametrize("value", ["-8e2", "-8E+2", "-800.0", "-.8e3"])
def test_negative_numbers_in_exponent_form(capsys, value):
    """`--landing 1000 -8e2 200` is a landing, not an unknown option -8e2."""
    assert run([*PUB, "--landing", "1000", value, "200"]) == 0
    row = capsys.readouterr()[0].splitlines()[-1].split()
    want = bl.Rigid.published("A").predict([[1000.0, -800.0, 200.0]])[0]
    assert [float(v) for v in row[:3]] == [1000.0, -800.0, 200.0]
    assert [float(v) for v in row[3:6]] == pytest.approx(want, rel=1e-5)


def test_input_header_and_comments_still_read(tmp_path, capsys):
    # A file with a header is a table: one separator throughout (a file without one may mix them).
    f = tmp_path / "in.csv"
    f.write_text("# landings\nxdot0, ydot0, omega0\n1000, -800, 200\n\n-5e2, -3e2, 9e2  # a comment\n")
    assert run([*PUB, "--input", str(f)]) == 0
    rows = [line.split() for line in capsys.readouterr()[0].splitlines() if not line.startswith("#")]
    assert [[float(v) for v in r[:3]] for r in rows] == [[1000, -800, 200], [-500, -300, 900]]


def test_input_row_behind_a_hash_is_refused_not_skipped(tmp_path, capsys):
    f = tmp_path / "in.csv"
    f.write_text("xdot0,ydot0,omega0\n150,-270,400\n#N/A,-260,300\n140,-260,300\n")
    code = run([*PUB, "--input", str(f)])
    err = capsys.readouterr()[1]
    check(code, err, EXIT_DATA, "line 3")  # read as the loader reads it: #N/A is a missing value
    assert "'#N/A'" in err


@pytest.mark.parametrize("kind", ["fifo", "dev_zero"])
def test_input_that_is_not_a_regular_file_is_refused(tmp_path, capsys, kind):
    f = tmp_path / "in.csv"
    if kind == "fifo":
        os.mkfifo(f)  # reading it would block forever
    else:
        f.symlink_to("/dev/zero")  # reading it would never end
    code = run([*PUB, "--input", str(f)])
    check(code, capsys.readouterr()[1], EXIT_DATA, "not a regular file")



@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_sheet_by_number_of_a_workbook_that_is_a_fifo_is_refused_without_hanging(tmp_path):
    """--sheet 1 is resolved by the loader after its file checks (the command line opened the workbook first)."""
    f = tmp_path / "book.xlsx"
    os.mkfifo(f)
    proc = subprocess.run([sys.executable, "-m", "bouncelab", "info", str(f), "--sheet", "1"], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == EXIT_DATA and "not a regular file" in proc.stderr


def test_fit_save_survives_a_reader_that_goes_away(tmp_path):
    """`bouncelab fit ... --save F | head -1`: the reader leaves after one line; the law is still saved."""
    import shlex

    law = tmp_path / "law.json"
    cmd = f"{shlex.quote(sys.executable)} -m bouncelab fit Rigid A --save {shlex.quote(str(law))} | head -1"
    proc = subprocess.run(["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("[[Fit]] Rigid")
    assert bl.load_law(law) == bl.fit(bl.Rigid, bl.load_campaign("A")).model
