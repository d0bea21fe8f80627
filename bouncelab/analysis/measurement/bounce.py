"""One tracked bounce measured: contact detection, then velocities and spins on each side
(:func:`measure_bounce`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.analysis.measurement.contact import detect_contact
from bouncelab.analysis.measurement.input_checks import (
    JITTER_RTOL,
    _as_1d,
    _check_finite,
    _check_int_at_least,
    _frame_interval,
)
from bouncelab.analysis.measurement.results import ContactDetection
from bouncelab.analysis.measurement.spin import estimate_spin
from bouncelab.analysis.measurement.velocity import (
    IntervalKind,
    VelocityMethod,
    _check_velocity_options,
    estimate_velocity,
)
from bouncelab.core.errors import DataError
from bouncelab.core.units import COMPONENT_UNITS, COMPONENTS


def measure_bounce(
    track: xr.Dataset | Mapping[str, Any],
    *,
    level: float = 0.95,
    interval: IntervalKind = "prediction",
    method: VelocityMethod = "differences",
    guard: int = 1,
    window: int | None = None,
    min_frames: int = 5,
    contact: ContactDetection | None = None,
    jitter_rtol: float = JITTER_RTOL,
    missing_frames: bool = False,
) -> xr.Dataset:
    """Landing and lift-off states with their interval half-widths, from one tracked bounce.

    Parameters
    ----------
    track
        A Dataset (as from
        :func:`~bouncelab.analysis.trajectories.simulate_tracked_bounce`) or a
        mapping with 1-D arrays ``t`` (s), ``x``, ``y`` (ball-centre, radii),
        ``spin`` (per-frame spin, rad/s) and ``lowest`` (height of the lowest
        visible point, radii), one value per frame. ``t`` may be a coordinate.
    level
        Coverage level of all intervals.
    interval, method
        Velocity interval and estimator
        (:func:`~bouncelab.analysis.measurement.estimate_velocity`); the
        defaults are the paper's. Spin always uses
        :func:`~bouncelab.analysis.measurement.estimate_spin`.
    guard
        Frames next to each detected contact instant left out of the fits
        (default 1), so that a detection one frame late cannot let a contact
        frame into a flight fit; the first spin sample after lift-off also
        spans part of the contact.
    window
        Use at most this many frames on each side (the ones closest to the
        bounce); ``None`` uses all.
    min_frames
        Fewest flight frames required on each side (at least 4).
    contact
        A detection to use instead of
        :func:`~bouncelab.analysis.measurement.detect_contact` on ``lowest``
        (``lowest`` is then not needed).
    jitter_rtol
        Largest accepted relative deviation of a frame interval from the mean.
    missing_frames
        Accept frame times that skip whole frame periods (frames a camera
        dropped, at the times its file records, as
        :func:`~bouncelab.tracking.track_clip` gives them for a ``.cine``);
        by default unequal intervals are refused.

    Returns
    -------
    xarray.Dataset
        Over dimension ``component`` (``xdot, ydot, omega``, with ``unit``):
        ``landing`` and ``liftoff`` (scaled units) evaluated at the detected
        touch-down and lift-off times, and ``landing_pi``, ``liftoff_pi`` (the
        interval half-widths). attrs: ``touchdown_time``, ``liftoff_time``,
        ``touchdown_index``, ``liftoff_index``, ``n_frames_before``,
        ``n_frames_after``, ``level``, ``interval``, ``method``, ``guard``.
        Concatenate results along a new ``bounce`` dimension and pass them to
        :func:`bouncelab.data.campaign.make_campaign` to build a campaign.

    Raises
    ------
    DataError
        A missing variable, mismatched lengths, unequal frame intervals, NaN in
        a frame used, too few frames on a side, or no detectable contact.

    Examples
    --------
    >>> from bouncelab.analysis.trajectories import simulate_tracked_bounce
    >>> track = simulate_tracked_bounce([1063.0, -810.0, 219.0], [700.0, 280.0, -550.0], seed=0)
    >>> m = measure_bounce(track)
    >>> bool(abs(m["landing"].sel(component="ydot") + 810.0) < m["landing_pi"].sel(component="ydot"))
    True
    """
    level = _check_velocity_options(level, interval, method)
    for name, value, low in (("guard", guard, 0), ("min_frames", min_frames, 4)):
        _check_int_at_least(name, value, low)
    if window is not None and (
        isinstance(window, bool) or not isinstance(window, int | np.integer) or window < min_frames
    ):
        raise DataError(f"window must be None or an integer >= min_frames ({min_frames}); got {window!r}",
                        option="window")
    if contact is not None and not isinstance(contact, ContactDetection):
        raise DataError(f"contact must be a ContactDetection or None; got {type(contact).__name__}", option="contact")

    names = ("t", "x", "y", "spin") + (("lowest",) if contact is None else ())
    arrays = _track_arrays(track, names)
    t = arrays["t"]
    _frame_interval(t, jitter_rtol=jitter_rtol, missing_frames=missing_frames)
    n = t.size
    if contact is None:
        contact = detect_contact(t, arrays["lowest"], jitter_rtol=jitter_rtol, missing_frames=missing_frames)
    i, j = contact.touchdown_index, contact.liftoff_index
    if not (0 <= i <= j < n):
        raise DataError(f"contact frames ({i}, {j}) are not ordered frames of this {n}-frame track", option="contact")

    stop_b = max(i - guard, 0)
    start_b = 0 if window is None else max(stop_b - window, 0)
    start_a = min(j + 1 + guard, n)
    stop_a = n if window is None else min(start_a + window, n)
    sides = {
        "landing": (slice(start_b, stop_b), contact.touchdown_time, "before touch-down"),
        "liftoff": (slice(start_a, stop_a), contact.liftoff_time, "after lift-off"),
    }
    values: dict[str, np.ndarray] = {}
    half: dict[str, np.ndarray] = {}
    used: dict[str, int] = {}
    for key, (sl, t_eval, where) in sides.items():
        count = sl.stop - sl.start
        if count < min_frames:
            raise DataError(
                f"only {count} usable frames {where} (frames {sl.start}..{sl.stop - 1}, after leaving "
                f"{guard} guard frame(s)); need at least {min_frames}", option="track"
            )
        for name in ("x", "y", "spin"):
            bad = ~np.isfinite(arrays[name][sl])
            if bad.any():
                frame = sl.start + int(np.argmax(bad))
                raise DataError(f"{name} is NaN or infinite at frame {frame}, which is used {where}",
                                column=name)
        vx = estimate_velocity(t[sl], arrays["x"][sl], t_eval, level=level, interval=interval,
                               method=method, jitter_rtol=jitter_rtol, missing_frames=missing_frames)
        vy = estimate_velocity(t[sl], arrays["y"][sl], t_eval, level=level, interval=interval,
                               method=method, jitter_rtol=jitter_rtol, missing_frames=missing_frames)
        w = estimate_spin(arrays["spin"][sl], level=level)
        values[key] = np.array([vx.value, vy.value, w.value])
        half[key] = np.array([vx.half_width, vy.half_width, w.half_width])
        used[key] = count

    kind = "prediction" if interval == "prediction" else "confidence"
    long = f"half-width of the {level:.0%} {kind} interval (spin: CI of the mean)"
    return xr.Dataset(
        {
            "landing": ("component", values["landing"], {
                "long_name": "state at touch-down", "units": "scaled"}),
            "liftoff": ("component", values["liftoff"], {
                "long_name": "state at lift-off", "units": "scaled"}),
            "landing_pi": ("component", half["landing"], {"long_name": long, "units": "scaled"}),
            "liftoff_pi": ("component", half["liftoff"], {"long_name": long, "units": "scaled"}),
        },
        coords={"component": list(COMPONENTS), "unit": ("component", list(COMPONENT_UNITS))},
        attrs={
            "touchdown_time": contact.touchdown_time,
            "liftoff_time": contact.liftoff_time,
            "touchdown_index": i,
            "liftoff_index": j,
            "n_frames_before": used["landing"],
            "n_frames_after": used["liftoff"],
            "level": level,
            "interval": interval,
            "method": method,
            "guard": int(guard),
        },
    )


def _track_arrays(track, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    if isinstance(track, xr.Dataset):
        have = set(map(str, track.variables))
    elif isinstance(track, Mapping):
        have = set(map(str, track))
    else:
        raise DataError(
            f"a track must be an xarray.Dataset or a mapping of arrays; got {type(track).__name__}", option="track"
        )
    missing = [name for name in names if name not in have]
    if missing:
        raise DataError(f"track has no {missing} variable(s); it has {sorted(have)}", column=missing[0],
                        option="track")
    out = {}
    for name in names:
        value = track[name]
        if isinstance(value, xr.DataArray) and value.ndim != 1:
            raise DataError(f"{name} must be 1-D (one value per frame); got dims {value.dims}", column=name,
                            option=name)
        out[name] = _as_1d(value.values if isinstance(value, xr.DataArray) else value, name)
    lengths = {name: arr.size for name, arr in out.items()}
    if len(set(lengths.values())) > 1:
        raise DataError(f"track variables must have one value per frame; got lengths {lengths}", option="track")
    _check_finite(out["t"], "t")
    return out
