"""Where a fitted law's values came from: :class:`Provenance`, the law's metadata beside its value.

A law is a value (its class, parameters and options): two laws with the same values are
equal, whatever made them. What data a law was fitted to is not part of that value but it
matters to anyone who uses the law: a law fitted to the synthetic surrogates describes the
generator of those bounces, not real turf, and a law used beyond the landings it was fitted
on extrapolates. :func:`bouncelab.fit` therefore gives the fitted law a
:class:`Provenance` (``law.provenance``), the law file written by
:meth:`~bouncelab.BounceModel.to_json` carries it, and :func:`~bouncelab.load_law` restores
it. It never changes equality or hashing, and :meth:`~bouncelab.BounceModel.replace` (a law
with other values) drops it.

Examples
--------
>>> import bouncelab as bl
>>> law = bl.fit(bl.Rigid, bl.load_campaign("A"), method="structured").model
>>> law.provenance.synthetic, law.provenance.n_bounces, law.provenance.generator
(True, 330, 'CraterContact')
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bouncelab.core import __version__, checks
from bouncelab.core.errors import ParameterError
from bouncelab.core.units import BALL_RADIUS_M

__all__ = ["RANGE_NAMES", "RANGE_UNITS", "Provenance", "landing_ranges", "outside_ranges"]

#: The landing quantities whose fitted ranges a provenance records, in this order.
RANGE_NAMES = ("xdot0", "ydot0", "omega0", "speed", "angle_deg")

#: Their units (scaled units; the angle of incidence in degrees below the horizontal).
RANGE_UNITS = {"xdot0": "radius/s", "ydot0": "radius/s", "omega0": "rad/s", "speed": "radius/s",
               "angle_deg": "degrees below the horizontal, atan(-ydot0 / |xdot0|)"}

#: data_kind values that mean synthetic bounces.
_SYNTHETIC_KINDS = ("synthetic surrogate", "synthetic", "simulated")


def _quantities(landing: np.ndarray) -> dict[str, np.ndarray]:
    p = np.asarray(landing, dtype=np.float64).reshape(-1, 3)
    return {"xdot0": p[:, 0], "ydot0": p[:, 1], "omega0": p[:, 2], "speed": np.hypot(p[:, 0], p[:, 1]),
            "angle_deg": np.degrees(np.arctan2(-p[:, 1], np.abs(p[:, 0])))}


def landing_ranges(landing: np.ndarray) -> dict[str, tuple[float, float]]:
    """``{quantity: (min, max)}`` of (n, 3) scaled landings, for :data:`RANGE_NAMES`."""
    return {k: (float(v.min()), float(v.max())) for k, v in _quantities(landing).items()}


def outside_ranges(landing: np.ndarray, ranges: Mapping[str, tuple[float, float]]) -> tuple[np.ndarray, str]:
    """Which landings lie outside ``ranges`` (a boolean per landing) and a sentence on the first of them."""
    q = _quantities(landing)
    out = np.zeros(len(q["xdot0"]), dtype=bool)
    first = ""
    for name in RANGE_NAMES:
        if name not in ranges:
            continue
        lo, hi = ranges[name]
        bad = (q[name] < lo) | (q[name] > hi)
        out |= bad
    if out.any():
        row = int(np.argmax(out))
        parts = []
        for name in RANGE_NAMES:
            if name in ranges:
                lo, hi = ranges[name]
                v = float(q[name][row])
                if v < lo or v > hi:
                    parts.append(f"{name} {v:.4g} outside the fitted {lo:.4g}..{hi:.4g}")
        first = f"first: landing row {row + 1}, {', '.join(parts)}"
    return out, first


@dataclass(frozen=True)
class Provenance:
    """What a fitted law was fitted to, and how.

    Attributes
    ----------
    n_bounces
        Number of bounces fitted.
    data_kind
        The campaign's ``data_kind`` attr: ``"measured"``, ``"synthetic surrogate"`` or
        ``"unknown"`` (bare arrays say nothing about where they came from).
    campaign
        The campaign's name (``"A"``), or None.
    source
        The file the bounces were read from, or what generated them
        (``"bouncelab.simulation.simulate_campaign(seed=330)"``), or None.
    surrogate
        ``"turf"`` or ``"published"`` for the embedded surrogates, else None.
    generator
        The law that generated synthetic bounces (``"CraterContact"`` for the turf surrogates,
        ``"PiecewiseAffine.published('A')"`` for the published ones), when the campaign says.
    warning
        The campaign's own warning (what made synthetic data), if any.
    ball_radius_m
        The ball radius the bounces were scaled with, in metres.
    method, objective, seed
        How the law was fitted (:func:`bouncelab.fit`'s method, objective and seed).
    fitted_with
        The bouncelab version that fitted it.
    landing_ranges
        ``{quantity: (min, max)}`` of the fitted landings for ``xdot0``, ``ydot0``, ``omega0``,
        ``speed`` (radii/s, rad/s) and ``angle_deg`` (the angle of incidence, degrees below the
        horizontal): where the law was fitted, not where it holds.
    """

    n_bounces: int
    data_kind: str = "unknown"
    campaign: str | None = None
    source: str | None = None
    surrogate: str | None = None
    generator: str | None = None
    warning: str | None = None
    ball_radius_m: float = BALL_RADIUS_M
    method: str | None = None
    objective: str | None = None
    seed: int | None = None
    fitted_with: str | None = None
    landing_ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)

    @property
    def synthetic(self) -> bool:
        """Whether the bounces fitted were synthetic (a surrogate or a simulation), not measured."""
        return self.data_kind in _SYNTHETIC_KINDS

    # ------------------------------------------------------------------ from a fit
    @classmethod
    def of_fit(cls, data: Any, landing: np.ndarray, *, method: str | None = None, objective: str | None = None,
               seed: int | None = None) -> Provenance:
        """The provenance of a law fitted to ``landing`` (the bounces actually fitted) from ``data``
        (a campaign Dataset, whose attrs say what it is, or bare arrays, which say nothing)."""
        attrs: Mapping[str, Any] = getattr(data, "attrs", None) or {}
        is_dataset = hasattr(data, "data_vars")
        kind = str(attrs.get("data_kind", "unknown")) if is_dataset else "unknown"
        if str(attrs.get("simulated", "")).lower() == "yes" and kind == "unknown":
            kind = "synthetic surrogate"
        campaign = _text(attrs.get("campaign"))
        surrogate = _text(attrs.get("surrogate"))
        generator = _text(attrs.get("generator_law")) or _text(attrs.get("turf_law"))
        if generator is None and surrogate == "published" and campaign:
            generator = f"PiecewiseAffine.published({campaign!r})"  # what generate_surrogate uses
        try:
            radius = float(attrs.get("ball_radius_m", BALL_RADIUS_M))
        except (TypeError, ValueError, OverflowError):
            radius = BALL_RADIUS_M
        return cls(
            n_bounces=len(landing), data_kind=kind, campaign=campaign,
            source=_text(attrs.get("source")) if is_dataset else "arrays (landing, liftoff)",
            surrogate=surrogate, generator=generator,
            warning=_text(attrs.get("warning")) if kind in _SYNTHETIC_KINDS else None,
            ball_radius_m=radius, method=method, objective=objective, seed=seed, fitted_with=__version__,
            landing_ranges=landing_ranges(landing) if len(landing) else {},
        )

    # ------------------------------------------------------------------ words
    def summary(self) -> str:
        """One line: what the law was fitted to (``"330 bounces of campaign 'A' (SYNTHETIC ...)"``)."""
        what = f"{self.n_bounces} bounces"
        if self.campaign:
            what += f" of campaign {self.campaign!r}"
        elif self.source:
            what += f" from {self.source}"
        if self.synthetic:
            made = []
            if self.surrogate:
                made.append(f"surrogate {self.surrogate!r}")
            if self.generator:
                made.append(f"generated by {self.generator}")
            what += f" (SYNTHETIC{': ' + ', '.join(made) if made else ''}; not measured bounces)"
        elif self.data_kind == "measured":
            what += " (measured)"
        else:
            what += " (not said whether measured or synthetic)"
        how = ", ".join(x for x in (self.method and f"by {self.method}",
                                    self.fitted_with and f"bouncelab {self.fitted_with}") if x)
        return what + (f", {how}" if how else "")

    def synthetic_tag(self) -> str | None:
        """A short mark for a law fitted to synthetic data (``str(law)`` ends with it), or None for other data."""
        if not self.synthetic:
            return None
        made = [f"campaign {self.campaign!r}" if self.campaign else None,
                f"surrogate {self.surrogate!r}" if self.surrogate else None,
                f"generated by {self.generator}" if self.generator else None]
        what = ", ".join(m for m in made if m)
        return f"fitted to SYNTHETIC bounces{f' ({what})' if what else ''}, not measured ones"

    def synthetic_note(self) -> str | None:
        """The sentence a user must read about a law fitted to synthetic data, or None for other data."""
        if not self.synthetic:
            return None
        return (f"this law was fitted to synthetic bounces ({self.summary()}): it describes the model that "
                "generated them, not real turf; no claim about real turf may rest on it")

    # ------------------------------------------------------------------ JSON
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description (the ``"provenance"`` of a law file)."""
        return {
            "n_bounces": self.n_bounces, "data_kind": self.data_kind, "synthetic": self.synthetic,
            "campaign": self.campaign, "source": self.source, "surrogate": self.surrogate,
            "generator": self.generator, "warning": self.warning, "ball_radius_m": self.ball_radius_m,
            "method": self.method, "objective": self.objective, "seed": self.seed, "fitted_with": self.fitted_with,
            "landing_ranges": {k: [float(v[0]), float(v[1])] for k, v in self.landing_ranges.items()},
            "landing_range_units": {k: RANGE_UNITS[k] for k in self.landing_ranges if k in RANGE_UNITS},
        }

    @classmethod
    def from_dict(cls, d: Any, where: str = "the law description", law: str | None = None) -> Provenance:
        """Rebuild from :meth:`to_dict` output (ParameterError naming the field for anything malformed).

        ``where`` says in words where the provenance was read, ``law`` names the law it belongs to (the
        error's ``law``); the error's ``parameter`` is the field, e.g. ``"provenance.n_bounces"``.
        """
        if not isinstance(d, Mapping):
            raise ParameterError(f"{where}: 'provenance' must be a mapping; got {type(d).__name__}", law=law,
                                 parameter="provenance", value=d)

        def refused(exc: ParameterError) -> ParameterError:  # the check's error, said where and for which law
            return ParameterError(f"{where}: provenance field {exc.message}", law=law,
                                  parameter=f"provenance.{exc.parameter}", value=exc.value)

        def field_(name: str, kinds: tuple[type, ...], default: Any = None) -> Any:
            value = d.get(name, default)
            if value is not None and (not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds)):
                raise ParameterError(f"{where}: provenance field {name!r} must be "
                                     f"{' or '.join(k.__name__ for k in kinds)}; got {checks.shown(value)}", law=law,
                                     parameter=f"provenance.{name}", value=value)
            try:
                if isinstance(value, str):
                    checks.text(value, name)  # no lone surrogate: it would crash print(law) and every write
                elif isinstance(value, int | float):
                    checks.finite(value, name)  # no 10**400
            except ParameterError as exc:
                raise refused(exc) from None
            return value

        n = field_("n_bounces", (int,))
        if n is None or n < 0:
            raise ParameterError(f"{where}: provenance field 'n_bounces' must be a count >= 0; got {checks.shown(n)}",
                                 law=law, parameter="provenance.n_bounces", value=n)
        radius = field_("ball_radius_m", (int, float), BALL_RADIUS_M)
        if not (isinstance(radius, int | float) and math.isfinite(radius) and radius > 0):
            raise ParameterError(f"{where}: provenance field 'ball_radius_m' must be a positive number of metres; "
                                 f"got {radius!r}", law=law, parameter="provenance.ball_radius_m", value=radius)
        seed = field_("seed", (int,))
        if seed is not None:
            try:
                checks.seed(seed)
            except ParameterError as exc:
                raise refused(exc) from None
        raw = field_("landing_ranges", (Mapping,), {}) or {}  # (null: none recorded)
        ranges: dict[str, tuple[float, float]] = {}
        for key, pair in raw.items():
            ok = (key in RANGE_NAMES and isinstance(pair, list | tuple) and len(pair) == 2
                  and all(isinstance(v, int | float) and not isinstance(v, bool) and _finite(v) for v in pair)
                  and pair[0] <= pair[1])
            if not ok:
                raise ParameterError(f"{where}: provenance landing_ranges[{checks.shown(key)}] must be [min, max] of "
                                     f"one of {list(RANGE_NAMES)}; got {checks.shown(pair)}", law=law,
                                     parameter=f"provenance.landing_ranges[{checks.shown(key)}]", value=pair)
            ranges[key] = (float(pair[0]), float(pair[1]))
        return cls(
            n_bounces=n, data_kind=field_("data_kind", (str,), "unknown") or "unknown",
            campaign=field_("campaign", (str,)), source=field_("source", (str,)),
            surrogate=field_("surrogate", (str,)), generator=field_("generator", (str,)),
            warning=field_("warning", (str,)), ball_radius_m=float(radius), method=field_("method", (str,)),
            objective=field_("objective", (str,)), seed=seed,
            fitted_with=field_("fitted_with", (str,)), landing_ranges=ranges,
        )


def _finite(value: float) -> bool:
    """Whether a number is finite (False for an integer beyond a float, which math.isfinite cannot take)."""
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _text(value: Any) -> str | None:
    """An attr as text, None when absent or empty."""
    if value is None:
        return None
    text = str(value)
    return text or None
