"""Exception types raised by bouncelab.

Every problem with user input is reported with one of these, never with a
silently wrong number. ``DataError`` is for data (arrays, files, campaigns);
``ParameterError`` for the parameters and bounds of a bounce law; ``OutputError``
for a file or folder that cannot be written.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any, NamedTuple

__all__ = [
    "BouncelabError",
    "BouncelabWarning",
    "Code",
    "DataError",
    "DroppedRowsWarning",
    "FitError",
    "Hint",
    "LargeResultWarning",
    "MissingFileError",
    "NonphysicalLiftoffWarning",
    "NotFittedError",
    "OutputError",
    "OutsideFittedRangeWarning",
    "ParameterError",
    "SyntheticDataWarning",
    "UnknownLawError",
    "python_hint",
]


def row_text(row: int, label: object = None) -> str:
    """How messages name a 1-based row: ``row 3``, or with the caller's pandas index label
    ``row 3 (row label 'shot-2')`` (a NumPy scalar label printed as the plain number, 7 not np.int64(7))."""
    return f"row {row}" + ("" if label is None else f" (row label {plain_label(label)!r})")


def plain_label(label: object) -> object:
    """A pandas index label as Python has it: a NumPy scalar becomes its Python number or string."""
    item = getattr(label, "item", None)
    return item() if item is not None and type(label).__module__ == "numpy" else label


class Hint(NamedTuple):
    """What a person can change to put an error right: an option of the call, and a value to give it.

    Errors carry their hints as data; the edge words them. In Python (:func:`python_hint`) a hint is a
    keyword, ``units={'spin': 'rpm'}``; the command line words the same hint with its own flag
    (``--spin-unit rpm``, :mod:`bouncelab.cli.messages`).

    Attributes
    ----------
    option
        The keyword of the call (``"units"``, ``"columns"``, ``"missing"``, ``"header_row"``, ``"sheet"``,
        ``"intervals"``, ``"surrogate"``, ``"plausible"``, ...).
    value
        The value to give it, or None when the hint only names the option.
    note
        A few words on what the value means, e.g. ``"standard deviations, multiplied by 1.96"``.
    """

    option: str
    value: Any = None
    note: str = ""


class Code(str):
    """A hint's value that is Python code rather than a value, shown as written: ``Hint("plausible",
    Code("PLAUSIBLE_RANGES.widened(max_spin=...)"))`` reads ``plausible=PLAUSIBLE_RANGES.widened(max_spin=...)``,
    not a quoted string, also inside a mapping (``bounds={'mu': (low, high)}``). It equals the plain string of
    its text."""

    __slots__ = ()

    def __repr__(self) -> str:
        return str(self)


def python_hint(hint: Hint) -> str:
    """A hint in Python's words: ``units={'spin': 'rpm'}``, or ``plausible=...`` when it has no value."""
    text = f"{hint.option}=..." if hint.value is None else f"{hint.option}={hint.value!r}"
    return text + (f" ({hint.note})" if hint.note else "")


