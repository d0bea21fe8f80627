"""``bouncelab.compare``: fit several laws to one campaign and lay them out as the paper's tables.

Everything law-specific comes from the laws: their parameters (scalars get a
column each, arrays a one-line summary), their diagnostics, and, for the
paper's campaigns, the values the paper published for laws of those names.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.data import published
from bouncelab.data.campaign import synthetic_warning
from bouncelab.errors import FitError
from bouncelab.fitting.fitter import check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.splits import split_by_setting
from bouncelab.fitting.tasks import map_tasks
from bouncelab.laws.base import BounceModel, law_name
from bouncelab.metrics import ERROR_COLUMNS

__all__ = ["PAPER_LAWS", "Comparison", "compare", "law_instance"]

#: The paper's four laws, in the order of its Tables 3 and 2.
PAPER_LAWS = ("Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine")
_LABELS = {"delta_xdot": "Delta xdot", "delta_ydot": "Delta ydot", "delta_omega": "Delta omega", "n": "bounces"}


@dataclass
class Comparison:
    """Fits of several laws to one campaign, as labelled tables.

    Attributes
    ----------
    results
        Law name -> :class:`~bouncelab.FitResult`.
    table
        One row per law: its parameters (scalars as numbers, arrays summarised as
        text), then delta and Delta q on the fitted data (``train_*``) and, with a
        split, on the held-out data (``test_*``), then the laws' diagnostics
        (``train_<name>``, ``test_<name>``). Fractions, not per cent.
    campaign
        "A" or "B" when the data are (a surrogate of) one of the paper's campaigns, else None.
    """

    results: dict[str, FitResult]
    table: pd.DataFrame
    campaign: str | None = None
    split: str | None = None
    notes: list[str] = field(default_factory=list)
    units: dict[str, str] = field(default_factory=dict)

    def _which(self) -> str:
        return "test" if self.split else "train"

    def parameter_columns(self) -> list[str]:
        """Columns of :attr:`table` that hold parameters."""
        err = {f"{p}_{c}" for p in ("train", "test") for c in ERROR_COLUMNS}
        diag = {f"{p}_{k}" for r in self.results.values() for p in ("train", "test")
                for k in (*r.diagnostics, *r.test_diagnostics)}
        return [c for c in self.table.columns if c not in err and c not in diag]

    def _diagnostic_names(self) -> list[str]:
        names: list[str] = []
        for r in self.results.values():
            for k in (r.test_diagnostics if self.split else r.diagnostics):
                if k not in names:
                    names.append(k)
        return names

    def by_class(self, law: str) -> pd.DataFrame:
        """The Table 2 layout for one law: errors overall, on roll and on slip, and its diagnostics (overall).

        On the held-out bounces with a split, else on the fitted ones.
        """
        if law not in self.results:
            raise FitError(f"no law {law!r} in this comparison; it has {list(self.results)}")
        res = self.results[law]
        which = self._which()
        t = res.errors.loc[which].loc[:, ["n", *ERROR_COLUMNS]].rename(index={"all": "overall"})
        diags = res.test_diagnostics if which == "test" else res.diagnostics
        for key, value in diags.items():
            t[key] = np.nan
            t.loc["overall", key] = value
        t.attrs["data"] = which
        return t

    def published(self) -> pd.DataFrame | None:
        """The paper's published values for the same laws (Table 3, and Table 2's overall figures)."""
        if self.campaign is None:
            return None
        rows = {law: published.paper_values(self.campaign, law) for law in self.table.index}
        out = pd.DataFrame(rows).T
        out = out.reindex(index=list(self.table.index))
        out.index.name = "law"
        return out

    def side_by_side(self) -> pd.DataFrame:
        """Our values beside the paper's: columns (quantity, source) with source "bouncelab" and "paper"."""
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in (*ERROR_COLUMNS,
                                                                              *self._diagnostic_names())})
        cols = [c for c in (*self.parameter_columns(), *ERROR_COLUMNS, *self._diagnostic_names()) if c in ours.columns]
        frames = {"bouncelab": ours[cols]}
        paper = self.published()
        if paper is not None:
            frames["paper"] = paper.reindex(index=ours.index, columns=cols)
        out = pd.concat(frames, axis=1).swaplevel(axis=1)
        return out.reindex(columns=pd.MultiIndex.from_product([cols, list(frames)]))

    def _label(self, q: str) -> str:
        unit = self.units.get(q, "1")
        return _LABELS.get(q, q if unit == "1" or q.endswith(f" [{unit}]") else f"{q} [{unit}]")

    def to_markdown(self, digits: int = 3) -> str:
        """The comparison as markdown, laid out as the paper's Tables 3 and 2.

        Rows are quantities and columns laws; each cell reads ``ours (paper)``
        where the paper published a value. Errors and fractions are in per cent,
        as printed in the paper. Every law with diagnostics also gets its table by
        slip/roll class (the Table 2 layout).
        """
        title = f"campaign {self.campaign}" if self.campaign else "this campaign"
        which = "held-out" if self.split else "fitted"
        paper = self.published()
        diag = self._diagnostic_names()
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in (*ERROR_COLUMNS, *diag)})
        quantities = [c for c in (*self.parameter_columns(), *ERROR_COLUMNS, *diag)
                      if c in ours.columns and ours[c].notna().any()]
        brackets = "; the paper's values in brackets" if paper is not None else ""
        lines = [f"### Laws fitted to {title} (errors on the {which} bounces{brackets})\n"]
        lines.append("| quantity | " + " | ".join(ours.index) + " |")
        lines.append("|---|" + "---|" * len(ours.index))
        for q in quantities:
            cells = []
            for law in ours.index:
                cell = _fmt(ours.loc[law, q], q, digits, percent=q in ERROR_COLUMNS or q in diag)
                if cell and paper is not None and law in paper.index and q in paper.columns:
                    ref = _fmt(paper.loc[law, q], q, digits, percent=q in ERROR_COLUMNS or q in diag)
                    cell += f" ({ref})" if ref else ""
                cells.append(cell)
            lines.append(f"| {self._label(q)} | " + " | ".join(cells) + " |")
        for law, res in self.results.items():
            if not (res.test_diagnostics if self.split else res.diagnostics):
                continue
            t = self.by_class(law)
            ref = None if self.campaign is None else published.paper_by_class(self.campaign, law)
            brackets = ", the paper's in brackets" if ref is not None else ""
            lines.append(f"\n### {law} by class (Table 2 layout; errors on the {t.attrs['data']} bounces"
                         f"{brackets})\n")
            cols = ["overall", "roll", "slip"]
            lines.append("| quantity | " + " | ".join(cols) + " |")
            lines.append("|---|" + "---|" * len(cols))
            extra = [c for c in t.columns if c not in ("n", *ERROR_COLUMNS)]
            for q in ("n", *ERROR_COLUMNS, *extra):
                cells = []
                for sub in cols:
                    cell = _fmt(t.loc[sub, q], q, digits, percent=q != "n") if sub in t.index else ""
                    if cell and ref is not None and q != "n" and q in ref.columns and sub in ref.index:
                        r = _fmt(ref.loc[sub, q], q, digits, percent=True)
                        cell += f" ({r})" if r else ""
                    cells.append(cell)
                lines.append(f"| {self._label(q)} | " + " | ".join(cells) + " |")
        for note in self.notes:
            lines.append(f"\n> {note}")
        return "\n".join(lines) + "\n"

    def __repr__(self) -> str:
        return f"Comparison({list(self.results)}, campaign={self.campaign!r}, split={self.split!r})"

    def _repr_markdown_(self) -> str:
        return self.to_markdown()


