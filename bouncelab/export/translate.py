r"""Translate the restricted Python of bouncelab's numba kernels into C99 and JavaScript.

A compiled law's mathematics lives in one place: its numba kernel (:mod:`bouncelab.laws._kernels`,
:mod:`bouncelab.laws._contact_kernels`, or a user's own). This module reads the kernel's Python source
(``kernel.py_func``, :func:`inspect.getsource`) and writes the same arithmetic, operation by operation
and in the same order, as C99 (which C++ compilers accept too) or as JavaScript, so that an exported
law and bouncelab compute the same IEEE-754 double-precision results. It types the code as numba does
(int64, float64, boolean, tuples, arrays), specialising each helper for the types it is called with.

The supported subset
--------------------
Functions
    Plain functions decorated with :func:`bouncelab.core._jit.jit` (or ``numba.njit``), with positional
    parameters (defaults that are constants allowed); calls by position or keyword to other such
    functions, however deep, but not recursive. Every function must end with a ``return`` of a value.
Values
    Floats (double), integers (64-bit), booleans, tuples of these (also nested, returned, passed and
    unpacked), and read-only float arrays passed in as kernel arguments (indexed ``A[i]``, ``A[0, 2]``).
Names outside the function
    Module-level (or closure) numbers, booleans and tuples of them are constants; ``math.pi``,
    ``math.e``, ``math.tau``, ``math.inf``, ``math.nan``; other jit functions.
Statements
    Assignment to a name or to a tuple of names (``a, b = b, a`` is simultaneous, as in Python),
    augmented assignment (``+= -= *= /=``), ``if``/``elif``/``else``, ``while``, ``for ... in range(...)``
    with a constant step, ``break``, ``continue``, ``return``, ``pass`` and docstrings.
Expressions
    ``+ - * / **`` (``**`` with a float exponent: C's ``pow``), unary ``- + not``, comparisons (chained
    ones too), ``and``/``or`` of booleans, ``x if c else y``, ``min``/``max`` (Python's rule: the first
    of equal values, NaN as Python orders it), ``abs``, ``float()``, and ``math.sqrt exp log log10 log1p
    expm1 sin cos tan asin acos atan atan2 sinh cosh tanh asinh acosh atanh hypot pow copysign fabs isnan
    isinf isfinite``; tuple indexing (constant index, or an integer variable for a tuple of one type).

Anything else (lists, ``//`` and ``%``, bitwise operators, strings, ``None``, attributes other than
``math``'s, calls of non-jit functions, numpy, ``while``/``for`` with ``else``, ``try``, ``with``,
``global``, nested functions, integer exponents, truthiness of numbers...) is refused with an
:class:`ExportError` naming the function, file, line and construct: the translator never guesses.

Differences from numba that remain (documented in each exported file): numba raises on a division by zero
and on a tuple index out of range, where the exported code follows IEEE (inf or NaN) and takes the last
element. In JavaScript, integers are doubles (exact below 2^53), ``Math.exp``, ``Math.sin``... may differ
from the C library's in the last bit, and ``**`` is a correctly rounded ``$pow`` written out in the module
(double-double arithmetic), because Node's ``Math.pow`` differs from the C library's ``pow`` for about 8 %
of arguments, enough for TurfContact's event location to amplify.
"""

from __future__ import annotations

import ast
import builtins
import functools
import inspect
import math
import numbers
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass, field
from decimal import Decimal, localcontext
from fractions import Fraction
from typing import Any

import numpy as np

from bouncelab.core.errors import LawDefinitionError

__all__ = ["ArrayType", "ExportError", "Program", "TupleType", "is_jit_function", "value_type"]


class ExportError(LawDefinitionError):
    """A law that cannot be exported: its kernel uses a construct outside the translator's subset (see
    :mod:`bouncelab.export.translate`), or it has no compiled kernel at all.

    Attributes
    ----------
    law
        The law's name, when known.
    method
        ``"kernel"``.
    function
        The Python function at fault (qualified name), when the kernel's code is at fault.
    file, line
        Where in that function's source file.
    construct
        The construct refused (``"a list"``, ``"the operator //"``...).
    """

    def __init__(self, message: str = "", *, law: str | None = None, method: str | None = "kernel",
                 function: str | None = None, file: str | None = None, line: int | None = None,
                 construct: str | None = None) -> None:
        super().__init__(message, law=law, method=method)
        self.function = function
        self.file = file
        self.line = line
        self.construct = construct


# ------------------------------------------------------------------------------------------- types
FLOAT, INT, BOOL = "double", "int64", "bool"


@dataclass(frozen=True)
class TupleType:
    """A tuple of the given element types (numba's Tuple / UniTuple)."""

    elems: tuple[Any, ...]

    def __str__(self) -> str:
        return "(" + ", ".join(map(str, self.elems)) + ")"


@dataclass(frozen=True)
class ArrayType:
    """A read-only float64 array of the given shape (a kernel argument)."""

    shape: tuple[int, ...]

    def __str__(self) -> str:
        return f"float64 array {self.shape}"


def _numeric(t: Any) -> bool:
    return t in (FLOAT, INT)


def unify(a: Any, b: Any) -> Any:
    """The type of a variable assigned both ``a`` and ``b`` (numba's rule: int and float make float)."""
    if a == b:
        return a
    if _numeric(a) and _numeric(b):
        return FLOAT
    if isinstance(a, TupleType) and isinstance(b, TupleType) and len(a.elems) == len(b.elems):
        return TupleType(tuple(unify(x, y) for x, y in zip(a.elems, b.elems, strict=True)))
    raise TypeError(f"{a} and {b}")


def value_type(value: Any) -> Any:
    """The numba type of a Python value given to a kernel (float, int, bool, tuple, float array)."""
    if isinstance(value, bool | np.bool_):
        return BOOL
    if isinstance(value, numbers.Integral):
        if not -(2**63) <= int(value) < 2**63:
            raise TypeError(f"the integer {value} does not fit 64 bits")
        return INT
    if isinstance(value, numbers.Real):
        return FLOAT
    if isinstance(value, tuple):
        return TupleType(tuple(value_type(v) for v in value))
    if isinstance(value, np.ndarray):
        if value.dtype.kind != "f" or value.ndim == 0:
            raise TypeError(f"an array of {value.dtype} with shape {value.shape} (only float arrays of one or more "
                            "dimensions are supported)")
        return ArrayType(tuple(int(s) for s in value.shape))
    raise TypeError(f"a {type(value).__name__}")


def is_jit_function(obj: Any) -> bool:
    """Whether ``obj`` is a numba dispatcher (a jit function with its Python function in ``py_func``)."""
    return inspect.isfunction(getattr(obj, "py_func", None)) and callable(obj)


# ------------------------------------------------------------------------------------------- names
# Names a translated variable must not take: keywords of C, C++ and JavaScript, the C library's (math.h,
# stdlib.h: functions and macros, including POSIX's j0, y1...) and JavaScript's globals. Such a variable
# gets a trailing underscore in both languages.
_RESERVED = frozenset("""
auto break case char const continue default do double else enum extern float for goto if inline int long
register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
_Bool _Complex _Imaginary alignas alignof and and_eq asm bitand bitor bool catch char16_t char32_t class compl
constexpr const_cast decltype delete dynamic_cast explicit export false friend mutable namespace new noexcept
not not_eq nullptr operator or or_eq private protected public reinterpret_cast static_assert static_cast
template this thread_local throw true try typeid typename using virtual wchar_t xor xor_eq
arguments await eval function in instanceof let null of super typeof undefined var with yield implements
interface package Infinity NaN Math Number Object Array Boolean String Symbol Error JSON globalThis
j0 j1 jn y0 y1 yn gamma lgamma tgamma signgam drem erf erfc fmin fmax fmod round lround llround trunc floor
ceil rint nearbyint remainder remquo frexp ldexp modf scalbn logb ilogb nan nextafter fdim fma cbrt exp2 log2
abs labs llabs div ldiv lldiv exit abort free malloc calloc realloc rand srand atoi atof strtod qsort bsearch
errno assert isnan isinf isfinite isnormal signbit fpclassify isgreater isless isunordered INFINITY NAN
HUGE_VAL M_PI M_E NULL EOF size_t ptrdiff_t main
""".split()) | frozenset(n for n in dir(math) if not n.startswith("_"))

