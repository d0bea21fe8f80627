"""One clip tracked frame by frame: ball centre, lowest visible point and spin samples (:func:`track_clip`).

The output is the per-frame track that
:func:`bouncelab.analysis.measurement.measure_bounce` works from, in the
library's scaled units: positions in ball radii with ``y`` up and the surface
at ``y = 0``, time in seconds, spin in rad/s anticlockwise.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import checks
from bouncelab.core.errors import DataError
from bouncelab.core.units import BALL_RADIUS_M
from bouncelab.tracking.detect import estimate_background, find_ball
from bouncelab.tracking.frames import Clip, open_clip
from bouncelab.tracking.rates import FPS_AGREEMENT, FPS_RANGE, FPS_SOURCES, FrameRateError, agree, check_fps
from bouncelab.tracking.rotation import _window_rotation, rotation_window

__all__ = ["FPS_AGREEMENT", "FPS_RANGE", "FPS_SOURCES", "FrameRateError", "check_fps", "frame_times", "track_clip"]

def track_clip(
    source,
    *,
    fps: float | None = None,
    ball_radius_m: float = BALL_RADIUS_M,
    pixels_per_metre: float | None = None,
    radius_range: tuple[float, float] | None = None,
    name: str | None = None,
    memory_budget: float | None = None,
    fps_source: str = "argument",
) -> xr.Dataset:
    """Track the ball through a clip.

    The clip is read frame by frame (the background's sampled frames, then the
    ball in each frame; the rotation between frames is measured on the ball's
    surroundings kept in that pass), so the memory taken does not grow with its
    length; a clip within half the memory budget is read once and kept
    (:func:`~bouncelab.tracking.frames.open_clip`). The track is the same
    whichever way the frames are read.

    Parameters
    ----------
    source
        A Phantom ``.cine``, a Photron ``.mraw`` (or its header), a video
        file, a folder of images, a ``.npy`` file, a ``.npz`` with
        ``frames``, an array (t, h, w) or (t, h, w, 3), or a
        :class:`~bouncelab.tracking.frames.Clip`.
    fps
        Frame rate, frames/s, within :data:`FPS_RANGE`. Not needed for a
        camera file, which records its frames' times
        (:attr:`~bouncelab.tracking.frames.Clip.times`): the track is measured
        at those times, so frames the camera dropped leave a gap rather than
        shifting every later frame; an ``fps`` given with such a file must
        agree with its times (within :data:`FPS_AGREEMENT`). Required for
        other sources (video containers often store a playback rate, not the
        camera's).
    ball_radius_m
        Ball radius, m (default 21.35 mm); with ``pixels_per_metre`` it sets
        the scale.
    pixels_per_metre
        Image scale. ``None`` (default): the scale is the ball's detected
        radius (median over the frames where the ball is clear of the turf),
        so positions are in ball radii directly.
    radius_range
        Smallest and largest ball radius to look for, pixels (default 4 px to
        half the frame height).
    name
        Name of the clip in errors and attrs (default: the path).
    memory_budget
        Bytes the clip's frames may take (default
        :data:`bouncelab.tracking.frames.MEMORY_BUDGET`, 1 GiB).
    fps_source
        Where ``fps`` came from, one of :data:`FPS_SOURCES`, for the errors.

    Returns
    -------
    xarray.Dataset
        Over ``frame`` (every frame of the clip) with coordinate ``t`` (s; a
        camera file's own times, from its trigger, else ``frame / fps``):
        ``x``, ``y`` (ball centre, radii; y up, surface at 0), ``lowest``
        (height of the lowest visible point, radii), ``spin`` (rotation from
        the previous frame over the frame period, rad/s anticlockwise; NaN
        for the first frame, after a frame where the ball was lost and where
        too few features matched), ``found`` (bool), ``col``, ``row``,
        ``radius_px`` (pixels, row down), ``n_inliers`` (matched features
        kept). attrs: ``clip``, ``fps``, ``time_source`` (``"TIME64 block"``,
        ``"frame rate"``: the file's header; ``"fps"``: the rate given;
        ``"fps and stream timestamps"``: the rate given, with the frames a
        video's timestamps show missing),
        ``missing_after`` and ``missing_counts`` (frames the camera did not
        record: ``missing_counts[i]`` after frame ``missing_after[i]``),
        ``radius_px`` (scale), ``surface_row``, ``dropped_frames`` (list of
        frames where the ball was not found).

    Raises
    ------
    FrameRateError
        A missing frame rate, one outside :data:`FPS_RANGE`, or one that
        disagrees with the times a camera file records (a
        :class:`~bouncelab.core.errors.DataError` with the value and its source).
    DataError
        Unreadable, truncated or damaged source, frames that would take more
        than the memory budget (saying how much), or a ball found in no frame.
    """
    if name is not None:
        label = name
    elif isinstance(source, Clip):
        label = source.name
    else:
        label = "array" if isinstance(source, np.ndarray) else str(source)
    if fps is not None:
        fps = check_fps(fps, label, fps_source)
    if not (0 < checks.finite(ball_radius_m, "ball_radius_m", error=DataError) < 1):
        raise DataError(f"ball_radius_m must be a radius in metres in (0, 1); got {ball_radius_m!r}", file=label,
                        option="ball_radius_m")
    if pixels_per_metre is not None:
        checks.positive(pixels_per_metre, "pixels_per_metre", error=DataError)
    frames = open_clip(source, name=label, memory_budget=memory_budget)
    times, fps, time_source = frame_times(frames, fps, label, fps_source)
    frames.check_working_memory()
    n, h, _w = frames.shape
    if radius_range is None:
        radius_range = (4.0, h / 2.0)
        if pixels_per_metre is not None:
            r_px = pixels_per_metre * ball_radius_m
            if not 1.0 <= r_px <= max(h, _w):
                raise DataError(f"pixels_per_metre={pixels_per_metre:g} makes the ball {r_px:.3g} px in radius in "
                                f"{_w} x {h} frames: is the scale in pixels per metre?", file=label,
                                option="pixels_per_metre")
            radius_range = (0.8 * r_px, 1.2 * r_px)
    bg = estimate_background(frames)

    col = np.full(n, np.nan)
    row = np.full(n, np.nan)
    rad = np.full(n, np.nan)
    low = np.full(n, np.nan)
    near = None
    # A clip not held in memory is not read again for the rotation: each frame's ball is kept with a margin.
    crops = None if frames.in_memory else _Crops(frames.shape, frames.memory_budget // 4)
    prev = None
    for k, frame in frames.frames():
        predicted = None
        if k >= 2 and np.isfinite(col[k - 1]) and np.isfinite(col[k - 2]):
            ahead = (times[k] - times[k - 1]) / (times[k - 1] - times[k - 2])  # 1 unless frames are missing
            predicted = (col[k - 1] + ahead * (col[k - 1] - col[k - 2]),
                         row[k - 1] + ahead * (row[k - 1] - row[k - 2]), rad[k - 1])
        c = find_ball(frame, bg, radius_range=radius_range, near=near, predicted=predicted)
        if c is None:
            near = None
        else:
            col[k], row[k], rad[k], low[k] = c.col, c.row, c.radius, c.lowest_row
            near = (c.col, c.row, c.radius)
        if crops is not None and prev is not None:
            crops.keep(k - 1, prev, col, row, rad)  # now that the motion to frame k is known
        prev = frame
    if crops is not None and prev is not None:
        crops.keep(n - 1, prev, col, row, rad)
    del prev
    found = np.isfinite(col)
    if not found.any():
        raise DataError(f"the ball was not found in any of the {n} frames (is it bright on a dark background, "
                        f"and between {radius_range[0]:.0f} and {radius_range[1]:.0f} px in radius?)", file=label)

    # Scale: the detected radius where the ball is clear of the turf (its whole rim visible).
    clear = found.copy()
    if bg.surface_row is not None:
        clear &= row + rad < bg.surface_row - 2.0
    if pixels_per_metre is not None:
        r_scale = pixels_per_metre * ball_radius_m
    else:
        r_scale = float(np.median(rad[clear] if clear.any() else rad[found]))

    spin = np.full(n, np.nan)
    inl = np.zeros(n, dtype=int)
    dts = np.diff(times, prepend=times[0] - 1.0 / fps)  # each frame's interval from the last (s)
    guess = 0.0  # rad/s
    pairs = (np.flatnonzero(found[1:] & found[:-1]) + 1).tolist()  # frames whose rotation from the last is measured
    for k, a, b, origin in _rotation_windows(frames, crops, pairs, col, row, r_scale):
        rot = _window_rotation(a, b, origin, (col[k - 1], row[k - 1]), (col[k], row[k]), r_scale,
                               guess=guess * dts[k], surface_row=bg.surface_row, max_features=40, min_inliers=4,
                               refine=True)
        inl[k] = rot.n_inliers
        if np.isfinite(rot.angle):
            spin[k] = rot.angle / dts[k]
            guess = spin[k]

    ref = bg.surface_row if bg.surface_row is not None else float(h)
    gaps = frames.gaps if time_source != "fps" else []
    attrs: dict[str, Any] = {
        "clip": label,
        "fps": fps,
        "time_source": time_source,
        "missing_after": [k for k, _ in gaps],
        "missing_counts": [m for _, m in gaps],
        "radius_px": r_scale,
        "scale_from": "pixels_per_metre" if pixels_per_metre is not None else "detected radius",
        "ball_radius_m": float(ball_radius_m),
        "surface_row": "none" if bg.surface_row is None else float(bg.surface_row),
        "dropped_frames": np.flatnonzero(~found).tolist(),
        "conventions": "x, y in ball radii (y up, surface at y = 0); spin in rad/s anticlockwise; t in s",
    }
    return xr.Dataset(
        {
            "x": ("frame", col / r_scale, {"units": "radius", "long_name": "ball-centre x"}),
            "y": ("frame", (ref - row) / r_scale, {"units": "radius", "long_name": "ball-centre y"}),
            "lowest": ("frame", (ref - low) / r_scale, {
                "units": "radius", "long_name": "height of the lowest visible point of the ball"}),
            "spin": ("frame", spin, {"units": "rad/s", "long_name": "spin from the rotation since the previous frame"}),
            "found": ("frame", found),
            "col": ("frame", col, {"units": "px"}),
            "row": ("frame", row, {"units": "px", "long_name": "ball-centre row (down)"}),
            "radius_px": ("frame", rad, {"units": "px"}),
            "n_inliers": ("frame", inl),
        },
        coords={"frame": np.arange(n), "t": ("frame", times, {"units": "s"})},
        attrs=attrs,
    )


class _Crops:
    """The ball and its surroundings in each frame of a clip that is read frame by frame, so that the
    rotation between frames needs no second reading of the clip. Stops keeping (and the rotation reads the
    clip again) beyond ``limit`` bytes."""

    def __init__(self, shape: tuple[int, int, int], limit: int) -> None:
        self.h, self.w = shape[1:]
        self.limit, self.nbytes, self.full = limit, 0, False
        self.windows: dict[int, tuple[int, int, np.ndarray]] = {}

    def keep(self, j: int, frame: np.ndarray, col, row, rad) -> None:
        if self.full or not np.isfinite(col[j]):
            return
        # Room for the rotation window of either pair (j - 1, j), (j, j + 1): the ball's radius (the scale, a
        # median of the radii, is not known yet: 1.25 times this frame's) plus 6 px plus 1.5 times the motion.
        moves = [np.hypot(col[i] - col[j], row[i] - row[j]) for i in (j - 1, j + 1)
                 if 0 <= i < col.size and np.isfinite(col[i])]
        m = int(np.ceil(1.25 * rad[j] + 12 + 1.5 * max(moves, default=0.0)))
        c0, r0 = max(int(col[j]) - m, 0), max(int(row[j]) - m, 0)
        c1, r1 = min(int(col[j]) + m + 1, self.w), min(int(row[j]) + m + 1, self.h)
        size = (c1 - c0) * (r1 - r0) * frame.itemsize
        if self.nbytes + size > self.limit:
            self.full, self.windows = True, {}
            return
        self.windows[j] = (c0, r0, np.array(frame[r0:r1, c0:c1]))
        self.nbytes += size

    def view(self, j: int, window: tuple[int, int, int, int]) -> np.ndarray | None:
        """Pixels ``window`` = (c0, r0, c1, r1) of frame ``j``, or None if not kept."""
        kept = self.windows.get(j)
        if kept is None:
            return None
        x0, y0, arr = kept
        c0, r0, c1, r1 = window
        if c0 < x0 or r0 < y0 or c1 > x0 + arr.shape[1] or r1 > y0 + arr.shape[0]:
            return None
        return arr[r0 - y0 : r1 - y0, c0 - x0 : c1 - x0]


def _rotation_windows(frames, crops: _Crops | None, pairs: list[int], col, row, r_scale: float):
    """For each frame k of ``pairs`` in order: (k, window of frame k - 1, window of frame k, window origin),
    from the kept crops where they hold it, else from a reading of the frames concerned."""
    shape = frames.shape[1:]
    windows = {k: rotation_window((col[k - 1], row[k - 1]), (col[k], row[k]), r_scale, shape) for k in pairs}
    views: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    if crops is not None:
        for k in pairs:
            a, b = crops.view(k - 1, windows[k]), crops.view(k, windows[k])
            if a is not None and b is not None:
                views[k] = (a, b)
    missing = [k for k in pairs if k not in views]
    if missing and crops is not None:  # a window the crops do not hold: read those frames (once, together)
        got: dict[tuple[int, int], np.ndarray] = {}
        for j, frame in frames.frames(sorted({i for k in missing for i in (k - 1, k)})):
            for k in (j, j + 1):
                if k in windows and k not in views:
                    c0, r0, c1, r1 = windows[k]
                    got[(k, j)] = np.array(frame[r0:r1, c0:c1])
        for k in missing:
            views[k] = (got[(k, k - 1)], got[(k, k)])
        missing = []
    if missing:  # the clip is in memory: its frames, in one pass
        last = None
        for j, frame in frames.frames(sorted({i for k in missing for i in (k - 1, k)})):
            if j in windows and last is not None and last[0] == j - 1:
                c0, r0, c1, r1 = windows[j]
                yield j, last[1][r0:r1, c0:c1], frame[r0:r1, c0:c1], (c0, r0)
            last = (j, frame)
        return
    for k in pairs:
        c0, r0, _, _ = windows[k]
        yield k, views[k][0], views[k][1], (c0, r0)


def frame_times(frames: Clip, fps: float | None, label: str, fps_source: str = "argument"
                ) -> tuple[np.ndarray, float, str]:
    """(times in s, frame rate, where they come from) of a clip's frames: the times a camera file records
    (``fps``, if given, must agree with them), else ``frame / fps`` (a frame missing from a video's
    timestamps counted in), with the rate a rendered ``.npz`` clip stores where ``fps`` is not given (one
    given must agree with it).

    Raises
    ------
    FrameRateError
        No times and no ``fps``; an ``fps`` that disagrees with the file's times or stored rate by more
        than :data:`FPS_AGREEMENT`; a file rate outside :data:`FPS_RANGE`.
    """
    n = len(frames)
    if frames.times is None and frames.fps is not None:  # a rendered clip: its stored rate (checked), no times
        agree(fps, frames.fps, fps_source, label, f"the frame rate the clip file records ({frames.fps:g} frames/s); "
              "leave the frame rate out to use it")
        if fps is None:
            fps, fps_source = frames.fps, "clip file"
    if frames.times is None or frames.time_source == "stream timestamps":
        fps = check_fps(fps, label, fps_source)
        gaps = frames.gaps
        if not gaps:
            return np.arange(n) / fps, fps, "fps"
        # A container's timestamps are at its own (playback) rate, but a gap in them is a missing frame.
        periods = np.ones(n - 1)
        for k, missing in gaps:
            periods[k] += missing
        return np.r_[0.0, np.cumsum(periods)] / fps, fps, "fps and stream timestamps"
    own = check_fps(frames.fps, label, "clip file")
    origin = {"TIME64 block": "the times of its TIME64 block"}.get(str(frames.time_source), "its header's frame rate")
    agree(fps, own, fps_source, label, f"the frame times the file records ({own:g} frames/s, from {origin}); the "
           "file's times are the camera's: leave the frame rate out to use them")
    return np.asarray(frames.times, dtype=float), own, str(frames.time_source)


