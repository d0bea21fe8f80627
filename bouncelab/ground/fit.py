r"""Surfaces fitted to launch-monitor shots: :func:`fit_surface` and its result, :class:`SurfaceFit`.

A launch monitor exports, for every shot, how the ball landed (speed, descent angle, spin) and
where it stopped (carry, total, side, side total). :func:`fit_surface` finds the
:class:`~bouncelab.ground.Surface` on which :func:`bouncelab.ground.run` takes each shot's landing to
the rest point the file gives: the bounce law's parameters, the sliding friction, the Stimpmeter
speed (rolling resistance) and, where the file gives the spin at launch, the rate at which the spin
decays in flight.

The model of a shot
-------------------
Target frame: x along the target line, y to the left, z up; ``carry``, ``total`` along the
target line, ``side``, ``side_total`` across it, **positive to the right** (as TrackMan writes
them). The ball lands at ``(carry, -side)`` with speed :math:`s` at the descent angle
:math:`\gamma` below the horizontal, heading :math:`h` to the right of the target line:

.. math::

    v = s\,(\cos\gamma\cos h,\; -\cos\gamma\sin h,\; -\sin\gamma), \qquad
    \tan h = g_h\, \mathrm{side} / \mathrm{carry},

with :math:`g_h` the ``heading_gain`` (1: the ball lands travelling along the chord from the
tee, as a straight shot does; 2: a ball launched along the target line that curves at a constant
rate; 0 when the file has no side). The spin vector is the spin rate :math:`\omega` about an axis
that keeps its direction in flight (a spinning ball's axis is gyroscopically stable):
perpendicular to the launch direction, at the launch angle :math:`\theta` above the horizontal
(``launch_angle``; 0 when the file has none), and tilted by the spin axis :math:`\alpha`
(positive: the ball curves right, TrackMan's sign; 0 when the file has none). In the frame of the
landing heading (x along it, y to its left, z up):
:math:`\omega\,(\sin\alpha\sin\theta,\; -\cos\alpha,\; -\sin\alpha\cos\theta)` (pure backspin is
:math:`-\omega\,\hat y`; its Magnus force at launch, :math:`\omega \times v`, points right for
:math:`\alpha > 0`). The axis's component along the travel (:math:`\omega\sin\alpha\sin\theta`)
makes the contact point slip sideways, so a ball launched upwards with a tilted axis kicks to the
side of its curve on landing; the component about the vertical does not act on the ground.
Where the file gives the spin at launch, the landing spin is

.. math:: \omega = \omega_{\text{launch}}\, e^{-k T}

with :math:`T` the flight time and :math:`k` the ``spin_decay`` rate (1/s), a fitted parameter in
[0, 0.25] 1/s (0: no decay; 0.25: a 6 s drive keeps 22 % of its spin), not a measured one.
The predicted rest point is the landing point plus :func:`~bouncelab.ground.run`'s
``rest_position`` on flat ground; the predicted roll-out is ``total - carry`` along the target line
and the lateral roll-out ``side_total - side``.

The fit
-------
Each shot's error is the distance :math:`d` (m) between its predicted and its observed rest
point (with no ``side_total`` in the file: its roll-out error). The objective is the mean
pseudo-Huber loss :math:`c^2(\sqrt{1 + d^2/c^2} - 1)` with :math:`c` = ``loss_scale`` = 1 m:
:math:`d^2/2` for small errors (smooth at the optimum, where a mean absolute error has a kink
per shot on which a local search stalls), :math:`c\,d` for large ones (a few wild totals do not
pull the fit). It is minimised by NLopt's global search (CRS2 with local mutation) in the box
of the parameters' bounds (on a subset of ``global_shots`` shots, each put on the ground after
at most 15 bounces: this stage only locates the basin), then its best distinct points polished
locally (BOBYQA) on the subset, the best restarted, and polished on all the shots with the full
model. One objective evaluation is one call
of :func:`~bouncelab.ground.run` on all the shots of the fit. The shots are held out by
default: ``folds``-fold over shots (or over sessions or clubs, ``groups=``), each fold fitted on the others
and scored on its own; the surface returned is fitted to all the shots.

What it means
-------------
A launch monitor's ``total`` is its own estimate (few monitors follow the ball to rest: most
model the roll), so a surface fitted to an export reproduces the monitor's roll model, not the
turf. A surface fitted to measured roll-outs (totals measured with a tape or a laser) is a
calibration of the turf for those landings. Either way the fit is only as wide as the shots.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core.checks import real_array
from bouncelab.core.errors import DataError, FitError, Hint, ParameterError
from bouncelab.core.units import ANGLE_UNITS, BALL_RADIUS_M, SPEED_UNITS, SPIN_UNITS, canonical_unit
from bouncelab.laws.parameters import Parameter, Parameters

if TYPE_CHECKING:
    import pandas as pd

    from bouncelab.ground.surface import Surface
    from bouncelab.laws import BounceModel

__all__ = ["FIT_MAX_BOUNCES", "GLOBAL_MAX_BOUNCES", "SURFACE_PARAMETERS", "ShotArrays", "SurfaceFit", "fit_surface",
           "predict_shots"]

#: The surface's own parameters a fit can vary (beside the law's): search box, physical range, start.
SURFACE_PARAMETERS: dict[str, Parameter] = {
    "sliding_friction": Parameter(name="sliding_friction", bounds=(0.05, 1.0), physical=(1e-6, math.inf), unit="1",
                                  value=0.4, doc="Coulomb friction of the ball skidding on the surface"),
    "stimp_m": Parameter(name="stimp_m", bounds=(0.3, 4.6), physical=(1e-3, math.inf), unit="m", value=1.5,
                         doc="Stimpmeter reading (1 ft to 15 ft): the rolling resistance"),
    "spin_decay": Parameter(name="spin_decay", bounds=(0.0, 0.25), physical=(0.0, 1.0), unit="1/s", value=0.05,
                            doc="exponential decay rate of the spin in flight (launch spin only)"),
    "heading_gain": Parameter(name="heading_gain", bounds=(0.0, 3.0), physical=(0.0, 4.0), unit="1", value=1.0,
                              doc="tan(landing heading) / (side / carry) (files with side and side_total)"),
}

_REQUIRED = ("landing_speed", "landing_angle", "spin", "carry", "total")
_NUMERIC = (*_REQUIRED, "spin_axis", "launch_angle", "side", "side_total", "flight_time")
# variable -> (kind of unit, the unit assumed when none is given)
_KINDS = {"landing_speed": ("velocity", "m/s"), "landing_angle": ("angle", "rad"), "spin": ("spin", "rad/s"),
          "spin_axis": ("angle", "rad"), "launch_angle": ("angle", "rad"), "carry": ("distance", "m"),
          "total": ("distance", "m"), "side": ("distance", "m"), "side_total": ("distance", "m"),
          "flight_time": ("time", "s")}
_SPIN_KINDS = ("launch", "landing")
_GROUPS = ("auto", "shot", "session", "club")
_MAX_SPEED = 90.0  # m/s: the unit guard's limits (bouncelab.core.plausibility.PLAUSIBLE_RANGES)
_MIN_SPEED = 1.0
_MAX_SPIN = 20_000.0 * 2.0 * math.pi / 60.0  # rad/s
# Medians no set of golf shots lands with (a drive lands at about 27 m/s with 2,500 rpm; wedges spin up to
# about 10,000 rpm; the paper's fastest landing is 56 m/s), and the longest flight (a drive hangs 6-7 s).
_MAX_MEDIAN_SPEED, _MAX_MEDIAN_SPIN_RPM, _MAX_FLIGHT_S = 45.0, 12_000.0, 20.0
#: Fewest shots a fit takes (per fold's training set too).
MIN_SHOTS = 10
#: Bounces after which a fit's runs put a ball on the ground (:func:`~bouncelab.ground.run`'s ``max_bounces``).
#: A surface that keeps a landing bouncing longer is not one a fit should find, and parameters that do so
#: (a tilted law that relaunches a ball for ever) would make each evaluation cost 100 rounds of bounces.
FIT_MAX_BOUNCES = 40
#: Identifiability (:attr:`SurfaceFit.identifiable`): a fold's parameters are as good as the final fit's when
#: their mean error on all the shots is within EQUIVALENT_RELATIVE of it plus EQUIVALENT_M (m); a parameter is
#: determined when the final fit and those folds agree to within AGREE_FRACTION of its box and the mean error
#: rises by SENSITIVE_M (m) or more when it alone moves 5 % of its box either way.
EQUIVALENT_RELATIVE, EQUIVALENT_M, AGREE_FRACTION, SENSITIVE_M = 0.02, 0.01, 0.1, 0.01
#: Bounces after which the global stage puts a ball on the ground: it only locates the basin (the polish runs
#: every shot to ``max_bounces``), and each bounce round costs a pass over the shots still bouncing.
GLOBAL_MAX_BOUNCES = 15
#: Distinct good points of the global stage that are polished locally (the best polished one is kept).
POLISH_STARTS = 3


# --------------------------------------------------------------------------------------------- shots
@dataclass(frozen=True)
class ShotArrays:
    """Shots as SI arrays (m/s, rad, rad/s, m, s), one element per shot.

    ``spin_axis``, ``launch_angle``, ``side``, ``side_total``, ``flight_time``, ``club`` and
    ``session`` are None where the shots have none; ``labels`` are the shots' labels (the
    ``shot`` coordinate or the DataFrame's index).
    """

    landing_speed: np.ndarray
    landing_angle: np.ndarray
    spin: np.ndarray
    spin_kind: str
    carry: np.ndarray
    total: np.ndarray
    labels: np.ndarray
    spin_axis: np.ndarray | None = None
    launch_angle: np.ndarray | None = None
    side: np.ndarray | None = None
    side_total: np.ndarray | None = None
    flight_time: np.ndarray | None = None
    club: np.ndarray | None = None
    session: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.landing_speed)

    @property
    def lateral(self) -> bool:
        """Whether the shots give side and side total (a lateral roll-out to fit)."""
        return self.side is not None and self.side_total is not None

    @property
    def roll(self) -> np.ndarray:
        """Observed roll-out along the target line, ``total - carry`` (m)."""
        return self.total - self.carry

    @property
    def side_roll(self) -> np.ndarray | None:
        """Observed lateral roll-out, ``side_total - side`` (m, positive to the right), or None."""
        return self.side_total - self.side if self.lateral else None

    def take(self, idx: np.ndarray) -> ShotArrays:
        """The shots at positions ``idx``."""
        changes = {f: (None if getattr(self, f) is None else getattr(self, f)[idx])
                   for f in ("landing_speed", "landing_angle", "spin", "carry", "total", "labels", "spin_axis",
                             "launch_angle", "side", "side_total", "flight_time", "club", "session")}
        return replace(self, **changes)


def _frame_units(frame: Any) -> Mapping[str, str]:
    units = frame.attrs.get("units", {}) if hasattr(frame, "attrs") else {}
    return units if isinstance(units, Mapping) else {}


def _convert(values: np.ndarray, name: str, unit: Any) -> np.ndarray:
    """``values`` of variable ``name`` in ``unit`` converted to SI; DataError for an unknown unit."""
    kind, default = _KINDS[name]
    if unit is None:
        unit = default
    if kind in ("velocity", "spin", "angle"):
        try:
            canon = canonical_unit(str(unit), kind)
        except DataError as exc:
            raise DataError(exc.message, column=name, option="units") from None
        if kind == "velocity":
            factor = SPEED_UNITS[canon]
            return values * (BALL_RADIUS_M if factor is None else factor)
        if kind == "spin":
            return values * SPIN_UNITS[canon]
        return values * (ANGLE_UNITS[canon] * math.pi / 180.0)
    from bouncelab.data.shots import shot_unit_factor  # load_shots' table of distances and times: one table

    try:
        return values * shot_unit_factor(unit, kind)
    except DataError as exc:
        raise DataError(exc.message, column=name, option="units") from None


def _column(source: Any, name: str, labels: np.ndarray, unit: Any) -> np.ndarray:
    raw = np.asarray(source)
    if raw.ndim != 1:
        raise DataError(f"{name} must have one value per shot; got shape {raw.shape}", column=name)
    if raw.dtype == object:  # a missing cell (None, pandas' NA) is a missing value, named below with its row
        import pandas as pd

        raw = np.array([math.nan if v is None or v is pd.NA else v for v in raw], dtype=object)
    # text, bools and dates are refused, not turned into numbers by astype(float)
    values = real_array(raw, name, "one per shot", error=DataError, column=name)
    bad = ~np.isfinite(values)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise DataError(f"{int(bad.sum())} shot(s) have no finite {name} (NaN or infinite; first: {values[row]!r}); "
                        f"drop them first", column=name, row=row + 1, row_label=labels[row],
                        hints=[Hint("missing", "drop", "load_shots drops shots with blank cells")])
    return _convert(values, name, unit)


def _text(source: Any) -> np.ndarray:
    out = np.asarray(source, dtype=object)
    return np.array(["unknown" if v is None or (isinstance(v, float) and math.isnan(v)) else str(v) for v in out],
                    dtype=object)


def _shot_arrays(shots: Any, spin_kind: str | None = None, *, outcome: bool = True) -> ShotArrays:
    """The one adapter from :func:`bouncelab.ground.load_shots`'s result (or a DataFrame) to :class:`ShotArrays`.

    An xarray Dataset with dimension ``shot`` (units in each variable's ``attrs["units"]``; the
    spin's kind in ``spin.attrs["spin_at"]`` or the Dataset's ``attrs["spin_at"]``, as ``load_shots``
    writes them) or a pandas DataFrame with the same column names in SI units (m/s, rad, rad/s, m, s) unless
    ``frame.attrs["units"]`` maps a column to its unit (``{"landing_angle": "deg"}``), the spin's
    kind in ``frame.attrs["spin_at"]``. ``spin_kind=`` overrides both.
    """
    import pandas as pd
    import xarray as xr

    if isinstance(shots, xr.Dataset):
        if "shot" not in shots.dims:
            raise DataError(f"the shots Dataset needs a 'shot' dimension; it has {list(shots.dims)}", option="shots")
        labels = np.asarray(shots["shot"].values) if "shot" in shots.coords else np.arange(shots.sizes["shot"])
        names = set(shots.variables)

        def get(name: str) -> Any:
            da = shots[name]
            if da.dims != ("shot",):
                raise DataError(f"{name} must have the single dimension 'shot'; it has {da.dims}", column=name)
            return da.values

        def unit(name: str) -> Any:
            u = shots[name].attrs.get("units")
            if u is None and _KINDS[name][0] == "angle":
                raise DataError(f"{name} has no attrs['units'] ('deg' or 'rad'): an angle's unit is not guessed",
                                column=name, option="units")
            return u

        kind = shots["spin"].attrs.get("spin_at") if "spin" in names else None
        kind = kind or shots.attrs.get("spin_at")
    elif isinstance(shots, pd.DataFrame):
        labels = np.asarray(shots.index)
        names = set(shots.columns)
        frame_units = _frame_units(shots)

        def get(name: str) -> Any:
            return shots[name].to_numpy()

        def unit(name: str) -> Any:
            return frame_units.get(name)

        kind = shots.attrs.get("spin_at")
    else:
        raise DataError(f"shots must be the Dataset of bouncelab.ground.load_shots or a pandas DataFrame; got "
                        f"{type(shots).__name__}", option="shots")
    missing = [n for n in _REQUIRED if n not in names and (outcome or n != "total")]
    if missing:
        raise DataError(f"the shots have no {missing[0]!r} (they need {list(_REQUIRED)}; they have "
                        f"{sorted(map(str, names))})", column=missing[0])
    kind = spin_kind if spin_kind is not None else kind
    if kind not in _SPIN_KINDS:
        raise DataError(f"say whether the spin is the spin at launch or at landing (spin.attrs['spin_at'] or "
                        f"the shots' attrs['spin_at']: 'launch' or 'landing'); got {kind!r}", column="spin",
                        option="spin_kind", hints=[Hint("spin_kind", "launch"), Hint("spin_kind", "landing")])
    if len(labels) == 0:
        raise FitError("the shots are empty", option="shots")
    cols = {n: _column(get(n), n, labels, unit(n)) for n in _NUMERIC if n in names}
    if "total" not in cols:
        cols["total"] = np.full(len(labels), np.nan)
    if kind == "launch" and "flight_time" not in cols:
        raise DataError("the spin is the spin at launch, so its decay in flight needs each shot's flight_time (s); "
                        "the shots have none", column="flight_time",
                        hints=[Hint("spin_kind", "landing", "if the spin is the landing spin")])
    out = ShotArrays(landing_speed=cols["landing_speed"], landing_angle=cols["landing_angle"], spin=cols["spin"],
                     spin_kind=kind, carry=cols["carry"], total=cols["total"], labels=labels,
                     spin_axis=cols.get("spin_axis"), launch_angle=cols.get("launch_angle"), side=cols.get("side"),
                     side_total=cols.get("side_total"),
                     flight_time=cols.get("flight_time"),
                     club=_text(get("club")) if "club" in names else None,
                     session=_text(get("session")) if "session" in names else None)
    _check_plausible(out)
    return out


def _refuse(values: np.ndarray, bad: np.ndarray, name: str, labels: np.ndarray, what: str,
            hints: Iterable[Hint] = ()) -> None:
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise DataError(f"{int(bad.sum())} shot(s) have {what} (first: {values[row]:.6g})", column=name,
                        row=row + 1, row_label=labels[row], hints=hints)


def _check_plausible(s: ShotArrays) -> None:
    """The unit guard for shots: a value that only makes sense in another unit is refused, naming it."""
    units = [Hint("units", "...", "the variable's attrs['units']")]
    _refuse(s.landing_speed, (s.landing_speed < _MIN_SPEED) | (s.landing_speed > _MAX_SPEED), "landing_speed",
            s.labels, f"a landing speed outside {_MIN_SPEED:g}-{_MAX_SPEED:g} m/s: is its unit right?", units)
    deg = np.degrees(s.landing_angle)
    if deg.max() < 1.6 and len(deg) > 1:
        raise DataError(f"every landing angle is below 1.6 degrees (largest {deg.max():.3g} deg): radians read as "
                        "degrees? A landing comes down at 10-60 degrees", column="landing_angle", hints=units)
    _refuse(deg, (deg <= 0.0) | (deg > 90.0), "landing_angle", s.labels,
            "a descent angle outside (0, 90] degrees (the angle below the horizontal, positive; in degrees "
            "here): radians read as degrees, or degrees read as radians?", units)
    _refuse(s.spin * 60 / (2 * math.pi), np.abs(s.spin) > _MAX_SPIN, "spin", s.labels,
            "a spin above 20,000 rpm (shown in rpm): rpm read as rad/s?", units)
    # Whole-column guards: values each possible alone but not as a file's median.
    for name, values, limit, shown, why in (
            ("landing_speed", s.landing_speed, _MAX_MEDIAN_SPEED, "m/s", "mph or km/h read as m/s?"),
            ("spin", np.abs(s.spin) * 60 / (2 * math.pi), _MAX_MEDIAN_SPIN_RPM, "rpm", "rpm read as rad/s?")):
        median = float(np.median(values))
        if median > limit:
            raise DataError(f"the shots' median {name} is {median:.4g} {shown}, above the {limit:g} {shown} no set "
                            f"of golf shots lands with: {why}", column=name, hints=units)
    if s.spin_axis is not None:
        ax = np.degrees(s.spin_axis)
        _refuse(ax, np.abs(ax) >= 90.0, "spin_axis", s.labels, "a spin axis tilted 90 degrees or more (in degrees)",
                units)
    if s.launch_angle is not None:
        la = np.degrees(s.launch_angle)
        _refuse(la, np.abs(la) >= 90.0, "launch_angle", s.labels, "a launch angle of 90 degrees or more (in degrees)",
                units)
    _refuse(s.carry, s.carry <= 0.0, "carry", s.labels, "a carry of 0 m or less")
    if s.flight_time is not None:
        _refuse(s.flight_time, (s.flight_time <= 0.0) | (s.flight_time > _MAX_FLIGHT_S), "flight_time", s.labels,
                f"a flight time outside (0, {_MAX_FLIGHT_S:g}] s: milliseconds read as seconds?", units)


# ---------------------------------------------------------------------------------------- the model
@dataclass(frozen=True)
class _Landings:
    """What of the shots the objective needs, precomputed once (scaled units; trigonometry by libm)."""

    speed: np.ndarray  # radii/s
    cos_g: np.ndarray
    sin_g: np.ndarray
    spin: np.ndarray  # rad/s, at launch or landing
    cos_a: np.ndarray
    sin_a: np.ndarray
    cos_t: np.ndarray  # of the launch angle
    sin_t: np.ndarray
    flight_time: np.ndarray | None
    ratio: np.ndarray  # side / carry (0 without side)
    carry: np.ndarray
    side: np.ndarray


def _landings(s: ShotArrays) -> _Landings:
    # math's functions (libm) rather than NumPy's SIMD ones: the same bits on every CPU (tests/test_bits.py).
    cos, sin = np.frompyfunc(math.cos, 1, 1), np.frompyfunc(math.sin, 1, 1)
    axis = s.spin_axis if s.spin_axis is not None else np.zeros(len(s))
    launch = s.launch_angle if s.launch_angle is not None else np.zeros(len(s))
    side = s.side if s.side is not None else np.zeros(len(s))
    return _Landings(speed=s.landing_speed / BALL_RADIUS_M, cos_g=cos(s.landing_angle).astype(float),
                     sin_g=sin(s.landing_angle).astype(float), spin=s.spin, cos_a=cos(axis).astype(float),
                     sin_a=sin(axis).astype(float), cos_t=cos(launch).astype(float),
                     sin_t=sin(launch).astype(float), flight_time=s.flight_time, ratio=side / s.carry,
                     carry=s.carry, side=side)


@dataclass(frozen=True)
class _Model:
    """How a vector of parameter values becomes a surface and predicted rest points."""

    law: Any  # the law given (its options, and the values of its held parameters)
    names: tuple[str, ...]  # every parameter, law's elements first
    law_elements: tuple[tuple[str, int, tuple[int, ...]], ...]  # (law parameter, number of elements, shape)
    name: str
    max_bounces: int

    def surface(self, values: Mapping[str, float], description: str = "") -> Surface:
        from bouncelab.ground.surface import Surface

        kwargs, flat = {}, [values[n] for n in self.names]
        i = 0
        for pname, size, shape in self.law_elements:
            chunk = flat[i:i + size]
            kwargs[pname] = chunk[0] if not shape else np.reshape(chunk, shape)
            i += size
        law = self.law.replace(**kwargs)
        return Surface(name=self.name, law=law, sliding_friction=values["sliding_friction"],
                       stimp_m=values["stimp_m"], pivot_retention=1.0, description=description)

    def rest(self, values: Mapping[str, float], land: _Landings, limit: bool = True,
             max_bounces: int | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Predicted roll-out along the target line and to the right (m), and which shots hit ``max_bounces``
        (None unless ``limit``: the search needs no per-shot table)."""
        return _rest(self.surface(values), values.get("spin_decay", 0.0), values.get("heading_gain", 0.0), land,
                     max_bounces or self.max_bounces, limit)