_MATH_CONSTANTS = {"pi": math.pi, "e": math.e, "tau": math.tau, "inf": math.inf, "nan": math.nan}
# math function -> (number of arguments, C name, JavaScript name, result type)
_MATH_FUNCS = {
    **{n: (1, n, f"Math.{n}", FLOAT) for n in ("sqrt", "exp", "log", "log10", "log1p", "expm1", "sin", "cos", "tan",
                                           "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh",
                                           "atanh")},
    "atan2": (2, "atan2", "Math.atan2", FLOAT), "hypot": (2, "hypot", "Math.hypot", FLOAT),
    "pow": (2, "pow", "$pow", FLOAT), "copysign": (2, "copysign", "$copysign", FLOAT),
    "fabs": (1, "fabs", "Math.abs", FLOAT),
    "isnan": (1, "isnan", "Number.isNaN", BOOL), "isinf": (1, "isinf", "$isinf", BOOL),
    "isfinite": (1, "isfinite", "Number.isFinite", BOOL),
}
_BUILTINS = ("min", "max", "abs", "float", "range")
_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_CMPOPS = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}
_REFUSED_NODES = {
    ast.List: "a list", ast.Dict: "a dict", ast.Set: "a set", ast.ListComp: "a list comprehension",
    ast.SetComp: "a set comprehension", ast.DictComp: "a dict comprehension", ast.GeneratorExp: "a generator",
    ast.Lambda: "a lambda", ast.JoinedStr: "an f-string", ast.Starred: "a starred expression",
    ast.NamedExpr: "an assignment expression (:=)", ast.Await: "await", ast.Yield: "yield",
    ast.YieldFrom: "yield from", ast.Slice: "a slice", ast.FunctionDef: "a nested function",
    ast.AsyncFunctionDef: "a nested function", ast.ClassDef: "a class", ast.Try: "try", ast.With: "with",
    ast.Raise: "raise", ast.Assert: "assert", ast.Delete: "del", ast.Import: "import", ast.ImportFrom: "import",
    ast.Global: "global", ast.Nonlocal: "nonlocal", ast.AnnAssign: "an annotated assignment",
    ast.AsyncFor: "async for", ast.AsyncWith: "async with", ast.Match: "match",
}


#: numba's fastmath flags that cannot change a finite result (bouncelab.core._jit.ROW_FLAGS): allowed.
_IEEE_SAFE_FLAGS = frozenset({"nnan", "ninf", "nsz"})


def _live_names(body: Sequence[ast.stmt]) -> set[str]:
    """The variables whose values matter: read by a condition, a loop's range, a return, or an assignment
    to a variable that matters (to a fixed point). Assignments to the others are left out of the output
    (the subset has no side effects), so that no variable is set and never used."""
    live: set[str] = set()

    def reads(node: ast.AST | None) -> set[str]:
        return set() if node is None else {n.id for n in ast.walk(node) if isinstance(n, ast.Name)
                                           and isinstance(n.ctx, ast.Load)}

    def visit(stmts: Sequence[ast.stmt]) -> set[str]:
        out: set[str] = set()
        for s in stmts:
            if isinstance(s, ast.Assign):
                if any(n in live for n, _ in _leaves(s.targets[0])):
                    out |= reads(s.value)
            elif isinstance(s, ast.AugAssign):
                if isinstance(s.target, ast.Name) and s.target.id in live:
                    out |= reads(s.value) | {s.target.id}
            elif isinstance(s, ast.If | ast.While):
                out |= reads(s.test) | visit(s.body) | visit(s.orelse)
            elif isinstance(s, ast.For):
                out |= reads(s.iter) | visit(s.body)
            elif isinstance(s, ast.Return):
                out |= reads(s.value)
        return out

    while True:
        new = visit(body)
        if new <= live:
            return live
        live |= new


class _Unknown(Exception):
    """A variable read before any assignment typed it (in the fixed-point passes)."""


def _refuse(fn: _Function, node: ast.AST | None, what: str, detail: str = "") -> ExportError:
    line = None if node is None else getattr(node, "lineno", None)
    line = None if line is None else line + fn.line_offset
    where = f"{fn.qualname} ({fn.file}" + (f", line {line}" if line else "") + ")"
    text = (f"cannot translate {where}: {what}{': ' + detail if detail else ''} is outside the subset "
            "bouncelab.export translates (see bouncelab.export.translate); nothing was written")
    return ExportError(text, function=fn.qualname, file=fn.file, line=line, construct=what)


# ------------------------------------------------------------------------------------------- functions
class _Function:
    """A jit function's source, parsed, with the names outside it resolved (constants folded in)."""

    def __init__(self, dispatcher: Any) -> None:
        func = dispatcher.py_func
        self.dispatcher = dispatcher
        self.func = func
        self.qualname = f"{func.__module__}.{func.__qualname__}"
        try:
            self.file = inspect.getsourcefile(func) or "?"
            source = textwrap.dedent(inspect.getsource(func))
        except (OSError, TypeError) as exc:
            raise ExportError(f"cannot translate {self.qualname}: its source code is not available ({exc})",
                              function=self.qualname, construct="no source") from None
        self.line_offset = func.__code__.co_firstlineno - 1
        try:
            tree = ast.parse(source)
        except SyntaxError:  # a lambda inside a larger expression, say
            raise _refuse(self, None, "a function that is not a plain def") from None
        fdef = tree.body[0]
        if not isinstance(fdef, ast.FunctionDef):
            raise _refuse(self, None, "a function that is not a plain def")
        self.fdef = fdef
        a = fdef.args
        if a.vararg or a.kwarg or a.kwonlyargs:
            raise _refuse(self, fdef, "*args, **kwargs or keyword-only parameters")
        self.params = [p.arg for p in (*a.posonlyargs, *a.args)]
        defaults = list(a.defaults)
        self.defaults: dict[str, ast.expr] = dict(zip(self.params[len(self.params) - len(defaults):], defaults,
                                                      strict=True))
        fastmath = getattr(dispatcher, "targetoptions", {}).get("fastmath")
        if fastmath is True or (fastmath and set(fastmath) - _IEEE_SAFE_FLAGS):
            raise _refuse(self, fdef, f"a function compiled with fastmath={fastmath!r}", "its results are not "
                          "IEEE arithmetic's, which the exported code follows (only the flags "
                          f"{sorted(_IEEE_SAFE_FLAGS)} are allowed)")
        for node in (n for part in (*fdef.body, *a.defaults) for n in ast.walk(part)):  # not the decorators
            for kind, what in _REFUSED_NODES.items():
                if isinstance(node, kind):
                    raise _refuse(self, node, what)
        if not fdef.body or not isinstance(fdef.body[-1], ast.Return):
            raise _refuse(self, fdef.body[-1] if fdef.body else fdef, "a function that does not end with a return")
        self.locals = set(self.params)
        for node in ast.walk(fdef):
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                self.locals.add(node.id)
        self.callees: dict[str, Any] = {}
        self.builtins: set[str] = set()
        scope = dict(func.__globals__)
        if func.__closure__:
            scope.update(zip(func.__code__.co_freevars, (c.cell_contents for c in func.__closure__), strict=True))
        self.body = [self._resolve(stmt, scope) for stmt in fdef.body]
        for name, default in list(self.defaults.items()):
            self.defaults[name] = self._resolve(default, scope)
        self.read = _live_names(self.body)

    def _resolve(self, node: ast.AST, scope: dict[str, Any]) -> Any:
        """``node`` with the outside names replaced: numbers by constants, math's constants by values."""
        fn = self

        class Resolver(ast.NodeTransformer):
            def visit_Attribute(self, n: ast.Attribute) -> ast.AST:
                if isinstance(n.value, ast.Name) and n.value.id not in fn.locals and scope.get(n.value.id) is math:
                    if n.attr in _MATH_CONSTANTS:
                        return ast.copy_location(ast.Constant(_MATH_CONSTANTS[n.attr]), n)
                    if n.attr in _MATH_FUNCS:
                        return n
                    raise _refuse(fn, n, f"math.{n.attr}")
                raise _refuse(fn, n, "an attribute", ast.unparse(n))

            def visit_Name(self, n: ast.Name) -> ast.AST:
                if n.id in fn.locals:
                    return n
                if n.id in scope:
                    value = scope[n.id]
                elif n.id in _BUILTINS:
                    fn.builtins.add(n.id)
                    return n
                elif hasattr(builtins, n.id):
                    raise _refuse(fn, n, f"the built-in {n.id!r}")
                else:
                    raise _refuse(fn, n, f"the name {n.id!r}", "not defined")
                alias = next((f for f in _MATH_FUNCS if value is getattr(math, f, None)), None)
                if alias is not None:  # from math import sqrt
                    return ast.copy_location(ast.Attribute(ast.Name("math", ast.Load()), alias, ast.Load()), n)
                if is_jit_function(value):
                    fn.callees[n.id] = value
                    return n
                try:
                    return ast.copy_location(_constant_node(value), n)
                except TypeError as exc:
                    raise _refuse(fn, n, f"the module-level name {n.id!r}", f"{exc}; only numbers, booleans, tuples "
                                  "of them and jit functions can be used from outside a kernel") from None

        return Resolver().visit(node)


