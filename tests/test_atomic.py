"""Atomic writes keep the old file on failure, keep its mode, and follow symlinks."""

from __future__ import annotations

import os
import stat

import pytest

from bouncelab.core.atomic import atomic_path, atomic_write_text


def test_failed_write_keeps_previous_file(tmp_path):
    target = tmp_path / "law.json"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("disk full")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["law.json"]  # no temporary file left


def test_new_file_gets_umask_mode_not_0600(tmp_path):
    old = os.umask(0o022)
    try:
        path = atomic_write_text(tmp_path / "new.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


def test_existing_mode_is_kept(tmp_path):
    target = tmp_path / "shared.txt"
    target.write_text("old")
    target.chmod(0o664)
    atomic_write_text(target, "new")
    assert target.read_text() == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o664


def test_symlink_is_kept_and_its_target_replaced(tmp_path):
    real = tmp_path / "real.txt"
    real.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(real)
    atomic_write_text(link, "new")
    assert link.is_symlink()
    assert real.read_text() == "new"


def test_missing_folder_and_directory_target_are_refused(tmp_path):
    from bouncelab.core.errors import OutputError

    with pytest.raises(OutputError) as err:
        atomic_write_text(tmp_path / "nope" / "x.txt", "x")
    assert (err.value.path, err.value.reason) == (str(tmp_path / "nope" / "x.txt"), "no such folder")
    with pytest.raises(OutputError) as err:
        atomic_write_text(tmp_path, "x")
    assert (err.value.path, err.value.reason) == (str(tmp_path), "a folder")


def test_every_to_json_with_a_path_words_a_failed_write_as_an_output_error(tmp_path):
    """Laws, surfaces and exported laws write through core.atomic.write_output: an OutputError naming the path."""
    import bouncelab as bl
    from bouncelab.core.errors import OutputError
    from bouncelab.export import to_c
    from bouncelab.ground import Surface

    target = tmp_path / "missing" / "out.json"
    law = bl.Rigid(r=0.5, mu=0.4)
    for write in (law.to_json, Surface(name="test", law=law, sliding_friction=0.4, stimp_m=3.0).to_json,
                  lambda path: to_c(law, path)):
        with pytest.raises(OutputError) as err:
            write(target)
        assert (err.value.path, err.value.reason) == (str(target), "no such folder")
        assert isinstance(err.value, OSError) and not target.parent.exists()
