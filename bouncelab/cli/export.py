"""``bouncelab export``: a law as a self-contained C99 header, JavaScript ES module or C# class.

``bouncelab export LAW.json --lang c -o law.h`` writes the law of a law file (``bouncelab fit
--save``, ``law.to_json``) with its values baked in; ``bouncelab export Rigid --published A --lang js``
the paper's published values of a law; ``--lang cs -o Law.cs`` a C# class for Unity, Godot or .NET.
Without ``-o`` the source goes to standard output. The work is :func:`bouncelab.export.export_law`'s.
Exit codes: 0 written; 2 bad command line or an output that cannot be written; 3 a law file that
cannot be opened (missing, a folder); 4 a file that is not a law (not JSON, another JSON), a law or
``--import`` module that cannot be found, or a law that cannot be exported (no values, a kernel the
translator cannot read).
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
    from bouncelab.export import DEFAULT_CLASS, DEFAULT_PREFIX, LANGUAGES

    p = sub.add_parser(
        "export", help="write a law as a C99 header, a JavaScript module or a C# class",
        description="Translate a law's compiled kernel into C99 (a header; C++ compilers accept it), JavaScript "
                    "(an ES module) or C# (a static class that Unity, Godot and Mono compile), its values baked in, "
                    "its conventions, units, parameters and validity domain in the comment at the top. Entry "
                    "points: C bouncelab_predict(landing, liftoff, n) and bouncelab_predict_one(xdot, ydot, omega, "
                    "out); JavaScript predict(landings, out) on Float64Arrays and predictOne(xdot, ydot, omega, "
                    "out); C# Predict(landings, liftoffs) and PredictOne(xdot, ydot, omega, liftoff); scaled units "
                    "(radii/s, rad/s).",
        epilog="Compile the C with -ffp-contract=off and without -ffast-math to get bouncelab's numbers (to 1e-12). "
               "Exit codes: 0 written, 2 bad command line or output, 3 a law file that cannot be opened, 4 a file "
               "that is not a law, a law or --import module not found, or a law that cannot be exported.",
    )
    p.add_argument("law", help="a law JSON file (from 'fit --save' or law.to_json; a law of your own needs --import), "
                               "or a law name with --published")
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
    from bouncelab.export import ExportError, export_law

    if args.prefix is not None and args.lang != "c":
        raise UsageError("--prefix is for --lang c: an ES module's names are its own (import it under any name), "
                         "a C# class's are its members (give --class-name or --namespace)")
    for flag, value in (("--class-name", args.class_name), ("--namespace", args.namespace)):
        if value is not None and args.lang != "cs":
            raise UsageError(f"{flag} is for --lang cs" + (" (a C header's names take --prefix)"
                                                            if args.lang == "c" else ""))
    law = law_argument(args, "--lang c -o law.h")
    to_stdout = args.output in ("-", "")
    options = {"c": {"prefix": args.prefix}, "js": {},
               "cs": {"class_name": args.class_name, "namespace": args.namespace}}[args.lang]
    try:
        text = export_law(law, args.lang, None if to_stdout else args.output, **options)
    except ExportError as exc:
        print(f"bouncelab export: {message(exc)}", file=sys.stderr)
        return EXIT_FIT
    if to_stdout:
        sys.stdout.write(text)
    else:
        print(f"{law!r} written to {args.output} ({_WHAT[args.lang]})")
    return EXIT_OK
