r"""Objectives: the paper's error measures as functions of a law's parameter vector.

An objective is a weighted sum of delta (eq. error) and the three Delta q
(eq. error_individual), all computed in one pass over the bounces:

* ``"delta"`` (default): delta alone, as the paper's genetic-algorithm fits;
* ``"xdot"``, ``"ydot"``, ``"omega"``: one Delta q component;
* a mapping such as ``{"delta": 1.0, "omega": 0.5}``: a weighted sum.

Each bounce's error is divided by the norm of its landing, ``||p0_i||`` (the
paper's weighting). Weighting by measurement error instead: ``"delta_pi"``
(also ``"xdot_pi"``, ``"ydot_pi"``, ``"omega_pi"``, or ``"weighting": "pi"`` in a
mapping) divides it by the size of the bounce's 95 % prediction intervals,

.. math::

    \delta_{PI} = \frac1n \sum_i \frac{\lVert p_{F,i} - \hat p_{F,i} \rVert}{h_i}, \qquad
    h_i = \sqrt{\lVert h_{F,i} \rVert^2 + \lVert h_{0,i} \rVert^2},

with :math:`h_{F,i}` and :math:`h_{0,i}` the half-widths of the lift-off's and
landing's prediction intervals (``liftoff_pi``, ``landing_pi`` of a campaign).
Combining them in quadrature treats the law's response to a landing error as
one to one (a first-order approximation; the laws damp most components). A
bounce measured twice as precisely counts twice as much, and the value is the
mean residual in units of its 95 % interval (about 1 when a law predicts as
well as the measurements allow). The data must carry the intervals.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.core.errors import FitError
from bouncelab.fitting.vector import ParameterVector
from bouncelab.metrics import ERROR_COLUMNS

__all__ = [
    "WEIGHTINGS",
    "ErrorMeasure",
    "bounce_weights",
    "mean_one",
    "objective_label",
    "objective_weighting",
    "objective_weights",
    "sample_weights",
]

#: How each bounce's error is weighted: by ``1 / ||p0||`` (the paper) or by ``1 / h`` (prediction intervals).
WEIGHTINGS = ("landing", "pi")

_NAMES = {"delta": 0, "xdot": 1, "ydot": 2, "omega": 3,
          "delta_xdot": 1, "delta_ydot": 2, "delta_omega": 3}


def objective_weights(objective: str | Mapping[str, float]) -> np.ndarray:
    """Weights over ``[delta, Delta xdot, Delta ydot, Delta omega]`` for an objective spec."""
    w = np.zeros(4)
    objective_weighting(objective)  # validates the weighting
    if isinstance(objective, str):
        name = objective[:-3] if objective.endswith("_pi") else objective
        if name not in _NAMES:
            raise FitError(f"unknown objective {objective!r}; use 'delta', 'xdot', 'ydot', 'omega' (with '_pi' to "
                           "weight by prediction intervals) or a mapping", option="objective")
        w[_NAMES[name]] = 1.0
        return w
    if isinstance(objective, Mapping) and objective:
        for key, value in objective.items():
            if key == "weighting":
                continue
            if key not in _NAMES:
                raise FitError(f"unknown objective term {key!r}; terms are 'delta', 'xdot', 'ydot', 'omega'",
                               option="objective")
            v = float(value)
            if not np.isfinite(v) or v < 0:
                raise FitError(f"objective weight of {key!r} must be a non-negative number; got {value!r}",
                               option="objective")
            w[_NAMES[key]] += v
        if not w.any():
            raise FitError("objective weights are all zero", option="objective")
        return w
    raise FitError(f"objective must be a name or a non-empty mapping of weights; got {objective!r}", option="objective")


def objective_weighting(objective: str | Mapping[str, Any]) -> str:
    """``"pi"`` if the objective weights bounces by their prediction intervals, else ``"landing"``."""
    if isinstance(objective, str):
        return "pi" if objective.endswith("_pi") else "landing"
    if isinstance(objective, Mapping):
        weighting = objective.get("weighting", "landing")
        if weighting not in WEIGHTINGS:
            raise FitError(f"objective 'weighting' must be one of {WEIGHTINGS}; got {weighting!r}", option="objective")
        return weighting
    return "landing"


def bounce_weights(data: Any, landing: np.ndarray) -> np.ndarray:
    """``1 / h_i`` of every bounce from the prediction intervals ``data`` carries (see the module).

    Raises
    ------
    FitError
        The data carry no ``liftoff_pi`` (a pair of arrays never does), or a bounce's
        intervals are all zero (it could not be weighed; row named).
    """
    import xarray as xr

    if not isinstance(data, xr.Dataset) or "liftoff_pi" not in data.data_vars:
        raise FitError("a prediction-interval weighted objective needs data that carry them: a campaign Dataset with "
                       "'liftoff_pi' (and optionally 'landing_pi'), e.g. make_campaign(..., liftoff_pi=..., "
                       "landing_pi=...); these data have none", option="objective")
    h2 = np.zeros(len(landing))
    for var in ("liftoff_pi", "landing_pi"):
        if var in data.data_vars:
            h = np.asarray(data[var].transpose("bounce", "component").values, dtype=np.float64)
            h2 += np.einsum("ij,ij->i", h, h)
    bad = ~(np.isfinite(h2) & (h2 > 0))
    if bad.any():
        row = int(np.argmax(bad))
        raise FitError(f"bounce {row + 1} has prediction intervals of zero width ({int(bad.sum())} bounce(s)); a "
                       "prediction-interval weighted objective cannot weigh it", option="objective")
    return 1.0 / np.sqrt(h2)


def sample_weights(sample_weight: Any, n: int) -> np.ndarray | None:
    """The user's per-bounce weights, validated, as float64 (None stays None).

    Raises
    ------
    DataError
        Not one real number per bounce, or a weight that is negative, NaN or infinite (row named),
        or all weights zero.
    """
    from bouncelab.core.errors import DataError

    if sample_weight is None:
        return None
    w = np.asarray(sample_weight)
    if w.dtype.kind not in "iuf" or w.shape != (n,):
        raise DataError(f"sample_weight must be {n} real numbers, one per bounce; got {w.dtype} values of shape "
                        f"{w.shape}", column="sample_weight", option="sample_weight")
    w = w.astype(np.float64)
    bad = ~np.isfinite(w) | (w < 0)
    if bad.any():
        row = int(np.argmax(bad))
        raise DataError(f"a weight must be a finite number >= 0; got {w[row]!r} ({int(bad.sum())} bounce(s))",
                        column="sample_weight", row=row + 1, option="sample_weight")
    if not (w > 0).any():
        raise DataError("sample_weight is zero for every bounce; nothing would be fitted", column="sample_weight",
                        option="sample_weight")
    return np.ascontiguousarray(w)


def mean_one(w: np.ndarray) -> np.ndarray:
    """Positive weights scaled to mean 1 (only their ratios matter), without overflow or underflow."""
    w = w / w.max()
    return np.ascontiguousarray(w / w.mean())


def objective_label(weights: np.ndarray, weighting: str = "landing") -> str:
    """Readable form of objective weights, e.g. ``'delta'``, ``'1*delta + 0.5*delta_omega'`` or ``'delta_pi'``."""
    nz = np.flatnonzero(weights)
    if len(nz) == 1 and weights[nz[0]] == 1.0:
        return ERROR_COLUMNS[nz[0]] + ("_pi" if weighting == "pi" else "")
    label = " + ".join(f"{weights[i]:g}*{ERROR_COLUMNS[i]}" for i in nz)
    return label + (" (weighted by prediction intervals)" if weighting == "pi" else "")


class ErrorMeasure:
    """delta and Delta q of a law on fixed data, as a function of its flat parameter vector
    (:class:`~bouncelab.fitting.vector.ParameterVector`).

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
        from bouncelab.core.validation import as_states, check_same_length, inverse_norms

        self.model = model
        self.landing, _ = as_states(landing, "landing", landing=True)
        self.liftoff, _ = as_states(liftoff, "liftoff")
        check_same_length(self.landing, self.liftoff, "landing", "liftoff")
        self.inv_norm = inverse_norms(self.landing)
        self.n = len(self.landing)
        self._sums = model._error_function(self.landing, self.liftoff, self.inv_norm)
        self._values = ParameterVector(model).values

    def errors(self, theta: Any) -> np.ndarray:
        """``[delta, Delta xdot, Delta ydot, Delta omega]`` at ``theta`` (flat parameter vector)."""
        return np.asarray(self._sums(self._values(theta)), dtype=np.float64) / self.n

    def value(self, theta: Any, weights: Any) -> float:
        """Weighted sum of the four errors at ``theta``."""
        return float(np.dot(np.asarray(weights, dtype=np.float64), self.errors(theta)))
