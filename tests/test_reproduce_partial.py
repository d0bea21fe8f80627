"""`bouncelab reproduce` completes on any campaign it can load (issue 22, items 2 and 6, and SIGTERM).

A step that cannot run on the data is skipped with its reason (report, summary, ``Report.skipped``), the
exit code says partial (5); no fit returns parameters outside its own bounds; printed planes always have a
form; a SIGTERM leaves no staging folder and a later run removes what a killed one left; the report says
only what its data show.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_FIT, EXIT_OK, EXIT_PARTIAL
from bouncelab.core.errors import DataError, FitError
from bouncelab.core.units import polar_from_state, state_from_polar
from bouncelab.fitting.comparison import generating_law
from bouncelab.laws.plane_fitting import canonical_plane
from bouncelab.report import folder as rf
from bouncelab.report import pipeline as rp
from bouncelab.report import steps as rs
from bouncelab.report.model import Section

REPO = Path(__file__).resolve().parents[1]


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def quick(monkeypatch):
    """The paper's four laws only and 5 bootstrap resamples: the same steps, in a few seconds. (Module constants,
    so that the old code takes them too.)"""
    monkeypatch.setattr(rs, "BEYOND_PAPER_LAWS", ())
    monkeypatch.setattr(rs, "BOOTSTRAP_RESAMPLES", 5)
    monkeypatch.setattr(rs, "ASSESS_OPTIONS", {"k": 5, "starts": 2, "profile_points": 5, "local_points": 1})


def write_lab_file(path: Path) -> Path:
    """A 60-shot launcher file as a lab writes it: a title line, polar columns, a units row, three empty cells.

    Made from Rigid(r=0.5, mu=0.1) plus 2 % noise at one spin setting (2900-3100 rpm): every bounce slips, so
    the paper's SVM has one class only, and the spin carries no information, so the delta-optimal plane
    search ends on the edge of its box, parallel to the omega axis (the old code printed it as
    ``normal = [6e+15, 1e+16, 1]`` and died drawing Fig. 3).
    """
    rng = np.random.default_rng(5)
    n = 60
    polar = np.column_stack([rng.uniform(15, 30, n), rng.uniform(25, 60, n), rng.uniform(2900, 3100, n)])
    landing = state_from_polar(polar, kind="landing")
    liftoff = bl.Rigid(r=0.5, mu=0.1).predict(landing)
    liftoff = liftoff + 0.02 * np.linalg.norm(landing, axis=1, keepdims=True) * rng.standard_normal(liftoff.shape)
    rows = np.column_stack([polar_from_state(landing, kind="landing"), polar_from_state(liftoff, kind="liftoff")])
    lines = ["Launcher test 2026-05-02, lab turf", "speed_in,angle_in,spin_in,speed_out,angle_out,spin_out",
             "m/s,deg,rpm,m/s,deg,rpm"]
    for i, row in enumerate(rows):
        cells = [f"{v:.4g}" for v in row]
        if i in (7, 23, 41):
            cells[(i % 5) + 1] = ""  # an empty cell: the row is dropped with --missing drop
        lines.append(",".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return path


def load_lab(path: Path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bl.errors.DroppedRowsWarning)
        return bl.load_campaign(path, missing="drop")


def write_tracked_campaign(path: Path, n: int = 12) -> Path:
    """A campaign as `bouncelab track` writes it for n clips: one clip per bounce, each its own setting (named
    by the clip), prediction intervals, measured data; here from Rigid(r=0.5, mu=0.3) plus noise."""
    rng = np.random.default_rng(3)
    polar = np.column_stack([rng.uniform(15, 30, n), rng.uniform(25, 60, n), rng.uniform(1000, 6000, n)])
    landing = state_from_polar(polar, kind="landing")
    liftoff = bl.Rigid(r=0.5, mu=0.3).predict(landing)
    liftoff = liftoff + 0.01 * np.linalg.norm(landing, axis=1, keepdims=True) * rng.standard_normal((n, 3))
    clips = [f"clips/bounce_{k:02d}.avi" for k in range(n)]
    ds = bl.make_campaign(landing, liftoff, setting=[Path(c).stem for c in clips],
                          landing_pi=0.01 * np.abs(landing) + 1.0, liftoff_pi=0.01 * np.abs(liftoff) + 1.0,
                          ball_radius_m=0.02135, source=f"bouncelab track: {n} clip(s) measured from video",
                          data_kind="measured").assign_coords(clip=("bounce", clips))
    return bl.save_campaign(ds, path)


def inside_bounds(law) -> dict[str, bool]:
    """Parameter name -> whether every element lies inside the law's default search box."""
    out = {}
    for spec in law.parameter_specs:
        value = np.ravel(np.asarray(getattr(law, spec.name), dtype=float))
        lo, hi = spec.bound_arrays()
        out[spec.name] = bool(np.all(np.isfinite(value)) and np.all(value >= lo) and np.all(value <= hi))
    return out


