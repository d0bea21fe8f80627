"""``bouncelab`` command line.

Commands
--------
``bouncelab reproduce``  the paper's whole analysis: tables, fitted laws, figures, index.html
``bouncelab fit``        fit one law to a campaign and print the report (optionally save the law)
``bouncelab predict``    lift-off states from landing states, in any units
``bouncelab info``       what a campaign file (or the embedded default) or a camera clip (.cine, .mraw) holds
``bouncelab track``      high-speed clips of bounces to a campaign file (cli/track.py)
``bouncelab export``     a law as a C99 header or a JavaScript module (cli/export.py)

Exit codes: 0 success; 2 bad command line; 3 bad or missing data file; 4 a law or fit
that cannot be done as asked; 5 (``reproduce``) the report is written but partial: some
steps could not run on the data and were skipped, each with its reason in the report and
the run summary; 1 anything unexpected (a bug: please report it).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.cli.laws import add_import_option, import_modules, law_argument, named_law
from bouncelab.cli.messages import (
    EXIT_DATA,
    EXIT_FIT,
    EXIT_OK,
    EXIT_USAGE,
    UsageError,
    message,
)
from bouncelab.cli.options import finite, positive, whole

# A negative number on the command line, exponent and inf/nan included: argparse (before Python 3.13)
# only knows "-8" and "-8.5", so "--landing 1000 -8e2 200" read "-8e2" as an unknown option.
_NEGATIVE_NUMBER = re.compile(r"^-(?:\d[\d_]*(?:\.[\d_]*)?|\.\d[\d_]*)(?:[eE][-+]?\d+)?$|^-(?:inf|infinity|nan)$",
                              re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER





def _json_option(name: str, text: str | None, example: str) -> dict | None:
    """The JSON object an option holds; UsageError for malformed JSON or anything but an object."""
    if not text:
        return None
    try:
        value = json.loads(text)
    except json.JSONDecodeError as exc:
        raise UsageError(f"{name}: malformed JSON ({exc.msg} at character {exc.pos}); write e.g. {example}") from None
    except (ValueError, RecursionError) as exc:  # an integer of thousands of digits, nesting too deep
        raise UsageError(f"{name}: JSON that cannot be read ({exc}); write e.g. {example}") from None
    if not isinstance(value, dict):
        raise UsageError(f"{name} must be a JSON object, e.g. {example}; got {type(value).__name__} {text!r}")
    return value


def _load(source: str, args: argparse.Namespace):
    from bouncelab.data.io import load_campaign

    columns = _json_option("--columns", getattr(args, "columns", None),
                           '\'{"landing": ["vx0", "vy0", "w0"], "liftoff": ["vx1", "vy1", "w1"]}\'')
    units = {}
    if getattr(args, "velocity_unit", None):
        units["velocity"] = args.velocity_unit
    if getattr(args, "spin_unit", None):
        units["spin"] = args.spin_unit
    if getattr(args, "angle_unit", None):
        units["angle"] = args.angle_unit
    surrogate = {"surrogate": args.surrogate} if getattr(args, "surrogate", None) else {}
    # Loader options only when given, so an embedded campaign is loaded as before; its errors name their hints
    # as flags where they are printed (cli.messages.message).
    options = {key: getattr(args, key) for key in ("sheet", "header_row", "intervals")
               if getattr(args, key, None) is not None}
    return load_campaign(source, columns=columns, units=units or None, missing=getattr(args, "missing", "raise"),
                         **options, **surrogate)


def _add_data_options(p: argparse.ArgumentParser, missing: str = "raise") -> None:
    # the embedded surrogates' names, not the loader's module: building the parser (--help, --version) must not
    # import the loader, pandas and xarray
    from bouncelab.data.embedded import SURROGATES as EMBEDDED_SURROGATES

    p.add_argument("--columns", help='JSON column mapping, e.g. \'{"landing": ["vx0","vy0","w0"], '
                                      '"liftoff": ["vx1","vy1","w1"], "setting": "cond"}\'; a state given as '
                                      'speed, angle and spin: {"speed": "v_in", "angle": "a_in", "spin": "w_in"}')
    p.add_argument("--sheet", metavar="NAME", help="Excel sheet to read: its name, or a 0-based index if no sheet "
                                                   "has that name (default: the first visible sheet)")
    p.add_argument("--header-row", type=whole(1, "(a line number, counting from 1)"), metavar="N",
                   help="1-based line (text file) or row (Excel) of the header; lines above it are ignored "
                        "(default: the first line that is not a comment or a title)")
    p.add_argument("--missing", choices=("raise", "drop"), default=missing,
                   help="rows with an empty or NA cell: raise (an error naming the cell) or drop (leave them out, "
                        f"with a warning listing them); default {missing}")
    p.add_argument("--intervals", choices=("pi95", "sd"),
                   help="what the file's interval columns hold: pi95 (half-widths of 95 %% intervals) or sd (one "
                        "standard deviation, multiplied by 1.96); default: the names say (vx0_pi, vx0_sd), and "
                        "vx0_err or vx0_unc, which could be either, are refused until this says")
    p.add_argument("--velocity-unit", help="velocity unit of the file (m/s, ft/s, mph, km/h, radius/s)")
    p.add_argument("--spin-unit", help="spin unit of the file (rad/s, rpm, rev/s, deg/s)")
    p.add_argument("--angle-unit", choices=("deg", "rad"),
                   help="unit of the angles of a file giving speed, angle and spin (default deg, unless the header "
                        "says)")
    p.add_argument("--surrogate", choices=EMBEDDED_SURROGATES,
                   help="which synthetic surrogate the embedded campaigns A and B are: turf (default: simulated from "
                        "turf physics, the calibrated law of bouncelab.simulation.surrogate.TURF_CALIBRATION, through "
                        "camera frames) or published (made from the paper's published laws, so comparing the "
                        "paper's laws on it is circular); see docs/simulation.md")


def build_parser() -> argparse.ArgumentParser:
    from bouncelab.core import __version__

    parser = _Parser(
        prog="bouncelab",
        description="Golf-ball bounce laws: fit, compare and use them (Biber et al.'s analysis, reproducible).",
        epilog="Exit codes: 0 ok, 2 bad command line, 3 bad data file, 4 fit or law error, 5 reproduce wrote a "
               "partial report (steps skipped, reasons in the report), 1 unexpected.",
    )
    parser.add_argument("--version", action="version", version=f"bouncelab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    rep = sub.add_parser("reproduce", help="run the paper's whole analysis and write a report",
                         description="Fit the paper's four laws (and the beyond-the-paper ones), write tables "
                                     "(markdown, CSV), laws (JSON), figures (PNG) and index.html. A step that "
                                     "cannot run on the data (too few bounces for a law, one slip/roll class, "
                                     "no repeated launcher setting...) is skipped, with its reason in the report "
                                     "and the summary at the end; the rest is written.",
                         epilog="Exit codes: 0 complete report, 5 report written but partial (steps skipped), "
                                "2 bad command line or output folder, 3 bad data file, 4 bad law, 1 unexpected.")
    rep.add_argument("--campaign", nargs="+", default=None, metavar="A|B",
                     help="embedded campaigns to analyse (default: A B unless --data is given)")
    rep.add_argument("--data", nargs="+", default=[], metavar="FILE", help="bounce-data files to analyse")
    rep.add_argument("--label", nargs="+", default=None, metavar="NAME",
                     help="a name for each --data file (default: the file name); A or B puts the paper's "
                          "published values for that campaign beside the results")
    rep.add_argument("--out", default="report",
                     help="output folder (default: report): new, empty or a previous report, which is replaced "
                          "only once the new one is complete")
    rep.add_argument("--seed", type=int, default=0, help="seed of the split and of every fit")
    rep.add_argument("--no-figures", action="store_true", help="skip the figures (no matplotlib needed)")
    rep.add_argument("--figure-units", metavar="UNITS",
                     help="units of the figures' axes: scaled (default: radii/s, rad/s), si (m/s, rad/s), "
                          "lab (m/s, rpm), imperial (mph, rpm), or VELOCITY,SPIN such as ft/s,rev/s; "
                          "tables stay in scaled units")
    rep.add_argument("--quiet", action="store_true", help="no progress display")
    rep.add_argument("--laws", dest="law_set", nargs="+", default=None, metavar="LAW",
                     help="the laws to fit, compare and cross-validate, instead of the default (the paper's Rigid, "
                          "PennerVarying, PennerFixed, PiecewiseAffine and, beyond it, TangentialRestitution, "
                          "CompliantImpact, TurfContact): built-in names in any case or a user law's module:Class "
                          "(see --import); e.g. --laws Rigid PennerFixed")
    rep.add_argument("--law", dest="laws", action="append", default=[], metavar="LAW",
                     help="a further law to fit and compare beside those of --laws or the default (repeatable): a "
                          "built-in name or a user law's module:Class (see --import)")
    rep.add_argument("--bootstrap", type=whole(0, "resamples"), default=None, metavar="N",
                     help="resamples of the parameter bootstrap (default 100; 0 leaves it out)")
    add_import_option(rep)
    _add_data_options(rep, missing="drop")  # the report names every row it drops

    fit = sub.add_parser("fit", help="fit one law and print the fit report")
    fit.add_argument("law", help="Rigid, PennerFixed, PennerVarying, PiecewiseAffine, TangentialRestitution, "
                                 "CompliantImpact, TurfContact, CraterContact or a user law's module:Class "
                                 "(case-insensitive)")
    fit.add_argument("data", nargs="?", default="A", help="A, B (embedded) or a data file (default: A)")
    fit.add_argument("--method", help="a fitting method of the law: global (every law), structured (Rigid), "
                                      "plane (PiecewiseAffine's default) or svm (PiecewiseAffine)")
    fit.add_argument("--objective", default="delta", help="delta (default), xdot, ydot or omega")
    fit.add_argument("--algorithm", help="NLopt global algorithm: DIRECT_L, CRS2_LM, ISRES, ESCH, MLSL")
    fit.add_argument("--seed", type=int, default=0)
    fit.add_argument("--bounds", help='JSON bounds, e.g. \'{"mu": [0, 3]}\'')
    fit.add_argument("--save", metavar="FILE", help="write the fitted law as JSON")
    fit.add_argument("--json", action="store_true", help="print the result as JSON instead of a report")
    fit.add_argument("--option", dest="options", action="append", default=[], metavar="KEY=VALUE",
                     help="an option of the fitting method, VALUE as JSON or a bare word (repeatable), e.g. "
                          "--option maxeval=2000 --option svm_plane=hyperplane")
    add_import_option(fit)
    _add_data_options(fit)

    pred = sub.add_parser("predict", help="lift-off states from landing states",
                          description="Give landings as numbers (--landing, --speed-angle-spin) or a file of rows "
                                      "(--input), in the units you name; lift-offs are printed in the same units "
                                      "(as speed, angle and spin for a file that gives them so).")
    pred.add_argument("law", help="a law JSON file (from 'fit --save') or a law name with --published A|B")
    pred.add_argument("--published", metavar="A|B", type=str.upper, choices=["A", "B"],
                      help="use the paper's published values of the named law for campaign A or B")
    pred.add_argument("--landing", nargs=3, type=finite, action="append", metavar=("XDOT", "YDOT", "OMEGA"),
                      help="one landing state; repeat for more")
    pred.add_argument("--speed-angle-spin", nargs=3, type=finite, action="append", metavar=("SPEED", "ANGLE", "SPIN"),
                      help="one landing as speed, angle of incidence below the horizontal (deg unless --angle-unit "
                           "rad) and backspin")
    pred.add_argument("--input", metavar="FILE",
                      help="a text file of landings ('-': standard input): columns named xdot0, ydot0, omega0 or "
                           "speed, angle, spin, in any order, units in the header or a units row under it "
                           "(m/s,deg,rpm); without a header, three numbers a line: xdot0 ydot0 omega0")
    pred.add_argument("--velocity-unit", help="unit of velocities (default: an --input file's header, else radius/s)")
    pred.add_argument("--spin-unit", help="unit of spin (default: an --input file's header, else rad/s)")
    pred.add_argument("--angle-unit", choices=("deg", "rad"),
                      help="unit of angles of incidence (default: an --input file's header, else deg)")
    pred.add_argument("--radius-mm", type=positive, default=21.35, help="ball radius in mm (default 21.35)")
    add_import_option(pred)

    info = sub.add_parser("info", help="describe a campaign (embedded or a file) or a camera clip's header")
    info.add_argument("data", nargs="?", default=None,
                      help="A, B, a data file (default: both embedded), or a camera clip (.cine, .mraw)")
    _add_data_options(info)

    from bouncelab.cli.track import add_parser as add_track_parser  # implementation in cli/track.py

    add_track_parser(sub)
    from bouncelab.cli.export import add_parser as add_export_parser  # implementation in cli/export.py

    add_export_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``bouncelab`` command; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    import warnings

    with warnings.catch_warnings(), _interrupts_kept() as interrupted:  # (both restored when the command ends)
        _one_line_warnings(args.command)
        code = _run(args)
    if interrupted and code != 130:  # a Ctrl-C that a library swallowed (numba's compiler does): still 130
        print(f"bouncelab {args.command}: interrupted", file=sys.stderr)
        return 130
    return code


@contextlib.contextmanager
def _interrupts_kept() -> Iterator[list[int]]:
    """During the block, Ctrl-C (SIGINT) raises KeyboardInterrupt as usual and is also noted in the yielded
    list, so that an interrupt some library caught and dropped still ends the command with 130. Only where
    Python's own handler is installed, in the main thread."""
    import signal
    import threading

    noted: list[int] = []
    if threading.current_thread() is not threading.main_thread() or \
            signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        yield noted
        return

    def handler(signum: int, frame: Any) -> None:
        noted.append(signum)
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield noted
    finally:
        signal.signal(signal.SIGINT, previous)


