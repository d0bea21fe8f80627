"""Which law is which: the names laws are known by, the registry of law classes, finding a class by name.

Every concrete law class registers itself when it is defined. bouncelab's own laws are known by their
class names (``"Rigid"``), anybody else's by ``module:QualName``; a class defined in a script run as
``__main__`` is named by the module that imports the script, so that a law file written by the
script loads wherever that module is imported (:func:`law_name`, :func:`law_class`).
"""

from __future__ import annotations

import keyword
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from bouncelab.core.errors import ParameterError, UnknownLawError

if TYPE_CHECKING:
    from bouncelab.laws.interface import Law

__all__ = ["MAIN_MODULES", "is_builtin", "law_class", "law_name", "register", "registered_laws", "script_module"]

_REGISTRY: dict[str, type[Law]] = {}
_REGISTRY_LOCK = threading.Lock()


def is_builtin(cls: type) -> bool:
    return cls.__module__ == "bouncelab" or cls.__module__.startswith("bouncelab.")


#: Module names under which Python runs a script (``python myscript.py``; multiprocessing's workers).
MAIN_MODULES = ("__main__", "__mp_main__")


def script_module(cls: type) -> tuple[str | None, str | None]:
    """For a class defined in a script run as ``__main__``: the module name that imports that script
    (``"myscript"`` for ``python myscript.py``, ``"pkg.tool"`` for ``python -m pkg.tool``) and the
    script's file; ``(None, file or None)`` when no module name would import it (a notebook, a
    file name that is not an identifier). ``(None, None)`` for a class of an ordinary module."""
    if cls.__module__ not in MAIN_MODULES:
        return None, None
    mod = sys.modules.get(cls.__module__)
    if mod is None or getattr(mod, cls.__qualname__.split(".")[0], None) is None:
        return None, None  # __main__ is not the script that defined it (an interactive shell's launcher)
    file = getattr(mod, "__file__", None)
    file = None if file is None else str(Path(file).resolve())
    spec_name = getattr(getattr(mod, "__spec__", None), "name", None)
    if spec_name and spec_name not in MAIN_MODULES:
        return spec_name, file
    if file is not None:
        stem = Path(file).stem
        if stem.isidentifier() and not keyword.iskeyword(stem):
            return stem, file
    return None, file


def law_name(cls: type[Law] | Law) -> str:
    """The name a law is known by: the class name for bouncelab's own laws, ``module:QualName`` otherwise.

    A class defined in a script run as ``__main__`` (``python myscript.py``) is named by the
    module that imports the script (``myscript:MyLaw``): the name under which it is registered
    in any process that imports ``myscript``, so that a law file written by the script loads
    there. In a notebook (no script file) it stays ``__main__:MyLaw``.
    """
    cls = cls if isinstance(cls, type) else type(cls)
    if is_builtin(cls):
        return cls.__name__
    module = script_module(cls)[0] or cls.__module__
    return f"{module}:{cls.__qualname__}"


def registered_laws() -> dict[str, type[Law]]:
    """Every concrete law class known, by :func:`law_name`; user laws also by class name when unambiguous."""
    with _REGISTRY_LOCK:
        classes = list(_REGISTRY.values())
    out = {law_name(c): c for c in classes}
    short: dict[str, list[type[Law]]] = {}
    for c in classes:
        short.setdefault(c.__name__, []).append(c)
    for name, cands in short.items():
        if name not in out and len(cands) == 1:
            out[name] = cands[0]
    return out