def _constant_node(value: Any) -> ast.expr:
    if isinstance(value, bool | np.bool_):
        return ast.Constant(bool(value))
    if isinstance(value, numbers.Integral):
        return ast.Constant(int(value))
    if isinstance(value, numbers.Real):
        return ast.Constant(float(value))
    if isinstance(value, tuple):
        return ast.Tuple([_constant_node(v) for v in value], ast.Load())
    raise TypeError(f"it is a {type(value).__name__}")


# ------------------------------------------------------------------------------------------- typing
@dataclass
class _Spec:
    """One function specialised for its argument types: its variables' types and its name in the output."""

    fn: _Function
    argtypes: tuple[Any, ...]
    name: str = ""
    env: dict[str, Any] = field(default_factory=dict)
    ret: Any = None
    types: dict[int, Any] = field(default_factory=dict)    # id(expression node) -> type
    calls: dict[int, _Spec] = field(default_factory=dict)  # id(call node) -> callee
    args: dict[int, list[ast.expr]] = field(default_factory=dict)  # id(call node) -> arguments in order


class _Typer:
    """Types one function for given argument types: numba's unification, to a fixed point over loops."""

    def __init__(self, program: Program, spec: _Spec) -> None:
        self.program = program
        self.spec = spec
        self.fn = spec.fn
        self.strict = False
        self.changed = False

    def run(self) -> None:
        fn, spec = self.fn, self.spec
        spec.env = dict(zip(fn.params, spec.argtypes, strict=True))
        for _ in range(30):
            self.changed = False
            for stmt in fn.body:
                self.stmt(stmt)
            if not self.changed:
                break
        self.strict = True
        spec.types.clear()
        spec.calls.clear()
        for stmt in fn.body:
            self.stmt(stmt)
        if self.changed:  # cannot happen once the fixed point is reached; refuse rather than emit
            raise _refuse(fn, None, "types that do not settle")

    # -------------------------------------------------------------- statements
    def assign(self, name: str, t: Any, node: ast.AST) -> None:
        env = self.spec.env
        if name in env:
            try:
                new = unify(env[name], t)
            except TypeError as exc:
                raise _refuse(self.fn, node, f"the variable {name!r} holding values of types {exc}") from None
            if isinstance(new, ArrayType):
                raise _refuse(self.fn, node, f"assigning an array to {name!r}")
            if new != env[name]:
                env[name] = new
                self.changed = True
        else:
            if isinstance(t, ArrayType):
                raise _refuse(self.fn, node, f"assigning an array to {name!r}")
            env[name] = t
            self.changed = True

    def unpack(self, target: ast.expr, t: Any, s: ast.stmt) -> None:
        if isinstance(target, ast.Name):
            self.assign(target.id, t, s)
        elif isinstance(target, ast.Tuple):
            if not isinstance(t, TupleType) or len(t.elems) != len(target.elts):
                raise _refuse(self.fn, s, f"unpacking {t} into {len(target.elts)} names")
            for e, et in zip(target.elts, t.elems, strict=True):
                self.unpack(e, et, s)
        else:
            raise _refuse(self.fn, s, "assigning to " + ast.unparse(target))

    def stmt(self, s: ast.stmt) -> None:
        try:
            self._stmt(s)
        except _Unknown as exc:
            if self.strict:
                raise _refuse(self.fn, s, f"the variable {exc.args[0]!r} read before it is assigned") from None

    def _stmt(self, s: ast.stmt) -> None:
        fn = self.fn
        if isinstance(s, ast.Assign):
            if len(s.targets) != 1:
                raise _refuse(fn, s, "a chained assignment (a = b = ...)")
            target = s.targets[0]
            t = self.expr(s.value)
            if isinstance(target, ast.Name):
                self.assign(target.id, t, s)
            else:
                self.unpack(target, t, s)
        elif isinstance(s, ast.AugAssign):
            if not isinstance(s.target, ast.Name):
                raise _refuse(fn, s, "augmented assignment to " + ast.unparse(s.target))
            if s.target.id not in self.spec.env:
                raise _Unknown(s.target.id)
            t = self.binop(s, s.op, self.spec.env[s.target.id], self.expr(s.value))
            self.assign(s.target.id, t, s)
        elif isinstance(s, ast.If | ast.While):
            if s.orelse and isinstance(s, ast.While):
                raise _refuse(fn, s, "a while loop with an else clause")
            self.condition(s.test)
            for b in s.body:
                self.stmt(b)
            for b in s.orelse:
                self.stmt(b)
        elif isinstance(s, ast.For):
            if s.orelse:
                raise _refuse(fn, s, "a for loop with an else clause")
            if not isinstance(s.target, ast.Name):
                raise _refuse(fn, s, "a for loop over something other than one name")
            self.range_args(s)
            self.assign(s.target.id, INT, s)
            for b in s.body:
                self.stmt(b)
        elif isinstance(s, ast.Return):
            if s.value is None:
                raise _refuse(fn, s, "a return without a value")
            t = self.expr(s.value)
            if isinstance(t, ArrayType):
                raise _refuse(fn, s, "returning an array")
            if self.spec.ret is None:
                self.spec.ret, self.changed = t, True
            else:
                try:
                    new = unify(self.spec.ret, t)
                except TypeError as exc:
                    raise _refuse(fn, s, f"returns of different types {exc}") from None
                if new != self.spec.ret:
                    self.spec.ret, self.changed = new, True
        elif isinstance(s, ast.Expr):
            if not (isinstance(s.value, ast.Constant) and isinstance(s.value.value, str)):
                raise _refuse(fn, s, "an expression statement", ast.unparse(s))
        elif not isinstance(s, ast.Break | ast.Continue | ast.Pass):
            raise _refuse(fn, s, f"the statement {type(s).__name__}")

    def range_args(self, s: ast.For) -> list[ast.expr]:
        it = s.iter
        if not (isinstance(it, ast.Call) and isinstance(it.func, ast.Name) and it.func.id == "range"
                and it.func.id not in self.fn.locals and not it.keywords and 1 <= len(it.args) <= 3):
            raise _refuse(self.fn, s, "a for loop over something other than range(...)")
        for a in it.args:
            if self.expr(a) != INT:
                raise _refuse(self.fn, s, "range() of a non-integer")
        if len(it.args) == 3:
            step = it.args[2]
            value = _const_int(step)
            if value is None or value == 0:
                raise _refuse(self.fn, s, "range() with a step that is not a non-zero integer constant")
        return list(it.args)

    def condition(self, node: ast.expr) -> None:
        t = self.expr(node)
        if t != BOOL:
            raise _refuse(self.fn, node, f"a condition of type {t} (write the comparison out)", ast.unparse(node))

    # -------------------------------------------------------------- expressions
    def expr(self, node: ast.expr) -> Any:
        t = self._expr(node)
        if self.strict:
            self.spec.types[id(node)] = t
        return t

    def binop(self, node: ast.AST, op: ast.operator, a: Any, b: Any) -> Any:
        if type(op) not in _BINOPS:
            raise _refuse(self.fn, node, f"the operator {_op_text(op)}")
        if not (_numeric(a) and _numeric(b)):
            raise _refuse(self.fn, node, f"arithmetic on {a} and {b}")
        if isinstance(op, ast.Div):
            return FLOAT
        if isinstance(op, ast.Pow):
            if b == INT:
                raise _refuse(self.fn, node, "** with an integer exponent (write the product, or a float exponent)")
            return FLOAT
        return INT if a == b == INT else FLOAT

    def _expr(self, node: ast.expr) -> Any:
        fn = self.fn
        if isinstance(node, ast.Constant):
            v = node.value
            if isinstance(v, bool):
                return BOOL
            if isinstance(v, int):
                if not -(2**63) <= v < 2**63:
                    raise _refuse(fn, node, f"the integer {v}", "it does not fit 64 bits")
                return INT
            if isinstance(v, float):
                return FLOAT
            raise _refuse(fn, node, f"the constant {v!r}")
        if isinstance(node, ast.Name):
            if node.id not in fn.locals:
                raise _refuse(fn, node, f"the function {node.id!r} used as a value")
            if node.id not in self.spec.env:
                raise _Unknown(node.id)
            return self.spec.env[node.id]
        if isinstance(node, ast.Tuple):
            return TupleType(tuple(self.expr(e) for e in node.elts))
        if isinstance(node, ast.BinOp):
            return self.binop(node, node.op, self.expr(node.left), self.expr(node.right))
        if isinstance(node, ast.UnaryOp):
            t = self.expr(node.operand)
            if isinstance(node.op, ast.Not):
                if t != BOOL:
                    raise _refuse(fn, node, f"'not' of a {t} (write the comparison out)")
                return BOOL
            if isinstance(node.op, ast.USub | ast.UAdd) and _numeric(t):
                return t
            raise _refuse(fn, node, f"the unary operator {_op_text(node.op)} on {t}")
        if isinstance(node, ast.BoolOp):
            for v in node.values:
                if self.expr(v) != BOOL:
                    raise _refuse(fn, node, "'and'/'or' of values that are not booleans")
            return BOOL
        if isinstance(node, ast.Compare):
            types = [self.expr(node.left)] + [self.expr(c) for c in node.comparators]
            for op, a, b in zip(node.ops, types, types[1:], strict=False):
                if type(op) not in _CMPOPS:
                    raise _refuse(fn, node, f"the comparison {_op_text(op)}")
                ok = (_numeric(a) and _numeric(b)) or (a == b == BOOL and isinstance(op, ast.Eq | ast.NotEq))
                if not ok:
                    raise _refuse(fn, node, f"comparing {a} with {b}")
            return BOOL
        if isinstance(node, ast.IfExp):
            self.condition(node.test)
            a, b = self.expr(node.body), self.expr(node.orelse)
            try:
                t = unify(a, b)
            except TypeError as exc:
                raise _refuse(fn, node, f"a conditional expression of types {exc}") from None
            if isinstance(t, TupleType) and not (a == b):
                raise _refuse(fn, node, f"a conditional expression choosing between tuples of types {a} and {b}")
            if isinstance(t, ArrayType):
                raise _refuse(fn, node, "a conditional expression choosing an array")
            return t
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        raise _refuse(fn, node, f"the expression {type(node).__name__}", ast.unparse(node))

    def call(self, node: ast.Call) -> Any:
        fn = self.fn
        f = node.func
        if isinstance(f, ast.Attribute):  # math.X (resolved: only math's functions remain as attributes)
            nargs, _, _, result = _MATH_FUNCS[f.attr]
            if node.keywords or len(node.args) != nargs:
                raise _refuse(fn, node, f"math.{f.attr} with {len(node.args)} argument(s)")
            for a in node.args:
                if not _numeric(self.expr(a)):
                    raise _refuse(fn, node, f"math.{f.attr} of a non-number")
            return result
        if not isinstance(f, ast.Name) or f.id in fn.locals:
            raise _refuse(fn, node, "a call of " + ast.unparse(f))
        if f.id in fn.builtins:
            if node.keywords:
                raise _refuse(fn, node, f"{f.id}() with keywords")
            types = [self.expr(a) for a in node.args]
            if f.id in ("min", "max"):
                if len(types) < 2 or not all(_numeric(t) for t in types):
                    raise _refuse(fn, node, f"{f.id}() of other than two or more numbers")
                return INT if all(t == INT for t in types) else FLOAT
            if f.id == "abs":
                if len(types) != 1 or not _numeric(types[0]):
                    raise _refuse(fn, node, "abs() of other than one number")
                return types[0]
            if f.id == "float":
                if len(types) != 1 or not _numeric(types[0]):
                    raise _refuse(fn, node, "float() of other than one number")
                return FLOAT
            raise _refuse(fn, node, f"{f.id}() outside a for loop's header")
        callee = fn.callees.get(f.id)
        if callee is None:
            raise _refuse(fn, node, f"a call of {f.id}")
        target = self.program.function(callee)
        args = self.bind(node, target)
        spec = self.program.specialize(target, tuple(self.expr(a) for a in args), caller=fn, node=node)
        if self.strict:
            self.spec.calls[id(node)] = spec
            self.spec.args[id(node)] = args
        return spec.ret

    def bind(self, node: ast.Call, target: _Function) -> list[ast.expr]:
        """The call's arguments in the callee's parameter order (keywords and constant defaults placed)."""
        params = target.params
        if len(node.args) > len(params):
            raise _refuse(self.fn, node, f"a call of {target.qualname} with too many arguments")
        bound: dict[str, ast.expr] = dict(zip(params, node.args, strict=False))
        for kw in node.keywords:
            if kw.arg is None or kw.arg not in params or kw.arg in bound:
                raise _refuse(self.fn, node, f"a call of {target.qualname} with keyword {kw.arg!r}")
            bound[kw.arg] = kw.value
        for p in params:
            if p not in bound:
                if p not in target.defaults:
                    raise _refuse(self.fn, node, f"a call of {target.qualname} without its argument {p!r}")
                default = target.defaults[p]
                if not isinstance(default, ast.Constant | ast.Tuple):
                    raise _refuse(target, default, f"the default of {p!r}", "not a constant")
                bound[p] = default
        return [bound[p] for p in params]

    def subscript(self, node: ast.Subscript) -> Any:
        fn = self.fn
        t = self.expr(node.value)
        idx = node.slice
        if isinstance(t, TupleType):
            n = len(t.elems)
            k = _const_int(idx)
            if k is not None:
                if not -n <= k < n:
                    raise _refuse(fn, node, f"the index {k} of a tuple of {n}")
                self.expr(idx)
                return t.elems[k]
            if self.expr(idx) != INT:
                raise _refuse(fn, node, "a tuple index that is not an integer")
            if len(set(t.elems)) != 1:
                raise _refuse(fn, node, f"a variable index into a tuple of mixed types {t}")
            if not isinstance(node.value, ast.Name | ast.Tuple):
                raise _refuse(fn, node, "a variable index into a tuple that is not a variable")
            return t.elems[0]
        if isinstance(t, ArrayType):
            parts = idx.elts if isinstance(idx, ast.Tuple) else [idx]
            if len(parts) != len(t.shape):
                raise _refuse(fn, node, f"indexing a {len(t.shape)}-d array with {len(parts)} index(es)")
            for p, size in zip(parts, t.shape, strict=True):
                k = _const_int(p)
                if k is not None and not -size <= k < size:
                    raise _refuse(fn, node, f"the index {k} of an array axis of {size}")
                if self.expr(p) != INT:
                    raise _refuse(fn, node, "an array index that is not an integer")
            if isinstance(idx, ast.Tuple) and self.strict:
                self.spec.types[id(idx)] = TupleType((INT,) * len(parts))
            return FLOAT
        raise _refuse(fn, node, f"indexing a {t}")