class BouncelabError(Exception):
    """Base class of every error bouncelab raises on purpose.

    Every bouncelab error carries its facts as attributes (the file, column and row of a
    :class:`DataError`, the law and parameter of a :class:`ParameterError`) and, in ``hints``, the
    options a person can change to put it right; ``str(error)`` words them for Python, and the
    command line words the same facts with its flags. Code and tests read the attributes, not the text.

    Attributes
    ----------
    message
        What is wrong, without where (the fields) and without the hints.
    hints
        :class:`Hint` s: the options that would put it right (alternatives).
    """

    def __init__(self, message: str = "", *, hints: Iterable[Hint] = ()) -> None:
        super().__init__(message)
        self.message = message
        self.hints = tuple(hints)

    def where(self) -> str:
        """Where the problem is, in words (empty for errors that have no place)."""
        return ""

    def render(self, speak: Callable[[Hint], str] = python_hint) -> str:
        """The error in words: where, what, and the hints worded by ``speak`` (Python keywords by default)."""
        where = self.where()
        text = f"{where}: {self.message}" if where else self.message
        if self.hints:
            text += "; " + ("pass " if speak is python_hint else "give ") + " or ".join(map(speak, self.hints))
        return text

    def __str__(self) -> str:
        return self.render()

    def __reduce__(self) -> tuple:  # keyword fields survive pickling (errors cross process boundaries)
        fields = {k: v for k, v in vars(self).items() if k != "message"}
        return _rebuild, (type(self), (self.message,), fields)


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
    option
        The argument of the call at fault (``"kind"``, ``"units"``, ``"tol"``, ``"settings"``...), when the
        problem is an argument rather than a place in the data; the message names it too.
    hints
        The options of the call that would put it right (:class:`Hint`).
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        column: str | None = None,
        row: int | None = None,
        row_label: object = None,
        option: str | None = None,
        hints: Iterable[Hint] = (),
    ) -> None:
        super().__init__(message, hints=hints)
        self.file = None if file is None else str(file)
        self.column = column
        self.row = row
        self.row_label = None if row_label is None else plain_label(row_label)
        self.option = option

    def where(self) -> str:
        where = []
        if self.file is not None:
            where.append(f"file {self.file!r}")
        if self.column is not None:
            where.append(f"column {self.column!r}")
        if self.row is not None:
            where.append(row_text(self.row, self.row_label))
        return ", ".join(where)


class MissingFileError(DataError, FileNotFoundError):
    """A file to read does not exist (``file`` names it): a :class:`DataError`, and a ``FileNotFoundError``
    as Python's own would be, so code catching either keeps working."""

    def __init__(self, message: str, *, file: str | None = None, hints: Iterable[Hint] = ()) -> None:
        super().__init__(message, file=file, hints=hints)
        self.errno = 2  # ENOENT, as the OSError it stands for
        self.strerror = message
        self.filename = self.file

    def __str__(self) -> str:
        return self.render()  # OSError would format errno and strerror instead

    def __reduce__(self) -> tuple:
        return _rebuild, (type(self), (self.message,), {"file": self.file, "hints": self.hints})


class ParameterError(BouncelabError, ValueError):
    """A law parameter, a bound or an option is missing, non-finite or outside its physical range.

    Attributes
    ----------
    law
        The law's name (:func:`bouncelab.laws.law_name`), when a law is concerned.
    parameter
        The parameter (or option, or array element such as ``"A1[0,2]"``) at fault, when one is.
    value
        The value that was refused, when there is one.
    """

    def __init__(self, message: str = "", *, law: str | None = None, parameter: str | None = None,
                 value: Any = None, hints: Iterable[Hint] = ()) -> None:
        super().__init__(message, hints=hints)
        self.law = law
        self.parameter = parameter
        self.value = value


class NotFittedError(ParameterError):
    """The law has unset parameters: construct it with values or fit it first (``missing`` lists them)."""

    def __init__(self, message: str = "", *, law: str | None = None, missing: Iterable[str] = (),
                 parameter: str | None = None, value: Any = None, hints: Iterable[Hint] = ()) -> None:
        super().__init__(message, law=law, parameter=parameter, value=value, hints=hints)
        self.missing = tuple(missing)


