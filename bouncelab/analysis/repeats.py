"""Repeatability of bounces launched with the same launcher setting.

The paper (Methods, "Repeatability") repeats each launcher setting 6 or 12
times and, "for each test condition, the mean and 95 % CI's on the mean were
calculated for each quantity (horizontal velocity xdot, vertical velocity ydot
and spin omega), both on their inbound and on outbound measurements". Those
means and intervals are the circles and error bars of its Appendix Fig. 9, and
the Discussion observes that "in the majority of cases, the confidence
intervals on the outbound measurements are wider than those on inbound" --
the turf adds variability of its own to that of the launcher.

:func:`repeatability` computes the per-setting means and Student-t intervals;
:func:`repeatability_summary` puts a number on the Discussion's observation.

All quantities are in the paper's scaled units: ``xdot`` and ``ydot`` in ball
radii per second, ``omega`` in rad/s.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr
from scipy import stats

from bouncelab.core import checks
from bouncelab.core.errors import DataError, Hint
from bouncelab.core.units import COMPONENTS
from bouncelab.data.campaign import setting_labels
from bouncelab.data.inputs import campaign_arrays

__all__ = ["STATES", "repeatability", "repeatability_summary"]

#: Labels of the ``state`` dimension of :func:`repeatability`: before touch-down and after lift-off.
STATES = ("landing", "liftoff")

_UNITS = "radius/s (xdot, ydot), rad/s (omega)"
_COMPONENT_UNIT = {"xdot": "radius/s", "ydot": "radius/s", "omega": "rad/s"}


def repeatability(
    data: Any,
    *,
    level: float = 0.95,
    settings: Sequence[Any] | np.ndarray | None = None,
    infer: bool = True,
) -> xr.Dataset:
    """Mean and Student-t confidence interval of the mean of each quantity, per launcher setting.

    For the ``n`` bounces of one setting and one quantity ``q`` (``xdot``,
    ``ydot`` or ``omega``, at landing or at lift-off):

    .. math::

        \\bar q = \\frac1n \\sum_i q_i, \\qquad
        s = \\sqrt{\\frac{1}{n-1} \\sum_i (q_i - \\bar q)^2}, \\qquad
        h = t_{(1+\\mathrm{level})/2,\\; n-1} \\, \\frac{s}{\\sqrt n},

    and the interval is ``[q_bar - h, q_bar + h]``, where ``t_{p, nu}`` is the
    ``p`` quantile of Student's t distribution with ``nu`` degrees of freedom
    (:func:`scipy.stats.t.ppf`). This is the paper's "95 % CI on the mean"
    (section "Repeatability"), plotted as error bars in its Appendix Fig. 9.
    ``s`` and ``h`` are NaN for a setting with a single bounce.

    Parameters
    ----------
    data
        A campaign Dataset, or a ``(landing, liftoff)`` or
        ``(landing, liftoff, setting)`` tuple of (n, 3) arrays in scaled units.
    level
        Confidence level of the intervals, in (0, 1); default 0.95 (the paper's).
    settings
        Launcher setting label (int or str) of each bounce, length n. Overrides
        the data's ``setting`` coordinate when given.
    infer
        When neither ``settings`` nor a ``setting`` coordinate is available,
        infer the settings by clustering the landing conditions
        (:func:`bouncelab.data.settings.infer_settings` with its defaults) and
        warn; with ``infer=False`` raise instead.

    Returns
    -------
    xarray.Dataset
        Dimensions ``("setting", "state", "component")`` with coordinates
        ``setting`` (the labels, sorted; in order of first appearance if they
        cannot be sorted), ``state = ["landing", "liftoff"]`` and
        ``component = ["xdot", "ydot", "omega"]``. Variables, all in scaled
        units (radii/s for ``xdot``, ``ydot``; rad/s for ``omega``):

        ``mean`` (setting, state, component)
            Mean over the repeats.
        ``std`` (setting, state, component)
            Sample standard deviation (``ddof=1``); NaN when ``n < 2``.
        ``half_width`` (setting, state, component)
            ``t_{(1+level)/2, n-1} * std / sqrt(n)``; NaN when ``n < 2``.
        ``ci_low``, ``ci_high`` (setting, state, component)
            ``mean -+ half_width``.
        ``n`` (setting)
            Number of bounces with that setting.

        attrs: the campaign's attrs (for a Dataset), ``level`` and
        ``settings_source``: ``"data"`` (the ``setting`` coordinate),
        ``"argument"`` (the ``settings`` argument) or
        ``"inferred by clustering"``.

    Raises
    ------
    DataError
        Bad campaign or arrays, a ``level`` outside (0, 1), a ``settings`` of
        the wrong length or with missing labels, or no settings with
        ``infer=False``.

    Warns
    -----
    UserWarning
        When the settings are inferred by clustering.

    Examples
    --------
    >>> import bouncelab as bl
    >>> rep = repeatability(bl.load_campaign("A"))
    >>> dict(rep.sizes)
    {'setting': 55, 'state': 2, 'component': 3}
    >>> int(rep["n"].sel(setting=1))
    6
    """
    level = _check_level(level)
    p0, pf, setting = campaign_arrays(data)
    n_bounces = p0.shape[0]
    if n_bounces == 0:
        raise DataError("the data hold no bounces", option="data")
    if settings is not None:
        labels = setting_labels(settings, n_bounces)
        source = "argument"
    elif setting is not None:
        labels = setting_labels(setting, n_bounces)
        source = "data"
    elif infer:
        from bouncelab.data.settings import infer_settings

        labels = infer_settings(data)
        source = "inferred by clustering"
        warnings.warn(
            f"the data have no 'setting' coordinate: {len(np.unique(labels))} launcher settings were inferred "
            "by clustering the landing conditions (bouncelab.infer_settings); pass settings=... to use known ones",
            UserWarning,
            stacklevel=2,
        )
    else:
        raise DataError(
            "the data have no 'setting' coordinate (launcher setting of each bounce) and infer=False: add the "
            "coordinate", column="setting", option="infer",
            hints=[Hint("settings", None, "one label per bounce"), Hint("infer", True, "to cluster them")]
        )

    uniq = _setting_order(labels)
    states = np.stack([p0, pf], axis=1)  # (n, state, component)
    k = len(uniq)
    mean = np.empty((k, len(STATES), len(COMPONENTS)))
    std = np.full_like(mean, np.nan)
    half = np.full_like(mean, np.nan)
    counts = np.empty(k, dtype=np.int64)
    for i, lab in enumerate(uniq):
        members = states[labels == lab]
        m = members.shape[0]
        counts[i] = m
        mean[i] = members.mean(axis=0)
        if m >= 2:
            std[i] = members.std(axis=0, ddof=1)
            half[i] = stats.t.ppf((1.0 + level) / 2.0, m - 1) * std[i] / np.sqrt(m)

    dims = ("setting", "state", "component")

    def var(values: np.ndarray, long_name: str) -> tuple[tuple[str, ...], np.ndarray, dict[str, str]]:
        return dims, values, {"long_name": long_name, "units": _UNITS}

    attrs: dict[str, Any] = dict(data.attrs) if isinstance(data, xr.Dataset) else {}
    attrs.update({"level": float(level), "settings_source": source})
    return xr.Dataset(
        {
            "mean": var(mean, "mean over the repeats of a launcher setting"),
            "std": var(std, "sample standard deviation over the repeats (ddof=1)"),
            "half_width": var(half, f"half-width of the {level:.3g} Student-t confidence interval of the mean"),
            "ci_low": var(mean - half, "lower end of the confidence interval of the mean"),
            "ci_high": var(mean + half, "upper end of the confidence interval of the mean"),
            "n": ("setting", counts, {"long_name": "number of bounces with the setting"}),
        },
        coords={
            "setting": ("setting", uniq, {"long_name": "launcher setting"}),
            "state": ("state", list(STATES)),
            "component": ("component", list(COMPONENTS)),
        },
        attrs=attrs,
    )


def repeatability_summary(rep: xr.Dataset) -> pd.DataFrame:
    """How much wider the lift-off confidence intervals are than the landing ones.

    Quantifies the paper's Discussion: "in the majority of cases, the
    confidence intervals on the outbound measurements are wider than those on
    inbound", which it reads as the turf's response not being fully
    deterministic. Only settings with at least two bounces (finite
    half-widths at both states) are compared.

    Parameters
    ----------
    rep
        The result of :func:`repeatability`.

    Returns
    -------
    pandas.DataFrame
        One row per component (``xdot``, ``ydot``, ``omega``) and a row
        ``all`` pooling the three, with columns

        ``unit``
            Unit of the half-widths in that row: ``"radius/s"`` (``xdot``,
            ``ydot``), ``"rad/s"`` (``omega``), ``"mixed"`` (``all``).
        ``median_half_width_landing``, ``median_half_width_liftoff``
            Median over the settings of the CI half-width ``h`` at landing and
            at lift-off, in the row's unit. The ``all`` row has none (NaN): a
            median over values in different units would mean nothing. Its
            ratio and fraction, which have no unit, pool the three components.
        ``median_ratio``
            Median over the settings of ``h_liftoff / h_landing`` (NaN where
            ``h_landing = 0``, and ignored then).
        ``fraction_liftoff_wider``
            Fraction of the compared settings where ``h_liftoff > h_landing``
            (strictly); the paper's "majority of cases" is a fraction above 0.5.
        ``n_compared``
            Number of settings compared (those with ``n >= 2``).

        attrs: ``level`` and ``campaign`` (when known).

    Raises
    ------
    DataError
        If ``rep`` is not a :func:`repeatability` result.
    """
    if not isinstance(rep, xr.Dataset) or "half_width" not in rep.data_vars:
        raise DataError("repeatability_summary needs the Dataset returned by repeatability() (with 'half_width')",
                        option="rep")
    hw = rep["half_width"]
    if set(hw.dims) != {"setting", "state", "component"}:
        raise DataError(f"'half_width' must have dimensions (setting, state, component); got {hw.dims}",
                        column="half_width", option="rep")
    have_states = [str(s) for s in rep["state"].values]
    if not set(STATES) <= set(have_states):
        raise DataError(f"the 'state' coordinate must hold {list(STATES)}; got {have_states}", column="state",
                        option="rep")
    comps = [str(c) for c in rep["component"].values]
    land = hw.sel(state="landing").transpose("setting", "component").values
    lift = hw.sel(state="liftoff").transpose("setting", "component").values
    ok = np.isfinite(land) & np.isfinite(lift)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(ok & (land > 0), lift / land, np.nan)
    wider = (lift > land) & ok

    def row(cols: np.ndarray | slice, medians: bool) -> dict[str, float | int]:
        okc, r, w = ok[:, cols], ratio[:, cols], wider[:, cols]
        n_cmp = int(okc.sum())
        return {
            "median_half_width_landing": _nanmedian(land[:, cols][okc]) if medians else np.nan,
            "median_half_width_liftoff": _nanmedian(lift[:, cols][okc]) if medians else np.nan,
            "median_ratio": _nanmedian(r[okc]),
            "fraction_liftoff_wider": float(w.sum() / n_cmp) if n_cmp else np.nan,
            "n_compared": n_cmp,
        }

    rows = {c: {"unit": _COMPONENT_UNIT.get(c, ""), **row(np.array([j]), True)} for j, c in enumerate(comps)}
    rows["all"] = {"unit": "mixed", **row(slice(None), False)}
    out = pd.DataFrame.from_dict(rows, orient="index")
    out.index.name = "component"
    out["n_compared"] = out["n_compared"].astype(np.int64)
    out.attrs["level"] = rep.attrs.get("level", np.nan)
    if "campaign" in rep.attrs:
        out.attrs["campaign"] = rep.attrs["campaign"]
    return out


def _nanmedian(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return float(np.median(values)) if values.size else float("nan")


def _check_level(level: float) -> float:
    return checks.fraction(level, "level", error=DataError)


def _setting_order(labels: np.ndarray) -> np.ndarray:
    """Distinct labels, sorted when they can be, otherwise in order of first appearance."""
    try:
        return np.unique(labels)
    except TypeError:  # pragma: no cover - _check_settings leaves only ints, floats, bools or strings
        return pd.unique(labels)