def _const_int(node: ast.AST) -> int | None:
    """The value of an integer constant (``3``, ``-1``), else None."""
    if isinstance(node, ast.Constant) and isinstance(node.value, int) and not isinstance(node.value, bool):
        return node.value
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        inner = _const_int(node.operand)
        if inner is not None:
            return -inner if isinstance(node.op, ast.USub) else inner
    return None


def _op_text(op: ast.AST) -> str:
    return {ast.FloorDiv: "//", ast.Mod: "%", ast.MatMult: "@", ast.BitAnd: "&", ast.BitOr: "|", ast.BitXor: "^",
            ast.LShift: "<<", ast.RShift: ">>", ast.Invert: "~", ast.Is: "is", ast.IsNot: "is not", ast.In: "in",
            ast.NotIn: "not in"}.get(type(op), type(op).__name__)


# ------------------------------------------------------------------------------------------- program
class Program:
    """The translation of one kernel and everything it calls, for one language.

    Parameters
    ----------
    lang
        ``"c"`` (C99 that C++ compilers accept) or ``"js"`` (an ES module's functions).
    prefix
        C only: the prefix of every name the output defines (so that several laws can be included in one
        program); JavaScript modules need none and use ``$`` for generated names.
    """

    def __init__(self, lang: str, prefix: str = "bouncelab_") -> None:
        if lang not in ("c", "js"):
            raise ValueError(lang)
        self.lang = lang
        self.prefix = prefix if lang == "c" else "$"
        self._functions: dict[int, _Function] = {}
        self._specs: dict[tuple[int, tuple], _Spec] = {}
        self._active: set[tuple[int, tuple]] = set()
        self._names: set[str] = set()
        self._emitted: list[str] = []      # function definitions, callees first
        self._done: set[int] = set()       # id(spec) emitted
        self.tuples: dict[TupleType, str] = {}
        self._tuple_defs: list[str] = []
        self.helpers: set[str] = set()

    # -------------------------------------------------------------- building
    def function(self, dispatcher: Any) -> _Function:
        key = id(dispatcher.py_func)
        if key not in self._functions:
            self._functions[key] = _Function(dispatcher)
        return self._functions[key]

    def specialize(self, fn: _Function, argtypes: tuple[Any, ...], *, caller: _Function | None = None,
                   node: ast.AST | None = None) -> _Spec:
        key = (id(fn.func), argtypes)
        if key in self._active:
            raise _refuse(caller or fn, node, f"a recursive call of {fn.qualname}")
        spec = self._specs.get(key)
        if spec is None:
            spec = _Spec(fn, argtypes)
            self._active.add(key)
            try:
                _Typer(self, spec).run()
            finally:
                self._active.discard(key)
            if spec.ret is None:
                raise _refuse(fn, None, "a function whose return type cannot be found")
            spec.name = self._unique(self.prefix + "f_" + fn.func.__name__)
            self._specs[key] = spec
        return spec

    def _unique(self, name: str) -> str:
        out, k = name, 2
        while out in self._names:
            out, k = f"{name}_{k}", k + 1
        self._names.add(out)
        return out

    def entry(self, dispatcher: Any, argtypes: tuple[Any, ...]) -> _Spec:
        """Type the kernel for its arguments and emit it with everything it calls; its specialisation."""
        fn = self.function(dispatcher)
        spec = self.specialize(fn, argtypes)
        self.emit(spec)
        return spec

    def tuple_name(self, t: TupleType) -> str:
        """C: the struct type of a tuple type (defined once, nested tuples first)."""
        if t not in self.tuples:
            for e in t.elems:
                if isinstance(e, TupleType):
                    self.tuple_name(e)
            name = self.tuples[t] = f"{self.prefix}tuple{len(self.tuples)}"
            fields = "; ".join(f"{self.ctype(e)} v{k}" for k, e in enumerate(t.elems))
            params = ", ".join(f"{self.ctype(e)} a{k}" for k, e in enumerate(t.elems))
            sets = " ".join(f"t.v{k} = a{k};" for k in range(len(t.elems)))
            self._tuple_defs.append(f"typedef struct {{ {fields}; }} {name};\n"
                                    f"static inline {name} {name}_make({params}) {{ {name} t; {sets} return t; }}")
        return self.tuples[t]

    def ctype(self, t: Any) -> str:
        if t == FLOAT:
            return "double"
        if t == INT:
            return "long long"
        if t == BOOL:
            return "int"
        if isinstance(t, TupleType):
            return self.tuple_name(t)
        raise TypeError(t)

    # -------------------------------------------------------------- output
    def definitions(self) -> str:
        """Everything emitted, in order: tuple types (C), helpers, then the functions."""
        parts = []
        if self.lang == "c":
            parts += self._tuple_defs
        parts += [(_js_pow() if (self.lang, h) == ("js", "pow") else _HELPERS[self.lang][h]).replace("$P", self.prefix)
                  for h in sorted(self.helpers)]
        parts += self._emitted
        return "\n\n".join(parts)

    def emit(self, spec: _Spec) -> None:
        if id(spec) in self._done:
            return
        self._done.add(id(spec))
        for callee in spec.calls.values():
            self.emit(callee)
        self._emitted.append(_Emitter(self, spec).function())

    def literal(self, value: Any, t: Any = None) -> str:
        """A constant in the output language (exact: floats by their shortest round-trip repr)."""
        c = self.lang == "c"
        if isinstance(value, bool | np.bool_):
            return ("1" if value else "0") if c else ("true" if value else "false")
        if isinstance(value, numbers.Integral) and t != FLOAT:
            v = int(value)
            text = str(abs(v)) + ("LL" if c and abs(v) > 2**31 - 1 else "")
            return f"(-{text})" if v < 0 else text
        v = float(value)
        if math.isnan(v):
            return "NAN" if c else "NaN"
        if math.isinf(v):
            text = "INFINITY" if c else "Infinity"
        else:
            text = repr(abs(v))
            if c and not any(ch in text for ch in ".e"):
                text += ".0"
        return f"(-{text})" if math.copysign(1.0, v) < 0 else text