class UnknownLawError(ParameterError):
    """No bounce law is registered under a name (:func:`bouncelab.laws.law_class`, a law file).

    Attributes
    ----------
    law_name
        The name asked for (``"Rigid"``, ``"mylaws:MyLaw"``).
    module, qualname
        For a ``module:QualName`` name, its two parts (None for a short name).
    module_imported
        Whether ``module`` is imported in this process: False means "import it first", True
        means the module is there but defines no such law.
    script
        The file of the script that defined the law, when a law file says it was defined in a
        script run as ``__main__`` (None otherwise).
    """

    def __init__(self, message: str, *, law_name: str, module: str | None = None, qualname: str | None = None,
                 module_imported: bool = False, script: str | None = None) -> None:
        super().__init__(message, law=law_name)
        self.law_name = law_name
        self.module = module
        self.qualname = qualname
        self.module_imported = module_imported
        self.script = script

    def __reduce__(self) -> tuple:  # keyword fields survive pickling (errors cross process boundaries)
        return _rebuild, (type(self), self.args, {"law_name": self.law_name, "module": self.module,
                                                  "qualname": self.qualname, "module_imported": self.module_imported,
                                                  "script": self.script})


class FitError(BouncelabError, ValueError):
    """A fit cannot be run as asked (too few bounces, empty class, bad option, a result outside its bounds).

    Attributes
    ----------
    law
        The law being fitted, when known.
    option
        The option of the call at fault (``"method"``, ``"bounds"``, ``"k"``, ``"maxeval"``...), when one is.
    """

    def __init__(self, message: str = "", *, law: str | None = None, option: str | None = None,
                 hints: Iterable[Hint] = ()) -> None:
        super().__init__(message, hints=hints)
        self.law = law
        self.option = option


class LawDefinitionError(BouncelabError, TypeError):
    """A law class is written wrongly (a kernel that is not compiled, regime codes out of range, a result of
    the wrong shape); ``law`` names the class and ``method`` the method at fault (``"_predict"``...)."""

    def __init__(self, message: str = "", *, law: str | None = None, method: str | None = None,
                 hints: Iterable[Hint] = ()) -> None:
        super().__init__(message, hints=hints)
        self.law = law
        self.method = method


class OutputError(BouncelabError, OSError, ValueError):
    """A file or folder bouncelab was asked to write cannot be written (a read-only or missing folder, a
    folder where a file should be, a full disk); nothing is left half-written: a file already at the path
    is unchanged.

    An ``OSError`` (what writing a file raises, so code that catches ``OSError`` around a write still
    does) and, as the command line's output error always was, a ``ValueError``. The ``bouncelab``
    command exits with status 2 for it.

    Attributes
    ----------
    path
        The file or folder that could not be written, when known.
    reason
        Why, in words (the operating system's reason, e.g. ``"Permission denied"``), when known.
    errno
        The operating system's error number (``errno.EACCES``...), when one caused it.
    """

    def __init__(self, message: str, *, path: str | None = None, reason: str | None = None,
                 errno: int | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.path = None if path is None else str(path)
        self.reason = reason
        self.filename = self.path  # as an OSError has them
        self.strerror = reason
        if errno is not None:
            self.errno = errno

    def __str__(self) -> str:
        return self.message  # OSError would format errno and strerror instead

    def __reduce__(self) -> tuple:
        return _rebuild, (type(self), (self.message,), {"path": self.path, "reason": self.reason,
                                                        "errno": getattr(self, "errno", None)})


def _rebuild(cls: type, args: tuple, fields: dict) -> BaseException:
    return cls(*args, **fields)


class BouncelabWarning(UserWarning):
    """Base class of every warning bouncelab issues on purpose."""


class NonphysicalLiftoffWarning(BouncelabWarning):
    """A law with the paper's published values predicts lift-offs into the ground or gaining energy."""


class LargeResultWarning(BouncelabWarning):
    """A call builds a much larger result than needed (e.g. regime names for millions of landings)."""


class DroppedRowsWarning(BouncelabWarning):
    """``load_campaign(..., missing="drop")`` left out incomplete rows; the message lists them."""


class SyntheticDataWarning(BouncelabWarning):
    """A law read from a file was fitted to synthetic bounces (a surrogate or a simulation), not to measurements."""


class OutsideFittedRangeWarning(BouncelabWarning):
    """``predict(..., warn_outside_fitted=True)``: some landings lie outside those the law was fitted on."""
