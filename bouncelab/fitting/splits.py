"""Held-out evaluation: the paper's one-bounce-per-setting test set and grouped cross-validation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core.errors import DataError, FitError
from bouncelab.data.inputs import campaign_arrays

__all__ = ["CrossValidation", "cross_validate", "split_by_setting"]


def _settings_of(data: Any) -> np.ndarray:
    _, _, setting = campaign_arrays(data)
    if setting is None:
        raise DataError(
            "the data have no 'setting' coordinate (launcher setting of each bounce); infer one with "
            "ds.assign_coords(setting=('bounce', bouncelab.infer_settings(ds))) or pass a setting per bounce",
            column="setting"
        )
    return np.asarray(setting)


def split_by_setting(data: xr.Dataset, seed: int = 0) -> tuple[xr.Dataset, xr.Dataset]:
    """The paper's validation split: one random bounce of each launcher setting goes to the test set.

    Section "A piecewise-linear data fit": "One data point from each launcher
    setting (chosen at random) was removed from the general set of data and
    placed into a testing set".

    Parameters
    ----------
    data
        A campaign Dataset with a ``setting`` coordinate.
    seed
        Seed of the random choice.

    Returns
    -------
    train, test
        Two campaign Datasets (``bounce`` coordinates keep the original indices).
    """
    if not isinstance(data, xr.Dataset):
        raise DataError("split_by_setting needs a campaign Dataset (with a 'setting' coordinate)", option="data")
    from bouncelab.fitting.fitter import check_seed

    setting = _settings_of(data)
    rng = np.random.default_rng(check_seed(seed))
    test_idx = []
    for s in pd.unique(setting):
        members = np.flatnonzero(setting == s)
        if len(members) < 2:
            continue  # a setting with one bounce stays in training: it cannot give a bounce away
        test_idx.append(int(rng.choice(members)))
    test = np.zeros(len(setting), dtype=bool)
    test[test_idx] = True
    if not test.any():
        raise DataError("no launcher setting has two or more bounces, so none can be held out", column="setting")
    return data.isel(bounce=np.flatnonzero(~test)), data.isel(bounce=np.flatnonzero(test))


@dataclass
class CrossValidation:
    """Result of :func:`cross_validate`: held-out errors of each fold and their summary."""

    folds: pd.DataFrame
    law: str

    @property
    def delta(self) -> float:
        """Mean held-out delta over the folds."""
        return float(self.folds["test_delta"].mean())

    @property
    def delta_std(self) -> float:
        """Standard deviation of the held-out delta over the folds."""
        return float(self.folds["test_delta"].std(ddof=1)) if len(self.folds) > 1 else float("nan")

    def __repr__(self) -> str:
        return (f"CrossValidation({self.law}, k={len(self.folds)}: held-out delta {self.delta:.4f} "
                f"+- {self.delta_std:.4f}, fitted delta {self.folds['train_delta'].mean():.4f})")


def cross_validate(model: Any, data: xr.Dataset, *, k: int = 5, seed: int = 0, executor: Any = None,
                   **fit_kwargs: Any) -> CrossValidation:
    """Grouped k-fold cross-validation by launcher setting.

    All repeats of a setting fall in the same fold, so a law is always scored
    on settings it has not seen (scikit-learn's ``GroupKFold`` with shuffling).

    Parameters
    ----------
    model
        A law instance, class or name, as for :func:`bouncelab.fit`.
    data
        A campaign Dataset with a ``setting`` coordinate.
    k
        Number of folds (at most the number of settings).
    seed
        Seed of the fold assignment and of each fit.
    executor
        Where to run the folds: any :class:`concurrent.futures.Executor` or a dask ``Client`` (see
        :func:`bouncelab.fitting.tasks.map_tasks`); serially by default. The result does not depend on it.
    **fit_kwargs
        Passed to :func:`bouncelab.fit` (e.g. ``objective``, ``method``).

    Returns
    -------
    CrossValidation
        One row per fold: bounces, fitted and held-out delta and Delta q, and the
        law's diagnostics on the held-out bounces (``test_<name>``).
    """
    from sklearn.model_selection import GroupKFold

    from bouncelab.fitting.fitter import check_seed, law_instance, refuse_sample_weight
    from bouncelab.fitting.tasks import map_tasks
    from bouncelab.laws import law_name

    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "cross_validate")
    seed = check_seed(seed)
    setting = _settings_of(data)
    n_groups = len(pd.unique(setting))
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or not 2 <= k <= n_groups:
        raise FitError(f"k must be an integer between 2 and the number of settings ({n_groups}); got {k!r}",
                       law=law_name(law), option="k")
    try:
        splitter = GroupKFold(n_splits=k, shuffle=True, random_state=seed % 2**32)
    except TypeError:  # scikit-learn < 1.6 has no shuffling GroupKFold: shuffle the group labels instead
        splitter = GroupKFold(n_splits=k)
        uniq = pd.unique(setting)
        perm = dict(zip(uniq, np.random.default_rng(seed).permutation(len(uniq)), strict=True))
        setting = np.array([perm[s] for s in setting])
    folds = splitter.split(np.zeros(len(setting)), groups=setting)
    tasks = [(i + 1, law, data.isel(bounce=tr), data.isel(bounce=te), seed, fit_kwargs)
             for i, (tr, te) in enumerate(folds)]
    rows = map_tasks(_fold, tasks, executor)
    return CrossValidation(folds=pd.DataFrame(rows).set_index("fold"), law=law_name(law))


def _fold(task: tuple) -> dict[str, Any]:
    """One fold of :func:`cross_validate` (a module-level function, so executors can pickle it)."""
    from bouncelab.fitting.fitter import fit

    i, law, train, test, seed, fit_kwargs = task
    res = fit(law, train, test=test, seed=seed, **fit_kwargs)
    return {"fold": i, "n_train": res.n_train, "n_test": res.n_test, "train_delta": res.delta,
            "test_delta": res.test_delta,
            **{f"test_{c}": v for c, v in zip(("delta_xdot", "delta_ydot", "delta_omega"), res.test_delta_q,
                                              strict=True)},
            **{f"test_{key}": v for key, v in res.test_diagnostics.items()}}
