"""The report's tables as markdown (each ``tables/NAME_*.md`` file, and the page's tables through
:func:`bouncelab.core._html.markdown`)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

__all__ = ["assessment_markdown", "frame_markdown", "table2_markdown"]


def frame_markdown(df: pd.DataFrame, percent: bool = False, missing: str = "nan", mark: str | None = None) -> str:
    """A DataFrame as a markdown table; numbers to 4 significant digits, or as per cent; NaN as ``missing``.

    ``mark``: the row of that name (the law that generated synthetic data) gets the generator's mark (†).
    """
    from bouncelab.fitting.comparison import GENERATOR_MARK

    def cell(v: Any) -> str:
        if not isinstance(v, float | np.floating):
            return str(v)
        if np.isnan(v):
            return missing
        return f"{100 * v:.3g} %" if percent else f"{v:.4g}"

    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join([str(df.index.name or ""), *cols]) + " |", "|" + "---|" * (len(cols) + 1)]
    for idx, row in df.iterrows():
        label = f"{idx} {GENERATOR_MARK}" if mark is not None and str(idx) == mark else str(idx)
        lines.append("| " + " | ".join([label, *map(cell, row)]) + " |")
    return "\n".join(lines) + "\n"


def table2_markdown(name: str, pw: dict, ds: xr.Dataset) -> str:
    """Table 2: the piecewise-affine laws of ``pw`` (label -> FitResult on the paper's split), errors on the
    held-out bounces. The paper's Table 2 (its SVM plane on its test set) stands in brackets beside the SVM's
    held-out figures only, the comparable ones; on synthetic data it is labelled as a reference, and the
    footnote says when PiecewiseAffine generated the data."""
    from bouncelab.core import published
    from bouncelab.fitting.comparison import GENERATOR_MARK, generating_law, generator_note

    camp = str(ds.attrs.get("campaign", "")).upper()
    paper = published.TABLE2.loc[camp] if camp in published.CAMPAIGNS else None
    synthetic = ds.attrs.get("data_kind") == "synthetic surrogate"
    brackets = ""
    if paper is not None and any("SVM" in label for label in pw):
        brackets = ("; in brackets beside the SVM plane's figures the paper's Table 2 (its SVM plane on its measured "
                    "test bounces): a reference, not a validation, as these bounces are synthetic" if synthetic
                    else "; the paper's Table 2 (SVM plane, its test set) in brackets")
    mark = f" {GENERATOR_MARK}" if generating_law(ds) == "PiecewiseAffine" else ""
    lines = [f"### Piecewise-affine law{mark}, campaign {name}: errors on the held-out bounces "
             f"(one per launcher setting){brackets}\n"]
    head = ["quantity"]
    for label in pw:
        head += [f"{label}: overall", "roll", "slip"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "---|" * len(head))
    diagnostics = list(dict.fromkeys(k for res in pw.values() for k in res.test_diagnostics))
    for q in ("n", "delta", "delta_xdot", "delta_ydot", "delta_omega", *diagnostics):
        cells = [q]
        for res in pw.values():
            t = res.errors.loc["test"]
            for subset in ("all", "roll", "slip"):
                if q in diagnostics:
                    v = res.test_diagnostics.get(q) if subset == "all" else None
                else:
                    v = t.loc[subset, q] if subset in t.index else None
                if v is None or (isinstance(v, float) and np.isnan(v)):
                    cells.append("")
                    continue
                cell = f"{int(v)}" if q == "n" else f"{100 * v:.3g} %"
                key = "overall" if subset == "all" else subset
                if (paper is not None and q != "n" and q in paper.columns
                        and "SVM" in next(k for k, r in pw.items() if r is res)):
                    ref = paper.loc[key, q]
                    cell += f" ({100 * ref:.3g} %)" if np.isfinite(ref) else ""
                cells.append(cell)
        lines.append("| " + " | ".join(cells) + " |")
    for label, res in pw.items():
        law_line = "; ".join(line for line in res.model._summary_lines() if line.startswith("plane"))
        lines.append(f"\n- {label}: {law_line} (fitted on {res.n_train} bounces, "
                     f"delta on them {100 * res.delta:.3g} %)")
    footnote = generator_note(generating_law(ds), ["PiecewiseAffine"])
    if footnote is not None:
        lines.append(f"\n> {footnote}")
    return "\n".join(lines) + "\n"


def assessment_markdown(name: str, assessments: dict[str, Any], options: dict[str, Any], *,
                        not_assessed: dict[str, str], failed: dict[str, str], generator: str | None) -> str:
    """The report's assessment section: per law its free parameters, training and held-out delta and verdict
    counts, then one table of every assessed law's parameters with their verdicts (:func:`bouncelab.assess`), and
    the laws not assessed with the reason (errors in per cent, as in the other tables)."""
    from bouncelab.fitting.assessment import VERDICTS
    from bouncelab.fitting.comparison import GENERATOR_MARK, generator_note

    def mark(law: str) -> str:
        return f"{law} {GENERATOR_MARK}" if law == generator else law

    boot = options["n_bootstrap"]
    lines = [f"### Assessment of each law, campaign {name}: held-out errors and identifiability (beyond the paper)\n",
             f"bouncelab.assess with {options['k']} folds grouped by launcher setting, "
             + (f"{boot} bootstrap resamples of whole launcher settings (95 % percentile intervals), " if boot else
                "no bootstrap (0 resamples: no intervals, no correlations), ")
             + f"{options['starts']} independent global fits from random starts, and a profile of each parameter "
               f"({options['profile_points']} points over its search box and {options['local_points']} on each side "
               "of the estimate, every other parameter refitted). A parameter is identifiable when its profile leaves "
               "the noise of the data on both sides of the estimate, weakly identifiable when the data cannot bound "
               "it on a side (or a second minimum fits as well), not identifiable along a flat direction "
               "(docs/assessment.md).\n"]
    if assessments:
        head = ["law", "free parameters", "delta, training", "delta, held out", *VERDICTS]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for law, a in assessments.items():
            s = a.summary()
            counts = [str(s[f"n_{v.replace(' ', '_')}"]) for v in VERDICTS]
            lines.append(f"| {mark(law)} | {s['n_free']} | {100 * s['train_delta']:.3g} % | "
                         f"{100 * s['heldout_delta']:.3g} % +- {100 * s['heldout_delta_sd']:.3g} % | "
                         + " | ".join(counts) + " |")
        lines.append("")
        head = ["law", "parameter", "estimate", "95 % bootstrap interval", "spread over starts",
                "profile within noise", "verdict", "correlated with"]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for law, a in assessments.items():
            lines += [f"| {mark(law)} | {par} | " + " | ".join(cells) + " |" for par, cells in a.table_rows()]
    for law, why in failed.items():
        lines.append(f"\n> {law}: not assessed, skipped: {why}")
    if not_assessed:
        lines.append("\n> Not assessed here, to keep the report quick (bouncelab.assess(law, data) assesses any law): "
                     + "; ".join(f"{law}: {why}" for law, why in not_assessed.items()) + ".")
    footnote = generator_note(generator, list(assessments))
    if footnote is not None and generator in assessments:
        lines.append(f"\n> {footnote}")
    return "\n".join(lines) + "\n"