# ------------------------------------------------------------------------------ the lab file (issue case a)
def test_piecewise_fit_of_the_lab_file_stays_inside_its_bounds_and_draws(tmp_path):
    """`bouncelab fit PiecewiseAffine` printed normal = [6.4e+15, 1.3e+16, 1], offset = -5.5e+18 for such a file,
    outside the law's own bounds, and Fig. 3 died on it; now the plane is stored inside the box and drawn."""
    ds = load_lab(write_lab_file(tmp_path / "lab.csv"))
    assert ds.sizes["bounce"] == 57
    res = bl.fit(bl.PiecewiseAffine, ds)
    law = res.model
    assert all(inside_bounds(law).values()), inside_bounds(law)
    assert not law.has_paper_form() and law.normal[2] == 0.0  # parallel to the omega axis, stored as such
    text = res.report() + law.plane_equation()
    assert "e+1" not in text and "[s/radius" not in text and "n . p0" not in text
    plots = pytest.importorskip("bouncelab.plots")
    fig = plots.plot_landing_space(ds, law)
    legend = " ".join(t.get_text() for t in fig.legends[0].get_texts())
    assert "separating plane" in legend and "e+" not in legend and "omega" not in legend.split("plane")[1][:5]
    pytest.importorskip("matplotlib.pyplot").close(fig)


def test_reproduce_the_lab_file_writes_a_partial_report_and_says_what_it_skipped(quick, capsys, tmp_path):
    lab = write_lab_file(tmp_path / "lab.csv")
    out = tmp_path / "rep"
    code, stdout, err = run(capsys, "reproduce", "--data", lab, "--missing", "drop", "--out", out, "--no-figures",
                            "--quiet")
    assert code == EXIT_PARTIAL, err
    assert "report written to" in stdout and "partial report" in stdout
    assert "lab: Table 2: paper's SVM plane:" in stdout and "{'roll': 0, 'slip': 54}" in stdout
    index = (out / "index.html").read_text()
    assert "A partial report" in index and "the SVM needs both classes" in index
    assert "paper's SVM plane: skipped" in (out / "tables" / "lab_table2.md").read_text()
    # The fitted law written to the report is inside its own bounds.
    law = bl.load_law(out / "laws" / "lab_PiecewiseAffine.json")
    assert all(inside_bounds(law).values()), inside_bounds(law)
    assert "e+1" not in (out / "tables" / "lab_table3.md").read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lab.csv", "rep"]


