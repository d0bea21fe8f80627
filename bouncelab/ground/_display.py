"""The HTML views of the ground phase (``_repr_html_``): a Surface, a RunResult and a SurfaceFit.

One builder per class; the classes only call them. Every text from data is escaped
(:mod:`bouncelab.core._html`); figures are inline PNGs when matplotlib is installed
(:mod:`bouncelab.core._inline`) and a line saying so when it is not.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core._html import escape, fragment, parameter_table, table
from bouncelab.core._inline import figure
from bouncelab.laws._display import law_section, unit_text

__all__ = ["MAX_PATHS", "MAX_SHOT_ROWS", "run_result_html", "surface_fit_html", "surface_html"]

#: Runs of up to this many shots list every shot; larger ones summarise each column (min, median, max).
MAX_SHOT_ROWS = 12
#: Runs of up to this many shots are drawn as paths (side view); larger ones as their rest points (plan view).
MAX_PATHS = 50
#: Samples per second of the drawn paths (at most; the run's own rate if lower).
PATH_RATE = 200.0

_TOTALS = ("liftoff_speed", "liftoff_angle_deg", "liftoff_backspin", "bounces", "bounce_carry", "roll", "total_run",
           "lateral", "time_to_rest")


def _facts(pairs: list[tuple[str, str]]) -> str:
    return "<dl>" + "".join(f"<dt>{escape(k)}</dt><dd>{escape(v)}</dd>" for k, v in pairs) + "</dl>"


# ------------------------------------------------------------------------------------------------ Surface
def surface_body(surface: Any, heading: str = "h3") -> str:
    """The surface's numbers, where they come from, and its law (no wrapper)."""
    parts = [f"<{heading}>Surface {escape(surface.name)}</{heading}>"]
    if surface.description:
        parts.append(f"<p class='note'>{escape(surface.description)}</p>")
    parts.append(_facts([
        ("sliding friction", f"{surface.sliding_friction:.4g}"),
        ("green speed (Stimpmeter)", f"{surface.stimp_m:.4g} m ({surface.stimp_ft:.3g} ft)"),
        ("rolling deceleration", f"{surface.rolling_deceleration:.4g} m/s² (rolling resistance "
                                 f"{surface.rolling_resistance:.4g})"),
        ("pivot retention", f"{surface.pivot_retention:.4g}"),
        ("steepest slope a ball rests on", f"{surface.max_slope_deg():.3g}°"),
    ]))
    parts.append(law_section(surface.law, heading="h4", equation=False))
    return "\n".join(parts)


def surface_html(surface: Any) -> str:
    """A Surface's view: its numbers, its provenance (description) and its bounce law's parameters."""
    return fragment(surface_body(surface))


# ------------------------------------------------------------------------------------------------ RunResult
def _units(run: Any) -> dict[str, str]:
    length = run.length_unit
    u = getattr(run, "_units", None)
    speed = getattr(u, "velocity_unit", None) or ("radius/s" if length == "radius" else "m/s")
    spin = getattr(u, "spin_unit", None) or "rad/s"
    return {"liftoff_speed": speed, "liftoff_angle_deg": "deg", "liftoff_backspin": spin, "bounces": "",
            "bounce_carry": length, "roll": length, "total_run": length, "lateral": length, "time_to_rest": "s"}


