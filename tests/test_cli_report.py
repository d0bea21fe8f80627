"""`bouncelab reproduce` writes only inside --out, and leaves a complete report or the previous one.

The analysis itself is tested in test_cli.py; here ``_campaign`` (the per-campaign analysis) is
replaced by a fast stand-in that returns a section the way the real one does, so these tests run in
well under a second each and exercise the naming, the staging folder and the swap.
"""

from __future__ import annotations

import errno
import json
import os
import resource
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import bouncelab as bl
from bouncelab.cli.main import main
from bouncelab.cli.messages import EXIT_DATA, EXIT_OK, EXIT_USAGE
from bouncelab.report import folder as rf
from bouncelab.report import pipeline as rp
from bouncelab.report import steps as rs
from bouncelab.report.model import LawFile, Section, Table


def _fake_campaign(name, source, ds, **_):
    """One table and one law per campaign, named as the real analysis names them."""
    sec = Section(name=name, inputs=rs.inputs_of(source, ds))
    sec.tables["table3"] = Table("Table 3", "table3", f"### {name}\n", pd.DataFrame({"n": [ds.sizes["bounce"]]}))
    sec.laws["Rigid"] = LawFile("Rigid", "Rigid", bl.Rigid(r=0.5, mu=0.3))
    return sec


@pytest.fixture
def fast(monkeypatch):
    monkeypatch.setattr(rp, "_campaign", _fake_campaign)


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def files_under(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()}


@pytest.mark.parametrize("attr", ["../../x", "ABSOLUTE"])
def test_output_paths_never_come_from_the_data(fast, capsys, tmp_path, attr):
    """A file's ``campaign`` attribute ("../../x", an absolute path) must not steer where files go."""
    outside = tmp_path / "elsewhere" / "evil"
    campaign = str(outside) if attr == "ABSOLUTE" else attr
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    evil = work / "evil.nc"
    bl.save_campaign(bl.load_campaign("A").assign_attrs(campaign=campaign), evil)
    before = files_under(tmp_path)
    code, _, err = run(capsys, "reproduce", "--data", evil, "--out", work / "report", "--no-figures", "--quiet")
    assert code == EXIT_OK, err
    new = files_under(tmp_path) - before
    assert new and all(f.startswith("a/b/report/") for f in new), sorted(new)
    assert "a/b/report/tables/evil_table3.md" in new  # named by the file, as given on the command line
    assert not (tmp_path / "elsewhere").exists()


def test_labels_and_names_are_cleaned(fast, capsys, tmp_path):
    wet, dry, odd = tmp_path / "turf (wet).nc", tmp_path / "dry.nc", tmp_path / "-.nc"
    for f in (wet, dry, odd):
        bl.save_campaign(bl.load_campaign("A"), f)
    code, _, err = run(capsys, "reproduce", "--data", wet, dry, "--out", tmp_path / "r", "--no-figures", "--quiet")
    assert code == EXIT_OK, err
    assert {"tables/turf_wet_table3.md", "tables/dry_table3.md", "index.html"} <= files_under(tmp_path / "r")
    code, _, err = run(capsys, "reproduce", "--data", wet, dry, odd, "--label", "../up", "A", "..", "--out",
                       tmp_path / "r2", "--no-figures", "--quiet")
    assert code == EXIT_OK, err
    assert {"tables/up_table3.md", "tables/A_table3.md", "tables/campaign_table3.md"} <= files_under(tmp_path / "r2")
    assert rs.campaign_file_name("turf (wet)") == "turf_wet"
    assert rs.campaign_file_name("..") == "campaign"