# Helpers the translated code may call ($P is the prefix). Python's min(a, b) is b if b < a else a, its
# max(a, b) b if b > a else a (numba's too): neither fmin nor Math.min, which treat NaN and -0 otherwise.
_HELPERS = {
    "c": {
        "min_f": "static inline double $Pmin_f(double a, double b) { return b < a ? b : a; }",
        "max_f": "static inline double $Pmax_f(double a, double b) { return b > a ? b : a; }",
        "min_i": "static inline long long $Pmin_i(long long a, long long b) { return b < a ? b : a; }",
        "max_i": "static inline long long $Pmax_i(long long a, long long b) { return b > a ? b : a; }",
    },
    "js": {
        "min_f": "function $min(a, b) { return b < a ? b : a; }",
        "max_f": "function $max(a, b) { return b > a ? b : a; }",
        "copysign": "function $copysign(x, y) {\n  const ax = Math.abs(x);\n"
                    "  return (y < 0 || (y === 0 && 1 / y < 0)) ? -ax : ax;\n}",
        "isinf": "function $isinf(x) { return x === Infinity || x === -Infinity; }",
    },
}


def _dd(q: Fraction) -> tuple[float, float]:
    """``q`` as a double-double: the nearest double and the nearest double to the rest."""
    hi = float(q)
    return hi, float(q - Fraction(hi))


