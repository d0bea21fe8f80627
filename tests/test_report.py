"""`bouncelab.reproduce` from Python, and a report that says everything it did (issues 30.3, 31.2, 32.2).

The report names its source files, the units read, the seed, the rows dropped and every item of the paper's
set it did not make, with the reason; it says which figure to trust where Table 2 and grouped
cross-validation disagree, and flags a law with more parameters than its data support; in a notebook it
shows itself (tables and figures inline).
"""

from __future__ import annotations

import base64
import re
import subprocess
import sys
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_PARTIAL
from bouncelab.report import steps as rs
from bouncelab.report.model import Figure, Inputs, Report, Section, Skipped, Table

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))
from test_reproduce_partial import write_lab_file  # noqa: E402  (the 60-shot lab file with three empty cells)

QUICK_ASSESS = {"k": 5, "starts": 2, "profile_points": 5, "local_points": 1}


@pytest.fixture
def quick(monkeypatch):
    """The paper's four laws only, few bootstrap resamples and short profiles: the same steps, in seconds."""
    monkeypatch.setattr(rs, "BEYOND_PAPER_LAWS", ())
    monkeypatch.setattr(rs, "BOOTSTRAP_RESAMPLES", 5)
    monkeypatch.setattr(rs, "ASSESS_OPTIONS", QUICK_ASSESS)


@pytest.fixture
def lab(tmp_path) -> Path:
    return write_lab_file(tmp_path / "lab.csv")


