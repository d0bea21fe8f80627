"""Issue 32, item 3: the tour's notebooks (``docs/notebooks/``) run, are stored without outputs, and are shown in
the docs.

Each notebook is executed here with nbclient on an ipykernel running this Python (the ``test`` extra;
nothing is downloaded), in a temporary folder, and must show what it is there to show. Its documentation
page (``NAME.md``, written by ``docs/notebooks/make_pages.py`` from a run) must show the notebook's own
text and code, with tables and figures from that run, and be listed in the site's navigation.
"""

from __future__ import annotations

import base64
import importlib.util
import re
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat", reason="the notebooks need the test extra (nbformat, nbclient, ipykernel)")
pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

ROOT = Path(__file__).resolve().parents[1]
HERE = ROOT / "docs" / "notebooks"
_spec = importlib.util.spec_from_file_location("make_pages", HERE / "make_pages.py")
make_pages = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_pages)

NOTEBOOKS = ["01_camera_to_campaign", "02_fit_and_compare", "03_assess_and_calibrate", "04_surface_runout"]

#: What each notebook's outputs must show (text in its outputs, read as one string), beyond running.
SHOWS = {
    "01_camera_to_campaign": ["failures: []", "gaps (after frame, missing): [(27, 2)]", "5000 frames/s, 12-bit",
                              "data_kind:      synthetic surrogate", "within targets"],
    "02_fit_and_compare": ["synthetic surrogate - 330 bounces", "<h3>Fit of Rigid by global</h3>",
                           "<th>Rigid</th><th>PennerFixed</th><th>PennerVarying</th>", "ẏ_F = -r ẏ_0"],
    "03_assess_and_calibrate": ["<h3>Assessment of Rigid</h3>", "<th>identifiability</th>",
                                "<h3>Hierarchical calibration of Rigid</h3>", "NOT converged"],
    "04_surface_runout": ["<h3>Surface tee B (synthetic fit)</h3>", "<h3>Run of 5 shot(s) on surface tee B",
                          "turf-B preset", "flight skid roll rest"],
}


def _outputs_text(nb) -> str:
    parts = []
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream":
                parts.append(out.get("text", ""))
            for value in out.get("data", {}).values():
                parts.append(value if isinstance(value, str) else "")
    return "\n".join(parts)


def test_the_tour_is_these_notebooks():
    assert [p.stem for p in make_pages.notebooks()] == NOTEBOOKS


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_each_notebook_is_stored_without_outputs(name):
    nb = nbformat.read(HERE / f"{name}.ipynb", as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(c.outputs == [] and c.execution_count is None for c in code)
    assert nb.metadata["kernelspec"]["name"] == "python3"
    first = nb.cells[0]
    assert first.cell_type == "markdown" and first.source.startswith("# ")
    assert "synthetic" in first.source.lower()  # every notebook says its data are synthetic, first


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_each_notebook_has_its_page_in_the_docs_with_tables_and_figures(name):
    nb = nbformat.read(HERE / f"{name}.ipynb", as_version=4)
    text = (HERE / f"{name}.md").read_text(encoding="utf-8")
    # The page shows the notebook's own text and code (else: python docs/notebooks/make_pages.py).
    assert make_pages.without_outputs(text).rstrip() == make_pages.page(nb, name).rstrip()
    assert f"notebooks/{name}.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    # ... and what a run of it gave: tables, and figures (inline PNGs, or files beside the page).
    outputs = "".join(re.findall(rf"{re.escape(make_pages.OPEN)}(.*?){re.escape(make_pages.CLOSE)}", text, re.S))
    assert "<table" in outputs
    inline = re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", outputs)
    files = re.findall(r"\]\((img/[^)]+\.png)\)", outputs)
    assert inline or files
    assert all(base64.b64decode(p).startswith(b"\x89PNG") for p in inline)
    for f in files:
        png = HERE / f
        assert png.read_bytes().startswith(b"\x89PNG") and png.stat().st_size < 200_000
    for shown in SHOWS[name]:
        assert shown in outputs, shown


@pytest.mark.slow
@pytest.mark.parametrize("name", NOTEBOOKS)
def test_each_notebook_runs_and_shows_what_it_says(name, tmp_path):
    """Runs in CI (slow: 6-12 s each with the kernel's start on a 2-core machine)."""
    nb, seconds = make_pages.execute(HERE / f"{name}.ipynb", tmp_path)
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.get("output_type") == "error"]
    assert not errors
    shown = _outputs_text(nb)
    for text in SHOWS[name]:
        assert text in shown, text
    assert "<table" in shown and ("image/png" in str(nb) or "data:image/png;base64," in shown)
    if name == "01_camera_to_campaign":
        assert "<td>False</td>" not in shown  # every clip measured within the tracking's targets
        assert sorted(p.name for p in (tmp_path / "clips").iterdir())[0] == "s1_r1.cine"
    print(f"{name}: {seconds:.1f} s")
