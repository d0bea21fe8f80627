"""Synthetic high-speed clips of a bounce with known truth (:func:`render_clip`).

The renderer draws what the paper's camera saw (section "Experimental set up"):
a white ball with a seam line and a regular array of black dots, against a
black background, with a strip of turf in front of the surface that hides the
lower part of the ball while it is pressed into the surface. It is used by the
tests and benchmarks of :mod:`bouncelab.tracking` to check positions, spins,
contact times and interval coverage against the truth.

Geometry and conventions
------------------------
* The trajectory is :func:`bouncelab.analysis.trajectories.simulate_tracked_bounce`
  with no tracker noise: gravity and quadratic drag in flight (DOP853), a cubic
  Hermite path during contact (the centre dips below one radius, so the ball
  sinks into the turf), spin constant in flight and linear in contact.
* Lab frame: ``x`` to the right, ``y`` **up**, surface at ``y = 0``, angles
  anticlockwise (bouncelab's convention). Image: column to the right, row
  **down**. A lab point ``(x, y)`` (radii) is drawn at column
  ``x0 + x R`` and row ``surface_row - y R`` with ``R`` the ball radius in
  pixels.
* The ball is a sphere seen in orthographic projection along the spin axis
  (the camera plane aligned with the plane of motion, as in the paper), so the
  visible front hemisphere turns rigidly by the orientation angle ``theta(t)``;
  the dots and the seam are drawn on the sphere (foreshortened near the limb).
* Pixels are anti-aliased by supersampling; the limb by an analytic coverage
  ramp. Sensor noise is Gaussian (grey levels) and the frames are 8-bit, or of
  ``bit_depth`` bits (uint16 frames, the same scene and noise on a finer scale,
  as a 12-bit camera records it).
  Optional motion blur averages sub-frame renders over the exposure.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.analysis.trajectories import simulate_tracked_bounce
from bouncelab.core import checks
from bouncelab.core.errors import DataError, Hint

__all__ = ["RenderedClip", "ball_pattern", "render_clip"]

# Grey levels of the scene (8-bit).
BACKGROUND_LEVEL = 6.0
BALL_LEVEL = 215.0
MARK_LEVEL = 35.0
TURF_LEVEL = 55.0
TURF_TEXTURE = 12.0
#: Largest frame side rendered, pixels.
MAX_SIDE = 8192


@dataclass(frozen=True)
class RenderedClip:
    """A rendered clip and its truth.

    Attributes
    ----------
    frames
        (t, h, w) grey frames: uint8, or uint16 of ``settings["bit_depth"]`` bits.
    fps
        Frame rate, frames/s.
    radius_px
        Ball radius, pixels.
    truth
        The noise-free track (:func:`~bouncelab.analysis.trajectories.simulate_tracked_bounce`)
        with ``theta`` (orientation, rad, anticlockwise in the lab frame) and
        the pixel centre ``col``, ``row`` added; attrs hold ``true_landing``,
        ``true_liftoff``, ``true_touchdown_time``, ``true_liftoff_time``.
    settings
        The rendering settings.
    """

    frames: np.ndarray
    fps: float
    radius_px: float
    truth: xr.Dataset
    settings: dict[str, Any] = field(default_factory=dict)

    def save(self, path) -> Path:
        """Write the frames, the frame rate and the true states to a compressed ``.npz`` (atomically).

        :func:`~bouncelab.tracking.read_frames` reads the ``frames``; the file
        also holds ``fps``, ``true_landing`` and ``true_liftoff`` (scaled units).
        """
        import io

        from bouncelab.core.atomic import atomic_write_bytes

        buf = io.BytesIO()
        np.savez_compressed(buf, frames=self.frames, fps=self.fps, true_landing=self.landing,
                            true_liftoff=self.liftoff)
        return atomic_write_bytes(path, buf.getvalue())

    @property
    def landing(self) -> np.ndarray:
        return np.asarray(self.truth.attrs["true_landing"], dtype=float)

    @property
    def liftoff(self) -> np.ndarray:
        return np.asarray(self.truth.attrs["true_liftoff"], dtype=float)


def ball_pattern(n_lat: int = 5, n_lon: int = 10, seam_normal=(0.35, 0.25, 0.9)) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors of the dot centres (a latitude-longitude array) and the seam's plane normal.

    The dots sit at ``n_lat`` latitudes between -60 and 60 degrees and
    ``n_lon`` longitudes (shifted by half a step on every other latitude), plus
    the two poles; the seam is the great circle normal to ``seam_normal``.
    The body frame's z axis is the spin axis (towards the camera).
    """
    dots = [(0.0, 0.0, 1.0), (0.0, 0.0, -1.0)]
    for i, lat in enumerate(np.linspace(-np.pi / 3, np.pi / 3, n_lat)):
        # latitude measured from the equator of the z axis: z = sin(lat)
        shift = 0.5 * (i % 2)
        for k in range(n_lon):
            lon = 2 * np.pi * (k + shift) / n_lon
            dots.append((np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)))
    normal = np.asarray(seam_normal, dtype=float)
    return np.asarray(dots), normal / np.linalg.norm(normal)