def test_report_has_a_manifest_and_rerun_replaces_it(fast, capsys, tmp_path):
    out = tmp_path / "rep"
    assert run(capsys, "reproduce", "--campaign", "A", "B", "--out", out, "--no-figures", "--quiet")[0] == EXIT_OK
    manifest = json.loads((out / rf.MANIFEST).read_text())
    assert set(manifest["files"]) | {rf.MANIFEST} == files_under(out)
    # A second run with fewer campaigns replaces the report as a whole: B's files go.
    assert run(capsys, "reproduce", "--campaign", "A", "--out", out, "--no-figures", "--quiet")[0] == EXIT_OK
    assert not any(f.startswith("tables/B_") for f in files_under(out))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]  # no staging or old folder left beside it


def test_failed_run_leaves_previous_report_intact(fast, capsys, tmp_path, monkeypatch):
    out = tmp_path / "rep"
    assert run(capsys, "reproduce", "--campaign", "A", "--out", out, "--no-figures", "--quiet")[0] == EXIT_OK
    before = {f: (out / f).read_bytes() for f in files_under(out)}

    real = rf.atomic_write_text

    def disk_full(path, text, *args, **kw):
        if Path(path).name == "B_table3.md":  # its CSV is written, then the disk fills up
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        return real(path, text, *args, **kw)

    monkeypatch.setattr(rf, "atomic_write_text", disk_full)
    code, _, err = run(capsys, "reproduce", "--campaign", "B", "--out", out, "--no-figures", "--quiet")
    assert code == EXIT_USAGE
    assert "No space left on device" in err and "previous report" in err and "Traceback" not in err
    assert {f: (out / f).read_bytes() for f in files_under(out)} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_failed_first_run_leaves_nothing(capsys, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("vx0,vy0,w0,vx1,vy1,w1\n100,-200,30,50,60,10\n100,abc,30,50,60,10\n")
    code, _, _ = run(capsys, "reproduce", "--campaign", "A", "--data", bad, "--out", tmp_path / "rep", "--quiet")
    assert code == EXIT_DATA
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.csv"]


def test_interrupted_run_leaves_previous_report(fast, capsys, tmp_path, monkeypatch):
    out = tmp_path / "rep"
    assert run(capsys, "reproduce", "--campaign", "A", "--out", out, "--no-figures", "--quiet")[0] == EXIT_OK
    before = files_under(out)

    def interrupted(*args, **_):
        raise KeyboardInterrupt

    monkeypatch.setattr(rp, "_campaign", interrupted)
    assert run(capsys, "reproduce", "--campaign", "B", "--out", out, "--no-figures", "--quiet")[0] == 130
    assert files_under(out) == before and sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_out_that_is_not_a_report_is_refused(fast, capsys, tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my notes")
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--out", mine, "--no-figures", "--quiet")
    assert code == EXIT_USAGE and "not a bouncelab report" in err
    assert files_under(mine) == {"notes.txt"}
    # A previous report with a file the user added is refused too, naming the file.
    rep = tmp_path / "rep"
    assert run(capsys, "reproduce", "--campaign", "A", "--out", rep, "--no-figures", "--quiet")[0] == EXIT_OK
    (rep / "tables" / "my_plot.py").write_text("print(1)")
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--out", rep, "--no-figures", "--quiet")
    assert code == EXIT_USAGE and "tables/my_plot.py" in err
    assert (rep / "tables" / "my_plot.py").read_text() == "print(1)"
    (rep / "tables" / "my_plot.py").unlink()
    (rep / "data_link").symlink_to(mine, target_is_directory=True)
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--out", rep, "--no-figures", "--quiet")
    assert code == EXIT_USAGE and "data_link" in err and (rep / "data_link").is_symlink()
    # An empty folder is fine, and keeps its permission bits.
    empty = tmp_path / "empty"
    empty.mkdir(mode=0o750)
    os.chmod(empty, 0o750)
    assert run(capsys, "reproduce", "--campaign", "A", "--out", empty, "--no-figures", "--quiet")[0] == EXIT_OK
    assert (empty / "index.html").exists() and (empty.stat().st_mode & 0o777) == 0o750


def test_previous_report_of_an_older_version_is_recognised(fast, capsys, tmp_path):
    """Reports written before the manifest existed list their files in index.html."""
    old = tmp_path / "rep"
    (old / "tables").mkdir(parents=True)
    (old / "tables" / "A_table3.md").write_text("old")
    (old / "index.html").write_text("<!doctype html><html><head><meta charset='utf-8'><title>bouncelab report"
                                    "</title></head><body><h2>Files</h2><ul><li><a href='tables/A_table3.md'>"
                                    "tables/A_table3.md</a></li></ul></body></html>")
    assert run(capsys, "reproduce", "--campaign", "B", "--out", old, "--no-figures", "--quiet")[0] == EXIT_OK
    assert "tables/B_table3.md" in files_under(old) and "tables/A_table3.md" not in files_under(old)


def _limit_file_size():  # runs in the child before exec
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a too-large write fails with EFBIG instead of killing
    resource.setrlimit(resource.RLIMIT_FSIZE, (64, 64))


def test_fit_save_failure_prints_the_fit_and_keeps_the_old_file(capsys, tmp_path, monkeypatch):
    law = tmp_path / "law.json"
    law.write_text("previous law\n")

    def too_big(*args, **_):
        raise OSError(errno.EFBIG, "File too large")

    monkeypatch.setattr("bouncelab.core.atomic.os.replace", too_big)
    code, out, err = run(capsys, "fit", "Rigid", "A", "--save", law)
    assert code == EXIT_USAGE
    assert "[[Fit]] Rigid" in out and "law written" not in out
    assert "File too large" in err and "not saved" in err
    assert law.read_text() == "previous law\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["law.json"]


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(resource, "RLIMIT_FSIZE"), reason="needs RLIMIT_FSIZE")
def test_fit_save_failure_keeps_previous_law_and_prints_the_fit(tmp_path):
    """A file-size limit stops the write of the new law: the old file is intact, the fit is shown, exit 2."""
    law = tmp_path / "law.json"
    law.write_text("previous law\n")
    proc = subprocess.run([sys.executable, "-m", "bouncelab", "fit", "PennerFixed", "A", "--save", str(law)],
                          capture_output=True, text=True, preexec_fn=_limit_file_size)
    assert proc.returncode == EXIT_USAGE, proc.stderr
    assert "[[Fit]] PennerFixed" in proc.stdout  # the finished fit is not lost
    assert "not saved" in proc.stderr and "Traceback" not in proc.stderr
    assert law.read_text() == "previous law\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["law.json"]


def test_fit_save_to_a_folder_is_refused_before_fitting(capsys, tmp_path, monkeypatch):
    import bouncelab.fitting as fitting

    def no_fit(*args, **kwargs):
        raise AssertionError("the fit must not run")

    monkeypatch.setattr(fitting, "fit", no_fit)
    for target in (tmp_path, tmp_path / "missing" / "law.json"):
        code, _, err = run(capsys, "fit", "Rigid", "A", "--save", target)
        assert code == EXIT_USAGE and str(target) in err


def test_report_files_are_written_atomically(capsys, tmp_path, monkeypatch):
    """Every table goes through bouncelab.core.atomic: a failed write leaves no half-written file."""
    calls = []
    real = rf.atomic_write_text

    def spy(path, text, *a, **k):
        calls.append(Path(path).name)
        return real(path, text, *a, **k)

    monkeypatch.setattr(rf, "atomic_write_text", spy)
    rf._write_table(pd.DataFrame({"a": [1.0, np.nan]}), "### t\n", tmp_path / "x_table")
    assert calls == ["x_table.csv", "x_table.md"]


def test_figure_units_flag_reaches_the_figures_and_the_report_text(capsys, tmp_path, monkeypatch):
    seen = []

    def campaign(name, source, ds, *, units=None, **_):
        seen.append(units)
        return _fake_campaign(name, source, ds)

    monkeypatch.setattr(rp, "_campaign", campaign)
    out = tmp_path / "rep"
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--figure-units", "ft/s,rev/s", "--out", out, "--quiet")
    assert code == EXIT_OK, err
    assert (seen[0].velocity, seen[0].spin) == ("ft/s", "rev/s")
    assert "in the figures: velocities in ft/s, spin in rev/s" in (out / "index.html").read_text()
    code, _, err = run(capsys, "reproduce", "--campaign", "A", "--figure-units", "lab", "--out", out, "--quiet")
    assert code == EXIT_OK and (seen[1].velocity, seen[1].spin) == ("m/s", "rpm")
    assert run(capsys, "reproduce", "--campaign", "A", "--out", out, "--quiet")[0] == EXIT_OK
    assert seen[2].velocity == "radius/s" and "in the figures" not in (out / "index.html").read_text()


def test_out_holding_the_current_folder_is_refused(fast, capsys, tmp_path, monkeypatch):
    here = tmp_path / "empty"
    here.mkdir()
    monkeypatch.chdir(here)
    for out in (".", str(tmp_path)):
        code, _, err = run(capsys, "reproduce", "--campaign", "A", "--out", out, "--no-figures", "--quiet")
        assert code == EXIT_USAGE and "current folder" in err
    assert here.is_dir() and list(here.iterdir()) == []


@pytest.mark.slow
@pytest.mark.skipif(not hasattr(resource, "RLIMIT_FSIZE"), reason="needs RLIMIT_FSIZE")
def test_real_run_failing_late_keeps_previous_report(tmp_path):
    """End to end: a real reproduce run hits a file-size limit part-way (its first file over 8000 bytes);
    the previous report is byte for byte as it was and no partial folder is left."""
    out = tmp_path / "rep"
    cmd = [sys.executable, "-m", "bouncelab", "reproduce", "--campaign", "A", "--no-figures", "--quiet", "--out",
           str(out)]
    subprocess.run(cmd, check=True, capture_output=True)
    before = {f: (out / f).read_bytes() for f in files_under(out)}

    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (8000, 8000))  # small tables fit, larger files do not

    proc = subprocess.run([*cmd[:5], "B", *cmd[6:]], capture_output=True, text=True, preexec_fn=limit)
    assert proc.returncode == EXIT_USAGE, proc.stderr
    assert "File too large" in proc.stderr and "previous report" in proc.stderr and "Traceback" not in proc.stderr
    assert {f: (out / f).read_bytes() for f in files_under(out)} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["rep"]


