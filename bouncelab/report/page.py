"""The report's page: ``index.html`` in the report folder, and the report's own view in a notebook.

One function, :func:`report_html`, writes both: the page links its figures and files (``inline=False``,
the folder's ``index.html``) or holds its figures as base64 PNGs (``inline=True``, what
``Report._repr_html_`` shows, so that a report shows itself wherever it is displayed).
"""

from __future__ import annotations

from typing import Any

from bouncelab.core._html import escape, fragment, image, markdown, page

# The report's types (bouncelab.report.model) are not imported here, not even for type checkers: the model
# imports this module to show itself, and the package has no import circle, counted either way.
Report = Section = Any

__all__ = ["report_html"]


def _paper_values(report: Report) -> str:
    """What the brackets in the tables mean, said only when some campaign has the paper's values."""
    from bouncelab.core import published

    with_paper = [n for n, sec in report.sections.items() if sec.paper_campaign in published.CAMPAIGNS]
    if not with_paper:
        return ("None of these campaigns is one of the paper's, so no published values are shown beside "
                "the results.")
    synthetic = [n for n in with_paper if report.sections[n].synthetic]
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


def _items(records: list[Any]) -> str:
    return "".join(f"<li>campaign {escape(c)}, {escape(w)}: {escape(r)}</li>" for c, w, r in records)


def _inputs(sec: Section) -> str:
    rows = "".join(f"<dt>{escape(what)}</dt><dd>{escape(text)}</dd>" for what, text in sec.inputs.lines())
    return f"<dl class='inputs'>{rows}</dl>"


def _section(report: Report, name: str, sec: Section, inline: bool) -> list[str]:
    parts = [f"<h2 id='{escape(name)}'>Campaign {escape(name)}</h2>", _inputs(sec)]
    for note in sec.notes:
        parts.append(f"<p class='warning'>{escape(note)}</p>")
    if sec.generator:
        gen = escape(sec.generator)
        parts.append(f"<p class='warning'>{gen} generated these data: " + (
            "in every table of laws it is marked †, and its fit is not a test of it.</p>"
            if sec.generator in sec.law_names else
            "it is not among the laws fitted here; a fit of it would be no test of it.</p>"))
    if sec.caveats:
        parts.append("<div class='note'><p><b>What to trust:</b></p><ul>"
                     + "".join(f"<li>{escape(text)}</li>" for text in sec.caveats) + "</ul></div>")
    for table in sec.tables.values():
        if table.markdown is not None:
            parts.append(markdown(table.markdown))
    listed = [law for law in sec.laws.values() if law.listed]
    if listed:
        if inline or report.out is None:
            laws = ", ".join(escape(law.name) for law in listed)
            where = "" if report.out is None else f" in {escape(report.out / 'laws')}"
            parts.append(f"<p>Fitted laws (JSON{where}, load with <code>bouncelab.load_law</code>; in Python, "
                         f"<code>report.sections[{escape(repr(name))}].comparison</code>): {laws}</p>")
        else:
            links = ", ".join(f"<a href='{escape(law.files(name)[0])}'>{escape(law.name)}</a>" for law in listed)
            parts.append(f"<p>Fitted laws (JSON, load with <code>bouncelab.load_law</code>): {links}</p>")
    for fig in sec.figures.values():
        cap = escape(fig.caption)
        if fig.png is None:
            parts.append(f"<h3>{cap}</h3><p class='warning'>Not drawn: {escape(fig.reason)}</p>")
        elif inline:
            parts.append(f"<h3>{cap}</h3>{image(fig.png, fig.caption)}")
        else:
            rel = escape(fig.files(name)[0])
            parts.append(f"<h3>{cap}</h3><a href='{rel}'><img src='{rel}' alt='{cap}'></a>")
    return parts


def report_html(report: Report, *, inline: bool, standalone: bool) -> str:
    """The report's page: with its figures as files beside it (``inline=False``: ``index.html``) or inside it
    (base64 PNGs); a whole document (``standalone``) or a fragment for a notebook cell."""
    from bouncelab.core import __version__
    from bouncelab.core.published import CITATION

    runs = (f"seed {report.seed} (the held-out split, the folds, every fit and the bootstrap's resampling); laws: "
            f"{', '.join(report.laws)}; bootstrap: "
            + (f"{report.bootstrap} resamples of whole launcher settings" if report.bootstrap else "left out (0)"))
    parts = ["<h1>bouncelab: golf-ball bounce laws</h1>",
             f"<p>The analysis of {escape(CITATION.rstrip('.'))}, run on each campaign below. "
             f"Made by bouncelab {__version__} in {report.elapsed:.1f} s. Errors are the paper's delta and "
             "Delta q (fractions of the landing state's norm, shown in per cent); velocities are in ball radii per "
             f"second and spin in rad/s{_figure_units(report)}. {_paper_values(report)}</p>",
             f"<p>Run with {escape(runs)}.</p>",
             "<nav>" + "".join(f"<a href='#{escape(n)}'>campaign {escape(n)}</a>" for n in report.sections)
             + "</nav>"]
    skipped = report.skipped
    if skipped:
        parts.append(f"<div class='warning' id='skipped'><p><b>A partial report:</b> {len(skipped)} step(s) could "
                     f"not run on these data and were skipped; everything else is below.</p><ul>{_items(skipped)}"
                     "</ul></div>")
    left_out = report.left_out
    if left_out:
        parts.append(f"<div class='note' id='not-made'><p><b>Not made:</b> {len(left_out)} item(s) of the report, "
                     f"by choice or for want of what they need in the data:</p><ul>{_items(left_out)}</ul></div>")
    for name, sec in report.sections.items():
        parts += _section(report, name, sec, inline)
    if report.out is None:
        parts.append("<p>Kept in memory (<code>out=None</code>): no files written.</p>")
    elif inline:
        parts.append(f"<p>Written to {escape(report.out)} ({len(report.files)} files).</p>")
    else:
        rels = [escape(p.relative_to(report.out).as_posix()) for p in report.files]
        items = "".join(f"<li><a href='{r}'>{r}</a></li>" for r in rels)
        parts.append(f"<h2>Files</h2><ul>{items}</ul>")
    body = "\n".join(parts)
    return page("bouncelab report", body) if standalone else fragment(body)
