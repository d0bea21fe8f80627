r"""scikit-learn: a bounce law as a 3-output regressor, :class:`BounceRegressor`.

``X`` holds landings ``[xdot0, ydot0, omega0]`` and ``Y`` lift-offs
``[xdotF, ydotF, omegaF]``, both (n, 3) in scaled units (radii/s, rad/s; see
:mod:`bouncelab.core.units`). ``fit`` runs :func:`bouncelab.fit`, ``predict``
the fitted law, and ``score`` is :math:`-\delta` (eq. error of the paper), so
that greater is better as scikit-learn's model selection expects:

.. math::

    \text{score} = -\delta = -\frac1n \sum_i \frac{\lVert p_{F,i} - \hat p_{F,i} \rVert}{\lVert p_{0,i} \rVert}.

Examples
--------
Grouped cross-validation by launcher setting, and a grid over laws:

>>> import bouncelab as bl
>>> from sklearn.model_selection import GroupKFold, cross_val_score
>>> ds = bl.load_campaign("A")
>>> X, Y, groups = ds.landing.values, ds.liftoff.values, ds.setting.values
>>> scores = cross_val_score(bl.BounceRegressor("Rigid"), X, Y, groups=groups, cv=GroupKFold(5))
>>> bool((scores < 0).all())
True
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from sklearn.base import BaseEstimator, MultiOutputMixin, RegressorMixin
from sklearn.exceptions import NotFittedError as _SklearnNotFittedError
from sklearn.utils.validation import check_is_fitted

from bouncelab.core.errors import DataError, FitError, ParameterError
from bouncelab.core.errors import NotFittedError as _BouncelabNotFittedError
from bouncelab.laws.base import BounceModel

__all__ = ["BounceRegressor", "EstimatorNotFittedError"]


class EstimatorNotFittedError(_BouncelabNotFittedError, _SklearnNotFittedError):
    """``predict`` or ``score`` of a :class:`BounceRegressor` before ``fit``.

    Both scikit-learn's :class:`sklearn.exceptions.NotFittedError` (what
    scikit-learn code and its estimator checks catch) and bouncelab's
    :class:`bouncelab.core.errors.NotFittedError` (a law without values); both are
    ``ValueError``s.
    """


class BounceRegressor(MultiOutputMixin, RegressorMixin, BaseEstimator):
    """A bounce law fitted and used as a scikit-learn regressor (landings in, lift-offs out).

    Parameters
    ----------
    law : str, BounceModel class or instance, default "Rigid"
        The law to fit: a name in any case (``"PennerFixed"``, or ``"module:QualName"`` for your
        own laws), a class, or an instance (its values, if any, start the search;
        its options, e.g. ``fade_xdot``, are kept). ``law__<name>`` in
        :meth:`set_params` and in ``GridSearchCV`` grids sets a parameter or option
        of the law (a start value for a parameter unless it is also in ``fixed``).
    method : str, optional
        Fitting method of the law (see :func:`bouncelab.fit`); default the law's own default.
    objective : str or mapping, default "delta"
        The fit objective (``"delta"``, ``"omega"``, ``{"delta": 1, "omega": 0.5}`` ...).
    seed : int, default 0
        Seed of the fit.
    bounds : mapping, optional
        Search bounds, parameter name -> (low, high).
    fixed : sequence or mapping, optional
        Parameters held in the fit (names, or name -> value).
    method_options : mapping, optional
        Options of the fitting method (e.g. ``{"maxeval": 200}``).

    Attributes
    ----------
    law_ : BounceModel
        The fitted law.
    fit_result_ : bouncelab.FitResult
        The whole fit (``print(est.fit_result_)`` gives its report).
    n_features_in_ : int
        Always 3 (``xdot0, ydot0, omega0``).
    """

    def __init__(self, law: Any = "Rigid", *, method: str | None = None, objective: Any = "delta", seed: int = 0,
                 bounds: Mapping[str, Any] | None = None, fixed: Any = None,
                 method_options: Mapping[str, Any] | None = None) -> None:
        self.law = law
        self.method = method
        self.objective = objective
        self.seed = seed
        self.bounds = bounds
        self.fixed = fixed
        self.method_options = method_options

    # ------------------------------------------------------------------ scikit-learn protocol
    def __sklearn_tags__(self):
        tags = super().__sklearn_tags__()
        tags.target_tags.required = True
        tags.target_tags.multi_output = True
        tags.target_tags.single_output = False
        tags.input_tags.allow_nan = False
        return tags

    def set_params(self, **params: Any) -> BounceRegressor:
        """Set estimator parameters; ``law__<name>=value`` sets a parameter or option of the law."""
        nested = {k.split("__", 1)[1]: v for k, v in params.items() if k.startswith("law__")}
        rest = {k: v for k, v in params.items() if not k.startswith("law__")}
        super().set_params(**rest)
        if nested:
            self.law = _law_instance(self.law).replace(**nested)
        return self

    # ------------------------------------------------------------------ fit, predict, score
    def fit(self, X: Any, y: Any, sample_weight: Any = None) -> BounceRegressor:
        """Fit the law to landings ``X`` and lift-offs ``y`` ((n, 3) each, scaled units).

        ``sample_weight`` (one non-negative weight per bounce) weighs each bounce in the fit, as
        :func:`bouncelab.fit`'s ``sample_weight``.

        Raises
        ------
        DataError
            Bad arrays, naming ``X`` (landings) or ``y`` (lift-offs) and, for a value, its row (1-based) and
            column: not 2-D, not 3 columns, fewer than 2 bounces, complex, sparse or non-numeric values,
            NaN or infinite values, a landing with ``ydot0 >= 0``, different numbers of rows; bad weights.
            A ``DataError`` is a ``ValueError``, as scikit-learn expects; the messages keep
            scikit-learn's wording where its checks look for it ("1 sample(s)", "Complex data not supported").
        FitError, ParameterError
            As :func:`bouncelab.fit` (too few bounces, a bad objective, bounds or method).
        """
        from bouncelab.fitting.fitter import fit

        if y is None:
            raise DataError("BounceRegressor requires y to be passed, but the target y is None: give the lift-offs, "
                            "an (n, 3) array [xdotF, ydotF, omegaF]", option="y")
        p0, pf = _pair(X, y, min_samples=2)
        result = fit(_law_instance(self.law), (p0, pf), method=self.method, objective=self.objective,
                     seed=self.seed, bounds=self.bounds, fixed=self.fixed, sample_weight=sample_weight,
                     **dict(self.method_options or {}))
        self.fit_result_ = result
        self.law_ = result.model
        self.n_features_in_ = 3
        return self

    def predict(self, X: Any) -> np.ndarray:
        """Lift-offs (n, 3) of landings ``X`` predicted by the fitted law.

        Raises
        ------
        EstimatorNotFittedError
            Before ``fit``: an instance of scikit-learn's ``sklearn.exceptions.NotFittedError`` (as
            scikit-learn's tools expect) and of :class:`bouncelab.core.errors.NotFittedError`.
        DataError
            Bad landings, as in :meth:`fit` (naming the row and column of a bad value).
        """
        self._check_fitted()
        return np.asarray(self.law_.predict(_states(X, "landing")))

    def score(self, X: Any, y: Any, sample_weight: Any = None) -> float:
        """``-delta`` of the fitted law on landings ``X`` and lift-offs ``y`` (greater is better).

        ``sample_weight`` weighs each bounce's term of delta (a weighted mean). Before ``fit``, an
        :class:`EstimatorNotFittedError` (scikit-learn's ``NotFittedError``, as :meth:`predict`).
        """
        from bouncelab.fitting.objective import sample_weights
        from bouncelab.metrics import error_terms

        self._check_fitted()
        p0, pf = _pair(X, y)
        weights = sample_weights(sample_weight, len(p0))  # as in fit: one finite weight >= 0 per bounce
        terms = error_terms(p0, pf, self.law_.predict(p0))[:, 0]
        return -float(np.average(terms, weights=weights))


    def _check_fitted(self) -> None:
        try:
            check_is_fitted(self, "law_")
        except _SklearnNotFittedError as exc:
            raise EstimatorNotFittedError(str(exc), missing=("law_",)) from None


def _states(x: Any, name: str, min_samples: int = 1) -> np.ndarray:
    """Validated (n, 3) states: scikit-learn's shared checks (sparse, complex, empty), then bouncelab's (NaN,
    magnitude, sign), every failure a DataError naming X or y (and the row and column of a bad value)."""
    from sklearn.utils.validation import check_array

    from bouncelab.core.validation import _from_labelled, as_states

    arg = "X" if name == "landing" else "y"
    what = f"{name} ({arg})"
    columns = "[xdot0, ydot0, omega0]" if arg == "X" else "[xdotF, ydotF, omegaF]"
    try:
        # NaN and infinity are left to as_states, which names the row and the column
        arr = check_array(_from_labelled(x, name, None), dtype=np.float64, ensure_min_samples=min_samples,
                          ensure_all_finite=False, input_name=arg)
    except (ValueError, TypeError) as exc:
        if isinstance(exc, DataError):
            raise
        text = str(exc).split("\n")[0].strip()
        dim = np.ndim(x) if not hasattr(x, "toarray") else 2
        if text.startswith("Expected 2D array") or text.startswith("Found array with dim"):
            text = (f"must be a 2-D array (n, 3), one bounce {columns} per row; got a {dim}-D array of shape "
                    f"{np.shape(x)}" + (f" (one bounce is [{columns}])" if np.shape(x) == (3,) else ""))
        elif text.startswith("Complex data not supported"):
            text = f"Complex data not supported: {arg} holds real numbers {columns}"
        raise DataError(f"{what}: {text}", option=arg) from None
    if arr.shape[1] != 3:
        raise DataError(f"{what} needs 3 columns {columns} (3 features); got {arr.shape[1]} feature(s), "
                        f"n_features = {arr.shape[1]}, shape {arr.shape}", option=arg)
    return as_states(arr, name, landing=name == "landing")[0]


def _pair(X: Any, y: Any, min_samples: int = 1) -> tuple[np.ndarray, np.ndarray]:
    from bouncelab.core.validation import check_same_length

    p0, pf = _states(X, "landing", min_samples), _states(y, "liftoff", min_samples)
    check_same_length(p0, pf, "landing (X)", "liftoff (y)", option="y")
    return p0, pf


def _law_instance(law: Any) -> BounceModel:
    """The ``law`` parameter as a law, read as :func:`bouncelab.fit` reads it; a bad one is a ParameterError."""
    from bouncelab.fitting.fitter import law_instance

    try:
        return law_instance(law)
    except FitError as exc:
        raise ParameterError(exc.message, law=exc.law, parameter="law", value=law, hints=exc.hints) from None