def _draw_paths(run: Any):
    n = len(run)
    length = run.length_unit

    def draw(fig: Any) -> None:
        ax = fig.subplots()
        if n <= MAX_PATHS:
            path = run.sample(min(run.rate, PATH_RATE))
            pos = path["position"].to_numpy()  # (shot, time, axis)
            h = run.heading
            for i in range(n):
                along = pos[i] @ h[i]
                (line,) = ax.plot(along, pos[i, :, 2], lw=0.9)
                ax.plot(along[-1], pos[i, -1, 2], "v", color=line.get_color(), ms=4)
            ax.set_xlabel(f"along the landing heading ({length}); a triangle marks where the ball rests", fontsize=8)
            ax.set_ylabel(f"height ({length})", fontsize=8)
        else:
            rest = np.asarray(run.rest_position)
            ax.scatter(rest[:, 0], rest[:, 1], s=4, alpha=0.5)
            ax.set_xlabel(f"x ({length})", fontsize=8)
            ax.set_ylabel(f"y ({length})", fontsize=8)
            ax.set_title(f"rest points of the {n} shots (landing at the origin)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)

    return draw


def run_result_html(run: Any) -> str:
    """A RunResult's view: the run in a sentence, a table of its shots (each shot, or each column's range for
    many), the shots flagged, and the paths (side view) or rest points (plan view)."""
    t = run.totals
    units = _units(run)
    n = len(run)
    parts = [f"<h3>Run of {n} shot(s) on surface {escape(run.surface.name)}</h3>",
             f"<p>Lengths in {escape(run.length_unit)}; at rest after {float(np.max(run.rest_time)):.3g} s at "
             f"most; paths sampled at {run.rate:g} per second (<code>.path</code>).</p>"]
    cols = [c for c in _TOTALS if c in t.columns]
    header = [f"{c} ({units[c]})" if units.get(c) else c for c in cols]
    if n <= MAX_SHOT_ROWS:
        rows = [[str(i), *r] for i, r in zip(t.index, t[cols].to_numpy(dtype=float).tolist(), strict=True)]
        parts.append(table(rows, ["shot", *header], caption="Each shot (first bounce's lift-off, then the run)"))
    else:
        q = t[cols].astype(float).quantile([0.0, 0.5, 1.0])
        rows = [[name, *q.loc[k].tolist()] for k, name in ((0.0, "min"), (0.5, "median"), (1.0, "max"))]
        parts.append(table(rows, ["", *header], caption=f"The {n} shots: each column's range and median"))
    flags = {"into_ground": "bounces the law sent into the ground", "energy_gain": "bounces that gained energy",
             "bounce_limit": "shots still bouncing at max_bounces"}
    said = [f"{int(np.sum(t[c]))} {text}" for c, text in flags.items() if c in t.columns and np.sum(t[c])]
    if said:
        parts.append(f"<p class='warning'>{escape('; '.join(said))}.</p>")
    alt = "paths of the shots, side view" if n <= MAX_PATHS else "rest points of the shots, plan view"
    parts.append(figure(_draw_paths(run), alt, size=(7.0, 2.4 if n <= MAX_PATHS else 3.2)))
    return fragment("\n".join(parts))


# ------------------------------------------------------------------------------------------------ SurfaceFit
def _draw_rolls(pred: Any):
    def draw(fig: Any) -> None:
        ax = fig.subplots()
        ax.scatter(pred["observed_roll"], pred["predicted_roll"], s=8, alpha=0.7)
        lo = float(min(pred["observed_roll"].min(), pred["predicted_roll"].min()))
        hi = float(max(pred["observed_roll"].max(), pred["predicted_roll"].max()))
        ax.plot([lo, hi], [lo, hi], color="k", lw=0.6)
        ax.set_xlabel("observed roll-out (m)", fontsize=8)
        ax.set_ylabel("predicted (m)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)

    return draw


def surface_fit_html(fit: Any) -> str:
    """A SurfaceFit's view: what was fitted, each parameter with its bounds and whether the shots determine it,
    the held-out errors (or the in-sample ones without folds), notes, and predicted against observed roll-outs."""
    what = "rest-point distance" if fit.lateral else "absolute roll-out"
    parts = [f"<h3>Surface fitted to {fit.n_shots} launch-monitor shots: law {escape(fit.law)}</h3>",
             f"<p>{escape(fit.spin_kind)} spin, {'with side data' if fit.lateral else 'no side data'}; mean "
             f"{what} error {fit.mean_error:.3f} m on all the shots; {fit.n_evaluations} evaluations in "
             f"{fit.elapsed:.1f} s; seed {fit.seed}.</p>"]
    rows = []
    for name, r in fit.parameters.iterrows():
        row = {"name": str(name), "value": float(r["value"]), "unit": unit_text(str(r["unit"])),
               "bounds": (float(r["low"]), float(r["high"])), "vary": bool(r["vary"])}
        if r["vary"]:
            row["identifiability"] = "determined" if r["identified"] else "NOT determined by these shots"
            notes = []
            if np.isfinite(r["fold_min"]):
                notes.append(f"fold range {r['fold_min']:.4g} to {r['fold_max']:.4g}")
            notes.append(f"sensitivity {r['sensitivity']:.3g} m")
            if r["at_bound"]:
                notes.append(f"at its {r['at_bound']} bound")
            row["note"] = "; ".join(notes)
        rows.append(row)
    parts.append(parameter_table(rows, caption="Parameters (sensitivity: rise of the mean error at ±5 % of the box)",
                                 digits=5))
    held = len(fit.heldout) > 0
    errors = fit.errors if held else fit.fitted_errors
    names = {"shots": "shots", "observed_median_roll": "median roll (m)", "median_abs_error": "median |error| (m)",
             "abs_error_q25": "q25 |error| (m)", "abs_error_q75": "q75 |error| (m)", "mae": "mean |error| (m)",
             "baseline_median_abs_error": "baseline median |error| (m)"}
    cols = [c for c in names if c in errors.columns]
    caption = (f"Held out ({len(fit.folds)} folds over {fit.groups}s): roll-out = total - carry" if held else
               "No held-out errors (folds=0): roll-out on the fitted shots")
    parts.append(table([[str(k), *r.tolist()] for k, r in errors[cols].iterrows()], ["", *[names[c] for c in cols]],
                       caption=caption))
    if fit.bounce_limit:
        parts.append(f"<p class='warning'>{fit.bounce_limit} shot(s) were still bouncing at max_bounces on the "
                     "fitted surface.</p>")
    notes = [str(n) for n in fit.notes if str(n).strip()]
    if notes:
        parts.append("<div class='note'><ul>" + "".join(f"<li>{escape(n)}</li>" for n in notes) + "</ul></div>")
    pred = fit.heldout if held else fit.fitted_predictions
    if len(pred):
        parts.append(figure(_draw_rolls(pred), "predicted against observed roll-out", size=(3.6, 3.0)))
    parts.append(surface_body(fit.surface, heading="h4"))
    return fragment("\n".join(parts))