@pytest.mark.slow
def test_reproduce_the_lab_file_with_figures_end_to_end(tmp_path):
    """The issue's run as a user types it: 46 s then `[10/21] figures ... FAILED`, exit 4, no report."""
    lab = write_lab_file(tmp_path / "lab.csv")
    proc = subprocess.run([sys.executable, "-m", "bouncelab", "reproduce", "--data", str(lab), "--missing", "drop",
                           "--out", str(tmp_path / "rep")], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == EXIT_PARTIAL, proc.stderr
    assert "Traceback" not in proc.stderr and "FAILED" not in proc.stderr
    assert (tmp_path / "rep" / "figures" / "lab_fig3_landing_space.png").stat().st_size > 10_000
    assert "partial report" in proc.stdout and "paper's SVM plane" in proc.stdout


# --------------------------------------------------------------------- the tracked campaign (issue case b)
def test_reproduce_a_12_bounce_tracked_campaign_skips_what_it_cannot_do(quick, capsys, tmp_path):
    clips = write_tracked_campaign(tmp_path / "clips.nc")
    out = tmp_path / "rep"
    code, stdout, err = run(capsys, "reproduce", "--data", clips, "--out", out, "--no-figures", "--quiet")
    assert code == EXIT_PARTIAL, err
    assert "clips: Table 3: PiecewiseAffine: 12 bounces are too few for a piecewise-affine law (need 16)" in stdout
    assert "clips: Repeatability: no launcher setting has two or more bounces" in stdout
    assert "clips: Table 2" in stdout  # the paper's split holds one bounce out of settings that have two
    table3 = (out / "tables" / "clips_table3.md").read_text()
    assert "PiecewiseAffine was not fitted: 12 bounces are too few" in table3 and "| Rigid |" in table3
    assert "Skipped: no launcher setting" in (out / "tables" / "clips_repeatability_summary.md").read_text()
    index = (out / "index.html").read_text()
    assert "A partial report" in index and "need 16" in index
    for law in ("Rigid", "PennerVarying", "PennerFixed"):
        assert bl.load_law(out / "laws" / f"clips_{law}.json").is_fitted
    assert not (out / "laws" / "clips_PiecewiseAffine.json").exists()


def test_python_reproduce_records_what_was_skipped(quick, tmp_path):
    clips = write_tracked_campaign(tmp_path / "clips.nc")
    report = rp.reproduce(data=[clips], out=tmp_path / "rep", figures=False, progress=False,
                          law_set=["rigid", "PiecewiseAffine"], bootstrap=0)
    assert not report.complete
    steps = {what: why for campaign, what, why in report.skipped if campaign == "clips"}
    assert "need 16" in steps["Table 3: PiecewiseAffine"]
    assert "bootstrap" not in " ".join(steps)  # left out on purpose (bootstrap=0): not a skip
    assert ("clips", "Parameter bootstrap", "bootstrap resamples set to 0") in report.left_out
    # With a law set the data can carry (no PiecewiseAffine), only the repeatability remains impossible.
    report = rp.reproduce(data=[clips], out=tmp_path / "rep2", figures=False, progress=False, law_set=["Rigid"],
                          bootstrap=3)
    assert [what for _, what, _ in report.skipped] == ["Repeatability"]


def test_a_complete_report_exits_0(quick, capsys, tmp_path):
    ds = bl.load_campaign("A").isel(bounce=slice(0, 120))
    data = bl.save_campaign(ds, tmp_path / "part.nc")
    code, stdout, err = run(capsys, "reproduce", "--data", data, "--out", tmp_path / "rep", "--no-figures",
                            "--quiet", "--laws", "Rigid", "PiecewiseAffine", "--bootstrap", "3")
    assert code == EXIT_OK, stdout + err
    assert "partial" not in stdout and "A partial report" not in (tmp_path / "rep" / "index.html").read_text()


# ------------------------------------------------------------------------------------------ --laws
def test_laws_option_chooses_the_laws_and_law_adds_one(monkeypatch, capsys, tmp_path):
    seen = {}

    def record(name, source, ds, *, laws=(), bootstrap=0, **_):
        seen["laws"] = [bl.laws.law_name(m) for m in laws]
        seen["bootstrap"] = bootstrap
        return Section(name=name, inputs=rs.inputs_of(source, ds))

    monkeypatch.setattr(rp, "_campaign", record)
    base = ["reproduce", "--campaign", "A", "--no-figures", "--quiet"]
    assert run(capsys, *base, "--out", tmp_path / "r1")[0] == EXIT_OK
    assert seen["laws"] == ["Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine", "TangentialRestitution",
                            "CompliantImpact", "TurfContact"] and seen["bootstrap"] == rs.BOOTSTRAP_RESAMPLES
    assert run(capsys, *base, "--out", tmp_path / "r2", "--laws", "rigid", "PENNERFIXED", "--law", "CraterContact",
               "--law", "Rigid", "--bootstrap", "7")[0] == EXIT_OK
    assert seen["laws"] == ["Rigid", "PennerFixed", "CraterContact"] and seen["bootstrap"] == 7
    assert run(capsys, *base, "--out", tmp_path / "r3", "--law", "CraterContact")[0] == EXIT_OK
    assert seen["laws"][-1] == "CraterContact" and len(seen["laws"]) == 8  # --law alone adds to the default
    code, _, err = run(capsys, *base, "--out", tmp_path / "r4", "--laws", "Rigid", "Bouncy")
    assert code == EXIT_FIT and "Bouncy" in err and not (tmp_path / "r4").exists()  # before any work
    with pytest.raises(SystemExit):
        main(["reproduce", "--bootstrap", "-1"])
    with pytest.raises(FitError) as e:
        rp.reproduce(["A"], out=tmp_path / "r5", progress=False, figures=False, bootstrap=-2)
    assert e.value.option == "bootstrap"
    with pytest.raises(FitError) as e:  # one resample has no spread: it skipped every assessment
        rp.reproduce(["A"], out=tmp_path / "r6", progress=False, figures=False, bootstrap=1)
    assert e.value.option == "bootstrap" and not (tmp_path / "r6").exists()


def test_only_typed_errors_become_skips(monkeypatch, tmp_path):
    """A step failing with a DataError is skipped; a bug (any other exception) still stops the run, leaving
    nothing behind."""
    import bouncelab.analysis.contact_velocity as cv

    data = bl.save_campaign(bl.load_campaign("A").isel(bounce=slice(0, 60)), tmp_path / "part.nc")
    kw = {"out": tmp_path / "rep", "figures": False, "progress": False, "law_set": ["Rigid"], "bootstrap": 0}

    def no_data(ds):
        raise DataError("no tangential velocities in these data")

    monkeypatch.setattr(cv, "tangential_summary", no_data)
    report = rp.reproduce(data=[data], **kw)
    assert ("part", "Tangential velocities", "no tangential velocities in these data") in report.skipped

    def bug(ds):
        raise RuntimeError("a bug")

    monkeypatch.setattr(cv, "tangential_summary", bug)
    before = (tmp_path / "rep" / "index.html").read_bytes()
    with pytest.raises(RuntimeError, match="a bug"):
        rp.reproduce(data=[data], **kw)
    assert (tmp_path / "rep" / "index.html").read_bytes() == before  # the previous report is untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["part.nc", "rep"]


# ------------------------------------------------------------------------------------ bounds and planes
def test_the_issues_plane_is_stored_inside_the_box():
    normal, offset = canonical_plane(np.array([6.4058e15, 1.3003e16, 1.0]), -5.48e18)
    assert np.abs(normal).max() == 1.0 and normal[2] == 0.0 and -3000 <= offset <= 3000
    assert normal[0] == pytest.approx(6.4058e15 / 1.3003e16) and offset == pytest.approx(-5.48e18 / 1.3003e16)
    flipped, _ = canonical_plane(-np.array([0.5, 2.0, 1e-20]), 100.0)
    assert str(flipped[2]) == "0.0" or flipped[2] == 0.0  # no "-0"
    for bad in ([0.0, 0.0, 0.0], [np.nan, 1.0, 1.0]):
        with pytest.raises(FitError):
            canonical_plane(np.array(bad), 1.0)


def test_a_plane_without_the_papers_form_is_drawn_and_printed_in_its_unit_form():
    law = bl.PiecewiseAffine(**{**bl.published.piecewise_parameters("A"), "normal": [6.4058e15, 1.3003e16, 1.0],
                                "offset": -5.48e18})
    assert not law.has_paper_form()
    for text in (law.plane_equation(), "\n".join(law._summary_lines())):
        assert "e+" not in text and "xdot0" in text
    plots = pytest.importorskip("bouncelab.plots")
    ds = bl.load_campaign("A")
    fig = plots.plot_landing_space(ds, law)
    legend = " ".join(t.get_text() for t in fig.legends[0].get_texts())
    assert "e+" not in legend and r"\dot{x}_0" in legend
    pytest.importorskip("matplotlib.pyplot").close(fig)


def test_no_fitting_method_returns_parameters_outside_the_search_box():
    """A method's own result (a closed form, least squares) outside the box, or missing, is a FitError naming the
    parameter, whatever method returned it."""

    class Loose(bl.Rigid):
        @bl.laws.base.fit_method("closed_form")
        def _fit_closed(self, problem, *, mu=2.0):
            from bouncelab.laws import FitOutcome

            return FitOutcome(model=self.replace(r=0.5, mu=mu), objective_value=0.0, algorithm="closed form")

    ds = bl.load_campaign("A")
    with pytest.raises(FitError) as e:  # mu = 2, outside the law's search box 0..1.5
        bl.fit(Loose, ds, method="closed_form")
    assert e.value.law.endswith(".Loose") and e.value.option == "bounds"
    assert "returned mu = 2, outside the law's search box 0..1.5" in e.value.message  # the value and the box
    assert [h.option for h in e.value.hints] == ["bounds", "method"] and e.value.hints[1].value == "global"
    assert e.value.hints[0].value == {"mu": "(low, high)"}
    assert bl.fit(Loose, ds, method="closed_form", bounds={"mu": (0, 3)}).model.mu == 2.0  # widened on purpose
    assert bl.fit(Loose, ds, method="closed_form", mu=1.0).model.mu == 1.0
    with pytest.raises(FitError) as e:  # no value for mu
        bl.fit(Loose, ds, method="closed_form", mu=None)
    assert e.value.law.endswith(".Loose") and e.value.option == "method" and "'mu'" in e.value.message


def test_fitted_planes_of_the_surrogates_are_inside_the_box():
    """Campaign B's delta-optimal plane was stored as (-0.44, 1.98, 1), outside the normal's box [-1, 1]; the
    same plane is now stored with its largest coefficient 1 and printed in the paper's form as before."""
    res = bl.fit(bl.PiecewiseAffine, bl.load_campaign("B"))
    assert all(inside_bounds(res.model).values())
    assert np.abs(res.model.normal).max() == 1.0
    assert "omega0 =" in res.model.plane_equation()


# -------------------------------------------------------------------------------------------- SIGTERM
def _wait_for(predicate, timeout: float = 120.0) -> None:
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > end:
            raise AssertionError("timed out")
        time.sleep(0.05)


def _staging(folder: Path) -> list[Path]:
    return [p for p in folder.iterdir() if re.fullmatch(r"\.rep\.(new|old)-[a-z0-9_]{8}", p.name)]


def _start(tmp_path: Path) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "bouncelab", "reproduce", "--campaign", "A", "--no-figures", "--quiet",
           "--out", str(tmp_path / "rep")]
    return subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_sigterm_mid_run_leaves_no_staging_folder(tmp_path):
    """`timeout`, batch schedulers and systemd stop a job with SIGTERM: the staging folder goes, as for Ctrl-C,
    and the process still ends of the signal."""
    proc = _start(tmp_path)
    try:
        _wait_for(lambda: _staging(tmp_path) or proc.poll() is not None)
        assert proc.poll() is None, proc.communicate()
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        with contextlib.suppress(ProcessLookupError):
            proc.kill()
    assert proc.returncode == -signal.SIGTERM, err
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no .rep.new-XXXXXXXX, no report


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_a_later_run_removes_what_a_killed_run_left(tmp_path, monkeypatch, capsys):
    proc = _start(tmp_path)
    try:
        _wait_for(lambda: _staging(tmp_path) or proc.poll() is not None)
        proc.kill()  # SIGKILL: nothing can clean up
        proc.communicate(timeout=60)
    finally:
        with contextlib.suppress(ProcessLookupError):
            proc.kill()
    left = _staging(tmp_path)
    assert len(left) == 1 and left[0].is_dir()

    def fake(name, source, ds, **_):
        return Section(name=name, inputs=rs.inputs_of(source, ds))

    monkeypatch.setattr(rp, "_campaign", fake)
    rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=True)
    assert "left by an earlier run that was killed" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


