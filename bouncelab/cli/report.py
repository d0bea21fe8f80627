"""Formatting of the ``bouncelab reproduce`` report: markdown tables and the one-page ``index.html``."""

from __future__ import annotations

import html
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
import xarray as xr

if TYPE_CHECKING:
    from bouncelab.cli.reproduce import Report

__all__ = ["assessment_markdown", "frame_markdown", "index_html", "md_to_html", "table2_markdown"]


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


def md_to_html(md: str) -> str:
    """The small markdown subset written here (headings, tables, lists, quotes, paragraphs) as HTML."""
    out, table = [], []

    def flush():
        if table:
            rows = [r.strip().strip("|").split("|") for r in table if not set(r.strip()) <= set("|-: ")]
            head, body = rows[0], rows[1:]
            out.append("<table><thead><tr>" + "".join(f"<th>{html.escape(c.strip())}</th>" for c in head)
                       + "</tr></thead><tbody>"
                       + "".join("<tr>" + "".join(f"<td>{html.escape(c.strip())}</td>" for c in r) + "</tr>"
                                 for r in body) + "</tbody></table>")
            table.clear()

    for line in md.splitlines():
        if line.startswith("|"):
            table.append(line)
            continue
        flush()
        if line.startswith("### "):
            out.append(f"<h3>{html.escape(line[4:])}</h3>")
        elif line.startswith("> "):
            out.append(f"<blockquote>{html.escape(line[2:])}</blockquote>")
        elif line.startswith("- "):
            out.append(f"<ul><li>{html.escape(line[2:])}</li></ul>")
        elif line.strip():
            out.append(f"<p>{html.escape(line)}</p>")
    flush()
    return "\n".join(out)


_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
thead { background: #f2f2f2; }
img { max-width: 100%; border: 1px solid #ddd; margin: 0.4em 0 1.4em; }
.warning { background: #fff3cd; border: 1px solid #e0c36c; padding: 0.6em 1em; }
blockquote { color: #555; border-left: 3px solid #ccc; margin: 0.6em 0; padding-left: 0.8em; }
nav a { margin-right: 1em; }
"""


def _paper_values(report: Report) -> str:
    """What the brackets in the tables mean, said only when some campaign has the paper's values."""
    from bouncelab.core import published

    with_paper = [n for n, sec in report.sections.items() if sec.get("paper_campaign") in published.CAMPAIGNS]
    if not with_paper:
        return ("None of these campaigns is one of the paper's, so no published values are shown beside "
                "the results.")
    synthetic = [n for n in with_paper if report.sections[n].get("synthetic")]
    measured = [n for n in with_paper if n not in synthetic]
    text = ("Values in brackets are the paper's published results on its measured bounces, each beside a figure "
            "of the same kind only (Table 3's beside errors on the fitted bounces, Table 2's, a test set, beside "
            "errors on held-out bounces).")
    if measured:
        text += f" They are shown for the campaigns labelled as the paper's campaigns A and B: {', '.join(measured)}."
    if synthetic:
        text += (f" For {', '.join(synthetic)}, synthetic surrogates of the paper's campaigns, they are a reference, "
                 "not a validation: agreement or disagreement with them says nothing about real turf.")
    return text


def _figure_units(report: Report) -> str:
    units = report.figure_units
    if not units:
        return ""
    return f" in the tables (in the figures: velocities in {units['velocity']}, spin in {units['spin']})"


def index_html(report: Report) -> str:
    from bouncelab.core import __version__
    from bouncelab.core.published import CITATION

    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>bouncelab report</title>",
             f"<style>{_CSS}</style></head><body>",
             "<h1>bouncelab: golf-ball bounce laws</h1>",
             f"<p>The analysis of {html.escape(CITATION.rstrip('.'))}, run on each campaign below. "
             f"Made by bouncelab {__version__} in {report.elapsed:.1f} s. Errors are the paper's delta and "
             "Delta q (fractions of the landing state's norm, shown in per cent); velocities are in ball radii per "
             f"second and spin in rad/s{_figure_units(report)}. {_paper_values(report)}</p>",
             "<nav>" + "".join(f"<a href='#{html.escape(n)}'>campaign {html.escape(n)}</a>" for n in report.sections)
             + "</nav>"]
    skipped = report.skipped
    if skipped:
        items = "".join(f"<li>campaign {html.escape(c)}, {html.escape(w)}: {html.escape(r)}</li>"
                        for c, w, r in skipped)
        parts.append(f"<div class='warning' id='skipped'><p><b>A partial report:</b> {len(skipped)} step(s) could "
                     f"not run on these data and were skipped; everything else is below.</p><ul>{items}</ul></div>")
    for name, sec in report.sections.items():
        parts.append(f"<h2 id='{html.escape(name)}'>Campaign {html.escape(name)}</h2>")
        for note in sec["notes"]:
            parts.append(f"<p class='warning'>{html.escape(note)}</p>")
        if sec.get("generator"):
            gen = html.escape(sec["generator"])
            parts.append(f"<p class='warning'>{gen} generated these data: " + (
                "in every table of laws it is marked †, and its fit is not a test of it.</p>"
                if sec["generator"] in sec.get("law_names", ()) else
                "it is not among the laws fitted here; a fit of it would be no test of it.</p>"))
        for _title, md in sec["tables"].items():
            parts.append(md_to_html(md))
        if sec["laws"]:
            links = ", ".join(f"<a href='{html.escape(p.relative_to(report.out).as_posix())}'>{html.escape(n)}</a>"
                              for n, p in sec["laws"].items())
            parts.append(f"<p>Fitted laws (JSON, load with <code>bouncelab.load_law</code>): {links}</p>")
        for caption, path in sec["figures"].items():
            rel = html.escape(path.relative_to(report.out).as_posix())
            cap = html.escape(caption)
            parts.append(f"<h3>{cap}</h3><a href='{rel}'><img src='{rel}' alt='{cap}'></a>")
        for caption, (_label, why) in sec.get("figures_skipped", {}).items():
            parts.append(f"<h3>{html.escape(caption)}</h3><p class='warning'>Not drawn: {html.escape(why)}</p>")
    rels = [html.escape(p.relative_to(report.out).as_posix()) for p in report.files]
    items = "".join(f"<li><a href='{r}'>{r}</a></li>" for r in rels)
    parts.append(f"<h2>Files</h2><ul>{items}</ul></body></html>")
    return "\n".join(parts)
