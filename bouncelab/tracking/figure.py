"""The per-clip diagnostic figure (:func:`diagnostic_figure`): the track over a frame, the contact
interval on the lowest visible point, and the spin samples with the estimates. Needs matplotlib.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from bouncelab.core.atomic import atomic_path

__all__ = ["diagnostic_figure"]


def diagnostic_figure(frames: np.ndarray, track: xr.Dataset, measurement: xr.Dataset | None = None,
                      path: str | Path | None = None):
    """Draw (and optionally save as PNG) the diagnostic figure of one clip.

    Parameters
    ----------
    frames
        (t, h, w) frames of the clip, or its :class:`~bouncelab.tracking.frames.Clip`
        (only the frame shown is read).
    track
        From :func:`~bouncelab.tracking.track_clip`.
    measurement
        From :func:`~bouncelab.tracking.measure_clip` (``None`` if it failed:
        the figure then shows the track only).
    path
        Where to write the PNG (atomically); ``None`` only returns the figure.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels: (a) the frame at touch-down with the tracked centres
        (dots) and the detected circles at touch-down and lift-off, the surface
        line dashed; (b) the height of the lowest visible point against time
        with the detected contact interval shaded; (c) the spin samples
        against time with the landing and lift-off spins and their intervals.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    t = track["t"].values * 1e3
    found = track["found"].values
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), gridspec_kw={"width_ratios": [1.6, 1, 1]})
    ax = axes[0]
    k_show = int(measurement.attrs["touchdown_index"]) if measurement is not None else int(np.argmax(found))
    ax.imshow(frames[k_show], cmap="gray", vmin=0, vmax=255)
    ax.plot(track["col"].values, track["row"].values, ".", ms=2.5, color="tab:orange", label="tracked centre")
    if measurement is not None:
        for key, color in (("touchdown_index", "tab:red"), ("liftoff_index", "tab:green")):
            k = int(measurement.attrs[key])
            if found[k]:
                circ = plt.Circle((track["col"].values[k], track["row"].values[k]), track["radius_px"].values[k],
                                  fill=False, color=color, lw=1)
                ax.add_patch(circ)
    if track.attrs.get("surface_row", "none") != "none":
        ax.axhline(float(track.attrs["surface_row"]), color="tab:cyan", ls="--", lw=0.8, label="surface line")
    ax.set_title(f"{Path(str(track.attrs.get('clip', ''))).name}: frame {k_show}")
    ax.legend(loc="upper right", fontsize=7)
    ax.set_axis_off()

    ax = axes[1]
    ax.plot(t, track["lowest"].values, ".-", ms=3, lw=0.6)
    if measurement is not None:
        ax.axvspan(measurement.attrs["touchdown_time"] * 1e3, measurement.attrs["liftoff_time"] * 1e3,
                   color="tab:red", alpha=0.15, label="contact")
        ax.legend(fontsize=7)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("lowest visible point (radii)")
    ax.set_title("touch-down and lift-off")

    ax = axes[2]
    ax.plot(t, track["spin"].values, ".", ms=4, color="0.3", label="spin samples")
    if measurement is not None:
        sides = (("landing", 0.0, measurement.attrs["touchdown_time"]),
                 ("liftoff", measurement.attrs["liftoff_time"], float(track["t"].values[-1])))
        for key, a, b in sides:
            w = float(measurement[key].sel(component="omega"))
            hw = float(measurement[f"{key}_pi"].sel(component="omega"))
            ax.hlines(w, a * 1e3, b * 1e3, color="tab:blue")
            ax.fill_between([a * 1e3, b * 1e3], w - hw, w + hw, color="tab:blue", alpha=0.2)
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("spin (rad/s, anticlockwise)")
    ax.set_title("spin samples and estimates (95 %)")
    fig.tight_layout()
    if path is not None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=110, format="png")
    return fig
