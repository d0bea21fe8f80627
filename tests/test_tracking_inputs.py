"""Issue 22, item 7: clips that cannot be right are refused, and a clip is read within a memory budget.

Impossible frame rates (a typed error with the value and its source), frames read frame by frame (memory
bounded by the frames needed, not the clip's length; the same track as from memory), truncated or damaged
files named, negative pixel values refused rather than clipped, a clip played backwards refused.
"""

from __future__ import annotations

import math
import re
import tracemalloc

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")

import bouncelab.tracking.frames as frames_module  # noqa: E402
from bouncelab.analysis.measurement import estimate_velocity, measure_bounce  # noqa: E402
from bouncelab.analysis.trajectories import simulate_tracked_bounce  # noqa: E402
from bouncelab.core.errors import DataError  # noqa: E402
from bouncelab.tracking import (  # noqa: E402
    FrameRateError,
    clip_settings,
    measure_clip,
    measure_clips,
    read_frames,
    render_clip,
    track_clip,
)

SMALL = {"size": (144, 288), "radius_px": 18.0, "n_before": 14, "n_after": 14, "contact_frames": 6.0}
LANDING = (1063.0, -810.0, 219.0)
LIFTOFF = (696.7, 440.6, -696.7)  # Rigid.published("A") of LANDING


@pytest.fixture(scope="module")
def clip():
    return render_clip(LANDING, LIFTOFF, **SMALL, frame_offset=0.4, seed=3)


@pytest.fixture(scope="module")
def track(clip):
    return track_clip(clip.frames, fps=clip.fps, name="small")


# ------------------------------------------------------------------------------------------------ frame rates


@pytest.mark.parametrize("fps", [1e300, 1e30, 2e7, 0.5, 1e-300])
def test_an_impossible_frame_rate_is_a_data_error_with_its_value_and_source(clip, fps):
    with pytest.raises(FrameRateError) as e:
        measure_clip(track_clip(clip.frames, fps=fps, name="c.avi"))  # was a ZeroDivisionError for 1e300
    assert (e.value.file, e.value.fps, e.value.source) == ("c.avi", fps, "argument")


def test_a_clip_storing_an_impossible_frame_rate_fails_alone_naming_the_source(tmp_path, clip):
    bad = tmp_path / "bad.npz"
    np.savez_compressed(bad, frames=clip.frames, fps=1e300)
    good = tmp_path / "good.npz"
    clip.save(good)
    res = measure_clips([bad, good])  # was a ZeroDivisionError out of measure_clips
    assert [f.clip for f in res.failures] == [str(bad)] and res.campaign.sizes["bounce"] == 1
    err = res.failures[0].error
    assert isinstance(err, DataError) and err.source == "clip file" and err.fps == 1e300
    assert "1e+300" in res.failures[0].reason and "stored in the clip file" in res.failures[0].reason


@pytest.mark.parametrize("stored", [0.0, -5.0, math.nan, math.inf, "5000", True, 5000 + 1j, [5000.0, 5000.0]],
                         ids=["zero", "negative", "nan", "inf", "text", "bool", "complex", "two"])
@pytest.mark.parametrize("given", [None, 5000.0])
def test_a_stored_frame_rate_is_checked_where_the_clip_is_opened(tmp_path, clip, stored, given):
    """A hostile .npz's stored fps is a FrameRateError naming the clip file, with or without a given fps (a given
    one was divided by a stored 0 and taken as agreeing with a stored NaN; text, a bool or a complex number was read
    as a number, two numbers as no rate at all)."""
    path = tmp_path / "hostile.npz"
    np.savez_compressed(path, frames=clip.frames, fps=stored)
    with pytest.raises(FrameRateError) as e:
        track_clip(path, fps=given)
    assert e.value.source == "clip file" and e.value.file == str(path)
    assert "the fps stored in the clip file" in e.value.message
    if np.ndim(stored) == 0:
        assert e.value.fps == stored or math.isnan(stored)


def test_frame_rates_from_settings_name_where_they_came_from(tmp_path):
    manifest = tmp_path / "m.csv"
    manifest.write_text("clip,fps\na.avi,1e300\nb.avi,\n")
    with pytest.raises(FrameRateError) as e:
        clip_settings(["a.avi"], manifest=manifest)
    assert e.value.source == "manifest" and e.value.fps == "1e300"
    assert "the manifest's fps" in e.value.message  # said in words too
    with pytest.raises(FrameRateError) as e:
        clip_settings(["s1_1e300fps.avi"], pattern=r"_(?P<fps>[\d.e+]+)fps")
    assert e.value.source == "file name"
    with pytest.raises(DataError) as e:  # --fps inf: the argument, not the file name
        clip_settings(["a.avi"], fps=float("inf"), pattern=r"(?P<setting>s\d)")
    assert e.value.source == "argument" and "file name" not in str(e.value)
    # an empty manifest cell keeps the frame rate given as the argument
    s = clip_settings(["b.avi"], fps=5000, manifest=manifest)["b.avi"]
    assert s.fps == 5000 and s.fps_source == "argument"