def _fmt(v: Any, name: str, digits: int, *, percent: bool = False) -> str:
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and np.isnan(v)):
        return ""
    if name == "n":
        return f"{int(v)}"
    if percent:
        return f"{100 * v:.{digits}g} %"
    return f"{v:.{digits}g}"


def _summarise(value: Any) -> Any:
    """A table cell for a parameter: the number, or a one-line text for an array."""
    if value is None:
        return np.nan
    if np.ndim(value) == 0:
        return float(value)
    return np.array2string(np.asarray(value), separator=", ", max_line_width=10_000,
                           formatter={"float_kind": lambda v: f"{v:.3g}"}).replace("\n", "")


def compare(
    data: xr.Dataset | Any,
    laws: Sequence[Any] = PAPER_LAWS,
    *,
    split: str | None = None,
    seed: int = 0,
    executor: Any = None,
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
    executor
        Where to run the fits (see :func:`bouncelab.fitting.tasks.map_tasks`); serially by default.
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
    seed = check_seed(seed)
    if isinstance(laws, str | BounceModel) or isinstance(laws, type):
        laws = [laws]
    models = [law_instance(law) for law in laws]
    if not models:
        raise FitError("give at least one law to compare")
    names = [law_name(m) for m in models]
    if len(set(names)) != len(names):
        raise FitError(f"each law may appear once; got {names}")
    if split is not None:
        refuse_sample_weight(fit_kwargs, "compare(split='setting')")
    train, test = (split_by_setting(data, seed) if split == "setting" else (data, None))
    fits = map_tasks(_fit_task, [(m, train, test, seed, fit_kwargs) for m in models], executor)
    results = dict(zip(names, fits, strict=True))
    # A parameter name carried in different units by different laws gets a column per unit: the
    # plain name keeps the unit of bouncelab's own law that has it (so the paper's values stay beside
    # it), else of the first law; the others are named "name [unit]".
    plain: dict[str, str] = {}
    for res in sorted(results.values(), key=lambda r: ":" in law_name(r.model)):  # bouncelab's own first
        for pname, p in res.model.params.items():
            plain.setdefault(pname, p.unit)
    rows, units = {}, {}
    for name, res in results.items():
        row: dict[str, Any] = {}
        for pname, p in res.model.params.items():
            col = pname if p.unit == plain[pname] else f"{pname} [{p.unit}]"
            row[col] = _summarise(p.value)
            units[col] = p.unit
        for prefix in ("train", "test"):
            if prefix in res.errors.index.get_level_values(0):
                for c in ERROR_COLUMNS:
                    row[f"{prefix}_{c}"] = res.errors.loc[(prefix, "all"), c]
        row.update({f"train_{k}": v for k, v in res.diagnostics.items()})
        row.update({f"test_{k}": v for k, v in res.test_diagnostics.items()})
        rows[name] = row
    table = pd.DataFrame.from_dict(rows, orient="index")
    params = [c for c in table.columns if c in units]
    errs = [f"{p}_{c}" for p in ("train", "test") for c in ERROR_COLUMNS if f"{p}_{c}" in table.columns]
    rest = [c for c in table.columns if c not in params and c not in errs]
    table = table[params + errs + rest]
    table.index.name = "law"
    campaign = None
    if isinstance(data, xr.Dataset) and str(data.attrs.get("campaign", "")).upper() in published.CAMPAIGNS:
        campaign = str(data.attrs["campaign"]).upper()
    notes = []
    objectives = sorted({res.objective for res in results.values()} - {"delta"})
    if objectives:  # the errors beside the paper's are its measures; the fits minimised something else
        notes.append(f"Fitted by minimising {', '.join(objectives)}, not the paper's delta; the errors shown are the "
                     "paper's unweighted delta and Delta q of those fits.")
    note = synthetic_warning(data)  # the data say what made them (published laws, a simulation, rendered clips)
    if note is not None:
        if campaign is not None:
            note += " Agreement with the paper's numbers for its measured campaign is expected only roughly."
        notes.append(note)
    return Comparison(results=results, table=table, campaign=campaign, split=split, notes=notes, units=units)


def _fit_task(task: tuple) -> FitResult:
    """One law's fit in :func:`compare` (a module-level function, so executors can pickle it)."""
    model, train, test, seed, fit_kwargs = task
    return fit(model, train, test=test, seed=seed, **fit_kwargs)
