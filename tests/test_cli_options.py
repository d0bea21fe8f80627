"""The argument types shared by the subcommands (bouncelab.cli.options)."""

import argparse

import pytest

from bouncelab.cli.options import finite, positive, whole


@pytest.mark.parametrize("text", ["x", "nan", "inf", "-inf", ""])
def test_finite_refuses_what_is_not_a_finite_number(text):
    with pytest.raises(argparse.ArgumentTypeError):
        finite(text)


def test_finite_and_positive_accept_numbers():
    assert finite("-2.5e3") == -2500.0
    assert positive("1e-9") == 1e-9


@pytest.mark.parametrize("text", ["0", "-1", "nan"])
def test_positive_refuses_zero_negative_and_nan(text):
    with pytest.raises(argparse.ArgumentTypeError):
        positive(text)


def test_whole_checks_its_minimum_and_says_what_it_counts():
    jobs = whole(1, "processes")
    assert jobs("3") == 3
    with pytest.raises(argparse.ArgumentTypeError, match="processes"):
        jobs("0")
    with pytest.raises(argparse.ArgumentTypeError):
        jobs("1.5")
    assert whole(0)("0") == 0


def test_parser_names_the_option_and_exits_2(capsys):
    from bouncelab.cli.main import main

    with pytest.raises(SystemExit) as exit_:
        main(["reproduce", "--bootstrap", "-1"])
    assert exit_.value.code == 2
    assert "--bootstrap" in capsys.readouterr().err


def test_a_folder_of_clips_includes_npz_and_npy_frame_files(tmp_path):
    from bouncelab.cli.track import expand_clips

    for name in ("a.npy", "b.npz", "c.mp4", "notes.txt"):
        (tmp_path / name).write_bytes(b"")
    assert [p.rsplit("/", 1)[1] for p in expand_clips([str(tmp_path)])] == ["a.npy", "b.npz", "c.mp4"]
