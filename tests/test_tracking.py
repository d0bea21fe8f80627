"""bouncelab.tracking on rendered clips: each stage, the sign conventions, and every bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2")

from bouncelab.core.errors import DataError, Hint  # noqa: E402
from bouncelab.tracking import (  # noqa: E402
    FrameRateError,
    clip_settings,
    estimate_background,
    find_ball,
    frame_rotation,
    measure_clip,
    measure_clips,
    read_frames,
    render_clip,
    track_clip,
)

# A small clip: 18 px ball radius on 144 x 288 frames, 14 frames a side.
SMALL = {"size": (144, 288), "radius_px": 18.0, "n_before": 14, "n_after": 14, "contact_frames": 6.0}
LANDING = (1063.0, -810.0, 219.0)
LIFTOFF = (696.7, 440.6, -696.7)  # Rigid.published("A") of LANDING, given to skip compiling the law


@pytest.fixture(scope="module")
def small_clip():
    return render_clip(LANDING, LIFTOFF, **SMALL, frame_offset=0.4, seed=3)


@pytest.fixture(scope="module")
def small_track(small_clip):
    return track_clip(small_clip.frames, fps=small_clip.fps, name="small")


def test_renderer_truth_and_scene(small_clip):
    c = small_clip
    assert c.frames.dtype == np.uint8 and c.frames.shape[1:] == (144, 288)
    assert c.frames.shape[0] == c.truth.sizes["frame"]
    # The ball is bright where the truth says it is, the background dark, the turf strip in between.
    k = 0
    r, col = round(c.truth.row.values[k]), round(c.truth.col.values[k])
    assert c.frames[k, r - 3 : r + 4, col - 3 : col + 4].max() > 150
    assert np.median(c.frames[k, :20, :]) < 20
    surface = int(c.settings["surface_row"])
    assert 30 < np.median(c.frames[k, surface + 2 :, :]) < 90
    # The truth carries the states given, and a rotation that follows the spin.
    assert c.liftoff.tolist() == list(LIFTOFF)
    dtheta = np.diff(c.truth.theta.values) * c.fps
    assert dtheta[0] == pytest.approx(LANDING[2])


def test_renderer_refuses_a_ball_leaving_the_frame():
    with pytest.raises(DataError) as e:  # the ball leaves the frame
        render_clip(LANDING, LIFTOFF, size=(64, 64), radius_px=10, n_before=40, n_after=40)
    assert e.value.option == "size"
    assert [h.option for h in e.value.hints] == ["size", "n_before", "n_after", "radius_px"]


def test_detection_is_sub_pixel_in_flight_and_behind_the_turf(small_clip):
    c = small_clip
    bg = estimate_background(c.frames)
    assert bg.surface_row == pytest.approx(c.settings["surface_row"], abs=0.6)
    phase = c.truth.phase.values
    err_flight, err_contact = [], []
    for k in range(c.frames.shape[0]):
        ball = find_ball(c.frames[k], bg, radius_range=(9, 36))
        assert ball is not None, f"frame {k}"
        e = (ball.col - c.truth.col.values[k], ball.row - c.truth.row.values[k], ball.radius - c.radius_px)
        (err_contact if phase[k] == "contact" else err_flight).append(e)
    flight = np.abs(np.array(err_flight))
    # Sub-pixel: centre and radius within a fifth of a pixel in every flight frame (noise 5 grey levels).
    assert flight.max() < 0.2
    assert np.sqrt((flight[:, :2] ** 2).mean()) < 0.08
    # Pressed into the turf, the visible upper part still places the centre within a third of a pixel.
    assert np.abs(np.array(err_contact)[:, :2]).max() < 0.35


def test_detection_reports_no_ball():
    frames = np.full((6, 64, 64), 5, np.uint8)
    bg = estimate_background(frames)
    assert find_ball(frames[0], bg) is None


@pytest.mark.parametrize("omega", [400.0, -400.0])
def test_rotation_sign_is_the_lab_convention(omega):
    # A ball moving to the right with backspin (omega > 0) turns anticlockwise in the lab frame
    # (y up), which is clockwise on the screen (rows down): the lab angle must come out positive.
    c = render_clip((900.0, -700.0, omega), liftoff=(600.0, 300.0, omega), size=(96, 160), radius_px=14,
                    n_before=4, n_after=4, noise=2.0, seed=5)
    angles = []
    for k in range(1, 4):
        rot = frame_rotation(c.frames[k - 1], c.frames[k], (c.truth.col.values[k - 1], c.truth.row.values[k - 1]),
                             (c.truth.col.values[k], c.truth.row.values[k]), c.radius_px)
        angles.append(rot.angle)
        assert rot.n_inliers >= 4
    assert np.mean(angles) * c.fps == pytest.approx(omega, rel=0.1)


def test_rotation_sign_of_a_picture_turned_on_screen():
    # Turned clockwise as seen on the screen, the picture turns by a *positive* angle in image
    # coordinates (rows down) but clockwise, a negative angle, in the lab frame (y up).
    c = render_clip(LANDING, LIFTOFF, size=(96, 160), radius_px=14, n_before=2, n_after=2, noise=0.0, seed=1)
    img = c.frames[0]
    centre = (float(c.truth.col.values[0]), float(c.truth.row.values[0]))
    for deg in (-5.0, 5.0):  # cv2: a positive angle turns the picture anticlockwise on the screen
        m = cv2.getRotationMatrix2D(centre, deg, 1.0)
        turned = cv2.warpAffine(img, m, img.shape[::-1], flags=cv2.INTER_CUBIC)
        rot = frame_rotation(img, turned, centre, centre, c.radius_px)
        assert rot.angle == pytest.approx(np.deg2rad(deg), rel=0.05)


def test_track_in_scaled_units(small_clip, small_track):
    tr = small_track
    assert tr.attrs["dropped_frames"] == []
    assert tr.attrs["radius_px"] == pytest.approx(18.0, abs=0.1)
    truth = small_clip.truth
    flight = truth.phase.values != "contact"
    # Positions in ball radii, y up from the surface: the truth's y within 0.02 radii.
    assert np.abs(tr.y.values[flight] - truth.y.values[flight]).max() < 0.03
    dx = tr.x.values - truth.x.values
    assert np.ptp(dx[flight]) < 0.04  # x has an arbitrary origin, but the same scale
    # The lowest visible point: y - 1 in flight, the surface line (0) in contact.
    assert np.abs(tr.lowest.values[flight] - (truth.y.values[flight] - 1)).max() < 0.06
    assert np.abs(tr.lowest.values[~flight]).max() < 0.1
    spin = tr.spin.values
    assert np.isnan(spin[0]) and tr.t.values[1] == pytest.approx(1 / 5000)


def test_measure_clip_recovers_the_states_within_their_intervals(small_clip, small_track):
    m = measure_clip(small_track)
    contact = np.flatnonzero(small_clip.truth.phase.values == "contact")
    assert abs(m.attrs["touchdown_index"] - contact[0]) <= 1
    assert abs(m.attrs["liftoff_index"] - contact[-1]) <= 1
    for side, truth in (("landing", small_clip.landing), ("liftoff", small_clip.liftoff)):
        err = np.abs(m[side].values - truth)
        assert (err < m[f"{side}_pi"].values).all(), (side, err, m[f"{side}_pi"].values)
    # The spin is the mean of the measured samples before touch-down (the first frame has none).
    i = m.attrs["touchdown_index"]
    samples = small_track.spin.values[: i - 1]
    assert np.isnan(samples[0])
    assert float(m.landing.sel(component="omega")) == pytest.approx(np.nanmean(samples))
    assert m.attrs["spin_samples_before"] == np.isfinite(samples).sum()
    # Positions method: calibrated intervals, also covering here.
    mp = measure_clip(small_track, method="positions", interval="confidence")
    assert np.abs(mp["landing"].values[:2] - small_clip.landing[:2]).max() < 3 * mp["landing_pi"].values[:2].max()


def test_frames_from_arrays_folders_and_videos(tmp_path, small_clip):
    f = small_clip.frames[:5]
    rgb = np.repeat(f[..., None], 3, axis=-1)
    assert np.array_equal(read_frames(rgb), f)
    # 16-bit frames are scaled to 8 bits by the clip's largest value.
    scaled = np.rint(f * (255.0 / f.max())).astype(np.uint8)
    assert np.array_equal(read_frames(f.astype(np.uint16) * 257), scaled)
    folder = tmp_path / "frames"
    folder.mkdir()
    for k in range(5):  # unpadded numbers: frame_10 must come after frame_2
        cv2.imwrite(str(folder / f"frame_{k * 4}.png"), f[k])
    assert np.array_equal(read_frames(folder), f)
    tif = tmp_path / "tif"
    tif.mkdir()
    for k in range(5):
        cv2.imwrite(str(tif / f"img{k:03d}.tif"), f[k].astype(np.uint16) * 257)
    assert np.array_equal(read_frames(tif), scaled)
    avi = tmp_path / "clip.avi"
    w = cv2.VideoWriter(str(avi), cv2.VideoWriter_fourcc(*"MJPG"), 25, (f.shape[2], f.shape[1]), False)
    for k in range(5):
        w.write(f[k])
    w.release()
    v = read_frames(avi)
    assert v.shape == f.shape and np.abs(v.astype(int) - f).mean() < 3
    np.savez_compressed(tmp_path / "clip.npz", frames=f)
    assert np.array_equal(read_frames(tmp_path / "clip.npz"), f)


def test_bad_frame_sources_name_the_file(tmp_path):
    with pytest.raises(DataError) as e:
        read_frames(tmp_path / "missing.avi")
    assert e.value.file.endswith("missing.avi") and "no such file" in e.value.message
    bad = tmp_path / "broken.avi"
    bad.write_bytes(b"not a video at all")
    with pytest.raises(DataError) as e:
        read_frames(bad)
    assert e.value.file.endswith("broken.avi")
    folder = tmp_path / "imgs"
    folder.mkdir()
    cv2.imwrite(str(folder / "f1.png"), np.zeros((16, 16), np.uint8))
    (folder / "f2.png").write_bytes(b"damaged")
    with pytest.raises(DataError) as e:
        read_frames(folder)
    assert e.value.file.endswith("f2.png")
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(DataError) as e:
        read_frames(empty)
    assert e.value.file.endswith("empty") and "no images" in e.value.message
    with pytest.raises(DataError) as e:  # not (t, h, w) frames
        read_frames(np.zeros((4, 16), np.uint8))
    assert e.value.option == "frames"


def test_bad_clips_get_data_errors_naming_file_and_frames(small_clip):
    with pytest.raises(FrameRateError) as e:  # missing
        track_clip(small_clip.frames, fps=None, name="c1.avi")
    assert (e.value.file, e.value.fps, e.value.source) == ("c1.avi", None, "argument")
    assert e.value.hints[0] == Hint("fps", None, "the camera's recording rate, e.g. 5000")
    with pytest.raises(FrameRateError) as e:  # not positive
        track_clip(small_clip.frames, fps=-5, name="c1.avi")
    assert (e.value.file, e.value.fps) == ("c1.avi", -5)
    with pytest.raises(DataError) as e:  # the ball is not found in any frame
        track_clip(np.full((10, 64, 64), 3, np.uint8), fps=5000, name="dark.avi")
    assert e.value.file == "dark.avi" and "not found" in e.value.message
    short = render_clip(LANDING, LIFTOFF, **{**SMALL, "n_before": 3}, seed=2)
    with pytest.raises(DataError) as e:  # too few frames before touch-down
        measure_clip(track_clip(short.frames, fps=5000, name="short.avi"))
    assert e.value.file == "short.avi" and "frames 0.." in e.value.message  # the frames are named
    tail = render_clip(LANDING, LIFTOFF, **{**SMALL, "n_after": 2}, seed=2)
    with pytest.raises(DataError) as e:
        measure_clip(track_clip(tail.frames, fps=5000, name="tail.avi"))
    assert e.value.file == "tail.avi"


def test_measure_clips_goes_on_past_failures_and_reads_settings(tmp_path, small_clip):
    good = tmp_path / "s1_r1_5000fps.npz"
    np.savez_compressed(good, frames=small_clip.frames)
    other = tmp_path / "s2_r1_5000fps.npz"
    np.savez_compressed(other, frames=render_clip(LANDING, LIFTOFF, **SMALL, seed=4).frames)
    broken = tmp_path / "s3_r1_5000fps.avi"
    broken.write_bytes(b"junk")
    manifest = tmp_path / "manifest.csv"
    manifest.write_text("clip,fps,setting\ns1_r1_5000fps.npz,5000,low\ns2_r1_5000fps.npz,5000,high\n")
    clips = [good, other, broken]
    settings = clip_settings(clips, manifest=manifest)
    assert settings[str(good)].setting == "low" and settings[str(good)].fps == 5000
    assert settings[str(broken)].fps is None
    by_name = clip_settings(clips, pattern=r"(?P<setting>s\d)_r\d_(?P<fps>\d+)fps")
    assert by_name[str(broken)].fps == 5000 and by_name[str(other)].setting == "s2"
    seen = []
    res = measure_clips(clips, settings=settings, progress=lambda d, n, c: seen.append((d, n)))
    assert seen[-1] == (3, 3)
    assert [f.clip for f in res.failures] == [str(broken)]
    assert "frame rate is missing" in res.failures[0].reason
    ds = res.campaign
    assert ds.sizes["bounce"] == 2 and list(ds.setting.values) == ["low", "high"]
    assert np.abs(ds.landing.values[0] - small_clip.landing).max() < ds.landing_pi.values[0].max()


def test_settings_errors(tmp_path):
    m = tmp_path / "m.csv"
    m.write_text("name,fps\na.avi,5000\n")
    with pytest.raises(DataError) as e:  # no 'clip' column
        clip_settings(["a.avi"], manifest=m)
    assert (e.value.file, e.value.column) == (str(m), "clip")
    m.write_text("clip,fps\na.avi,fast\n")
    with pytest.raises(FrameRateError) as e:  # fps is not a number
        clip_settings(["a.avi"], manifest=m)
    assert (e.value.file, e.value.fps, e.value.source) == ("a.avi", "fast", "manifest")
    with pytest.raises(DataError) as e:  # not a regular expression
        clip_settings(["a.avi"], pattern="(?P<fps")
    assert e.value.option == "pattern"


def _write_clips(folder, n, seed0=10):
    folder.mkdir(exist_ok=True)
    rng = np.random.default_rng(seed0)
    for k in range(n):
        landing = (rng.uniform(900, 1200), -rng.uniform(650, 850), rng.uniform(-150, 350))
        liftoff = (0.65 * landing[0], -0.5 * landing[1], -0.6 * landing[0])
        render_clip(landing, liftoff, **SMALL, seed=seed0 + k).save(folder / f"s{k % 4}_r{k}_5000fps.npz")


def test_cli_track_writes_a_campaign_and_summarises_failures(tmp_path, capsys):
    from bouncelab.cli.main import main
    from bouncelab.data.io import load_campaign

    clips = tmp_path / "clips"
    _write_clips(clips, 2)
    (clips / "s9_r9_5000fps.avi").write_bytes(b"not a video")
    out = tmp_path / "campaign.nc"
    rc = main(["track", str(clips), "--pattern", r"(?P<setting>s\d)_r\d+_(?P<fps>\d+)fps", "--synthetic",
               "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 0
    assert "2 of 3 clip(s) measured" in err and "s9_r9_5000fps.avi" in err and "cannot open the video" in err
    assert "3/3 clips" in err  # the progress bar reached the end
    ds = load_campaign(str(out))
    assert ds.sizes["bounce"] == 2 and ds.attrs["data_kind"] == "synthetic surrogate"
    assert list(ds.setting.values) == ["s0", "s1"]
    assert [Path(str(c)).name for c in ds["clip"].values] == ["s0_r0_5000fps.npz", "s1_r1_5000fps.npz"]  # clip of each


def test_cli_track_checks_its_outputs_and_frame_rate_before_tracking(tmp_path, capsys, monkeypatch):
    from bouncelab.cli.main import main
    from bouncelab.tracking import campaign as tracking_campaign

    clips = tmp_path / "clips"
    _write_clips(clips, 1)
    avi = tmp_path / "clip.avi"
    avi.write_bytes(b"junk")
    monkeypatch.setattr(tracking_campaign, "_process_clip", lambda job: pytest.fail("tracked before the checks"))
    (tmp_path / "afile").write_text("x")
    for argv, needle in [
        (["--fps", "5000", "--out", str(tmp_path / "c.csv")], ".nc suffix"),
        (["--fps", "5000", "--out", str(tmp_path / "nodir" / "c.nc")], "does not exist"),
        (["--fps", "5000", "--out", str(tmp_path)], "is a folder"),
        (["--fps", "5000", "--out", str(tmp_path / "c.nc"), "--figures", str(tmp_path / "afile")], "is a file"),
    ]:
        assert main(["track", str(clips), *argv, "--quiet"]) == 2
        assert needle in capsys.readouterr().err
    assert main(["track", str(avi), "--out", str(tmp_path / "c.nc"), "--quiet"]) == 2  # no frame rate anywhere
    assert "--fps is needed" in capsys.readouterr().err


def test_rendered_npz_clips_carry_their_frame_rate(tmp_path, capsys):
    from bouncelab.cli.main import main
    from bouncelab.tracking.frames import stored_fps

    clips = tmp_path / "clips"
    _write_clips(clips, 1)
    clip = next(clips.iterdir())
    renamed = clips / "bounce.npz"  # no fps in the name either
    clip.rename(renamed)
    assert stored_fps(renamed) == 5000.0 and stored_fps(tmp_path / "none.npz") is None
    out = tmp_path / "c.nc"
    assert main(["track", str(renamed), "--out", str(out), "--quiet"]) == 0, capsys.readouterr().err
    assert out.exists()
    # A given --fps that disagrees with the clip's own rate is refused (it was taken silently: speeds off by 20 %);
    # one that agrees is accepted.
    assert main(["track", str(renamed), "--fps", "4000", "--out", str(tmp_path / "d.nc"), "--quiet"]) == 3
    err = capsys.readouterr().err
    assert "fps 4000 frames/s disagrees with the frame rate the clip file records (5000 frames/s)" in err
    assert not (tmp_path / "d.nc").exists()
    assert main(["track", str(renamed), "--fps", "5000", "--out", str(tmp_path / "e.nc"), "--quiet"]) == 0


def test_track_clip_takes_a_rendered_clips_own_frame_rate(tmp_path):
    """The library's track_clip reads a rendered .npz clip's stored rate as the command does (one place,
    frame_times): without fps the same track as with the stored rate; a disagreeing fps is refused, named."""
    from bouncelab.tracking import FrameRateError, track_clip

    clips = tmp_path / "clips"
    _write_clips(clips, 1)
    clip = next(clips.iterdir())
    own = track_clip(clip)
    given = track_clip(clip, fps=5000.0)
    assert own.attrs["fps"] == given.attrs["fps"] == 5000.0
    np.testing.assert_array_equal(own["t"].values, given["t"].values)
    with pytest.raises(FrameRateError) as e:
        track_clip(clip, fps=4000.0)
    assert (e.value.fps, e.value.source) == (4000.0, "argument")
    assert "disagrees with the frame rate the clip file records (5000 frames/s)" in str(e.value)


def test_a_clip_path_that_does_not_exist_is_named_before_any_frame_rate_question(tmp_path, capsys):
    from bouncelab.cli.main import main

    assert main(["track", str(tmp_path / "nope"), "--out", str(tmp_path / "c.nc")]) == 3
    assert f"no such file or folder: '{tmp_path / 'nope'}'" in capsys.readouterr().err


def test_a_missing_clip_among_others_fails_alone(tmp_path, capsys):
    """A missing clip is one failed clip: the others are measured and written (the command's promise)."""
    from bouncelab.cli.main import main

    clips = tmp_path / "clips"
    _write_clips(clips, 1)
    good = next(clips.iterdir())
    out = tmp_path / "c.nc"
    assert main(["track", str(good), str(tmp_path / "nope.npz"), "--out", str(out), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "1 of 2 clip(s) measured" in err and "nope.npz" in err and "no such file" in err
    assert out.exists()


def test_cli_track_exit_codes(tmp_path, capsys):
    from bouncelab.cli.main import main

    bad = tmp_path / "bad.avi"
    bad.write_bytes(b"junk")
    out = tmp_path / "c.nc"
    assert main(["track", str(bad), "--fps", "5000", "--out", str(out), "--quiet"]) == 3
    assert not out.exists()
    assert "no clip could be measured" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        main(["track", str(bad), "--fps", "-1", "--out", str(out)])  # refused by argparse, naming --fps
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        main(["track", str(bad)])  # --out missing
    assert e.value.code == 2


@pytest.mark.slow
def test_cli_track_then_reproduce_on_a_folder_of_rendered_clips(tmp_path):
    from bouncelab.cli.main import main
    from bouncelab.data.io import load_campaign

    # Bounces of the embedded (synthetic) campaign A that fit in a small frame, eight settings of six
    # repeats, so that the fits and the held-out split of `reproduce` have both slip and roll.
    a = load_campaign("A")
    ok = ((np.abs(a.landing.values[:, 0]) < 1500) & (a.landing.values[:, 1] > -1100)
          & (a.liftoff.values[:, 1] < 700) & (np.abs(a.liftoff.values[:, 0]) < 1400))
    good = [s for s in np.unique(a.setting.values) if ok[a.setting.values == s].all()]
    slip = np.abs(a.liftoff.values[:, 0] + a.liftoff.values[:, 2])  # contact-point speed at lift-off
    good.sort(key=lambda s: slip[a.setting.values == s].mean())
    settings = good[:4] + good[-4:]  # mostly rolling and mostly slipping settings
    clips = tmp_path / "clips"
    clips.mkdir()
    for k in np.flatnonzero(np.isin(a.setting.values, settings)):
        render_clip(a.landing.values[k], a.liftoff.values[k], **SMALL, seed=int(k)).save(
            clips / f"s{a.setting.values[k]}_r{k}_5000fps.npz")
    out = tmp_path / "campaign.nc"
    figs = tmp_path / "figs"
    assert main(["track", str(clips), "--pattern", r"(?P<setting>s\d+)_r\d+_(?P<fps>\d+)fps", "--synthetic",
                 "--quiet", "--jobs", "2", "--figures", str(figs), "--out", str(out)]) == 0
    assert len(list(figs.glob("*.png"))) == len(list(clips.iterdir())) == 48
    assert main(["reproduce", "--data", str(out), "--no-figures", "--quiet", "--out", str(tmp_path / "rep")]) == 0
    assert (tmp_path / "rep" / "index.html").exists()


def test_motion_blur_and_the_diagnostic_figure(tmp_path, small_clip, small_track):
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from bouncelab.tracking.figure import diagnostic_figure

    blurred = render_clip(LANDING, LIFTOFF, **{**SMALL, "n_before": 8, "n_after": 8}, motion_blur=0.5, seed=7)
    sharp = render_clip(LANDING, LIFTOFF, **{**SMALL, "n_before": 8, "n_after": 8}, seed=7)
    assert not np.array_equal(blurred.frames, sharp.frames)
    # The exposure ends at the frame time: a blurred ball is centred half an exposure behind it,
    # and the tracker finds that centre (sub-pixel) rather than losing the ball.
    tr = track_clip(blurred.frames, fps=5000, name="blurred")
    assert tr.attrs["dropped_frames"] == []
    k = 4
    behind = 0.25 * np.array([blurred.truth.col.values[k] - blurred.truth.col.values[k - 1],
                              blurred.truth.row.values[k] - blurred.truth.row.values[k - 1]])
    expect = np.array([blurred.truth.col.values[k], blurred.truth.row.values[k]]) - behind
    assert np.abs(np.array([tr.col.values[k], tr.row.values[k]]) - expect).max() < 0.3
    m = measure_clip(small_track)
    out = tmp_path / "fig.png"
    fig = diagnostic_figure(small_clip.frames, small_track, m, out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and len(fig.axes) == 3
    plt.close(fig)


def test_frames_without_the_ball_are_dropped_and_reported(small_clip):
    frames = small_clip.frames.copy()
    frames[2:4] = np.median(small_clip.frames, axis=0).astype(np.uint8)  # the empty scene: no ball
    tr = track_clip(frames, fps=5000, name="gaps")
    assert tr.attrs["dropped_frames"] == [2, 3]
    assert not tr.found.values[2:4].any() and np.isnan(tr.x.values[2:4]).all()
    assert np.isnan(tr.spin.values[4])  # no rotation across a lost frame
    m = measure_clip(tr)  # the longest run of found frames: 4 onwards
    assert m.attrs["first_frame"] == 4 and m.attrs["dropped_frames"] == [2, 3]
    assert abs(m.attrs["touchdown_index"] - np.flatnonzero(small_clip.truth.phase.values == "contact")[0]) <= 1
    # Lost frames that leave too few before the bounce: the error names them.
    frames[4:12] = frames[2]
    with pytest.raises(DataError) as e:
        measure_clip(track_clip(frames, fps=5000, name="gaps.avi"))
    assert e.value.file == "gaps.avi" and "ball lost in frames 2-11" in e.value.message  # the frames are named


def test_mp4_video(tmp_path, small_clip):
    f = small_clip.frames[:6]
    mp4 = tmp_path / "clip.mp4"
    w = cv2.VideoWriter(str(mp4), cv2.VideoWriter_fourcc(*"mp4v"), 25, (f.shape[2], f.shape[1]), False)
    if not w.isOpened():
        pytest.skip("this OpenCV build cannot write MP4")
    for k in range(6):
        w.write(f[k])
    w.release()
    v = read_frames(mp4)
    assert v.shape == f.shape and np.abs(v.astype(int) - f).mean() < 4


@pytest.mark.slow
def test_clips_in_parallel_processes_give_the_same_campaign(tmp_path):
    clips = tmp_path / "clips"
    _write_clips(clips, 3)
    (clips / "broken_5000fps.avi").write_bytes(b"junk")
    paths = sorted(clips.iterdir())
    one = measure_clips(paths, fps=5000)
    two = measure_clips(paths, fps=5000, workers=2)
    assert [f.clip for f in one.failures] == [f.clip for f in two.failures] == [str(clips / "broken_5000fps.avi")]
    for var in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
        assert np.array_equal(one.campaign[var].values, two.campaign[var].values)


@pytest.mark.parametrize("ppm", [1e9, 10.0])
def test_a_scale_that_makes_no_ball_in_the_frame_is_refused(tmp_path, ppm):
    """pixels_per_metre sets the ball's size in pixels: one that makes the ball bigger than the frame or smaller
    than a pixel is not a scale in pixels per metre (millimetres, say), refused naming it before any tracking."""
    from bouncelab.core.errors import DataError
    from bouncelab.tracking import track_clip

    clips = tmp_path / "clips"
    _write_clips(clips, 1)
    with pytest.raises(DataError, match="is the scale in pixels per metre") as e:
        track_clip(next(clips.iterdir()), fps=5000.0, pixels_per_metre=ppm)
    assert e.value.option == "pixels_per_metre"
