"""Laws and surfaces outside Python: a fitted law, or a surface's whole ground phase, as a self-contained C99
header, JavaScript ES module or C# class.

>>> import bouncelab as bl
>>> from bouncelab.export import to_c, to_cs, to_js
>>> header = to_c(bl.Rigid.published("A"))          # or to_c(law, "rigid_A.h"), bouncelab export
>>> "void bouncelab_predict(const double *landing, double *liftoff, long n)" in header
True
>>> module = to_js(bl.Rigid.published("A"))         # export function predict(landings, out), predictOne(...)
>>> "public static class BouncelabLaw" in to_cs(bl.Rigid.published("A"))
True

The code is the law's own numba kernel translated operation by operation: the front end
(:mod:`bouncelab.export.frontend`, which documents the Python subset it reads) turns the kernel into
one small intermediate form (:mod:`bouncelab.export.ir`: typed scalar functions), and one emitter per
language (:mod:`bouncelab.export.emit`) prints it. The law's values are baked in; the file's top
comment gives the law, its conventions and units, its parameters and its validity domain, and how to
compile it so that its results agree with bouncelab's to 1e-12 of the landing's norm.

A surface (:class:`bouncelab.ground.Surface`, or a preset's name) exports the same way, its ground
phase whole: :func:`export_surface` (``bouncelab export SURFACE.json``) translates the kernels of
:mod:`bouncelab.ground` (the 3-D bounce, and the run from the landing to rest) with the surface's
values baked in, in SI units (:mod:`bouncelab.export.ground`).

>>> "int bouncelab_run(const double v[3]" in export_surface("green-fast", "c")
True

This package sits above the laws and the ground phase (it imports them; they do not import it) and is
the only one that imports both them and the emitters.
"""

from __future__ import annotations

import importlib
from typing import Any

from bouncelab.export.names import (
    DEFAULT_CLASS,
    DEFAULT_PREFIX,
    DEFAULT_SURFACE_CLASS,
    DEFAULT_SURFACE_PREFIX,
    LANGUAGES,
)

# The translator is imported on first use (PEP 562): the command line's parser reads only the names above.
_LAZY = {"ExportError": "errors", **dict.fromkeys(("REFUSALS", "export_surface", "surface_c", "surface_cs",
                                                   "surface_js"), "ground"),
         **dict.fromkeys(("c_header", "cs_class", "export_law", "js_module", "to_c", "to_cs", "to_js"), "law")}

__all__ = ["DEFAULT_CLASS", "DEFAULT_PREFIX", "DEFAULT_SURFACE_CLASS", "DEFAULT_SURFACE_PREFIX", "LANGUAGES",
           "REFUSALS", "ExportError", "c_header", "cs_class", "export_law", "export_surface", "js_module",
           "surface_c", "surface_cs", "surface_js", "to_c", "to_cs", "to_js"]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(f"bouncelab.export.{_LAZY[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'bouncelab.export' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
