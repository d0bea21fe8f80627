"""Small figures for the HTML views, drawn to PNG bytes when matplotlib is installed (the ``plot`` extra).

The views (``_repr_html_``) must work without matplotlib: :func:`png_of` then gives None and
:func:`figure` a line saying what is missing. Figures are drawn on a bare
:class:`matplotlib.figure.Figure` with the Agg canvas, never through ``pyplot``: a view leaves no open
figure behind and a notebook's inline backend does not show it a second time.
"""

from __future__ import annotations

import io
from collections.abc import Callable
from typing import Any

from bouncelab.core._html import escape, image

__all__ = ["NO_MATPLOTLIB", "figure", "png_of"]

#: What a view says where a figure would be without matplotlib.
NO_MATPLOTLIB = "Figure not drawn: matplotlib is not installed (pip install 'bouncelab[plot]')."


def png_of(draw: Callable[[Any], None], *, size: tuple[float, float] = (6.0, 2.6), dpi: int = 80,
           note: str | None = None) -> bytes | None:
    """PNG bytes of the figure ``draw(fig)`` fills (a :class:`matplotlib.figure.Figure` of ``size`` inches), or
    None when matplotlib cannot be imported. ``note`` is written small in the figure's top-right corner (e.g.
    that the data are synthetic)."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        return None
    fig = Figure(figsize=size, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    draw(fig)
    if note:
        fig.suptitle(note, x=0.99, ha="right", fontsize=7, color="#a33")
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return buffer.getvalue()


def figure(draw: Callable[[Any], None], alt: str, *, size: tuple[float, float] = (6.0, 2.6),
           note: str | None = None) -> str:
    """The figure as an inline ``<img>`` (:func:`bouncelab.core._html.image`), or a short note without matplotlib."""
    png = png_of(draw, size=size, note=note)
    return f"<p class='note'>{escape(NO_MATPLOTLIB)}</p>" if png is None else image(png, alt)
