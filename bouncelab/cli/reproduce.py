"""``bouncelab reproduce``: the paper's whole analysis for one or more campaigns, written to a folder.

For every campaign (the embedded surrogates "A" and "B", or data files):

* Table 3 layout: the rigid family and the piecewise-affine law fitted to all bounces by
  bouncelab's global search, beside the paper's published values (plus, beyond the paper,
  the tangential-restitution law and the paper's own two-stage procedure for Rigid);
* Table 2 layout: the piecewise-affine law on the paper's split (one bounce per launcher
  setting held out), by the paper's SVM procedure and by bouncelab's delta-optimal plane;
* beyond the paper: 5-fold cross-validated delta of every law, grouped by launcher setting, and
  bootstrap intervals of the rigid family's parameters (resampling whole launcher settings);
* the analyses: repeatability per setting, tangential-velocity counts, prediction-interval widths;
* the fitted laws as JSON, every table as markdown and CSV, the figures as PNG;
* one ``index.html`` showing it all.
"""

from __future__ import annotations

import html
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.errors import DataError

__all__ = ["BOOTSTRAP_RESAMPLES", "Report", "reproduce"]

#: Resamples of the parameter bootstrap in the report (about 4 s per campaign on two cores).
BOOTSTRAP_RESAMPLES = 100


@dataclass
class Report:
    """What :func:`reproduce` wrote."""

    out: Path
    index: Path
    files: list[Path] = field(default_factory=list)
    sections: dict[str, dict[str, Any]] = field(default_factory=dict)
    elapsed: float = 0.0