def test_read_only_folders_are_refused_before_any_work(fast, capsys, tmp_path, monkeypatch):
    """What a non-root user sees for a read-only --out or parent (root passes os.access, hence the stand-in)."""
    out = tmp_path / "rep"
    assert run(capsys, "reproduce", "--campaign", "A", "--out", out, "--no-figures", "--quiet")[0] == EXIT_OK
    before = files_under(out)
    real = os.access
    for read_only, needle in ((out, "the folder is not writable"), (tmp_path, "is not writable")):
        monkeypatch.setattr(os, "access", lambda p, mode, ro=read_only: False if Path(p) == ro else real(p, mode))
        code, _, err = run(capsys, "reproduce", "--campaign", "B", "--out", out, "--no-figures", "--quiet")
        monkeypatch.setattr(os, "access", real)
        assert code == EXIT_USAGE and needle in err
        assert files_under(out) == before


def test_reproduce_surrogate_option_loads_the_named_embedded_campaigns(monkeypatch, capsys, tmp_path):
    seen = {}

    def record(name, source, ds, **kw):
        seen[name] = ds.attrs.get("surrogate")
        return _fake_campaign(name, source, ds, **kw)

    monkeypatch.setattr(rp, "_campaign", record)
    data = bl.save_campaign(bl.load_campaign("B", surrogate="published"), tmp_path / "mine.nc")
    code, _, _ = run(capsys, "reproduce", "--campaign", "A", "--data", data, "--surrogate", "turf",
                     "--out", tmp_path / "r", "--no-figures", "--quiet")
    assert code == EXIT_OK
    assert seen == {"A": "turf", "mine": "published"}  # the option names the embedded ones; a file is itself
    rp.reproduce(["B"], out=tmp_path / "r2", figures=False, progress=False, surrogate="turf")
    assert seen["B"] == "turf"
    rp.reproduce(["A"], out=tmp_path / "r4", figures=False, progress=False)  # the default is the turf surrogate
    assert seen["A"] == "turf"
    rp.reproduce(["A"], out=tmp_path / "r5", figures=False, progress=False, surrogate="published")
    assert seen["A"] == "published"
    with pytest.raises(bl.DataError) as e:
        rp.reproduce(["B"], out=tmp_path / "r3", figures=False, progress=False, surrogate="paper")
    assert e.value.option == "surrogate"
    assert not (tmp_path / "r3").exists()