def _run(args: argparse.Namespace) -> int:
    """Run one command; every user error becomes a message and an exit code (no traceback)."""
    # (only light imports before the try: a Ctrl-C during a command's own imports exits 130 too)
    from bouncelab.core.atomic import protect_inputs
    from bouncelab.core.errors import DataError, FitError, OutputError, ParameterError

    try:
        with protect_inputs(_input_files(args)):  # no output may replace a file the command reads
            if args.command == "track":
                from bouncelab.cli.track import run as run_track

                return run_track(args)
            import_modules(getattr(args, "imports", []))
            if args.command == "export":
                from bouncelab.cli.export import run as run_export

                return run_export(args)
            return {"reproduce": _reproduce, "fit": _fit, "predict": _predict, "info": _info}[args.command](args)
    except BrokenPipeError:
        # The reader went away (e.g. `bouncelab fit ... | head`): stop quietly, as Unix tools do.
        _stdout_to_devnull()
        return EXIT_OK
    except (UsageError, OutputError) as exc:
        print(f"bouncelab {args.command}: {message(exc)}", file=sys.stderr)
        return EXIT_USAGE
    except (DataError, OSError) as exc:  # OSError here is reading an input: writes are OutputErrors
        print(f"bouncelab {args.command}: data error: {_oneline(exc)}", file=sys.stderr)
        return EXIT_DATA
    except (FitError, ParameterError) as exc:
        print(f"bouncelab {args.command}: {message(exc)}", file=sys.stderr)
        return EXIT_FIT
    except ImportError as exc:
        print(f"bouncelab {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"bouncelab {args.command}: interrupted", file=sys.stderr)
        return 130


def _input_files(args: argparse.Namespace) -> list[str]:
    """The files a command reads (law files, data files, clips, a manifest), as given."""
    files: list[str] = []
    for key in ("law", "data", "input", "clips", "manifest"):
        value = getattr(args, key, None)
        files += [value] if isinstance(value, str) else [v for v in value or () if isinstance(v, str)]
    return files


def _stdout_to_devnull() -> None:
    """After a broken pipe: further output (and Python's flush at exit) goes nowhere instead of failing."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())


def _one_line_warnings(command: str) -> None:
    """bouncelab's own warnings as one line each on stderr, like the errors (no source line quoted)."""
    import warnings

    from bouncelab.core.errors import BouncelabWarning

    default = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, BouncelabWarning):
            print(f"bouncelab {command}: warning: {message}", file=sys.stderr)
        else:
            default(message, category, filename, lineno, file, line)

    warnings.showwarning = show