def law_class(name: str, *, case_sensitive: bool = True, script: str | None = None) -> type[Law]:
    """The law class known by ``name`` (see :func:`law_name`).

    A short name always means bouncelab's own law of that name, never a user's
    class that happens to share it. A short name that only user classes carry is
    accepted when exactly one does. A ``module:QualName`` is the class of that
    module, or the class of a script run as ``__main__`` that ``module`` names
    (see :func:`law_name`); ``__main__:QualName`` (how a script's laws were named
    before, and still are in a notebook) is the one registered user class of that
    qualified name, whatever its module.

    Parameters
    ----------
    name
        The law's name.
    case_sensitive
        Whether the spelling must match exactly (the command line is not).
    script
        The file of the script that defined the law, if a law file says so: it is named in
        the error, and among several classes of that qualified name it picks the one
        defined in that file.

    Raises
    ------
    UnknownLawError
        (a ParameterError) No law of that name is registered: the error says what to import,
        and carries ``law_name``, ``module``, ``qualname``, ``module_imported``, ``script``.
    ParameterError
        A short name shared by several user classes, or a ``__main__`` name that several
        registered classes could be (listing their qualified names).
    """
    if not isinstance(name, str) or not name:
        raise ParameterError(f"a law name must be a non-empty string; got {name!r}", value=name)
    if not case_sensitive:
        try:  # the exact spelling wins over laws whose names differ from it only in case
            return law_class(name, case_sensitive=True, script=script)
        except UnknownLawError:
            pass
    with _REGISTRY_LOCK:
        classes = list(_REGISTRY.values())

    def same(a: str, b: str) -> bool:
        return a == b if case_sensitive else a.lower() == b.lower()

    if ":" in name:
        return _qualified_class(name, classes, same, script)
    builtin = [c for c in classes if is_builtin(c) and same(c.__name__, name)]
    if len(builtin) == 1:
        return builtin[0]
    users = [c for c in classes if not is_builtin(c) and same(c.__name__, name)]
    if len(users) == 1 and not builtin:
        return users[0]
    if len(builtin) + len(users) > 1:
        cands = sorted(f"{c.__module__}:{c.__qualname__}" for c in builtin + users)
        raise ParameterError(f"the law name {name!r} is ambiguous; use one of the qualified names {cands}", law=name)
    known = sorted(law_name(c) for c in classes)
    raise UnknownLawError(f"unknown law {name!r}; known laws: {known}", law_name=name)


def _qualified_class(name: str, classes: list[type[Law]], same: Callable[[str, str], bool],
                     script: str | None) -> type[Law]:
    """The class of a ``module:QualName`` name (see :func:`law_class`)."""
    module, _, qualname = name.partition(":")
    hits = [c for c in classes if same(f"{c.__module__}:{c.__qualname__}", name)]
    if not hits:  # a script's class, named by the module that imports the script
        hits = [c for c in classes if c.__module__ in MAIN_MODULES and same(law_name(c), name)]
    if not hits and module in MAIN_MODULES:  # a script's or a notebook's law, wherever its class lives now
        hits = [c for c in classes if not is_builtin(c) and same(c.__qualname__, qualname)]
        if len(hits) > 1 and script is not None:
            from_script = [c for c in hits if _defined_in(c, script)]
            hits = from_script if len(from_script) == 1 else hits
    if len(hits) == 1:
        return hits[0]
    if len(hits) > 1:
        cands = sorted(f"{c.__module__}:{c.__qualname__}" for c in hits)
        raise ParameterError(f"the law name {name!r} is ambiguous: several registered laws could be it, "
                             f"{cands}; load the law in a process that imports only one of them", law=name)
    imported = module in sys.modules
    if module in MAIN_MODULES:
        where = f"in the script {script}" if script else "in a script or notebook run as __main__"
        stem = Path(script).stem if script else None
        how = (f"import that script's module first (import {stem})" if stem and stem.isidentifier()
               else "import (or define) the module that defines it first")
        msg = (f"unknown law {name!r}: no bounce law named {qualname!r} is registered in this process; it was "
               f"defined {where}; {how} (a law description never imports code)")
    elif imported:
        laws = sorted(law_name(c) for c in classes if c.__module__ == module)
        msg = (f"unknown law {name!r}: the module {module!r} is imported but defines no bounce law {qualname!r} "
               f"(its laws: {laws})")
    else:
        script_note = f" (the script {script})" if script else ""
        msg = (f"unknown law {name!r}: no bounce law is registered as {name!r} in this process; import the module "
               f"that defines it first (import {module}{script_note}; a law description never imports code)")
    raise UnknownLawError(msg, law_name=name, module=module, qualname=qualname, module_imported=imported,
                          script=script)


def _defined_in(cls: type, script: str) -> bool:
    """Whether ``cls`` comes from the file ``script``."""
    file = getattr(sys.modules.get(cls.__module__), "__file__", None)
    try:
        return file is not None and Path(file).resolve() == Path(script).resolve()
    except (OSError, ValueError):
        return False


def register(cls: type[Law]) -> None:
    """Make a concrete law class known by its names (called when the class is defined)."""
    with _REGISTRY_LOCK:
        _REGISTRY[f"{cls.__module__}:{cls.__qualname__}"] = cls