def render_clip(
    landing=(1063.0, -810.0, 219.0),
    liftoff=None,
    *,
    law=None,
    fps: float = 5000.0,
    size: tuple[int, int] = (256, 512),
    radius_px: float = 20.0,
    n_before: int = 40,
    n_after: int = 40,
    contact_frames: float = 8.0,
    noise: float = 5.0,
    motion_blur: float = 0.0,
    surface_row: float | None = None,
    touchdown_col: float | None = None,
    dot_radius: float = 0.12,
    seam_width: float = 0.05,
    supersample: int = 3,
    frame_offset: float | None = None,
    bit_depth: int = 8,
    seed: int | np.random.Generator | None = None,
) -> RenderedClip:
    """Render a high-speed clip of one bounce with known truth.

    Parameters
    ----------
    landing
        True state at touch-down ``[xdot, ydot, omega]`` (radii/s, radii/s,
        rad/s, anticlockwise; ``omega > 0`` is backspin for a ball moving in +x).
    liftoff
        True state at lift-off; ``None`` takes it from ``law.predict(landing)``.
    law
        A bouncelab law (used when ``liftoff`` is None); default
        ``bouncelab.Rigid.published("A")``.
    fps
        Frame rate, frames/s.
    size
        ``(height, width)`` of the frames, pixels.
    radius_px
        Ball radius, pixels.
    n_before, n_after, contact_frames, frame_offset
        Frames recorded before touch-down and after lift-off, the contact
        duration in frame periods, and where touch-down falls between frames
        (see :func:`~bouncelab.analysis.trajectories.simulate_tracked_bounce`).
    noise
        Standard deviation of the sensor noise, grey levels.
    motion_blur
        Exposure as a fraction of the frame period (0: a sharp instant).
    surface_row
        Image row of the surface line ``y = 0`` (default: 80 % of the height).
    touchdown_col
        Column of the touch-down point (default: the column that centres the
        track horizontally).
    dot_radius, seam_width
        Angular radius of the dots and half-width of the seam, rad.
    supersample
        Samples per pixel side inside the ball.
    bit_depth
        Bits of the frames, 8 (uint8, default) to 16 (uint16): the scene's grey
        levels (and ``noise``), given on the 8-bit scale, times
        ``(2**bit_depth - 1) / 255``, rounded.
    seed
        Seed of the noise, the turf texture and (if not given) the frame offset.

    Returns
    -------
    RenderedClip

    Raises
    ------
    DataError
        Bad settings, or a ball that leaves the frame.
    """
    rng = checks.generator(seed, error=DataError)
    if liftoff is None:
        if law is None:
            from bouncelab.laws import Rigid

            law = Rigid.published("A")
        liftoff = np.asarray(law.predict(np.asarray(landing, dtype=float)[None, :], plausible=None),  # any state
                             dtype=float)[0]
    try:
        h, w = size
    except (TypeError, ValueError):
        raise DataError(f"size must be (height, width) in pixels; got {checks.shown(size)}", option="size") from None
    if isinstance(h, float | np.floating) and float(h).is_integer():  # (256.0 is a whole number of pixels)
        h = int(h)
    if isinstance(w, float | np.floating) and float(w).is_integer():
        w = int(w)
    h, w = (checks.count(v, "size", 16, maximum=MAX_SIDE, error=DataError) for v in (h, w))
    if not 2.0 <= checks.finite(radius_px, "radius_px", error=DataError) < min(h, w) / 2:
        raise DataError(f"radius_px must be in [2, {min(h, w) / 2}); got {radius_px!r}", option="radius_px")
    checks.positive(noise, "noise", allow_zero=True, error=DataError)
    checks.count(bit_depth, "bit_depth", 8, maximum=16, error=DataError)
    checks.fraction(motion_blur, "motion_blur", closed=True, error=DataError)
    track = simulate_tracked_bounce(
        landing, liftoff, fps=fps, n_before=n_before, n_after=n_after, contact_frames=contact_frames,
        position_noise=0.0, angle_noise=0.0, frame_offset=frame_offset, seed=rng,
    )
    dt = 1.0 / float(fps)
    x = track["x"].values
    y = track["y"].values
    # Orientation: the spin samples are exact rotation increments (theta_k - theta_{k-1}) / dt.
    theta = np.cumsum(np.concatenate([[0.0], track["spin"].values[1:] * dt]))
    surface_row = 0.8 * h if surface_row is None else float(surface_row)
    if touchdown_col is None:
        touchdown_col = w / 2 - radius_px * (x.min() + x.max()) / 2
    col = touchdown_col + radius_px * x
    row = surface_row - radius_px * y
    margin = radius_px + 2
    bad = (col < margin) | (col > w - 1 - margin) | (row < margin)
    if bad.any():
        k = int(np.argmax(bad))
        raise DataError(f"the ball leaves the {w} x {h} frame at frame {k} (centre column {col[k]:.1f}, "
                        f"row {row[k]:.1f})", option="size",
                        hints=[Hint("size", None, "larger"), Hint("n_before", None, "fewer frames"),
                               Hint("n_after", None, "fewer frames"), Hint("radius_px", None, "a smaller ball")])

    dots, seam = ball_pattern()
    cos_dot = np.cos(dot_radius)
    turf = TURF_LEVEL + TURF_TEXTURE * _smooth_texture(rng, h, w)
    rows = np.arange(h, dtype=np.float32)[:, None]
    # The turf strip in front of the ball, from the surface line down; the row it starts in is
    # partly covered (pixel centres at integer rows).
    turf_cover = np.clip(rows + 0.5 - surface_row, 0.0, 1.0)
    n = x.size
    top = (1 << int(bit_depth)) - 1
    gain = top / 255.0
    frames = np.empty((n, h, w), dtype=np.uint8 if bit_depth == 8 else np.uint16)
    subs = 1 if motion_blur == 0 else 5
    for k in range(n):
        img = np.full((h, w), BACKGROUND_LEVEL, dtype=np.float32)
        acc = np.zeros((h, w), dtype=np.float32)
        for s in range(subs):
            # Sub-frame instants spread over the exposure, ending at the frame time.
            f = 0.0 if subs == 1 else motion_blur * (s + 0.5) / subs - motion_blur
            kk = max(k - 1, 0)
            lam = f if k > 0 else 0.0
            c = col[k] + lam * (col[k] - col[kk])
            r = row[k] + lam * (row[k] - row[kk])
            th = theta[k] + lam * (theta[k] - theta[kk])
            acc += _draw_ball(h, w, c, r, radius_px, th, dots, cos_dot, seam, seam_width, supersample)
        img = img + acc / subs
        img = turf_cover * turf + (1.0 - turf_cover) * img
        if noise > 0:
            img = img + noise * rng.standard_normal((h, w)).astype(np.float32)
        frames[k] = np.clip(np.rint(img if bit_depth == 8 else img * gain), 0, top).astype(frames.dtype)
    truth = track.drop_vars(["spin", "lowest"]).assign(
        theta=("frame", theta, {"units": "rad", "long_name": "orientation, anticlockwise in the lab frame"}),
        col=("frame", col, {"units": "px", "long_name": "ball-centre column"}),
        row=("frame", row, {"units": "px", "long_name": "ball-centre row (down)"}),
    )
    settings = {"fps": float(fps), "size": (h, w), "radius_px": float(radius_px), "noise": float(noise),
                "motion_blur": float(motion_blur), "surface_row": surface_row, "dot_radius": dot_radius,
                "seam_width": seam_width, "bit_depth": int(bit_depth)}
    truth.attrs.update(settings | {"size": f"{h}x{w}"})
    return RenderedClip(frames=frames, fps=float(fps), radius_px=float(radius_px), truth=truth, settings=settings)


