"""What the three emitters share: C, JavaScript and C# write statements and expressions alike.

:class:`Emitter` prints a :class:`~bouncelab.export.ir.Program` statement by statement: blocks in
braces, ``if``/``else if``/``else``, ``while``, counted ``for`` loops, every operation parenthesised
(so that the order of operations is the Python source's, whatever the language's precedence rules).
A language supplies the rest through small hooks: its names, types, literals, conversions,
intrinsic functions (and the helpers some need), array loads, and how a function returns several
values (:meth:`Emitter.return_multi`, :meth:`Emitter.call_multi`).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import ClassVar

from bouncelab.export import ir

__all__ = ["Emitter", "hypot_scaling", "pow_constants", "strip_parens"]


def _dd(q: Fraction) -> tuple[float, float]:
    """``q`` as a double-double: the nearest double and the nearest double to the rest."""
    hi = float(q)
    return hi, float(q - Fraction(hi))


@functools.cache
def pow_constants() -> tuple[tuple[float, float], list[tuple[float, float]], list[tuple[float, float]]]:
    """The double-double constants of the correctly rounded pow that the JavaScript and C# outputs carry
    (C has the C library's): ln 2, ``1 / (2k + 1)`` for k < 22 (atanh's series) and ``1 / j!`` for j < 11."""
    with localcontext() as ctx:
        ctx.prec = 60
        ln2 = _dd(Fraction(Decimal(2).ln()))
    atanh = [_dd(Fraction(1, 2 * k + 1)) for k in range(22)]
    fact = [_dd(Fraction(1, math.factorial(j))) for j in range(11)]
    return ln2, atanh, fact


def hypot_scaling(indent: str) -> str:
    """The lines of the JavaScript and C# outputs' hypot (both languages write them alike) that scale ``x >= y``
    by an exact power of two where their squares would overflow or underflow, each line after ``indent``: one
    text, so that the two outputs keep the same operations, and so the same bits."""
    return "\n".join(indent + line for line in ("if (x > 1e150) s = 2.409919865102884e-181;",
                                                 "else if (x < 1e-150) s = 4.149515568880993e+180;",
                                                 "x *= s;", "y *= s;"))


def strip_parens(text: str) -> str:
    """``text`` without its outer parentheses when they enclose all of it (``(a + b)`` -> ``a + b``), but for
    a sequence (``(a, b)``), which needs them."""
    if not (text.startswith("(") and text.endswith(")")):
        return text
    depth = 0
    for k, ch in enumerate(text):
        depth += ch == "("
        depth -= ch == ")"
        if (depth == 0 and k < len(text) - 1) or (depth == 1 and ch == ","):  # (a, b): JavaScript's comma operator
            return text
    return text[1:-1]


class Emitter:
    """Prints an IR program in one language (a subclass per language).

    ``helpers`` collects the names of the helper functions the printed code calls, so that
    :meth:`definitions` writes those (and only those) before the functions.
    """

    #: The language's name, for messages.
    language = ""
    #: The declaration of a ``for`` loop's integer counters (``long long``, ``let``...).
    loop_decl = ""
    #: How ``==`` and ``!=`` are written.
    equality: ClassVar[dict[str, str]] = {"==": "==", "!=": "!="}
    indent = "    "

    def __init__(self, program: ir.Program) -> None:
        self.program = program
        self.helpers: set[str] = set()
        self._fn: ir.Function | None = None
        self._rename: dict[str, str] = {}
        self.extra: dict[str, str] = {}  # locals an emitter adds while printing a function (temporaries)

    # -------------------------------------------------------------- hooks a language gives
    def function_name(self, name: str) -> str:
        """The name of the program's function ``name`` in the output."""
        return name

    def type_name(self, t: ir.Type) -> str:
        raise NotImplementedError

    def literal(self, value: object, t: str) -> str:
        raise NotImplementedError

    def cast(self, text: str) -> str:
        """An integer as a float."""
        raise NotImplementedError

    def intrinsic(self, name: str, args: list[str], operand: str, result: str) -> str:
        """The intrinsic ``name`` of ``args`` (of type ``operand``), of type ``result``."""
        raise NotImplementedError

    def load(self, array: str, index: list[str], t: ir.ArrayType) -> str:
        """An element of an array, to read (:class:`~bouncelab.export.ir.Load`) or to write
        (:class:`~bouncelab.export.ir.Store`)."""
        return array + "".join(f"[{i}]" for i in index)

    def head(self, fn: ir.Function, params: list[str]) -> str:
        """The line that opens a function's definition (up to its ``{``)."""
        raise NotImplementedError

    def param(self, name: str, t: ir.Type) -> str:
        return f"{self.type_name(t)} {name}"

    def declare(self, name: str, t: str) -> str:
        return f"{self.type_name(t)} {name} = {self.literal(False if t == ir.BOOL else 0, t)};"

    def prologue(self, fn: ir.Function, read: set[str]) -> list[str]:
        """Lines at the top of a function's body, before its locals (C: unused parameters cast to void)."""
        return []

    def return_multi(self, fn: ir.Function, values: Sequence[ir.Expr]) -> list[str]:
        raise NotImplementedError

    def call(self, e: ir.Call) -> str:
        """A call of a function of one result, as an expression."""
        return f"{self.function_name(e.func)}({', '.join(self.expr(a) for a in e.args)})"

    def tail_call(self, fn: ir.Function, s: ir.TailCall) -> list[str]:
        """Lines that return the results of a call (``fn`` the function returning them)."""
        raise NotImplementedError

    def call_multi(self, s: ir.CallMulti) -> list[str]:
        """Lines that call a function of several results and put them into the statement's targets."""
        raise NotImplementedError

    def helper_text(self, name: str) -> str:
        """The definition of helper ``name``."""
        raise NotImplementedError

    def local_clashes(self, name: str) -> bool:
        """Whether a local's name would clash with the language's own names (it is then renamed)."""
        return False

    # -------------------------------------------------------------- the program
    def definitions(self) -> str:
        """Every function of the program, callees first, after the helpers they call."""
        functions = [self.function(fn) for fn in self.program.functions]
        helpers = [self.helper_text(h) for h in sorted(self.helpers)]
        return "\n\n".join([*helpers, *functions])

    def function(self, fn: ir.Function) -> str:
        self._fn = fn
        names = {n for n, _ in fn.params} | set(fn.locals) | {n for s in ir.walk(fn.body) if isinstance(s, ir.For)
                                                                for n in (s.counter, s.limit)}
        self._rename = {}
        for name in sorted(names):
            if self.local_clashes(name):
                new = name + "_"
                while new in names or self.local_clashes(new):
                    new += "_"
                names.add(new)
                self._rename[name] = new
        read = ir.stores(fn)
        for e in ir.walk_exprs(fn.body):
            read |= ir.reads(e)
        self.extra = {}  # locals an emitter adds while printing the body (temporaries)
        body = self.block(fn.body, 1)
        lines = [self.indent + line for line in self.prologue(fn, read)]
        lines += [self.indent + self.declare(self.local(n), t) for n, t in (*fn.locals.items(), *self.extra.items())]
        head = self.head(fn, [self.param(self.local(n), t) for n, t in fn.params])
        doc = f"/* {fn.source} */\n" if fn.source else ""
        return doc + head + "\n" + "\n".join([*lines, *body]) + "\n}"

    def local(self, name: str) -> str:
        return self._rename.get(name, name)

    # -------------------------------------------------------------- statements
    def block(self, body: Sequence[ir.Stmt], depth: int) -> list[str]:
        out: list[str] = []
        for s in body:
            out += self.stmt(s, depth)
        return out

    def stmt(self, s: ir.Stmt, depth: int) -> list[str]:
        pad = self.indent * depth
        if isinstance(s, ir.Assign):
            return [f"{pad}{self.local(s.target)} = {strip_parens(self.expr(s.value))};"]
        if isinstance(s, ir.Store):
            assert self._fn is not None
            t = dict(self._fn.params)[s.array]
            target = self.load(self.local(s.array), [strip_parens(self.index(i)) for i in s.index], t)
            return [f"{pad}{target} = {strip_parens(self.expr(s.value))};"]
        if isinstance(s, ir.CallMulti):
            return [pad + line for line in self.call_multi(s)]
        if isinstance(s, ir.If):
            out = [f"{pad}if ({self.cond(s.cond)}) {{", *self.block(s.then, depth + 1)]
            orelse = s.orelse
            while len(orelse) == 1 and isinstance(orelse[0], ir.If):
                out += [f"{pad}}} else if ({self.cond(orelse[0].cond)}) {{", *self.block(orelse[0].then, depth + 1)]
                orelse = orelse[0].orelse
            if orelse:
                out += [f"{pad}}} else {{", *self.block(orelse, depth + 1)]
            return [*out, f"{pad}}}"]
        if isinstance(s, ir.While):
            return [f"{pad}while ({self.cond(s.cond)}) {{", *self.block(s.body, depth + 1), f"{pad}}}"]
        if isinstance(s, ir.For):
            c, n = self.local(s.counter), self.local(s.limit)
            cmp = "<" if s.step > 0 else ">"
            inc = f"{c}++" if s.step == 1 else (f"{c}--" if s.step == -1
                                                else f"{c} += {self.literal(s.step, ir.I64)}")
            head = (f"for ({self.loop_decl} {c} = {strip_parens(self.expr(s.start))}, "
                    f"{n} = {strip_parens(self.expr(s.stop))}; {c} {cmp} {n}; {inc}) {{")
            return [pad + head, *self.block(s.body, depth + 1), f"{pad}}}"]
        if isinstance(s, ir.Break):
            return [f"{pad}break;"]
        if isinstance(s, ir.Continue):
            return [f"{pad}continue;"]
        if isinstance(s, ir.TailCall):
            assert self._fn is not None
            return [pad + line for line in self.tail_call(self._fn, s)]
        if isinstance(s, ir.Return):
            assert self._fn is not None
            if self._fn.multi:
                return [pad + line for line in self.return_multi(self._fn, s.values)]
            return [f"{pad}return {strip_parens(self.expr(s.values[0]))};"]
        raise TypeError(s)

    def cond(self, e: ir.Expr) -> str:
        return strip_parens(self.expr(e))

    # -------------------------------------------------------------- expressions
    def expr(self, e: ir.Expr) -> str:
        if isinstance(e, ir.Const):
            return self.literal(e.value, e.type)
        if isinstance(e, ir.Var):
            return self.local(e.name)
        if isinstance(e, ir.Cast):
            return self.cast(self.expr(e.x))
        if isinstance(e, ir.Binary):
            return f"({self.expr(e.a)} {e.op} {self.expr(e.b)})"
        if isinstance(e, ir.Neg):
            return f"(-{self.expr(e.x)})"
        if isinstance(e, ir.Not):
            return f"(!{self.expr(e.x)})"
        if isinstance(e, ir.Compare):
            return f"({self.expr(e.a)} {self.equality.get(e.op, e.op)} {self.expr(e.b)})"
        if isinstance(e, ir.Logic):
            op = " && " if e.op == "and" else " || "
            return "(" + op.join(self.expr(x) for x in e.items) + ")"
        if isinstance(e, ir.Select):
            return f"({self.cond(e.cond)} ? {self.expr(e.a)} : {self.expr(e.b)})"
        if isinstance(e, ir.Intrinsic):
            return self.intrinsic(e.name, [self.expr(a) for a in e.args], e.args[0].type, e.type)
        if isinstance(e, ir.Call):
            return self.call(e)
        if isinstance(e, ir.Load):
            assert self._fn is not None
            t = dict(self._fn.params)[e.array]
            return self.load(self.local(e.array), [strip_parens(self.index(i)) for i in e.index], t)
        raise TypeError(e)

    def index(self, e: ir.Expr) -> str:
        return self.expr(e)