class _Progress:
    """A one-line-per-step progress display on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total, self.enabled, self.step = total, enabled, 0
        self.start = time.perf_counter()

    def __call__(self, message: str) -> _Step:
        self.step += 1
        return _Step(self, message)


class _Step:
    def __init__(self, progress: _Progress, message: str) -> None:
        self.p, self.message = progress, message

    def __enter__(self) -> _Step:
        self.t = time.perf_counter()
        if self.p.enabled:
            print(f"[{self.p.step:>2}/{self.p.total}] {self.message} ...", end="", file=sys.stderr, flush=True)
        return self

    def __exit__(self, exc_type, *exc: Any) -> None:
        if self.p.enabled:
            status = "done" if exc_type is None else "FAILED"
            print(f" {status} ({time.perf_counter() - self.t:.1f} s)", file=sys.stderr, flush=True)


def _write_table(df: pd.DataFrame, md: str, stem: Path, files: list[Path]) -> None:
    stem.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(stem.with_suffix(".csv"))
    stem.with_suffix(".md").write_text(md)
    files += [stem.with_suffix(".csv"), stem.with_suffix(".md")]


def _frame_markdown(df: pd.DataFrame, percent: bool = False) -> str:
    """A DataFrame as a markdown table; numbers to 4 significant digits, or as per cent."""

    def cell(v: Any) -> str:
        if not isinstance(v, float | np.floating):
            return str(v)
        return f"{100 * v:.3g} %" if percent else f"{v:.4g}"

    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join([str(df.index.name or ""), *cols]) + " |", "|" + "---|" * (len(cols) + 1)]
    for idx, row in df.iterrows():
        lines.append("| " + " | ".join([str(idx), *map(cell, row)]) + " |")
    return "\n".join(lines) + "\n"


def _steps_per_campaign(figures: bool) -> int:
    return 8 + (1 if figures else 0)  # load, 7 analysis steps, figures


def reproduce(
    campaigns: list[str] | tuple[str, ...] = ("A", "B"),
    data: list[str] | tuple[str, ...] = (),
    out: str | Path = "report",
    *,
    seed: int = 0,
    figures: bool = True,
    progress: bool = True,
    load: Callable[[str], xr.Dataset] | None = None,
) -> Report:
    """Run the paper's analysis for each campaign and write the report folder.

    Parameters
    ----------
    campaigns
        Embedded campaigns ("A", "B").
    data
        Paths of bounce-data files (see :func:`bouncelab.load_campaign`).
    out
        Output folder (created if needed; files in it are overwritten).
    seed
        Seed of the held-out split and of every fit.
    figures
        Draw the figures (needs matplotlib, the ``plot`` extra).
    progress
        Show a progress display on stderr.
    load
        How to load a source (default :func:`bouncelab.load_campaign`).

    Returns
    -------
    Report
    """
    from bouncelab.data.io import load_campaign

    sources = [*campaigns, *data]
    if not sources:
        raise DataError("nothing to reproduce: give campaigns (A, B) or data files")
    if figures:
        from bouncelab.plots._common import pyplot

        pyplot()  # fail early, before any work, if matplotlib is missing
    load = load or load_campaign
    start = time.perf_counter()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    report = Report(out=out, index=out / "index.html")
    step = _Progress(len(sources) * _steps_per_campaign(figures) + 1, progress)  # + index.html
    loaded = []
    for src in sources:
        with step(f"loading {src}"):
            ds = load(src)
        name = str(ds.attrs.get("campaign") or Path(str(src)).stem)
        if name in [n for n, _ in loaded]:
            name = f"{name}_{len(loaded) + 1}"
        loaded.append((name, ds))
    for name, ds in loaded:
        report.sections[name] = _campaign(name, ds, out, seed, figures, step, report.files)
    with step("writing index.html"):
        report.elapsed = time.perf_counter() - start
        report.index.write_text(_index_html(report))
        report.files.append(report.index)
    return report


def _campaign(name: str, ds: xr.Dataset, out: Path, seed: int, figures: bool, step: _Progress,
              files: list[Path]) -> dict[str, Any]:
    from bouncelab.analysis.repeats import repeatability, repeatability_summary
    from bouncelab.analysis.tangential import tangential_summary
    from bouncelab.fitting import bootstrap, compare, cross_validate, fit, infer_settings, split_by_setting
    from bouncelab.fitting.comparison import PAPER_LAWS
    from bouncelab.laws import PiecewiseAffine, Rigid, registered_laws

    section: dict[str, Any] = {"notes": [], "tables": {}, "figures": {}, "laws": {}}
    if ds.attrs.get("data_kind") == "synthetic surrogate":
        section["notes"].append(ds.attrs.get("warning", "synthetic surrogate data"))
    if "setting" not in ds.coords:
        labels = infer_settings(ds)
        ds = ds.assign_coords(setting=("bounce", labels))
        section["notes"].append(
            f"The data record no launcher settings; {len(np.unique(labels))} settings were inferred by clustering "
            "the landing conditions (bouncelab.infer_settings)."
        )
    tables = out / "tables"

    with step(f"{name}: fitting the paper's laws to all bounces (Table 3)"):
        cmp = compare(ds, [*PAPER_LAWS, "TangentialRestitution"], seed=seed)
        structured = fit(Rigid, ds, method="structured", seed=seed)
        md = cmp.to_markdown()
        md += ("\n### The paper's two-stage procedure for Rigid (r by least squares on ydot, then mu)\n\n"
               f"r = {structured.model.r:.4g}, mu = {structured.model.mu:.4g}, delta = {100 * structured.delta:.3g} % "
               f"(global search: delta = {100 * cmp.results['Rigid'].delta:.3g} %)\n")
        _write_table(cmp.side_by_side(), md, tables / f"{name}_table3", files)
        section["tables"]["Table 3: laws fitted to all bounces"] = md
        laws_dir = out / "laws"
        laws_dir.mkdir(exist_ok=True)
        for law_name, res in cmp.results.items():
            path = laws_dir / f"{name}_{law_name}.json"
            res.model.to_json(path)
            files.append(path)
            section["laws"][law_name] = path
        section["comparison"] = cmp

    with step(f"{name}: piecewise-affine law on the paper's split, SVM and delta plane (Table 2)"):
        train, test = split_by_setting(ds, seed)
        pw = {}
        for method, label in (("svm", "paper's SVM plane"), ("plane", "bouncelab's delta-optimal plane")):
            pw[label] = fit(PiecewiseAffine, train, test=test,
                            method=method, seed=seed)
        rows = []
        for label, res in pw.items():
            for data_name in ("train", "test"):
                t = res.errors.loc[data_name]
                for subset in t.index:
                    rows.append({"method": label, "data": data_name, "subset": subset, **t.loc[subset].to_dict(),
                                 "mismatched": (res.mismatched if data_name == "train" else res.test_mismatched)
                                 if subset == "all" else np.nan})
        t2 = pd.DataFrame(rows).set_index(["method", "data", "subset"])
        md = _table2_markdown(name, pw, ds)
        _write_table(t2, md, tables / f"{name}_table2", files)
        section["tables"]["Table 2: piecewise-affine law, held-out bounces"] = md
        section["piecewise"] = pw
        for label, res in pw.items():
            key = "svm" if "SVM" in label else "plane"
            path = out / "laws" / f"{name}_PiecewiseAffine_{key}_train.json"
            res.model.to_json(path)
            files.append(path)

    with step(f"{name}: 5-fold cross-validation by launcher setting (beyond the paper)"):
        rows = {}
        for law in [*PAPER_LAWS, "TangentialRestitution"]:
            cls = registered_laws()[law]
            cv = cross_validate(cls, ds, k=min(5, len(np.unique(ds.setting.values))), seed=seed)
            rows[law] = {"cv_delta": cv.delta, "cv_delta_std": cv.delta_std,
                         "fitted_delta": float(cv.folds["train_delta"].mean())}
        cvt = pd.DataFrame(rows).T
        cvt.index.name = "law"
        md = (f"### Cross-validated delta, campaign {name} (5 folds grouped by launcher setting)\n\n"
              + _frame_markdown(cvt, percent=True))
        _write_table(cvt, md, tables / f"{name}_crossvalidation", files)
        section["tables"]["Cross-validation (beyond the paper)"] = md

    with step(f"{name}: parameter uncertainty, bootstrap over launcher settings (beyond the paper)"):
        frames = {}
        for law in ("Rigid", "PennerVarying", "PennerFixed"):
            boot = bootstrap(registered_laws()[law], ds, n=BOOTSTRAP_RESAMPLES, seed=seed)
            frames[law] = boot.summary()
        boot_table = pd.concat(frames, names=["law", "parameter"])
        md = (f"### Parameter uncertainty, campaign {name}: {BOOTSTRAP_RESAMPLES} bootstrap resamples of whole "
              "launcher settings (95 % percentile intervals)\n\n")
        md += _frame_markdown(boot_table.reset_index().set_index("law"))
        _write_table(boot_table, md, tables / f"{name}_bootstrap", files)
        section["tables"]["Parameter uncertainty (beyond the paper)"] = md

    with step(f"{name}: repeatability per launcher setting"):
        rep = repeatability(ds)
        summ = repeatability_summary(rep)
        rep_df = rep.to_dataframe()
        rep_df.to_csv(tables / f"{name}_repeatability.csv")
        files.append(tables / f"{name}_repeatability.csv")
        md = (f"### Repeatability, campaign {name}: 95 % CI half-widths of the mean per setting\n\n"
              + _frame_markdown(summ))
        _write_table(summ, md, tables / f"{name}_repeatability_summary", files)
        section["tables"]["Repeatability"] = md
        section["repeatability"] = rep

    with step(f"{name}: tangential velocities and prediction intervals"):
        tang = tangential_summary(ds)
        md = f"### Tangential velocity v_P = xdot + omega, campaign {name}\n\n" + _frame_markdown(tang)
        _write_table(tang, md, tables / f"{name}_tangential", files)
        section["tables"]["Tangential velocities"] = md
        if "landing_pi" in ds.data_vars:
            widths = {}
            for state in ("landing", "liftoff"):
                w = 2 * ds[f"{state}_pi"] / np.abs(ds[state]).mean("bounce")
                widths[state] = w.median("bounce").to_pandas()
            pit = pd.DataFrame(widths)
            pit.index.name = "component"
            md = (f"### Median 95 % prediction-interval width / campaign mean |q|, campaign {name}\n\n"
                  + _frame_markdown(pit, percent=True))
            _write_table(pit, md, tables / f"{name}_prediction_intervals", files)
            section["tables"]["Prediction intervals"] = md

    with step(f"{name}: checking the fitted laws reload"):
        from bouncelab.laws import load_law

        for law_name, path in section["laws"].items():
            again = load_law(path)
            if again != cmp.results[law_name].model:
                raise RuntimeError(f"{path} does not reload to the fitted law")

    if figures:
        with step(f"{name}: figures"):
            section["figures"] = _figures(name, ds, cmp, pw, test, rep, out / "figures", files)
    return section


def _figures(name, ds, cmp, pw, test, rep, folder: Path, files: list[Path]) -> dict[str, Path]:
    from bouncelab.fitting.piecewise import fit_svm
    from bouncelab.plots import (
        plot_landing_space,
        plot_pi_widths,
        plot_predictions,
        plot_repeatability,
        plot_slices,
        plot_tangential,
        save_figure,
    )
    from bouncelab.plots._common import pyplot

    plt = pyplot()
    folder.mkdir(parents=True, exist_ok=True)
    p0, pf = ds.landing.values, ds.liftoff.values
    svm = fit_svm(np.ascontiguousarray(p0), np.ascontiguousarray(pf))
    plane_law = cmp.results["PiecewiseAffine"].model
    figs = {
        "Fig. 3: landing conditions, slip/roll classes, the delta-optimal plane and SVM support vectors":
            ("fig3_landing_space", lambda: plot_landing_space(ds, plane_law, support=svm)),
        "Fig. 6: prediction-interval widths": ("fig6_pi_widths", lambda: plot_pi_widths(ds)),
        "Fig. 7: tangential velocity at landing and lift-off": ("fig7_tangential", lambda: plot_tangential(ds)),
        "Fig. 8: predicted vs observed lift-off (held-out bounces ringed)":
            ("fig8_predictions", lambda: plot_predictions(
                ds, {law: res.model for law, res in cmp.results.items() if law != "TangentialRestitution"},
                test=test)),
        "Fig. 9: repeatability of each launcher setting": ("fig9_repeatability", lambda: plot_repeatability(rep)),
        "Fig. 10: all landing/lift-off slices": ("fig10_slices", lambda: plot_slices(ds)),
    }
    made = {}
    for caption, (stem, draw) in figs.items():
        if stem == "fig6_pi_widths" and "landing_pi" not in ds.data_vars:
            continue
        fig = draw()
        path = save_figure(fig, folder / f"{name}_{stem}.png")
        plt.close(fig)
        files.append(path)
        made[caption] = path
    return made


def _table2_markdown(name: str, pw: dict, ds: xr.Dataset) -> str:
    from bouncelab.data import published

    camp = str(ds.attrs.get("campaign", "")).upper()
    paper = published.TABLE2.loc[camp] if camp in published.CAMPAIGNS else None
    lines = [f"### Piecewise-affine law, campaign {name}: errors on the held-out bounces "
             "(one per launcher setting); the paper's Table 2 in brackets\n"]
    head = ["quantity"]
    for label in pw:
        head += [f"{label}: overall", "roll", "slip"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "---|" * len(head))
    for q in ("n", "delta", "delta_xdot", "delta_ydot", "delta_omega", "mismatched"):
        cells = [q]
        for res in pw.values():
            t = res.errors.loc["test"]
            for subset in ("all", "roll", "slip"):
                if q == "mismatched":
                    v = res.test_mismatched if subset == "all" else None
                else:
                    v = t.loc[subset, q] if subset in t.index else None
                if v is None or (isinstance(v, float) and np.isnan(v)):
                    cells.append("")
                    continue
                cell = f"{int(v)}" if q == "n" else f"{100 * v:.3g} %"
                key = "overall" if subset == "all" else subset
                if paper is not None and q != "n" and "SVM" in next(k for k, r in pw.items() if r is res):
                    ref = paper.loc[key, q]
                    cell += f" ({100 * ref:.3g} %)" if np.isfinite(ref) else ""
                cells.append(cell)
        lines.append("| " + " | ".join(cells) + " |")
    for label, res in pw.items():
        lines.append(f"\n- {label}: {res.model.plane_equation()} (fitted on {res.n_train} bounces, "
                     f"delta on them {100 * res.delta:.3g} %)")
    return "\n".join(lines) + "\n"


def _md_to_html(md: str) -> str:
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


def _index_html(report: Report) -> str:
    from bouncelab import __version__
    from bouncelab.data.published import CITATION

    parts = ["<!doctype html><html><head><meta charset='utf-8'><title>bouncelab report</title>",
             f"<style>{_CSS}</style></head><body>",
             "<h1>bouncelab: golf-ball bounce laws</h1>",
             f"<p>Reproduction of the analysis of {html.escape(CITATION)} "
             f"Made by bouncelab {__version__} in {report.elapsed:.1f} s. Errors are the paper's delta and "
             "Delta q (fractions of the landing state's norm, shown in per cent); velocities in ball radii per "
             "second, spin in rad/s.</p>",
             "<nav>" + "".join(f"<a href='#{html.escape(n)}'>campaign {html.escape(n)}</a>" for n in report.sections)
             + "</nav>"]
    for name, sec in report.sections.items():
        parts.append(f"<h2 id='{html.escape(name)}'>Campaign {html.escape(name)}</h2>")
        for note in sec["notes"]:
            parts.append(f"<p class='warning'>{html.escape(note)}</p>")
        for _title, md in sec["tables"].items():
            parts.append(_md_to_html(md))
        if sec["laws"]:
            links = ", ".join(f"<a href='{html.escape(p.relative_to(report.out).as_posix())}'>{html.escape(n)}</a>"
                              for n, p in sec["laws"].items())
            parts.append(f"<p>Fitted laws (JSON, load with <code>bouncelab.load_law</code>): {links}</p>")
        for caption, path in sec["figures"].items():
            rel = html.escape(path.relative_to(report.out).as_posix())
            cap = html.escape(caption)
            parts.append(f"<h3>{cap}</h3><a href='{rel}'><img src='{rel}' alt='{cap}'></a>")
    rels = [html.escape(p.relative_to(report.out).as_posix()) for p in report.files]
    items = "".join(f"<li><a href='{r}'>{r}</a></li>" for r in rels)
    parts.append(f"<h2>Files</h2><ul>{items}</ul></body></html>")
    return "\n".join(parts)
