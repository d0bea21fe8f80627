"""From a high-speed clip to the landing and lift-off states: the video front end on the shipped clip.

What it shows
    * reading a clip (:func:`bouncelab.tracking.read_frames`): the shipped example is a
      rendered 39-frame clip (256 x 128 pixels, 5000 fps, ball radius 16 px, sensor noise
      2.5 grey levels, 0.8 MB) with known truth, stored as ``bouncelab/tracking/files/example_clip.npz``;
    * tracking the ball (:func:`bouncelab.tracking.track_clip`): sub-pixel centre, lowest
      visible point and spin samples, in ball radii and rad/s (y up, omega anticlockwise);
    * measuring the bounce (:func:`bouncelab.tracking.measure_clip`): touch-down and lift-off
      from the lowest visible point, the states with the paper's 95 % intervals, printed
      beside the truth the clip was rendered from;
    * with ``--figure``, the diagnostic figure written to a PNG in a new temporary directory;
    * with ``--cine``, the clip written as a Phantom ``.cine`` first
      (:func:`bouncelab.tracking.write_cine`, first image number -20, in a new temporary
      directory) and tracked from that file without a frame rate: the file's own frame times.

Run it from the repository root (a few seconds)::

    python examples/track_clip.py [--figure] [--cine]
"""

from __future__ import annotations

import argparse
import tempfile
from importlib import resources
from pathlib import Path

import numpy as np

from bouncelab.tracking import measure_clip, read_frames, track_clip, write_cine


def main() -> None:
    ap = argparse.ArgumentParser(description="Track the shipped example clip.")
    ap.add_argument("--figure", action="store_true", help="write the diagnostic figure (needs matplotlib)")
    ap.add_argument("--cine", action="store_true", help="track the clip written as a Phantom .cine (no frame rate)")
    args = ap.parse_args()

    path = resources.files("bouncelab.tracking") / "files" / "example_clip.npz"
    with resources.as_file(path) as clip_path:
        frames = read_frames(clip_path)
        with np.load(clip_path) as f:
            fps = float(f["fps"])
            truth = {"landing": f["true_landing"], "liftoff": f["true_liftoff"]}
    if args.cine:
        cine = Path(tempfile.mkdtemp()) / "example_clip.cine"
        write_cine(cine, frames, fps=fps, first_image_no=-20)
        track = track_clip(cine)  # the frame times are the file's
        print(f"written to {cine} and tracked from it: times {track['t'].values[0] * 1e3:.1f} to "
              f"{track['t'].values[-1] * 1e3:.1f} ms from the trigger ({track.attrs['time_source']})")
    else:
        track = track_clip(frames, fps=fps, name="example_clip.npz")
    m = measure_clip(track)
    print(f"{frames.shape[0]} frames of {frames.shape[2]} x {frames.shape[1]} px at {fps:.0f} fps; "
          f"ball radius {track.attrs['radius_px']:.2f} px; frames where it was lost: {track.attrs['dropped_frames']}")
    print(f"touch-down at frame {m.attrs['touchdown_index']} ({1e3 * m.attrs['touchdown_time']:.3f} ms), "
          f"lift-off at frame {m.attrs['liftoff_index']} ({1e3 * m.attrs['liftoff_time']:.3f} ms)")
    print(f"{'':8} {'component':>9} {'measured':>10} {'95 % PI':>8} {'truth':>9}")
    for side in ("landing", "liftoff"):
        for k, comp in enumerate(("xdot", "ydot", "omega")):
            print(f"{side:8} {comp:>9} {m[side].values[k]:10.1f} {m[side + '_pi'].values[k]:8.1f} "
                  f"{truth[side][k]:9.1f}")
    if args.figure:
        import matplotlib.pyplot as plt

        from bouncelab.tracking.figure import diagnostic_figure

        out = Path(tempfile.mkdtemp()) / "example_clip.png"
        plt.close(diagnostic_figure(frames, track, m, out))
        print(f"figure written to {out}")


if __name__ == "__main__":
    main()
