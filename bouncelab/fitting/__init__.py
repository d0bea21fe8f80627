"""Fitting bounce laws: ``fit`` (the law's own or the generic method), held-out evaluation, comparison,
the bootstrap, parameter sweeps; any of them on a dask cluster.

Nothing here names a law: every law-specific step (parameters, fitting methods,
report lines, diagnostics) is read from the law (see :mod:`bouncelab.laws.base`).
"""

from bouncelab.fitting.comparison import PAPER_LAWS, Comparison, compare
from bouncelab.fitting.fitter import fit, resolve_bounds
from bouncelab.fitting.problem import Problem
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.search import GLOBAL_ALGORITHMS, LOCAL_ALGORITHMS
from bouncelab.fitting.splits import CrossValidation, cross_validate, split_by_setting
from bouncelab.fitting.sweep import sweep
from bouncelab.fitting.tasks import map_tasks
from bouncelab.fitting.uncertainty import Bootstrap, bootstrap

__all__ = [
    "GLOBAL_ALGORITHMS",
    "LOCAL_ALGORITHMS",
    "PAPER_LAWS",
    "Bootstrap",
    "Comparison",
    "CrossValidation",
    "FitResult",
    "Problem",
    "bootstrap",
    "compare",
    "cross_validate",
    "fit",
    "map_tasks",
    "resolve_bounds",
    "split_by_setting",
    "sweep",
]
