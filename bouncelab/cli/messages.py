"""How the command line speaks: its exit codes, its own usage error, and the library's errors in its words.

The library's errors carry their facts as fields (the file, column and row of a :class:`DataError`, the
option a hint is about); the library words them in Python keywords. The command line words the same facts
with its flags (:func:`message`), so that no library module needs to know the command line exists.
"""

from __future__ import annotations

import json

from bouncelab.core.errors import BouncelabError, Code, Hint, python_hint

__all__ = ["EXIT_DATA", "EXIT_FIT", "EXIT_OK", "EXIT_PARTIAL", "EXIT_UNEXPECTED", "EXIT_USAGE", "UsageError",
           "flag_hint", "message"]

#: Exit codes: success, a bug, a bad command line or output, a bad data file, a law or fit that cannot be
#: done as asked, and (``reproduce``) a report written without some steps.
EXIT_OK, EXIT_UNEXPECTED, EXIT_USAGE, EXIT_DATA, EXIT_FIT, EXIT_PARTIAL = 0, 1, 2, 3, 4, 5


class UsageError(Exception):
    """A command line that cannot be run as given (exit code 2)."""


# The library's options, as the command line's flags.
_FLAGS = {"columns": "--columns", "sheet": "--sheet", "missing": "--missing", "header_row": "--header-row",
          "intervals": "--intervals", "surrogate": "--surrogate", "fps": "--fps", "seed": "--seed",
          "bounds": "--bounds", "method": "--method", "objective": "--objective", "manifest": "--manifest",
          "pattern": "--pattern", "algorithm": "--algorithm", "law_set": "--laws", "bootstrap": "--bootstrap",
          "figure_units": "--figure-units"}
_UNIT_FLAGS = {"velocity": "--velocity-unit", "spin": "--spin-unit", "angle": "--angle-unit"}


def flag_hint(hint: Hint) -> str:
    """A hint in the command line's words: ``--spin-unit rpm``, ``--missing drop``, ``--columns '{...}'``.

    An option the command line has no flag for is named as the Python keyword it is
    (``plausible=... (in Python)``), so the advice is never lost.
    """
    option, value = hint.option, hint.value
    note = f" ({hint.note})" if hint.note else ""
    if option == "units" and isinstance(value, dict) and set(value) <= set(_UNIT_FLAGS):
        return " ".join(f"{_UNIT_FLAGS[kind]} {unit}" for kind, unit in value.items()) + note
    if option == "columns" and value is not None:
        return "--columns '" + json.dumps(value) + "'" + note
    if option == "bounds" and isinstance(value, dict):  # JSON pairs; a placeholder "(low, high)" as [low, high]
        pairs = (f"{json.dumps(str(k))}: " + ("[" + str(v).strip("()") + "]" if isinstance(v, Code)
                                              else json.dumps(list(v))) for k, v in value.items())
        return "--bounds '{" + ", ".join(pairs) + "}'" + note
    if option in _FLAGS:
        words = " ".join(map(str, value)) if isinstance(value, list | tuple) else str(value)  # nargs="+"
        return _FLAGS[option] + ("" if value is None else f" {words}") + note
    return python_hint(hint) + " (in Python)"


def message(exc: BaseException) -> str:
    """A library error in the command line's words: its facts, and its hints as flags."""
    if isinstance(exc, BouncelabError):
        return exc.render(flag_hint)
    return str(exc)
