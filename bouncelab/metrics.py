r"""The paper's error measures.

With landing states :math:`\mathbf p_0^i`, measured lift-off :math:`\mathbf p_F^i`
and predicted lift-off :math:`\mathbf P_F^i` for :math:`N` bounces:

.. math::

    \delta = \frac1N \sum_i \frac{\lVert \mathbf p_F^i - \mathbf P_F^i \rVert}{\lVert \mathbf p_0^i \rVert}
    \quad\text{(eq. error)},\qquad
    \Delta q = \frac1N \sum_i \frac{| q_F^i - Q_F^i |}{\lVert \mathbf p_0^i \rVert}
    \quad\text{(eq. error_individual)}

for :math:`q \in \{\dot x, \dot y, \omega\}`. Both are dimensionless fractions
(0.319 is the paper's 31.9 %) and are meaningful only in scaled units, where the
three components have comparable size.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd

from bouncelab.core.errors import DataError
from bouncelab.core.slip_roll import SLIP_ROLL_CLASSES, _slip_codes
from bouncelab.core.validation import States, as_states, check_same_length, inverse_norms
from bouncelab.data.inputs import campaign_arrays

__all__ = ["ERROR_COLUMNS", "delta", "delta_q", "error_table", "error_terms", "score"]

#: Column names of error tables: delta then Delta q for xdot, ydot, omega.
ERROR_COLUMNS = ("delta", "delta_xdot", "delta_ydot", "delta_omega")


def _arrays(landing: States, liftoff: States, predicted: States) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    p0, _ = as_states(landing, "landing", landing=True)
    pf, _ = as_states(liftoff, "liftoff")
    pp, _ = as_states(predicted, "predicted")
    check_same_length(p0, pf, "landing", "liftoff")
    check_same_length(p0, pp, "landing", "predicted")
    return p0, pf, pp


def error_terms(p0: np.ndarray, pf: np.ndarray, pp: np.ndarray, inv: np.ndarray | None = None) -> np.ndarray:
    """Per-bounce (n, 4) terms whose means are delta, Delta xdot, Delta ydot, Delta omega (validated arrays).

    ``inv`` is ``1 / ||p0||`` when already known (:func:`bouncelab.core.validation.inverse_norms`).
    """
    inv = inverse_norms(p0) if inv is None else inv
    err = pf - pp
    return np.column_stack([np.linalg.norm(err, axis=1), np.abs(err)]) * inv[:, None]


def delta(landing: States, liftoff: States, predicted: States) -> float:
    r"""Overall error :math:`\delta` (eq. error), a dimensionless fraction.

    Parameters
    ----------
    landing, liftoff, predicted
        (n, 3) states ``[xdot, ydot, omega]`` in scaled units (radii/s, rad/s).

    Examples
    --------
    >>> delta([[3.0, -4.0, 0.0]], [[1.0, 1.0, 0.0]], [[1.0, 1.0, 0.5]])
    0.1
    """
    p0, pf, pp = _arrays(landing, liftoff, predicted)
    return float(error_terms(p0, pf, pp)[:, 0].mean())


def delta_q(landing: States, liftoff: States, predicted: States) -> np.ndarray:
    r"""Per-component errors :math:`\Delta q` (eq. error_individual), in the order xdot, ydot, omega."""
    p0, pf, pp = _arrays(landing, liftoff, predicted)
    return error_terms(p0, pf, pp)[:, 1:].mean(axis=0)


def error_table(
    landing: States,
    liftoff: States,
    predicted: States,
    classes: Any = None,
) -> pd.DataFrame:
    """delta and Delta q overall and for each class of bounce (the layout of the paper's Table 2).

    Parameters
    ----------
    landing, liftoff, predicted
        (n, 3) states in scaled units.
    classes
        Optional length-n labels (e.g. from :func:`bouncelab.classify_slip_roll`).

    Returns
    -------
    pandas.DataFrame
        Index ``"all"`` then each class in sorted order; columns ``n`` and
        :data:`ERROR_COLUMNS` (fractions).
    """
    p0, pf, pp = _arrays(landing, liftoff, predicted)
    if classes is not None:
        labels = np.asarray(classes)
        if labels.shape != (len(p0),):
            raise DataError(f"classes must have one label per bounce ({len(p0)}); got shape {labels.shape}",
                            option="classes")
    return _error_table(error_terms(p0, pf, pp), classes)


def _error_table(terms: np.ndarray, classes: Any = None) -> pd.DataFrame:
    """The table of :func:`error_table` from per-bounce terms (internal: no validation)."""
    rows = {"all": terms}
    if classes is not None:
        labels = np.asarray(classes)
        for c in sorted(set(labels.tolist())):
            rows[str(c)] = terms[labels == c]
    table = pd.DataFrame(
        [[len(t), *t.mean(axis=0)] for t in rows.values()],
        index=pd.Index(list(rows), name="subset"),
        columns=["n", *ERROR_COLUMNS],
    )
    table["n"] = table["n"].astype(int)
    return table


def score(model: Any, data: Any, *, by: str | None = "slip_roll") -> pd.DataFrame:
    """Error table of a law on a campaign.

    Parameters
    ----------
    model
        A fitted :class:`~bouncelab.BounceModel`.
    data
        A campaign Dataset or a ``(landing, liftoff)`` pair.
    by
        ``"slip_roll"`` (measured slip/roll class, the paper's breakdown),
        ``"regime"`` (the law's own regimes) or ``None`` (overall only).
    """
    from bouncelab.laws.base import BounceModel

    if not isinstance(model, BounceModel):
        from bouncelab.core.errors import ParameterError

        raise ParameterError(f"model must be a bounce law (a BounceModel); got {type(model).__name__}",
                             parameter="model")
    if by not in (None, "slip_roll", "regime"):
        raise DataError(f"by must be 'slip_roll', 'regime' or None; got {by!r}", option="by")
    p0, pf, _ = campaign_arrays(data)
    pred = model._evaluate(p0)  # a law's wrong shape: LawDefinitionError
    if by is None:
        classes = None
    elif by == "slip_roll":
        classes = np.asarray(SLIP_ROLL_CLASSES)[_slip_codes(p0, pf)]
    else:
        classes = np.asarray(model.regimes)[model._classify(p0)]
    return _error_table(error_terms(p0, pf, pred), classes)
