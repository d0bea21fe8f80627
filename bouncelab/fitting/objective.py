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

__all__ = ["ErrorMeasure", "objective_weights"]

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
    """delta and Delta q of a law family on fixed data, as a function of the parameter vector.

    Uses the law's compiled one-pass kernel when it has one (the built-in rigid
    family), otherwise ``predict`` and NumPy; either way one call returns all
    four errors.
    """

    def __init__(self, model: Any, landing: np.ndarray, liftoff: np.ndarray) -> None:
        self.model = model
        self.landing = landing
        self.liftoff = liftoff
        self.inv_norm = 1.0 / np.linalg.norm(landing, axis=1)
        self.n = len(landing)
        make = getattr(model, "_error_kernel", None)
        self._sums = make(landing, liftoff, self.inv_norm) if make is not None else None

    def unit_function(self, base: np.ndarray, lo: np.ndarray, span: np.ndarray, free: np.ndarray,
                      weights: np.ndarray):
        """The objective as a function of the free parameters scaled to the unit box.

        Parameters are ``base`` where not ``free``, else ``lo + u * span`` (in order);
        the result is the ``weights``-weighted sum of the four errors. Compiled laws
        evaluate it in one compiled call.
        """
        make = getattr(self.model, "_unit_objective", None)
        if make is not None:
            return make(self.landing, self.liftoff, self.inv_norm, base, lo, span, free, weights)
        idx = np.flatnonzero(free)
        w = tuple(float(v) for v in weights)

        def f(u: np.ndarray) -> float:
            theta = np.array(base, dtype=np.float64)
            theta[idx] = lo[idx] + u * span[idx]
            return self.value(theta.tolist(), w)

        return f

    def value(self, theta: list[float], weights: tuple[float, float, float, float]) -> float:
        """Weighted sum of the four errors at ``theta`` (a list of floats, in spec order)."""
        if self._sums is not None:
            sd, sx, sy, sw = self._sums(theta)
        else:
            sd, sx, sy, sw = self.errors(theta) * self.n
        w0, w1, w2, w3 = weights
        return (w0 * sd + w1 * sx + w2 * sy + w3 * sw) / self.n

    def errors(self, theta) -> np.ndarray:
        """``[delta, Delta xdot, Delta ydot, Delta omega]`` at ``theta``."""
        if self._sums is not None:
            return np.asarray(self._sums(list(map(float, theta)))) / self.n
        pred = self.model._predict(self.landing, np.asarray(theta, dtype=np.float64))
        err = self.liftoff - pred
        terms = np.column_stack([np.linalg.norm(err, axis=1), np.abs(err)]) * self.inv_norm[:, None]
        return terms.mean(axis=0)
