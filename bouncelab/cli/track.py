"""``bouncelab track``: high-speed clips of bounces to a campaign file.

Each CLIP is a camera file (Phantom ``.cine``, Photron ``.mraw`` with its ``.cihx`` or ``.cih``),
a video file, a folder of images or a ``.npz``/``.npy`` of frames (a folder holding only clips,
not images, is expanded to its clips). Camera files record their frames' times, which the
measurement uses (frames the camera dropped leave a gap): they need no ``--fps``, and an
``--fps`` that disagrees with their times is refused. Clips that fail are
summarised with the reason and do not stop the others. Exit codes: 0 at least
one clip measured (the campaign is written), 2 bad command line or an output
that cannot be written (``--out``, ``--figures``), 3 no clip could be measured,
or the bounces measured are not golf bounces at the frame rate given.

The frame rate, the file-name pattern and the outputs are checked before any
clip is tracked: ``--fps`` must be a finite number of frames per second within
:data:`CAMERA_FPS_RANGE`; ``--pattern`` must compile, name only groups that set
something, and match each file name (the name only, never its folder) within
:data:`PATTERN_SECONDS` (a pattern with catastrophic backtracking, such as
``(a+)+$``, is stopped and refused instead of hanging); ``--out`` must be a
``.nc`` file in an existing folder where a file can be created.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from bouncelab.cli.messages import EXIT_DATA, EXIT_OK, EXIT_USAGE, UsageError, message
from bouncelab.cli.options import finite, positive, whole
from bouncelab.core.errors import DataError

#: Frame rates ``--fps`` accepts, frames/s. Below 100 no camera films a golf bounce (a ball at 25 m/s moves
#: 0.25 m between frames, the whole contact falls between two of them): 24-60 frames/s is the playback rate a
#: video container stores, not the camera's. Above 10^7 no video camera records. (The library, which also reads
#: slow test clips, accepts 1 to 10^7: bouncelab.tracking.FPS_RANGE.)
CAMERA_FPS_RANGE = (100.0, 1e7)
#: Longest ``--pattern`` may take to match one file name, in seconds (a file name matches in microseconds).
PATTERN_SECONDS = 1.0
#: The named groups ``--pattern`` may set (bouncelab.tracking.clip_settings).
PATTERN_GROUPS = ("setting", "fps", "ball_radius_mm", "pixels_per_metre")
_FPS_HINT = "give the camera's recording rate, e.g. --fps 5000 (not the video's playback rate, often 25 or 30)"



def _fps(text: str) -> float:
    """--fps: frames per second within CAMERA_FPS_RANGE (argparse type)."""
    value = finite(text)
    low, high = CAMERA_FPS_RANGE
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive number of frames per second; got {text!r}")
    if value < low:
        raise argparse.ArgumentTypeError(f"{text} frames/s is slower than any camera that can film a bounce "
                                         f"(under {low:g}); {_FPS_HINT}")
    if value > high:
        raise argparse.ArgumentTypeError(f"{text} frames/s is faster than any video camera records (over "
                                         f"{high:.0e}); {_FPS_HINT}")
    return value



def _ball_radius_mm(text: str) -> float:
    from bouncelab.core.units import BALL_RADIUS_RANGE_M

    value = finite(text)
    low, high = (1000.0 * r for r in BALL_RADIUS_RANGE_M)
    if not low <= value <= high:
        raise argparse.ArgumentTypeError(f"a ball's radius in millimetres, {low:g} to {high:g} (a golf ball's is "
                                         f"21.35); got {text!r}")
    return value


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
                   help="camera files (Phantom .cine, Photron .mraw beside its .cihx or .cih), video files (AVI, "
                        "MP4, ...), folders of images (PNG, TIFF, BMP) or .npz/.npy frame files; a folder of such "
                        "clips is expanded")
    p.add_argument("--fps", type=_fps,
                   help="the camera's recording rate, frames/s, 100 to 1e7 (unless in the manifest, the file names "
                        "or a .npz clip); not a video's playback rate. Not needed for .cine and .mraw files, which "
                        "record their frames' times (if given, it must agree with them)")
    p.add_argument("--ball-radius-mm", type=_ball_radius_mm, default=21.35, help="ball radius, mm (default 21.35)")
    p.add_argument("--pixels-per-mm", type=positive,
                   help="image scale (default: from the ball's detected radius)")
    p.add_argument("--manifest", metavar="FILE",
                   help="CSV with a column 'clip' and any of fps, setting, ball_radius_mm, pixels_per_metre")
    p.add_argument("--pattern", metavar="REGEX",
                   help=r"regular expression searched in each file name (not its folder) with named groups among "
                        r"setting, fps, ball_radius_mm, pixels_per_metre; e.g. "
                        r"'(?P<setting>s\d+)_r\d+_(?P<fps>\d+)fps'; a pattern that takes over 1 s on a name is refused")
    p.add_argument("--method", choices=["differences", "positions"], default="differences",
                   help="velocity estimator: the paper's (differences, default) or quadratic positions")
    p.add_argument("--campaign", default="", help="campaign name stored in the file")
    p.add_argument("--surface", default="", help="surface description stored in the file")
    p.add_argument("--synthetic", action="store_true", help="mark the campaign as synthetic (rendered clips)")
    p.add_argument("--figures", metavar="DIR", help="write a diagnostic figure per clip there (PNG)")
    p.add_argument("--jobs", type=whole(1, "processes"), default=1,
                   help="clips tracked at once, in separate processes (default 1)")
    p.add_argument("--out", required=True, help="campaign file to write (.nc)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def expand_clips(paths: list[str]) -> list[str]:
    """The clips named: a folder with images is one clip; a folder without is expanded to its clips."""
    from bouncelab.tracking.frames import ARRAY_SUFFIXES, IMAGE_SUFFIXES, VIDEO_SUFFIXES

    # A Photron clip is named by its .mraw (its header beside it is not another clip).
    clip_suffixes = (*VIDEO_SUFFIXES, *ARRAY_SUFFIXES, ".cine", ".mraw")
    out: list[str] = []
    for p in map(Path, paths):
        if p.is_dir() and not any(q.suffix.lower() in IMAGE_SUFFIXES for q in p.iterdir()):
            inner = sorted(q for q in p.iterdir() if q.suffix.lower() in clip_suffixes or q.is_dir())
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
    """Refuse --out and --figures before any tracking, which a bad output path would throw away (OutputError):
    a folder, a missing folder, another suffix, or a folder where no file can be created (read-only)."""
    from bouncelab.cli.reproduce import OutputError, check_output_file

    check_output_file(out, "--out", "campaign.nc", suffix=".nc")
    _check_writable(Path(out).expanduser().parent, f"--out {out!r}")
    if figures is not None:
        fig = Path(figures).expanduser()
        if fig.exists() and not fig.is_dir():
            raise OutputError(f"--figures {figures!r} is a file, not a folder")
        existing = next(f for f in (fig, *fig.absolute().parents) if f.exists())  # created if missing
        _check_writable(existing, f"--figures {figures!r}")


def _check_writable(folder: Path, said: str) -> None:
    """OutputError unless a file can be created in ``folder`` (tried: permission bits do not tell for root, ACLs
    or a read-only file system)."""
    from bouncelab.cli.reproduce import OutputError

    try:
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".bouncelab-probe-")
    except OSError as exc:
        raise OutputError(f"{said}: cannot create a file in the folder {str(folder)!r} "
                          f"({exc.strerror or exc}); nothing was tracked") from None
    os.close(fd)
    os.unlink(probe)


class _Slow(Exception):
    """A --pattern match that took longer than PATTERN_SECONDS."""


def _compile_pattern(pattern: str) -> re.Pattern[str]:
    """--pattern compiled once, with named groups that set something (UsageError otherwise)."""

    try:
        regex = re.compile(pattern)
    except (re.error, RecursionError, OverflowError) as exc:
        raise UsageError(f"--pattern {pattern!r} is not a regular expression: {exc}") from None
    unknown = sorted(set(regex.groupindex) - set(PATTERN_GROUPS))
    if unknown:
        raise UsageError(f"--pattern {pattern!r} has the group(s) {unknown}, which set nothing; the groups read are "
                         f"{', '.join(PATTERN_GROUPS)}, e.g. (?P<fps>\\d+)fps")
    if not regex.groupindex:
        raise UsageError(f"--pattern {pattern!r} has no named group, so it sets nothing; name groups among "
                         f"{', '.join(PATTERN_GROUPS)}, e.g. '(?P<setting>s\\d+)_r\\d+_(?P<fps>\\d+)fps'")
    return regex


def _check_pattern_time(regex: re.Pattern[str], clips: list[str], seconds: float | None = None,
                        in_process: bool | None = None) -> None:
    """Refuse (UsageError) a --pattern that takes longer than ``seconds`` on one of the clips' file names.

    Python's regular expressions backtrack: ``(a+)+$`` on a name of 40 a's would run for days. Each name is
    matched with a timer (SIGALRM interrupts the match, on the main thread of a POSIX system); elsewhere the
    names are matched in a child process that is stopped after ``seconds`` a name (plus its start-up).
    ``seconds`` defaults to PATTERN_SECONDS.
    """

    seconds = PATTERN_SECONDS if seconds is None else seconds
    names = [Path(c).name for c in clips]
    if in_process is None:
        in_process = hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
    try:
        if in_process:
            for k, name in enumerate(names):
                _search_with_timer(regex, name, seconds, k)
        else:
            _search_in_child(regex, names, seconds)
    except _Slow as slow:
        raise UsageError(f"--pattern {regex.pattern!r} takes longer than {seconds:g} s on the file name "
                         f"{names[slow.args[0]]!r} (catastrophic backtracking, e.g. a repeated group inside a repeated "
                         "group such as (a+)+); simplify it: match the name's parts literally, e.g. "
                         r"'(?P<setting>s\d+)_r\d+_(?P<fps>\d+)fps'") from None


def _search_with_timer(regex: re.Pattern[str], name: str, seconds: float, index: int) -> None:
    """Search ``name``; _Slow(index) if it takes over ``seconds`` (the timer's signal interrupts the match)."""
    def alarm(signum, frame):
        raise _Slow(index)

    previous = signal.signal(signal.SIGALRM, alarm)
    start = time.monotonic()
    old_delay, old_interval = signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        regex.search(name)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if old_delay > 0:  # a timer of the caller's (a test timeout...) goes on with the time it had left
            signal.setitimer(signal.ITIMER_REAL, max(old_delay - (time.monotonic() - start), 1e-3), old_interval)


#: Seconds a child Python is given to start, before it searches the names (the fallback of _search_in_child).
CHILD_START_SECONDS = 10.0
# Searches the names (NUL-separated on stdin) and prints the index of each as it is done.
_CHILD = ("import re, sys\nr = re.compile(sys.argv[1], int(sys.argv[2]))\n"
          "for k, name in enumerate(sys.stdin.read().split('\\0')):\n"
          "    r.search(name)\n    print(k, flush=True)\n")


def _search_in_child(regex: re.Pattern[str], names: list[str], seconds: float) -> None:
    """Search the names in a child Python, stopped after ``seconds`` a name (and CHILD_START_SECONDS); _Slow(index of
    the name it was on) when stopped. A child that cannot run leaves the names unchecked."""
    try:
        subprocess.run([sys.executable, "-I", "-c", _CHILD, regex.pattern, str(int(regex.flags))],
                       input="\0".join(names), capture_output=True, text=True, check=True,
                       timeout=CHILD_START_SECONDS + seconds * len(names))
    except subprocess.TimeoutExpired as exc:
        out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        raise _Slow(min(len(out.split()), len(names) - 1)) from None
    except (OSError, subprocess.CalledProcessError):
        return


def _fps_source(setting) -> str:
    """A clip's frame rate and where it came from, in the command line's words (``--fps 30``)."""
    if setting is None or setting.fps is None:
        return "the frame rate or frame times stored in the clip file"
    if setting.fps_source == "argument":
        return f"--fps {setting.fps:g}"
    where = "its file name (--pattern)" if setting.fps_source == "file name" else "the manifest (--manifest)"
    return f"{setting.fps:g} frames/s from {where}"


def _check_frame_rates(settings: dict) -> None:
    """A frame rate from the manifest or a file name within CAMERA_FPS_RANGE, or a DataError saying where from."""
    low, high = CAMERA_FPS_RANGE
    for clip, s in settings.items():
        if s.fps is not None and not low <= s.fps <= high:
            raise DataError(f"{_fps_source(s)} is not a camera's recording rate ({low:g} to {high:.0e} frames/s); "
                            f"{_FPS_HINT}", file=clip)


def _check_states(res, settings: dict, args: argparse.Namespace) -> None:
    """The unit guard of the tracked campaign, in the command line's words: speeds and spins measured from
    frames scale with the frame rate, so states that no golf bounce has mean a wrong --fps (or manifest or
    file-name rate)."""
    from bouncelab.core.plausibility import PLAUSIBLE_RANGES, implausibility

    ds = res.campaign
    why = implausibility(ds["landing"].values, ds["liftoff"].values, radius_m=float(ds.attrs["ball_radius_m"]),
                         ranges=PLAUSIBLE_RANGES, lower=True)
    if why is None:
        return
    clips = [str(c) for c in ds["clip"].values]
    at_fault = clips if why.row is None else [clips[why.row]]
    used = " and ".join(sorted({_fps_source(settings.get(c)) for c in at_fault}))
    if why.row is None:  # a lower limit, broken by the median of all the bounces: too few frames a second
        what, direction = f"the bounces measured in the {len(clips)} clip(s) are not golf bounces", "low"
    else:  # an upper limit, broken by one bounce: too many
        what, direction = f"the bounce measured in {Path(at_fault[0]).name} is not a golf bounce", "high"
    raise DataError(f"{what}: {why.reason}. Speeds and spins measured from frames scale with the frame rate, so "
                    f"the rate used ({used}) is likely too {direction}: {_FPS_HINT}; nothing written to {args.out}",
                    file=at_fault[0] if why.row is not None else None)


def run(args: argparse.Namespace) -> int:
    """Run ``bouncelab track``; returns the exit code."""
    from bouncelab.cli.reproduce import OutputError
    from bouncelab.data.io import save_campaign
    from bouncelab.tracking import FrameRateError, clip_settings, measure_clips
    from bouncelab.tracking.frames import CAMERA_SUFFIXES

    _check_outputs(args.out, args.figures)
    regex = _compile_pattern(args.pattern) if args.pattern is not None else None
    clips = expand_clips(args.clips)
    if args.fps is None and not args.manifest and regex is None \
            and not any(Path(c).suffix.lower() in (".npz", *CAMERA_SUFFIXES) for c in clips):
        missing = next((c for c in args.clips if not os.path.lexists(c)), None)
        if missing is not None:  # say that, not that a frame rate is needed (a missing clip among others is
            from bouncelab.core.errors import MissingFileError  # one failed clip, as any clip that cannot be read)

            raise MissingFileError("no such file or folder", file=missing)
        print("bouncelab track: --fps is needed: the frame rate is not in a manifest, a --pattern or the clips "
              "(.cine and .mraw files record it; e.g. --fps 5000)", file=sys.stderr)
        return EXIT_USAGE
    if not clips:
        print("bouncelab track: no clips found in the folders given", file=sys.stderr)
        return EXIT_DATA
    if regex is not None:
        _check_pattern_time(regex, clips)
    ppm = None if args.pixels_per_mm is None else args.pixels_per_mm * 1000.0
    try:
        settings = clip_settings(clips, fps=args.fps, ball_radius_m=args.ball_radius_mm / 1000.0,
                                 pixels_per_metre=ppm, manifest=args.manifest, pattern=regex)
    except FrameRateError as exc:  # the library says where the rate came from; the command line names its flag
        where = {"argument": "--fps", "manifest": "the manifest (--manifest)",
                 "file name": "its file name (--pattern)"}.get(exc.source, "the clip file")
        raise DataError(f"frame rate {exc.fps!r} from {where} is not a camera's recording rate; {_FPS_HINT}",
                        file=exc.file) from None
    _check_frame_rates(settings)
    bar = _Bar(len(clips), not args.quiet)
    res = measure_clips(clips, settings=settings, method=args.method, campaign=args.campaign, surface=args.surface,
                        data_kind="synthetic surrogate" if args.synthetic else "measured", progress=bar,
                        keep_tracks=False, figure_dir=args.figures, workers=args.jobs, plausible=None)
    n_ok = len(res.measurements)
    print(f"{n_ok} of {len(clips)} clip(s) measured", file=sys.stderr)
    if res.failures:
        print(f"{len(res.failures)} clip(s) failed:", file=sys.stderr)
        for f in res.failures:  # the error in the command line's words (its hints as flags)
            print(f"  {f.clip}: {f.reason if f.error is None else message(f.error)}", file=sys.stderr)
    if res.campaign is None:
        raise DataError(f"no clip could be measured (reasons above); nothing written to {args.out}")
    _check_states(res, settings, args)
    try:
        save_campaign(res.campaign, args.out)
    except OSError as exc:  # checked before tracking, but a folder can become read-only, a disk fill up
        raise OutputError(f"--out {args.out!r}: the {n_ok} bounce(s) measured are not saved: cannot write the file "
                          f"({exc.strerror or exc}); any previous file there is unchanged") from None
    print(f"campaign of {n_ok} bounce(s) written to {args.out}")
    if args.figures:
        print(f"diagnostic figures in {args.figures}")
    return EXIT_OK