@pytest.mark.skipif(os.name != "posix", reason="POSIX signals")
def test_sigterm_handler_is_restored_and_a_previous_handler_still_runs(tmp_path, monkeypatch):
    calls = []

    def previous(signum, frame):
        calls.append(signum)

    def terminated(name, source, ds, **_):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(1)  # the handler raises here
        raise AssertionError("SIGTERM did not interrupt the run")

    monkeypatch.setattr(rp, "_campaign", terminated)
    old = signal.signal(signal.SIGTERM, previous)
    try:
        with pytest.raises(rf._Terminated):
            rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=False)
        assert signal.getsignal(signal.SIGTERM) is previous and calls == [signal.SIGTERM]
    finally:
        signal.signal(signal.SIGTERM, old)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(os.name != "posix", reason="folder locks")
def test_stale_folder_cleanup_removes_only_bouncelabs_own_unused_folders(tmp_path):
    import fcntl

    out = tmp_path / "rep"
    old_time = time.time() - 3600

    def folder(name: str, files=("tables/x.md",), when: float = old_time) -> Path:
        p = tmp_path / name
        p.mkdir()
        for f in files:
            (p / f).parent.mkdir(parents=True, exist_ok=True)
            (p / f).write_text("x")
        for q in [*p.rglob("*"), p]:
            os.utime(q, (when, when))
        return p

    stale = folder(".rep.new-abcdefgh")
    old_report = folder(".rep.old-12345678", files=("index.html", "laws/A_Rigid.json", rf.MANIFEST))
    mine = folder(".rep.new-zzzzzzzz", files=("tables/x.md", "notes.txt"))  # a file a report never writes
    other = folder(".other.new-abcdefgh")
    odd = folder(".rep.new-abc")  # not mkdtemp's 8 characters
    fresh = folder(".rep.new-xxxxxxxx", when=time.time() + 60)  # changed after this run started
    busy = folder(".rep.new-yyyyyyyy")
    (tmp_path / ".rep.new-wwwwwwww").write_text("a file, not a folder")
    target = folder("elsewhere", files=("tables/x.md",))
    (tmp_path / ".rep.new-vvvvvvvv").symlink_to(target)
    fd = os.open(busy, os.O_RDONLY)
    fcntl.flock(fd, fcntl.LOCK_EX)  # a run still working in it
    try:
        removed = rf.remove_stale_staging(out, before=time.time())
    finally:
        os.close(fd)
    assert sorted(removed) == sorted([stale, old_report])
    for kept in (mine, other, odd, fresh, busy, target, tmp_path / ".rep.new-wwwwwwww", tmp_path / ".rep.new-vvvvvvvv"):
        assert kept.exists() or kept.is_symlink()
    assert (target / "tables" / "x.md").exists()


