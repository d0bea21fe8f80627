"""Small HTML pieces for the objects that show themselves (``_repr_html_``) and for the report's page.

Standard library only (:mod:`html`, :mod:`base64`): no template engine, nothing to install. Every
text that comes from data (names, units, file names, numbers) goes through :func:`escape`; the
helpers return HTML text that callers join. Everything is wrapped in a ``<div class="bouncelab">``
by :func:`fragment` (a notebook cell) or :func:`page` (a whole document), whose style sheet
:data:`STYLE` is scoped to that class so that it never restyles the rest of a notebook.

>>> table([["r", 0.5432], ["mu", float("nan")]], header=["parameter", "value"])
'<table><thead><tr><th>parameter</th><th>value</th></tr></thead><tbody><tr><td>r</td><td>0.5432</td></tr><tr><td>mu</td><td>–</td></tr></tbody></table>'
"""

from __future__ import annotations

import base64
import html
import math
import numbers
import re
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

__all__ = ["PARAMETER_COLUMNS", "STYLE", "cell", "escape", "fragment", "image", "markdown", "page",
           "parameter_table", "table"]

#: The style of every bouncelab HTML view, scoped to ``.bouncelab`` (a notebook's own styles stay as they are).
STYLE = """
.bouncelab { font-family: system-ui, sans-serif; color: #222; line-height: 1.4; }
.bouncelab table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.9em; }
.bouncelab th, .bouncelab td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
.bouncelab th:first-child, .bouncelab td:first-child { text-align: left; }
.bouncelab thead { background: #f2f2f2; }
.bouncelab img { max-width: 100%; border: 1px solid #ddd; margin: 0.4em 0 1.4em; }
.bouncelab .warning { background: #fff3cd; border: 1px solid #e0c36c; padding: 0.6em 1em; }
.bouncelab .note { background: #eef4fb; border: 1px solid #9bb9dd; padding: 0.6em 1em; }
.bouncelab blockquote { color: #555; border-left: 3px solid #ccc; margin: 0.6em 0; padding-left: 0.8em; }
.bouncelab nav a { margin-right: 1em; }
.bouncelab dl { display: grid; grid-template-columns: max-content auto; gap: 0.2em 1em; }
.bouncelab dt { font-weight: 600; }
.bouncelab dd { margin: 0; }
"""

#: The columns :func:`parameter_table` knows, in their order, with their headings.
PARAMETER_COLUMNS = {"name": "parameter", "value": "value", "unit": "unit", "bounds": "bounds",
                     "physical": "physical range", "vary": "varies", "uncertainty": "uncertainty",
                     "identifiability": "identifiability", "note": "note", "doc": "meaning"}


def escape(value: Any) -> str:
    """``str(value)`` safe inside HTML text and attribute values (quotes escaped too)."""
    return html.escape(str(value), quote=True)


def cell(value: Any, *, digits: int = 4, missing: str = "–") -> str:
    """One value as escaped text: numbers to ``digits`` significant digits, NaN and None as ``missing``,
    booleans as yes/no, sequences (arrays) as ``[a, b, ...]``."""
    if value is None:
        return missing
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, numbers.Integral):
        return escape(int(value))
    if isinstance(value, numbers.Real):
        v = float(value)
        return missing if math.isnan(v) else escape(f"{v:.{digits}g}")
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        return escape(value)
    return "[" + ", ".join(cell(v, digits=digits, missing=missing) for v in value) + "]"


def table(rows: Iterable[Sequence[Any]], header: Sequence[Any] | None = None, *, caption: str | None = None,
          digits: int = 4, missing: str = "–") -> str:
    """A ``<table>`` of ``rows`` (each a sequence of cells, formatted by :func:`cell`) under ``header``."""
    parts = ["<table>"]
    if caption:
        parts.append(f"<caption>{escape(caption)}</caption>")
    if header is not None:
        parts.append("<thead><tr>" + "".join(f"<th>{escape(h)}</th>" for h in header) + "</tr></thead>")
    parts.append("<tbody>" + "".join("<tr>" + "".join(f"<td>{cell(v, digits=digits, missing=missing)}</td>"
                                                      for v in row) + "</tr>" for row in rows) + "</tbody>")
    parts.append("</table>")
    return "".join(parts)


def parameter_table(parameters: Iterable[Mapping[str, Any]], *, caption: str | None = None, digits: int = 4) -> str:
    """A table of parameters, one mapping per parameter with any of the keys of :data:`PARAMETER_COLUMNS`
    (``name``, ``value``, ``unit``, ``bounds`` and ``physical`` as ``(low, high)``, ``vary``, ``uncertainty``,
    ``identifiability``, ``note``, ``doc``); a column appears when some parameter has it."""
    rows = list(parameters)
    columns = [key for key in PARAMETER_COLUMNS if any(key in row for row in rows)]

    def value(row: Mapping[str, Any], key: str) -> Any:
        v = row.get(key)
        if key in ("bounds", "physical") and v is not None:
            low, high = v
            return f"[{cell(low, digits=digits)}, {cell(high, digits=digits)}]"  # (escaped by cell below)
        return v

    return table(([value(row, key) for key in columns] for row in rows), [PARAMETER_COLUMNS[k] for k in columns],
                 caption=caption, digits=digits)


def image(png: bytes, alt: str, *, mime: str = "image/png") -> str:
    """An ``<img>`` holding ``png`` itself (a data URI): it shows without any file beside the page."""
    data = base64.b64encode(png).decode("ascii")
    return f"<img src='data:{mime};base64,{data}' alt='{escape(alt)}'>"


_HEADING = re.compile(r"^(#{1,6}) (.*)$")


def markdown(md: str) -> str:
    """The small markdown subset bouncelab writes (headings, pipe tables, ``- `` lists, ``> `` quotes,
    paragraphs) as HTML; every text escaped, nothing else interpreted."""
    out: list[str] = []
    block: list[str] = []
    kind = ""

    def flush() -> None:
        nonlocal kind
        if kind == "table":
            rows = [r.strip().strip("|").split("|") for r in block if not set(r.strip()) <= set("|-: ")]
            head, body = rows[0], rows[1:]
            out.append(table(([c.strip() for c in r] for r in body), [c.strip() for c in head]))
        elif kind == "list":
            out.append("<ul>" + "".join(f"<li>{escape(item)}</li>" for item in block) + "</ul>")
        block.clear()
        kind = ""

    for line in md.splitlines():
        this = "table" if line.startswith("|") else "list" if line.startswith("- ") else ""
        if this != kind:
            flush()
        if this:
            kind = this
            block.append(line if this == "table" else line[2:])
        elif m := _HEADING.match(line):
            level = len(m[1])
            out.append(f"<h{level}>{escape(m[2])}</h{level}>")
        elif line.startswith("> "):
            out.append(f"<blockquote>{escape(line[2:])}</blockquote>")
        elif line.strip():
            out.append(f"<p>{escape(line)}</p>")
    flush()
    return "\n".join(out)


def fragment(body: str) -> str:
    """``body`` wrapped for a notebook cell: its own scoped style sheet, nothing outside the ``div``."""
    return f"<div class='bouncelab'><style>{STYLE}</style>\n{body}\n</div>"


def page(title: str, body: str) -> str:
    """A whole HTML document titled ``title`` holding ``body``."""
    return (f"<!doctype html><html><head><meta charset='utf-8'><title>{escape(title)}</title>"
            f"<style>body {{ margin: 2em auto; max-width: 1200px; }}{STYLE}</style></head>"
            f"<body><div class='bouncelab'>\n{body}\n</div></body></html>")