def test_reproduce_is_at_the_top_level_and_loads_lazily():
    code = ("import sys, bouncelab as bl; light = 'bouncelab.report' not in sys.modules and 'pandas' not in "
            "sys.modules; import bouncelab.report as r; "
            "print(light, bl.reproduce is r.reproduce, bl.Report is r.Report, 'reproduce' in dir(bl))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert out.stdout.split() == ["True", "True", "True", "True"]


# ------------------------------------------------------------------------------------------- the lab file
def test_the_readmes_lab_file_command_works_on_a_file_with_empty_cells(quick, lab, tmp_path, capsys):
    """`bouncelab reproduce --data my_bounces.csv --velocity-unit m/s --spin-unit rpm` failed on the first empty
    cell; now the incomplete rows are dropped and the report names them, with its file, units and seed."""
    out = tmp_path / "rep"
    code = main(["reproduce", "--data", str(lab), "--velocity-unit", "m/s", "--spin-unit", "rpm", "--out", str(out),
                 "--no-figures", "--quiet", "--laws", "Rigid", "PiecewiseAffine"])  # (two laws: quicker)
    stdout, err = capsys.readouterr()
    assert code == EXIT_PARTIAL, err  # the SVM of Table 2 needs both slip/roll classes: a skip, named below
    assert all(f"row {r}" in err for r in (8, 24, 42))  # the loader's own warning, on stderr as it happens
    said = {"source": f"campaign lab: {lab}", "file": str(lab.resolve()), "bounces": "measured, 57 bounces",
            "units": "units read: velocity m/s, spin rpm, angle deg",
            "dropped": "rows dropped: 3 (a missing value), data rows 8, 24, 42",
            "seed": "seed 0; laws: Rigid, PiecewiseAffine; bootstrap: 5 resamples",
            "intervals": "prediction intervals: none in the data",
            "table": "lab: Prediction intervals (table): the data have no prediction-interval columns",
            "figures": "lab: Figures (Figs. 3 and 6-10, lever arm): figures=False (--no-figures)",
            "skipped": "lab: Table 2: paper's SVM plane:"}
    for what, text in said.items():
        assert text in stdout, what
    assert stdout.index("not made") < stdout.index("partial report")
    page = (out / "index.html").read_text()
    for text in (str(lab.resolve()), "velocity m/s, spin rpm, angle deg", "data rows 8, 24, 42", "Run with seed 0",
                 "Not made:", "Prediction intervals (table): the data have no prediction-interval columns",
                 "A partial report"):
        assert text in page, text


def test_missing_raise_refuses_the_file_and_names_the_cell(lab, tmp_path, capsys):
    code = main(["reproduce", "--data", str(lab), "--velocity-unit", "m/s", "--spin-unit", "rpm", "--missing", "raise",
                 "--out", str(tmp_path / "rep"), "--quiet"])
    err = capsys.readouterr().err
    assert code == EXIT_DATA
    assert "column 'speed_out', row 8: empty cell" in err and "--missing drop" in err
    assert not (tmp_path / "rep").exists()


def test_python_reproduce_reads_units_and_drops_rows_by_default(quick, lab):
    with pytest.raises(bl.DataError) as e:
        bl.reproduce(data=[lab], out=None, missing="raise", progress=False, figures=False)
    assert (e.value.column, e.value.row) == ("speed_out", 8)
    with pytest.raises(bl.DataError) as e:
        bl.reproduce(data=[lab], out=None, missing="skip", progress=False, figures=False)
    assert e.value.option == "missing"
    with pytest.warns(bl.errors.DroppedRowsWarning):
        report = bl.reproduce(data=[lab], out=None, units={"velocity": "m/s", "spin": "rpm"}, progress=False,
                              figures=False, law_set=["Rigid", "PennerVarying", "TangentialRestitution"], bootstrap=0)
    assert list(report.sections) == ["lab"]  # data files alone: the embedded campaigns are not added
    inputs = report.inputs["lab"]
    assert (inputs.source, inputs.origin, inputs.bounces) == (str(lab), str(lab.resolve()), 57)
    assert inputs.dropped_rows == (8, 24, 42) and inputs.units.startswith("velocity m/s, spin rpm")
    assert inputs.intervals is None and "inferred by clustering" in inputs.settings
    assert report.out is None and report.index is None and report.files == []
    # The laws with more parameters than the data support are flagged, from the assessment's verdicts.
    flagged = {text.split(" ", 1)[0] for _, text in report.caveats if "more parameters than" in text}
    flat = {law for law, a in report.sections["lab"].assessments.items()
            if "not identifiable" in a.verdicts.values()}
    assert flagged == flat and flat  # TangentialRestitution's e_t, on these 57 bounces
    law = next(iter(flat))
    text = next(t for _, t in report.caveats if t.startswith(law))
    for par, verdict in report.sections["lab"].assessments[law].verdicts.items():
        assert (f"({par}" in text or f", {par}" in text) == (verdict == "not identifiable")


def test_every_item_of_the_papers_set_is_made_or_said_not_made(quick, lab, tmp_path):
    """Each table and figure of the paper's set is in the report, or listed as skipped or left out with why."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bl.errors.DroppedRowsWarning)
        report = bl.reproduce(data=[lab], out=tmp_path / "rep", progress=False, figures=False, bootstrap=0)
    sec = report.sections["lab"]
    said = {what for _, what, _ in [*report.skipped, *report.left_out]}
    papers = {"table3": "Table 3", "table2": "Table 2", "repeatability_summary": "Repeatability",
              "tangential": "Tangential velocities", "prediction_intervals": "Prediction intervals"}
    for stem, name in papers.items():
        made = stem in sec.tables and sec.tables[stem].frame is not None
        assert made or any(w.startswith(name) for w in said), name
    assert "prediction_intervals" not in sec.tables  # no interval columns: left out, with the reason
    assert any(w.startswith("Figures") and "figures=False" in r for _, w, r in report.left_out)
    assert ("lab", "Parameter bootstrap", "bootstrap resamples set to 0") in report.left_out


@pytest.mark.slow
def test_lab_file_report_with_figures_says_why_fig6_is_missing(quick, lab, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bl.errors.DroppedRowsWarning)
        report = bl.reproduce(data=[lab], out=tmp_path / "rep", progress=False, bootstrap=0)
    sec = report.sections["lab"]
    assert ("lab", "Fig. 6: prediction-interval widths", rs.NO_INTERVALS) in report.left_out
    drawn = {f.label for f in sec.figures.values() if f.png is not None}
    assert drawn | {s.step for s in report.skipped} >= {"Fig. 3", "Fig. 7", "Fig. 8", "Fig. 9", "Fig. 10"}
    page = (tmp_path / "rep" / "index.html").read_text()
    assert "Fig. 6: prediction-interval widths: the data have no prediction-interval columns" in page
    # the notebook view holds the same figures, inline, byte for byte those written
    html = report._repr_html_()
    shown = [base64.b64decode(m) for m in re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", html)]
    files = sorted((tmp_path / "rep" / "figures").glob("*.png"))
    assert len(shown) == len(files) == len(drawn) and sorted(shown) == sorted(f.read_bytes() for f in files)


# ------------------------------------------------------------------------------------- from Python, in memory
def test_reproduce_from_python_keeps_the_report_in_memory(quick, tmp_path, monkeypatch):
    part = bl.save_campaign(bl.load_campaign("A").isel(bounce=slice(0, 120)), tmp_path / "part.nc")
    monkeypatch.chdir(tmp_path)
    report = bl.reproduce(data=[part], out=None, progress=False, figures=False, law_set=["Rigid", "PiecewiseAffine"],
                          bootstrap=3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["part.nc"]  # nothing written
    sec = report.sections["part"]
    assert repr(sec) == "<Section part: 120 bounces, 10 tables, 0 figures, 4 laws, 0 skipped, 1 not made>"
    assert report.complete and report.seed == 0 and report.laws == ("Rigid", "PiecewiseAffine")
    pd.testing.assert_frame_equal(sec.tables["table3"].frame, sec.comparison.side_by_side())
    assert sec.inputs.units == "scaled (radii/s, rad/s), as stored" and sec.inputs.dropped_rows == ()
    assert sec.inputs.intervals.startswith("95 % half-widths")
    assert isinstance(sec.laws["Rigid"].model, bl.Rigid) and sec.laws["Rigid"].model.is_fitted
    html = report._repr_html_()
    assert html.startswith("<div class='bouncelab'>") and "<html" not in html
    assert "Kept in memory" in html and "Piecewise-affine law" in html and "<table>" in html
    assert "Campaign part" in html and str(part) in html


def test_the_page_shows_itself_with_its_figures_inline():
    """A report made by hand: its notebook view holds the PNG itself; index.html links the file."""
    png = b"\x89PNG\r\n\x1a\n" + bytes(range(40))
    sec = Section(name="x", inputs=Inputs("x.csv", "/data/x.csv", "measured", "velocity m/s", 3, (2,)))
    md = "### A <table>\n\n| a | b |\n|---|---|\n| 1 & 2 | 3 |\n"
    sec.tables["t"] = Table("T", "t", md, pd.DataFrame({"a": [1]}))
    sec.figures["f"] = Figure("Fig. 9: a caption", "f", "Fig. 9", png)
    sec.figures["g"] = Figure("Fig. 10: not drawn", "g", "Fig. 10", reason="too few <bounces>")
    sec.skipped.append(Skipped("x", "Fig. 10", "too few <bounces>"))
    report = Report(out=Path("/r"), sections={"x": sec}, seed=7, laws=("Rigid",), bootstrap=0)
    report.files = [Path("/r/tables/x_t.csv"), Path("/r/figures/x_f.png")]
    view = report._repr_html_()
    assert base64.b64encode(png).decode() in view and "figures/x_f.png" not in view
    assert "<h3>A &lt;table&gt;</h3>" in view and "<td>1 &amp; 2</td>" in view  # escaped, never raw
    assert "Not drawn: too few &lt;bounces&gt;" in view and "A partial report" in view
    assert "data rows 2" in view and "/data/x.csv" in view and "seed 7" in view
    page = report.to_html(inline=False)
    assert page.startswith("<!doctype html>") and "<title>bouncelab report</title>" in page
    assert "<img src='figures/x_f.png'" in page and "base64" not in page
    assert "<li><a href='figures/x_f.png'>figures/x_f.png</a></li>" in page
    assert repr(report) == "<bouncelab Report of x in '/r': partial, 1 step(s) skipped>"


# ---------------------------------------------------------------------------------------------- caveats
def _split(delta_test: float, terms: np.ndarray) -> tuple[SimpleNamespace, SimpleNamespace]:
    """A stand-in for Table 2's fit: predictions whose per-bounce delta terms are ``terms``."""
    p0 = np.tile([[300.0, -400.0, 0.0]], (len(terms), 1))  # |p0| = 500
    pf = np.tile([[100.0, 200.0, 50.0]], (len(terms), 1))
    predicted = pf + np.column_stack([500 * terms, np.zeros((len(terms), 2))])
    errors = pd.DataFrame({"delta": [delta_test]}, index=pd.MultiIndex.from_tuples([("test", "all")]))
    model = SimpleNamespace(predict=lambda landing: predicted)
    return SimpleNamespace(model=model, errors=errors), SimpleNamespace(landing=SimpleNamespace(values=p0),
                                                                        liftoff=SimpleNamespace(values=pf))


def test_table2_and_grouped_cross_validation_disagreeing_says_which_to_trust():
    rng = np.random.default_rng(0)
    terms = 0.033 + 0.01 * rng.standard_normal(40)
    res, test = _split(float(terms.mean()), terms)
    folds = SimpleNamespace(scores={"delta": 0.127, "delta_sd": 0.091}, k=5)  # the 57-shot file
    text = rs._split_against_folds("bouncelab's delta-optimal plane", res, folds, test)
    assert text is not None and "Table 2's held-out delta, 3." in text and "12.7 % +- 9.1 %" in text
    assert "Trust the cross-validation" in text and "never saw" in text
    close = SimpleNamespace(scores={"delta": float(terms.mean()) + 0.01, "delta_sd": 0.091}, k=5)
    assert rs._split_against_folds("plane", res, close, test) is None  # within their spread: nothing to say
    # the spread is the two estimates' combined standard error: a split of few, scattered bounces says nothing
    wide = np.array([0.0, 0.0, 0.0, 0.2])
    res, test = _split(float(wide.mean()), wide)
    assert rs._split_against_folds("plane", res, folds, test) is None


def test_a_law_that_fits_far_better_than_it_predicts_is_flagged():
    res = SimpleNamespace(delta=0.03, n_free=28)
    text = rs._overfits("PiecewiseAffine", res, SimpleNamespace(scores={"delta": 0.127, "delta_sd": 0.02}, k=5))
    assert text is not None and "more parameters than these data support" in text and "28 free" in text
    assert rs._overfits("PiecewiseAffine", res, SimpleNamespace(scores={"delta": 0.035, "delta_sd": 0.01}, k=5)) is None


def test_the_summary_words_everything_the_report_holds():
    from bouncelab.cli.reproduce import summarise, summary_lines

    sec = Section(name="x", inputs=Inputs("x.csv", "/data/x.csv", "measured", "velocity m/s, spin rpm", 57, (8, 24)))
    sec.left_out.append(Skipped("x", "Fig. 6: prediction-interval widths", "no interval columns"))
    sec.caveats.append("PiecewiseAffine: trust the cross-validation")
    sec.skipped.append(Skipped("x", "Repeatability", "no repeated setting"))
    report = Report(out=Path("/r"), sections={"x": sec}, seed=3, laws=("Rigid", "PiecewiseAffine"), bootstrap=0)
    lines = summary_lines(report, "rep")
    assert lines == [
        "report written to rep/index.html",
        "campaign x: x.csv (/data/x.csv), measured, 57 bounces",
        "  units read: velocity m/s, spin rpm",
        "  rows dropped: 2 (a missing value), data rows 8, 24",
        "  prediction intervals: none in the data",
        "seed 3; laws: Rigid, PiecewiseAffine; bootstrap: left out (0)",
        "not made (1, by choice or for want of what they need in the data):",
        "  x: Fig. 6: prediction-interval widths: no interval columns",
        "what to trust:",
        "  x: PiecewiseAffine: trust the cross-validation",
        "partial report: 1 step(s) could not run on the data and were skipped (exit code 5):",
        "  x: Repeatability: no repeated setting"]
    assert summarise(report, "rep") == EXIT_PARTIAL
