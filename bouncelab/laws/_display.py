"""A law's HTML view (``BounceModel._repr_html_``): what it is, its equation, its parameters and what it was fitted to.

The equation is the law class's ``equation`` attribute when it has one (plain text), else the
``.. math::`` blocks of its docstring as Unicode text (:mod:`bouncelab.core._tex`): no MathJax, nothing
loaded. Every piece comes from the law's declaration (:attr:`~bouncelab.BounceModel.params`,
``regimes``, options, ``_summary_lines``) and its provenance, so a law written by a user shows itself
as bouncelab's own do. The pieces are reused by the views of the layers above (a fit, a surface).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.core._html import cell, escape, fragment, parameter_table, table
from bouncelab.core._tex import math_blocks, summary_line
from bouncelab.laws.provenance import RANGE_UNITS, Provenance
from bouncelab.laws.registry import law_name

__all__ = ["bound_value", "equation_text", "law_html", "law_section", "parameter_rows", "provenance_html",
           "unit_text"]

#: Shown where a law's view would list identifiability: a law alone does not know it.
IDENTIFIABILITY_UNKNOWN = ("Which parameters the data determine is not known from the law alone: "
                           "bouncelab.assess(law, data) tells (identifiable, weakly or not).")


def unit_text(unit: str) -> str:
    """A parameter's unit as the views print it: nothing for a dimensionless number ("1")."""
    return "" if unit in ("1", "") else unit


def equation_text(cls: type) -> str:
    """The law's equation as plain text: its class attribute ``equation`` (a string) if it has one, else the
    ``.. math::`` blocks of its docstring (blank line between blocks); "" when it states none."""
    given = getattr(cls, "equation", None)
    if isinstance(given, str) and given.strip():
        return given.strip()
    return "\n\n".join(math_blocks(cls.__doc__))


def _value(value: Any) -> Any:
    """A parameter value for :func:`bouncelab.core._html.cell`: a number, or an array as nested lists."""
    if value is None or np.ndim(value) == 0:
        return value
    return np.asarray(value).tolist()


def bound_value(value: Any) -> Any:
    """A bound for a table: a number, also for an array whose elements share it; else nested lists."""
    if value is None or np.ndim(value) == 0:
        return value
    arr = np.asarray(value, dtype=float)
    return float(arr.flat[0]) if arr.size and bool(np.all(arr == arr.flat[0])) else arr.tolist()


def parameter_rows(law: Any, *, identifiability: Mapping[str, str] | None = None) -> list[dict[str, Any]]:
    """One mapping per parameter of ``law`` for :func:`~bouncelab.core._html.parameter_table`: value, unit, search
    bounds, physical range, whether it varies in a fit, its meaning, and ``identifiability`` where given."""
    rows = []
    for name, p in law.params.items():
        row = {"name": name, "value": _value(p.value), "unit": unit_text(p.unit),
               "bounds": tuple(bound_value(b) for b in p.bounds),
               "physical": tuple(bound_value(b) for b in p.physical),
               "vary": p.vary, "doc": p.doc}
        if identifiability is not None:
            row["identifiability"] = identifiability.get(name)
        rows.append(row)
    return rows


def provenance_html(prov: Provenance | None) -> str:
    """What the law was fitted to: a warning for synthetic bounces, the landings it was fitted on."""
    if prov is None:
        return "<p>Provenance: none recorded (a law given its values, not fitted by bouncelab.fit).</p>"
    parts = []
    note = prov.synthetic_note()
    if note is not None:
        parts.append(f"<p class='warning'>{escape(note[0].upper() + note[1:])}.</p>")
    parts.append(f"<p>Fitted to {escape(prov.summary())}.</p>")
    if prov.source:
        parts.append(f"<p>Source: {escape(prov.source)}</p>")
    if prov.landing_ranges:
        rows = [[k, lo, hi, RANGE_UNITS.get(k, "")] for k, (lo, hi) in prov.landing_ranges.items()]
        parts.append(table(rows, ["landings fitted", "min", "max", "unit"],
                           caption="Where the law was fitted (not where it holds)"))
    return "\n".join(parts)


def law_section(law: Any, *, heading: str = "h3", equation: bool = True, provenance: bool = True,
                identifiability: Mapping[str, str] | None = None) -> str:
    """The body of a law's view (no wrapper): heading, summary, equation, parameters, options, regimes, the law's
    own lines, provenance. ``identifiability`` (parameter -> verdict) adds that column."""
    cls = type(law)
    state = "" if law.is_fitted else " (unfitted: no values yet)"
    parts = [f"<{heading}>{escape(law_name(law))}{escape(state)}</{heading}>"]
    summary = summary_line(cls.__doc__)
    if summary:
        parts.append(f"<p>{escape(summary)}</p>")
    eq = equation_text(cls) if equation else ""
    if eq:
        parts.append(f"<pre class='equation'>{escape(eq)}</pre>")
    parts.append(parameter_table(parameter_rows(law, identifiability=identifiability), caption="Parameters",
                                 digits=6))
    if identifiability is None and equation:
        parts.append(f"<p>{escape(IDENTIFIABILITY_UNKNOWN)}</p>")
    facts = []
    if law.regimes:
        facts.append(("regimes", escape(", ".join(law.regimes))))
    defaults = {o.name: o.default for o in law.option_specs}
    for name, value in law.options.items():
        facts.append((f"option {name}", cell(value, digits=6) + ("" if value is not defaults[name] else " (default)")))
    if facts:
        parts.append("<dl>" + "".join(f"<dt>{escape(k)}</dt><dd>{v}</dd>" for k, v in facts) + "</dl>")
    lines = law._summary_lines()
    if lines:
        parts.append("<ul>" + "".join(f"<li>{escape(line)}</li>" for line in lines) + "</ul>")
    if provenance:
        parts.append(provenance_html(law.provenance))
    return "\n".join(parts)


def law_html(law: Any) -> str:
    """The law's view in a notebook (``_repr_html_``)."""
    return fragment(law_section(law))
