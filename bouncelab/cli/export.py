"""``bouncelab export``: a law, or a surface's ground phase, as a self-contained C99 header, JavaScript ES
module or C# class.

``bouncelab export LAW.json --lang c -o law.h`` writes the law of a law file (``bouncelab fit
--save``, ``law.to_json``) with its values baked in; ``bouncelab export Rigid --published A --lang js``
the paper's published values of a law; ``--lang cs -o Law.cs`` a C# class for Unity, Godot or .NET.
``bouncelab export SURFACE.json --lang c -o surface.h`` (a file of ``Surface.to_json``) or
``bouncelab export --surface green-fast --lang cs`` (a preset) writes a surface's whole ground phase: the
3-D bounce and the run to rest, in SI units. Without ``-o`` the source goes to standard output. The work
is :func:`bouncelab.export.export_law`'s and :func:`bouncelab.export.export_surface`'s.
Exit codes: 0 written; 2 bad command line or an output that cannot be written; 3 a law file that
cannot be opened (missing, a folder); 4 a file that is not a law or a surface (not JSON, another JSON),
a law, preset or ``--import`` module that cannot be found, or a law that cannot be exported (no values,
a kernel the translator cannot read).
"""

from __future__ import annotations

import argparse
import sys

from bouncelab.cli.laws import add_import_option, law_argument
from bouncelab.cli.messages import EXIT_FIT, EXIT_OK, UsageError, message

__all__ = ["add_parser", "run"]

_WHAT = {"c": "C99 header", "js": "JavaScript ES module", "cs": "C# class"}


def add_parser(sub) -> argparse.ArgumentParser:
    """Register the ``export`` subcommand on ``sub`` (the main parser's subparsers)."""
    from bouncelab.export.names import DEFAULT_CLASS, DEFAULT_PREFIX, LANGUAGES

    p = sub.add_parser(
        "export", help="write a law, or a surface's ground phase, as a C99 header, a JavaScript module or a C# class",
        description="Translate a law's compiled kernel into C99 (a header; C++ compilers accept it), JavaScript "
                    "(an ES module) or C# (a static class that Unity, Godot and Mono compile), its values baked in, "
                    "its conventions, units, parameters and validity domain in the comment at the top. Entry "
                    "points: C bouncelab_predict(landing, liftoff, n) and bouncelab_predict_one(xdot, ydot, omega, "
                    "out); JavaScript predict(landings, out) on Float64Arrays and predictOne(xdot, ydot, omega, "
                    "out); C# Predict(landings, liftoffs) and PredictOne(xdot, ydot, omega, liftoff); scaled units "
                    "(radii/s, rad/s). A surface (a file of Surface.to_json, or --surface NAME for a preset) exports "
                    "its whole ground phase, bouncelab.ground's kernels with its law, friction and green speed baked "
                    "in: C bouncelab_bounce3d(v, w, n, v_out, w_out) and bouncelab_run(v, w, n, rest, &t_rest); "
                    "JavaScript bounce3d(v, w, n) and run(v, w, n); C# BouncelabSurface.Bounce3D and .Run; SI units "
                    "(m/s, rad/s, metres, seconds), z up.",
        epilog="Compile the C with -ffp-contract=off and without -ffast-math to get bouncelab's numbers (to 1e-12). "
               "A surface's run bakes in bouncelab.ground.run's defaults (min_apex_m 2 mm, max_bounces 100, no "
               "air). Exit codes: 0 written, 2 bad command line or output, 3 a law file that cannot be opened, 4 a "
               "file that is not a law or a surface, a law, preset or --import module not found, or a law that "
               "cannot be exported.",
    )
    p.add_argument("law", nargs="?", help="a law JSON file (from 'fit --save' or law.to_json; a law of your own needs "
                                          "--import), a law name with --published, or a surface JSON file (from "
                                          "Surface.to_json)")
    p.add_argument("--surface", metavar="NAME", default=None,
                   help="export a preset surface's ground phase, e.g. green-fast (see bouncelab.ground.preset)")
    p.add_argument("--published", metavar="A|B", type=str.upper, choices=["A", "B"],
                   help="export the paper's published values of the named law for campaign A or B")
    p.add_argument("--lang", required=True, choices=LANGUAGES,
                   help="c (a C99 header), js (an ES module) or cs (a C# class)")
    p.add_argument("-o", "--output", metavar="FILE", default="-",
                   help="file to write (e.g. law.h, law.mjs, Law.cs); '-' or none: standard output")
    p.add_argument("--prefix", default=None, metavar="NAME",
                   help=f"C only: the prefix of every name the header defines (default {DEFAULT_PREFIX}); give each "
                        "law of one program its own, e.g. --prefix turf_a_")
    p.add_argument("--class-name", default=None, metavar="NAME",
                   help=f"C# only: the static class's name (default {DEFAULT_CLASS}); give each law of one program "
                        "its own, e.g. --class-name TurfA")
    p.add_argument("--namespace", default=None, metavar="NAME",
                   help="C# only: the namespace of the class, e.g. Golf.Bounce (default: the global namespace)")
    add_import_option(p)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``bouncelab export``; returns the exit code (library errors reach the main command's handlers)."""
    from bouncelab.export import ExportError, export_law, export_surface

    if args.prefix is not None and args.lang != "c":
        raise UsageError("--prefix is for --lang c: an ES module's names are its own (import it under any name), "
                         "a C# class's are its members (give --class-name or --namespace)")
    for flag, value in (("--class-name", args.class_name), ("--namespace", args.namespace)):
        if value is not None and args.lang != "cs":
            raise UsageError(f"{flag} is for --lang cs" + (" (a C header's names take --prefix)"
                                                            if args.lang == "c" else ""))
    surface = _surface_argument(args)
    what = surface if surface is not None else law_argument(args, "--lang c -o law.h")
    to_stdout = args.output in ("-", "")
    options = {"c": {"prefix": args.prefix}, "js": {},
               "cs": {"class_name": args.class_name, "namespace": args.namespace}}[args.lang]
    try:
        if surface is not None:
            text = export_surface(surface, args.lang, None if to_stdout else args.output, **options)
        else:
            text = export_law(what, args.lang, None if to_stdout else args.output, **options)
    except ExportError as exc:
        print(f"bouncelab export: {message(exc)}", file=sys.stderr)
        return EXIT_FIT
    if to_stdout:
        sys.stdout.write(text)
    elif surface is not None:
        print(f"surface {surface.name!r} ({surface.law!r}) written to {args.output} ({_WHAT[args.lang]}: its ground "
              "phase, SI units)")
    else:
        print(f"{what!r} written to {args.output} ({_WHAT[args.lang]})")
    return EXIT_OK


def _surface_argument(args: argparse.Namespace):
    """The surface to export (``--surface NAME``, or a file written by ``Surface.to_json``), or None for a law."""
    import json
    from pathlib import Path

    from bouncelab.ground import load_surface, preset

    if args.surface is not None:
        if args.law is not None or args.published:
            raise UsageError("--surface NAME exports a preset surface: give no law (or law file) and no --published")
        return preset(args.surface)
    if args.law is None:
        raise UsageError("give a law file, a law name with --published, a surface file, or --surface NAME "
                         "(e.g. bouncelab export --surface green-fast --lang c -o surface.h)")
    path = Path(args.law)
    if args.published or not path.is_file():
        return None
    try:
        head = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        return None  # not JSON: the law reader says what is wrong with it
    if isinstance(head, dict) and "surface" in head:
        return load_surface(path)
    return None
