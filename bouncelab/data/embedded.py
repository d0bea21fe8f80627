"""The campaigns shipped inside the package: their names, the surrogates they come as, and their files.

The files themselves are made by :mod:`bouncelab.simulation.surrogate` (``python -m
bouncelab.simulation.surrogate --write``); the loader only needs to know where they are, so these facts
live here, below both.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["DEFAULT_SURROGATE", "EMBEDDED_CAMPAIGNS", "SURROGATES", "embedded_file_name", "embedded_path"]

#: Names of the campaigns shipped with the package (``load_campaign("A")``).
EMBEDDED_CAMPAIGNS = ("A", "B")

#: The embedded surrogates: ``"published"`` (made from the paper's published laws,
#: :func:`bouncelab.simulation.surrogate.generate_surrogate`) and ``"turf"`` (simulated with the calibrated
#: turf of :data:`bouncelab.simulation.surrogate.TURF_CALIBRATION`).
SURROGATES = ("published", "turf")

#: The surrogate ``load_campaign("A")`` and ``("B")`` return when none is named: the one the calibration
#: measures closer to the paper (docs/simulation.md, "The shipped surrogates against the paper": its
#: objective J, 0.18 for "turf" against 4.4 for "published", and fewer rolling lift-offs; the median miss is
#: level). "published" is made from the very laws the paper fitted, so the comparisons on it are circular.
DEFAULT_SURROGATE = "turf"


def embedded_file_name(campaign: str, surrogate: str = DEFAULT_SURROGATE) -> str:
    """Name of the embedded file of ``campaign`` and ``surrogate`` in ``bouncelab/data/files``
    (``campaign_B.nc`` for the published surrogate, which came first; ``campaign_B_turf.nc``)."""
    return f"campaign_{campaign}.nc" if surrogate == "published" else f"campaign_{campaign}_{surrogate}.nc"


def embedded_path(campaign: str, surrogate: str = DEFAULT_SURROGATE) -> Path:
    """Path of the embedded file of ``campaign`` and ``surrogate`` inside the package."""
    return Path(__file__).parent / "files" / embedded_file_name(campaign, surrogate)
