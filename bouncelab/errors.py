"""Exception types raised by bouncelab.

Every problem with user input is reported with one of these, never with a
silently wrong number. ``DataError`` is for data (arrays, files, campaigns);
``ParameterError`` for the parameters and bounds of a bounce law; ``OutputError``
for a file or folder that cannot be written.
"""

from __future__ import annotations

__all__ = [
    "BouncelabError",
    "BouncelabWarning",
    "DataError",
    "DroppedRowsWarning",
    "FitError",
    "LargeResultWarning",
    "NonphysicalLiftoffWarning",
    "NotFittedError",
    "OutputError",
    "ParameterError",
]


def row_text(row: int, label: object = None) -> str:
    """How messages name a 1-based row: ``row 3``, or with the caller's pandas index label
    ``row 3 (row label 'shot-2')`` (a NumPy scalar label printed as the plain number, 7 not np.int64(7))."""
    return f"row {row}" + ("" if label is None else f" (row label {plain_label(label)!r})")


def plain_label(label: object) -> object:
    """A pandas index label as Python has it: a NumPy scalar becomes its Python number or string."""
    item = getattr(label, "item", None)
    return item() if item is not None and type(label).__module__ == "numpy" else label


class BouncelabError(Exception):
    """Base class of every error bouncelab raises on purpose."""


class DataError(BouncelabError, ValueError):
    """Bad bounce data: the message names the file, column and row at fault.

    Attributes
    ----------
    file, column, row
        Where the problem is, when known (``row`` is 1-based: the first data
        row of a file or the first bounce of an array is row 1).
    row_label
        The row's label in the caller's pandas index, when the data came as a
        DataFrame (``row`` is still its 1-based position).
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        column: str | None = None,
        row: int | None = None,
        row_label: object = None,
    ) -> None:
        self.file = None if file is None else str(file)
        self.column = column
        self.row = row
        self.row_label = None if row_label is None else plain_label(row_label)
        where = []
        if self.file is not None:
            where.append(f"file {self.file!r}")
        if column is not None:
            where.append(f"column {column!r}")
        if row is not None:
            where.append(row_text(row, self.row_label))
        self.message = message
        super().__init__(f"{', '.join(where)}: {message}" if where else message)


class ParameterError(BouncelabError, ValueError):
    """A law parameter or a bound is missing, non-finite or outside its physical range."""


class NotFittedError(ParameterError):
    """The law has unset parameters: construct it with values or fit it first."""


class FitError(BouncelabError, ValueError):
    """A fit cannot be run as asked (too few bounces, empty class, bad option)."""


class LawDefinitionError(BouncelabError, TypeError):
    """A law class is written wrongly (a kernel that is not compiled, regime codes out of range)."""


class OutputError(BouncelabError, OSError, ValueError):
    """A file or folder bouncelab was asked to write cannot be written (a read-only or missing folder, a
    folder where a file should be, a full disk); nothing is left half-written.

    An ``OSError`` (what writing a file raises) and, as the command line's output error always was, a
    ``ValueError``. The ``bouncelab`` command exits with status 2 for it.

    Attributes
    ----------
    path
        The file or folder that could not be written, when known.
    errno
        The operating system's error number (``errno.EACCES``...), when one caused it.
    """

    def __init__(self, message: str, *, path: str | None = None, errno: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.path = None if path is None else str(path)
        if errno is not None:
            self.errno = errno  # str(self) stays the message: OSError formats only errno with strerror


class BouncelabWarning(UserWarning):
    """Base class of every warning bouncelab issues on purpose."""


class NonphysicalLiftoffWarning(BouncelabWarning):
    """A law with the paper's published values predicts lift-offs into the ground or gaining energy."""


class LargeResultWarning(BouncelabWarning):
    """A call builds a much larger result than needed (e.g. regime names for millions of landings)."""


class DroppedRowsWarning(BouncelabWarning):
    """``load_campaign(..., missing="drop")`` left out incomplete rows; the message lists them."""