@functools.cache
def _js_pow() -> str:
    """JavaScript's ``$pow``: C's pow correctly rounded, in double-double arithmetic (constants exact from Python)."""
    with localcontext() as ctx:
        ctx.prec = 60
        ln2 = _dd(Fraction(Decimal(2).ln()))
    atanh = [_dd(Fraction(1, 2 * k + 1)) for k in range(22)]
    fact = [_dd(Fraction(1, math.factorial(j))) for j in range(11)]

    def arr(pairs: list[tuple[float, float]]) -> str:
        return "[" + ", ".join(f"{h!r}, {lo!r}" for h, lo in pairs) + "]"

    return f"""// pow(x, y) correctly rounded (but for near-ties and |y ln x| > 700), in double-double arithmetic.
// Node's Math.pow differs from the C library's pow in the last bit for about 8 % of arguments; this one only
// where the C library's pow is not correctly rounded itself (about 0.1 % of arguments).
const $LN2H = {ln2[0]!r}, $LN2L = {ln2[1]!r};
const $ATANH = {arr(atanh)};
const $INVFACT = {arr(fact)};
const $F64 = new Float64Array(1), $U32 = new Uint32Array($F64.buffer);
const $HI = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1 ? 1 : 0;
let $h = 0, $l = 0;
function $add(ah, al, bh, bl) {{
  const s = ah + bh, v = s - ah, e = (ah - (s - v)) + (bh - v);
  const t = al + bl, w = t - al, f = (al - (t - w)) + (bl - w);
  const g = e + t, h = s + g, k = f + (g - (h - s));
  $h = h + k; $l = k - ($h - h);
}}
function $mul(ah, al, bh, bl) {{
  const p = ah * bh;
  const ca = 134217729 * ah, ahh = ca - (ca - ah), alo = ah - ahh;
  const cb = 134217729 * bh, bhh = cb - (cb - bh), blo = bh - bhh;
  const e = ((ahh * bhh - p) + ahh * blo + alo * bhh) + alo * blo + (ah * bl + al * bh);
  $h = p + e; $l = e - ($h - p);
}}
function $pow(x, y) {{
  if (!(x > 0) || x === Infinity || !Number.isFinite(y) || y === 0 || x === 1) {{
    if (x === 1 || y === 0) return 1;  // as C's pow, also for NaN
    if (x === -1 && (y === Infinity || y === -Infinity)) return 1;
    return Math.pow(x, y);  // C's other special values
  }}
  let e = 0;
  if (x < 2.2250738585072014e-308) {{ x *= 18014398509481984; e = -54; }}
  $F64[0] = x;
  const top = $U32[$HI];
  e += ((top >>> 20) & 0x7ff) - 1023;
  $U32[$HI] = (top & 0x000fffff) | 0x3ff00000;
  let m = $F64[0];
  if (m > 1.4142135623730951) {{ m *= 0.5; e += 1; }}
  // ln m = 2 atanh(s), s = (m - 1) / (m + 1): a series in s^2 <= 0.0295
  const d = m + 1, dv = d - m, dl = (m - (d - dv)) + (1 - dv);
  const q1 = (m - 1) / d;
  $mul(q1, 0, d, dl);
  $add(m - 1, 0, -$h, -$l);
  const q2 = $h / d, sh = q1 + q2, sl = q2 - (sh - q1);
  $mul(sh, sl, sh, sl);
  const zh = $h, zl = $l;
  let ph = $ATANH[42], pl = $ATANH[43];
  for (let k = 40; k >= 0; k -= 2) {{
    $mul(ph, pl, zh, zl);
    $add($h, $l, $ATANH[k], $ATANH[k + 1]);
    ph = $h;
    pl = $l;
  }}
  $mul(ph, pl, sh, sl);
  const ah = 2 * $h, al = 2 * $l;
  $mul(e, 0, $LN2H, $LN2L);
  $add($h, $l, ah, al);
  $mul($h, $l, y, 0);  // t = y ln x
  const th = $h, tl = $l;
  if (!(Math.abs(th) < 700)) return Math.pow(x, y);
  // exp(t) = 2^k exp(r), |r| <= ln2 / 2, exp(r) = exp(r / 256)^256
  const k = Math.round(th / $LN2H);
  $mul(k, 0, $LN2H, $LN2L);
  $add(th, tl, -$h, -$l);
  const rh = $h / 256, rl = $l / 256;
  ph = $INVFACT[20]; pl = $INVFACT[21];
  for (let j = 18; j >= 0; j -= 2) {{
    $mul(ph, pl, rh, rl);
    $add($h, $l, $INVFACT[j], $INVFACT[j + 1]);
    ph = $h;
    pl = $l;
  }}
  for (let i = 0; i < 8; i++) {{ $mul(ph, pl, ph, pl); ph = $h; pl = $l; }}
  $U32[$HI] = (k + 1023) << 20;
  $U32[1 - $HI] = 0;
  return ph * $F64[0];
}}"""


