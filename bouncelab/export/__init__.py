"""Laws outside Python: a fitted law as a self-contained C99 header or JavaScript ES module.

>>> import bouncelab as bl
>>> header = bl.Rigid.published("A").to_c()          # or law.to_c("rigid_A.h"), bouncelab export
>>> "void bouncelab_predict(const double *landing, double *liftoff, long n)" in header
True
>>> module = bl.Rigid.published("A").to_js()         # export function predict(landings), predictOne(...)

The code is the law's own numba kernel translated operation by operation
(:mod:`bouncelab.export.translate`, which documents the Python subset it reads), with the law's values
baked in; the file's top comment gives the law, its conventions and units, its parameters and its
validity domain, and how to compile it (``-ffp-contract=off``, no ``-ffast-math``) so that its results
agree with bouncelab's to 1e-12 of the landing's norm.
"""

from __future__ import annotations

from bouncelab.export.law import DEFAULT_PREFIX, LANGUAGES, c_header, export_law, js_module
from bouncelab.export.translate import ExportError

__all__ = ["DEFAULT_PREFIX", "LANGUAGES", "ExportError", "c_header", "export_law", "js_module"]
