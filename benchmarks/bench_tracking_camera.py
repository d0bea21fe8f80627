"""Camera files (issue 32): dropped frames measured at the file's times against the nominal rate, 12 bits
against 8, and the .cine reader's speed beside pims's.

Renders bounces (512 x 256 px, 5,000 fps, ball 40 px across, noise 5 grey levels on the 8-bit scale, 40
frames a side, random landings with lift-offs from ``Rigid.published("A")``) at 12 bits, drops two
consecutive frames 4 to 30 frames before touch-down (as a camera's buffer does), and writes each clip as a
Phantom .cine (12 bits in 16-bit words, first image number -20, the TIME64 block holding the gap). Each is
measured three ways:

* **file times**: ``track_clip(path)``, no frame rate given: the frames' own times (the gap is two periods);
* **nominal rate**: the same frames tracked at ``fps=5000``, as if every frame followed the last by 1/fps
  (what a reader that ignores the TIME64 block, or an export through the camera software, gives);
* **8 bits**: the clip without dropped frames, its 12-bit frames rounded to 8 bits, at its rate, against
  the same clip read from the 12-bit .cine.

Errors: the largest velocity error of landing and lift-off as a % of the speed (target 0.5 %), the largest
spin error over 2 % |omega| + 5 rad/s (target below 1). Then the time to read every frame of one .cine,
bouncelab's reader against ``pims.Cine`` (if installed), in one run, as a ratio, and whether the two read the
same pixels.

Run::

    python benchmarks/bench_tracking_camera.py --clips 12      # about 2 minutes
    python benchmarks/bench_tracking_camera.py --quick         # 2 clips, 3 read timings: checks it runs (CI)
"""

from __future__ import annotations

import argparse
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np


def _errors(m, clip) -> tuple[float, float]:
    worst_v, worst_w = 0.0, 0.0
    for side, true in (("landing", clip.landing), ("liftoff", clip.liftoff)):
        got = m[side].values
        worst_v = max(worst_v, float(np.abs(got[:2] - true[:2]).max() / np.hypot(*true[:2])))
        worst_w = max(worst_w, float(abs(got[2] - true[2]) / (0.02 * abs(true[2]) + 5.0)))
    return 100 * worst_v, worst_w


def _read_speed(path: Path, repeats: int = 9) -> str:
    from bouncelab.tracking.cine import read_cine

    cine = read_cine(path)
    n = cine.image_count

    def ours():
        for k in range(n):
            cine.frame(k)

    def theirs():
        import pims

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            reader = pims.Cine(str(path))
            for k in range(n):
                reader.get_frame(k)
            reader.close()

    try:
        import pims
    except ImportError:
        return f"reading {n} frames: bouncelab {n / min(_timed(ours) for _ in range(repeats)):.0f} frames/s; pims " \
               "not installed"
    times: dict[str, list[float]] = {"bouncelab": [], "pims": []}
    for _ in range(repeats):  # interleaved, so that the machine's load falls on both alike
        times["bouncelab"].append(_timed(ours))
        times["pims"].append(_timed(theirs))
    ta, tb = min(times["bouncelab"]), min(times["pims"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        reader = pims.Cine(str(path))
        same = all(np.array_equal(cine.frame(k), np.asarray(reader.get_frame(k))) for k in range(n))
        reader.close()
    return (f"reading {n} frames of {cine.width} x {cine.height} (12 bits in 16-bit words), best of {repeats}: "
            f"bouncelab {n / ta:.0f} frames/s, pims {n / tb:.0f} frames/s; bouncelab {tb / ta:.2f}x the speed of "
            f"pims (each frame read out of the file, top row first); the same pixels: {same}")


def _timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--clips", type=int, default=None, help="clips rendered (default 12; 2 with --quick)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--quick", action="store_true", help="2 clips and 3 read timings: checks it runs (CI)")
    args = ap.parse_args()
    args.clips = args.clips or (2 if args.quick else 12)

    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-camera-") as folder:  # ~46 MB a clip: removed after
        _measure(args.clips, args.seed, args.quick, Path(folder))


def _measure(clips: int, seed: int, quick: bool, folder: Path) -> None:
    """Render, write, track and measure ``clips`` clips in ``folder``; print the table and the read speeds."""
    from bouncelab import Rigid
    from bouncelab.tracking import measure_clip, read_frames, render_clip, track_clip
    from bouncelab.tracking.cine import write_cine

    rng = np.random.default_rng(seed)
    law = Rigid.published("A")
    landings = np.column_stack([rng.uniform(800, 1300, clips), -rng.uniform(600, 900, clips),
                                rng.uniform(-200, 600, clips)])
    liftoffs = law.predict(landings)
    rows = []
    for k in range(clips):
        clip = render_clip(landings[k], liftoffs[k], size=(256, 512), radius_px=20.0, n_before=40, n_after=40,
                           bit_depth=12, seed=seed + k)
        n = len(clip.frames)
        before = int(rng.integers(4, 31))  # frames before touch-down (frame 40) where the two go missing
        keep = np.ones(n, bool)
        keep[[40 - before - 1, 40 - before]] = False
        times = (-20 + np.arange(n)) / clip.fps
        path = folder / f"clip{k:02d}.cine"
        write_cine(path, clip.frames[keep], fps=clip.fps, times=times[keep], first_image_no=-20, bit_depth=12)
        at_times = _errors(measure_clip(track_clip(path)), clip)
        nominal = _errors(measure_clip(track_clip(read_frames(path), fps=clip.fps, name=path.name)), clip)
        full = folder / f"full{k:02d}.cine"
        write_cine(full, clip.frames, fps=clip.fps, first_image_no=-20, bit_depth=12)
        deep = _errors(measure_clip(track_clip(full)), clip)
        eight = np.rint(clip.frames.astype(np.float64) * (255.0 / 4095.0)).astype(np.uint8)
        shallow = _errors(measure_clip(track_clip(eight, fps=clip.fps)), clip)
        rows.append((before, *at_times, *nominal, *deep, *shallow))
        print(f"clip {k:2d}: 2 frames dropped {before:2d} frames before touch-down | velocity error (% of speed) / "
              f"spin error (of 2 % + 5 rad/s): file times {at_times[0]:.3f} / {at_times[1]:.2f}, nominal rate "
              f"{nominal[0]:.3f} / {nominal[1]:.2f}; no drop: 12 bits {deep[0]:.3f} / {deep[1]:.2f}, "
              f"8 bits {shallow[0]:.3f} / {shallow[1]:.2f}", flush=True)
    r = np.array(rows)
    for label, col in (("file times (dropped frames)", 1), ("nominal rate (dropped frames)", 3),
                       ("12-bit .cine (no drop)", 5), ("rounded to 8 bits (no drop)", 7)):
        v, w = r[:, col], r[:, col + 1]
        print(f"{label:32}: velocity error median {np.median(v):.3f} %, max {v.max():.3f} %, within 0.5 %: "
              f"{np.mean(v < 0.5):.0%}; spin within target: {np.mean(w < 1):.0%} (worst {w.max():.2f})")
    print(_read_speed(folder / "full00.cine", repeats=3 if quick else 9))


if __name__ == "__main__":
    main()