def _oneline(exc: BaseException) -> str:
    if isinstance(exc, OSError) and exc.strerror and exc.filename:
        return f"{exc.strerror}: {exc.filename!r}"
    return message(exc)



def _figure_units(text: str | None):
    """--figure-units: a preset name or VELOCITY,SPIN; checked now (exit 2), before any work."""
    if text is None:
        return None
    from bouncelab.core.errors import DataError
    from bouncelab.plots._common import figure_units

    parts = [p.strip() for p in text.split(",")]
    if len(parts) > 2:
        raise UsageError(f"--figure-units takes a preset or VELOCITY,SPIN (e.g. m/s,rpm); got {text!r}")
    spec = parts[0] if len(parts) == 1 else {"velocity": parts[0], "spin": parts[1]}
    try:
        return figure_units(spec)
    except DataError as exc:  # its hints are units= mappings: the flag takes VELOCITY,SPIN
        example = next((h.value for h in exc.hints if h.option == "units" and isinstance(h.value, dict)), None)
        said = "" if example is None else f"; e.g. --figure-units {example['velocity']},{example['spin']}"
        raise UsageError(f"--figure-units: {exc.message}{said}") from None


def _reproduce(args: argparse.Namespace) -> int:
    from bouncelab.cli.reproduce import reproduce, summarise

    campaigns = args.campaign if args.campaign is not None else ([] if args.data else ["A", "B"])
    labels = dict(zip(args.data, args.label or [], strict=False))
    if args.label is not None and len(args.label) != len(args.data):
        raise UsageError(f"give one --label per --data file: {len(args.data)} file(s), {len(args.label)} label(s)")

    if getattr(args, "surrogate", None) and not campaigns:
        raise UsageError(f"--surrogate {args.surrogate} names which embedded campaigns A and B are, but this run has "
                         "only --data files, which are loaded as they are; drop --surrogate or add --campaign A/B")

    # In a run with data files the file options (--columns, units, --sheet, --header-row, --intervals) are theirs,
    # not the embedded campaigns'; without data files they reach the loader, which refuses them for a campaign.
    file_options = ("columns", "velocity_unit", "spin_unit", "angle_unit", "sheet", "header_row", "intervals")
    embedded_args = argparse.Namespace(**{**vars(args), **({k: None for k in file_options} if args.data else
                                                             {"sheet": None, "header_row": None})})

    def load(src: str):
        # --surrogate names which embedded campaigns A and B are; data files are loaded as they are
        ds = _load(src, embedded_args if src in campaigns else argparse.Namespace(**{**vars(args), "surrogate": None}))
        return ds.assign_attrs(campaign=labels[src]) if src in labels else ds

    law_set = None if args.law_set is None else [named_law(name) for name in args.law_set]
    report = reproduce(
        campaigns=campaigns, data=args.data, out=args.out, seed=args.seed, figures=not args.no_figures,
        progress=not args.quiet, load=load, labels=labels, figure_units=_figure_units(args.figure_units),
        laws=[named_law(name) for name in args.laws], law_set=law_set, bootstrap=args.bootstrap,
    )
    return summarise(report, args.out)


