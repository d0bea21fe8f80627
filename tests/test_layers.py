"""The architecture holds: layers point one way, no import circle, and a law imports neither pandas nor the loader.

The import graph is read from the source: module- and function-level imports, and those under
``if TYPE_CHECKING:`` too (a type hint is a dependency: the arrows of the annotations point one way as well).
"""

from __future__ import annotations

import ast
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "bouncelab"

#: The folders from the bottom up, as the README's Layout lists them: each may import only from those
#: before it (the top-level package itself, ``bouncelab``, is the public face and sits above them all).
LAYERS = ["core", "laws", "data", "metrics", "fitting", "analysis", "simulation", "ground", "export",
          "estimators", "plots", "tracking", "report", "cli", "__main__"]


def _modules() -> dict[str, Path]:
    mods = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        mods[name] = path
    return mods


def import_graph() -> dict[str, set[str]]:
    """Module -> the bouncelab modules it imports (at any level of the file)."""
    mods = _modules()
    edges: dict[str, set[str]] = defaultdict(set)
    for name, path in mods.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                    base = ".".join(anchor + ([base] if base else []))
                subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in mods]
                targets = subs + ([base] if len(subs) < len(node.names) else [])
            else:
                continue
            for target in targets:
                while target and target not in mods:
                    target = target.rsplit(".", 1)[0] if "." in target else ""
                if target.startswith("bouncelab") and target != name:
                    edges[name].add(target)
    return edges


def _layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "bouncelab"


def test_no_import_circle_between_modules() -> None:
    edges = import_graph()
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(v: str) -> None:  # depth-first search; a grey node met again closes a circle
        state[v] = 1
        path.append(v)
        for w in sorted(edges.get(v, ())):
            if state.get(w) == 1:
                pytest.fail("import circle: " + " -> ".join([*path[path.index(w):], w]))
            if w not in state:
                visit(w)
        path.pop()
        state[v] = 2

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10_000))
    for v in sorted(_modules()):
        if v not in state:
            visit(v)


def test_layers_point_one_way() -> None:
    edges = import_graph()
    layers = {_layer(m) for m in _modules()} - {"bouncelab"}
    assert layers <= set(LAYERS), f"folders not placed in LAYERS (and the README's Layout): {layers - set(LAYERS)}"
    upward = sorted((a, b) for a, targets in edges.items() for b in targets
                    if _layer(a) in LAYERS and (_layer(b) == "bouncelab"
                                                or (_layer(b) in LAYERS
                                                    and LAYERS.index(_layer(b)) > LAYERS.index(_layer(a)))))
    assert not upward, f"imports that point up the layers: {upward}"


def test_the_graph_sees_imports_inside_functions_and_for_type_checkers() -> None:
    """The reader counts a function-level import and one under TYPE_CHECKING (else the tests above could pass
    by not looking)."""
    edges = import_graph()
    assert "bouncelab.laws._contact_kernels" in edges["bouncelab.laws.compliant"]  # imported inside a method
    assert "bouncelab.laws.interface" in edges["bouncelab.laws.registry"]  # only under TYPE_CHECKING
    assert len(edges) > 50 and sum(map(len, edges.values())) > 300


@pytest.mark.parametrize("module", ["bouncelab.laws", "bouncelab.core.units", "bouncelab.core.plausibility"])
def test_laws_and_core_import_neither_pandas_nor_the_loader(module) -> None:
    code = (f"import sys, {module}; "
            "heavy = ('pandas', 'xarray', 'bouncelab.data.io', 'bouncelab.data.campaign'); "
            "bad = [m for m in heavy if m in sys.modules]; "
            "print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=PACKAGE.parent)
    assert out.stdout.strip() == "[]", out.stdout
