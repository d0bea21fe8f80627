"""The reference-shot suite: five landings run to rest on every preset surface.

A fixed table of landings (:data:`SHOTS`) and their outcomes on each preset surface
(:data:`bouncelab.ground.surface.PRESET_NAMES`): first lift-off, bounce count, carry of the
bounces, roll, total run. The table is checked in (``docs/ground/reference_shots.csv``) and
a test regenerates it, so any change to a law, a surface or the ground model shows as a diff.

The landings: the paper's typical driver landing (93.6 ft/s, 37.3 degrees, 34.9 rev/s of
backspin; its Fig. 4) and four illustrative landings chosen inside the ranges of its Table 1
for *both* campaigns (speed 6.35-38.7 m/s, angle of incidence 18.3-76.4 degrees, spin -3750
to 9100 rpm), not measured shots. All travel in +x on flat ground, backspin positive in rpm.

Regenerate (from the repository root)::

    python -m bouncelab.ground.shots --write docs

writes ``docs/ground/reference_shots.csv``, the Markdown table
``docs/snippets/ground_reference_shots.md`` and the plot
``docs/img/ground_reference_paths.png``; without ``--write`` it prints the table.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from bouncelab.ground.surface import PRESET_NAMES, preset

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["CSV_NAME", "SHOTS", "TOLERANCE", "landings", "plot_paths", "reference_table", "write"]

#: name -> (speed m/s, angle of incidence in degrees, backspin rpm, what it stands for)
SHOTS: dict[str, tuple[float, float, float, str]] = {
    "driver": (93.6 * 0.3048, 37.3, 34.9 * 60.0,
               "the paper's typical driver landing (93.6 ft/s, 37.3 deg, 34.9 rev/s)"),
    "mid-iron": (20.0, 48.0, 6000.0, "a mid iron: steeper, more backspin"),
    "wedge": (15.0, 52.0, 9000.0, "a wedge with high backspin (Table 1's campaign A reaches 9100 rpm)"),
    "chip": (8.0, 30.0, 2500.0, "a chip: slow and shallow"),
    "low-runner": (20.0, 20.0, -1000.0, "a low runner with topspin"),
}

#: Where the checked-in table lives, relative to the docs folder.
CSV_NAME = "ground/reference_shots.csv"
#: Tolerance of the regenerated table against the checked-in one: |new - old| <= atol + rtol |old| for every
#: number (lengths in m, speeds in m/s, spins in rpm, times in s), counts equal.
TOLERANCE = {"rtol": 1e-6, "atol": 1e-5}

_COLUMNS = ["liftoff_speed", "liftoff_angle_deg", "liftoff_backspin", "bounces", "bounce_carry", "roll", "total_run",
            "time_to_rest", "into_ground"]
_UNITS = {"velocity": "m/s", "spin": "rpm"}


def landings() -> tuple[np.ndarray, np.ndarray]:
    """Velocities (m/s) and spin vectors (rpm) of :data:`SHOTS`, (5, 3) each: +x, z up, backspin -y."""
    speed, angle, spin = (np.array([s[i] for s in SHOTS.values()]) for i in range(3))
    a = np.radians(angle)
    v = np.column_stack([speed * np.cos(a), np.zeros(len(a)), -speed * np.sin(a)])
    w = np.column_stack([np.zeros(len(a)), -spin, np.zeros(len(a))])
    return v, w


def reference_table(surfaces: tuple[str, ...] = PRESET_NAMES) -> pd.DataFrame:
    """Outcomes of every shot on every surface (one row each), in m, m/s, rpm and s."""
    import pandas as pd

    from bouncelab.ground.runout import run

    v, w = landings()
    frames = []
    for name in surfaces:
        t = run(v, w, preset(name), units=_UNITS).totals[_COLUMNS]
        t.insert(0, "shot", list(SHOTS))
        t.insert(0, "surface", name)
        frames.append(t)
    return pd.concat(frames, ignore_index=True)


def _landing_table() -> str:
    lines = ["| shot | speed (m/s) | angle (deg) | backspin (rpm) | |", "|---|---:|---:|---:|---|"]
    for name, (speed, angle, spin, text) in SHOTS.items():
        lines.append(f"| {name} | {speed:.2f} | {angle:.1f} | {spin:.0f} | {text} |")
    return "\n".join(lines)


def markdown(table: pd.DataFrame) -> str:
    """The outcome table as Markdown (rounded for reading; the CSV has the full figures)."""
    head = ("| surface | shot | lift-off speed (m/s) | lift-off angle (deg) | lift-off backspin (rpm) | bounces | "
            "bounce carry (m) | roll (m) | total run (m) | time to rest (s) |")
    lines = [head, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in table.itertuples(index=False):
        lines.append(f"| {r.surface} | {r.shot} | {r.liftoff_speed:.2f} | {r.liftoff_angle_deg:.1f} | "
                     f"{r.liftoff_backspin:.0f} | {r.bounces} | {r.bounce_carry:.2f} | {r.roll:.2f} | "
                     f"{r.total_run:.2f} | {r.time_to_rest:.2f} |")
    return "\n".join(lines)


def plot_paths(path: str | Path, surfaces: tuple[str, ...] = PRESET_NAMES, rate: float = 200.0) -> Path:
    """Side view (height against distance) of every reference shot on every surface, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bouncelab.ground.runout import run

    v, w = landings()
    fig, axes = plt.subplots(len(surfaces), 1, figsize=(8.0, 1.9 * len(surfaces)), sharex=True)
    axes = np.atleast_1d(axes)
    for ax, name in zip(axes, surfaces, strict=True):
        ds = run(v, w, preset(name), units=_UNITS, rate=rate).path
        for i, shot in enumerate(SHOTS):
            p = ds["position"].isel(shot=i)
            (line,) = ax.plot(p.sel(axis="x"), p.sel(axis="z"), lw=1.0, label=shot)
            ax.plot(float(p.sel(axis="x")[-1]), 0.0, "v", color=line.get_color(), ms=5)
        ax.set_ylabel("height (m)")
        ax.set_title(name, fontsize=9, loc="left")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, ncol=len(SHOTS), loc="upper right")
    axes[-1].set_xlabel("distance from the first landing (m); a triangle marks where the ball rests")
    fig.tight_layout()
    from bouncelab.core.atomic import atomic_path

    out = Path(path)
    with atomic_path(out, "the plot") as tmp:  # (a device or a FIFO is refused, a failed write leaves no file)
        fig.savefig(tmp, dpi=80, format="png")
    plt.close(fig)
    return out


def write(docs: str | Path) -> list[Path]:
    """Regenerate the checked-in CSV, the Markdown table and the plot under the docs folder ``docs``."""
    from bouncelab.core.atomic import atomic_write_text

    docs = Path(docs)
    table = reference_table()
    csv = docs / CSV_NAME
    csv.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(csv, table.to_csv(index=False, float_format="%.6f", lineterminator="\n"))
    md = docs / "snippets" / "ground_reference_shots.md"
    png = docs / "img" / "ground_reference_paths.png"
    md.parent.mkdir(parents=True, exist_ok=True)
    png.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(md, _landing_table() + "\n\n" + markdown(table) + "\n")
    plot_paths(png)
    return [csv, md, png]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bouncelab.ground.shots", description=__doc__.splitlines()[0])
    parser.add_argument("--write", metavar="DOCS", help="regenerate the CSV, Markdown table and plot under DOCS")
    args = parser.parse_args(argv)
    if args.write:
        for p in write(args.write):
            print(f"wrote {p}")
    else:
        import pandas as pd

        with pd.option_context("display.width", 200, "display.max_columns", 20):
            print(reference_table().round(3).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
