"""Shared plumbing of the figures: lazy matplotlib, labels, styles, input checks, the synthetic-data note."""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import units as _u
from bouncelab.core.errors import DataError, Hint, ParameterError
from bouncelab.core.units import COMPONENTS
from bouncelab.data.inputs import campaign_arrays

#: Named unit sets for the ``units=`` argument of the plots: name -> (velocity unit, spin unit).
UNIT_PRESETS: dict[str, tuple[str, str]] = {
    "scaled": ("radius/s", "rad/s"),  # the paper's scaled units (the default)
    "si": ("m/s", "rad/s"),
    "lab": ("m/s", "rpm"),  # what launch monitors and testers read
    "imperial": ("mph", "rpm"),
}


@dataclass(frozen=True)
class FigureUnits:
    """Units of a figure's axes. Data stay in scaled units; only plotted values and labels convert.

    ``velocity`` is any speed unit of :mod:`bouncelab.core.units` (m/s, ft/s, mph, km/h,
    radius/s), ``spin`` any spin unit (rad/s, rpm, rev/s, deg/s); ``radius_m`` is the ball
    radius used to turn radii/s into a speed (default 21.35 mm).
    """

    velocity: str = "radius/s"
    spin: str = "rad/s"
    radius_m: float = _u.BALL_RADIUS_M

    @property
    def factors(self) -> np.ndarray:
        """Multipliers from scaled (xdot, ydot, omega) to these units."""
        v = float(_u.velocity_from_scaled(1.0, self.velocity, radius_m=self.radius_m))
        return np.array([v, v, float(_u.spin_from_scaled(1.0, self.spin))])

    def convert(self, values: Any) -> np.ndarray:
        """(..., 3) scaled states in these units."""
        return np.asarray(values, dtype=float) * self.factors

    def velocity_factor(self) -> float:
        return float(self.factors[0])

    def unit(self, component: str) -> str:
        """Axis-label unit of ``component`` ("xdot", "ydot", "omega" or "velocity")."""
        if component == "omega":
            return self.spin
        return "radii/s" if self.velocity == "radius/s" else self.velocity


def figure_units(units: Any = None) -> FigureUnits:
    """The :class:`FigureUnits` a plot's ``units=`` argument names.

    ``None`` or ``"scaled"``: the paper's scaled units (radii/s, rad/s). A preset name
    (``"si"``: m/s and rad/s; ``"lab"``: m/s and rpm; ``"imperial"``: mph and rpm), a mapping
    ``{"velocity": "m/s", "spin": "rpm", "radius_m": 0.02135}`` (any key may be left out), or
    a :class:`FigureUnits`.

    Raises
    ------
    DataError
        An unknown preset, key or unit.
    """
    if units is None:
        return FigureUnits()
    if isinstance(units, FigureUnits):
        return units
    if isinstance(units, str):
        preset = UNIT_PRESETS.get(units.strip().lower())
        if preset is None:
            raise DataError(f"unknown figure units {units!r}; use one of {sorted(UNIT_PRESETS)} or a mapping of a "
                            "'velocity' and a 'spin' unit", option="units",
                            hints=[Hint("units", {"velocity": "m/s", "spin": "rpm"})])
        return FigureUnits(*preset)
    if isinstance(units, Mapping):
        extra = set(units) - {"velocity", "spin", "radius_m"}
        if extra:
            raise DataError(f"figure units take the keys 'velocity', 'spin' and 'radius_m'; got {sorted(extra)}",
                            option="units")
        radius = units.get("radius_m", _u.BALL_RADIUS_M)
        try:
            radius = float(radius)
        except (TypeError, ValueError):
            raise DataError(f"radius_m must be a length in metres; got {radius!r}", option="radius_m") from None
        fu = FigureUnits(_u.canonical_unit(units.get("velocity", "radius/s"), "velocity"),
                         _u.canonical_unit(units.get("spin", "rad/s"), "spin"), radius)
        fu.factors  # noqa: B018 - validates the radius now, not at the first plot call
        return fu
    raise DataError(f"units must be None, a preset name {sorted(UNIT_PRESETS)} or a mapping; "
                    f"got {type(units).__name__}", option="units")

