"""Fitting bounce laws: NLopt global search, the paper's procedures, held-out evaluation, comparison."""

from bouncelab.fitting.comparison import PAPER_LAWS, Comparison, compare
from bouncelab.fitting.fitter import fit, resolve_bounds
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.search import GLOBAL_ALGORITHMS, LOCAL_ALGORITHMS
from bouncelab.fitting.splits import CrossValidation, cross_validate, infer_settings, split_by_setting
from bouncelab.fitting.uncertainty import Bootstrap, bootstrap

__all__ = [
    "GLOBAL_ALGORITHMS",
    "LOCAL_ALGORITHMS",
    "PAPER_LAWS",
    "Bootstrap",
    "Comparison",
    "CrossValidation",
    "FitResult",
    "bootstrap",
    "compare",
    "cross_validate",
    "fit",
    "infer_settings",
    "resolve_bounds",
    "split_by_setting",
]