def _method_options(items: list[str]) -> dict[str, Any]:
    """--option KEY=VALUE pairs: VALUE read as JSON (numbers, true/false, lists), else kept as text."""
    options: dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip().isidentifier():
            raise UsageError(f"--option takes KEY=VALUE, e.g. --option maxeval=2000; got {item!r}")
        try:
            options[key.strip()] = json.loads(value)
        except (ValueError, RecursionError):  # (not JSON, or an integer of thousands of digits: the text itself)
            options[key.strip()] = value
    return options


def _bounds(text: str | None) -> dict[str, tuple] | None:
    example = '\'{"mu": [0, 3]}\''
    raw = _json_option("--bounds", text, example)
    if raw is None:
        return None
    for name, pair in raw.items():
        if not (isinstance(pair, list) and len(pair) == 2):
            raise UsageError(f"--bounds: the bounds of {name!r} must be a [low, high] pair, e.g. {example}; "
                             f"got {json.dumps(pair)}")
    return {name: tuple(pair) for name, pair in raw.items()}


def _fit(args: argparse.Namespace) -> int:
    from bouncelab.cli.reproduce import OutputError, check_output_file
    from bouncelab.fitting import fit

    bounds = _bounds(args.bounds)
    if args.save:
        check_output_file(args.save, "--save", "law.json")  # before a possibly long fit
    data = _load(args.data, args)
    options = _method_options(args.options)
    if args.algorithm is not None:  # an option of the search methods
        options["algorithm"] = args.algorithm
    res = fit(named_law(args.law), data, method=args.method, objective=args.objective, seed=args.seed,
              bounds=bounds, **options)
    # The result is printed before the law is saved, so a failed save loses no work; a reader that went away
    # (`| head`) does not stop the save either.
    try:
        if args.json:
            print(json.dumps(res.to_dict(), indent=2, default=float), flush=True)
        else:
            print(res.report(), flush=True)
    except BrokenPipeError:
        if not args.save:
            raise
        _stdout_to_devnull()
    if args.save:
        try:
            res.model.to_json(args.save)  # atomic: a failed write leaves the previous file intact
        except OutputError as exc:  # (to_json's own, with the path and the reason)
            raise OutputError(f"the fit above is not saved: cannot write {args.save!r} ({exc.reason or exc}); any "
                              "previous file there is unchanged", path=exc.path, reason=exc.reason,
                              errno=getattr(exc, "errno", None)) from None
        if not args.json:
            print(f"law written to {args.save}")
    return EXIT_OK