#: Marker and colour of each measured slip/roll class (the paper's Fig. 8: roll = triangles, slip = circles).
CLASS_STYLE = {
    "roll": {"marker": "^", "color": "tab:blue", "label": "roll"},
    "slip": {"marker": "o", "color": "tab:orange", "label": "slip"},
}
#: Colours of landing and lift-off quantities (the paper's Fig. 6: green inbound, red outbound).
STATE_COLOR = {"landing": "tab:green", "liftoff": "tab:red"}

_SYMBOL = {"xdot": r"\dot{x}", "ydot": r"\dot{y}", "omega": r"\omega"}
_SUFFIX = {"landing": "0", "liftoff": "F"}
_NOTE_GID = "bouncelab-synthetic-note"
NOTE_TEXT = "synthetic surrogate data"
_INSTALL = "plotting needs matplotlib: pip install bouncelab[plot]"


def pyplot():
    """Import and return ``matplotlib.pyplot``, on the Agg backend when there is no display.

    A backend the user chose (``MPLBACKEND``, matplotlibrc, ``matplotlib.use``, a
    notebook) is left alone; only an unresolved backend on a headless machine is
    set to the non-interactive Agg.
    """
    try:
        import matplotlib
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise ImportError(_INSTALL) from exc
    if "matplotlib.pyplot" not in sys.modules and _headless():
        chosen = getattr(matplotlib.rcParams, "_get_backend_or_none", lambda: None)()
        if chosen is None and not os.environ.get("MPLBACKEND"):
            matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _headless() -> bool:
    if sys.platform in ("darwin", "win32"):
        return False
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def label(component: str, state: str = "landing", *, prefix: str = "", units: bool = True,
          fu: FigureUnits | None = None) -> str:
    """Axis label such as ``'$\\dot{x}_0$ [radii/s]'`` or ``'$\\omega_F$ [rpm]'`` (units of ``fu``)."""
    text = f"{prefix}${_SYMBOL[component]}_{_SUFFIX[state]}$"
    unit = (fu or FigureUnits()).unit(component)
    return f"{text} [{unit}]" if units else text


def symbol(component: str) -> str:
    """``'$\\dot{x}$'`` etc., for Delta q annotations."""
    return f"${_SYMBOL[component]}$"


def campaign_name(attrs: dict) -> str:
    name = str(attrs.get("campaign", "") or "").strip()
    return f"Campaign {name}" if name else "Campaign"


def campaign_data(data: Any, *, name: str = "data") -> tuple[np.ndarray, np.ndarray, dict]:
    """Landing, lift-off (n, 3) and attrs of a campaign Dataset (or ``(landing, liftoff)`` pair)."""
    p0, pf, _ = campaign_arrays(data, name=name)
    if len(p0) == 0:
        raise DataError(f"{name} holds no bounces; there is nothing to plot", option=name)
    attrs = dict(data.attrs) if isinstance(data, xr.Dataset) else {}
    return p0, pf, attrs


def new_figure(fig: Any, *, nrows: int, ncols: int, figsize: tuple[float, float], **subplot_kw: Any):
    """A constrained-layout figure (or the caller's empty one) with an ``nrows x ncols`` grid of axes."""
    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=figsize, layout="constrained")
    else:
        _check_figure(fig)
        if fig.axes:
            raise ParameterError("fig must be an empty matplotlib Figure (this plot adds its own grid of axes)",
                                 parameter="fig")
    axes = fig.subplots(nrows, ncols, squeeze=False, **subplot_kw)
    return fig, axes