# ----------------------------------------------------------------------------------- a report that says only
def test_generating_law_is_read_from_the_campaign():
    assert generating_law(bl.load_campaign("A", surrogate="turf")) == "CraterContact"
    assert generating_law(bl.load_campaign("B", surrogate="published")) == "PiecewiseAffine"
    measured = bl.load_campaign("A").assign_attrs(data_kind="measured")
    assert generating_law(measured) is None
    own = bl.make_campaign(measured.landing.values, measured.liftoff.values, data_kind="synthetic surrogate",
                           attrs={"generator_law": "Rigid"})
    assert generating_law(own) == "Rigid"


def test_comparison_marks_the_generator_and_labels_the_papers_values_as_a_reference():
    ds = bl.load_campaign("A", surrogate="published")  # generated by the paper's published PiecewiseAffine
    cmp = bl.compare(ds, ["Rigid", "PiecewiseAffine"])
    md = cmp.to_markdown()
    assert "| quantity | Rigid | PiecewiseAffine † |" in md
    assert "† PiecewiseAffine generated these data: its fit is not a test of it" in md
    assert "a reference, not a validation" in md and "(31.9 %)" in md
    # Table 2's figures are the paper's test set: not beside errors on the fitted bounces.
    assert "(7.27 %)" not in md and "(6.56 %)" not in md and "(6.79 %)" not in md
    # The plane is an equation; its normal and offset have no unit of their own.
    assert "| plane |" in md and "omega0 = " in md and "s/radius, s/radius" not in md and "n . p0" not in md
    held = bl.compare(ds, ["PiecewiseAffine"], split="setting").to_markdown()
    assert "(7.27 %)" in held and "(6.79 %)" in held and "held-out" in held
    turf = bl.compare(bl.load_campaign("A", surrogate="turf"), ["Rigid"]).to_markdown()
    assert "CraterContact generated these data (it is not among the laws here)" in turf
    measured = bl.compare(ds.assign_attrs(data_kind="measured"), ["Rigid"]).to_markdown()
    assert "the paper's values in brackets" in measured and "reference" not in measured and "†" not in measured