def _rest(surface: Surface, decay: float, gain: float, land: _Landings, max_bounces: int,
          limit: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The model of a shot (module notes): its landing in the target frame, run to rest on ``surface``."""
    from bouncelab.ground.runout import run

    if land.flight_time is not None and decay:
        k = -float(decay)
        spin = land.spin * np.array([math.exp(k * t) for t in land.flight_time])
    else:
        spin = land.spin
    t = gain * land.ratio  # tan(h)
    c = 1.0 / np.sqrt(1.0 + t * t)  # cos h
    sh = t * c  # sin h (to the right)
    # heading frame: e_h = (c, -sh, 0), left of it e_l = (sh, c, 0)
    v_h, v_z = land.speed * land.cos_g, -land.speed * land.sin_g
    w_h = spin * land.sin_a * land.sin_t  # the axis perpendicular to the launch direction (module notes)
    w_l = -spin * land.cos_a
    w_z = -spin * land.sin_a * land.cos_t
    v = np.column_stack([v_h * c, -v_h * sh, v_z])
    w = np.column_stack([w_h * c + w_l * sh, -w_h * sh + w_l * c, w_z])
    # BounceLimitWarning: the fit counts such shots and reports them, and the callers silence the warning
    # (see _quiet: warnings.catch_warnings is not safe around threads that share the filters).
    res = run(v, w, surface, max_bounces=max_bounces)
    rest = res.rest_position * BALL_RADIUS_M
    return rest[:, 0], -rest[:, 1], np.asarray(res.totals["bounce_limit"]) if limit else None


def predict_shots(shots: Any, surface: Surface | str, *, spin_decay: float | None = None,
                  heading_gain: float = 1.0, spin_kind: str | None = None,
                  max_bounces: int = 100) -> pd.DataFrame:
    """Where launch-monitor shots would stop on a surface: their landings run to rest (the model of the module notes).

    Parameters
    ----------
    shots
        As for :func:`fit_surface` (``total`` and ``side_total`` are not needed).
    surface
        A :class:`~bouncelab.ground.Surface` or a preset's name.
    spin_decay
        The spin's decay rate in flight (1/s), required when the shots give the spin at launch
        (not used for landing spin).
    heading_gain
        ``tan(landing heading) / (side / carry)`` (1: the ball lands along the chord from the tee).
    spin_kind
        ``"launch"`` or ``"landing"``, if the shots do not say.
    max_bounces
        As for :func:`~bouncelab.ground.run`.

    Returns
    -------
    pandas.DataFrame
        One row per shot (indexed by the shots' labels), in metres: ``roll`` (total - carry
        along the target line), ``total``, ``side_roll`` and ``side_total`` (positive to the
        right; only where the shots give a side), ``bounce_limit``.

    Raises
    ------
    DataError
        As :func:`fit_surface` for the shots.
    ParameterError
        A missing or bad ``spin_decay``, ``heading_gain`` or ``max_bounces``, or an unknown preset.
    """
    import pandas as pd

    from bouncelab.ground.surface import Surface, preset

    if isinstance(surface, str):
        surface = preset(surface)
    if not isinstance(surface, Surface):
        raise ParameterError(f"surface must be a bouncelab.ground.Surface or a preset name; got "
                             f"{type(surface).__name__}", parameter="surface")
    s = _shot_arrays(shots, spin_kind, outcome=False)
    if s.spin_kind == "launch" and spin_decay is None:
        raise ParameterError("the shots give the spin at launch: say how fast it decays in flight (spin_decay, 1/s; "
                             "0 for none)", parameter="spin_decay", hints=[Hint("spin_decay", 0.05)])
    decay = 0.0 if s.spin_kind == "landing" else _value(spin_decay, "spin_decay")
    gain = _value(heading_gain, "heading_gain")
    if isinstance(max_bounces, bool) or not isinstance(max_bounces, int | np.integer) or max_bounces < 1:
        raise ParameterError(f"max_bounces must be a whole number >= 1; got {max_bounces!r}", parameter="max_bounces")
    with _quiet():
        along, right, limit = _rest(surface, decay, gain, _landings(s), int(max_bounces), True)
    data = {"roll": along, "total": s.carry + along}
    if s.side is not None:
        data.update(side_roll=right, side_total=s.side + right)
    data["bounce_limit"] = limit
    return pd.DataFrame(data, index=pd.Index(s.labels, name="shot"))


def _value(value: Any, name: str) -> float:
    """``value`` as a float inside the physical range of :data:`SURFACE_PARAMETERS` ``[name]``."""
    lo, hi = SURFACE_PARAMETERS[name].physical
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer) or not (
            lo <= value <= hi):
        raise ParameterError(f"{name} must be a number in [{lo:g}, {hi:g}] ({SURFACE_PARAMETERS[name].doc}); got "
                             f"{value!r}", parameter=name, value=value)
    return float(value)


def _quiet() -> Any:
    """Silence :class:`~bouncelab.ground.BounceLimitWarning` (the fit counts those shots) on the main thread.

    ``warnings.catch_warnings`` changes the process's filters: entered and left by several threads
    at once it can restore the wrong ones. The main thread (serial fits, a process executor's
    worker, the caller of :func:`fit_surface` around a thread executor) silences; a worker thread
    relies on its caller's filter.
    """
    import contextlib
    import threading

    from bouncelab.ground.runout import BounceLimitWarning

    if threading.current_thread() is not threading.main_thread():
        return contextlib.nullcontext()
    ctx = warnings.catch_warnings()

    @contextlib.contextmanager
    def quiet():
        with ctx:
            warnings.simplefilter("ignore", BounceLimitWarning)
            yield

    return quiet()


def _errors(along: np.ndarray, right: np.ndarray, s: ShotArrays) -> np.ndarray:
    """Per shot: distance between predicted and observed rest points (m); roll-out error alone without side."""
    return np.sqrt(_squared(along, right, s))


def _squared(along: np.ndarray, right: np.ndarray, s: ShotArrays) -> np.ndarray:
    d_along = along - s.roll
    if not s.lateral:
        return d_along * d_along
    d_right = right - s.side_roll
    return d_along * d_along + d_right * d_right


def _loss(along: np.ndarray, right: np.ndarray, s: ShotArrays, scale: float) -> float:
    """The objective: the mean pseudo-Huber loss of the rest-point distances d, ``c^2 (sqrt(1 + d^2/c^2) - 1)`` (m^2).

    d^2 / 2 for distances well under the scale ``c``, ``c d`` well over it: smooth at the optimum (where a
    mean absolute error has a kink per shot, on which a local search stalls) and robust to outliers.
    """
    c2 = scale * scale
    return float(np.mean(c2 * (np.sqrt(1.0 + _squared(along, right, s) / c2) - 1.0)))


# ------------------------------------------------------------------------------------ the search
@dataclass(frozen=True)
class _Task:
    """One fit (all shots, or one fold's training shots): picklable, so an executor can run it."""

    model: _Model
    shots: ShotArrays
    start: dict[str, float]
    vary: tuple[str, ...]
    low: np.ndarray
    high: np.ndarray
    seed: int
    maxeval: int
    local_maxeval: int
    final_maxeval: int
    global_shots: int
    loss_scale: float
    fold: int  # 0: all shots


@dataclass(frozen=True)
class _Outcome:
    values: dict[str, float]
    objective: float
    n_evaluations: int
    stop: str
    elapsed: float
    infeasible: int


def _nlopt(algorithm: int, f: Any, x0: np.ndarray, maxeval: int, *, step: float | None = None,
           seen: list | None = None) -> tuple[np.ndarray, float, str]:
    """One NLopt run in the unit box; the best point it saw, its value and why it stopped (``seen`` collects
    every point and value)."""
    import nlopt

    from bouncelab.fitting.search import run_nlopt

    d = len(x0)
    best = [x0.copy(), math.inf]

    raised: list[BaseException] = []

    def wrapped(x: np.ndarray, grad: np.ndarray) -> float:
        try:
            v = f(x)
        except BaseException as exc:  # (an interrupt NLopt might lose: run_nlopt re-raises it)
            raised.append(exc)
            raise
        v = 1e300 if not math.isfinite(v) else v
        if v < best[1]:
            best[0], best[1] = x.copy(), v
        if seen is not None:
            seen.append((v, x.copy()))
        return v

    opt = nlopt.opt(algorithm, d)
    opt.set_lower_bounds(np.zeros(d))
    opt.set_upper_bounds(np.ones(d))
    opt.set_min_objective(wrapped)
    opt.set_maxeval(int(maxeval))
    if step is not None:
        opt.set_initial_step(np.full(d, step))
        opt.set_xtol_rel(1e-6)
    try:
        run_nlopt(opt, np.clip(x0, 0.0, 1.0), raised)
        stop = {1: "success", 3: "ftol reached", 4: "xtol reached", 5: "maxeval reached"}.get(
            opt.last_optimize_result(), str(opt.last_optimize_result()))
    except (nlopt.RoundoffLimited, ValueError, RuntimeError) as exc:  # NLopt's failure codes: keep the best point
        stop = f"stopped ({type(exc).__name__})"
    return best[0], best[1], stop


def _distinct(seen: list, k: int, distance: float) -> list[np.ndarray]:
    """Up to ``k`` of the best points seen, pairwise at least ``distance`` apart (max norm), best first."""
    chosen: list[np.ndarray] = []
    for _, x in sorted(seen, key=lambda item: item[0]):
        if all(np.max(np.abs(x - c)) >= distance for c in chosen):
            chosen.append(x)
            if len(chosen) == k:
                break
    return chosen


def _run_task(task: _Task) -> _Outcome:
    """Fit one task: NLopt's CRS2 global search in the unit box of the varied parameters, then a BOBYQA polish.

    With more than ``global_shots`` shots the global stage and its polish run on a random
    subset of that many (drawn with the task's seed), and a last polish on all of them. The
    global stage puts a ball on the ground after :data:`GLOBAL_MAX_BOUNCES` bounces.
    """
    import nlopt

    width = task.high - task.low
    infeasible = [0]
    calls = [0]

    def values_at(x: np.ndarray) -> dict[str, float]:
        values = dict(task.start)
        for name, lo, w, xi in zip(task.vary, task.low, width, x, strict=True):
            values[name] = float(lo + w * min(max(xi, 0.0), 1.0))
        return values

    def objective(shots: ShotArrays, max_bounces: int | None = None) -> Any:
        land = _landings(shots)

        def f(x: np.ndarray) -> float:
            calls[0] += 1
            try:
                along, right, _ = task.model.rest(values_at(x), land, limit=False, max_bounces=max_bounces)
            except (ParameterError, DataError):  # a point where the law or the surface is refused
                infeasible[0] += 1
                return math.inf
            return _loss(along, right, shots, task.loss_scale)

        return f

    start = time.perf_counter()
    x0 = np.array([(task.start[name] - lo) / w if w > 0 else 0.0
                   for name, lo, w in zip(task.vary, task.low, width, strict=True)])
    n = len(task.shots)
    subset = n > task.global_shots
    first = task.shots
    if subset:
        pick = np.random.default_rng(task.seed).choice(n, task.global_shots, replace=False)
        first = task.shots.take(np.sort(pick))
    nlopt.srand(int(task.seed))
    with _quiet():
        rough = objective(first, min(GLOBAL_MAX_BOUNCES, task.model.max_bounces))
        seen: list = []
        x, fx, stop = _nlopt(nlopt.GN_CRS2_LM, rough, x0, task.maxeval, seen=seen)
        stops = [f"global {stop}"]
        if task.local_maxeval:
            # Polish the best distinct points of the global stage and keep the best: the loss has valleys
            # (restitution against spin decay, say) in which one local search from one point can stall.
            fine = objective(first)
            best = None
            for k, point in enumerate(_distinct(seen, POLISH_STARTS, 0.1)):
                xk, fk, stop = _nlopt(nlopt.LN_BOBYQA, fine, point, task.local_maxeval, step=0.02)
                stops.append(f"local {k + 1} {stop}")
                if best is None or fk < best[1]:
                    best = (xk, fk)
            x, fx = best
            x, fx, stop = _nlopt(nlopt.LN_BOBYQA, fine, x, task.local_maxeval, step=0.05)  # restart wider
            stops.append(f"restart {stop}")
        if subset and task.final_maxeval:
            x, fx, stop = _nlopt(nlopt.LN_BOBYQA, objective(task.shots), x, task.final_maxeval, step=0.005)
            stops.append(f"on all shots {stop}")
        elif subset or not task.local_maxeval:
            fx = objective(task.shots)(x)  # the loss of the full model on all the shots
    return _Outcome(values=values_at(x), objective=float(fx), n_evaluations=calls[0], stop="; ".join(stops),
                    elapsed=time.perf_counter() - start, infeasible=infeasible[0])


# ------------------------------------------------------------------------------------ the result
@dataclass
class SurfaceFit:
    """What :func:`fit_surface` found: the surface, its parameters, held-out errors and a report.

    Attributes
    ----------
    surface
        The fitted :class:`~bouncelab.ground.Surface` (fitted to all the shots), usable as a
        preset: :func:`~bouncelab.ground.run`, ``to_json``, ``bouncelab export``.
    params
        The parameters (:class:`~bouncelab.laws.Parameters`): value, bounds, unit, whether it varied.
    parameters
        A table per parameter: ``value``, ``low``, ``high``, ``unit``, ``vary``, ``fold_min`` and
        ``fold_max`` (its range over the final fit and the folds as good as it on all the shots;
        NaN when there are none), ``sensitivity`` (how much the mean error, in m,
        rises when the parameter alone moves by 5 % of its box either way, the smaller rise),
        ``at_bound`` and ``identified`` (see :attr:`identifiable`).
    heldout
        One row per shot, from the fold that held it out: ``fold``, ``club`` (if any),
        ``observed_roll``, ``predicted_roll``, ``roll_error`` (predicted - observed, m) and, with
        side data, ``observed_side_roll``, ``predicted_side_roll``, ``side_roll_error``,
        ``distance_error``. Empty when ``folds=0``.
    errors
        The held-out errors summarised, one row for all shots and one per club: ``shots``,
        ``observed_median_roll``, ``median_abs_error`` of the roll-out, its quartiles
        ``abs_error_q25`` and ``abs_error_q75``, ``mae``, and ``baseline_median_abs_error``: the
        error of predicting every held-out shot's roll-out by the median roll-out of its fold's
        training shots (what the physics must beat).
    fitted_errors, fitted_predictions
        The same summary, and the same per-shot table without ``fold``, for the fitted surface
        on the shots it was fitted to (in-sample).
    folds
        One row per fold: shots fitted and held out, held-out median absolute roll-out error,
        the loss reached, evaluations, time, each varied parameter's value, its parameters'
        ``mean_error_all_shots`` and whether that is as good as the final fit's (``equivalent``).
    mean_error
        The fitted surface's mean rest-point distance (or absolute roll-out) error on all the
        shots (m).
    loss
        The objective's value there (mean pseudo-Huber loss, m^2).
    n_evaluations, elapsed
        Objective evaluations and wall time (s) of all the fits (folds and final).
    bounce_limit
        Shots whose run with the fitted surface was still bouncing at ``max_bounces``.
    spin_kind, groups, seed, law, notes
        As given or found.
    """

    surface: Surface
    params: Parameters
    parameters: pd.DataFrame
    heldout: pd.DataFrame
    errors: pd.DataFrame
    fitted_errors: pd.DataFrame
    fitted_predictions: pd.DataFrame
    folds: pd.DataFrame
    mean_error: float
    loss: float
    n_evaluations: int
    elapsed: float
    bounce_limit: int
    spin_kind: str
    groups: str
    seed: int
    law: str
    n_shots: int
    lateral: bool
    notes: list[str] = field(default_factory=list)
    _model: _Model | None = field(default=None, repr=False)
    _values: dict[str, float] = field(default_factory=dict, repr=False)

    @property
    def identifiable(self) -> dict[str, bool]:
        """Varied parameter -> whether the shots determine it.

        Each fold's parameters are scored on all the shots: a fold whose mean error there is
        within 2 % (+ 1 cm) of the final fit's is one the shots cannot tell from it; a worse one
        ended its search in another basin and is left out (``folds["equivalent"]``). A parameter
        counts as determined when the final fit and those folds agree to within 10 % of its
        search box and the mean error rises by at least 1 cm when it alone moves 5 % of the box
        either way from the fitted value. Without such folds only the second test applies. The
        verdict is local: a distant basin that fits almost as well shows only when a fold's
        search lands in it.
        """
        t = self.parameters[self.parameters["vary"]]
        return {str(k): bool(v) for k, v in t["identified"].items()}

    def predict(self, shots: Any, *, spin_kind: str | None = None) -> pd.DataFrame:
        """Predicted roll-out and rest point of ``shots`` on the fitted surface.

        :func:`predict_shots` with the fitted surface, spin decay and heading gain.

        Parameters
        ----------
        shots
            As for :func:`fit_surface` (``total`` and ``side_total`` are not needed).
        spin_kind
            ``"launch"`` or ``"landing"``, if the shots do not say; it must be the kind the
            surface was fitted to.

        Returns
        -------
        pandas.DataFrame
            One row per shot (indexed by the shots' labels), in metres: ``roll`` (total - carry
            along the target line), ``total``, ``side_roll`` and ``side_total`` (positive to the
            right; the side columns only where the shots give a side), ``bounce_limit``.
        """
        kind = _shot_arrays(shots, spin_kind, outcome=False).spin_kind
        if kind != self.spin_kind:
            raise DataError(f"the surface was fitted to {self.spin_kind} spin; these shots give {kind} spin",
                            column="spin", option="spin_kind")
        v = self._values
        return predict_shots(shots, self.surface, spin_decay=v.get("spin_decay", 0.0),
                             heading_gain=v.get("heading_gain", 0.0), spin_kind=kind,
                             max_bounces=self._model.max_bounces)

    def report(self) -> str:
        """The readable report (also ``str(result)``)."""
        lines = [f"Surface fitted to {self.n_shots} launch-monitor shots ({self.spin_kind} spin"
                 f"{', with side' if self.lateral else ', no side data'}): law {self.law}",
                 f"fitted surface: mean {'rest-point distance' if self.lateral else 'absolute roll-out'} error "
                 f"{self.mean_error:.3f} m on all shots; {self.n_evaluations} evaluations in {self.elapsed:.1f} s",
                 "", "parameters (fold range: the final fit's and the folds' as good as it on all shots; sensitivity: "
                 "rise of the mean error, m, at +-5 % of the box):"]
        t = self.parameters
        head = f"  {'name':<17}{'value':>11}  {'bounds':<17}{'unit':<7}{'fold range':<21}{'sensitivity':>11}  note"
        lines.append(head)
        for name, r in t.iterrows():
            bounds = f"[{r['low']:.4g}, {r['high']:.4g}]"
            if not r["vary"]:
                lines.append(f"  {name:<17}{r['value']:>11.5g}  {bounds:<17}{r['unit']:<7}{'':<21}{'':>11}  held")
                continue
            frange = "" if np.isnan(r["fold_min"]) else f"{r['fold_min']:.4g} - {r['fold_max']:.4g}"
            note = "determined" if r["identified"] else "NOT determined by these shots"
            if r["at_bound"]:
                note += f"; at its {r['at_bound']} bound"
            lines.append(f"  {name:<17}{r['value']:>11.5g}  {bounds:<17}{r['unit']:<7}{frange:<21}"
                         f"{r['sensitivity']:>11.3g}  {note}")
        lines.append("")
        if len(self.heldout):
            lines.append(f"held out ({len(self.folds)} folds over {self.groups}s), roll-out = total - carry (m):")
            lines += ["  " + line for line in _error_table(self.errors).splitlines()]
        else:
            lines.append("no held-out errors (folds=0); roll-out on the fitted shots (m):")
            lines += ["  " + line for line in _error_table(self.fitted_errors).splitlines()]
        if self.bounce_limit:
            lines.append(f"{self.bounce_limit} shot(s) were still bouncing at max_bounces on the fitted surface")
        lines += ["", *self.notes]
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()

    def __repr__(self) -> str:
        e = self.errors if len(self.heldout) else self.fitted_errors
        what = "held-out" if len(self.heldout) else "fitted"
        return (f"SurfaceFit({self.law} on {self.n_shots} shots: {what} median |roll error| "
                f"{e.loc['all', 'median_abs_error']:.3g} m, median roll {e.loc['all', 'observed_median_roll']:.3g} m)")

    def _repr_html_(self) -> str:
        from bouncelab.ground._display import surface_fit_html  # the notebook view

        return surface_fit_html(self)


def _prediction_table(s: ShotArrays, along: np.ndarray, right: np.ndarray, fold: np.ndarray | None) -> pd.DataFrame:
    import pandas as pd

    data: dict[str, Any] = {} if fold is None else {"fold": fold}
    if s.club is not None:
        data["club"] = s.club
    data.update(observed_roll=s.roll, predicted_roll=along, roll_error=along - s.roll)
    if s.lateral:
        data.update(observed_side_roll=s.side_roll, predicted_side_roll=right, side_roll_error=right - s.side_roll,
                    distance_error=np.hypot(along - s.roll, right - s.side_roll))
    return pd.DataFrame(data, index=pd.Index(s.labels, name="shot"))


def _error_table(t: pd.DataFrame) -> str:
    cols = {"shots": "shots", "observed_median_roll": "median roll", "median_abs_error": "median |err|",
            "abs_error_q25": "q25 |err|", "abs_error_q75": "q75 |err|", "mae": "mean |err|",
            "baseline_median_abs_error": "baseline median |err|"}
    shown = t[[c for c in cols if c in t]].rename(columns=cols)
    return shown.to_string(float_format=lambda x: f"{x:.3g}")


def _summary(observed: np.ndarray, predicted: np.ndarray, club: np.ndarray | None,
             baseline: np.ndarray | None) -> pd.DataFrame:
    import pandas as pd

    def row(m: np.ndarray) -> dict[str, float]:
        e = np.abs(predicted[m] - observed[m])
        q25, q50, q75 = np.quantile(e, [0.25, 0.5, 0.75])
        out = {"shots": int(m.sum()), "observed_median_roll": float(np.median(observed[m])),
               "median_abs_error": float(q50), "abs_error_q25": float(q25), "abs_error_q75": float(q75),
               "mae": float(e.mean())}
        if baseline is not None:
            out["baseline_median_abs_error"] = float(np.median(np.abs(baseline[m] - observed[m])))
        return out

    rows = {"all": row(np.ones(len(observed), dtype=bool))}
    if club is not None:
        for c in sorted(set(club)):
            rows[f"club {c}"] = row(club == c)
    return pd.DataFrame.from_dict(rows, orient="index")


# ------------------------------------------------------------------------------------- fit_surface
def _law(law: Any) -> BounceModel:
    from bouncelab.fitting.fitter import law_instance

    try:
        return law_instance(law)
    except FitError as exc:
        raise FitError(exc.message, law=exc.law, option="law", hints=exc.hints) from None


def _parameter_table(law: BounceModel, lateral: bool, spin_kind: str) -> list[Parameter]:
    """Every parameter of the fit (the law's elements, then the surface's), starts and boxes as defaults."""
    params = []
    for spec in law.parameter_specs:
        lo, hi = spec.bound_arrays()
        plo, phi = spec.physical_arrays()
        value = law.parameters[spec.name]
        flat = (0.5 * (lo + hi)) if value is None else np.ravel(value)
        for i, name in enumerate(spec.element_names()):
            params.append(Parameter(name=name.replace("[", "_").replace(",", "_").replace("]", "")
                                    if not spec.is_scalar else name,
                                    bounds=(float(lo[i]), float(hi[i])), physical=(float(plo[i]), float(phi[i])),
                                    unit=spec.unit, doc=spec.doc, value=float(flat[i]), vary=spec.vary))
    params += [SURFACE_PARAMETERS["sliding_friction"], SURFACE_PARAMETERS["stimp_m"]]
    params.append(SURFACE_PARAMETERS["spin_decay"].replace(
        value=SURFACE_PARAMETERS["spin_decay"].value if spin_kind == "launch" else 0.0, vary=spin_kind == "launch"))
    params.append(SURFACE_PARAMETERS["heading_gain"].replace(
        value=1.0 if lateral else 0.0, vary=lateral))
    return params


def _settle(params: list[Parameter], vary: Any, start: Mapping[str, float] | None,
            bounds: Mapping[str, tuple[float, float]] | None, spin_kind: str, lateral: bool) -> list[Parameter]:
    """Apply ``vary``, ``start`` and ``bounds`` to the default parameters, checking each against its physical range."""
    names = [p.name for p in params]
    by_name = {p.name: p for p in params}
    if vary is None:
        chosen = {p.name: p.vary for p in params}
    else:
        if isinstance(vary, str):
            vary = [vary]
        if isinstance(vary, Mapping):
            chosen = {n: by_name[n].vary and n not in vary for n in names} | {k: bool(v) for k, v in vary.items()}
            asked = list(vary)
        elif isinstance(vary, Iterable):
            asked = list(vary)
            chosen = {n: n in asked for n in names}
        else:
            raise FitError(f"vary must be None, a list of parameter names or a mapping name -> bool; got {vary!r}",
                           option="vary")
        unknown = [n for n in asked if n not in by_name]
        if unknown:
            raise FitError(f"no parameter {unknown[0]!r} to vary; the parameters are {names}", option="vary")
        for n in asked:
            if not chosen[n]:
                continue
            if n == "spin_decay" and spin_kind != "launch":
                raise FitError("spin_decay applies to launch spin only; these shots give the spin at landing",
                               option="vary")
            if n == "heading_gain" and not lateral:
                raise FitError("heading_gain needs the shots' side and side_total; these shots have none",
                               option="vary")
    for mapping, what in ((start, "start"), (bounds, "bounds")):
        if mapping is None:
            continue
        if not isinstance(mapping, Mapping):
            raise FitError(f"{what} must be a mapping name -> value; got {type(mapping).__name__}", option=what)
        unknown = [n for n in mapping if n not in by_name]
        if unknown:
            raise FitError(f"{what} names no parameter {unknown[0]!r}; the parameters are {names}", option=what)
    out = []
    for p in params:
        lo, hi = p.bounds
        plo, phi = p.physical
        if bounds and p.name in bounds:
            try:
                lo, hi = (float(b) for b in bounds[p.name])
            except (TypeError, ValueError):
                raise FitError(f"bounds[{p.name!r}] must be a (low, high) pair of numbers; got {bounds[p.name]!r}",
                               option="bounds") from None
            if not (math.isfinite(lo) and math.isfinite(hi) and plo <= lo < hi <= phi):
                raise FitError(f"bounds[{p.name!r}] = ({lo:g}, {hi:g}) must satisfy {plo:g} <= low < high <= {phi:g} "
                               f"(its physical range: {p.doc})", option="bounds")
        value = p.value
        if start and p.name in start:
            try:
                value = float(start[p.name])
            except (TypeError, ValueError):
                raise FitError(f"start[{p.name!r}] must be a number; got {start[p.name]!r}", option="start") from None
        if not (math.isfinite(value) and plo <= value <= phi):
            raise FitError(f"start[{p.name!r}] = {value!r} is outside its physical range [{plo:g}, {phi:g}]",
                           option="start")
        if chosen[p.name] and not lo <= value <= hi:
            raise FitError(f"the start of {p.name!r} ({value:g}) is outside its bounds [{lo:g}, {hi:g}]",
                           option="start")
        out.append(p.replace(bounds=(lo, hi), value=value, vary=chosen[p.name]))
    if not any(p.vary for p in out):
        raise FitError("no parameter varies; name some in vary=", option="vary")
    return out


def _folds(s: ShotArrays, folds: int, groups: str, seed: int) -> tuple[list[np.ndarray], str]:
    """Index arrays of the held-out shots of each fold, and the grouping used."""
    if groups == "auto":
        groups = "session" if s.session is not None and len(set(s.session)) >= folds else "shot"
    rng = np.random.default_rng(seed)
    if groups == "shot":
        order = rng.permutation(len(s))
        return [np.sort(part) for part in np.array_split(order, folds)], groups
    labels = s.session if groups == "session" else s.club
    if labels is None:
        raise FitError(f"groups={groups!r}, but the shots have no {groups}", option="groups")
    uniq = sorted(set(labels))
    if len(uniq) < folds:
        raise FitError(f"groups={groups!r} needs at least folds={folds} different {groups}s; the shots have "
                       f"{len(uniq)}", option="groups")
    perm = rng.permutation(len(uniq))
    fold_of = {u: int(perm[i]) % folds for i, u in enumerate(uniq)}
    which = np.array([fold_of[v] for v in labels])
    return [np.flatnonzero(which == k) for k in range(folds)], groups


def fit_surface(shots: Any, law: Any = "PennerFixed", vary: Sequence[str] | Mapping[str, bool] | None = None, *,
                seed: int = 0, executor: Any = None, folds: int = 5, groups: str = "auto",
                start: Mapping[str, float] | None = None, bounds: Mapping[str, tuple[float, float]] | None = None,
                spin_kind: str | None = None, name: str = "fitted", maxeval: int | None = None,
                local_maxeval: int = 500, final_maxeval: int = 150, global_shots: int = 500,
                max_bounces: int = FIT_MAX_BOUNCES, loss_scale: float = 1.0) -> SurfaceFit:
    r"""Fit a :class:`~bouncelab.ground.Surface` to launch-monitor shots, held out by default.

    Finds the law's parameters, the sliding friction, the Stimpmeter speed and (launch spin
    only) the spin's decay rate in flight, and the landing heading's gain (side data only),
    so that :func:`~bouncelab.ground.run` on each shot's landing stops where the shot did: the
    mean distance (m) between predicted and observed rest points is minimised by NLopt's global
    search within the parameters' bounds (see :mod:`bouncelab.ground.fit` for the model).

    Parameters
    ----------
    shots
        The Dataset of :func:`bouncelab.ground.load_shots` (dimension ``shot``; variables
        ``landing_speed``, ``landing_angle``, ``spin``, ``carry``, ``total`` and optionally
        ``spin_axis``, ``launch_angle``, ``side``, ``side_total``, ``flight_time``, ``club``,
        ``session``; units
        in each variable's ``attrs["units"]``), or a DataFrame with those columns in SI units
        (m/s, rad, rad/s, m, s) unless ``frame.attrs["units"]`` maps a column to another unit
        (``{"landing_angle": "deg", "spin": "rpm"}``). ``landing_angle`` is the descent angle
        below the horizontal (positive); ``side`` and ``side_total`` are positive to the right;
        a positive ``spin_axis`` curves the ball right; ``launch_angle`` (optional) sets the
        direction of the spin axis, which is perpendicular to the launch.
    law
        The bounce law: a name, a class or an instance (whose values are the starts and the
        values of the parameters held, and whose options, such as ``fade_xdot``, are kept).
    vary
        Which parameters vary: None (the law's, ``sliding_friction``, ``stimp_m``,
        ``spin_decay`` for launch spin and ``heading_gain`` with side data), a list of names
        (the others held at their start) or a mapping name -> bool (changes to the default).
    seed
        Seed of the folds and of NLopt's search: the same seed, the same result.
    executor
        Where the fits run (the final one and one per fold): None (serially) or any
        :class:`concurrent.futures.Executor` or dask client; the results are the serial ones.
    folds
        Folds of the held-out errors (>= 2), or 0 for none (fit only).
    groups
        What a fold holds out: ``"shot"``, ``"session"``, ``"club"`` or ``"auto"`` (sessions
        when there are at least ``folds`` of them, else shots).
    start, bounds
        Starts and search boxes by parameter name (within each parameter's physical range).
    spin_kind
        ``"launch"`` or ``"landing"`` when the shots do not say.
    name
        The fitted surface's name.
    maxeval, local_maxeval, final_maxeval
        Evaluations of the global stage (default ``100 * (varied + 1)``), of its local polish,
        and of the last polish on all the shots (when ``global_shots`` took a subset).
    global_shots
        With more shots than this in a fit, the global stage and its polish run on a random
        subset of this many, then a last polish on all of them (each evaluation of the global
        stage is then cheaper; the optimum is the one of all the shots).
    max_bounces
        As for :func:`~bouncelab.ground.run`, for the fit's runs and the result's predictions
        (default :data:`FIT_MAX_BOUNCES` = 40); the result counts the shots that reach it.
    loss_scale
        The scale ``c`` (m) of the objective's pseudo-Huber loss: quadratic in a shot's
        rest-point distance below it, linear above (so a few wild totals do not pull the fit).

    Returns
    -------
    SurfaceFit
        ``.surface``, ``.predict(shots)``, held-out ``.errors``, ``.parameters`` and a report
        (``print(result)``).

    Raises
    ------
    DataError
        Missing variables, NaN values, a value that only makes sense in another unit, an
        unknown unit, an unknown spin kind (naming the variable and shot).
    FitError
        Too few shots, an unknown law name, bad ``vary``/``start``/``bounds``/``folds``/``groups``.
    """
    from bouncelab.fitting.fitter import check_count, check_seed
    from bouncelab.fitting.tasks import map_tasks
    from bouncelab.laws import law_name

    seed = check_seed(seed)
    base = _law(law)
    lname = law_name(base)
    if groups not in _GROUPS:
        raise FitError(f"groups must be one of {list(_GROUPS)}; got {groups!r}", option="groups")
    folds = 0 if folds in (0, None) else check_count(folds, "folds", 2)
    max_bounces = check_count(max_bounces, "max_bounces", 1)
    if isinstance(loss_scale, bool) or not isinstance(loss_scale, int | float) or not 0 < loss_scale < math.inf:
        raise FitError(f"loss_scale must be a positive number of metres; got {loss_scale!r}", option="loss_scale")
    loss_scale = float(loss_scale)
    local_maxeval = check_count(local_maxeval, "local_maxeval", 0)
    final_maxeval = check_count(final_maxeval, "final_maxeval", 0)
    global_shots = check_count(global_shots, "global_shots", MIN_SHOTS)
    if not isinstance(name, str) or not name.strip():
        raise FitError(f"name must be non-empty text; got {name!r}", option="name")
    s = _shot_arrays(shots, spin_kind)
    params = _settle(_parameter_table(base, s.lateral, s.spin_kind), vary, start, bounds, s.spin_kind, s.lateral)
    varied = [p for p in params if p.vary]
    maxeval = 100 * (len(varied) + 1) if maxeval is None else check_count(maxeval, "maxeval", 1)
    if folds > len(s):
        raise FitError(f"folds={folds} is more than the {len(s)} shots", option="folds")
    need = max(MIN_SHOTS, 2 * len(varied))
    smallest = len(s) - (math.ceil(len(s) / folds) if folds else 0)
    if smallest < need:
        raise FitError(f"{len(s)} shots are too few: a fit of {len(varied)} parameters takes at least {need} shots "
                       f"{'in each fold' if folds else ''} (a fold here fits {smallest})".rstrip(), option="shots")
    law_elements = tuple((spec.name, spec.size, spec.shape) for spec in base.parameter_specs)
    model = _Model(law=base, names=tuple(p.name for p in params), law_elements=law_elements, name=name,
                   max_bounces=max_bounces)
    starts = {p.name: float(p.value) for p in params}
    low = np.array([p.bounds[0] for p in varied])
    high = np.array([p.bounds[1] for p in varied])
    vnames = tuple(p.name for p in varied)
    held, groups_used = _folds(s, folds, groups, seed) if folds else ([], "none")
    tasks = [_Task(model, s, starts, vnames, low, high, seed, maxeval, local_maxeval, final_maxeval,
                   global_shots, loss_scale, 0)]
    for k, te in enumerate(held):
        train = np.setdiff1d(np.arange(len(s)), te)
        tasks.append(_Task(model, s.take(train), starts, vnames, low, high, seed + k + 1, maxeval, local_maxeval,
                           final_maxeval, global_shots, loss_scale, k + 1))
    t0 = time.perf_counter()
    with _quiet():  # around a thread executor too: its threads share these filters
        outcomes = map_tasks(_run_task, tasks, executor)
        return _result(model, s, params, outcomes, held, groups_used, seed, lname, time.perf_counter() - t0)


def _result(model: _Model, s: ShotArrays, params: list[Parameter], outcomes: list[_Outcome],
            held: list[np.ndarray], groups: str, seed: int, lname: str, elapsed: float) -> SurfaceFit:
    import pandas as pd

    final = outcomes[0]
    values = final.values
    land = _landings(s)
    # held-out predictions, fold by fold
    heldout = pd.DataFrame()
    fold_rows = []
    if held:
        n = len(s)
        pred_along, pred_right = np.full(n, np.nan), np.full(n, np.nan)
        fold_of, baseline = np.zeros(n, dtype=int), np.full(n, np.nan)
        for k, (te, out) in enumerate(zip(held, outcomes[1:], strict=True)):
            sub = s.take(te)
            along, right, _ = model.rest(out.values, _landings(sub), limit=False)
            pred_along[te], pred_right[te], fold_of[te] = along, right, k + 1
            train = np.setdiff1d(np.arange(n), te)
            baseline[te] = np.median(s.roll[train])
            e = np.abs(along - sub.roll)
            fold_rows.append({"fold": k + 1, "fitted_shots": len(train), "heldout_shots": len(te),
                              "heldout_median_abs_error": float(np.median(e)), "loss": out.objective,
                              "evaluations": out.n_evaluations, "elapsed_s": out.elapsed,
                              **{p.name: out.values[p.name] for p in params if p.vary}})
        heldout = _prediction_table(s, pred_along, pred_right, fold_of)
        errors = _summary(s.roll, pred_along, s.club, baseline)
    along, right, limit = model.rest(values, land)
    fitted_predictions = _prediction_table(s, along, right, None)
    fitted_errors = _summary(s.roll, along, s.club, np.full(len(s), np.median(s.roll)))
    if not held:
        errors = fitted_errors
    base_obj = float(np.mean(_errors(along, right, s)))  # the mean distance (m), as the report gives it
    # Each fold's parameters on all the shots: as good as the final fit (the shots cannot tell them apart), or
    # worse (that fold's search ended in another basin; its values say nothing of what the shots determine).
    tolerance = EQUIVALENT_RELATIVE * base_obj + EQUIVALENT_M
    for row, out in zip(fold_rows, outcomes[1:], strict=False):
        a, r, _ = model.rest(out.values, land, limit=False)
        row["mean_error_all_shots"] = float(np.mean(_errors(a, r, s)))
        row["equivalent"] = row["mean_error_all_shots"] <= base_obj + tolerance
    folds = pd.DataFrame(fold_rows).set_index("fold") if fold_rows else pd.DataFrame()
    alike = [r for r in fold_rows if r["equivalent"]]
    rows = {}
    for p in params:
        lo, hi = p.bounds
        row = {"value": values[p.name], "low": lo, "high": hi, "unit": p.unit, "vary": p.vary,
               "fold_min": np.nan, "fold_max": np.nan, "sensitivity": np.nan, "at_bound": "", "identified": False}
        if p.vary:
            w = hi - lo
            rises = []
            for sign in (-1.0, 1.0):
                moved = min(max(values[p.name] + sign * 0.05 * w, lo), hi)
                if moved == values[p.name]:
                    continue
                a, r, _ = model.rest({**values, p.name: moved}, land, limit=False)
                rises.append(float(np.mean(_errors(a, r, s))) - base_obj)
            row["sensitivity"] = min(rises) if rises else 0.0
            if values[p.name] - lo <= 1e-6 * w:
                row["at_bound"] = "lower"
            elif hi - values[p.name] <= 1e-6 * w:
                row["at_bound"] = "upper"
            fv = [values[p.name]] + [r[p.name] for r in alike]
            if alike:
                row["fold_min"], row["fold_max"] = min(fv), max(fv)
            row["identified"] = bool((max(fv) - min(fv)) <= AGREE_FRACTION * w and row["sensitivity"] >= SENSITIVE_M)
        rows[p.name] = row
    table = pd.DataFrame.from_dict(rows, orient="index")
    fitted_params = Parameters(p.replace(value=values[p.name]) for p in params)
    summary = errors.loc["all"]
    notes = ["The roll-out fitted is the file's total - carry. A launch monitor's total is its own estimate of the "
             "roll, so this surface reproduces the monitor's roll model for these landings, not a measurement of "
             "the turf; fitted to measured (tape or laser) totals it would calibrate the turf."]
    worse = [r["fold"] for r in fold_rows if not r["equivalent"]]
    if worse:
        notes.append(f"The search of fold(s) {worse} ended in a worse basin (their parameters on all shots: mean error "
                     f"above {base_obj + tolerance:.3g} m); a larger maxeval= may help. Their held-out errors count.")
    not_det = [n for n, r in rows.items() if r["vary"] and not r["identified"]]
    if not_det:
        notes.append(f"Not determined by these shots: {', '.join(not_det)} (the fit's value is one of many that "
                     f"predict as well; hold them with vary= or start= if you know them).")
    if int(limit.sum()):
        notes.append(f"{int(limit.sum())} shot(s) still bounced at max_bounces={model.max_bounces} on the fitted "
                     f"surface.")
    what = "held-out" if held else "in-sample"
    fitted = ", ".join(p.name for p in params if p.vary)
    held_text = ", ".join(f"{p.name}={values[p.name]:.4g}" for p in params if not p.vary)
    desc = (f"Fitted by bouncelab.ground.fit_surface ({lname}; varied: {fitted}"
            f"{'; held: ' + held_text if held_text else ''}) to {len(s)} launch-monitor shots ({s.spin_kind} spin), "
            f"roll-out = the file's total - carry (median {summary['observed_median_roll']:.3g} m); {what} median "
            f"absolute roll-out error {summary['median_abs_error']:.3g} m. A monitor's total is its own model of the "
            f"roll: this surface reproduces that model for such landings, not a measurement of the turf.")
    surface = model.surface(values, description=desc)
    return SurfaceFit(surface=surface, params=fitted_params, parameters=table, heldout=heldout, errors=errors,
                      fitted_errors=fitted_errors, fitted_predictions=fitted_predictions, folds=folds,
                      mean_error=base_obj, loss=float(final.objective),
                      n_evaluations=sum(o.n_evaluations for o in outcomes), elapsed=elapsed,
                      bounce_limit=int(limit.sum()), spin_kind=s.spin_kind, groups=groups, seed=seed, law=lname,
                      n_shots=len(s), lateral=s.lateral, notes=notes, _model=model, _values=dict(values))
