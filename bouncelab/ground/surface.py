r"""Surfaces: a bounce law, sliding friction and a green speed, named and serialisable.

A :class:`Surface` holds what :func:`bouncelab.ground.runout.run` needs to take a ball from its
landing to rest:

* ``law``: the bounce law (any :class:`~bouncelab.BounceModel`: fitted, published or
  physics-based), lifted to 3-D by :mod:`bouncelab.ground.bounce3d`;
* ``sliding_friction`` :math:`\mu_s`: Coulomb friction of the ball skidding on the grass
  after the bounces;
* ``stimp_m``: the green speed as a Stimpmeter reading :math:`S` (metres; ``stimp_ft=`` in
  feet). The Stimpmeter releases a ball rolling at :data:`STIMP_SPEED_M_S` = 1.83 m/s
  (6 ft/s) on a level green; with a constant rolling deceleration :math:`a` it stops after
  :math:`S = v_0^2 / 2a`, so :math:`a = v_0^2 / 2S` on flat ground. On a slope the
  deceleration is proportional to the normal load (a rolling-resistance coefficient
  :math:`\mu_r = a / g`, deceleration :math:`\mu_r g \cos\theta`), see
  :func:`bouncelab.ground.runout.run`;
* ``pivot_retention``: the fraction of the spin about the ground normal that a bounce keeps
  (pivot friction; 1 keeps it all).

Presets (:func:`preset`, :data:`PRESET_NAMES`) are documented in ``docs/simulators.md``
("The surfaces"): the paper's two turfs as its published laws (their tilt faded at small
speeds along the ground, :data:`PRESET_FADE_XDOT`), and slow, medium and fast greens.
Their green speeds are general guidance and their sliding friction an assumption, not
measurements of ours.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from bouncelab.core.checks import shown
from bouncelab.core.checks import text as check_text
from bouncelab.core.errors import Hint, ParameterError
from bouncelab.ground._inputs import check_law, positive, retention

__all__ = [
    "ASSUMED_SLIDING_FRICTION",
    "ASSUMED_TURF_STIMP_M",
    "GRAVITY",
    "PRESET_FADE_XDOT",
    "PRESET_NAMES",
    "STIMP_SPEED_M_S",
    "Surface",
    "load_surface",
    "preset",
]

#: Standard gravity used by the ground phase (m/s^2).
GRAVITY = 9.81
#: Speed of the ball leaving the Stimpmeter's ramp, rolling (USGA: 6 ft/s = 1.83 m/s).
STIMP_SPEED_M_S = 1.83
_FT = 0.3048

#: Sliding friction of a ball skidding on grass used by the presets: an ASSUMPTION of the order of
#: the coefficients quoted for a ball skidding on a putting green, not a measurement of ours.
ASSUMED_SLIDING_FRICTION = 0.4
#: Horizontal speed (radii/s; 1.07 m/s) below which the presets' Penner tilt fades to zero (the law's ``fade_xdot``):
#: an ASSUMPTION of bouncelab. The published laws tilt the ground against the direction of travel even for a
#: vertical drop, whose direction of travel is undefined: it would bounce off sideways, in a direction set by a
#: rounding error. Campaign A measured no landing that slow along the ground (its slowest: 74.9 radii/s);
#: campaign B's slowest was 1.10 radii/s (a landing at 89.5 degrees).
PRESET_FADE_XDOT = 50.0
#: Stimpmeter-equivalent reading of the paper's teeing turfs used by the turf presets (metres, about 5 ft):
#: an ASSUMPTION (grass cut longer than a green rolls slower); the paper measured bounces only.
ASSUMED_TURF_STIMP_M = 1.5


class Surface:
    """A named ground surface: bounce law, sliding friction, green speed and pivot friction.

    Parameters
    ----------
    name
        A name (non-empty text), e.g. ``"green-fast"``.
    law
        The bounce law, any :class:`~bouncelab.BounceModel` with all its parameters.
    sliding_friction
        Coulomb friction coefficient of the ball skidding on the surface (> 0).
    stimp_m, stimp_ft
        Green speed as a Stimpmeter reading in metres or in feet (exactly one of them, > 0).
    pivot_retention
        Fraction of the spin about the ground normal kept through a bounce, in [0, 1]
        (default 1: kept).
    description
        Free text: what the surface is and where its numbers come from (its provenance, shown
        by ``str(surface)`` and kept in its JSON).

    Raises
    ------
    ParameterError
        A missing or bad value, naming it.

    Examples
    --------
    >>> import bouncelab as bl
    >>> s = Surface(name="my green", law=bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_ft=10)
    >>> round(s.stimp_m, 3), round(s.rolling_deceleration, 4)
    (3.048, 0.5494)
    >>> Surface.from_dict(s.to_dict()) == s
    True
    """

    def __init__(self, name: str, law: Any, sliding_friction: float, stimp_m: float | None = None, *,
                 stimp_ft: float | None = None, pivot_retention: float = 1.0, description: str = "") -> None:
        if not isinstance(name, str) or not name.strip():
            raise ParameterError(f"a surface needs a name (non-empty text); got {shown(name)}", parameter="name",
                                 value=name)
        check_text(name, "name")
        if (stimp_m is None) == (stimp_ft is None):
            raise ParameterError("give the green speed as exactly one of stimp_m (metres) or stimp_ft (feet)",
                                 parameter="stimp_m",
                                 hints=[Hint("stimp_m", None, "metres"), Hint("stimp_ft", None, "feet")])
        stimp = positive(stimp_m, "stimp_m") if stimp_m is not None else positive(stimp_ft, "stimp_ft") * _FT
        check_text(description, "description")
        self.name = name
        self.law = check_law(law)
        self.sliding_friction = positive(sliding_friction, "sliding_friction")
        self.stimp_m = stimp
        self.pivot_retention = retention(pivot_retention)
        self.description = description

    # ----------------------------------------------------------------- derived
    @property
    def stimp_ft(self) -> float:
        """The Stimpmeter reading in feet."""
        return self.stimp_m / _FT

    @property
    def rolling_deceleration(self) -> float:
        """Rolling deceleration on flat ground, ``1.83**2 / (2 stimp_m)`` (m/s^2)."""
        return STIMP_SPEED_M_S ** 2 / (2.0 * self.stimp_m)

    @property
    def rolling_resistance(self) -> float:
        """Rolling-resistance coefficient ``rolling_deceleration / g`` (dimensionless)."""
        return self.rolling_deceleration / GRAVITY

    def max_slope_deg(self) -> float:
        """Steepest planar slope on which a ball can come to rest: ``tan(theta) = 7/5 mu_r`` (degrees).

        A rolling ball (I = 2/5 m R^2) is pulled down a slope by 5/7 g sin(theta) and held by
        ``mu_r g cos(theta)``; it also stops skidding only if ``tan(theta) < 7/2 mu_s``.
        """
        return math.degrees(min(math.atan(1.4 * self.rolling_resistance), math.atan(3.5 * self.sliding_friction)))

    def replace(self, **changes: Any) -> Surface:
        """A copy with some fields changed (``stimp_ft=`` replaces ``stimp_m``)."""
        fields = {"name": self.name, "law": self.law, "sliding_friction": self.sliding_friction,
                  "stimp_m": self.stimp_m, "pivot_retention": self.pivot_retention,
                  "description": self.description}
        if "stimp_ft" in changes:
            fields.pop("stimp_m")
        unknown = set(changes) - set(fields) - {"stimp_ft", "stimp_m"}
        if unknown:
            raise ParameterError(f"Surface has no field(s) {sorted(unknown)}", parameter=sorted(unknown)[0])
        fields.update(changes)
        return Surface(**fields)

    # ----------------------------------------------------------- serialisation
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description; the law as its own JSON description (:meth:`BounceModel.to_dict`)."""
        from bouncelab.core import __version__

        return {"surface": self.name, "law": self.law.to_dict(), "sliding_friction": self.sliding_friction,
                "stimp_m": self.stimp_m, "pivot_retention": self.pivot_retention,
                "description": self.description, "bouncelab_version": __version__}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Surface:
        """Rebuild a surface from :meth:`to_dict` output.

        Raises
        ------
        ParameterError
            A missing or unknown key, or a bad value (naming it).
        """
        from bouncelab.laws import law_from_dict

        if not isinstance(d, Mapping):
            raise ParameterError(f"a surface description is a mapping; got {type(d).__name__}", parameter="d")
        required = ("surface", "law", "sliding_friction", "stimp_m")
        missing = [k for k in required if k not in d]
        unknown = sorted(set(d) - {*required, "pivot_retention", "description", "bouncelab_version"})
        if missing or unknown:
            raise ParameterError(f"a surface description needs the keys {list(required)} (optional: "
                                 f"pivot_retention, description); missing {missing}, unknown {unknown}",
                                 parameter=(missing or unknown)[0])
        return cls(name=d["surface"], law=law_from_dict(d["law"]), sliding_friction=d["sliding_friction"],
                   stimp_m=d["stimp_m"], pivot_retention=d.get("pivot_retention", 1.0),
                   description=d.get("description", ""))

    def to_json(self, path: str | Path | None = None, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` if given (atomically)."""
        text = json.dumps(self.to_dict(), indent=2, **kwargs)
        if path is not None:
            from bouncelab.core.atomic import write_output

            write_output(path, text + "\n", "the surface")
        return text

    @classmethod
    def from_json(cls, text: str) -> Surface:
        """A surface from the JSON text of :meth:`to_json` (use :func:`load_surface` for a file)."""
        try:
            d = json.loads(text)
        except (TypeError, ValueError, RecursionError) as exc:  # (ValueError: also an integer too long to read)
            raise ParameterError(f"not a JSON surface description ({type(exc).__name__}: {exc})",
                                 parameter="text") from None
        return cls.from_dict(d)

    # ------------------------------------------------------------------ dunder
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Surface):
            return NotImplemented
        return (self.name, self.sliding_friction, self.stimp_m, self.pivot_retention, self.description) == (
            other.name, other.sliding_friction, other.stimp_m, other.pivot_retention, other.description) and (
            type(self.law) is type(other.law) and self.law == other.law)

    def __hash__(self) -> int:
        return hash((self.name, self.sliding_friction, self.stimp_m, self.pivot_retention))

    def __repr__(self) -> str:
        return (f"Surface(name={self.name!r}, law={self.law!r}, sliding_friction={self.sliding_friction:g}, "
                f"stimp_m={self.stimp_m:.4g} ({self.stimp_ft:.3g} ft), pivot_retention={self.pivot_retention:g})")

    def __str__(self) -> str:
        """The surface and, below it, where its numbers come from (its ``description``)."""
        return repr(self) + (f"\n  provenance: {self.description}" if self.description else "")

    def _repr_html_(self) -> str:
        from bouncelab.ground._display import surface_html  # the notebook view

        return surface_html(self)


def load_surface(path: str | Path) -> Surface:
    """Read a surface written by :meth:`Surface.to_json`.

    Raises
    ------
    DataError
        The file cannot be read: missing (a :class:`~bouncelab.core.errors.MissingFileError`), a folder,
        a FIFO or a device, larger than :data:`~bouncelab.core.files.MAX_FILE_BYTES`, not UTF-8 (``file``
        names it).
    ParameterError
        The file is not a surface description: not JSON, a missing or unknown key, a bad value (naming the
        file and the field).
    """
    from bouncelab.core.files import read_regular_text

    try:
        file = str(Path(path))
    except TypeError:
        raise ParameterError(f"load_surface takes the path of a surface JSON file; got {type(path).__name__}",
                             parameter="path", value=path) from None
    content = read_regular_text(Path(path).expanduser(), file)
    try:
        return Surface.from_json(content)
    except ParameterError as exc:
        raise ParameterError(f"{file}: {exc}", law=exc.law, parameter=exc.parameter, value=exc.value,
                             hints=exc.hints) from None


# ------------------------------------------------------------------------------ presets
_FADE_TEXT = ("Its tilt fades below 50 radii/s (1.07 m/s) of speed along the ground (fade_xdot), an assumption, so "
              "that a vertical drop stays put.")
_GREEN_SOURCE = ("Green speed: general guidance on Stimpmeter readings (about 7 ft is called very slow, 9 ft moderate, "
                 "11 ft and more fast; sources in docs/simulators.md), not measured by bouncelab. Bounce law: the "
                 "paper's published PennerVarying law of campaign B (fitted to bounces on a natural-grass teeing "
                 "area), an assumption: the paper measured no green. " + _FADE_TEXT + " Sliding friction 0.4: an "
                 "assumption. Not a measurement of any real green.")

#: name -> (law class name, campaign, stimp in metres, description)
_PRESETS: dict[str, tuple[str, str, float, str]] = {
    "turf-A": ("PennerVarying", "A", ASSUMED_TURF_STIMP_M,
               "The paper's campaign A: premium artificial teeing turf, 30 mm thick, on wood. Bounce law: its "
               "published PennerVarying law (Table 3: r=0.448, mu=0.969, k_p=1.543e-4), the paper's fit to bounces "
               "fired from a launcher onto that mat (330 recorded): a teeing mat on a rigid base, not a fairway or "
               "a green. " + _FADE_TEXT + " Rolling (stimp 1.5 m) and sliding friction (0.4): assumptions, the "
               "paper measured bounces only."),
    "turf-B": ("PennerVarying", "B", ASSUMED_TURF_STIMP_M,
               "The paper's campaign B: a well-maintained natural-grass teeing area. Bounce law: its published "
               "PennerVarying law (Table 3: r=0.222, mu=0.999, k_p=2.973e-4), the paper's fit to bounces fired "
               "from a launcher onto that tee (693 recorded): a teeing area, not a fairway or a green. "
               + _FADE_TEXT + " Rolling (stimp 1.5 m) and sliding friction (0.4): assumptions, the paper measured "
               "bounces only."),
    "green-slow": ("PennerVarying", "B", 7.5 * _FT, "A slow green, Stimpmeter 7.5 ft (2.29 m). " + _GREEN_SOURCE),
    "green-medium": ("PennerVarying", "B", 9.0 * _FT,
                     "A medium green, Stimpmeter 9 ft (2.74 m). " + _GREEN_SOURCE),
    "green-fast": ("PennerVarying", "B", 11.0 * _FT, "A fast green, Stimpmeter 11 ft (3.35 m). " + _GREEN_SOURCE),
}

#: Names of the preset surfaces, in the order of the docs.
PRESET_NAMES: tuple[str, ...] = tuple(_PRESETS)


def preset(name: str) -> Surface:
    """A preset surface by name (:data:`PRESET_NAMES`); see the module and ``docs/simulators.md``.

    Raises
    ------
    ParameterError
        An unknown name (the known ones listed).
    """
    from bouncelab import laws

    if not isinstance(name, str) or name not in _PRESETS:
        raise ParameterError(f"no preset surface {shown(name)}; presets: {list(PRESET_NAMES)}", parameter="surface",
                             value=name)
    law_name, campaign, stimp, text = _PRESETS[name]
    law = getattr(laws, law_name).published(campaign).replace(fade_xdot=PRESET_FADE_XDOT)
    return Surface(name=name, law=law, sliding_friction=ASSUMED_SLIDING_FRICTION, stimp_m=stimp, description=text)
