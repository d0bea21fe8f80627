"""The error of an export that cannot be made."""

from __future__ import annotations

from bouncelab.core.errors import LawDefinitionError

__all__ = ["ExportError"]


class ExportError(LawDefinitionError):
    """A law that cannot be exported: its kernel uses a construct outside the translator's subset (see
    :mod:`bouncelab.export.frontend`), or one a language cannot express, or it has no compiled kernel at all.

    Attributes
    ----------
    law
        The law's name, when known.
    method
        ``"kernel"``.
    function
        The Python function at fault (qualified name), when the kernel's code is at fault.
    file, line
        Where in that function's source file.
    construct
        The construct refused (``"a list"``, ``"the operator //"``...).
    """

    def __init__(self, message: str = "", *, law: str | None = None, method: str | None = "kernel",
                 function: str | None = None, file: str | None = None, line: int | None = None,
                 construct: str | None = None) -> None:
        super().__init__(message, law=law, method=method)
        self.function = function
        self.file = file
        self.line = line
        self.construct = construct
