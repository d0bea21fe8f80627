"""``bouncelab.compare``: fit several laws to one campaign and lay them out as the paper's tables."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.data import published
from bouncelab.errors import FitError
from bouncelab.fitting.fitter import fit
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.splits import split_by_setting
from bouncelab.laws.base import BounceModel, registered_laws
from bouncelab.metrics import ERROR_COLUMNS

__all__ = ["PAPER_LAWS", "Comparison", "compare"]

#: The paper's four laws, in the order of its Tables 3 and 2.
PAPER_LAWS = ("Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine")
_PARAM_COLUMNS = ("r", "mu", "k_p", "beta_deg", "e_t")
_LABELS = {"beta_deg": "beta [deg]", "k_p": "k_p [s/radius]", "delta_xdot": "Delta xdot", "delta_ydot": "Delta ydot",
           "delta_omega": "Delta omega", "mismatched": "mismatched", "n": "bounces"}


@dataclass
class Comparison:
    """Fits of several laws to one campaign, as labelled tables.

    Attributes
    ----------
    results
        Law name -> :class:`~bouncelab.FitResult`.
    table
        One row per law: scalar parameters, then delta and Delta q on the fitted
        data (``train_*``) and, with a split, on the held-out data (``test_*``).
        Fractions, not per cent.
    campaign
        "A" or "B" when the data are (a surrogate of) one of the paper's campaigns, else None.
    """

    results: dict[str, FitResult]
    table: pd.DataFrame
    campaign: str | None = None
    split: str | None = None
    notes: list[str] = field(default_factory=list)

    def piecewise_table(self) -> pd.DataFrame | None:
        """The Table 2 layout for the piecewise law: errors overall, on roll and on slip, and mismatched."""
        res = self.results.get("PiecewiseAffine")
        if res is None:
            return None
        which = "test" if res.n_test else "train"
        t = res.errors.loc[which].loc[:, ["n", *ERROR_COLUMNS]].rename(index={"all": "overall"})
        t["mismatched"] = np.nan
        t.loc["overall", "mismatched"] = res.test_mismatched if res.n_test else res.mismatched
        t.attrs["data"] = which
        return t

    def published(self) -> pd.DataFrame | None:
        """The paper's published values for the same laws (Table 3, and Table 2's overall delta)."""
        if self.campaign is None:
            return None
        rows = {}
        for law in self.table.index:
            if law in published.TABLE3.loc[self.campaign].index:
                rows[law] = published.TABLE3.loc[(self.campaign, law)]
            elif law == "PiecewiseAffine":
                t2 = published.TABLE2.loc[self.campaign]
                rows[law] = pd.Series({"delta": t2.loc["overall", "delta"]})  # Table 2 has no overall Delta q
        out = pd.DataFrame(rows).T.reindex(columns=[c for c in (*_PARAM_COLUMNS, *ERROR_COLUMNS)
                                                    if c in published.TABLE3.columns or c in ERROR_COLUMNS])
        out.index.name = "law"
        return out

    def side_by_side(self) -> pd.DataFrame:
        """Our values beside the paper's: columns (quantity, source) with source "bouncelab" and "paper"."""
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in ERROR_COLUMNS})
        cols = [c for c in (*_PARAM_COLUMNS, *ERROR_COLUMNS) if c in ours.columns]
        frames = {"bouncelab": ours[cols]}
        paper = self.published()
        if paper is not None:
            frames["paper"] = paper.reindex(index=ours.index, columns=cols)
        out = pd.concat(frames, axis=1).swaplevel(axis=1)
        return out.reindex(columns=pd.MultiIndex.from_product([cols, list(frames)]))

    def _which(self) -> str:
        return "test" if self.split else "train"

    def to_markdown(self, digits: int = 3) -> str:
        """The comparison as markdown, laid out as the paper's Tables 3 and 2.

        Rows are quantities and columns laws; each cell reads ``ours (paper)``
        where the paper published a value. Errors are in per cent, as printed in the paper.
        """
        title = f"campaign {self.campaign}" if self.campaign else "this campaign"
        which = "held-out" if self.split else "fitted"
        paper = self.published()
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in ERROR_COLUMNS})
        quantities = [c for c in (*_PARAM_COLUMNS, *ERROR_COLUMNS) if c in ours.columns and ours[c].notna().any()]
        lines = [f"### Laws fitted to {title} (errors on the {which} bounces; the paper's values in brackets)\n"]
        lines.append("| quantity | " + " | ".join(ours.index) + " |")
        lines.append("|---|" + "---|" * len(ours.index))
        for q in quantities:
            cells = []
            for law in ours.index:
                cell = _fmt(ours.loc[law, q], q, digits)
                if cell and paper is not None and law in paper.index and q in paper.columns:
                    ref = _fmt(paper.loc[law, q], q, digits)
                    cell += f" ({ref})" if ref else ""
                cells.append(cell)
            lines.append(f"| {_LABELS.get(q, q)} | " + " | ".join(cells) + " |")
        pw = self.piecewise_table()
        if pw is not None:
            lines.append(f"\n### Piecewise-affine law by class (Table 2 layout; errors on the {pw.attrs['data']} "
                         "bounces, the paper's in brackets)\n")
            t2 = published.TABLE2.loc[self.campaign] if self.campaign else None
            cols = ["overall", "roll", "slip"]
            lines.append("| quantity | " + " | ".join(cols) + " |")
            lines.append("|---|" + "---|" * len(cols))
            for q in ("n", *ERROR_COLUMNS, "mismatched"):
                cells = []
                for sub in cols:
                    cell = _fmt(pw.loc[sub, q], q, digits) if sub in pw.index else ""
                    if cell and t2 is not None and q != "n":
                        ref = _fmt(t2.loc[sub, q], q, digits)
                        cell += f" ({ref})" if ref else ""
                    cells.append(cell)
                lines.append(f"| {_LABELS.get(q, q)} | " + " | ".join(cells) + " |")
        for note in self.notes:
            lines.append(f"\n> {note}")
        return "\n".join(lines) + "\n"

    def __repr__(self) -> str:
        return f"Comparison({list(self.results)}, campaign={self.campaign!r}, split={self.split!r})"

    def _repr_markdown_(self) -> str:
        return self.to_markdown()