def test_reproduce_on_a_campaign_too_small_for_the_svm_still_writes_the_report(tmp_path, monkeypatch):
    """A small tracked campaign (few slipping bounces) gets the report, Table 2 without the SVM plane and a note."""
    monkeypatch.setattr(rs, "BEYOND_PAPER_LAWS", ())  # the paper's laws are enough here, and much faster
    monkeypatch.setattr(rs, "BOOTSTRAP_RESAMPLES", 5)
    ds = bl.load_campaign("A")
    cls = np.asarray(bl.classify_slip_roll(ds.landing.values, ds.liftoff.values))
    keep = np.r_[np.flatnonzero(cls == "roll")[:60], np.flatnonzero(cls == "slip")[:5]]
    small = bl.save_campaign(ds.isel(bounce=np.sort(keep)).assign_attrs(data_kind="measured"), tmp_path / "s.nc")
    report = rp.reproduce(data=[small], out=tmp_path / "rep", figures=False, progress=False)
    # The SVM's step is skipped, with its reason, in the report and in Report.skipped; the rest is written.
    assert not report.complete
    svm = [why for campaign, what, why in report.skipped if (campaign, what) == ("s", "Table 2: paper's SVM plane")]
    assert len(svm) == 1 and "at least 8 bounces" in svm[0]
    table2 = (tmp_path / "rep" / "tables" / "s_table2.md").read_text()
    assert "delta-optimal plane" in table2 and "SVM plane: overall" not in table2
    assert "paper's SVM plane: skipped" in table2 and "at least 8 bounces" in table2


