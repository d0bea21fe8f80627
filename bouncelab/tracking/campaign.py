"""Clips to bounce states: one clip measured (:func:`measure_clip`), many clips to a campaign
(:func:`measure_clips`), with settings from a manifest file or from the file names.
"""

from __future__ import annotations

import io
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.analysis.measurement import estimate_spin, measure_bounce
from bouncelab.core.errors import DataError, MissingFileError
from bouncelab.core.files import read_regular_text
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges
from bouncelab.core.units import BALL_RADIUS_M, INERTIA_FACTOR
from bouncelab.data.campaign import make_campaign
from bouncelab.tracking.frames import CAMERA_SUFFIXES, open_clip, stored_fps
from bouncelab.tracking.tracker import (
    FPS_SOURCES,
    check_fps,
    track_clip,
)

__all__ = ["ClipFailure", "ClipSettings", "TrackedCampaign", "clip_settings", "measure_clip", "measure_clips"]


def measure_clip(track: xr.Dataset, *, method: str = "differences", interval: str = "prediction",
                 guard: int = 1, min_frames: int = 5, energy_check: bool = True) -> xr.Dataset:
    """Landing and lift-off states of one tracked clip, with the paper's intervals.

    Touch-down and lift-off come from the lowest visible point and the states
    from :func:`bouncelab.analysis.measurement.measure_bounce` (its ``method``,
    ``interval``, ``guard`` and ``min_frames``), on the longest run of
    consecutive frames where the ball was found, at the frames' times (frames
    a camera dropped, which a ``.cine``'s times show, leave a gap of whole
    frame periods: ``missing_frames=True``). Spin samples that could not
    be measured (too few matched features) are left out of the spin estimate
    (:func:`~bouncelab.analysis.measurement.estimate_spin`) rather than
    stopping the measurement.

    A bounce cannot gain kinetic energy: a clip whose lift-off has more
    kinetic energy (translation and spin, ``xdot^2 + ydot^2 + k omega^2`` with
    ``k`` = :data:`~bouncelab.core.units.INERTIA_FACTOR`) than its landing by
    more than the measurement intervals allow (the lift-off's energy at the
    near ends of its intervals above the landing's at the far ends) is refused:
    such a clip is played backwards (reversed frames, a folder's frame numbers
    counting down) or its frames are out of order.

    Parameters
    ----------
    track
        From :func:`~bouncelab.tracking.track_clip`.
    energy_check
        Refuse a bounce that gains kinetic energy beyond its intervals
        (default); ``False`` keeps it (a moving surface can add energy).

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
        bounce, no detectable contact, too few spin samples on a side, or a
        lift-off with more kinetic energy than the landing (see above).
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
                           guard=guard, min_frames=min_frames, missing_frames=True)  # a camera's dropped frames
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
    if energy_check:
        _check_energy(m, clip)
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


def _energy_range(state: np.ndarray, half: np.ndarray) -> tuple[float, float, float]:
    """Kinetic energy ``xdot^2 + ydot^2 + k omega^2`` of a state, and its least and greatest values over the
    intervals (each component moved by its half-width towards or away from zero)."""
    weight = np.array([1.0, 1.0, INERTIA_FACTOR])
    a, h = np.abs(state), np.abs(half)
    return (float(weight @ a**2), float(weight @ np.maximum(a - h, 0.0) ** 2), float(weight @ (a + h) ** 2))


def _check_energy(m: xr.Dataset, clip: str) -> None:
    """DataError if the lift-off has more kinetic energy than the landing beyond the intervals."""
    e0, _, e0_high = _energy_range(m["landing"].values, m["landing_pi"].values)
    e1, e1_low, _ = _energy_range(m["liftoff"].values, m["liftoff_pi"].values)
    if e1_low > e0_high:
        raise DataError(
            f"the lift-off has {e1 / e0:.2f} times the landing's kinetic energy (translation and spin), beyond "
            f"the measurement intervals ({e1_low / e0_high:.2f} times at their ends): a bounce cannot gain "
            "energy. Is the clip played backwards (reversed frames, or image file numbers counting down)?",
            file=clip)


@dataclass(frozen=True)
class ClipSettings:
    """Settings of one clip: frame rate, launcher setting, scale.

    ``fps_source`` says where the frame rate came from (one of
    :data:`~bouncelab.tracking.tracker.FPS_SOURCES`), for the errors.
    """

    fps: float | None = None
    setting: str | None = None
    ball_radius_m: float = BALL_RADIUS_M
    pixels_per_metre: float | None = None
    fps_source: str = "argument"


@dataclass(frozen=True)
class ClipFailure:
    """A clip that could not be measured, why, and the error (a DataError, e.g. a
    :class:`~bouncelab.tracking.tracker.FrameRateError` with the frame rate's source)."""

    clip: str
    reason: str
    error: DataError | None = None


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
    FrameRateError
        A frame rate that is not a number or outside
        :data:`~bouncelab.tracking.tracker.FPS_RANGE`, with its source
        (``"argument"``, ``"manifest"`` or ``"file name"``).
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
            raise DataError(f"the file-name pattern {pattern!r} is not a regular expression: {exc}",
                            option="pattern") from None
    out = {}
    for clip in clips:
        p = Path(clip)
        values: dict[str, Any] = {}
        origin: dict[str, str] = {}  # where each value came from: the arguments unless named here
        for key in (str(p), p.name, p.stem):
            if key in rows:
                given = {k: v for k, v in rows[key].items() if v is not None}  # an empty cell keeps the default
                values.update(given)
                origin.update(dict.fromkeys(given, f"manifest {manifest}"))
                break
        if regex is not None:
            mt = regex.search(p.name)
            if mt is not None:
                found = {k: v for k, v in mt.groupdict().items() if v is not None}
                values.update(found)
                origin.update(dict.fromkeys(found, "file name"))
        name = str(clip)
        fps_source = {"file name": "file name", None: "argument"}.get(origin.get("fps"), "manifest")
        clip_fps = values.get("fps", fps)
        radius_mm = values.get("ball_radius_mm")
        out[name] = ClipSettings(
            fps=None if clip_fps is None else check_fps(clip_fps, name, fps_source),
            setting=None if values.get("setting") is None else str(values["setting"]),
            ball_radius_m=(ball_radius_m if radius_mm is None else
                           _number(radius_mm, "ball_radius_mm", name, origin["ball_radius_mm"]) / 1000.0),
            pixels_per_metre=_number(values.get("pixels_per_metre", pixels_per_metre), "pixels_per_metre", name,
                                     origin.get("pixels_per_metre", "arguments")),
            fps_source=fps_source,
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
    memory_budget: float | None = None,
    energy_check: bool = True,
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
        Frame rate of clips without settings (not needed for camera files,
        ``.cine`` and ``.mraw``, which record their frames' times; if given
        it must agree with them).
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
    memory_budget
        Bytes the frames of one clip may take in each process (default
        :data:`bouncelab.tracking.frames.MEMORY_BUDGET`, read now).
    energy_check
        As in :func:`measure_clip`: a clip whose bounce gains kinetic energy
        beyond its intervals fails (default).

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
    from bouncelab.tracking.frames import _budget

    budget = _budget(memory_budget)  # resolved here: spawned workers do not see a changed MEMORY_BUDGET
    jobs = [(clip, name, settings.get(name, ClipSettings(fps=fps)), method, figure_dir, budget, energy_check)
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
            raise DataError(f"the clips use different ball radii {sorted(radii)}; a campaign has one ball",
                            option="ball_radius_m")
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


def _process_clip(job) -> tuple[xr.Dataset | None, xr.Dataset | None, DataError | None, Path | None]:
    """Track, measure and draw one clip: (track, measurement, failure, figure path)."""
    clip, name, s, method, figure_dir, budget, energy_check = job
    frames = track = m = None
    failure = None
    try:
        fps, source = s.fps, s.fps_source if s.fps_source in FPS_SOURCES else "argument"
        if isinstance(clip, str | Path) and not Path(clip).exists():  # said as such, not as a missing frame rate
            raise MissingFileError("no such file or folder", file=name)
        if fps is not None or not records_times(clip):
            fps = check_fps(fps, name, source)  # before reading a long clip for nothing
        frames = open_clip(clip, name=name, memory_budget=budget)
        track = track_clip(frames, fps=fps, ball_radius_m=s.ball_radius_m, pixels_per_metre=s.pixels_per_metre,
                           name=name, fps_source=source)
        m = measure_clip(track, method=method, energy_check=energy_check)
    except DataError as exc:
        failure = exc
    figure = None
    if figure_dir is not None and track is not None:
        import matplotlib.pyplot as plt

        from bouncelab.tracking.figure import diagnostic_figure

        figure = Path(figure_dir) / f"{Path(name).stem}.png"
        plt.close(diagnostic_figure(frames, track, m, figure))
    return track, m, failure, figure


def _collect(result: TrackedCampaign, rows: list, radii: set, job, out, keep_tracks: bool) -> None:
    name, s = job[1], job[2]
    track, m, failure, figure = out
    if keep_tracks and track is not None:
        result.tracks[name] = track
    if figure is not None:
        result.figures[name] = figure
    if failure is not None:
        result.failures.append(ClipFailure(clip=name, reason=str(failure), error=failure))
        return
    result.measurements[name] = m
    rows.append((name, s, m))
    radii.add(s.ball_radius_m)


def records_times(clip) -> bool:
    """Whether ``clip`` records its frames' times or rate, so that no frame rate is needed: a camera file, or a
    rendered ``.npz`` clip with its ``fps`` (:func:`~bouncelab.tracking.frames.stored_fps`)."""
    return isinstance(clip, str | Path) and (Path(clip).suffix.lower() in CAMERA_SUFFIXES
                                             or stored_fps(clip) is not None)


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
        raise MissingFileError("no such manifest file", file=str(path))
    text = read_regular_text(path, str(path))  # (a FIFO would hang pandas, /dev/zero never end)
    try:
        df = pd.read_csv(io.StringIO(text), sep=None, engine="python", comment="#", dtype=str)
    except (OSError, ValueError, pd.errors.ParserError) as exc:
        raise DataError(f"cannot read the manifest: {exc}", file=str(path)) from None
    df.columns = [str(c).strip().lower() for c in df.columns]
    if "clip" not in df.columns:
        raise DataError(f"the manifest needs a 'clip' column; it has {list(df.columns)}", file=str(path),
                        column="clip")
    known = {"fps", "setting", "ball_radius_mm", "pixels_per_metre"}
    rows = {}
    for _, r in df.iterrows():
        rows[str(r["clip"]).strip()] = {k: (None if pd.isna(r[k]) else str(r[k]).strip())
                                        for k in df.columns if k in known}
    return rows


def _source(name: str, where: str) -> dict[str, str]:
    """Where a clip's number came from, as DataError fields: the argument ``name``, or the manifest's column."""
    if where == "argument":
        return {"option": name}
    return {"column": name} if where.startswith("manifest") else {}


def _number(value, name: str, clip: str, where: str) -> float | None:
    """``value`` as a positive number; ``where`` it came from (``manifest FILE``, ``file name`` or ``argument``,
    the clip_settings keyword) names it in the DataError."""
    if value is None:
        return None
    said = f"the {name} argument" if where == "argument" else f"{name} from the {where}"
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DataError(f"{said} is not a number: {value!r}", file=clip, **_source(name, where)) from None
    if not (np.isfinite(v) and v > 0):
        raise DataError(f"{said} must be a positive finite number; got {value!r}", file=clip, **_source(name, where))
    return v