def single_axes(ax: Any, *, figsize: tuple[float, float], projection: str | None = None):
    """The caller's axes (checked) or a new constrained-layout figure with one axes."""
    plt = pyplot()
    if ax is None:
        fig = plt.figure(figsize=figsize, layout="constrained")
        ax = fig.add_subplot(projection=projection)
        return fig, ax
    from matplotlib.axes import Axes

    if not isinstance(ax, Axes):
        raise TypeError(f"ax must be a matplotlib Axes; got {type(ax).__name__}")
    if projection == "3d" and getattr(ax, "name", "") != "3d":
        raise ParameterError("ax must be a 3-D axes: fig.add_subplot(projection='3d')", parameter="ax")
    return ax.figure, ax


def _check_figure(fig: Any) -> None:
    from matplotlib.figure import Figure

    if not isinstance(fig, Figure):
        raise TypeError(f"fig must be a matplotlib Figure; got {type(fig).__name__}")


def finish(fig: Any, attrs: dict, title: str, *, ax: Any = None) -> Any:
    """Set the title and, for synthetic data, the visible note; return ``fig``.

    With ``ax`` (a single axes drawn into a figure the caller owns) the title goes on the
    axes instead of the figure.
    """
    if ax is not None:
        ax.set_title(title)
    elif title:
        fig.suptitle(title, fontsize="large")
    add_synthetic_note(fig, attrs)
    return fig


def is_synthetic(attrs: dict) -> bool:
    return attrs.get("data_kind") == "synthetic surrogate"


def add_synthetic_note(fig: Any, attrs: dict) -> None:
    """Write "synthetic surrogate data" in the bottom-right corner, outside the axes, once per figure."""
    if not is_synthetic(attrs) or any(t.get_gid() == _NOTE_GID for t in fig.texts):
        return
    engine = fig.get_layout_engine()
    if engine is not None and type(engine).__name__ == "ConstrainedLayoutEngine":
        engine.set(rect=(0.0, 0.035, 1.0, 0.965))  # keep a strip at the bottom free for the note
    fig.text(
        0.995, 0.006, NOTE_TEXT, ha="right", va="bottom", fontsize="small", style="italic",
        color="firebrick", gid=_NOTE_GID,
    )


def has_synthetic_note(fig: Any) -> bool:
    """True when the figure carries the synthetic-data note."""
    return any(t.get_gid() == _NOTE_GID and t.get_text() == NOTE_TEXT for t in fig.texts)


def scatter_alpha(n: int) -> float:
    """Opaque for a few points, translucent for dense scatters (0.9 at 10 points, 0.6 at 300, 0.45 at 3000)."""
    return float(np.clip(1.1 - 0.2 * np.log10(max(n, 1)), 0.4, 0.9))


def class_handles(counts: dict[str, int], *, markersize: float = 7.0) -> list:
    """Opaque legend proxies for the slip/roll classes, labelled with their counts."""
    from matplotlib.lines import Line2D

    return [
        Line2D([], [], marker=style["marker"], color=style["color"], linestyle="none", markersize=markersize,
               label=f"{style['label']} ({counts.get(name, 0)})")
        for name, style in CLASS_STYLE.items()
    ]


def save_figure(fig: Any, path: str | Path, *, dpi: int = 150, **kwargs: Any) -> Path:
    """Save ``fig`` to ``path`` (format from the suffix, parent folders created); return the path.

    The file is written atomically (a temporary file beside it, then a rename): a failed save
    leaves any previous file at ``path`` intact. Further keyword arguments go to
    :meth:`matplotlib.figure.Figure.savefig`.
    """
    from bouncelab.core.atomic import atomic_path

    _check_figure(fig)
    path = Path(path)
    if not path.suffix:
        raise ParameterError(f"path needs a file suffix naming the format (.png, .pdf, .svg); got {str(path)!r}",
                             parameter="path", value=str(path))
    path.parent.mkdir(parents=True, exist_ok=True)
    kwargs.setdefault("format", path.suffix[1:].lower())
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, **kwargs)
    return path


__all__ = ["CLASS_STYLE", "COMPONENTS", "STATE_COLOR", "UNIT_PRESETS", "FigureUnits", "figure_units",
           "has_synthetic_note", "save_figure"]
