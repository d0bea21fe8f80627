"""The HTML views of fitting's results (``_repr_html_``): a FitResult, a Comparison, an Assessment, a Posterior.

Each view is one builder here; the classes only call it, so that a result keeps one job. The builders read
the results' public attributes only (a Posterior's through :func:`_get`, which falls back when an attribute
is missing, so that a renamed field costs a row of the view, not the view). Every text from data is escaped
(:mod:`bouncelab.core._html`); figures are inline PNGs when matplotlib is installed
(:mod:`bouncelab.core._inline`) and a line saying so when it is not. Errors are shown in per cent, as the
paper prints them (the results hold fractions).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.core._html import cell, escape, fragment, markdown, parameter_table, table
from bouncelab.core._inline import figure
from bouncelab.laws._display import bound_value, unit_text
from bouncelab.laws.provenance import Provenance
from bouncelab.laws.registry import law_name
from bouncelab.metrics import ERROR_COLUMNS

__all__ = ["assessment_html", "comparison_html", "fit_result_html", "posterior_html"]

#: Error columns as headed in the views (per cent).
ERROR_HEADINGS = {"n": "bounces", "delta": "δ (%)", "delta_xdot": "Δẋ (%)", "delta_ydot": "Δẏ (%)",
                  "delta_omega": "Δω (%)", "delta_sd": "δ sd over folds (%)"}
#: Most points drawn in a scatter of a view (a larger set is thinned evenly).
MAX_POINTS = 2000
_COMPONENTS = ("ẋ_F (radii/s)", "ẏ_F (radii/s)", "ω_F (rad/s)")


def _facts(pairs: list[tuple[str, Any]]) -> str:
    """A definition list of (label, value) pairs, values formatted by :func:`~bouncelab.core._html.cell`."""
    return "<dl>" + "".join(f"<dt>{escape(k)}</dt><dd>{v if isinstance(v, _Raw) else cell(v, digits=6)}</dd>"
                            for k, v in pairs) + "</dl>"


class _Raw(str):
    """Text already escaped (HTML) for :func:`_facts`."""


def _notes(notes: Any, css: str = "note") -> str:
    notes = [str(n) for n in (notes or [])]
    if not notes:
        return ""
    return f"<div class='{css}'><ul>" + "".join(f"<li>{escape(n)}</li>" for n in notes) + "</ul></div>"


def _error_rows(frame: Any, index_label: Any = None) -> tuple[list[list[Any]], list[str]]:
    """Rows and header of an error table (fractions in the frame, per cent in the view)."""
    cols = [c for c in ("n", *ERROR_COLUMNS, "delta_sd") if c in frame.columns]
    rows = []
    for idx, r in frame.iterrows():
        label = ", ".join(map(str, idx)) if isinstance(idx, tuple) else str(idx)
        rows.append([label, *[int(r[c]) if c == "n" else 100 * float(r[c]) for c in cols]])
    return rows, [index_label or "", *[ERROR_HEADINGS[c] for c in cols]]


def _thin(n: int) -> np.ndarray:
    return np.arange(n) if n <= MAX_POINTS else np.linspace(0, n - 1, MAX_POINTS).round().astype(int)


def _synthetic_mark(synthetic: bool) -> str | None:
    return "synthetic data" if synthetic else None


# ------------------------------------------------------------------------------------------------ FitResult
def _fit_parameter_rows(res: Any) -> list[dict[str, Any]]:
    rows = []
    for name, p in res.params.items():
        value = p.value if p.is_scalar else np.asarray(p.value).tolist()
        row: dict[str, Any] = {"name": name, "value": value, "unit": unit_text(p.unit)}
        if name in res.bounds:
            lo, hi = res.bounds[name]
            row["bounds"] = (bound_value(lo), bound_value(hi))
        row["vary"] = name not in res.fixed
        if p.stderr is not None:
            row["uncertainty"] = p.stderr if np.ndim(p.stderr) == 0 else np.asarray(p.stderr).tolist()
        notes = []
        if name in res.fixed:
            notes.append("held")
        elif name in res.at_bounds:
            notes.append(f"at {res.at_bounds[name]} bound")
        notes += [f"{k} at {v} bound" for k, v in res.at_bounds.items() if k.startswith(f"{name}[")]
        if name in res.insensitive:
            lo, hi = res.insensitive[name]
            row["identifiability"] = f"not determined by the data: the same fit from {lo:.4g} to {hi:.4g}"
        row["note"] = "; ".join(notes)
        rows.append(row)
    if not any(r.get("identifiability") for r in rows):
        for r in rows:
            r.pop("identifiability", None)
    return rows


def _draw_predictions(data: Mapping[str, tuple[np.ndarray, np.ndarray]], model: Any):
    labels = {"train": "fitted", "test": "held out"}

    def draw(fig: Any) -> None:
        axes = fig.subplots(1, 3)
        for name, (p0, pf) in data.items():
            keep = _thin(len(p0))
            pred = model._evaluate(p0[keep])
            for k, ax in enumerate(axes):
                ax.scatter(pf[keep, k], pred[:, k], s=5, alpha=0.6, label=labels.get(name, name))
        for k, ax in enumerate(axes):
            lo, hi = min(ax.get_xlim()[0], ax.get_ylim()[0]), max(ax.get_xlim()[1], ax.get_ylim()[1])
            ax.plot([lo, hi], [lo, hi], color="k", lw=0.6)
            ax.set_xlim(lo, hi)
            ax.set_ylim(lo, hi)
            ax.set_xlabel(f"measured {_COMPONENTS[k]}", fontsize=8)
            ax.tick_params(labelsize=7)
        axes[0].set_ylabel("predicted", fontsize=8)
        if len(data) > 1:
            axes[0].legend(fontsize=7)

    return draw


def fit_result_html(res: Any) -> str:
    """A FitResult's view: what the fit did, its parameters (with uncertainty where known), its errors per
    slip/roll class, diagnostics, notes and predicted against measured lift-offs."""
    law = res.model
    prov = law.provenance
    parts = [f"<h3>Fit of {escape(law_name(law))} by {escape(res.method)}</h3>"]
    note = None if prov is None else prov.synthetic_note()
    if note is not None:
        parts.append(f"<p class='warning'>{escape(note[0].upper() + note[1:])}.</p>")
    held = f", {res.n_test} held out" if res.n_test else ""
    parts.append(_facts([
        ("bounces", _Raw(escape(f"{res.n_train} fitted{held}"))),
        ("minimised", _Raw(escape(res.objective) + " = " + cell(res.objective_value, digits=6))),
        ("algorithm", res.algorithm),
        ("evaluations", _Raw(escape(f"{res.n_evaluations} ({res.n_global} global + {res.n_local} local)"))),
        ("time", _Raw(escape(f"{res.elapsed * 1e3:.1f} ms"))),
        ("seed", res.seed),
        ("stopped", res.stop_reason),
    ]))
    parts.append(parameter_table(_fit_parameter_rows(res), caption="Parameters", digits=6))
    lines = law._summary_lines()
    if lines:
        parts.append("<ul>" + "".join(f"<li>{escape(line)}</li>" for line in lines) + "</ul>")
    frame = res.errors.rename(index={"train": "fitted", "test": "held out"}, level=0)
    rows, header = _error_rows(frame, "bounces, class")
    parts.append(table(rows, header, caption="Errors by measured slip/roll class (per cent of the landing state)",
                       digits=4))
    if res.diagnostics:
        diag = [[k, v, res.test_diagnostics.get(k)] for k, v in res.diagnostics.items()]
        parts.append(table(diag, ["diagnostic", "fitted", "held out"], caption="The law's diagnostics"))
    parts.append(_notes(res.notes))
    if res.data:
        parts.append(figure(_draw_predictions(res.data, law), "predicted against measured lift-off",
                            size=(7.5, 2.5), note=_synthetic_mark(prov is not None and prov.synthetic)))
    if prov is not None:
        parts.append(f"<p>Fitted to {escape(prov.summary())}.</p>")
    return fragment("\n".join(p for p in parts if p))


# ------------------------------------------------------------------------------------------------ Comparison
def _draw_comparison(cmp: Any):
    t = cmp.table
    which = "test" if cmp.split else "train"
    series = [(f"{which}_delta", "held-out split" if cmp.split else "fitted bounces", None)]
    if "heldout_delta" in t.columns and t["heldout_delta"].notna().any():
        series.append(("heldout_delta", "cross-validated (held out)", "heldout_delta_sd"))

    def draw(fig: Any) -> None:
        ax = fig.subplots()
        y = np.arange(len(t.index))
        height = 0.8 / len(series)
        for k, (col, label, sd) in enumerate(series):
            if col not in t.columns:
                continue
            err = 100 * t[sd].to_numpy(dtype=float) if sd and sd in t.columns else None
            ax.barh(y + k * height, 100 * t[col].to_numpy(dtype=float), height, xerr=err, label=label)
        ax.set_yticks(y + height * (len(series) - 1) / 2, [str(i) for i in t.index], fontsize=8)
        ax.invert_yaxis()
        ax.set_xlabel("δ (%)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))

    return draw


def comparison_html(cmp: Any) -> str:
    """A Comparison's view: its tables (:meth:`~bouncelab.fitting.Comparison.to_markdown`, the paper's layout)
    and δ of each law, fitted and held out."""
    parts = []
    if getattr(cmp, "synthetic", False):
        parts.append("<p class='warning'>These bounces are synthetic: the fits describe the model that made them, "
                     "not real turf.</p>")
    parts.append(markdown(cmp.to_markdown()))
    if len(cmp.table.index):
        parts.append(figure(_draw_comparison(cmp), "delta of each law", size=(6.0, 0.6 + 0.35 * len(cmp.table.index)),
                            note=_synthetic_mark(getattr(cmp, "synthetic", False))))
    return fragment("\n".join(parts))


# ------------------------------------------------------------------------------------------------ Assessment
def _draw_profiles(profiles: Any, estimates: Mapping[str, float]):
    names = list(dict.fromkeys(profiles["parameter"]))[:8]

    def draw(fig: Any) -> None:
        axes = np.atleast_1d(fig.subplots(1, len(names)))
        for ax, name in zip(axes, names, strict=True):
            p = profiles[profiles["parameter"] == name].sort_values("value")
            ax.plot(p["value"], p["change"], marker=".", lw=1)
            ax.axhline(float(p["threshold"].iloc[0]), color="#a33", lw=0.8, ls="--")
            if name in estimates and np.isfinite(estimates[name]):
                ax.axvline(float(estimates[name]), color="k", lw=0.6)
            ax.set_xlabel(name, fontsize=8)
            ax.tick_params(labelsize=7)
        axes[0].set_ylabel("objective change", fontsize=8)

    return draw


def assessment_html(a: Any) -> str:
    """An Assessment's view: training and held-out errors, each parameter's estimate, intervals and
    identifiability verdict (with what it rests on), notes, and the profiles."""
    o = a.options
    n = int(a.scores.loc["training", "n"])
    parts = [f"<h3>Assessment of {escape(a.law)}</h3>",
             f"<p>{n} bounces; {a.n_free} free parameter(s); held out: {escape(o.get('k'))} folds by "
             f"{escape(a.split)}; bootstrap: {escape(o.get('n_bootstrap'))} resamples; {escape(o.get('starts'))} "
             "global starts.</p>"]
    prov = a.fit.model.provenance
    note = None if prov is None else prov.synthetic_note()
    if note is not None:
        parts.append(f"<p class='warning'>{escape(note[0].upper() + note[1:])}.</p>")
    rows, header = _error_rows(a.scores)
    parts.append(table(rows, header, caption="Errors (per cent of the landing state)"))
    level = o.get("level", 0.95)
    head = ["parameter", "estimate", f"{100 * level:g} % bootstrap interval", "spread over starts",
            "profile within noise", "identifiability", "correlated with"]
    parts.append(table([[name, *cells] for name, cells in a.table_rows()], head, caption="Parameters"))
    if "reason" in a.parameters.columns:
        why = [(str(k), f"{r['verdict']}: {r['reason']}") for k, r in a.parameters.iterrows()
               if r["verdict"] != "fixed"]
        if why:
            parts.append("<ul>" + "".join(f"<li><b>{escape(k)}</b> {escape(t)}</li>" for k, t in why) + "</ul>")
    for d in a.null_directions or []:
        parts_ = ", ".join(f"{k} {v:+.2f}" for k, v in d.get("parts", {}).items())
        parts.append(f"<p class='note'>A near-null direction of the residuals (singular value ratio "
                     f"{escape(cell(d.get('ratio')))}): {escape(parts_)}.</p>")
    parts.append(_notes(a.notes))
    if len(a.profiles):
        est = {str(k): float(v) for k, v in a.parameters["estimate"].items()
               if isinstance(v, int | float | np.floating) and math.isfinite(float(v))}
        parts.append("<p>Profiles: the objective's rise as each parameter is moved (the others refitted); the dashed "
                     "line is the data's noise.</p>")
        parts.append(figure(_draw_profiles(a.profiles, est), "profiles of the objective", size=(7.5, 2.2),
                            note=_synthetic_mark(prov is not None and prov.synthetic)))
    return fragment("\n".join(p for p in parts if p))


# ------------------------------------------------------------------------------------------------ Posterior
def _get(obj: Any, *names: str, default: Any = None) -> Any:
    """The first of ``names`` that ``obj`` has (a Posterior's fields may be renamed), else ``default``."""
    for name in names:
        if hasattr(obj, name):
            return getattr(obj, name)
    return default


def _draw_marginals(samples: Any):
    cols = list(samples.columns)[:8]

    def draw(fig: Any) -> None:
        axes = np.atleast_1d(fig.subplots(1, len(cols)))
        for ax, col in zip(axes, cols, strict=True):
            ax.hist(samples[col].to_numpy(dtype=float), bins=30, color="#4a7ab5")
            ax.set_xlabel(col, fontsize=7)
            ax.set_yticks([])
            ax.tick_params(labelsize=6)

    return draw


def _fixed(value: Any, decimals: int) -> str | None:
    """A number with ``decimals`` decimals (as the text report prints it), None for none."""
    return None if value is None else f"{float(value):.{decimals}f}"


def posterior_html(post: Any) -> str:
    """A Posterior's view: the model, the sampler and its convergence, the posterior summary, notes and each
    sampled number's marginal."""
    law = _get(post, "law", "model")
    name = law_name(law) if law is not None else "law"
    n = _get(post, "n_bounces", default=None)
    parts = [f"<h3>Hierarchical calibration of {escape(name)}</h3>"]
    synthetic = Provenance(0, data_kind=str(_get(post, "data_kind", default="unknown"))).synthetic
    if synthetic:
        parts.append("<p class='warning'>Calibrated on synthetic bounces: the posterior describes the model that "
                     "made them, not real turf.</p>")
    d = _get(post, "diagnostics", default={}) or {}
    converged = bool(d.get("converged", _get(post, "converged", default=False)))
    if not converged:
        parts.append(f"<p class='warning'>NOT converged: {escape(d.get('reason', 'see the diagnostics'))}. Treat the "
                     "numbers below as a demonstration, not an estimate.</p>")
    transforms = _get(post, "transforms", default={}) or {}
    vary = [f"{v} ({transforms[v].describe()})" if v in transforms and hasattr(transforms[v], "describe") else str(v)
            for v in (_get(post, "vary", default=[]) or [])]
    facts: list[tuple[str, Any]] = [("bounces", n), ("varying from bounce to bounce", ", ".join(vary) or "none"),
                                    ("residual term", _get(post, "residual", default=None))]
    if d:
        chains = d.get("chains")
        walkers = d.get("walkers")
        facts += [("sampler", f"{chains} chain(s), {walkers} walkers in all, {d.get('steps')} steps, burn-in "
                              f"{d.get('burn')}, {d.get('kept_steps')} kept per walker"),
                  ("acceptance", _fixed(d.get("acceptance"), 2)),
                  ("convergence", d.get("reason")),
                  ("max autocorrelation time", _fixed(max(d["autocorr"]) if d.get("autocorr") else None, 1)),
                  ("max split R-hat", _fixed(max(d["rhat"]) if d.get("rhat") else None, 3)),
                  ("time", None if d.get("elapsed_s") is None else f"{d['elapsed_s']:.1f} s")]
    parts.append(_facts(facts))
    try:
        summary = post.summary()
    except (AttributeError, TypeError, KeyError, ValueError):  # a posterior without the summary of today's
        summary = None
    if summary is not None:
        level = summary.attrs.get("level", 0.95)
        head = ["quantity", *[f"{c} ({100 * level:g} %)" if c in ("low", "high") else c for c in summary.columns]]
        parts.append(table([[str(k), *r.tolist()] for k, r in summary.iterrows()], head,
                           caption="Posterior (population values; scales in the transformed space)"))
    parts.append(_notes(_get(post, "notes", default=[])))
    samples = _get(post, "samples", default=None)
    if samples is not None and len(samples):
        parts.append(figure(_draw_marginals(samples), "posterior marginals", size=(7.5, 1.8),
                            note=_synthetic_mark(synthetic)))
    return fragment("\n".join(p for p in parts if p))
