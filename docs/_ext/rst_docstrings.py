"""Griffe extension: render bouncelab's reST-flavoured numpy docstrings as plain Markdown, offline.

bouncelab's docstrings are numpy style with a few reStructuredText constructs
that mkdocstrings (Markdown) does not understand. Before griffe parses a
docstring this extension rewrites, without touching the source files:

* cross-reference roles (``:class:`~bouncelab.Rigid```, ``:func:`fit```...) into
  optional autorefs links (a link when the target is documented, plain code otherwise);
* ``:math:`...``` and ``.. math::`` blocks into Unicode text (no MathJax: the docs
  build and read offline), blocks as ``text`` code blocks;
* reST simple tables (``=====  =====``) into ``text`` code blocks;
* ``::`` literal-block markers into ``:``;
* a class whose docstring is built at import time (``__doc__ = "..." + shared_text``, as
  bouncelab's Penner laws do), which static analysis sees as empty, gets its runtime
  docstring.

Loaded by mkdocs.yml (``plugins.mkdocstrings.handlers.python.options.extensions``).
"""

from __future__ import annotations

import importlib
import inspect
import re
from typing import Any

import griffe

from bouncelab.core._tex import tex_to_text  # one converter, shared with the laws' HTML views

_ROLE = re.compile(r":(?:py:)?(class|func|meth|mod|data|attr|obj|exc|const):`(~?)([^`<]+?)`")
_MATH_ROLE = re.compile(r":math:`([^`]+)`")
_BORDER = re.compile(r"^\s*=+(\s+=+)+\s*$")


def _role(match: re.Match, module: str) -> str:
    tilde, target = match.group(2), match.group(3).strip()
    text = target.rsplit(".", 1)[-1] if tilde else target
    if not target.startswith("bouncelab") and "." not in target:
        target = f"{module}.{target}"
    return f'<autoref identifier="{target}" optional><code>{text}</code></autoref>'


def _math_blocks(lines: list[str]) -> list[str]:
    out: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        m = re.match(r"^(\s*)\.\. math::\s*(.*)$", line)
        if not m:
            out.append(line)
            i += 1
            continue
        indent = len(m.group(1))
        body = [m.group(2)] if m.group(2).strip() else []
        i += 1
        while i < len(lines) and (not lines[i].strip() or len(lines[i]) - len(lines[i].lstrip()) > indent):
            body.append(lines[i].strip())
            i += 1
        text = "\n".join(tex_to_text(b) if b else "" for b in body).strip("\n")
        pad = " " * indent
        out += [f"{pad}```text", *[pad + t for t in text.splitlines()], f"{pad}```", ""]
    return out


def _tables(lines: list[str]) -> list[str]:
    out: list[str] = []
    i = 0
    while i < len(lines):
        if not _BORDER.match(lines[i]):
            out.append(lines[i])
            i += 1
            continue
        indent = len(lines[i]) - len(lines[i].lstrip())
        block = [lines[i]]
        i += 1
        while i < len(lines):
            block.append(lines[i])
            i += 1
            if _BORDER.match(block[-1]) and (i >= len(lines) or not lines[i].strip()):
                # the closing border: one followed by a blank line (or the end)
                break
        pad = " " * indent
        out += [f"{pad}```text", *block, f"{pad}```"]
    return out


def convert(text: str, module: str) -> str:
    """The Markdown form of one docstring."""
    lines = _tables(_math_blocks(text.splitlines()))
    out, fenced = [], False
    for line in lines:
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append(line)
        elif fenced:  # inside a code block: plain text only
            line = _ROLE.sub(lambda m: m.group(3).rsplit(".", 1)[-1] if m.group(2) else m.group(3), line)
            line = _MATH_ROLE.sub(lambda m: tex_to_text(m.group(1)), line)
            out.append(re.sub(r"``([^`]+)``", r"\1", line))
        else:
            line = _ROLE.sub(lambda m: _role(m, module), line)
            line = _MATH_ROLE.sub(lambda m: f"`{tex_to_text(m.group(1))}`", line)
            if not line.lstrip().startswith(">>>"):
                line = re.sub(r"(\S)::$", r"\1:", line)
            out.append(line)
    return "\n".join(out)


def _runtime_docstring(obj: griffe.Object) -> str | None:
    """The docstring a class has at runtime, when static analysis found none."""
    try:
        value = getattr(importlib.import_module(obj.module.path), obj.name)
    except Exception:  # documentation must not fail on an import problem
        return None
    doc = value.__dict__.get("__doc__") if isinstance(value, type) else None
    return inspect.cleandoc(doc) if isinstance(doc, str) and doc.strip() else None


class RstDocstrings(griffe.Extension):
    """Rewrite each docstring once, before griffe parses it."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is None and obj.is_class:
            text = _runtime_docstring(obj)
            if text:
                # parse it like the module's own docstring (the parser mkdocs.yml configures)
                like = obj.module.docstring
                parser = like.parser if like is not None and like.parser else "numpy"
                options = like.parser_options if like is not None else {}
                obj.docstring = griffe.Docstring(text, parent=obj, parser=parser, parser_options=options)
        doc = obj.docstring
        if doc is None or not doc.value or getattr(doc, "_rst_converted", False):
            return
        module = obj.module.path if not obj.is_module else obj.path
        doc.value = convert(doc.value, module)
        doc._rst_converted = True