def test_the_measurement_refuses_frame_times_that_are_not_seconds():
    tr = simulate_tracked_bounce([1063.0, -810.0, 219.0], [700.0, 280.0, -550.0], seed=0)
    for scale in (1e-300, 1e-100, 1e100):
        with pytest.raises(DataError) as e:  # the frame interval: 1e-300 was a ZeroDivisionError
            measure_bounce(tr.assign_coords(t=tr["t"] * scale))
        assert e.value.column == "t"
    t = np.arange(10) / 5000.0
    with pytest.raises(DataError) as e:  # positions whose squares overflow: the velocity cannot be computed
        estimate_velocity(t, 1e200 * np.arange(10.0) ** 2, t[-1])
    assert e.value.column == "pos"
    with pytest.raises(DataError) as e:  # OverflowError before
        estimate_velocity(t, np.arange(10.0), 1e200, method="positions")
    assert e.value.column == "pos"


# ------------------------------------------------------------------------------------------------ memory


@pytest.fixture(scope="module")
def long_clip(clip, tmp_path_factory):
    """The clip six times over (204 frames, 8.5 MB), as a .npy and a .npz file, and its track from memory."""
    frames = np.concatenate([clip.frames] * 6)
    folder = tmp_path_factory.mktemp("long")
    np.save(folder / "long.npy", frames)
    np.savez_compressed(folder / "long.npz", frames=frames)
    return frames, folder / "long.npy", folder / "long.npz", track_clip(frames, fps=clip.fps, name="long")


BUDGET = 5 << 20  # above the working memory of these frames (4.4 MiB), below twice the clip: read frame by frame


def test_a_clip_file_is_tracked_frame_by_frame_giving_the_same_track(long_clip):
    import xarray as xr

    from bouncelab.tracking import tracker

    _, npy, npz, track = long_clip
    assert track["found"].values.mean() > 0.9
    for source in (npz, npy):
        xr.testing.assert_identical(track_clip(source, fps=5000, name="long", memory_budget=BUDGET), track)
    # Crops of the ball beyond their share of the budget: the rotation reads the frames again, same result.
    keep = tracker._Crops.__init__
    try:
        tracker._Crops.__init__ = lambda self, shape, limit: keep(self, shape, 200_000)
        xr.testing.assert_identical(track_clip(npz, fps=5000, name="long", memory_budget=BUDGET), track)
    finally:
        tracker._Crops.__init__ = keep
    with pytest.raises(DataError) as e:  # says how much tracking takes, and the budget
        track_clip(npy, fps=5000, memory_budget=4 << 20)
    assert e.value.option == "memory_budget" and e.value.hints[0].option == "memory_budget"
    assert re.search(r"takes about 4\.4\d MiB of memory .* more than the memory budget of 4 MiB", e.value.message)


def test_tracking_memory_does_not_grow_with_the_clip(long_clip, monkeypatch):
    frames, npy, _, track = long_clip
    monkeypatch.setattr(frames_module, "MEMORY_BUDGET", BUDGET, raising=False)
    tracemalloc.start()
    try:
        tr = track_clip(npy, fps=5000, name="long")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    np.testing.assert_array_equal(tr["x"].values, track["x"].values)
    assert peak < 0.6 * frames.nbytes, (peak, frames.nbytes)  # was more than the whole clip


def test_reading_a_whole_clip_beyond_the_budget_says_how_much_it_would_take(tmp_path, long_clip):
    frames, npy, npz, _ = long_clip
    for path in (npy, npz):
        with pytest.raises(DataError) as e:
            read_frames(path, memory_budget=BUDGET)
        assert e.value.option == "memory_budget"
        assert "would take 8.07 MiB, more than the memory budget of 5 MiB" in e.value.message  # how much
        np.testing.assert_array_equal(read_frames(path), frames)