#: What ``--input -`` reads: standard input, named so in messages.
STDIN_NAME = "<stdin>"


def _read_input(args: argparse.Namespace, radius: float):
    """The landings of ``--input`` (a file, or ``-`` for standard input), read by column name
    (bouncelab.data.io.landings.read_landings) in the units the header or the flags give."""
    from bouncelab.data.io.landings import read_landings
    from bouncelab.data.io.load import MAX_FILE_BYTES

    units = {kind: getattr(args, f"{kind}_unit") for kind in ("velocity", "spin", "angle")
             if getattr(args, f"{kind}_unit") is not None}
    if args.input == "-":
        data = sys.stdin.buffer.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            from bouncelab.core.errors import DataError

            raise DataError(f"standard input holds more than the {MAX_FILE_BYTES / 2**30:g} GiB bouncelab reads",
                            file=STDIN_NAME)
        return read_landings(STDIN_NAME, data=data, units=units, radius_m=radius)
    return read_landings(args.input, units=units, radius_m=radius)


def _output_units(args: argparse.Namespace, table) -> dict[str, str]:
    """The units landings typed on the command line are read in and every result is printed in: the flags',
    else those an --input file's header gives, else the scaled ones (radii/s, rad/s) and degrees. Typed
    landings beside a file whose header gives another unit are refused: one unit per kind for all."""
    from bouncelab.data.io.landings import DEFAULT_UNITS

    out = {}
    typed = [flag for flag, given in (("--landing", args.landing), ("--speed-angle-spin", args.speed_angle_spin))
             if given]
    for kind in ("velocity", "spin", "angle"):
        flag = getattr(args, f"{kind}_unit")
        header = table.units.get(kind) if table is not None and table.unit_origins.get(kind) == "header" else None
        if flag is not None:
            out[kind] = flag
        elif header is not None:
            if typed and header != DEFAULT_UNITS[kind] and (kind != "angle" or args.speed_angle_spin):
                raise UsageError(f"the header of --input {args.input} gives the {kind} in {header}, but "
                                 f"{' and '.join(typed)} has no --{kind}-unit (so {DEFAULT_UNITS[kind]}); give "
                                 f"--{kind}-unit {header} to read and print them all in {header}")
            out[kind] = header
        else:
            out[kind] = DEFAULT_UNITS[kind]
    return out