def test_reproduce_intervals_applies_to_the_data_files_not_to_the_embedded_campaigns(monkeypatch, capsys, tmp_path):
    # Review (stop 19): --campaign A --data FILE --intervals sd failed with "does not apply to an embedded campaign".
    seen = {}

    def record(name, source, ds, **kw):
        seen[name] = ds
        return _fake_campaign(name, source, ds, **kw)

    monkeypatch.setattr(rp, "_campaign", record)
    ds = bl.load_campaign("B", surrogate="published")
    frame = pd.DataFrame(np.hstack([ds["landing"].values, ds["liftoff"].values, np.ones((ds.sizes["bounce"], 3))]),
                         columns=["vx0", "vy0", "w0", "vxF", "vyF", "wF", "vx0_unc", "vy0_unc", "w0_unc"])
    frame.to_csv(tmp_path / "mine.csv", index=False)
    argv = ["reproduce", "--campaign", "A", "--data", tmp_path / "mine.csv", "--velocity-unit", "radius/s",
            "--spin-unit", "rad/s", "--out", tmp_path / "r", "--no-figures", "--quiet"]
    code, _, err = run(capsys, *argv)
    assert code == EXIT_DATA and "--intervals sd" in err  # the file's names do not say: the flag must
    code, _, _ = run(capsys, *argv, "--intervals", "sd")
    assert code == EXIT_OK
    assert seen["A"].attrs["surrogate"] == "turf" and "interval_source" not in seen["A"].attrs
    np.testing.assert_allclose(seen["mine"]["landing_pi"].values, 1.959963984540054, rtol=1e-12)
