"""How the command line speaks: its exit codes, its own usage error, and the library's errors in its words.

The library's errors carry their facts as fields (the file, column and row of a :class:`DataError`, the
option a hint is about); the library words them in Python keywords. The command line words the same facts
with its flags (:func:`message`), so that no library module needs to know the command line exists.
"""

from __future__ import annotations

__all__ = ["EXIT_DATA", "EXIT_FIT", "EXIT_OK", "EXIT_PARTIAL", "EXIT_UNEXPECTED", "EXIT_USAGE", "UsageError"]

#: Exit codes: success, a bug, a bad command line or output, a bad data file, a law or fit that cannot be
#: done as asked, and (``reproduce``) a report written without some steps.
EXIT_OK, EXIT_UNEXPECTED, EXIT_USAGE, EXIT_DATA, EXIT_FIT, EXIT_PARTIAL = 0, 1, 2, 3, 4, 5


class UsageError(Exception):
    """A command line that cannot be run as given (exit code 2)."""
