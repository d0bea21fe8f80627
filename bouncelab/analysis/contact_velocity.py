"""Analysis of measured bounces: the velocity of the contact point at landing and lift-off (the paper's Fig. 7).

(Not to be confused with :mod:`bouncelab.laws.tangential_restitution`, a bounce law.)

The paper (Methods, "Distinguishing between slipping and rolling") follows the
velocity of the lowest point ``P`` of the ball,

.. math:: v_P = \\dot x + \\omega

in scaled units (radii/s; ``omega`` in rad/s, anticlockwise, so backspin is
positive for a ball moving in +x). ``v_P0`` is its value just before
touch-down and ``v_PF`` just after lift-off. A bounce *slips* throughout when
``v_P0`` and ``v_PF`` have the same non-zero sign; in every other case the
ball must have entered *rolling* (``v_P = 0``) at some point.

Its Results (section "Piecewise linear model slipping and rolling", Fig. 7)
and Discussion make observations that :func:`tangential_summary` counts:

* "balls seem rarely, if ever, to lift off in a state of rolling. There is
  always some slip at lift off": lift-offs with ``|v_PF|`` near zero
  (``near_zero_liftoff``) should be few;
* "a clear separation between those samples that lift off with positive
  tangential velocity from those with negative": ``liftoff_positive`` and
  ``liftoff_negative``;
* "The cases with v_p > 0 correspond to cases with high initial backspin. In
  such cases, the ball slips throughout the impact and lifts off with
  backspin again": ``backspin_slip`` (``v_P > 0`` at both ends);
* "the cases with v_p < 0 at lift-off tend to occur when either the ball
  landed with high topspin (v_p < 0 both at impact and lift-off)":
  ``topspin_slip``;
* "or where at some point during the bounce phase the ball entered rolling
  ... It is only the final of these cases that we refer to as a 'rolling'
  trajectory", and the Discussion: "balls that enter rolling during the bounce
  enter slip in the opposite sense, prior to take-off" and "balls lifting off
  with reversed tangential velocity; a behaviour not possible under the
  rigid-bounce theory": ``vp_reversal`` (the sign of ``v_P`` changes).

The paper's parenthesis for the rolling case reads "v_p < 0 initially, but
v_p > 0 at lift off", which contradicts the sentence it sits in (about
lift-offs with ``v_p < 0``) and the physics (friction drives a backspin
landing's ``v_P > 0`` towards zero); in the embedded surrogate campaigns, as
expected, almost all reversals go from ``v_P0 > 0`` to ``v_PF < 0``. Both
directions are counted separately (``vp_reversal_pos_to_neg``,
``vp_reversal_neg_to_pos``).

The names "topspin" and "backspin" assume travel in +x, as in the paper.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core.errors import DataError
from bouncelab.core.slip_roll import classify_slip_roll
from bouncelab.data.inputs import campaign_arrays

__all__ = [
    "NEAR_ZERO_FRACTION",
    "SUMMARY_ROWS",
    "tangential_crosstab",
    "tangential_summary",
    "tangential_velocities",
]

#: Default ``near_zero`` of :func:`tangential_summary`, as a fraction of the campaign's mean ``|v_P0|``.
NEAR_ZERO_FRACTION = 0.02

#: Row labels of :func:`tangential_summary`, in order.
SUMMARY_ROWS = (
    "n_bounces",
    "slip",
    "roll",
    "landing_positive",
    "landing_negative",
    "landing_zero",
    "liftoff_positive",
    "liftoff_negative",
    "liftoff_zero",
    "backspin_slip",
    "topspin_slip",
    "vp_reversal",
    "vp_reversal_pos_to_neg",
    "vp_reversal_neg_to_pos",
    "vp_zero",
    "spin_reversal",
    "near_zero_liftoff",
)

_SIGN_LABELS = {-1: "negative", 0: "zero", 1: "positive"}


def tangential_velocities(data: Any) -> xr.Dataset:
    """Contact-point velocity ``v_P = xdot + omega`` of each bounce at landing and at lift-off.

    Parameters
    ----------
    data
        A campaign Dataset, or a ``(landing, liftoff)`` or
        ``(landing, liftoff, setting)`` tuple of (n, 3) arrays in scaled units.

    Returns
    -------
    xarray.Dataset
        Dimension ``bounce`` (with the campaign's ``bounce`` and ``setting``
        coordinates when present) and variables

        ``vp_landing``, ``vp_liftoff``
            ``v_P0 = xdot0 + omega0`` and ``v_PF = xdotF + omegaF``, radii/s.
        ``sign_landing``, ``sign_liftoff``
            Their signs, -1, 0 or +1 (int8); exact zeros have sign 0.
        ``slip_roll``
            ``"slip"`` or ``"roll"``, the paper's classification
            (:func:`bouncelab.classify_slip_roll`): slip when the two signs
            are equal and non-zero.
        ``vp_reversal``
            ``sign_landing * sign_liftoff < 0``: ``v_P`` changed sign (the
            ball entered rolling and lifted off slipping the other way).
        ``spin_reversal``
            ``sign(omega0) * sign(omegaF) < 0``: the spin changed sign.

        attrs: the campaign's attrs (for a Dataset).

    Raises
    ------
    DataError
        Bad campaign or arrays.
    """
    p0, pf, setting = campaign_arrays(data)
    vp0 = p0[:, 0] + p0[:, 2]
    vpf = pf[:, 0] + pf[:, 2]
    s0 = np.sign(vp0).astype(np.int8)
    sf = np.sign(vpf).astype(np.int8)
    spin_rev = (np.sign(p0[:, 2]) * np.sign(pf[:, 2])) < 0
    coords: dict[str, Any] = {}
    attrs: dict[str, Any] = {}
    if isinstance(data, xr.Dataset):
        attrs = dict(data.attrs)
        if "bounce" in data.coords:
            coords["bounce"] = ("bounce", data["bounce"].values, dict(data["bounce"].attrs))
    if "bounce" not in coords:
        coords["bounce"] = ("bounce", np.arange(p0.shape[0]))
    if setting is not None:
        coords["setting"] = ("bounce", np.asarray(setting), {"long_name": "launcher setting"})
    return xr.Dataset(
        {
            "vp_landing": ("bounce", vp0, {"long_name": "contact-point velocity xdot + omega before touch-down",
                                           "units": "radius/s"}),
            "vp_liftoff": ("bounce", vpf, {"long_name": "contact-point velocity xdot + omega after lift-off",
                                           "units": "radius/s"}),
            "sign_landing": ("bounce", s0, {"long_name": "sign of vp_landing (-1, 0, +1)"}),
            "sign_liftoff": ("bounce", sf, {"long_name": "sign of vp_liftoff (-1, 0, +1)"}),
            "slip_roll": ("bounce", classify_slip_roll(p0, pf), {"long_name": "slip/roll class (paper)"}),
            "vp_reversal": ("bounce", (s0.astype(np.int16) * sf) < 0,
                            {"long_name": "v_P changed sign between landing and lift-off"}),
            "spin_reversal": ("bounce", spin_rev, {"long_name": "omega changed sign between landing and lift-off"}),
        },
        coords=coords,
        attrs=attrs,
    )


def tangential_summary(data: Any, *, near_zero: float | None = None) -> pd.DataFrame:
    """Counts of the contact-point behaviours the paper discusses around its Fig. 7.

    With ``v_P0`` and ``v_PF`` the contact-point velocities
    ``xdot + omega`` (radii/s) at landing and at lift-off
    (:func:`tangential_velocities`), the rows count bounces with

    ``n_bounces``
        All bounces.
    ``slip`` / ``roll``
        The paper's classification: slip when ``v_P0`` and ``v_PF`` have the
        same non-zero sign, roll otherwise ("the ball must have entered rolling
        at some point").
    ``landing_positive`` / ``landing_negative`` / ``landing_zero``
        ``v_P0 > 0`` (backspin strong enough, or topspin weak enough, for the
        contact point to move forward), ``< 0`` (high topspin), ``= 0``.
    ``liftoff_positive`` / ``liftoff_negative`` / ``liftoff_zero``
        ``v_PF > 0`` / ``< 0`` / ``= 0`` exactly: Fig. 7's "clear separation
        between those samples that lift off with positive tangential velocity
        from those with negative".
    ``backspin_slip``
        ``v_P > 0`` at both ends: "high initial backspin ... the ball slips
        throughout the impact and lifts off with backspin again".
    ``topspin_slip``
        ``v_P < 0`` at both ends: "the ball landed with high topspin".
        ``backspin_slip + topspin_slip = slip``.
    ``vp_reversal``
        ``v_P0 v_PF < 0``: the sign of ``v_P`` changed, so the ball entered
        rolling and then slipped the other way before lift-off -- the paper's
        "rolling" trajectory and its Discussion's "balls that enter rolling
        during the bounce enter slip in the opposite sense" (impossible under
        the rigid-bounce model, which keeps ``v_P = 0`` once rolling).
    ``vp_reversal_pos_to_neg`` / ``vp_reversal_neg_to_pos``
        The reversals split by direction (``v_P0 > 0 > v_PF`` is the
        backspin landing that ends slipping backwards at the contact point).
    ``vp_zero``
        ``v_P0 = 0`` or ``v_PF = 0`` exactly; ``vp_reversal + vp_zero = roll``.
    ``spin_reversal``
        ``omega0 omegaF < 0``: the spin changed sign (backspin landing lifting
        off with topspin, or the reverse); exact zeros are not reversals.
    ``near_zero_liftoff``
        ``|v_PF| <= near_zero``: lift-offs close to rolling. The paper finds
        "balls seem rarely, if ever, to lift off in a state of rolling. There
        is always some slip at lift off", i.e. this count should be small.

    Parameters
    ----------
    data
        A campaign Dataset, or a ``(landing, liftoff)`` or
        ``(landing, liftoff, setting)`` tuple of (n, 3) arrays in scaled units.
    near_zero
        Threshold on ``|v_PF|`` in radii/s (inclusive, like the ``tol`` of
        :func:`bouncelab.classify_slip_roll`). Default ``None``:
        :data:`NEAR_ZERO_FRACTION` (2 %) of the campaign's mean ``|v_P0|``,
        i.e. a lift-off counts as near rolling when its contact-point speed is
        under 2 % of a typical landing one (about 26 radii/s, 0.55 m/s, on
        the embedded campaigns, comparable to their measurement-interval
        half-widths).

    Returns
    -------
    pandas.DataFrame
        Index :data:`SUMMARY_ROWS`, columns ``count`` (int) and ``fraction``
        (count / n_bounces; NaN when there are no bounces). attrs:
        ``near_zero`` (the threshold used, radii/s), ``near_zero_rule``
        (how it was chosen) and ``campaign`` (when known).

    Raises
    ------
    DataError
        Bad campaign or arrays, or a negative or non-finite ``near_zero``.

    See Also
    --------
    tangential_crosstab : the full sign(v_P0) x sign(v_PF) table.
    """
    tv = tangential_velocities(data)
    vp0 = tv["vp_landing"].values
    vpf = tv["vp_liftoff"].values
    s0 = tv["sign_landing"].values
    sf = tv["sign_liftoff"].values
    n = vp0.size
    if near_zero is None:
        threshold = NEAR_ZERO_FRACTION * float(np.mean(np.abs(vp0))) if n else 0.0
        rule = f"{NEAR_ZERO_FRACTION:g} x mean |v_P0|"
    else:
        try:
            threshold = float(near_zero)
        except (TypeError, ValueError):
            raise DataError(f"near_zero must be a non-negative speed in radii/s; got {near_zero!r}",
                            option="near_zero") from None
        if not (np.isfinite(threshold) and threshold >= 0):
            raise DataError(f"near_zero must be a non-negative speed in radii/s; got {near_zero!r}", option="near_zero")
        rule = "given"
    slip = tv["slip_roll"].values == "slip"
    rev = tv["vp_reversal"].values
    counts = {
        "n_bounces": n,
        "slip": slip.sum(),
        "roll": (~slip).sum(),
        "landing_positive": (s0 > 0).sum(),
        "landing_negative": (s0 < 0).sum(),
        "landing_zero": (s0 == 0).sum(),
        "liftoff_positive": (sf > 0).sum(),
        "liftoff_negative": (sf < 0).sum(),
        "liftoff_zero": (sf == 0).sum(),
        "backspin_slip": ((s0 > 0) & (sf > 0)).sum(),
        "topspin_slip": ((s0 < 0) & (sf < 0)).sum(),
        "vp_reversal": rev.sum(),
        "vp_reversal_pos_to_neg": ((s0 > 0) & (sf < 0)).sum(),
        "vp_reversal_neg_to_pos": ((s0 < 0) & (sf > 0)).sum(),
        "vp_zero": ((s0 == 0) | (sf == 0)).sum(),
        "spin_reversal": tv["spin_reversal"].values.sum(),
        "near_zero_liftoff": (np.abs(vpf) <= threshold).sum(),
    }
    count = pd.Series({k: int(counts[k]) for k in SUMMARY_ROWS}, dtype=np.int64)
    out = pd.DataFrame({"count": count, "fraction": count / n if n else np.nan})
    out.index.name = "category"
    out.attrs.update({"near_zero": threshold, "near_zero_rule": rule})
    if "campaign" in tv.attrs:
        out.attrs["campaign"] = tv.attrs["campaign"]
    return out


def tangential_crosstab(data: Any, *, margins: bool = True) -> pd.DataFrame:
    """Number of bounces for each pair of signs of ``v_P0`` (rows) and ``v_PF`` (columns).

    Rows and columns are ``negative``, ``zero``, ``positive`` (exact zero is
    its own sign), always all three. The diagonal ``negative``/``negative`` is
    :func:`tangential_summary`'s ``topspin_slip``, ``positive``/``positive``
    its ``backspin_slip`` (together the paper's *slip*); the off-diagonal
    corners ``positive``/``negative`` and ``negative``/``positive`` are the
    ``v_P`` reversals; every cell but those two diagonal ones is the paper's
    *roll*.

    Parameters
    ----------
    data
        A campaign Dataset, or a ``(landing, liftoff)`` pair of (n, 3) arrays.
    margins
        Add a ``total`` row and column.

    Returns
    -------
    pandas.DataFrame
        Integer counts; index named ``sign_vp_landing``, columns
        ``sign_vp_liftoff``.
    """
    tv = tangential_velocities(data)
    labels = [_SIGN_LABELS[k] for k in (-1, 0, 1)]
    s0 = pd.Categorical([_SIGN_LABELS[int(v)] for v in tv["sign_landing"].values], categories=labels)
    sf = pd.Categorical([_SIGN_LABELS[int(v)] for v in tv["sign_liftoff"].values], categories=labels)
    table = pd.crosstab(
        pd.Series(s0, name="sign_vp_landing"), pd.Series(sf, name="sign_vp_liftoff"), dropna=False
    ).reindex(index=labels, columns=labels, fill_value=0).astype(np.int64)
    table.columns = pd.Index(list(table.columns), name="sign_vp_liftoff")
    table.index = pd.Index(list(table.index), name="sign_vp_landing")
    if margins:
        table["total"] = table.sum(axis=1)
        table.loc["total"] = table.sum(axis=0)
    return table
