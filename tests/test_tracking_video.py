"""Issue 32, item 1: any video FFmpeg reads, through PyAV (the ``video`` extra), with its stream timestamps;
OpenCV where PyAV is not installed."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")
av = pytest.importorskip("av")

import bouncelab.tracking.frames as frames_module  # noqa: E402
from bouncelab.core.errors import DataError  # noqa: E402
from bouncelab.tracking import measure_clip, open_clip, read_frames, render_clip, track_clip  # noqa: E402


def _write(path, frames, pts, *, codec="ffv1", pix_fmt="gray16le", rate=25):
    with av.open(str(path), "w") as out:
        stream = out.add_stream(codec, rate=rate)
        stream.width, stream.height = frames.shape[2], frames.shape[1]
        stream.pix_fmt = pix_fmt
        stream.time_base = Fraction(1, rate)
        for img, p in zip(frames, pts, strict=True):
            frame = av.VideoFrame.from_ndarray(img, format=pix_fmt)
            frame.pts, frame.time_base = p, Fraction(1, rate)
            for packet in stream.encode(frame):
                out.mux(packet)
        for packet in stream.encode():
            out.mux(packet)


def test_a_16_bit_video_keeps_its_bits_and_its_timestamps(tmp_path):
    frames = (np.random.default_rng(1).integers(0, 4096, (6, 32, 48)) * 16).astype(np.uint16)
    _write(tmp_path / "v.mkv", frames, [0, 1, 2, 5, 6, 7])
    clip = open_clip(tmp_path / "v.mkv")
    assert clip.dtype == np.float32 and clip.bit_depth == 16 and clip.time_source == "stream timestamps"
    np.testing.assert_allclose(clip.read(), frames.astype(float) * 255.0 / 65535.0, rtol=1e-6)
    np.testing.assert_allclose(clip.times, np.array([0, 1, 2, 5, 6, 7]) / 25.0)
    assert clip.gaps == [(2, 2)] and clip.fps is None and clip.metadata["container_frame_rate"] == 25.0


def test_a_frame_missing_from_a_videos_timestamps_is_measured_at_the_camera_rate(tmp_path):
    """The container's times are at its playback rate (25 frames/s): the camera's rate is given, and the two
    frames the timestamps skip are counted in, as with a .cine's own times."""
    c = render_clip((1063.0, -810.0, 219.0), (696.7, 440.6, -696.7), size=(160, 320), radius_px=14.0,
                    n_before=26, n_after=26, seed=5)
    n = len(c.frames)
    keep = np.ones(n, bool)
    keep[[18, 19]] = False
    _write(tmp_path / "drop.mkv", c.frames[keep], np.flatnonzero(keep).tolist(), pix_fmt="gray")
    with pytest.raises(DataError, match="missing"):  # a container's timestamps do not give the camera's rate
        track_clip(tmp_path / "drop.mkv")
    tr = track_clip(tmp_path / "drop.mkv", fps=c.fps)
    assert tr.attrs["time_source"] == "fps and stream timestamps" and tr.attrs["missing_after"] == [17]
    np.testing.assert_allclose(tr["t"].values, np.flatnonzero(keep) / c.fps)
    # At the frames' times the landing is measured as from the whole clip; at a uniform rate it is not.
    truth = c.landing[:2]
    whole = measure_clip(track_clip(c.frames, fps=c.fps))["landing"].values[:2]
    at_times = measure_clip(tr)["landing"].values[:2]
    uniform = measure_clip(track_clip(c.frames[keep], fps=c.fps))["landing"].values[:2]
    assert np.abs(at_times - truth).max() < 1.5 * np.abs(whole - truth).max() + 2.0
    assert np.abs(uniform - truth).max() > 3 * np.abs(at_times - truth).max()


def test_other_containers_and_the_opencv_reader(tmp_path, monkeypatch):
    frames = (np.random.default_rng(2).random((5, 32, 48)) * 255).astype(np.uint8)
    _write(tmp_path / "v.nut", frames, range(5), codec="ffv1", pix_fmt="gray")  # a suffix OpenCV's list lacks
    np.testing.assert_array_equal(read_frames(tmp_path / "v.nut"), frames)
    avi = tmp_path / "v.avi"
    w = cv2.VideoWriter(str(avi), cv2.VideoWriter_fourcc(*"MJPG"), 25, (48, 32), False)
    for f in frames:
        w.write(f)
    w.release()
    by_pyav = open_clip(avi)
    monkeypatch.setattr(frames_module, "VIDEO_READER", "opencv")
    by_opencv = open_clip(avi)
    assert by_pyav.time_source == "stream timestamps" and by_opencv.times is None
    assert np.abs(by_pyav.read().astype(int) - by_opencv.read()).mean() < 1.5
    monkeypatch.setattr(frames_module, "VIDEO_READER", "pyav")
    (tmp_path / "junk.webm").write_bytes(b"not a video")
    with pytest.raises(DataError) as e:
        open_clip(tmp_path / "junk.webm")
    assert e.value.file.endswith("junk.webm") and "cannot open the video" in e.value.message
