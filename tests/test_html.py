"""bouncelab.core._html: the small HTML pieces every ``_repr_html_`` is built from (standard library only)."""

from __future__ import annotations

import ast
import base64
import sys
from pathlib import Path

import numpy as np

from bouncelab.core import _html

REPO = Path(__file__).resolve().parents[1]


def test_everything_from_data_is_escaped():
    assert _html.escape("<b> & 'x' \"y\"") == "&lt;b&gt; &amp; &#x27;x&#x27; &quot;y&quot;"
    assert _html.table([["<script>", 1]], header=["a<", "b"]) == (
        "<table><thead><tr><th>a&lt;</th><th>b</th></tr></thead><tbody><tr><td>&lt;script&gt;</td><td>1</td></tr>"
        "</tbody></table>")
    assert "&lt;i&gt;" in _html.markdown("### <i>\n\n| <i> |\n|---|\n| 1 |\n") and "<i>" not in _html.markdown("<i>")
    assert "alt='a &#x27;b&#x27;'" in _html.image(b"x", "a 'b'")


def test_cells_are_formatted_for_reading():
    cell = _html.cell
    assert [cell(0.123456789), cell(12345.678), cell(np.float32(2.5)), cell(np.int64(7)), cell(3)] == [
        "0.1235", "1.235e+04", "2.5", "7", "3"]
    assert [cell(float("nan")), cell(None), cell(True), cell(False)] == ["–", "–", "yes", "no"]
    assert cell(np.array([1.0, 2.5, np.nan])) == "[1, 2.5, –]" and cell([[1, 2], [3, 4]]) == "[[1, 2], [3, 4]]"
    assert cell(0.123456789, digits=2) == "0.12" and cell(float("nan"), missing="nan") == "nan"


def test_parameter_table_shows_the_columns_it_is_given():
    html = _html.parameter_table([
        {"name": "r", "value": 0.5432, "unit": "", "bounds": (0.0, 1.0), "vary": True,
         "identifiability": "identifiable"},
        {"name": "mu", "value": 0.3, "unit": "", "bounds": (0.0, 1.5), "vary": False},
    ], caption="Rigid")
    head = html.split("<tbody>")[0]
    assert head.count("<th>") == 6 and "<th>uncertainty</th>" not in head  # no row has one: no column
    assert "<caption>Rigid</caption>" in html
    assert "<td>r</td><td>0.5432</td><td></td><td>[0, 1]</td><td>yes</td><td>identifiable</td>" in html
    assert "<td>mu</td><td>0.3</td><td></td><td>[0, 1.5]</td><td>no</td><td>–</td>" in html


def test_markdown_subset():
    md = "### Title\n\nSome text.\n\n| a | b |\n|---|---|\n| 1 | 2 |\n| 3 | 4 |\n\n- one\n- two\n> a note\n"
    html = _html.markdown(md)
    assert "<h3>Title</h3>" in html and "<p>Some text.</p>" in html
    assert "<tbody><tr><td>1</td><td>2</td></tr><tr><td>3</td><td>4</td></tr></tbody>" in html
    assert "<ul><li>one</li><li>two</li></ul>" in html and "<blockquote>a note</blockquote>" in html


def test_images_are_inline_and_wrappers_scope_their_style():
    png = bytes(range(256))
    img = _html.image(png, "fig")
    assert base64.b64decode(img.split("base64,")[1].split("'")[0]) == png
    frag = _html.fragment("<p>x</p>")
    assert frag.startswith("<div class='bouncelab'><style>") and frag.endswith("</div>")
    assert all(rule.strip().startswith(".bouncelab") for rule in _html.STYLE.strip().splitlines())
    page = _html.page("a <title>", "<p>x</p>")
    assert "<title>a &lt;title&gt;</title>" in page and "<div class='bouncelab'>" in page


def test_the_helper_needs_only_the_standard_library():
    tree = ast.parse((REPO / "bouncelab" / "core" / "_html.py").read_text(encoding="utf-8"))
    imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                for alias in node.names}
    imported |= {node.module.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert imported and imported <= set(sys.stdlib_module_names) | {"__future__"}, imported
