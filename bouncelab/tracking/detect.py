"""Finding the ball in a frame: a Hough-transform circle, refined to a sub-pixel centre and radius.

The paper located the ball with MATLAB's ``imfindcircles`` (a circular Hough
transform). Here the static scene (black background, turf strip) is first
removed by subtracting a background frame, the median of frames spread over the
clip (:func:`estimate_background`); OpenCV's ``HoughCircles`` then finds the
ball roughly (:func:`find_ball`), and the centre and radius are refined to a
fraction of a pixel by fitting a circle, robustly, to edge points found along
rays from the rough centre where the brightness crosses half the local
contrast of the ball's edge. Rays whose edge point is hidden by the turf (at or
below the surface line) are left out, so a ball pressed into the turf keeps an
unbiased centre from its visible upper part.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bouncelab.tracking._cv import cv2

__all__ = ["Background", "Circle", "background_indices", "estimate_background", "find_ball"]

_N_RAYS = 72
_RAY_STEP = 0.25  # px
_INSIDE = (0.75, 1.75)  # px inside the limb where each ray's brightness level is read


@dataclass(frozen=True)
class Background:
    """The static scene of a clip and what it tells.

    Attributes
    ----------
    image
        (h, w) float32 static scene (see :func:`estimate_background`).
    surface_row
        Image row of the top of the turf strip (the surface line, ``y = 0``),
        or ``None`` if the clip shows no strip.
    contrast
        Typical brightness of the ball above the background, grey levels.
    """

    image: np.ndarray
    surface_row: float | None
    contrast: float


@dataclass(frozen=True)
class Circle:
    """A ball found in a frame (pixels; row down).

    Attributes
    ----------
    col, row, radius
        Sub-pixel centre and radius.
    lowest_row
        Row of the lowest visible point of the ball (larger is lower).
    n_edge
        Edge points used in the circle fit.
    """

    col: float
    row: float
    radius: float
    lowest_row: float
    n_edge: int


def background_indices(n: int, n_samples: int = 31) -> np.ndarray:
    """The frames of an ``n``-frame clip that :func:`estimate_background` samples: ``n_samples`` spread evenly."""
    if n <= 0:
        return np.zeros(0, dtype=int)
    return np.unique(np.linspace(0, n - 1, min(n_samples, n)).round().astype(int))


def estimate_background(frames, *, n_samples: int = 31) -> Background:
    """Background of ``n_samples`` frames spread over the clip, the surface line and the ball's contrast.

    The ball moves, so at each pixel some of the sampled frames show the static
    scene: the background is a low quantile (15 %) of the sampled frames,
    raised by the typical gap between their median and that quantile (the
    noise's share), so that the ball may cover a pixel in up to 85 % of them.
    The surface line is the top of the bright band at the bottom of the
    background, found to a fraction of a row from the partly covered rows, if
    there is one.

    ``frames`` is a (t, h, w) uint8 array or a :class:`~bouncelab.tracking.frames.Clip`
    (only the sampled frames are read).
    """
    idx = background_indices(len(frames), n_samples)
    # Only the sampled frames, in one (len(idx), h, w) stack (a Clip reads just those).
    frames, idx = frames[idx], np.arange(len(idx))
    # A low quantile, not the median: a ball that falls and rises almost vertically covers the pixels
    # near its contact point in most frames. The quantile sits below the noise-free level by a
    # constant, measured (on a sample of pixels) as the typical gap between the median and the quantile.
    q = max(int(0.15 * (len(idx) - 1)), 0)
    low = _kth_smallest(frames, idx, q).astype(np.float32)
    few = frames.reshape(len(idx), -1)[:, :: max(frames[0].size // 4096, 1)].astype(np.float32)
    few.sort(axis=0)
    gap = float(np.median(few[len(idx) // 2] - few[q]))
    bg = (low + gap).astype(np.float32)
    h = bg.shape[0]
    rows = np.median(bg, axis=1)
    dark = float(np.median(rows[: h // 2]))
    band = float(np.median(rows[-max(h // 20, 1):]))
    surface_row = None
    if band - dark > 10.0:
        half = 0.5 * (dark + band)
        above = rows > half
        # The strip: the last run of bright rows reaching the bottom edge.
        k = h - 1
        while k >= 0 and above[k]:
            k -= 1
        if k < h - 1:
            # Row k + 1 is the first mostly-turf row; row k is covered by the fraction c of its height,
            # so the line is at k + 0.5 - c (pixel centres at integer rows).
            local = float(np.median(rows[k + 1 : k + 5]))
            c = float(np.clip((rows[k] - dark) / (local - dark), 0.0, 1.0)) if k >= 0 else 0.0
            # Row k + 1 may itself be partly covered (c' in (0.5, 1]).
            c1 = float(np.clip((rows[k + 1] - dark) / (local - dark), 0.0, 1.0))
            surface_row = k + 1.5 - c1 - c
    # The ball's brightness above the background: the brightest foreground of each sampled frame, its median
    # over the frames that show something at least half as bright as the brightest (the ball): frames without
    # the ball (before it enters, after it leaves) hold noise only, and a median over them all would be noise
    # once they are the majority.
    tops = np.array([cv2.blur(frames[i].astype(np.float32) - bg, (3, 3)).max() for i in idx])
    contrast = float(np.median(tops[tops >= 0.5 * tops.max()])) if tops.max() > 0 else float(np.median(tops))
    return Background(image=bg, surface_row=surface_row, contrast=contrast)


def _kth_smallest(frames: np.ndarray, idx: np.ndarray, q: int) -> np.ndarray:
    """Per pixel, the (q+1)-th smallest value over the frames ``idx``: a running insertion network of
    element-wise minima and maxima (much faster than a partial sort along the frame axis)."""
    best = [np.full(frames.shape[1:], np.iinfo(np.uint8).max if frames.dtype == np.uint8 else np.inf,
                    dtype=frames.dtype) for _ in range(q + 1)]
    for i in idx:
        x = frames[i]
        for j in range(q + 1):
            lo = np.minimum(best[j], x)
            x = np.maximum(best[j], x)
            best[j] = lo
    return best[q]


def find_ball(
    frame: np.ndarray,
    background: Background,
    *,
    radius_range: tuple[float, float] | None = None,
    near: tuple[float, ...] | None = None,
    predicted: tuple[float, float, float] | None = None,
) -> Circle | None:
    """Find the ball in one frame, or ``None``.

    Parameters
    ----------
    frame
        (h, w) grey frame.
    background
        From :func:`estimate_background`.
    radius_range
        Smallest and largest ball radius to look for, pixels (default: 4 px to
        half the frame height).
    near
        ``(col, row)`` or ``(col, row, radius)`` where the ball is expected
        (e.g. the previous frame's circle): the Hough search is limited to a
        window around it, which is faster. If nothing is found there, a given
        radius makes that circle the starting point of the refinement (a ball
        half hidden by the turf can escape the Hough transform); otherwise the
        whole frame is searched.
    predicted
        ``(col, row, radius)`` predicted from the previous frames' motion:
        the refinement starts there, without a Hough transform (faster); if
        it does not converge near it, ``near`` and the Hough transform are
        used.

    Returns
    -------
    Circle or None
        ``None`` if no ball-sized bright circle is in the frame (hidden,
        outside, or too few edge points for a fit).
    """
    fg = frame.astype(np.float32) - background.image
    h, w = fg.shape
    rmin, rmax = radius_range if radius_range is not None else (4.0, h / 2)
    thr = 0.5 * background.contrast
    coarse = None
    if predicted is not None:
        # Tracking: refine from where the motion so far puts the ball; the Hough transform only if that fails.
        fit = _refine(fg, float(predicted[0]), float(predicted[1]), float(predicted[2]), background.surface_row)
        if fit is not None and np.hypot(fit[0] - predicted[0], fit[1] - predicted[1]) < 0.3 * predicted[2]:
            coarse = (fit[0], fit[1], fit[2])
            moved = np.hypot(fit[0] - predicted[0], fit[1] - predicted[1]) + abs(fit[2] - predicted[2])
            if moved < 0.5 and 0.7 * rmin <= fit[2] <= 1.3 * rmax:
                # Converged from the prediction: the edge points do not depend on a ray origin this close.
                return Circle(col=float(fit[0]), row=float(fit[1]), radius=float(fit[2]),
                              lowest_row=float(_lowest_row(fg, fit[0], fit[1], fit[2])), n_edge=int(fit[3]))
    if coarse is None and near is not None:
        lo, hi = (0.75 * near[2], 1.3 * near[2]) if len(near) == 3 else (rmin, rmax)
        m = int(np.ceil(2.5 * hi + 8))
        c0, r0 = max(int(near[0]) - m, 0), max(int(near[1]) - m, 0)
        c1, r1 = min(int(near[0]) + m + 1, w), min(int(near[1]) + m + 1, h)
        coarse = _hough(fg[r0:r1, c0:c1], lo, hi, background.contrast)
        if coarse is not None:
            # A ball cut by the turf can fool the Hough radius; the last frame's radius is a better start.
            coarse = (coarse[0] + c0, coarse[1] + r0, float(near[2]) if len(near) == 3 else coarse[2])
    if coarse is None and near is not None and len(near) == 3:
        # The Hough transform can miss a ball half hidden by the turf: start from where it was.
        coarse = (float(near[0]), float(near[1]), float(near[2]))
    if coarse is None:
        lo, hi = rmin, rmax
        if hi > 2 * lo:
            # A wide search is slow: narrow it to the radius of a disc with the area of the bright pixels.
            area = float(np.count_nonzero(fg > thr))
            r_area = np.sqrt(area / np.pi)
            if lo <= r_area <= hi:
                lo, hi = max(lo, 0.7 * r_area), min(hi, 1.4 * r_area)
        coarse = _hough(fg, lo, hi, background.contrast)
    if coarse is None:
        return None
    col, row, rad = coarse
    if fg[int(np.clip(round(row), 0, h - 1)), int(np.clip(round(col), 0, w - 1))] < 0.2 * thr and \
            _disc_mean(fg, col, row, 0.7 * rad) < 0.5 * thr:
        return None  # a Hough circle on noise, not on a bright ball
    for _ in range(2):  # a second pass from the refined circle if the rough one was off
        fit = _refine(fg, col, row, rad, background.surface_row)
        if fit is None:
            return None
        moved = np.hypot(fit[0] - col, fit[1] - row) + abs(fit[2] - rad)
        col, row, rad, n_edge = fit
        if moved < 0.5:
            break
    if not (0.7 * rmin <= rad <= 1.3 * rmax):
        return None
    lowest = _lowest_row(fg, col, row, rad)
    return Circle(col=float(col), row=float(row), radius=float(rad), lowest_row=float(lowest), n_edge=int(n_edge))


def _hough(fg: np.ndarray, rmin: float, rmax: float, contrast: float):
    """Strongest circle of OpenCV's gradient Hough transform on the foreground, or None."""
    img = np.clip(fg * (200.0 / max(contrast, 1.0)), 0, 255).astype(np.uint8)
    img = cv2.GaussianBlur(img, (5, 5), 1.0)
    circles = cv2.HoughCircles(
        img, cv2.HOUGH_GRADIENT_ALT, dp=1, minDist=max(img.shape) or 1, param1=120, param2=0.5,
        minRadius=max(int(np.floor(rmin)), 1), maxRadius=max(int(np.ceil(rmax)), 2),
    )
    if circles is None or len(circles[0]) == 0:
        return None
    c = circles[0][0]
    return float(c[0]), float(c[1]), float(c[2])


def _disc_mean(fg: np.ndarray, col: float, row: float, rad: float) -> float:
    h, w = fg.shape
    r0, r1 = max(int(row - rad), 0), min(int(row + rad) + 1, h)
    c0, c1 = max(int(col - rad), 0), min(int(col + rad) + 1, w)
    if r0 >= r1 or c0 >= c1:
        return 0.0
    return float(fg[r0:r1, c0:c1].mean())


def _refine(fg: np.ndarray, col: float, row: float, rad: float, surface_row: float | None):
    """Circle fitted to sub-pixel edge points on rays from (col, row); None if too few points.

    On each ray the edge is where the (bilinearly interpolated) brightness last
    crosses half its level just inside the limb: for an area-sampled edge that is
    where the limb crosses the ray.
    """
    h, w = fg.shape
    m = int(np.ceil(1.6 * rad + 4))
    c0, r0 = max(int(col) - m, 0), max(int(row) - m, 0)
    c1, r1 = min(int(col) + m + 1, w), min(int(row) + m + 1, h)
    crop = fg[r0:r1, c0:c1]
    lc, lr = col - c0, row - r0
    ang = np.arange(_N_RAYS) * (2 * np.pi / _N_RAYS)
    radii = np.arange(0.5 * rad, 1.5 * rad + 3, _RAY_STEP, dtype=np.float32)
    ca, sa = np.cos(ang).astype(np.float32), np.sin(ang).astype(np.float32)
    map_x = (lc + radii[None, :] * ca[:, None]).astype(np.float32)
    map_y = (lr + radii[None, :] * sa[:, None]).astype(np.float32)
    prof = cv2.remap(crop, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    # Each ray's threshold is half the ball's brightness just inside the limb (the limb is darker
    # than the middle of the ball, so a global level would bias the radius).
    inside = (radii > rad - _INSIDE[1]) & (radii < rad - _INSIDE[0])
    if not inside.any():
        inside = radii < rad - 1
    level = prof[:, inside].mean(axis=1)
    level = np.maximum(level, 0.8 * np.median(level))  # a dark dot just inside the edge must not lower it
    # Extrapolate to the limb with the typical outward fall of brightness (limb darkening).
    deeper = (radii > rad - _INSIDE[1] - 2.0) & (radii < rad - _INSIDE[0] - 2.0)
    if deeper.any():
        fall = float(np.median(prof[:, deeper].mean(axis=1) - level)) / 2.0  # per px
        level = level - max(fall, 0.0) * (0.5 * (_INSIDE[0] + _INSIDE[1]))
    half = 0.5 * level
    above = prof >= half[:, None]
    # Outermost sample above the threshold on each ray, then linear interpolation of the crossing.
    last = prof.shape[1] - 1 - np.argmax(above[:, ::-1], axis=1)
    ok = above.any(axis=1) & (last < prof.shape[1] - 1)
    k = np.clip(last, 0, prof.shape[1] - 2)
    idx = np.arange(_N_RAYS)
    a, b = prof[idx, k], prof[idx, k + 1]
    frac = np.where(a != b, (a - half) / np.where(a != b, a - b, 1.0), 0.5)
    rr = radii[k] + np.clip(frac, 0, 1) * _RAY_STEP
    ex, ey = col + rr * ca, row + rr * sa
    if surface_row is not None:
        ok &= ey < surface_row - 2.0  # edge points at the turf are the turf's edge, not the ball's
    ok &= np.abs(rr - rad) < max(0.25 * rad, 3.0)
    if ok.sum() < 8:
        return None
    ex, ey = ex[ok].astype(float), ey[ok].astype(float)
    keep = np.ones(ex.size, dtype=bool)
    for _ in range(3):
        cx, cy, r = _fit_circle(ex[keep], ey[keep], iterations=1)
        res = np.hypot(ex - cx, ey - cy) - r
        scale = max(1.4826 * np.median(np.abs(res[keep] - np.median(res[keep]))), 0.05)
        new = np.abs(res) < 3.0 * scale
        if new.sum() < 8 or (new == keep).all():
            break
        keep = new
    cx, cy, r = _fit_circle(ex[keep], ey[keep])
    return cx, cy, r, int(keep.sum())


def _fit_circle(x: np.ndarray, y: np.ndarray, iterations: int = 5) -> tuple[float, float, float]:
    """Least-squares circle: algebraic (Kasa) start, then Gauss-Newton on the geometric distances."""
    xm, ym = x.mean(), y.mean()
    u, v = x - xm, y - ym
    a = np.stack([u, v, np.ones_like(u)])
    sol = np.linalg.solve(a @ a.T, a @ (u * u + v * v))
    cx, cy = sol[0] / 2, sol[1] / 2
    r = np.sqrt(max(sol[2] + cx * cx + cy * cy, 1e-12))
    for _ in range(iterations):
        dx, dy = u - cx, v - cy
        d = np.hypot(dx, dy)
        d = np.where(d > 0, d, 1e-12)
        jac = np.stack([-dx / d, -dy / d, -np.ones_like(d)])
        try:
            step = np.linalg.solve(jac @ jac.T, jac @ (r - d))
        except np.linalg.LinAlgError:
            break
        cx, cy, r = cx + step[0], cy + step[1], r + step[2]
        if np.abs(step).max() < 1e-6:
            break
    return float(cx + xm), float(cy + ym), float(r)


def _lowest_row(fg: np.ndarray, col: float, row: float, rad: float) -> float:
    """Row of the lowest visible point: in a central band of columns, the lowest row where the ball is
    brighter than half its level (sub-pixel), at most the circle's bottom."""
    h, w = fg.shape
    c0, c1 = max(round(col - 0.3 * rad), 0), min(round(col + 0.3 * rad) + 1, w)
    r0, r1 = max(round(row), 0), min(int(np.ceil(row + 1.4 * rad)) + 1, h)
    band = fg[r0:r1, c0:c1]
    if band.size == 0:
        return row + rad
    prof = band.max(axis=1)
    level = float(np.median(fg[max(int(row - 0.5 * rad), 0):int(row + 0.5 * rad) + 1, c0:c1]))
    level = max(level, float(np.percentile(prof, 75)))
    above = np.flatnonzero(prof >= 0.5 * level)
    if above.size == 0:
        return row
    k = int(above[-1])
    if k + 1 >= prof.size:
        return float(r0 + k)
    a, b = prof[k], prof[k + 1]
    frac = (a - 0.5 * level) / (a - b) if a != b else 0.5
    return float(r0 + k + np.clip(frac, 0.0, 1.0))
