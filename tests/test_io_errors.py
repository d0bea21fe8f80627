"""Issue 22, item 7: typed errors from loading and saving, and the CF spellings of per-minute spin.

A folder given to load_campaign, an Excel file without its reader, a campaign saved where it cannot be
written: each a bouncelab error naming the path (they were IsADirectoryError, ImportError, PermissionError).
``min-1`` (CF / UDUNITS) was refused where ``rpm`` loaded.
"""

from __future__ import annotations

import errno
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from bouncelab.core.errors import DataError
from bouncelab.core.units import canonical_unit, spin_to_scaled
from bouncelab.data.io import load_campaign, save_campaign
from bouncelab.data.io import read as io_read

ROOT = Path(__file__).resolve().parents[1]

# Two bounces in m/s and a spin unit (written in the header or a units row).
ROWS = [(20.1, -15.2, 3000.0, 9.5, 5.1, 1500.0), (12.25, -22.5, -1200.0, 6.1, 7.7, 600.0)]
NAMES = ["vx0", "vy0", "w0", "vxF", "vyF", "wF"]
RPM = 2 * math.pi / 60


def _csv(path: Path, spin_unit: str | None, *, in_header: bool = False, rows=ROWS) -> Path:
    units = ["m/s", "m/s", spin_unit, "m/s", "m/s", spin_unit]
    if spin_unit is None:
        lines = [",".join(NAMES)]
    elif in_header:
        lines = [",".join(f"{n} [{u}]" for n, u in zip(NAMES, units, strict=True))]
    else:
        lines = [",".join(NAMES), ",".join(units)]
    lines += [",".join(repr(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


# ------------------------------------------------------------------------------------------------ loading


def test_a_folder_is_a_data_error_naming_it(tmp_path):
    with pytest.raises(DataError) as e:  # was IsADirectoryError
        load_campaign(tmp_path)
    assert e.value.file == str(tmp_path) and "directory" in e.value.message


@pytest.mark.parametrize(("suffix", "package"), [(".xls", "xlrd"), (".xlsx", "openpyxl")])
def test_an_excel_file_without_its_reader_says_what_to_install(tmp_path, monkeypatch, suffix, package):
    path = tmp_path / f"book{suffix}"
    path.write_bytes(b"\xd0\xcf\x11\xe0 not read: the reader is missing")
    monkeypatch.setattr(io_read, "module_available", lambda name: name != package)
    with pytest.raises(DataError) as e:
        load_campaign(path)  # was an ImportError
    assert e.value.file == str(path)
    assert f"needs the package {package}: pip install 'bouncelab[excel]'" in e.value.message


def test_the_excel_extra_installs_both_readers():
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    names = {req.split(">")[0].split("=")[0].split("[")[0].strip().lower() for req in extras["excel"]}
    assert {"openpyxl", "xlrd"} <= names


# ------------------------------------------------------------------------------------------------ saving


def _campaign():
    return load_campaign("A")


def test_output_error_is_one_type_for_the_library_and_the_command_line():
    from bouncelab.cli.reproduce import OutputError as CliOutputError
    from bouncelab.core.errors import BouncelabError, OutputError

    assert CliOutputError is OutputError
    err = OutputError("cannot write 'x'", path="x", errno=errno.EACCES)
    assert isinstance(err, BouncelabError) and isinstance(err, OSError) and isinstance(err, ValueError)
    assert (str(err), err.path, err.errno) == ("cannot write 'x'", "x", errno.EACCES)


def test_saving_where_it_cannot_be_written_is_an_output_error_naming_the_path(tmp_path, monkeypatch):
    import tempfile

    from bouncelab.core.errors import OutputError

    ds = _campaign()
    target = tmp_path / "c.nc"

    def refuse(*args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied", str(tmp_path))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)  # a read-only folder, whoever runs the test
    with pytest.raises(OutputError) as e:  # was a bare PermissionError
        save_campaign(ds, target)
    assert (e.value.path, e.value.reason, e.value.errno) == (str(target), "Permission denied", errno.EACCES)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    (tmp_path / "in_the_way.nc").mkdir()
    with pytest.raises(OutputError) as e:
        save_campaign(ds, tmp_path / "in_the_way.nc")
    assert isinstance(e.value, OSError) and e.value.path == str(tmp_path / "in_the_way.nc")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc takes no new files on Linux only")
def test_saving_into_proc_is_an_output_error():
    from bouncelab.core.errors import OutputError

    with pytest.raises(OutputError) as e:
        save_campaign(_campaign(), "/proc/bouncelab-campaign.nc")
    assert e.value.path == "/proc/bouncelab-campaign.nc"


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes to read-only folders")
def test_saving_into_a_read_only_folder_is_an_output_error(tmp_path):
    from bouncelab.core.errors import OutputError

    ro = tmp_path / "ro"
    ro.mkdir()
    os.chmod(ro, 0o555)
    try:
        with pytest.raises(OutputError) as e:
            save_campaign(_campaign(), ro / "c.nc")
        assert (e.value.path, e.value.errno) == (str(ro / "c.nc"), errno.EACCES)
    finally:
        os.chmod(ro, 0o755)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc takes no new files on Linux only")
def test_track_out_where_it_cannot_be_written_is_an_output_problem(tmp_path, capsys):
    """Exit 2 (an output problem, as the docs say), not 3 ("data error")."""
    pytest.importorskip("cv2")
    from bouncelab.cli.main import main
    from bouncelab.tracking import render_clip

    clip = tmp_path / "s1_r1.npz"
    render_clip((1063.0, -810.0, 219.0), (696.7, 440.6, -696.7), size=(144, 288), radius_px=18.0, n_before=14,
                n_after=14, contact_frames=6.0, seed=3).save(clip)
    assert main(["track", str(clip), "--out", "/proc/bouncelab-campaign.nc", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "/proc/bouncelab-campaign.nc" in err and "data error" not in err


# ------------------------------------------------------------------------------------------------ units


@pytest.mark.parametrize("unit", ["min-1", "min^-1", "1/min", "min**-1", "min⁻¹", "rev/min", "r/min", "rev min-1",
                                  "revolutions per minute", "RPM"])
def test_per_minute_spin_is_rpm_wherever_a_unit_is_named(tmp_path, unit):
    assert canonical_unit(unit, "spin") == "rpm"  # min-1 was refused
    assert spin_to_scaled(60.0, unit) == pytest.approx(2 * math.pi)
    with pytest.raises(DataError, match="unknown velocity unit"):
        canonical_unit(unit, "velocity")
    expected = np.array([[r[2] * RPM for r in ROWS], [r[5] * RPM for r in ROWS]]).T
    for in_header in (True, False):  # a unit in the header, or in a units row
        ds = load_campaign(_csv(tmp_path / f"{in_header}.csv", unit, in_header=in_header))
        got = np.column_stack([ds.landing.values[:, 2], ds.liftoff.values[:, 2]])
        np.testing.assert_allclose(got, expected, rtol=1e-12)
    # units= names it too (the command line's --spin-unit passes it on)
    ds = load_campaign(_csv(tmp_path / "bare.csv", None), units={"velocity": "m/s", "spin": unit})
    np.testing.assert_allclose(ds.landing.values[:, 2], expected[:, 0], rtol=1e-12)


def test_cli_spin_unit_min_1(tmp_path, capsys):
    from bouncelab.cli.main import main

    bare = _csv(tmp_path / "bare.csv", None, rows=ROWS * 3)
    assert main(["info", str(bare), "--velocity-unit", "m/s", "--spin-unit", "min-1"]) == 0, capsys.readouterr().err
    assert "rpm" in capsys.readouterr().out
