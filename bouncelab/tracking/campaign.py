"""Clips to bounce states: one clip measured (:func:`measure_clip`), many clips to a campaign
(:func:`measure_clips`), with settings from a manifest file or from the file names.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.analysis.measurement import estimate_spin, measure_bounce
from bouncelab.data.campaign import make_campaign
from bouncelab.data.plausibility import PLAUSIBLE_RANGES, PlausibleRanges
from bouncelab.data.units import BALL_RADIUS_M
from bouncelab.errors import DataError
from bouncelab.tracking.frames import read_frames, stored_fps
from bouncelab.tracking.tracker import check_fps, track_clip

__all__ = ["ClipFailure", "ClipSettings", "TrackedCampaign", "clip_settings", "measure_clip", "measure_clips"]


def measure_clip(track: xr.Dataset, *, method: str = "differences", interval: str = "prediction",
                 guard: int = 1, min_frames: int = 5) -> xr.Dataset:
    """Landing and lift-off states of one tracked clip, with the paper's intervals.

    Touch-down and lift-off come from the lowest visible point and the states
    from :func:`bouncelab.analysis.measurement.measure_bounce` (its ``method``,
    ``interval``, ``guard`` and ``min_frames``), on the longest run of
    consecutive frames where the ball was found. Spin samples that could not
    be measured (too few matched features) are left out of the spin estimate
    (:func:`~bouncelab.analysis.measurement.estimate_spin`) rather than
    stopping the measurement.

    Parameters
    ----------
    track
        From :func:`~bouncelab.tracking.track_clip`.

    Returns
    -------
    xarray.Dataset
        As :func:`~bouncelab.analysis.measurement.measure_bounce`, with attrs
        ``clip``, ``first_frame`` (the run's first frame in the clip; the
        ``*_index`` attrs are frames of the clip), ``dropped_frames`` and
        ``spin_samples_before``/``after``.

    Raises
    ------
    DataError
        Naming the clip and the frame: too few frames before or after the
        bounce, no detectable contact, or too few spin samples on a side.
    """
    clip = str(track.attrs.get("clip", "clip"))
    found = np.asarray(track["found"].values, dtype=bool)
    start, stop = _longest_run(found)
    if stop - start == 0:
        raise DataError("the ball was not found in any frame", file=clip)
    run = track.isel(frame=slice(start, stop))
    n = stop - start
    try:
        m = measure_bounce(run.assign(spin=run["spin"].fillna(0.0)), method=method, interval=interval,
                           guard=guard, min_frames=min_frames)
    except DataError as exc:
        dropped = track.attrs.get("dropped_frames", [])
        where = f"frames {start}..{stop - 1} (ball lost in frames {_ranges(dropped)})" if dropped else \
            f"frames {start}..{stop - 1}"
        raise DataError(f"{exc.message} [in {where} of the clip]", file=clip) from None
    i, j = m.attrs["touchdown_index"], m.attrs["liftoff_index"]
    spin = run["spin"].values
    sides = {"landing": (0, max(i - guard, 0)), "liftoff": (min(j + 1 + guard, n), n)}
    counts = {}
    for key, (a, b) in sides.items():
        samples = spin[a:b]
        samples = samples[np.isfinite(samples)]
        counts[key] = int(samples.size)
        if samples.size < 3:
            side = "before touch-down" if key == "landing" else "after lift-off"
            raise DataError(f"only {samples.size} spin samples {side} "
                            f"(frames {start + a}..{start + b - 1}): too few matched features on the ball",
                            file=clip)
        est = estimate_spin(samples, level=m.attrs["level"])
        is_spin = m["component"] == "omega"
        m[key] = m[key].where(~is_spin, est.value)
        m[f"{key}_pi"] = m[f"{key}_pi"].where(~is_spin, est.half_width)
    m.attrs.update(
        clip=clip,
        first_frame=int(start),
        touchdown_index=int(start + i),
        liftoff_index=int(start + j),
        touchdown_time=float(m.attrs["touchdown_time"]),
        liftoff_time=float(m.attrs["liftoff_time"]),
        dropped_frames=list(track.attrs.get("dropped_frames", [])),
        spin_samples_before=counts["landing"],
        spin_samples_after=counts["liftoff"],
    )
    return m


@dataclass(frozen=True)
class ClipSettings:
    """Settings of one clip: frame rate, launcher setting, scale."""

    fps: float | None = None
    setting: str | None = None
    ball_radius_m: float = BALL_RADIUS_M
    pixels_per_metre: float | None = None
    #: Where ``fps`` came from: ``"manifest"``, ``"file name"`` (the pattern), ``"default"`` (the ``fps``
    #: argument of :func:`clip_settings`) or ``None`` (no frame rate given).
    fps_from: str | None = None


@dataclass(frozen=True)
class ClipFailure:
    """A clip that could not be measured, and why."""

    clip: str
    reason: str


@dataclass
class TrackedCampaign:
    """The result of :func:`measure_clips`.

    Attributes
    ----------
    campaign
        The campaign Dataset of the clips that were measured (``None`` if none).
    measurements
        Per clip name, the :func:`measure_clip` result.
    tracks
        Per clip name, the :func:`~bouncelab.tracking.track_clip` result.
    failures
        The clips that failed, with the reason.
    figures
        Per clip name, the diagnostic figure written.
    """

    campaign: xr.Dataset | None
    measurements: dict[str, xr.Dataset] = field(default_factory=dict)
    tracks: dict[str, xr.Dataset] = field(default_factory=dict)
    failures: list[ClipFailure] = field(default_factory=list)
    figures: dict[str, Path] = field(default_factory=dict)


def clip_settings(
    clips: Iterable[str | Path],
    *,
    fps: float | None = None,
    ball_radius_m: float = BALL_RADIUS_M,
    pixels_per_metre: float | None = None,
    manifest: str | Path | None = None,
    pattern: str | re.Pattern[str] | None = None,
) -> dict[str, ClipSettings]:
    """Settings of each clip, from the defaults given, a manifest file and a file-name pattern.

    Parameters
    ----------
    clips
        Clip paths.
    fps, ball_radius_m, pixels_per_metre
        Defaults for every clip.
    manifest
        A CSV file with a column ``clip`` (file name or path) and any of
        ``fps``, ``setting``, ``ball_radius_mm``, ``pixels_per_metre``; its
        values override the defaults. Clips not in the manifest keep the defaults.
    pattern
        A regular expression matched against each file name (without
        directory), with named groups among ``setting``, ``fps``,
        ``ball_radius_mm``, ``pixels_per_metre``; e.g.
        ``r"(?P<setting>s\\d+)_r\\d+_(?P<fps>\\d+)fps"`` (or the compiled pattern). Overrides the manifest.

    Raises
    ------
    DataError
        An unreadable manifest, a missing ``clip`` column, a value that is not a
        number, or a bad pattern.
    """
    rows: dict[str, dict[str, Any]] = {}
    if manifest is not None:
        rows = _read_manifest(Path(manifest))
    regex = None
    if pattern is not None:
        try:
            regex = re.compile(pattern)
        except re.error as exc:
            raise DataError(f"the file-name pattern {pattern!r} is not a regular expression: {exc}") from None
    out = {}
    for clip in clips:
        p = Path(clip)
        values: dict[str, Any] = {}
        origin: dict[str, str] = {}  # where each value came from, for the messages
        for key in (str(p), p.name, p.stem):
            if key in rows:
                values.update(rows[key])
                origin.update(dict.fromkeys(rows[key], f"manifest {manifest}"))
                break
        if regex is not None:
            mt = regex.search(p.name)
            if mt is not None:
                found = {k: v for k, v in mt.groupdict().items() if v is not None}
                values.update(found)
                origin.update(dict.fromkeys(found, "file name"))
        fps_value, fps_origin = values.get("fps", fps), origin.get("fps", "argument")
        out[str(clip)] = ClipSettings(
            fps=_number(fps_value, "fps", str(clip), fps_origin),
            setting=None if values.get("setting") is None else str(values["setting"]),
            ball_radius_m=(_number(values["ball_radius_mm"], "ball_radius_mm", str(clip), origin["ball_radius_mm"])
                           / 1000.0 if values.get("ball_radius_mm") is not None else ball_radius_m),
            pixels_per_metre=_number(values.get("pixels_per_metre", pixels_per_metre), "pixels_per_metre",
                                     str(clip), origin.get("pixels_per_metre", "argument")),
            fps_from=None if fps_value is None else "default" if fps_origin == "argument" else
            "file name" if fps_origin == "file name" else "manifest",
        )
    return out


def measure_clips(
    clips: Iterable[str | Path | np.ndarray],
    *,
    settings: Mapping[str, ClipSettings] | None = None,
    fps: float | None = None,
    campaign: str = "",
    surface: str = "",
    method: str = "differences",
    data_kind: str = "measured",
    progress: Callable[[int, int, str], None] | None = None,
    keep_tracks: bool = True,
    figure_dir: str | Path | None = None,
    workers: int | None = None,
    plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
) -> TrackedCampaign:
    """Track and measure many clips (one bounce each) into a campaign Dataset.

    A clip that fails (unreadable, ball never found, too few frames before or
    after the bounce, frame rate missing, ...) is recorded in ``failures`` with
    the reason and the others go on.

    Parameters
    ----------
    clips
        Clip paths (or arrays, named ``clip0``, ``clip1``, ...).
    settings
        Per clip (keyed by ``str(path)``), from :func:`clip_settings`;
        clips not in it use ``fps``.
    fps
        Frame rate of clips without settings.
    campaign, surface
        Names stored in the campaign's attrs.
    method
        Velocity estimator of :func:`measure_clip`.
    data_kind
        Stored in the campaign: ``"measured"`` (default) or, for rendered
        clips, ``"synthetic surrogate"``.
    progress
        Called as ``progress(done, total, clip)`` after each clip.
    keep_tracks
        Keep each clip's track in the result.
    figure_dir
        Write each tracked clip's diagnostic figure
        (:func:`~bouncelab.tracking.figure.diagnostic_figure`) there as
        ``<clip stem>.png`` (needs matplotlib); also for clips whose
        measurement failed once the ball was tracked.
    workers
        Track this many clips at once in separate processes (``None`` or 1:
        one after the other in this process). Results do not depend on it.
    plausible
        The unit guard of the campaign built
        (:func:`~bouncelab.data.campaign.make_campaign`); ``None`` leaves the check to the
        caller (the command line checks the states itself, to blame the frame rate).

    Returns
    -------
    TrackedCampaign
        The campaign (bounces in clip order, ``setting`` from the settings or
        the clip name, ``clip`` coordinate with the clip names), the per-clip
        measurements and tracks, and the failures.
    """
    items = list(clips)
    settings = dict(settings or {})
    result = TrackedCampaign(campaign=None)
    rows = []
    radii = set()
    names = [f"clip{k}" if isinstance(clip, np.ndarray) else str(clip) for k, clip in enumerate(items)]
    jobs = [(clip, name, settings.get(name, ClipSettings(fps=fps)), method, figure_dir)
            for clip, name in zip(items, names, strict=True)]
    if workers is not None and workers > 1 and len(jobs) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        # Spawned workers: each clip is independent; results come back in clip order.
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=min(workers, len(jobs)), mp_context=ctx) as pool:
            outcomes = pool.map(_process_clip, jobs)
            for k, out in enumerate(outcomes):
                _collect(result, rows, radii, jobs[k], out, keep_tracks)
                if progress is not None:
                    progress(k + 1, len(items), names[k])
    else:
        for k, job in enumerate(jobs):
            _collect(result, rows, radii, job, _process_clip(job), keep_tracks)
            if progress is not None:
                progress(k + 1, len(items), names[k])
    if rows:
        if len(radii) > 1:
            raise DataError(f"the clips use different ball radii {sorted(radii)}; a campaign has one ball")
        names = [r[0] for r in rows]
        settings_col = [r[1].setting if r[1].setting is not None else Path(r[0]).stem for r in rows]
        ds = make_campaign(
            np.array([r[2]["landing"].values for r in rows]),
            np.array([r[2]["liftoff"].values for r in rows]),
            setting=settings_col,
            landing_pi=np.array([r[2]["landing_pi"].values for r in rows]),
            liftoff_pi=np.array([r[2]["liftoff_pi"].values for r in rows]),
            campaign=campaign,
            surface=surface,
            ball_radius_m=radii.pop(),
            source=f"bouncelab track: {len(rows)} clip(s) measured from video",
            data_kind=data_kind,
            plausible=plausible,
        )
        result.campaign = ds.assign_coords(clip=("bounce", names))
    return result


def _process_clip(job) -> tuple[xr.Dataset | None, xr.Dataset | None, str | None, Path | None]:
    """Track, measure and draw one clip: (track, measurement, failure reason, figure path)."""
    clip, name, s, method, figure_dir = job
    frames = track = m = None
    reason = None
    try:
        fps = s.fps if s.fps is not None else stored_fps(clip)  # a rendered .npz clip knows its frame rate
        check_fps(fps, name)  # before reading a long clip for nothing
        frames = read_frames(clip, name=name)
        track = track_clip(frames, fps=fps, ball_radius_m=s.ball_radius_m, pixels_per_metre=s.pixels_per_metre,
                           name=name)
        m = measure_clip(track, method=method)
    except DataError as exc:
        reason = str(exc)
    figure = None
    if figure_dir is not None and track is not None:
        import matplotlib.pyplot as plt

        from bouncelab.tracking.figure import diagnostic_figure

        figure = Path(figure_dir) / f"{Path(name).stem}.png"
        plt.close(diagnostic_figure(frames, track, m, figure))
    return track, m, reason, figure


def _collect(result: TrackedCampaign, rows: list, radii: set, job, out, keep_tracks: bool) -> None:
    _, name, s, _, _ = job
    track, m, reason, figure = out
    if keep_tracks and track is not None:
        result.tracks[name] = track
    if figure is not None:
        result.figures[name] = figure
    if reason is not None:
        result.failures.append(ClipFailure(clip=name, reason=reason))
        return
    result.measurements[name] = m
    rows.append((name, s, m))
    radii.add(s.ball_radius_m)


def _longest_run(mask: np.ndarray) -> tuple[int, int]:
    best, start = (0, 0), None
    for k, v in enumerate(np.append(mask, False)):
        if v and start is None:
            start = k
        elif not v and start is not None:
            if k - start > best[1] - best[0]:
                best = (start, k)
            start = None
    return best


def _ranges(frames: list[int]) -> str:
    if not frames:
        return ""
    out, a, b = [], frames[0], frames[0]
    for f in frames[1:]:
        if f == b + 1:
            b = f
            continue
        out.append(f"{a}" if a == b else f"{a}-{b}")
        a = b = f
    out.append(f"{a}" if a == b else f"{a}-{b}")
    return ", ".join(out)


def _read_manifest(path: Path) -> dict[str, dict[str, Any]]:
    import pandas as pd

    if not path.exists():
        raise DataError("no such manifest file", file=str(path))
    try:
        df = pd.read_csv(path, sep=None, engine="python", comment="#", dtype=str)
    except (OSError, ValueError, pd.errors.ParserError) as exc:
        raise DataError(f"cannot read the manifest: {exc}", file=str(path)) from None
    df.columns = [str(c).strip().lower() for c in df.columns]
    if "clip" not in df.columns:
        raise DataError(f"the manifest needs a 'clip' column; it has {list(df.columns)}", file=str(path))
    known = {"fps", "setting", "ball_radius_mm", "pixels_per_metre"}
    rows = {}
    for _, r in df.iterrows():
        rows[str(r["clip"]).strip()] = {k: (None if pd.isna(r[k]) else str(r[k]).strip())
                                        for k in df.columns if k in known}
    return rows


def _number(value, name: str, clip: str, where: str) -> float | None:
    """``value`` as a positive number; ``where`` it came from (``manifest FILE``, ``file name`` or ``argument``,
    the clip_settings keyword) names it in the DataError."""
    if value is None:
        return None
    said = f"the {name} argument" if where == "argument" else f"{name} from the {where}"
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DataError(f"{said} is not a number: {value!r}", file=clip) from None
    if not (np.isfinite(v) and v > 0):
        raise DataError(f"{said} must be a positive finite number; got {value!r}", file=clip)
    return v