def test_a_huge_clip_is_refused_before_any_of_it_is_read(tmp_path, clip):
    # A (10^5, 1000, 1000) clip (a sparse file): refused before any of it is read (was a MemoryError).
    big = tmp_path / "big.npy"
    with open(big, "wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "|u1", "fortran_order": False,
                                                  "shape": (100_000, 1000, 1000)})
        fh.truncate(fh.tell() + 100_000 * 1000 * 1000)
    with pytest.raises(DataError) as e:
        read_frames(big)
    assert e.value.file.endswith("big.npy") and e.value.option == "memory_budget"
    assert "would take 93.1 GiB" in e.value.message  # how much
    with pytest.raises(DataError) as e:
        read_frames(clip.frames, memory_budget=-1)
    assert e.value.option == "memory_budget"


def test_truncated_or_damaged_clip_files_are_data_errors_naming_the_file(tmp_path, clip):
    npz = tmp_path / "cut.npz"
    clip.save(npz)
    npz.write_bytes(npz.read_bytes()[: npz.stat().st_size // 2])
    huge = tmp_path / "huge.npy"  # a header claiming 93 GiB over a few bytes (was a MemoryError)
    with open(huge, "wb") as fh:
        np.lib.format.write_array_header_1_0(fh, {"descr": "|u1", "fortran_order": False,
                                                  "shape": (100_000, 1000, 1000)})
        fh.write(b"\0" * 1000)
    npy = tmp_path / "cut.npy"
    np.save(npy, clip.frames)
    npy.write_bytes(npy.read_bytes()[:-100])
    nofr = tmp_path / "noframes.npz"
    np.savez(nofr, images=clip.frames)
    avi = tmp_path / "cut.avi"
    w = cv2.VideoWriter(str(avi), cv2.VideoWriter_fourcc(*"MJPG"), 25, clip.frames.shape[:0:-1], False)
    for f in clip.frames:
        w.write(f)
    w.release()
    whole = avi.read_bytes()
    avi.write_bytes(whole[: len(whole) // 2])  # half the frames, the index lost
    for path, needle in ((npz, "truncated or damaged"), (huge, "truncated"), (npy, "truncated"),
                         (nofr, "no 'frames' array"), (avi, "truncated or damaged")):
        with pytest.raises(DataError) as e:
            track_clip(path, fps=5000)
        assert e.value.file.endswith(path.name) and needle in e.value.message, (path, str(e.value))
        with pytest.raises(DataError):
            read_frames(path)


# ------------------------------------------------------------------------------------------------ values


def test_negative_pixel_values_are_refused_not_clipped(clip):
    for frames in (clip.frames.astype(np.int16) - 20, clip.frames.astype(np.float32) / 255.0 - 0.01):
        with pytest.raises(DataError) as e:  # negative values were clipped at 0 without a word
            track_clip(frames, fps=5000, name="signed.npz")
        assert e.value.file == "signed.npz" and "negative values (first in frame 0" in e.value.message
    # Signed frames without negative values read as their unsigned twins.
    np.testing.assert_array_equal(read_frames(clip.frames.astype(np.int16)), clip.frames)
    np.testing.assert_array_equal(read_frames(clip.frames.astype(np.int16) * 100),
                                  read_frames(clip.frames.astype(np.uint16) * 100))


def test_a_folder_mixing_8_and_16_bit_images_is_refused(tmp_path, clip):
    for k, f in enumerate(clip.frames[:4]):
        cv2.imwrite(str(tmp_path / f"f{k}.png"), f if k != 2 else f.astype(np.uint16) * 257)
    with pytest.raises(DataError) as e:  # np.stack made all 16-bit: 8-bit ones 257 x darker
        read_frames(tmp_path)
    assert e.value.file.endswith("f2.png") and "uint16" in e.value.message


def test_a_clip_played_backwards_is_refused(tmp_path, clip, track):
    assert measure_clip(track).attrs["clip"] == "small"  # forward: measured
    backwards = track_clip(clip.frames[::-1], fps=clip.fps, name="reversed.avi")
    with pytest.raises(DataError) as e:  # was measured as a bounce gaining energy x2
        measure_clip(backwards)
    assert e.value.file == "reversed.avi" and "kinetic energy" in e.value.message and "backwards" in e.value.message
    kept = measure_clip(backwards, energy_check=False)
    e0 = float(kept.landing.values @ (kept.landing.values * [1, 1, 0.4]))
    e1 = float(kept.liftoff.values @ (kept.liftoff.values * [1, 1, 0.4]))
    assert e1 > 1.8 * e0
    path = tmp_path / "reversed.npz"
    np.savez_compressed(path, frames=clip.frames[::-1])
    res = measure_clips([path], fps=clip.fps)
    assert res.campaign is None and "kinetic energy" in res.failures[0].reason