def _predict(args: argparse.Namespace) -> int:
    from bouncelab.core import units
    from bouncelab.core.errors import DataError

    law = law_argument(args, "--landing 1000 -800 200")
    radius = args.radius_mm / 1000.0
    table = _read_input(args, radius) if args.input else None
    out_units = _output_units(args, table)
    v, s, a = out_units["velocity"], out_units["spin"], out_units["angle"]
    chunks = []
    if args.landing:
        chunks.append(units.to_scaled(np.array(args.landing), velocity=v, spin=s, radius_m=radius))
    sas = None
    if args.speed_angle_spin:
        sas = np.array(args.speed_angle_spin)
        if a == "rad":
            sas[:, 1] = np.rad2deg(sas[:, 1])
        chunks.append(units.landing_from_speed_angle_spin(
            sas[:, 0], sas[:, 1], sas[:, 2], speed_unit=v, spin_unit=s, radius_m=radius))
    if table is not None:
        if table.form == "polar":  # the angle guard of --speed-angle-spin, for the file's angles too
            from bouncelab.core.plausibility import PLAUSIBLE_RANGES, landing_angle_error

            degrees = table.values[:, 1] if table.units["angle"] == "deg" else np.rad2deg(table.values[:, 1])
            low = landing_angle_error(degrees, PLAUSIBLE_RANGES)
            if low is not None:
                raise DataError(low[1], file=STDIN_NAME if args.input == "-" else args.input,
                                column=table.columns[1], row=low[0] + 1)
        chunks.append(table.states)
    if not chunks:
        raise DataError("give landings with --landing XDOT YDOT OMEGA, --speed-angle-spin or --input FILE")
    landing = np.vstack(chunks)
    # the unit guard, told the units the numbers were given in (and the typed angles in degrees)
    _check_landings(landing, argparse.Namespace(**{**vars(args), "velocity_unit": v, "spin_unit": s,
                                                   "speed_angle_spin": None if sas is None else sas.tolist()}), radius)
    liftoff = law.predict(landing, radius_m=radius)
    regimes = law.regime(landing, radius_m=radius)
    print(f"# law: {law!r}")
    if table is not None and table.form == "polar" and not args.landing:
        # Landings given as speed, angle and spin: lift-offs too, in the same units.
        p0 = units.polar_from_state(landing, kind="landing", speed_unit=v, spin_unit=s, radius_m=radius)
        pf = units.polar_from_state(liftoff, kind="liftoff", speed_unit=v, spin_unit=s, radius_m=radius)
        if a == "rad":
            p0[:, 1], pf[:, 1] = np.deg2rad(p0[:, 1]), np.deg2rad(pf[:, 1])
        print(f"# angle0 below the horizontal, angleF above it (beyond {90 if a == 'deg' else 'pi/2'}: the ball "
              "goes back)")
        print(f"# speed0[{v}] angle0[{a}] spin0[{s}] -> speedF[{v}] angleF[{a}] spinF[{s}] regime")
    else:
        p0 = units.from_scaled(landing, velocity=v, spin=s, radius_m=radius)
        pf = units.from_scaled(liftoff, velocity=v, spin=s, radius_m=radius)
        print(f"# xdot0[{v}] ydot0[{v}] omega0[{s}] -> xdotF[{v}] ydotF[{v}] omegaF[{s}] regime")
    for x0, xf, reg in zip(p0, pf, regimes, strict=True):
        print(" ".join(f"{x:.6g}" for x in (*x0, *xf)) + f" {reg}")
    return EXIT_OK


