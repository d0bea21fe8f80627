"""Peak memory of tracking a long full-HD clip (issue 22, item 7): 600 frames of 1920 x 1080 in an MJPG AVI,
or (issue 32) in a 12-bit Phantom .cine (16-bit words, 2.5 GB), read by memory map and tracked at full bit depth.

Renders one bounce (ball 80 px across, 20,000 fps, 297 frames a side) with
:func:`bouncelab.tracking.render_clip`, writes it as an MJPG AVI with OpenCV's
``VideoWriter`` (grey, quality 95) or, for a path ending in ``.cine``, as a 12-bit
``.cine`` (:func:`bouncelab.tracking.cine.write_cine`), and tracks it in a fresh
process, reporting the process's peak resident memory (``resource.getrusage``) and
the time. Measure the whole command from outside with GNU time as well::

    python benchmarks/bench_tracking_memory.py make /tmp/hd/clip.avi      # about a minute
    /usr/bin/time -v bouncelab track /tmp/hd/clip.avi --fps 20000 --out /tmp/hd/clip.nc --quiet
    python benchmarks/bench_tracking_memory.py track /tmp/hd/clip.avi     # peak RSS and time of track_clip

    python benchmarks/bench_tracking_memory.py make /tmp/hd/clip.cine     # a 12-bit .cine
    /usr/bin/time -v bouncelab track /tmp/hd/clip.cine --out /tmp/hd/cine.nc --quiet
    python benchmarks/bench_tracking_memory.py track /tmp/hd/clip.cine

``track`` prints beside the peak the size of the clip decoded into memory (frames x pixels x bytes per pixel),
what a tracker that reads the whole clip first would hold at least. ``--quick`` (CI) makes and tracks, each in a
fresh process as above, a short small clip (12 frames a side, 480 x 270 px) as an AVI and as a .cine in a
temporary folder.
"""

from __future__ import annotations

import argparse
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LANDING = (1063.0, -810.0, 219.0)
LIFTOFF = (696.7, 440.6, -696.7)  # Rigid.published("A") of LANDING


def make(path: Path, n_side: int = 297, size: tuple[int, int] = (1080, 1920)) -> None:
    """Render the clip (``size`` = rows, columns) and write it as a grey MJPG AVI, frame by frame, or a .cine."""
    import cv2

    from bouncelab.tracking import render_clip

    t0 = time.perf_counter()
    cine = path.suffix.lower() == ".cine"
    clip = render_clip(LANDING, LIFTOFF, fps=20000.0, size=size, radius_px=40.0, n_before=n_side,
                       n_after=n_side, contact_frames=6.0, seed=1, bit_depth=12 if cine else 8)
    path.parent.mkdir(parents=True, exist_ok=True)
    picture = f"{clip.frames.shape[0]} frames of {size[1]} x {size[0]}"
    if cine:
        from bouncelab.tracking.cine import write_cine

        write_cine(path, clip.frames, fps=clip.fps, bit_depth=12, first_image_no=-n_side)
        print(f"{path}: {picture}, 12 bits in 16-bit words, {path.stat().st_size / 1e6:.1f} MB, rendered and "
              f"written in {time.perf_counter() - t0:.0f} s")
        return
    w = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"MJPG"), 25, (size[1], size[0]), False)
    w.set(cv2.VIDEOWRITER_PROP_QUALITY, 95)
    for frame in clip.frames:
        w.write(frame)
    w.release()
    print(f"{path}: {picture}, {path.stat().st_size / 1e6:.1f} MB, rendered and written in "
          f"{time.perf_counter() - t0:.0f} s")


def decoded_bytes(path: Path) -> int:
    """Bytes of the whole clip decoded into memory: frames x rows x columns x bytes per pixel."""
    if path.suffix.lower() == ".cine":
        from bouncelab.tracking.cine import read_cine

        cine = read_cine(path)
        return cine.image_count * cine.width * cine.height * cine.frame(0).itemsize
    import cv2

    cap = cv2.VideoCapture(str(path))
    try:
        n, w, h = (int(cap.get(p)) for p in (cv2.CAP_PROP_FRAME_COUNT, cv2.CAP_PROP_FRAME_WIDTH,
                                              cv2.CAP_PROP_FRAME_HEIGHT))
    finally:
        cap.release()
    return n * w * h  # grey, 8 bits


def track(path: Path) -> None:
    """Track and measure the clip; print the peak resident memory of this process and the time."""
    from bouncelab.tracking import measure_clip, track_clip

    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    tr = track_clip(path, fps=None if path.suffix.lower() == ".cine" else 20000.0)  # a .cine has its times
    m = measure_clip(tr)
    el = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # KiB on Linux
    clip = decoded_bytes(path) / 2**20
    print(f"{tr.sizes['frame']} frames tracked in {el:.1f} s ({tr.sizes['frame'] / el:.0f} frames/s); "
          f"peak RSS {peak / 1024:.0f} MiB (after imports {before / 1024:.0f} MiB); the clip decoded into memory: "
          f"{clip:.0f} MiB (peak added / clip: {(peak - before) / 1024 / clip:.2f})")
    print("landing", m.landing.values.round(1), "true", LANDING)
    print("liftoff", m.liftoff.values.round(1), "true", LIFTOFF)


def quick() -> None:
    """A short small clip, as an AVI and as a .cine: each made, then tracked in a fresh process (CI)."""
    with tempfile.TemporaryDirectory(prefix="bouncelab-bench-memory-") as folder:
        for name in ("clip.avi", "clip.cine"):
            path = str(Path(folder) / name)
            for step in (["make", path, "--frames-a-side", "12", "--size", "270", "480"], ["track", path]):
                subprocess.run([sys.executable, __file__, *step], check=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["make", "track"], nargs="?", help="make a clip or track one")
    ap.add_argument("path", type=Path, nargs="?", help="the clip (.avi or .cine)")
    ap.add_argument("--frames-a-side", type=int, default=297, help="make: frames before and after contact (297)")
    ap.add_argument("--size", type=int, nargs=2, default=[1080, 1920], metavar=("ROWS", "COLUMNS"),
                    help="make: the picture (default 1080 1920)")
    ap.add_argument("--quick", action="store_true", help="make and track a short small clip of each kind (CI)")
    args = ap.parse_args()
    if args.quick:
        quick()
    elif args.what is None or args.path is None:
        ap.error("give make PATH or track PATH, or --quick")
    elif args.what == "make":
        make(args.path, args.frames_a_side, tuple(args.size))
    else:
        track(args.path)


if __name__ == "__main__":
    main()