def _draw_ball(h, w, col, row, radius, theta, dots, cos_dot, seam, seam_width, ss) -> np.ndarray:
    """Ball brightness above the background on an (h, w) image (0 outside the ball)."""
    out = np.zeros((h, w), dtype=np.float32)
    c0, c1 = max(int(np.floor(col - radius - 2)), 0), min(int(np.ceil(col + radius + 2)) + 1, w)
    r0, r1 = max(int(np.floor(row - radius - 2)), 0), min(int(np.ceil(row + radius + 2)) + 1, h)
    if c0 >= c1 or r0 >= r1:
        return out
    offs = (np.arange(ss) + 0.5) / ss - 0.5
    cc = (np.arange(c0, c1)[None, :, None, None] + offs[None, None, None, :]) - col
    rr = (np.arange(r0, r1)[:, None, None, None] + offs[None, None, :, None]) - row
    u = cc / radius  # lab x
    v = -rr / radius  # lab y (image rows point down)
    d2 = u * u + v * v
    d = np.sqrt(d2)
    # Coverage of the limb: a one-sample-wide linear ramp across the edge (anti-aliasing).
    cover = np.clip((1.0 - d) * radius * ss + 0.5, 0.0, 1.0)
    z = np.sqrt(np.clip(1.0 - d2, 0.0, None))
    # Body coordinates: undo the rotation by theta (anticlockwise in the lab frame).
    ct, st = np.cos(theta), np.sin(theta)
    bx = ct * u + st * v
    by = -st * u + ct * v
    p = np.stack([bx, by, z], axis=-1)
    on_dot = (p @ dots.T).max(axis=-1) > cos_dot
    on_seam = np.abs(p @ seam) < seam_width
    albedo = np.where(on_dot | on_seam, MARK_LEVEL, BALL_LEVEL) - BACKGROUND_LEVEL
    shade = 0.75 + 0.25 * z  # mild limb darkening
    val = (cover * albedo * shade).mean(axis=(2, 3))
    out[r0:r1, c0:c1] = val
    return out


def _smooth_texture(rng: np.random.Generator, h: int, w: int) -> np.ndarray:
    """A static grass-like texture of unit standard deviation (vertical streaks)."""
    from scipy.ndimage import gaussian_filter

    t = gaussian_filter(rng.standard_normal((h, w)), sigma=(3.0, 0.8))
    return (t / (t.std() or 1.0)).astype(np.float32)