def _check_landings(landing: np.ndarray, args: argparse.Namespace, radius: float) -> None:
    """The unit guard of typed landings, in flags: each landing must be one a golf ball can make (the guard of
    the law's predict, bouncelab.core.plausibility.landing_error), else it is refused naming the landing, the
    limit and, from the error's hints, the --velocity-unit/--spin-unit the numbers look like."""
    from bouncelab.core.errors import DataError
    from bouncelab.core.plausibility import PLAUSIBLE_RANGES, landing_angle_error, landing_error
    from bouncelab.core.units import canonical_unit
    from bouncelab.core.validation import as_states

    if args.speed_angle_spin:  # angles <= 0 or > 90 were refused by the conversion
        angle = landing_angle_error(np.array(args.speed_angle_spin)[:, 1], PLAUSIBLE_RANGES)
        if angle is not None:
            raise DataError(f"--speed-angle-spin: {angle[1]}")
    landing, _ = as_states(landing, "landing", landing=True)  # shape and sign first: their own messages
    given = {"velocity": args.velocity_unit, "spin": args.spin_unit}
    error = landing_error(landing, radius_m=radius, ranges=PLAUSIBLE_RANGES, units=given)
    if error is None:
        return
    text = f"landing {error.row}" + (f", {error.column}" if error.column else "") + f": {error.message}"
    for hint in error.hints:
        if hint.option == "units":  # the flags of the units that change
            changed = {kind: unit for kind, unit in hint.value.items() if unit != canonical_unit(given[kind], kind)}
            text += (f": if they are {' and '.join(changed.values())}, give the unit with "
                     + " ".join(f"--{kind}-unit {unit}" for kind, unit in changed.items()))
    widen = next((h.value for h in error.hints if h.option == "plausible" and h.value != "None"), None)
    if widen is not None:  # the command line keeps the ranges: widening them is for Python
        text += (f"; if they are right, predict in Python with the law's predict(..., plausible={widen}) (the "
                 "command line keeps bouncelab's plausible ranges, bouncelab.core.plausibility.PLAUSIBLE_RANGES)")
    raise DataError(text)


