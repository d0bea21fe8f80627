"""Execute the tour's notebooks and write each one's documentation page (``NAME.md`` beside ``NAME.ipynb``).

The notebooks are stored without outputs. This script runs each in a fresh temporary directory with
nbclient and an ipykernel running this Python (nothing is downloaded), and writes its page: the markdown
cells as they are, the code cells as Python blocks, and below each the outputs of that run (bouncelab's
HTML views and pandas tables as HTML, everything else as text, PNG figures as files in ``img/``). The
parts that come from a run sit between ``<!-- output -->`` and ``<!-- /output -->``, so that
``tests/test_notebooks.py`` can check that a page still shows its notebook's code and text.

Usage (from the repository root)::

    .venv/bin/python docs/notebooks/make_pages.py            # every notebook
    .venv/bin/python docs/notebooks/make_pages.py 02_fit     # those whose name contains 02_fit
"""

from __future__ import annotations

import base64
import contextlib
import json
import os
import re
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
IMG = HERE / "img"
#: The kernel the notebooks run on: this Python, whatever kernels the machine has installed.
KERNEL = "bouncelab-docs"
OPEN, CLOSE = "<!-- output -->", "<!-- /output -->"
HEADER = ("<!-- Made by docs/notebooks/make_pages.py from {name}.ipynb and a run of it: edit the notebook, then run "
          "`python docs/notebooks/make_pages.py` -->")


def notebooks() -> list[Path]:
    """The tour's notebooks, in order."""
    return sorted(HERE.glob("*.ipynb"))


@contextlib.contextmanager
def this_python_kernel() -> Iterator[str]:
    """A kernel spec named :data:`KERNEL` that runs ``python -m ipykernel_launcher`` with this interpreter, found
    first on ``JUPYTER_PATH`` for the duration; yields its name."""
    with tempfile.TemporaryDirectory(prefix="bouncelab-kernel-") as tmp:
        spec = Path(tmp) / "kernels" / KERNEL
        spec.mkdir(parents=True)
        (spec / "kernel.json").write_text(json.dumps({
            "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
            "display_name": "Python (bouncelab docs)", "language": "python"}))
        old = os.environ.get("JUPYTER_PATH")
        os.environ["JUPYTER_PATH"] = tmp + (os.pathsep + old if old else "")
        try:
            yield KERNEL
        finally:
            if old is None:
                os.environ.pop("JUPYTER_PATH", None)
            else:
                os.environ["JUPYTER_PATH"] = old


def execute(path: Path, cwd: Path, *, timeout: int = 300) -> tuple[Any, float]:
    """Run the notebook at ``path`` in the folder ``cwd``; return the executed notebook and its wall time (s).
    A cell that raises stops the run with nbclient's ``CellExecutionError``."""
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    with this_python_kernel() as kernel:
        client = NotebookClient(nb, timeout=timeout, kernel_name=kernel, resources={"metadata": {"path": str(cwd)}})
        start = time.perf_counter()
        client.execute()
    return nb, time.perf_counter() - start


def _is_html_view(html: str) -> bool:
    """HTML that a page shows as HTML: bouncelab's views and pandas tables (others, e.g. xarray's, as text)."""
    return html.lstrip().startswith("<div class='bouncelab'>") or 'class="dataframe"' in html


def _text_block(text: str) -> str:
    fence = "````" if "```" in text else "```"
    return f"{fence}text\n{text.rstrip()}\n{fence}"


def _outputs(cell: Any, stem: str, counter: list[int]) -> list[str]:
    parts = []
    for out in cell.get("outputs", []):
        kind = out.get("output_type")
        if kind == "stream":
            parts.append(_text_block(out.get("text", "")))
        elif kind in ("execute_result", "display_data"):
            data = out.get("data", {})
            html = data.get("text/html")
            if isinstance(html, list):
                html = "".join(html)
            if html and _is_html_view(html):
                parts.append(html.strip())
            elif "image/png" in data:
                counter[0] += 1
                IMG.mkdir(exist_ok=True)
                name = f"{stem}-{counter[0]}.png"
                (IMG / name).write_bytes(base64.b64decode(data["image/png"]))
                parts.append(f"![figure {counter[0]} of the notebook](img/{name})")
            elif "text/plain" in data:
                parts.append(_text_block(data["text/plain"]))
        elif kind == "error":
            parts.append(_text_block("\n".join(out.get("traceback", []))))
    return parts


def page(nb: Any, stem: str, *, seconds: float | None = None) -> str:
    """The markdown page of notebook ``nb`` (named ``stem``): with the outputs it holds, between the markers."""
    counter = [0]
    lines = [HEADER.format(name=stem), ""]
    for k, cell in enumerate(nb.cells):
        if cell.cell_type == "markdown":
            lines += [cell.source.strip(), ""]
            if k == 0:
                lines += [f"[Download the notebook]({stem}.ipynb) (stored without outputs; the outputs below are "
                          "from a run of it).", ""]
                if seconds is not None:
                    lines += [OPEN, f"This run took {seconds:.1f} s.", CLOSE, ""]
        elif cell.cell_type == "code":
            lines += ["```python", cell.source.rstrip(), "```", ""]
            outs = _outputs(cell, stem, counter)
            if outs:
                lines += [OPEN, "", *[p + "\n" for p in outs], CLOSE, ""]
    return "\n".join(lines).rstrip() + "\n"


def without_outputs(text: str) -> str:
    """A page with the parts that come from a run taken out (what must match the notebook itself)."""
    return re.sub(rf"{re.escape(OPEN)}.*?{re.escape(CLOSE)}\n\n?", "", text, flags=re.DOTALL)


def main(argv: list[str]) -> None:
    for path in notebooks():
        if argv and not any(a in path.stem for a in argv):
            continue
        for old in IMG.glob(f"{path.stem}-*.png") if IMG.exists() else ():
            old.unlink()
        with tempfile.TemporaryDirectory(prefix="bouncelab-nb-") as tmp:
            nb, seconds = execute(path, Path(tmp))
        path.with_suffix(".md").write_text(page(nb, path.stem, seconds=seconds), encoding="utf-8")
        print(f"{path.name:<32} {seconds:6.1f} s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
