"""Objectives: the paper's error measures as functions of a law's parameter vector.

An objective is a weighted sum of delta (eq. error) and the three Delta q
(eq. error_individual), all computed in one pass over the bounces:

* ``"delta"`` (default): delta alone, as the paper's genetic-algorithm fits;
* ``"xdot"``, ``"ydot"``, ``"omega"``: one Delta q component;
* a mapping such as ``{"delta": 1.0, "omega": 0.5}``: a weighted sum.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.errors import FitError
from bouncelab.metrics import ERROR_COLUMNS

__all__ = ["ErrorMeasure", "objective_label", "objective_weights"]

_NAMES = {"delta": 0, "xdot": 1, "ydot": 2, "omega": 3,
          "delta_xdot": 1, "delta_ydot": 2, "delta_omega": 3}


def objective_weights(objective: str | Mapping[str, float]) -> np.ndarray:
    """Weights over ``[delta, Delta xdot, Delta ydot, Delta omega]`` for an objective spec."""
    w = np.zeros(4)
    if isinstance(objective, str):
        if objective not in _NAMES:
            raise FitError(f"unknown objective {objective!r}; use 'delta', 'xdot', 'ydot', 'omega' or a mapping")
        w[_NAMES[objective]] = 1.0
        return w
    if isinstance(objective, Mapping) and objective:
        for key, value in objective.items():
            if key not in _NAMES:
                raise FitError(f"unknown objective term {key!r}; terms are 'delta', 'xdot', 'ydot', 'omega'")
            v = float(value)
            if not np.isfinite(v) or v < 0:
                raise FitError(f"objective weight of {key!r} must be a non-negative number; got {value!r}")
            w[_NAMES[key]] += v
        if not w.any():
            raise FitError("objective weights are all zero")
        return w
    raise FitError(f"objective must be a name or a non-empty mapping of weights; got {objective!r}")


def objective_label(weights: np.ndarray) -> str:
    """Readable form of objective weights, e.g. ``'delta'`` or ``'1*delta + 0.5*delta_omega'``."""
    nz = np.flatnonzero(weights)
    if len(nz) == 1 and weights[nz[0]] == 1.0:
        return ERROR_COLUMNS[nz[0]]
    return " + ".join(f"{weights[i]:g}*{ERROR_COLUMNS[i]}" for i in nz)


class ErrorMeasure:
    """delta and Delta q of a law on fixed data, as a function of its flat parameter vector.

    A convenience over the law's one objective hook,
    :meth:`~bouncelab.BounceModel._error_function` (compiled for compiled laws).

    Examples
    --------
    >>> import numpy as np, bouncelab as bl
    >>> ds = bl.load_campaign("A")
    >>> m = ErrorMeasure(bl.Rigid(), ds.landing.values, ds.liftoff.values)
    >>> bool(m.errors(np.array([0.5, 0.3]))[0] > 0)
    True
    """

    def __init__(self, model: Any, landing: Any, liftoff: Any) -> None:
        from bouncelab.data.validation import as_states, check_same_length, inverse_norms

        self.model = model
        self.landing, _ = as_states(landing, "landing", landing=True)
        self.liftoff, _ = as_states(liftoff, "liftoff")
        check_same_length(self.landing, self.liftoff, "landing", "liftoff")
        self.inv_norm = inverse_norms(self.landing)
        self.n = len(self.landing)
        self._sums = model._error_function(self.landing, self.liftoff, self.inv_norm)

    def errors(self, theta: Any) -> np.ndarray:
        """``[delta, Delta xdot, Delta ydot, Delta omega]`` at ``theta`` (flat parameter vector)."""
        return np.asarray(self._sums(np.ascontiguousarray(theta, dtype=np.float64)), dtype=np.float64) / self.n

    def value(self, theta: Any, weights: Any) -> float:
        """Weighted sum of the four errors at ``theta``."""
        return float(np.dot(np.asarray(weights, dtype=np.float64), self.errors(theta)))