def test_fit_report_prints_the_plane_with_honest_units():
    text = bl.fit(bl.PiecewiseAffine, bl.load_campaign("A"), method="svm").report()
    assert "[s/radius, s/radius, s]" not in text and "n . p0" not in text
    assert "(each term in rad/s)" in text and "(xdot0, ydot0 in radii/s, omega0 in rad/s)" in text


def test_lever_arm_histogram_marks_its_clipped_end_bins():
    plots = pytest.importorskip("bouncelab.plots")
    plt = pytest.importorskip("matplotlib.pyplot")
    ds = bl.load_campaign("A")
    fig = plots.plot_lever_arm(ds, [bl.PiecewiseAffine.published("A")])
    ax = fig.axes[0]
    gids = {p.get_gid() for p in ax.patches}
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    lever = bl.analysis.impulse.impulse_lever_arm(ds)["lever_arm"].values
    above = int((lever[np.isfinite(lever)] > 6).sum())
    assert above > 0  # the data do have values beyond the axis
    assert "clipped-above" in gids
    assert any(f"{above} above 6" in t for t in labels)
    assert any("end bins: also every value beyond [-2, 6]" in t for t in labels)
    plt.close(fig)
    inside = plots.plot_lever_arm((ds.landing.values, bl.Rigid(r=0.5, mu=0.3).predict(ds.landing.values)))
    assert not any(str(p.get_gid()).startswith("clipped") for p in inside.axes[0].patches)
    plt.close(inside)