class _Emitter:
    """Writes one specialised function in the program's language."""

    def __init__(self, program: Program, spec: _Spec) -> None:
        self.p = program
        self.c = program.lang == "c"
        self.spec = spec
        self.fn = spec.fn
        taken = set(self.fn.locals) | _RESERVED
        self.names: dict[str, str] = {}
        for name in sorted(self.fn.locals):
            out = name
            if out in _RESERVED or out.startswith(program.prefix) or not out.isascii():
                if not out.isascii():
                    raise _refuse(self.fn, None, f"the non-ASCII name {name!r}")
                out = name + "_"
                while out in taken:
                    out += "_"
                taken.add(out)
            self.names[name] = out
        self.taken = taken | set(self.names.values())
        self.counter = 0
        self.lines: list[str] = []
        self.depth = 1

    def fresh(self, base: str) -> str:
        while True:
            self.counter += 1
            name = f"{base}{self.counter}"
            if name not in self.taken:
                self.taken.add(name)
                return name

    def live(self, name: str) -> bool:
        return name in self.fn.read

    def out(self, text: str) -> None:
        self.lines.append("    " * self.depth + text)

    # -------------------------------------------------------------- the function
    def function(self) -> str:
        fn, spec = self.fn, self.spec
        params, prologue = [], []
        for name, t in zip(fn.params, spec.argtypes, strict=True):
            final = spec.env[name]
            pname = self.names[name]
            if final != t:  # a parameter assigned a wider type: a local of that type takes its value
                pname = self.fresh(pname + "_in")
                prologue.append((name, pname))
            params.append(self.param(pname, t))
            if not self.live(name) and final == t and self.c:
                self.out(f"(void){pname};")
        declared = set(fn.params) - {n for n, _ in prologue}
        for name in sorted(spec.env):
            if name in declared or not self.live(name):
                continue
            t = spec.env[name]
            init = next((src for n, src in prologue if n == name), None)
            self.out(self.declare(self.names[name], t, init))
        for s in fn.body:
            self.stmt(s)
        body = "\n".join(self.lines)
        if self.c:
            head = f"static inline {self.p.ctype(spec.ret)} {spec.name}({', '.join(params) or 'void'})"
        else:
            head = f"function {spec.name}({', '.join(params)})"
        doc = f"/* {fn.qualname} {_types_text(spec.argtypes)} -> {spec.ret} */"
        return f"{doc}\n{head} {{\n{body}\n}}"

    def param(self, name: str, t: Any) -> str:
        if not self.c:
            return name
        if isinstance(t, ArrayType):
            return f"const double {name}" + "".join(f"[{s}]" for s in t.shape)
        return f"{self.p.ctype(t)} {name}"

    def declare(self, name: str, t: Any, init: str | None = None) -> str:
        if self.c:
            if init is None:
                init = self.zero(t)
            return f"{self.p.ctype(t)} {name} = {init};"
        return f"let {name} = {init if init is not None else self.zero(t)};"

    def zero(self, t: Any) -> str:
        if isinstance(t, TupleType):
            if not self.c:
                return "null"
            return f"{self.p.tuple_name(t)}_make({', '.join(self.zero(e) for e in t.elems)})"
        return self.p.literal(False if t == BOOL else (0 if t == INT else 0.0), t)

    # -------------------------------------------------------------- statements
    def stmt(self, s: ast.stmt) -> None:
        c = self.c
        if isinstance(s, ast.Assign):
            self.assign(s.targets[0], s.value)
        elif isinstance(s, ast.AugAssign):
            name = s.target.id
            if self.live(name):
                t_old = self.spec.env[name]
                value = self.binop(s.op, self.names[name], self.expr(s.value), t_old, self.type(s.value))
                self.out(f"{self.names[name]} = {value};")
        elif isinstance(s, ast.If):
            self.out(f"if ({self.cond(s.test)}) {{")
            self.block(s.body)
            orelse = s.orelse
            while len(orelse) == 1 and isinstance(orelse[0], ast.If):
                self.out(f"}} else if ({self.cond(orelse[0].test)}) {{")
                self.block(orelse[0].body)
                orelse = orelse[0].orelse
            if orelse:
                self.out("} else {")
                self.block(orelse)
            self.out("}")
        elif isinstance(s, ast.While):
            self.out(f"while ({self.cond(s.test)}) {{")
            self.block(s.body)
            self.out("}")
        elif isinstance(s, ast.For):
            args = [self.expr(a) for a in s.iter.args]
            start, stop, step = ("0", args[0], 1) if len(args) == 1 else (args[0], args[1], 1)
            if len(args) == 3:
                step = _const_int(s.iter.args[2])
            i, n = self.fresh("i_"), self.fresh("n_")
            kind = "long long" if c else "let"
            cmp = "<" if step > 0 else ">"
            inc = f"{i}++" if step == 1 else f"{i} += {self.p.literal(step)}"
            self.out(f"for ({kind} {i} = {start}, {n} = {stop}; {i} {cmp} {n}; {inc}) {{")
            if self.live(s.target.id):
                self.depth += 1
                self.out(f"{self.names[s.target.id]} = {i};")
                self.depth -= 1
            self.block(s.body)
            self.out("}")
        elif isinstance(s, ast.Return):
            self.ret(s.value)
        elif isinstance(s, ast.Break):
            self.out("break;")
        elif isinstance(s, ast.Continue):
            self.out("continue;")
        # Pass and docstrings: nothing

    def block(self, body: Sequence[ast.stmt]) -> None:
        self.depth += 1
        for s in body:
            self.stmt(s)
        self.depth -= 1

    def cond(self, node: ast.expr) -> str:
        text = self.expr(node)
        return text[1:-1] if _wrapped(text) else text

    def assign(self, target: ast.expr, value: ast.expr) -> None:
        """``target = value``, ``a, b = ...`` and ``a, (b, c) = ...``: Python's simultaneous assignment."""
        if isinstance(target, ast.Name):
            if self.live(target.id):
                self.out(f"{self.names[target.id]} = {self.convert(value, self.spec.env[target.id])};")
            return
        if not any(self.live(n) for n, _ in _leaves(target)):
            return
        pairs: list[tuple[ast.expr, ast.expr]] = []  # (name or tuple of names, value)

        def pair(t: ast.expr, v: ast.expr) -> None:
            if isinstance(t, ast.Tuple) and isinstance(v, ast.Tuple):
                for te, ve in zip(t.elts, v.elts, strict=True):
                    pair(te, ve)
            elif any(self.live(n) for n, _ in _leaves(t)):
                pairs.append((t, v))

        pair(target, value)
        names = {n for t, _ in pairs for n, _ in _leaves(t)}
        reads = {x.id for _, v in pairs for x in ast.walk(v) if isinstance(x, ast.Name)}
        simple = not (reads & names) and all(isinstance(t, ast.Name) for t, _ in pairs)
        if simple:
            for t, v in pairs:
                self.out(f"{self.names[t.id]} = {self.convert(v, self.spec.env[t.id])};")
            return
        # Every value first (into temporaries), then the names: a, b = b, a swaps as in Python.
        self.out("{")
        self.depth += 1
        temps = []
        for t, v in pairs:
            tmp = self.fresh("t_")
            temps.append((t, tmp, self.type(v)))
            self.out(self.constant(tmp, self.type(v), self.expr(v)))
        for t, tmp, have in temps:
            for name, path in _leaves(t):
                if self.live(name):
                    text, kind = tmp, have
                    for k in path:
                        text, kind = self.field(text, k), kind.elems[k]
                    self.out(f"{self.names[name]} = {self.rebuild(text, kind, self.spec.env[name])};")
        self.depth -= 1
        self.out("}")

    def rebuild(self, text: str, have: Any, want: Any) -> str:
        """``text`` (a variable or its field: cheap to repeat) as type ``want`` (C: a tuple of other types rebuilt)."""
        if not self.c or have == want or not isinstance(want, TupleType):
            return text
        items = ", ".join(self.rebuild(self.field(text, k), h, w) for k, (h, w) in
                          enumerate(zip(have.elems, want.elems, strict=True)))
        return f"{self.p.tuple_name(want)}_make({items})"

    def constant(self, name: str, t: Any, text: str) -> str:
        return f"const {self.p.ctype(t)} {name} = {text};" if self.c else f"const {name} = {text};"

    def field(self, text: str, k: int) -> str:
        return f"{text}.v{k}" if self.c else f"{text}[{k}]"

    def convert(self, value: ast.expr, t: Any) -> str:
        """``value`` as type ``t`` (numbers convert by themselves; a tuple of other element types is rebuilt)."""
        have = self.type(value)
        text = self.expr(value)
        if not self.c or have == t or not isinstance(t, TupleType):
            return text
        if isinstance(value, ast.Tuple):
            return self.tuple_text(value.elts, t)
        raise _refuse(self.fn, value, f"a tuple of types {have} used as {t}")

    def ret(self, value: ast.expr) -> None:
        t = self.spec.ret
        have = self.type(value)
        if self.c and isinstance(t, TupleType) and have != t and not isinstance(value, ast.Tuple):
            tmp = self.fresh("t_")
            self.out("{")
            self.depth += 1
            self.out(self.constant(tmp, have, self.expr(value)))
            fields = ", ".join(self.field(tmp, k) for k in range(len(t.elems)))
            self.out(f"return {self.p.tuple_name(t)}_make({fields});")
            self.depth -= 1
            self.out("}")
            return
        text = self.convert(value, t)
        self.out(f"return {text[1:-1] if _wrapped(text) else text};")

    # -------------------------------------------------------------- expressions
    def type(self, node: ast.expr) -> Any:
        return self.spec.types[id(node)]

    def tuple_text(self, elts: Sequence[ast.expr], t: TupleType) -> str:
        items = ", ".join(self.convert(e, et) if isinstance(et, TupleType) else self.expr(e)
                          for e, et in zip(elts, t.elems, strict=True))
        return f"{self.p.tuple_name(t)}_make({items})" if self.c else f"[{items}]"

    def binop(self, op: ast.operator, a: str, b: str, ta: Any, tb: Any) -> str:
        if isinstance(op, ast.Pow):
            if not self.c:
                self.p.helpers.add("pow")
            return f"pow({a}, {b})" if self.c else f"$pow({a}, {b})"
        if isinstance(op, ast.Div) and self.c and ta == INT and tb == INT:
            return f"((double){a} / (double){b})"
        return f"({a} {_BINOPS[type(op)]} {b})"

    def expr(self, node: ast.expr) -> str:
        c, p = self.c, self.p
        t = self.type(node)
        if isinstance(node, ast.Constant):
            return p.literal(node.value, t)
        if isinstance(node, ast.Name):
            return self.names[node.id]
        if isinstance(node, ast.Tuple):
            return self.tuple_text(node.elts, t)
        if isinstance(node, ast.BinOp):
            return self.binop(node.op, self.expr(node.left), self.expr(node.right), self.type(node.left),
                              self.type(node.right))
        if isinstance(node, ast.UnaryOp):
            operand = self.expr(node.operand)
            return f"(!{operand})" if isinstance(node.op, ast.Not) else \
                f"({'-' if isinstance(node.op, ast.USub) else '+'}{operand})"
        if isinstance(node, ast.BoolOp):
            op = " && " if isinstance(node.op, ast.And) else " || "
            return "(" + op.join(self.expr(v) for v in node.values) + ")"
        if isinstance(node, ast.Compare):
            terms = [self.expr(node.left)] + [self.expr(x) for x in node.comparators]
            parts = []
            for op, a, b in zip(node.ops, terms, terms[1:], strict=False):
                sym = _CMPOPS[type(op)]
                if not c and sym in ("==", "!="):
                    sym += "="
                parts.append(f"({a} {sym} {b})")
            return parts[0] if len(parts) == 1 else "(" + " && ".join(parts) + ")"
        if isinstance(node, ast.IfExp):
            return f"({self.cond(node.test)} ? {self.expr(node.body)} : {self.expr(node.orelse)})"
        if isinstance(node, ast.Call):
            return self.call(node, t)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        raise _refuse(self.fn, node, f"the expression {type(node).__name__}")  # typed, so unreachable

    def call(self, node: ast.Call, t: Any) -> str:
        c, p = self.c, self.p
        f = node.func
        if isinstance(f, ast.Attribute):
            _, cname, jsname, _ = _MATH_FUNCS[f.attr]
            if not c and jsname.startswith("$"):
                p.helpers.add(jsname[1:])
            args = ", ".join(self.expr(a) for a in node.args)
            return f"{cname if c else jsname}({args})"
        if f.id in self.fn.builtins:
            args = [self.expr(a) for a in node.args]
            if f.id in ("min", "max"):
                kind = f"{f.id}_{'i' if t == INT and c else 'f'}"
                p.helpers.add(kind)
                name = f"{p.prefix}{kind}" if c else f"${f.id}"
                out = args[0]
                for a in args[1:]:
                    out = f"{name}({out}, {a})"
                return out
            if f.id == "abs":
                return (("fabs" if t == FLOAT else "llabs") if c else "Math.abs") + f"({args[0]})"
            return f"((double){args[0]})" if c else f"(+{args[0]})"  # float()
        spec = self.spec.calls[id(node)]
        args = self.spec.args[id(node)]
        return f"{spec.name}({', '.join(self.expr(a) for a in args)})"

    def subscript(self, node: ast.Subscript) -> str:
        t = self.type(node.value)
        idx = node.slice
        if isinstance(t, TupleType) and isinstance(node.value, ast.Tuple) and _const_int(idx) is not None:
            return self.expr(node.value.elts[_const_int(idx) % len(t.elems)])  # a constant tuple's element
        base = "" if isinstance(t, TupleType) and isinstance(node.value, ast.Tuple) else self.expr(node.value)
        if isinstance(t, TupleType):
            n = len(t.elems)
            k = _const_int(idx)
            if k is not None:
                return self.field(base, k % n)
            i = self.expr(idx)
            items = ([self.expr(e) for e in node.value.elts] if isinstance(node.value, ast.Tuple)
                     else [self.field(base, k) for k in range(n)])
            out = items[-1]  # numba raises on an index out of range; here: the last element
            for k in range(n - 2, -1, -1):
                out = f"(({i} == {k} || {i} == {k - n}) ? {items[k]} : {out})"
            return out
        parts = idx.elts if isinstance(idx, ast.Tuple) else [idx]
        out = base
        for part, size in zip(parts, t.shape, strict=True):
            k = _const_int(part)
            if k is not None:
                out += f"[{k % size}]"
            else:
                i = self.expr(part)
                out += f"[({i} < 0 ? {i} + {size} : {i})]"
        return out