def _info(args: argparse.Namespace) -> int:
    if args.data and Path(args.data).suffix.lower() in (".cine", ".mraw", ".cihx", ".cih"):
        from bouncelab.tracking import open_clip  # a camera clip: its header

        print(open_clip(args.data).describe())
        return EXIT_OK
    sources = [args.data] if args.data else ["A", "B"]
    for src in sources:
        ds = _load(src, args)
        print(describe(ds))
    return EXIT_OK


def describe(ds: Any) -> str:
    """A short text description of a campaign Dataset."""
    n = ds.sizes["bounce"]
    name = ds.attrs.get("campaign") or "(unnamed)"
    lines = [f"campaign {name!s}: {n} bounces, data kind: {ds.attrs.get('data_kind')}"]
    if ds.attrs.get("warning"):
        lines.append(f"  note: {ds.attrs['warning']}")
    lines.append(f"  surface: {ds.attrs.get('surface', '')}")
    lines.append(f"  source: {ds.attrs.get('source', '')}")
    if "setting" in ds.coords:
        counts = np.unique(ds["setting"].values, return_counts=True)[1]
        lines.append(f"  launcher settings: {len(counts)} (repeats per setting: {sorted(set(counts.tolist()))})")
    else:
        lines.append("  launcher settings: not recorded")
    for var in ("landing", "liftoff"):
        lo = ds[var].min("bounce").values
        hi = ds[var].max("bounce").values
        ranges = ", ".join(f"{c} [{a:.4g}, {b:.4g}]" for c, a, b in zip(("xdot", "ydot", "omega"), lo, hi, strict=True))
        lines.append(f"  {var}: {ranges} (radii/s, rad/s)")
    pis = [v for v in ("landing_pi", "liftoff_pi") if v in ds.data_vars]
    lines.append(f"  prediction intervals: {', '.join(pis) if pis else 'none'}")
    # how a lab file's intervals were read: they were converted on loading, so say from what
    for attr, label in (("interval_source", "read from"), ("interval_form", "form")):
        if ds.attrs.get(attr):
            lines.append(f"    {label}: {ds.attrs[attr]}")
    if ds.attrs.get("source_units"):
        lines.append(f"  source units: {ds.attrs['source_units']}")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