def test_report_on_a_synthetic_campaign_says_the_papers_values_are_a_reference(quick, tmp_path):
    report = rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=False,
                          law_set=["Rigid", "PiecewiseAffine"], bootstrap=3, surrogate="published")
    index = (tmp_path / "rep" / "index.html").read_text()
    assert "a reference, not a validation" in index and "says nothing about real turf" in index
    assert "PiecewiseAffine generated these data" in index
    table2 = (tmp_path / "rep" / "tables" / "A_table2.md").read_text()
    assert "Piecewise-affine law †" in table2 and "a reference, not a validation" in table2
    assert "(7.27 %)" in table2  # beside the SVM's held-out mismatch, its like
    table3 = (tmp_path / "rep" / "tables" / "A_table3.md").read_text()
    assert "(7.27 %)" not in table3
    assert "PiecewiseAffine †" in (tmp_path / "rep" / "tables" / "A_crossvalidation.md").read_text()
    assert report.complete
    assert json.loads((tmp_path / "rep" / rf.MANIFEST).read_text())["files"]


# ------------------------------------------------------------------------------ issue 24: held-out and assessment
def test_report_shows_held_out_beside_training_and_an_assessment_per_law(quick, tmp_path, monkeypatch):
    monkeypatch.setattr(rs, "NOT_CROSS_VALIDATED", frozenset({"PennerFixed"}))  # as TurfContact is by default
    report = rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=False, surrogate="published",
                          law_set=["Rigid", "PennerFixed", "PiecewiseAffine"], bootstrap=5)
    assert report.complete
    tables = tmp_path / "rep" / "tables"
    sec = report.sections["A"]
    cmp = sec.comparison
    # Table 3: the training errors with the paper's in brackets, then free parameters and held-out errors
    t3 = (tables / "A_table3.md").read_text()
    lines = t3.splitlines()
    train = next(line for line in lines if line.startswith("| delta |"))
    held = next(line for line in lines if line.startswith("| delta, held out (5 folds by setting) |"))
    assert "(31.9 %)" in train and "(" not in held.split("|", 2)[2]
    assert "| free parameters | 2 | 3 | 28 |" in t3
    rigid = cmp.table.loc["Rigid"]
    assert f"{100 * rigid['heldout_delta']:.3g} % +- {100 * rigid['heldout_delta_sd']:.3g} %" in held
    assert np.isnan(cmp.table.loc["PennerFixed", "heldout_delta"])  # left out, and the report says why
    assert "PennerFixed: no held-out errors (left out to keep the report quick" in t3
    assert ("heldout_delta", "bouncelab") in pd.read_csv(tables / "A_table3.csv", header=[0, 1],
                                                                          index_col=0).columns
    # the assessment: every law of the rigid family asked for, with verdicts; the others named, with the reason
    assert set(sec.assessments) == {"Rigid", "PennerFixed"}
    md = (tables / "A_assessment.md").read_text()
    assert "5 folds grouped by launcher setting, 5 bootstrap resamples" in md and "profile of each parameter (5 " in md
    for law, a in sec.assessments.items():
        for par, verdict in a.verdicts.items():
            assert f"| {law} | {par} | " in md and verdict in md
    assert "Not assessed here" in md and "PiecewiseAffine: 28 numbers" in md
    frame = pd.read_csv(tables / "A_assessment.csv", index_col=[0, 1])
    assert frame.loc[("Rigid", "r"), "verdict"] == sec.assessments["Rigid"].verdicts["r"]
    assert sec.not_assessed == {"PiecewiseAffine": rs.NOT_ASSESSED["PiecewiseAffine"]}
    # the bootstrap table is the assessment's own bootstrap (no second set of refits)
    boot = pd.read_csv(tables / "A_bootstrap.csv", index_col=[0, 1])
    summary = sec.assessments["Rigid"].bootstrap.summary()
    assert boot.loc[("Rigid", "r"), "ci_high"] == pytest.approx(summary.loc["r", "ci_high"], rel=1e-12)
    index = (tmp_path / "rep" / "index.html").read_text()
    assert "Assessment of each law, campaign A" in index and "A_assessment.md" in index


def test_an_assessment_that_cannot_run_is_a_skip(quick, tmp_path, monkeypatch):
    import bouncelab.fitting.assessment as assessment

    real = assessment.assess

    def refuse_rigid(model, data, **kw):
        if bl.laws.law_name(model) == "Rigid":
            raise FitError("too few launcher settings for this assessment")
        return real(model, data, **kw)

    monkeypatch.setattr(assessment, "assess", refuse_rigid)
    report = rp.reproduce(["A"], out=tmp_path / "rep", figures=False, progress=False,
                          law_set=["Rigid", "PennerFixed"], bootstrap=3)
    assert ("A", "assessment: Rigid", "too few launcher settings for this assessment") in report.skipped
    md = (tmp_path / "rep" / "tables" / "A_assessment.md").read_text()
    assert "Rigid: not assessed, skipped: too few launcher settings" in md and "| PennerFixed | r |" in md
    boot = (tmp_path / "rep" / "tables" / "A_bootstrap.md").read_text()
    assert "Rigid: skipped, its assessment could not run" in boot