def _fmt(v: Any, name: str, digits: int) -> str:
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and np.isnan(v)):
        return ""
    if name in (*ERROR_COLUMNS, "mismatched"):
        return f"{100 * v:.{digits}g} %"
    if name == "n":
        return f"{int(v)}"
    return f"{v:.{digits}g}"


def _law_instance(law: Any) -> BounceModel:
    if isinstance(law, str):
        known = registered_laws()
        if law not in known:
            raise FitError(f"unknown law {law!r}; known laws: {sorted(known)}")
        return known[law]()
    if isinstance(law, type) and issubclass(law, BounceModel):
        return law()
    if isinstance(law, BounceModel):
        return law
    raise FitError(f"laws must be names, classes or instances of bounce laws; got {law!r}")


def compare(
    data: xr.Dataset | Any,
    laws: Sequence[Any] = PAPER_LAWS,
    *,
    split: str | None = None,
    seed: int = 0,
    **fit_kwargs: Any,
) -> Comparison:
    """Fit several laws to the same bounces and tabulate them as the paper's Tables 3 and 2.

    Parameters
    ----------
    data
        A campaign Dataset (or ``(landing, liftoff)`` pair).
    laws
        Law names, classes or instances (default: the paper's four laws).
    split
        None: fit and score on all bounces (as the paper's Table 3).
        ``"setting"``: the paper's validation split (one bounce per launcher
        setting held out, :func:`~bouncelab.split_by_setting`); laws are fitted
        on the rest and scored on both (as its Table 2).
    seed
        Seed of the split and of every fit.
    **fit_kwargs
        Passed to :func:`bouncelab.fit` for every law (e.g. ``objective``).

    Examples
    --------
    >>> import bouncelab as bl
    >>> cmp = bl.compare(bl.load_campaign("A"), ["Rigid", "PennerFixed"])
    >>> print(cmp.to_markdown())  # doctest: +SKIP
    """
    if split not in (None, "setting"):
        raise FitError(f"split must be None or 'setting'; got {split!r}")
    models = [_law_instance(law) for law in laws]
    if not models:
        raise FitError("give at least one law to compare")
    names = [type(m).__name__ for m in models]
    if len(set(names)) != len(names):
        raise FitError(f"each law may appear once; got {names}")
    train, test = (split_by_setting(data, seed) if split == "setting" else (data, None))
    results, rows = {}, {}
    for name, model in zip(names, models, strict=True):
        res = fit(model, train, test=test, seed=seed, **fit_kwargs)
        results[name] = res
        row = {p: v for p, v in res.model.parameters.items() if p in _PARAM_COLUMNS}
        for prefix, table in (("train", "train"), ("test", "test")):
            if table in res.errors.index.get_level_values(0):
                for c in ERROR_COLUMNS:
                    row[f"{prefix}_{c}"] = res.errors.loc[(table, "all"), c]
        rows[name] = row
    table = pd.DataFrame(rows).T
    table = table.reindex(columns=[c for c in (*_PARAM_COLUMNS, *[f"{p}_{c}" for p in ("train", "test")
                                                                    for c in ERROR_COLUMNS])
                                   if c in table.columns])
    table.index.name = "law"
    campaign = None
    if isinstance(data, xr.Dataset) and str(data.attrs.get("campaign", "")).upper() in published.CAMPAIGNS:
        campaign = str(data.attrs["campaign"]).upper()
    notes = []
    if isinstance(data, xr.Dataset) and data.attrs.get("data_kind") == "synthetic surrogate":
        notes.append("These bounces are a synthetic surrogate made from the paper's published piecewise-affine "
                     "law, not the paper's measurements: agreement with the paper's numbers is expected only "
                     "roughly.")
    return Comparison(results=results, table=table, campaign=campaign, split=split, notes=notes)
