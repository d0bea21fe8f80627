"""The fitting protocol between :func:`bouncelab.fit` and a law: the problem a fitting method receives, what it
returns, and the decorator that registers a law's own fitting methods.

A law's fitting method is an ordinary method decorated with :func:`fit_method`; it receives a
:class:`FitProblem` (the validated bounces, the search box, the held parameters and services: the
objective of a law, NLopt's search, the generic global method) and returns a :class:`FitOutcome`.
Parameters go in and out as laws (:meth:`FitProblem.value`, :meth:`FitProblem.run_global`); only
:meth:`FitProblem.search`, NLopt's own search, works on a vector of numbers in the unit box.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from bouncelab.core.errors import ParameterError

if TYPE_CHECKING:
    from bouncelab.laws.interface import Law

__all__ = ["DEFAULT_LOCAL_ALGORITHM", "FitOutcome", "FitProblem", "fit_method", "fit_methods"]

#: Default local polish of the generic search (delta has kinks at regime changes, where
#: BOBYQA's quadratic models stall; see benchmarks/bench_algorithms.py).
DEFAULT_LOCAL_ALGORITHM = "NELDERMEAD"

_FIT_METHOD_ATTR = "__bouncelab_fit_method__"


class FitProblem(Protocol):
    """What a law's fitting method receives from :func:`bouncelab.fit` (implemented in ``bouncelab.fitting``).

    Attributes
    ----------
    landing, liftoff
        Validated ``(n, 3)`` C-contiguous float64 arrays of the bounces to fit.
    inv_norm
        The weight of each bounce's error in the objective: ``1 / ||p0||`` of every
        landing (delta and Delta q), or ``1 / h`` from its prediction intervals for a
        ``"delta_pi"`` objective (:mod:`bouncelab.fitting.objective`).
    setting
        Launcher setting of each bounce, or None.
    n
        Number of bounces.
    weights
        Weights of ``[delta, Delta xdot, Delta ydot, Delta omega]`` in the objective.
    seed
        Seed for anything random.
    box
        Search box, parameter name -> ``(low, high)`` (arrays for array parameters),
        the law's defaults updated by the user's ``bounds``.
    fixed
        Parameters held in this fit, name -> value.
    test
        Held-out ``(landing, liftoff)`` or None (for information; never fitted).
    sample_weight
        The user's weight of each bounce (positive: bounces of weight 0 are left out; mean 1), or None. It is in
        ``inv_norm`` (so in :meth:`value`); a method that fits anything else from the
        bounces (least squares, a classifier) must weigh them by it too.
    """

    landing: np.ndarray
    liftoff: np.ndarray
    inv_norm: np.ndarray
    setting: np.ndarray | None
    n: int
    weights: np.ndarray
    seed: int
    box: dict[str, tuple[Any, Any]]
    fixed: dict[str, Any]
    test: tuple[np.ndarray, np.ndarray] | None
    sample_weight: np.ndarray | None

    def value(self, law: Law) -> float:
        """The objective (the weighted mean error, delta by default) of ``law`` on the bounces fitted."""

    def search(self, f: Callable[[np.ndarray], float], x0: np.ndarray, **options: Any) -> Any:
        """Minimise ``f`` over the unit box ``[0, 1]^d`` from ``x0`` (NLopt global stage + local polish)."""

    def run_global(self, law: Law, **options: Any) -> FitOutcome:
        """The generic method: global search over the free parameters of ``law`` in ``box`` (options:
        ``algorithm``, ``local_algorithm``, ``maxeval``, ``hold`` (name -> value held in this call),
        ``criterion`` (a function of the parameters by keyword to minimise instead of the objective))."""


@dataclass
class FitOutcome:
    """What a fitting method returns to :func:`bouncelab.fit`.

    Attributes
    ----------
    model
        The fitted law.
    objective_value
        The objective at the fitted parameters, on the fitted data.
    algorithm
        The procedure, in words (e.g. ``"DIRECT_L + NELDERMEAD"``).
    n_global, n_local
        Objective evaluations per stage.
    stop_reason
        Why the optimizer(s) stopped.
    at_bounds
        Parameters (element names for arrays) that ended on a bound, name -> "lower"/"upper".
    insensitive
        Parameters the objective does not depend on near the optimum, name -> the
        range over which it stays the same.
    stderr
        Standard errors the method knows, parameter name -> value (array for arrays).
    notes
        Anything a user should know about this fit.
    extras
        Method-specific results (e.g. support-vector indices), for programs.
    """

    model: Law
    objective_value: float
    algorithm: str
    n_global: int = 0
    n_local: int = 0
    stop_reason: str = ""
    at_bounds: dict[str, str] = field(default_factory=dict)
    insensitive: dict[str, tuple[float, float]] = field(default_factory=dict)
    stderr: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    extras: dict[str, Any] = field(default_factory=dict)


def fit_method(name: str) -> Callable[[Callable], Callable]:
    """Register a method of a law class as the fitting method ``name`` of :func:`bouncelab.fit`.

    The method is called as ``method(law, problem, **options)`` with a
    :class:`FitProblem` and returns a :class:`FitOutcome`; its keyword-only
    arguments are its options (``bouncelab.fit`` refuses any other).

    Examples
    --------
    >>> class MyLaw(BounceModel):  # doctest: +SKIP
    ...     @fit_method("closed_form")
    ...     def _fit_closed_form(self, problem, *, damping: float = 0.0) -> FitOutcome: ...
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise ParameterError(f"a fitting method name must be an identifier; got {name!r}", value=name)

    def mark(func: Callable) -> Callable:
        setattr(func, _FIT_METHOD_ATTR, name)
        return func

    return mark


def fit_methods(cls: type) -> dict[str, Callable]:
    """The fitting methods of a law class, name -> function (``"global"`` first, then the class's own)."""
    out: dict[str, Callable] = {}
    for klass in reversed(cls.__mro__):
        for value in vars(klass).values():
            name = getattr(value, _FIT_METHOD_ATTR, None)
            if name is not None:
                out[name] = value
    return {"global": out.pop("global"), **out} if "global" in out else out
