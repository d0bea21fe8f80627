"""``bouncelab.compare``: fit several laws to one campaign and lay them out as the paper's tables.

Everything law-specific comes from the laws: their parameters (scalars get a
column each, arrays a one-line summary), their diagnostics, and, for the
paper's campaigns, the values the paper published for laws of those names, each
only beside a figure of the same kind: Table 3's errors (the laws fitted to all
bounces) beside errors on the fitted bounces, Table 2's (the piecewise-affine law on
its test set) beside errors on held-out bounces. On a synthetic campaign the paper's
values are labelled as what they are (its results on its measured bounces, a
reference, not a validation), and the law that generated the data is marked.

Beside the errors on the fitted bounces stand, by default, the number of free
parameters and the *held-out* errors of grouped k-fold cross-validation
(:func:`bouncelab.fitting.assessment.held_out_errors`, the machinery of
:func:`bouncelab.assess`): a law with more parameters always fits its own bounces
better, and only the held-out figures say whether it predicts others better.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core import published
from bouncelab.core.errors import DataError, FitError, Hint, ParameterError
from bouncelab.data.campaign import synthetic_warning
from bouncelab.fitting.assessment import HeldOut, _fold_groups, _held_out
from bouncelab.fitting.fitter import check_count, check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.result import FitResult
from bouncelab.fitting.splits import split_by_setting
from bouncelab.fitting.tasks import map_tasks
from bouncelab.laws import law_name
from bouncelab.laws.base import BounceModel
from bouncelab.metrics import ERROR_COLUMNS

__all__ = ["HELD_OUT_COLUMNS", "PAPER_LAWS", "SKIPPABLE", "Comparison", "compare", "generating_law",
           "law_instance", "paper_reference"]

#: The paper's four laws, in the order of its Tables 3 and 2.
PAPER_LAWS = ("Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine")
#: The errors that mean "this fit cannot be done on these data" (too few bounces, one regime only, a
#: degenerate plane...): ``compare(..., errors="skip")`` and ``bouncelab reproduce`` skip the law or step
#: with its message. Anything else is a bug and propagates.
SKIPPABLE = (FitError, DataError, ParameterError)
_LABELS = {"delta_xdot": "Delta xdot", "delta_ydot": "Delta ydot", "delta_omega": "Delta omega", "n": "bounces",
           "n_free": "free parameters"}
#: Columns of :attr:`Comparison.table` holding the held-out errors (fractions), and their spread over the folds.
HELD_OUT_COLUMNS = tuple(f"heldout_{c}" for c in ERROR_COLUMNS)
HELD_OUT_SD = "heldout_delta_sd"
#: Folds of the held-out errors by default (:func:`compare`'s ``k``).
HELD_OUT_FOLDS = 5
#: How the paper's values are introduced: plain for measured data, as a reference on synthetic data.
PAPER_LABEL = "the paper's values in brackets"
PAPER_LABEL_SYNTHETIC = ("in brackets, the paper's results on its measured bounces: a reference, not a validation, "
                         "as these bounces are synthetic")
#: The mark of the law that generated a synthetic campaign, in table headings.
GENERATOR_MARK = "†"


#: How the published surrogate's "source" attr starts (the module moved from data to simulation).
_PUBLISHED_SOURCE = r"bouncelab\.(data|simulation)\.surrogate\.generate_surrogate\("


def generating_law(data: Any) -> str | None:
    """The law that generated a synthetic campaign, as its attrs record it; None for anything else.

    Read from ``generator_law`` (any synthetic campaign may carry it, e.g. ``make_campaign(...,
    attrs={"generator_law": "Rigid"})``), else ``turf_law`` (:func:`bouncelab.simulate_campaign`:
    the turf surrogates are simulated with CraterContact), else, for the ``"published"`` surrogate
    (:func:`bouncelab.simulation.surrogate.generate_surrogate`), its generator, the paper's published
    PiecewiseAffine law. Only for ``data_kind="synthetic surrogate"``: a measured campaign has none.
    """
    if not isinstance(data, xr.Dataset) or data.attrs.get("data_kind") != "synthetic surrogate":
        return None
    for key in ("generator_law", "turf_law"):
        if data.attrs.get(key):
            return str(data.attrs[key])
    if (data.attrs.get("surrogate") == "published"
            or re.match(_PUBLISHED_SOURCE, str(data.attrs.get("source", "")))):
        return "PiecewiseAffine"
    return None


def generator_note(generator: str | None, laws: Sequence[str]) -> str | None:
    """The footnote naming the law that generated synthetic data (None when none is recorded)."""
    if generator is None:
        return None
    if generator in laws:
        return (f"{GENERATOR_MARK} {generator} generated these data: its fit is not a test of it (it is fitted to its "
                "own output, plus noise).")
    return f"{generator} generated these data (it is not among the laws here)."


def paper_reference(campaign: str, law: str, *, held_out: bool) -> dict[str, float]:
    """The paper's values for ``law`` that are comparable with ours: Table 3's parameters always; its errors
    (on all the bounces it fitted) only beside errors on fitted bounces (``held_out=False``); Table 2's overall
    figures (the piecewise-affine law on its test set) only beside errors on held-out bounces."""
    values = published.paper_values(campaign, law)
    if law == "PiecewiseAffine":  # Table 2: a test-set figure
        return values if held_out else {}
    if held_out:  # Table 3's errors are on the fitted bounces: keep only its parameters
        return {k: v for k, v in values.items() if k not in ERROR_COLUMNS}
    return values


def _plane_text(model: BounceModel) -> str | None:
    """A piecewise-affine law's plane as an equation (the form that exists), else None."""
    from bouncelab.laws.piecewise import PiecewiseAffine

    if isinstance(model, PiecewiseAffine) and model.normal is not None and model.offset is not None:
        return model.plane_equation(3)
    return None


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
        (``train_<name>``, ``test_<name>``), then ``n_free`` (the numbers the fit
        varied, elements of array parameters one by one) and, unless
        ``heldout=False``, the cross-validated errors ``heldout_delta``,
        ``heldout_delta_xdot``, ``heldout_delta_ydot``, ``heldout_delta_omega`` and
        ``heldout_delta_sd`` (their spread over the folds); NaN for a law left out of
        the cross-validation. Fractions, not per cent.
    campaign
        "A" or "B" when the data are (a surrogate of) one of the paper's campaigns, else None.
    skipped
        Law name -> why it could not be fitted (``compare(..., errors="skip")``).
    synthetic
        Whether the data are synthetic (the paper's values are then labelled as a reference).
    generator
        The law that generated synthetic data (:func:`generating_law`), marked in the tables.
    heldout
        Law name -> its held-out errors (:class:`~bouncelab.fitting.assessment.HeldOut`: the folds,
        the scores, ``split`` ``"setting"`` or ``"bounce"``, ``k``).
    heldout_skipped
        Law name -> why it has no held-out errors (left out by ``heldout=``, or its folds could
        not be fitted with ``errors="skip"``); the markdown says so.
    """

    results: dict[str, FitResult]
    table: pd.DataFrame
    campaign: str | None = None
    split: str | None = None
    notes: list[str] = field(default_factory=list)
    units: dict[str, str] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)
    synthetic: bool = False
    generator: str | None = None
    heldout: dict[str, HeldOut] = field(default_factory=dict)
    heldout_skipped: dict[str, str] = field(default_factory=dict)

    def _which(self) -> str:
        return "test" if self.split else "train"

    def parameter_columns(self) -> list[str]:
        """Columns of :attr:`table` that hold parameters."""
        err = {f"{p}_{c}" for p in ("train", "test") for c in ERROR_COLUMNS}
        err |= {"n_free", *HELD_OUT_COLUMNS, HELD_OUT_SD}
        diag = {f"{p}_{k}" for r in self.results.values() for p in ("train", "test")
                for k in (*r.diagnostics, *r.test_diagnostics)}
        return [c for c in self.table.columns if c not in err and c not in diag]

    def _held_out_columns(self) -> list[str]:
        return [c for c in (*HELD_OUT_COLUMNS, HELD_OUT_SD) if c in self.table.columns]

    def held_out_note(self) -> str | None:
        """What the held-out rows are, and which laws have none and why (None without held-out errors)."""
        if not self.heldout and not self.heldout_skipped:
            return None
        parts = []
        if self.heldout:
            first = next(iter(self.heldout.values()))
            groups = "launcher settings" if first.split == "setting" else "bounces (the data have no launcher settings)"
            parts.append(f"Held out: each law refitted {first.k} times on all the bounces but a fold of {groups} "
                         f"(grouped {first.k}-fold cross-validation, bouncelab.assess's folds), so that each bounce "
                         "is predicted once by a fit that saw none of its setting's repeats; +- is the spread of "
                         "delta over the folds. A law with more free parameters always fits its own bounces better; "
                         "the held-out figures say whether it predicts others better.")
        for law, why in self.heldout_skipped.items():
            parts.append(f"{law}: no held-out errors ({why}).")
        return " ".join(parts)

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
            raise FitError(f"no law {law!r} in this comparison; it has {list(self.results)}", law=law)
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
        """The paper's published values for the same laws that are comparable with this table's figures.

        Table 3's parameters; its errors only for a comparison on all bounces (``split=None``, errors on the
        fitted bounces, as Table 3's); Table 2's overall figures (a test set) only with a split (errors on
        held-out bounces). See :func:`paper_reference`.
        """
        if self.campaign is None:
            return None
        rows = {law: paper_reference(self.campaign, law, held_out=self.split is not None)
                for law in self.table.index}
        out = pd.DataFrame(rows).T
        out = out.reindex(index=list(self.table.index))
        out.index.name = "law"
        return out

    def side_by_side(self) -> pd.DataFrame:
        """Our values beside the paper's: columns (quantity, source) with source "bouncelab" and "paper"."""
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in (*ERROR_COLUMNS,
                                                                              *self._diagnostic_names())})
        cols = [c for c in (*self.parameter_columns(), *ERROR_COLUMNS, *self._diagnostic_names(), "n_free",
                            *self._held_out_columns()) if c in ours.columns]
        frames = {"bouncelab": ours[cols]}
        paper = self.published()
        if paper is not None:
            frames["paper"] = paper.reindex(index=ours.index, columns=cols)
        out = pd.concat(frames, axis=1).swaplevel(axis=1)
        return out.reindex(columns=pd.MultiIndex.from_product([cols, list(frames)]))

    def _label(self, q: str, units: dict[str, str] | None = None) -> str:
        unit = (self.units if units is None else units).get(q, "1")
        return _LABELS.get(q, q if unit in ("1", "") or q.endswith(f" [{unit}]") else f"{q} [{unit}]")

    def to_markdown(self, digits: int = 3) -> str:
        """The comparison as markdown, laid out as the paper's Tables 3 and 2.

        Rows are quantities and columns laws; each cell reads ``ours (paper)``
        where the paper published a value. Errors and fractions are in per cent,
        as printed in the paper. Below the errors, the number of free parameters and
        the held-out errors (cross-validated, ``+-`` their spread over the folds), with
        no paper values beside them (the paper has none of that kind). Every law with
        diagnostics also gets its table by slip/roll class (the Table 2 layout).
        """
        title = f"campaign {self.campaign}" if self.campaign else "this campaign"
        which = "held-out" if self.split else "fitted"
        paper = self.published()
        if paper is not None and not paper.notna().any().any():
            paper = None  # nothing comparable: no brackets, and no heading promising them
        diag = self._diagnostic_names()
        ours = self.table.rename(columns={f"{self._which()}_{c}": c for c in (*ERROR_COLUMNS, *diag)})
        # A plane is printed as its equation, not as a normal and an offset, whose scale (and so unit) is arbitrary.
        planes = {law: text for law, res in self.results.items() if (text := _plane_text(res.model)) is not None}
        params = self.parameter_columns()
        if planes:
            ours = ours.astype(object)
            for law in planes:
                for col in ("normal", "offset"):
                    if col in ours.columns:
                        ours.loc[law, col] = np.nan
            ours["plane"] = pd.Series(planes, dtype=object)
            units = dict(self.units, plane="1")
            at = params.index("normal") if "normal" in params else len(params)
            params = [*params[:at], "plane", *params[at:]]
        else:
            units = self.units
        quantities = [c for c in (*params, *ERROR_COLUMNS, *diag, "n_free", *HELD_OUT_COLUMNS)
                      if c in ours.columns and ours[c].notna().any()]
        brackets = ""
        if paper is not None:
            brackets = "; " + (PAPER_LABEL_SYNTHETIC if self.synthetic else PAPER_LABEL)
        mark = {law: law + (f" {GENERATOR_MARK}" if law == self.generator else "") for law in ours.index}
        lines = [f"### Laws fitted to {title} (errors on the {which} bounces{brackets})\n"]
        lines.append("| quantity | " + " | ".join(mark[law] for law in ours.index) + " |")
        lines.append("|---|" + "---|" * len(ours.index))
        held = next(iter(self.heldout.values()), None)
        for q in quantities:
            cells = []
            percent = q in ERROR_COLUMNS or q in diag or q in HELD_OUT_COLUMNS
            for law in ours.index:
                cell = _fmt(ours.loc[law, q], q, digits, percent=percent)
                if cell and q == HELD_OUT_COLUMNS[0] and HELD_OUT_SD in ours.columns:
                    sd = _fmt(ours.loc[law, HELD_OUT_SD], HELD_OUT_SD, digits, percent=True)
                    cell += f" +- {sd}" if sd else ""
                if cell and paper is not None and law in paper.index and q in paper.columns:
                    ref = _fmt(paper.loc[law, q], q, digits, percent=percent)
                    cell += f" ({ref})" if ref else ""
                cells.append(cell)
            if q in HELD_OUT_COLUMNS and held is not None:
                label = f"{self._label(q.removeprefix('heldout_'))}, held out ({held.k} folds by {held.split})"
            else:
                label = self._label(q, units)
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
        for law, res in self.results.items():
            if not (res.test_diagnostics if self.split else res.diagnostics):
                continue
            t = self.by_class(law)
            # Table 2 is the paper's test set: its values stand only beside held-out errors
            ref = (None if self.campaign is None or not self.split
                   else published.paper_by_class(self.campaign, law))
            brackets = ""
            if ref is not None:
                brackets = "; " + (PAPER_LABEL_SYNTHETIC if self.synthetic else "the paper's in brackets")
            lines.append(f"\n### {mark[law]} by class (Table 2 layout; errors on the {t.attrs['data']} bounces"
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
        footnote = generator_note(self.generator, list(ours.index))
        if footnote is not None:
            lines.append(f"\n> {footnote}")
        if (held_note := self.held_out_note()) is not None:
            lines.append(f"\n> {held_note}")
        for law, why in self.skipped.items():
            lines.append(f"\n> {law} was not fitted: {why}")
        for note in self.notes:
            lines.append(f"\n> {note}")
        return "\n".join(lines) + "\n"

    def __repr__(self) -> str:
        return f"Comparison({list(self.results)}, campaign={self.campaign!r}, split={self.split!r})"

    def _repr_markdown_(self) -> str:
        return self.to_markdown()

    def _repr_html_(self) -> str:
        from bouncelab.fitting._display import comparison_html  # the notebook view

        return comparison_html(self)


def _fmt(v: Any, name: str, digits: int, *, percent: bool = False) -> str:
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and np.isnan(v)):
        return ""
    if name in ("n", "n_free"):
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
    errors: str = "raise",
    heldout: bool | Sequence[str] | None = None,
    k: int = HELD_OUT_FOLDS,
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
        Seed of the split, of the folds and of every fit.
    executor
        Where to run the fits and the folds: any :class:`concurrent.futures.Executor` or a dask ``Client``
        (see :func:`bouncelab.fitting.tasks.map_tasks`); serially by default. The result does not depend on it.
    errors
        ``"raise"`` (default): a law that cannot be fitted to these data stops the comparison.
        ``"skip"``: it is left out and recorded, with the reason, in :attr:`Comparison.skipped`
        (and the markdown); only the errors of :data:`SKIPPABLE` (FitError, DataError,
        ParameterError) are skipped, anything else propagates. If no law can be fitted, FitError.
        A law whose folds cannot be fitted keeps its fit, without held-out errors
        (:attr:`Comparison.heldout_skipped`).
    heldout
        Held-out errors by grouped ``k``-fold cross-validation of all the bounces (whatever
        ``split``): folds of whole launcher settings, of single bounces when the data have no
        ``setting`` (:func:`bouncelab.fitting.assessment.held_out_errors`, as
        :func:`bouncelab.assess`). None (default): for every law where the data allow it;
        with a ``sample_weight`` (the folds would not carry the weights), with a single
        launcher setting, or for a law whose folds cannot be fitted, the law gets none and
        :attr:`Comparison.heldout_skipped` and the markdown say why. True: for every law,
        and any of those cases is an error (FitError, or skipped with ``errors="skip"``; a
        ``sample_weight`` is always a FitError);
        a list of law names: as True, for those only; False: none (no held-out columns).
        **Cost**: ``k`` more fits per law, so a comparison takes about ``k + 1`` times as
        long as the fits alone (the paper's four laws on 693 bounces: about a second more;
        a contact law such as TurfContact or CraterContact: minutes more).
    k
        Folds of the held-out errors (default 5; at most the number of settings, or bounces:
        fewer settings give fewer folds).
    **fit_kwargs
        Passed to :func:`bouncelab.fit` for every law (e.g. ``objective``).

    Examples
    --------
    >>> import bouncelab as bl
    >>> cmp = bl.compare(bl.load_campaign("A"), ["Rigid", "PennerFixed"])
    >>> print(cmp.to_markdown())  # doctest: +SKIP
    """
    if split not in (None, "setting"):
        raise FitError(f"split must be None or 'setting'; got {split!r}", option="split")
    if errors not in ("raise", "skip"):
        raise FitError(f"errors must be 'raise' or 'skip'; got {errors!r}", option="errors")
    seed = check_seed(seed)
    if isinstance(laws, str | BounceModel) or isinstance(laws, type):
        laws = [laws]
    models = [law_instance(law) for law in laws]
    if not models:
        raise FitError("give at least one law to compare", option="laws")
    names = [law_name(m) for m in models]
    if len(set(names)) != len(names):
        raise FitError(f"each law may appear once; got {names}", option="laws")
    if split is not None:
        refuse_sample_weight(fit_kwargs, "compare(split='setting')")
    auto = heldout is None
    cross = _heldout_names(True if auto else heldout, names)
    weighted = "sample_weight" in fit_kwargs
    if cross and weighted and not auto:
        raise FitError("compare's held-out errors take no sample_weight: the folds split the bounces and the "
                       "weights would not follow them; pass heldout=False to compare weighted fits",
                       option="sample_weight", hints=[Hint("heldout", False)])
    k = check_count(k, "k", 2)  # folds of the held-out errors
    train, test = (split_by_setting(data, seed) if split == "setting" else (data, None))
    fits = map_tasks(_fit_task, [(m, train, test, seed, fit_kwargs, errors == "skip") for m in models], executor)
    results = {name: res for name, res in zip(names, fits, strict=True) if isinstance(res, FitResult)}
    skipped = {name: res[1] for name, res in zip(names, fits, strict=True) if not isinstance(res, FitResult)}
    if not results:
        raise FitError("no law could be fitted: " + "; ".join(f"{k}: {v}" for k, v in skipped.items()))
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
    synthetic = isinstance(data, xr.Dataset) and data.attrs.get("data_kind") == "synthetic surrogate"
    if not cross:  # heldout=False: none asked for, so nothing to say about them
        held, held_skipped = {}, {}
    elif weighted:  # (auto: none; the folds would not carry the weights)
        held, held_skipped = {}, {name: "sample-weighted fits: the folds would not carry the weights" for name in
                                  results}
    else:
        held, held_skipped = _held_out_all(data, models, names, results, cross, k, seed, executor,
                                           "skip" if auto else errors, fit_kwargs)
    table["n_free"] = [results[name].n_free for name in table.index]
    if held or cross:
        for col in (*HELD_OUT_COLUMNS, HELD_OUT_SD):
            table[col] = [held[name].scores[col.removeprefix("heldout_")] if name in held else np.nan
                          for name in table.index]
    return Comparison(results=results, table=table, campaign=campaign, split=split, notes=notes, units=units,
                      skipped=skipped, synthetic=synthetic, generator=generating_law(data), heldout=held,
                      heldout_skipped=held_skipped)


def _heldout_names(heldout: Any, names: Sequence[str]) -> list[str]:
    """The laws (of ``names``) whose held-out errors ``heldout`` asks for."""
    if heldout is True:
        return list(names)
    if heldout is False:
        return []
    if isinstance(heldout, str):
        heldout = [heldout]
    try:
        chosen = [h if isinstance(h, str) else law_name(law_instance(h)) for h in heldout]
    except (TypeError, FitError):
        raise FitError(f"heldout must be True, False or a list of the compared laws' names; got {heldout!r}",
                       option="heldout") from None
    unknown = [h for h in chosen if h not in names]
    if unknown:
        raise FitError(f"heldout names {unknown}, which are not among the compared laws {list(names)}",
                       option="heldout")
    return [n for n in names if n in chosen]


def _held_out_all(data: Any, models: Sequence[BounceModel], names: Sequence[str], results: dict[str, FitResult],
                  cross: Sequence[str], k: int, seed: int, executor: Any, errors: str,
                  fit_kwargs: dict[str, Any]) -> tuple[dict[str, HeldOut], dict[str, str]]:
    """The held-out errors of the fitted laws named in ``cross``, and why the others have none."""
    held: dict[str, HeldOut] = {}
    skipped = {name: "left out of the cross-validation (heldout=)" for name in results if name not in cross}
    todo = [(m, name) for m, name in zip(models, names, strict=True) if name in cross and name in results]
    if not todo:
        return held, skipped
    grouped, groups, split = _fold_groups(data)
    n_groups = len(pd.unique(groups))
    if n_groups < 2:
        why = "one launcher setting only: no fold of settings can be held out"
        if errors == "raise":
            raise FitError(f"compare's held-out errors need two or more launcher settings: {why}", option="heldout",
                           hints=[Hint("heldout", False)])
        return held, {**skipped, **{name: why for _, name in todo}}
    folds = min(k, n_groups)
    for model, name in todo:
        try:
            held[name] = _held_out(model, grouped, k=folds, seed=seed, executor=executor, split=split,
                                   **fit_kwargs)
        except SKIPPABLE as exc:
            if errors == "raise":
                raise
            skipped[name] = f"its folds could not be fitted: {str(exc).strip().splitlines()[0]}"
    return held, skipped


def _fit_task(task: tuple) -> FitResult | tuple[str, str]:
    """One law's fit in :func:`compare` (a module-level function, so executors can pickle it); with ``skip``
    a fit these data cannot give returns ``("skipped", reason)`` (a picklable pair, not the exception)."""
    model, train, test, seed, fit_kwargs, skip = task
    try:
        return fit(model, train, test=test, seed=seed, **fit_kwargs)
    except SKIPPABLE as exc:
        if not skip:
            raise
        return ("skipped", str(exc))
