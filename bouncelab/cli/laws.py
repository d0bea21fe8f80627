"""How a command line names a law: by name, as ``module:Class``, or by a law JSON file; ``--import`` of user laws.

Shared by the commands that take a law (``fit``, ``predict``, ``reproduce --laws``, ``export``), so each
says the same thing about a law it cannot find.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
from pathlib import Path

from bouncelab.cli.messages import UsageError

__all__ = ["add_import_option", "import_modules", "law_argument", "laws_of_module", "named_law", "saved_law_name"]


def add_import_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--import", dest="imports", action="append", default=[], metavar="MODULE",
                   help="import a module that defines your own laws first (repeatable; the current folder is "
                        "searched, as by python -m), e.g. --import mylaws")




def import_modules(modules: list[str], law: str | None = None) -> None:
    """Import the modules a command line names (--import, or the module of a module:Class ``law``), searching
    the current folder first as ``python -m`` does, so that a user's laws register themselves.

    A module that is not there is told from one that is there but fails to import (its own import of a
    missing package, a syntax error): both are ParameterErrors naming the flag (or the law), the module and
    the folder searched."""
    import importlib
    import importlib.util

    from bouncelab.core.errors import ParameterError

    if modules and os.getcwd() not in sys.path:
        sys.path.insert(0, os.getcwd())
    for module in modules:
        said = f"--import {module}" if law is None else f"law {law!r}"
        how = "" if law is None else f" (a module:Class law imports its module, as --import {module} would)"
        if not re.fullmatch(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)*", module) or module.endswith(".py"):
            raise ParameterError(f"{said}: {module!r} is not a module name; write it as in an import statement "
                                 "(mylaws or lab.laws, without .py or a folder)")
        try:
            found = importlib.util.find_spec(module) is not None
        except ModuleNotFoundError:  # its package is missing
            found = False
        except Exception:
            found = True
        if not found:
            raise ParameterError(f"{said}: cannot import {module}: there is no module {module!r} in the current "
                                 f"folder ({os.getcwd()}) or the installed packages{how}; run bouncelab from the "
                                 f"folder that holds {module.split('.')[0]}.py, or check the name")
        try:
            importlib.import_module(module)
        except Exception as exc:
            raise ParameterError(f"{said}: the module {module!r} was found, but importing it failed: "
                                 f"{type(exc).__name__}: {exc}") from None


def laws_of_module(module: str) -> list[str]:
    """The bounce laws a module defines (module:Class names), from the registry."""
    from bouncelab.laws import law_name, registered_laws

    return sorted({law_name(c) for c in registered_laws().values() if c.__module__ == module})


def named_law(name: str):
    """The law a command line names: "rigid", "Rigid" and "RIGID" are one law; "pkg.module:Class" imports
    the module the user names (a law JSON file, by contrast, never imports code: use --import).

    A missing module (ParameterError naming --import and the current folder) is told from a module without
    that class (naming the laws the module does define)."""
    from bouncelab.core.errors import ParameterError
    from bouncelab.laws import law_class

    try:
        return law_class(name, case_sensitive=False)
    except ParameterError:
        if ":" not in name:
            raise
    module, _, cls = name.partition(":")
    import_modules([module], law=name)
    try:
        return law_class(name, case_sensitive=False)
    except ParameterError:
        defined = laws_of_module(module)
        listed = (f"it defines {', '.join(defined)}" if defined else
                  "it defines none (a bounce law is a class derived from bouncelab.BounceModel)")
        raise ParameterError(f"law {name!r}: module {module!r} was imported, but it defines no bounce law "
                             f"{cls!r}; {listed}") from None


def saved_law_name(path: str) -> str | None:
    """The law name a law JSON file holds ("law"), or None if it cannot be read as one."""
    from bouncelab.core.files import read_regular_text

    try:
        name = json.loads(read_regular_text(Path(path), path)).get("law")
    except (OSError, ValueError, AttributeError, RecursionError):  # (a DataError is a ValueError)
        return None
    return name if isinstance(name, str) else None


def law_argument(args: argparse.Namespace, example: str):
    """The law of ``predict`` or ``export``: published values of a named law (``args.law``, ``args.published``),
    or a law JSON file. A file naming a user's law whose module is not imported says to add --import (a law
    file never imports code). ``example`` ends the usage message's example command line."""
    from bouncelab.core.errors import ParameterError
    from bouncelab.laws import law_class, load_law

    if args.published:
        return named_law(args.law).published(args.published)
    if not (Path(args.law).suffix == ".json" or Path(args.law).exists()):
        raise UsageError(f"{args.law!r} is neither a law JSON file nor used with --published A|B "
                         f"(e.g. bouncelab {args.command} {args.law} --published A {example})")
    try:
        return load_law(args.law)
    except ParameterError:
        name = saved_law_name(args.law)
        if name is None or ":" not in name:
            raise
        try:
            law_class(name)
        except ParameterError:
            pass
        else:
            raise  # the law is known: the error is about something else (its parameters)
    module, _, cls = name.partition(":")
    if module == "__main__":  # saved from a script: the file cannot say which module to import
        tried = f" (--import {', '.join(args.imports)} defines no law {cls!r})" if args.imports else ""
        raise ParameterError(f"{args.law}: the law file names {name!r}, a law defined in a script run as the main "
                             f"program{tried}: give --import with the module that defines {cls} (the script's file "
                             "name without .py)") from None
    if module in sys.modules:
        defined = laws_of_module(module)
        listed = f"it defines {', '.join(defined)}" if defined else "it defines none"
        raise ParameterError(f"{args.law}: the law file names {name!r}, but module {module!r} (imported) defines no "
                             f"bounce law {cls!r}; {listed}") from None
    raise ParameterError(f"{args.law}: the law file names {name!r}, a law of your own, and a law file never imports "
                         f"code: add --import {module} (looked for in the current folder and the installed "
                         "packages)") from None
