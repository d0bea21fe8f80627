"""One emitter per language: each prints a :class:`~bouncelab.export.ir.Program` and nothing else.

:class:`~bouncelab.export.emit.c.CEmitter` (C99, which C++ compilers accept),
:class:`~bouncelab.export.emit.js.JSEmitter` (an ES module's functions) and
:class:`~bouncelab.export.emit.cs.CSharpEmitter` (C# 7.3 or older) share the statement and expression
printer of :class:`~bouncelab.export.emit.base.Emitter`; each adds its names, types, literals, math
functions and its way of returning several values. A new language is a new emitter: the front end
(:mod:`bouncelab.export.frontend`) and the intermediate form stay as they are.
"""

from __future__ import annotations

from bouncelab.export.emit.base import Emitter
from bouncelab.export.emit.c import CEmitter
from bouncelab.export.emit.cs import CSharpEmitter
from bouncelab.export.emit.js import JSEmitter

__all__ = ["EMITTERS", "CEmitter", "CSharpEmitter", "Emitter", "JSEmitter"]

#: The emitter of each language, by the name ``bouncelab export --lang`` takes.
EMITTERS: dict[str, type[Emitter]] = {"c": CEmitter, "js": JSEmitter, "cs": CSharpEmitter}