def _leaves(target: ast.expr, path: tuple[int, ...] = ()) -> list[tuple[str, tuple[int, ...]]]:
    """The names of an assignment target with their place in the value: ``a, (b, c)`` -> a (0,), b (1, 0)..."""
    if isinstance(target, ast.Name):
        return [(target.id, path)]
    if isinstance(target, ast.Tuple):
        return [leaf for k, e in enumerate(target.elts) for leaf in _leaves(e, (*path, k))]
    return []  # refused when typed


def _wrapped(text: str) -> bool:
    """Whether ``text`` is one parenthesised expression, ``(...)``, whose outer parentheses can go."""
    if not (text.startswith("(") and text.endswith(")")):
        return False
    depth = 0
    for k, ch in enumerate(text):
        depth += ch == "("
        depth -= ch == ")"
        if depth == 0 and k < len(text) - 1:
            return False
    return True


def _types_text(types: Sequence[Any]) -> str:
    return "(" + ", ".join(map(str, types)) + ")"


def translate(kernel: Any, argtypes: Sequence[Any], lang: str, prefix: str = "bouncelab_") -> tuple[Program, _Spec]:
    """Translate ``kernel`` (a jit function) for arguments of ``argtypes``: the program and its entry spec."""
    program = Program(lang, prefix)
    return program, program.entry(kernel, tuple(argtypes))

