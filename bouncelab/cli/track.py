"""``bouncelab track``: high-speed clips of bounces to a campaign file.

Each CLIP is a video file, a folder of images or a ``.npz`` of frames (a folder
holding only clips, not images, is expanded to its clips). Clips that fail are
summarised with the reason and do not stop the others. Exit codes: 0 at least
one clip measured (the campaign is written), 2 bad command line, 3 no clip
could be measured.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from bouncelab.errors import DataError

EXIT_OK, EXIT_USAGE, EXIT_DATA = 0, 2, 3


def add_parser(sub) -> argparse.ArgumentParser:
    """Register the ``track`` subcommand on ``sub`` (the main parser's subparsers)."""
    p = sub.add_parser(
        "track", help="track high-speed clips of bounces into a campaign file",
        description="Find the ball in each frame, its spin from matched features, touch-down and lift-off from "
                    "the lowest visible point, and the landing and lift-off states with the paper's intervals; "
                    "write one bounce per clip to a campaign file (NetCDF) that 'bouncelab reproduce --data' "
                    "reads.",
    )
    p.add_argument("clips", nargs="+", metavar="CLIP",
                   help="video files (AVI, MP4, ...), folders of images (PNG, TIFF, BMP) or .npz frame files; "
                        "a folder of such clips is expanded")
    p.add_argument("--fps", type=float, help="camera frame rate, frames/s (unless in the manifest or file names)")
    p.add_argument("--ball-radius-mm", type=float, default=21.35, help="ball radius, mm (default 21.35)")
    p.add_argument("--pixels-per-mm", type=float,
                   help="image scale (default: from the ball's detected radius)")
    p.add_argument("--manifest", metavar="FILE",
                   help="CSV with a column 'clip' and any of fps, setting, ball_radius_mm, pixels_per_metre")
    p.add_argument("--pattern", metavar="REGEX",
                   help=r"regular expression on file names with named groups setting, fps, ...; "
                        r"e.g. '(?P<setting>s\d+)_r\d+_(?P<fps>\d+)fps'")
    p.add_argument("--method", choices=["differences", "positions"], default="differences",
                   help="velocity estimator: the paper's (differences, default) or quadratic positions")
    p.add_argument("--campaign", default="", help="campaign name stored in the file")
    p.add_argument("--surface", default="", help="surface description stored in the file")
    p.add_argument("--synthetic", action="store_true", help="mark the campaign as synthetic (rendered clips)")
    p.add_argument("--figures", metavar="DIR", help="write a diagnostic figure per clip there (PNG)")
    p.add_argument("--jobs", type=int, default=1, help="clips tracked at once, in separate processes (default 1)")
    p.add_argument("--out", required=True, help="campaign file to write (.nc)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def expand_clips(paths: list[str]) -> list[str]:
    """The clips named: a folder with images is one clip; a folder without is expanded to its clips."""
    from bouncelab.tracking.frames import IMAGE_SUFFIXES, VIDEO_SUFFIXES

    out: list[str] = []
    for p in map(Path, paths):
        if p.is_dir() and not any(q.suffix.lower() in IMAGE_SUFFIXES for q in p.iterdir()):
            inner = sorted(q for q in p.iterdir()
                           if q.suffix.lower() in (*VIDEO_SUFFIXES, ".npz") or q.is_dir())
            out.extend(str(q) for q in inner)
        else:
            out.append(str(p))
    return out


class _Bar:
    """A one-line progress bar on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled, self.t0 = total, enabled, time.perf_counter()

    def __call__(self, done: int, total: int, clip: str) -> None:
        if not self.enabled:
            return
        width = 30
        fill = int(width * done / max(total, 1))
        el = time.perf_counter() - self.t0
        print(f"\r[{'#' * fill}{'.' * (width - fill)}] {done}/{total} clips ({el:.1f} s) {Path(clip).name[:40]:<40}",
              end="" if done < total else "\n", file=sys.stderr, flush=True)


def _check_outputs(out: str, figures: str | None) -> None:
    """Refuse --out and --figures before any tracking, which a bad output path would throw away (OutputError)."""
    from bouncelab.cli.reproduce import OutputError, check_output_file

    check_output_file(out, "--out", "campaign.nc", suffix=".nc")
    if figures is not None and Path(figures).expanduser().exists() and not Path(figures).expanduser().is_dir():
        raise OutputError(f"--figures {figures!r} is a file, not a folder")


def run(args: argparse.Namespace) -> int:
    """Run ``bouncelab track``; returns the exit code."""
    from bouncelab.data.io import save_campaign
    from bouncelab.tracking import clip_settings, measure_clips

    for name in ("fps", "ball_radius_mm", "pixels_per_mm", "jobs"):
        v = getattr(args, name)
        if v is not None and not v > 0:
            print(f"bouncelab track: --{name.replace('_', '-')} must be positive; got {v}", file=sys.stderr)
            return EXIT_USAGE
    _check_outputs(args.out, args.figures)
    clips = expand_clips(args.clips)
    if args.fps is None and not args.manifest and not args.pattern \
            and not any(Path(c).suffix.lower() == ".npz" for c in clips):
        print("bouncelab track: --fps is needed: the frame rate is not in a manifest, a --pattern or the clips "
              "(e.g. --fps 5000)", file=sys.stderr)
        return EXIT_USAGE
    if not clips:
        print("bouncelab track: no clips found in the folders given", file=sys.stderr)
        return EXIT_DATA
    ppm = None if args.pixels_per_mm is None else args.pixels_per_mm * 1000.0
    settings = clip_settings(clips, fps=args.fps, ball_radius_m=args.ball_radius_mm / 1000.0,
                             pixels_per_metre=ppm, manifest=args.manifest, pattern=args.pattern)
    bar = _Bar(len(clips), not args.quiet)
    res = measure_clips(clips, settings=settings, method=args.method, campaign=args.campaign, surface=args.surface,
                        data_kind="synthetic surrogate" if args.synthetic else "measured", progress=bar,
                        keep_tracks=False, figure_dir=args.figures, workers=args.jobs)
    n_ok = len(res.measurements)
    print(f"{n_ok} of {len(clips)} clip(s) measured", file=sys.stderr)
    if res.failures:
        print(f"{len(res.failures)} clip(s) failed:", file=sys.stderr)
        for f in res.failures:
            print(f"  {f.clip}: {f.reason}", file=sys.stderr)
    if res.campaign is None:
        raise DataError(f"no clip could be measured (reasons above); nothing written to {args.out}")
    save_campaign(res.campaign, args.out)
    print(f"campaign of {n_ok} bounce(s) written to {args.out}")
    if args.figures:
        print(f"diagnostic figures in {args.figures}")
    return EXIT_OK
