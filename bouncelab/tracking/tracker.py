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

from bouncelab.data.units import BALL_RADIUS_M
from bouncelab.errors import DataError
from bouncelab.tracking.detect import estimate_background, find_ball
from bouncelab.tracking.frames import read_frames
from bouncelab.tracking.rotation import frame_rotation

__all__ = ["track_clip"]


def track_clip(
    source,
    *,
    fps: float | None,
    ball_radius_m: float = BALL_RADIUS_M,
    pixels_per_metre: float | None = None,
    radius_range: tuple[float, float] | None = None,
    name: str | None = None,
) -> xr.Dataset:
    """Track the ball through a clip.

    Parameters
    ----------
    source
        A video file, a folder of images, a ``.npz`` with ``frames``, or an
        array (t, h, w) or (t, h, w, 3) (:func:`~bouncelab.tracking.read_frames`).
    fps
        Frame rate, frames/s (required: video containers often store a
        playback rate, not the camera's).
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

    Returns
    -------
    xarray.Dataset
        Over ``frame`` (every frame of the clip) with coordinate ``t`` (s):
        ``x``, ``y`` (ball centre, radii; y up, surface at 0), ``lowest``
        (height of the lowest visible point, radii), ``spin`` (rotation from
        the previous frame over the frame period, rad/s anticlockwise; NaN
        for the first frame, after a frame where the ball was lost and where
        too few features matched), ``found`` (bool), ``col``, ``row``,
        ``radius_px`` (pixels, row down), ``n_inliers`` (matched features
        kept). attrs: ``clip``, ``fps``, ``radius_px`` (scale), ``surface_row``,
        ``dropped_frames`` (list of frames where the ball was not found).

    Raises
    ------
    DataError
        Unreadable source, missing or bad frame rate, or a ball found in no frame.
    """
    label = name or (str(source) if not isinstance(source, np.ndarray) else "array")
    fps = check_fps(fps, label)
    if not (np.isfinite(ball_radius_m) and 0 < ball_radius_m < 1):
        raise DataError(f"ball_radius_m must be a radius in metres in (0, 1); got {ball_radius_m!r}", file=label)
    if pixels_per_metre is not None and not (np.isfinite(pixels_per_metre) and pixels_per_metre > 0):
        raise DataError(f"pixels_per_metre must be positive; got {pixels_per_metre!r}", file=label)
    frames = read_frames(source, name=label)
    n, h, _w = frames.shape
    if radius_range is None:
        radius_range = (4.0, h / 2.0)
        if pixels_per_metre is not None:
            r_px = pixels_per_metre * ball_radius_m
            radius_range = (0.8 * r_px, 1.2 * r_px)
    bg = estimate_background(frames)

    col = np.full(n, np.nan)
    row = np.full(n, np.nan)
    rad = np.full(n, np.nan)
    low = np.full(n, np.nan)
    near = None
    for k in range(n):
        predicted = None
        if k >= 2 and np.isfinite(col[k - 1]) and np.isfinite(col[k - 2]):
            predicted = (2 * col[k - 1] - col[k - 2], 2 * row[k - 1] - row[k - 2], rad[k - 1])
        c = find_ball(frames[k], bg, radius_range=radius_range, near=near, predicted=predicted)
        if c is None:
            near = None
            continue
        col[k], row[k], rad[k], low[k] = c.col, c.row, c.radius, c.lowest_row
        near = (c.col, c.row, c.radius)
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
    dt = 1.0 / fps
    guess = 0.0
    for k in range(1, n):
        if not (found[k] and found[k - 1]):
            continue
        rot = frame_rotation(frames[k - 1], frames[k], (col[k - 1], row[k - 1]), (col[k], row[k]), r_scale,
                             guess=guess, surface_row=bg.surface_row)
        inl[k] = rot.n_inliers
        if np.isfinite(rot.angle):
            spin[k] = rot.angle / dt
            guess = rot.angle

    ref = bg.surface_row if bg.surface_row is not None else float(h)
    attrs: dict[str, Any] = {
        "clip": label,
        "fps": fps,
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
        coords={"frame": np.arange(n), "t": ("frame", np.arange(n) * dt, {"units": "s"})},
        attrs=attrs,
    )


def check_fps(fps, label: str) -> float:
    """The frame rate as a positive float, or a DataError naming the clip."""
    if fps is None:
        raise DataError("the frame rate is missing: give fps (e.g. --fps 5000 or an fps column in the "
                        "manifest)", file=label)
    try:
        fps = float(fps)
    except (TypeError, ValueError):
        raise DataError(f"fps must be a number of frames per second; got {fps!r}", file=label) from None
    if not (np.isfinite(fps) and fps > 0):
        raise DataError(f"fps must be a positive number of frames per second; got {fps!r}", file=label)
    return fps
