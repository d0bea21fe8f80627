"""The ground phase for simulators: 3-D bounce, landing to rest on real surfaces, reference shots.

==========================  ===============================================================
:func:`bounce`              lift-off velocity and spin of 3-D landings from any 2-D law, on any plane
:func:`run`                 landings to rest: bounces, flights, skid and roll, vectorised and compiled
:class:`Surface`            a named, serialisable surface: law, sliding friction, green speed
:func:`preset`              the preset surfaces (the paper's two turfs; slow, medium, fast greens)
:class:`Air`                optional drag and lift in flight
:func:`fit_surface`         a surface fitted to launch-monitor shots, held out (:class:`SurfaceFit`)
:func:`predict_shots`       where launch-monitor shots would stop on a surface
:mod:`~.shots`              the reference-shot suite (``python -m bouncelab.ground.shots``)
:func:`load_shots`          launch-monitor exports in (:func:`bouncelab.data.shots.load_shots`)
==========================  ===============================================================

Conventions: right-handed axes, z up on flat ground, spin the angular-velocity vector (so
backspin for travel in +x has a negative y component); scaled units (radii, radii/s, rad/s)
unless ``units=`` says otherwise. See ``docs/simulators.md``, "The ground phase".
"""

from bouncelab.ground.bounce3d import bounce
from bouncelab.ground.fit import SurfaceFit, fit_surface, predict_shots
from bouncelab.ground.runout import (
    DEFAULT_MAX_BOUNCES,
    DEFAULT_MIN_APEX_M,
    EVENTS,
    PHASES,
    Air,
    BounceLimitWarning,
    RunResult,
    run,
)
from bouncelab.ground.surface import PRESET_NAMES, STIMP_SPEED_M_S, Surface, load_surface, preset

__all__ = [
    "DEFAULT_MAX_BOUNCES",
    "DEFAULT_MIN_APEX_M",
    "EVENTS",
    "PHASES",
    "PRESET_NAMES",
    "STIMP_SPEED_M_S",
    "Air",
    "BounceLimitWarning",
    "RunResult",
    "Surface",
    "SurfaceFit",
    "bounce",
    "fit_surface",
    "load_shots",
    "load_surface",
    "predict_shots",
    "preset",
    "run",
]


def __getattr__(name: str):  # load_shots lives in the data layer; pandas and xarray load only when it is asked for
    if name == "load_shots":
        from bouncelab.data.shots import load_shots
        return load_shots
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
