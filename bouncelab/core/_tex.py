"""The LaTeX and reStructuredText of bouncelab's docstrings as readable Unicode text (no MathJax, nothing to load).

Used where a docstring's equation is shown outside Python's help: a law's HTML view (its ``.. math::`` blocks,
:func:`math_blocks`) and the documentation site (``docs/_ext/rst_docstrings.py``). Best effort, for the LaTeX
bouncelab writes: dots and hats, fractions, roots, Greek letters and a few operators.

>>> tex_to_text(r"\\dot y_F = -r \\dot y_0, \\quad \\omega_F = \\omega_0 + \\tfrac52 k \\dot y_0")
'ẏ_F = -r ẏ_0,   ω_F = ω_0 + 5/2 k ẏ_0'
"""

from __future__ import annotations

import inspect
import re

__all__ = ["math_blocks", "plain", "summary_line", "tex_to_text"]

_TEX = [
    (r"\\operatorname\s*\{([^{}]*)\}", r"\1"),
    (r"\\tfrac\s*(\d)\s*(\d)", r"\1/\2"),
    (r"\\frac\s*(\w)\s*(\w)", r"\1/\2"),
    (r"\\[dt]?frac\{([^{}]*)\}\{([^{}]*)\}", r"(\1)/(\2)"),
    (r"\\sqrt\{([^{}]*)\}", r"√(\1)"),
    (r"\\text\{([^{}]*)\}", r"\1"),
    (r"\\mathrm\{([^{}]*)\}", r"\1"),
    (r"\\ddot\{\\mathbf\{(\w)\}\}", "\\1\u0308"),
    (r"\\hat\{\\mathbf\{(\w)\}\}", "\\1\u0302"),
    (r"\\mathbf\s*\{?(\w)\}?", r"\1"),
    (r"\\(?:left|right|bigl|bigr|Bigl|Bigr|Big|big|Bigg|bigg)(?![A-Za-z])", ""),
    (r"\\begin\{cases\}", ""),
    (r"\\end\{cases\}", ""),
    (r"\\(?:qquad|quad)", "   "),
    (r"\\[,;:!]", " "),
    (r"\\\\", "\n"),
]
_SYMBOLS = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "Delta": "Δ", "epsilon": "ε", "zeta": "ζ", "eta": "η",
    "theta": "θ", "kappa": "κ", "lambda": "λ", "mu": "μ", "nu": "ν", "xi": "ξ", "phi": "φ", "pi": "π", "rho": "ρ",
    "sigma": "σ", "tau": "τ", "chi": "χ", "psi": "ψ", "omega": "ω", "Omega": "Ω",
    "cdot": "·", "times": "×", "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥", "ne": "≠", "approx": "≈",
    "lVert": "‖", "rVert": "‖", "lvert": "|", "rvert": "|", "sum": "Σ", "in": "∈", "to": "→", "infty": "∞",
    "pm": "±", "mp": "∓", "partial": "∂",
    "cos": "cos ", "sin": "sin ", "tan": "tan ", "arctan": "arctan", "log": "log", "exp": "exp", "min": "min",
    "max": "max",
}
_ACCENTS = {"ddot": "\u0308", "dot": "\u0307", "hat": "\u0302"}
_DOTTED = {"x": "ẋ", "y": "ẏ"}


def _accent(match: re.Match) -> str:
    name, symbol = match.group(1), match.group(2)
    base = _SYMBOLS.get(symbol[1:], symbol[1:]) if symbol.startswith("\\") else symbol
    if name == "dot" and base in _DOTTED:
        return _DOTTED[base]
    return base + _ACCENTS[name]


def tex_to_text(tex: str) -> str:
    """Readable Unicode for the LaTeX used in bouncelab's docstrings (best effort)."""
    out = tex
    for pattern, repl in _TEX:
        out = re.sub(pattern, repl, out)
    out = re.sub(r"\\(ddot|dot|hat)\s*(?:\{\s*)?(\\[A-Za-z]+|\w)(?:\s*\})?", _accent, out)
    out = re.sub(r"\\([A-Za-z]+)", lambda m: _SYMBOLS.get(m.group(1), m.group(1)), out)
    out = re.sub(r"_\{([^{}]*)\}", r"_\1", out)
    out = re.sub(r"\^\{([^{}]*)\}", r"^\1", out)
    out = out.replace("&", " ").replace("{", "").replace("}", "")
    return re.sub(r"[ \t]{4,}", "   ", out).strip()


_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|obj|exc|const):`(~?)([^`<]+?)`")
_MATH_ROLE = re.compile(r":math:`([^`]+)`")


def plain(text: str) -> str:
    """One line of reStructuredText as plain text: roles as their names, ``:math:`` as Unicode, literals bare."""
    text = _ROLE.sub(lambda m: m.group(2).rsplit(".", 1)[-1] if m.group(1) else m.group(2), text)
    text = _MATH_ROLE.sub(lambda m: tex_to_text(m.group(1)), text)
    return re.sub(r"``([^`]+)``", r"\1", text)


def summary_line(doc: str | None) -> str:
    """The first paragraph of a docstring, as plain text on one line ("" for none)."""
    lines = inspect.cleandoc(doc or "").split("\n\n", 1)[0].split()
    return plain(" ".join(lines))


def math_blocks(doc: str | None) -> list[str]:
    """Each ``.. math::`` block of a docstring, as Unicode text (lines kept; blank lines between equations)."""
    lines = inspect.cleandoc(doc or "").splitlines()
    blocks: list[str] = []
    i = 0
    while i < len(lines):
        m = re.match(r"^(\s*)\.\. math::\s*(.*)$", lines[i])
        i += 1
        if not m:
            continue
        indent = len(m.group(1))
        body = [m.group(2)] if m.group(2).strip() else []
        while i < len(lines) and (not lines[i].strip() or len(lines[i]) - len(lines[i].lstrip()) > indent):
            body.append(lines[i].strip())
            i += 1
        text = "\n".join(tex_to_text(b) if b else "" for b in body).strip("\n")
        if text:
            blocks.append(re.sub(r"\n{3,}", "\n\n", text))
    return blocks
