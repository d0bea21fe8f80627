r"""The front end: the restricted Python of bouncelab's numba kernels, read into the intermediate form.

A compiled law's mathematics lives in one place: its numba kernel (:mod:`bouncelab.laws._kernels`,
:mod:`bouncelab.laws._contact_kernels`, or a user's own). This module reads the kernel's Python source
(``kernel.py_func``, :func:`inspect.getsource`), types it as numba does (int64, float64, boolean,
tuples, arrays), specialising each function it calls for the types it is called with, and writes it as
the typed scalar functions of :mod:`bouncelab.export.ir`, operation by operation and in the same order,
so that every language printed from them (:mod:`bouncelab.export.emit`) computes the same IEEE-754
double-precision results. Tuples become scalars there, and every conversion is written out.

The supported subset
--------------------
Functions
    Plain functions decorated with :func:`bouncelab.core._jit.jit` (or ``numba.njit``), with positional
    parameters (defaults that are constants allowed); calls by position or keyword to other such
    functions, however deep, but not recursive; ``f(x, *args)`` with ``args`` a tuple variable; a jit
    function passed as an argument (``law(xd, yd, w, *args)`` with ``law`` a parameter) is called
    directly, as numba specialises for it; a jit function of the enclosing scope (a closure, as the
    ground phase's row loops are built around a law's lift). Every function ends with a ``return`` of a
    value, or has no ``return`` at all: it returns nothing and is called as a statement.
Values
    Floats (double), integers (64-bit), booleans, tuples of these (also nested, returned, passed and
    unpacked), and float or integer arrays of a fixed shape passed in as arguments (indexed ``A[i]``,
    ``A[0, 2]``; ``A.shape[k]`` is a constant of the translation; alone or in a tuple argument).
    **Empty arrays** (a zero in the shape: an optional argument left out, or ``np.empty(0)``,
    ``np.empty((0, 6))`` made inside as a placeholder) have no place in the output: a load from one
    never runs where numba's code is correct (it would read past the array), so it reads as NaN, and
    comparisons with it are decided (false, as with NaN); a store into one is dropped; a parameter of
    that type is left out. With constant comparisons folded (``air.shape[0] == 0``) and ``and``/``or``
    of constants decided, the code of an unused option disappears.
Names outside the function
    Module-level (or closure) numbers, booleans and tuples of them are constants; ``math.pi``,
    ``math.e``, ``math.tau``, ``math.inf``, ``math.nan``; other jit functions.
Statements
    Assignment to a name, to an element of an array argument (``OUT[i, 3] = x``: a store; a boolean is
    stored as 1 or 0) or to a tuple of them (``a, b = b, a`` and ``A[0], A[1] = A[1], A[0]`` are
    simultaneous, as in Python), augmented assignment to a name (``+= -= *= /=``), ``if``/``elif``/
    ``else``, ``while``, ``for ... in range(...)`` with a constant step, ``break``, ``continue``,
    ``return``, ``pass``, docstrings, and a call of a jit function as a statement (its value dropped).
    Only an entry point (a function called from outside, :meth:`Translation.add`) may store into
    arrays: a call of a function that stores is refused, so every call inside the output has no
    effects (:mod:`bouncelab.export.ir`); a call as a statement of a function without effects does
    nothing and is not written.
Expressions
    ``+ - * / **`` (``**`` with a float exponent: C's ``pow``), unary ``- + not``, comparisons (chained
    ones too), ``and``/``or`` of booleans, ``x if c else y``, ``min``/``max`` (Python's rule: the first
    of equal values, NaN as Python orders it), ``abs``, ``float()``, and ``math.sqrt exp log log10 log1p
    expm1 sin cos tan asin acos atan atan2 sinh cosh tanh asinh acosh atanh hypot pow copysign fabs isnan
    isinf isfinite``; tuple indexing (constant index, or an integer variable for a tuple of one type).

Anything else (lists, ``//`` and ``%``, bitwise operators, strings, ``None``, attributes other than
``math``'s and an array's ``shape``, calls of non-jit functions, numpy but empty placeholders, arrays
made inside a function, ``while``/``for`` with ``else``, ``try``, ``with``,
``global``, nested functions, integer exponents, truthiness of numbers...) is refused with an
:class:`~bouncelab.export.errors.ExportError` naming the function, file, line and construct: the
translator never guesses.

Differences from numba that remain (documented in each exported file): numba raises on a division by zero
and on a tuple index out of range, where the exported code follows IEEE (inf or NaN) and takes the last
element. Each language's notes (its math library, its integers) are its emitter's
(:mod:`bouncelab.export.emit`).
"""

from __future__ import annotations

import ast
import builtins
import inspect
import math
import numbers
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bouncelab.export import ir
from bouncelab.export.errors import ExportError

__all__ = ["BOOL", "FLOAT", "INT", "ArrayType", "FuncType", "Translation", "TupleType", "is_jit_function",
           "leaf_types", "value_type"]


# ------------------------------------------------------------------------------------------- types
FLOAT, INT, BOOL = "double", "int64", "bool"
#: The type of what a function without a ``return`` returns (it is called as a statement only).
NONE = "none"


@dataclass(frozen=True)
class TupleType:
    """A tuple of the given element types (numba's Tuple / UniTuple)."""

    elems: tuple[Any, ...]

    def __str__(self) -> str:
        return "(" + ", ".join(map(str, self.elems)) + ")"


@dataclass(frozen=True)
class ArrayType:
    """An array of the given shape of floats (``FLOAT``) or integers (``INT``): a kernel argument, or
    an empty placeholder made by ``np.empty`` (a shape with a zero)."""

    shape: tuple[int, ...]
    dtype: str = "double"

    @property
    def empty(self) -> bool:
        """Whether it holds nothing (a zero in its shape): it has no place in the output (see the module)."""
        return 0 in self.shape

    def __str__(self) -> str:
        return f"{'float64' if self.dtype == FLOAT else 'int64'} array {self.shape}"


@dataclass(frozen=True)
class FuncType:
    """A jit function passed as an argument: known when translating, so its calls are direct and it is not
    a parameter of the output (as numba specialises a function for the dispatcher it is given)."""

    dispatcher: Any = field(compare=False)
    key: int = 0

    @staticmethod
    def of(dispatcher: Any) -> FuncType:
        return FuncType(dispatcher, id(dispatcher.py_func))

    def __str__(self) -> str:
        return f"function {self.dispatcher.py_func.__qualname__}"


def _holds(t: Any, kinds: Any) -> bool:
    """Whether type t is, or is a tuple holding, one of ``kinds``."""
    return isinstance(t, kinds) or (isinstance(t, TupleType) and any(_holds(e, kinds) for e in t.elems))


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
    """The numba type of a Python value given to a kernel (float, int, bool, tuple, float array, jit function)."""
    if is_jit_function(value):
        return FuncType.of(value)
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
        if value.dtype.kind not in "fiu" or value.ndim == 0:
            raise TypeError(f"an array of {value.dtype} with shape {value.shape} (only float and integer arrays of "
                            "one or more dimensions are supported)")
        return ArrayType(tuple(int(s) for s in value.shape), FLOAT if value.dtype.kind == "f" else INT)
    raise TypeError(f"a {type(value).__name__}")


def is_jit_function(obj: Any) -> bool:
    """Whether ``obj`` is a numba dispatcher (a jit function with its Python function in ``py_func``)."""
    return inspect.isfunction(getattr(obj, "py_func", None)) and callable(obj)


# ------------------------------------------------------------------------------------------- names
# Names a translated variable must not take: keywords of C, C++, JavaScript and C#, the C library's (math.h,
# stdlib.h: functions and macros, including POSIX's j0, y1...), JavaScript's globals and the .NET names the
# C# output uses. Such a variable gets a trailing underscore, in every language.
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
abstract as base byte checked decimal delegate event finally fixed foreach implicit internal is lock object out
override params readonly ref sbyte sealed stackalloc string uint ulong unchecked unsafe ushort var dynamic value
get set add remove partial where nameof when System Math BitConverter Double Single Int32 Int64 Object Console
""".split()) | frozenset(n for n in dir(math) if not n.startswith("_"))

_MATH_CONSTANTS = {"pi": math.pi, "e": math.e, "tau": math.tau, "inf": math.inf, "nan": math.nan}
# math function -> (number of arguments, result type); each is an intrinsic of the IR of the same name
_MATH_FUNCS = {
    **{n: (1, FLOAT) for n in ("sqrt", "exp", "log", "log10", "log1p", "expm1", "sin", "cos", "tan", "asin", "acos",
                               "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "fabs")},
    **{n: (2, FLOAT) for n in ("atan2", "hypot", "pow", "copysign")},
    **{n: (1, BOOL) for n in ("isnan", "isinf", "isfinite")},
}
_BUILTINS = ("min", "max", "abs", "float", "range")
_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
_CMPOPS = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}
_REFUSED_NODES = {
    ast.List: "a list", ast.Dict: "a dict", ast.Set: "a set", ast.ListComp: "a list comprehension",
    ast.SetComp: "a set comprehension", ast.DictComp: "a dict comprehension", ast.GeneratorExp: "a generator",
    ast.Lambda: "a lambda", ast.JoinedStr: "an f-string",
    ast.NamedExpr: "an assignment expression (:=)", ast.Await: "await", ast.Yield: "yield",
    ast.YieldFrom: "yield from", ast.Slice: "a slice", ast.FunctionDef: "a nested function",
    ast.AsyncFunctionDef: "a nested function", ast.ClassDef: "a class", ast.Try: "try", ast.With: "with",
    ast.Raise: "raise", ast.Assert: "assert", ast.Delete: "del", ast.Import: "import", ast.ImportFrom: "import",
    ast.Global: "global", ast.Nonlocal: "nonlocal", ast.AnnAssign: "an annotated assignment",
    ast.AsyncFor: "async for", ast.AsyncWith: "async with", ast.Match: "match",
}


#: What ``np.`` reads as in a resolved function (not an identifier, so no local variable can take it).
_NUMPY = "<numpy>"

#: numba's fastmath flags that cannot change a finite result (bouncelab.core._jit.ROW_FLAGS): allowed.
_IEEE_SAFE_FLAGS = frozenset({"nnan", "ninf", "nsz"})


class _Unknown(Exception):
    """A variable read before any assignment typed it (in the fixed-point passes)."""


def _refuse(fn: _Function, node: ast.AST | None, what: str, detail: str = "") -> ExportError:
    line = None if node is None else getattr(node, "lineno", None)
    line = None if line is None else line + fn.line_offset
    where = f"{fn.qualname} ({fn.file}" + (f", line {line}" if line else "") + ")"
    text = (f"cannot translate {where}: {what}{': ' + detail if detail else ''} is outside the subset "
            "bouncelab.export translates (see bouncelab.export.frontend); nothing was written")
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
        #: A function without any return returns nothing: it is called as a statement (it stores, or does nothing)
        self.void = not any(isinstance(n, ast.Return) for n in ast.walk(fdef))
        if not self.void and (not fdef.body or not isinstance(fdef.body[-1], ast.Return)):
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
        self.starred: dict[int, list[ast.expr]] = {}  # id(call node) -> its arguments, *tuples spread

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
                if isinstance(n.value, ast.Name) and n.value.id in fn.locals and n.attr == "shape":
                    return n  # an array's shape: constants of the translation's array types
                if (isinstance(n.value, ast.Name) and n.value.id not in fn.locals and scope.get(n.value.id) is np
                        and n.attr in ("empty", "zeros")):
                    return ast.copy_location(ast.Attribute(ast.Name(_NUMPY, ast.Load()), n.attr, ast.Load()), n)
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

    def __init__(self, program: Translation, spec: _Spec) -> None:
        self.program = program
        self.spec = spec
        self.fn = spec.fn
        self.strict = False
        self.changed = False

    def run(self) -> None:
        fn, spec = self.fn, self.spec
        spec.env = dict(zip(fn.params, spec.argtypes, strict=True))
        if fn.void:
            spec.ret = NONE
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
        if isinstance(t, FuncType) or isinstance(env.get(name), FuncType):
            raise _refuse(self.fn, node, f"assigning a function to {name!r}")
        if name in env:
            try:
                new = unify(env[name], t)
            except TypeError as exc:
                raise _refuse(self.fn, node, f"the variable {name!r} holding values of types {exc}") from None
            if isinstance(new, ArrayType) and not new.empty:
                raise _refuse(self.fn, node, f"assigning an array to {name!r}")
            if new != env[name]:
                env[name] = new
                self.changed = True
        else:
            if isinstance(t, ArrayType) and not t.empty:
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
        elif isinstance(target, ast.Subscript):
            self.store(target, t, s)
        else:
            raise _refuse(self.fn, s, "assigning to " + ast.unparse(target))

    def store(self, target: ast.Subscript, t: Any, s: ast.stmt) -> None:
        """``array[i, j] = value``: an element of an array argument, assigned a number or a boolean."""
        at = self.expr(target.value) if isinstance(target.value, ast.Name) else None
        if not isinstance(at, ArrayType):
            raise _refuse(self.fn, s, "assigning to " + ast.unparse(target), "only an element of an array can be "
                          "assigned")
        if target.value.id not in self.fn.params and not at.empty:
            raise _refuse(self.fn, s, "assigning to " + ast.unparse(target), "only an element of an array "
                          "argument can be assigned")
        self.expr(target)  # its indices
        if not (_numeric(t) or t == BOOL) or (at.dtype == INT and t == FLOAT):
            raise _refuse(self.fn, s, f"storing a {t} into an {at}")

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
            if _holds(t, ArrayType | FuncType):
                raise _refuse(fn, s, "returning an array or a function")
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
            if isinstance(s.value, ast.Call) and isinstance(s.value.func, ast.Name) and (
                    s.value.func.id in fn.callees or isinstance(self.spec.env.get(s.value.func.id), FuncType)):
                self.call(s.value)  # a call as a statement: its value, if any, is dropped
                if self.strict:
                    self.spec.types[id(s.value)] = NONE
            elif not (isinstance(s.value, ast.Constant) and isinstance(s.value.value, str)):
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
        if t == NONE:
            raise _refuse(self.fn, node, "the value of a function that returns nothing", ast.unparse(node))
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
        if isinstance(node, ast.Starred):
            raise _refuse(fn, node, "a starred expression", "only a call of a jit function can spread a tuple "
                          "variable, f(x, *args)")
        if isinstance(node, ast.Tuple):
            t = TupleType(tuple(self.expr(e) for e in node.elts))
            if _holds(t, ArrayType | FuncType):
                raise _refuse(fn, node, "a tuple holding an array or a function")
            return t
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
            if isinstance(t, ArrayType | FuncType):
                raise _refuse(fn, node, "a conditional expression choosing an array or a function")
            return t
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        if isinstance(node, ast.Attribute):  # an array's shape (the resolver let no other attribute through)
            t = self.expr(node.value)
            if not isinstance(t, ArrayType):
                raise _refuse(fn, node, f"the shape of a {t}")
            return TupleType((INT,) * len(t.shape))
        raise _refuse(fn, node, f"the expression {type(node).__name__}", ast.unparse(node))

    def call(self, node: ast.Call) -> Any:
        fn = self.fn
        f = node.func
        if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == _NUMPY:
            return self.empty_array(node)
        if isinstance(f, ast.Attribute):  # math.X (resolved: only math's functions remain as attributes)
            nargs, result = _MATH_FUNCS[f.attr]
            if node.keywords or len(node.args) != nargs:
                raise _refuse(fn, node, f"math.{f.attr} with {len(node.args)} argument(s)")
            for a in node.args:
                if not _numeric(self.expr(a)):
                    raise _refuse(fn, node, f"math.{f.attr} of a non-number")
            return result
        if isinstance(f, ast.Name) and isinstance(self.spec.env.get(f.id), FuncType):  # a function passed in
            return self.call_jit(node, self.spec.env[f.id].dispatcher)
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
        return self.call_jit(node, callee)

    def empty_array(self, node: ast.Call) -> ArrayType:
        """``np.empty(0)``, ``np.empty((0, 6))``: an array that holds nothing (a placeholder for an optional
        argument), which has no place in the output; any other array a function makes is refused."""
        shape = node.args[0] if len(node.args) == 1 and not node.keywords else None
        parts = shape.elts if isinstance(shape, ast.Tuple) else [shape]
        sizes = [_const_int(p) for p in parts] if shape is not None else [None]
        if None in sizes or 0 not in sizes or any(k < 0 for k in sizes):
            raise _refuse(self.fn, node, "an array made inside a function", "only empty placeholders such as "
                          "np.empty(0) or np.empty((0, 6)) (shapes of constants with a zero) can be translated")
        return ArrayType(tuple(sizes))

    def call_jit(self, node: ast.Call, callee: Any) -> Any:
        target = self.program.function(callee)
        args = self.bind(node, target)
        spec = self.program.specialize(target, tuple(self.expr(a) for a in args), caller=self.fn, node=node)
        if self.strict:
            self.spec.calls[id(node)] = spec
            self.spec.args[id(node)] = args
        return spec.ret

    def bind(self, node: ast.Call, target: _Function) -> list[ast.expr]:
        """The call's arguments in the callee's parameter order (keywords and constant defaults placed)."""
        params = target.params
        positional = self.spread(node)
        if len(positional) > len(params):
            raise _refuse(self.fn, node, f"a call of {target.qualname} with too many arguments")
        bound: dict[str, ast.expr] = dict(zip(params, positional, strict=False))
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

    def spread(self, node: ast.Call) -> list[ast.expr]:
        """The call's positional arguments with ``*t`` (t a tuple variable) spread into ``t[0], t[1]...``."""
        if not any(isinstance(a, ast.Starred) for a in node.args):
            return list(node.args)
        if id(node) not in self.fn.starred:  # made once: the nodes' types are kept by their ids
            out: list[ast.expr] = []
            for a in node.args:
                if not isinstance(a, ast.Starred):
                    out.append(a)
                    continue
                if not isinstance(a.value, ast.Name) or a.value.id not in self.fn.locals:
                    raise _refuse(self.fn, a, "a starred argument that is not a tuple variable")
                if a.value.id not in self.spec.env:
                    raise _Unknown(a.value.id)
                t = self.spec.env[a.value.id]
                if not isinstance(t, TupleType):
                    raise _refuse(self.fn, a, f"a starred argument of type {t}")
                out += [ast.copy_location(ast.Subscript(ast.Name(a.value.id, ast.Load()), ast.Constant(k), ast.Load()),
                                          a) for k in range(len(t.elems))]
            self.fn.starred[id(node)] = out
        return self.fn.starred[id(node)]

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
                if k is not None and not -size <= k < size and not t.empty:
                    raise _refuse(fn, node, f"the index {k} of an array axis of {size}")
                if self.expr(p) != INT:
                    raise _refuse(fn, node, "an array index that is not an integer")
            if isinstance(idx, ast.Tuple) and self.strict:
                self.spec.types[id(idx)] = TupleType((INT,) * len(parts))
            return t.dtype
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



# ------------------------------------------------------------------------------------------- lowering
_IR_TYPES = {FLOAT: ir.F64, INT: ir.I64, BOOL: ir.BOOL}
_IR_BINOPS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
_COMPARE = {"<": lambda a, b: a < b, "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
            "==": lambda a, b: a == b, "!=": lambda a, b: a != b}


def leaf_types(t: Any) -> list[str]:
    """The IR types of the scalars a value of type t is made of (a tuple's, in order; none for a function)."""
    if isinstance(t, TupleType):
        return [leaf for e in t.elems for leaf in leaf_types(e)]
    if isinstance(t, FuncType) or t == NONE:
        return []
    if isinstance(t, ArrayType):  # an empty one has no place in the output
        return [] if t.empty else [ir.ArrayType(t.shape, _IR_TYPES[t.dtype])]
    return [_IR_TYPES[t]]


def _atom(e: ir.Expr) -> bool:
    return isinstance(e, ir.Const | ir.Var)


class _Lowerer:
    """One specialised function as an IR function: tuples split into scalars, conversions written out,
    the values of functions of several results taken by statements."""

    def __init__(self, translation: Translation, spec: _Spec) -> None:
        self.tr = translation
        self.spec = spec
        self.fn = spec.fn
        self.taken: set[str] = set()
        self.names: dict[str, list[str]] = {}     # Python variable -> the IR names of its scalars
        self.types: dict[str, str] = {}           # IR local -> IR type
        self.block: list[ir.Stmt] = []
        self.idents: dict[str, str] = {}  # Python name -> its identifier (given up front: int and int_ differ)
        for name in sorted(self.fn.locals):
            ident = self._ident(name)
            while ident in self.taken:
                ident += "_"
            self.taken.add(ident)
            self.idents[name] = ident

    # -------------------------------------------------------------- names
    def _ident(self, name: str) -> str:
        if not name.isascii():
            raise _refuse(self.fn, None, f"the non-ASCII name {name!r}")
        out = name
        if out.startswith(ir.EMITTER_PREFIXES):
            out = "v" + out
        if out in _RESERVED:
            out += "_"
        return out

    def fresh(self, base: str) -> str:
        base = self._ident(base)
        out, k = base, 1
        while out in self.taken:
            k += 1
            out = f"{base}{k}" if not base[-1].isdigit() else f"{base}_{k}"
        self.taken.add(out)
        return out

    def temp(self, t: str, base: str = "t") -> str:
        name = self.fresh(base)
        self.types[name] = t
        return name

    def variable(self, name: str, t: Any) -> list[str]:
        """The IR locals of Python variable ``name`` of type t (made on first use)."""
        if name not in self.names:
            leaves = leaf_types(t)
            if isinstance(t, TupleType):
                out = [self.temp(lt, f"{self.idents[name]}_{k}") for k, lt in enumerate(leaves)]
            elif not leaves:  # an empty array
                out = []
            else:
                out = [self.idents[name]]
                self.types[out[0]] = leaves[0]
            self.names[name] = out
        return self.names[name]

    # -------------------------------------------------------------- the function
    def function(self) -> ir.Function:
        fn, spec = self.fn, self.spec
        params: list[tuple[str, Any]] = []
        prologue: list[ir.Stmt] = []
        for name, t in zip(fn.params, spec.argtypes, strict=True):
            final = spec.env[name]
            if isinstance(t, FuncType):
                continue
            if isinstance(t, ArrayType):
                if t.empty:  # it holds nothing: no parameter (loads from it never run; stores into it are dropped)
                    self.names[name] = []
                    continue
                pname = self.idents[name]
                self.names[name] = [pname]
                params.append((pname, ir.ArrayType(t.shape, _IR_TYPES[t.dtype])))
                continue
            if final == t:  # the parameter's scalars are the variable's
                leaves = self.variable(name, t)
                params += [(n, self.types[n]) for n in leaves]
            else:  # assigned a wider type: locals of that type take the parameters' values
                incoming = [self.fresh(f"{self.idents[name]}_in{k if len(leaf_types(t)) > 1 else ''}")
                            for k in range(len(leaf_types(t)))]
                params += list(zip(incoming, leaf_types(t), strict=True))
                leaves = self.variable(name, final)
                for target, src, st in zip(leaves, incoming, leaf_types(t), strict=True):
                    prologue.append(ir.Assign(target, self.conv(ir.Var(src, st), self.types[target])))
        self.block = prologue
        self.stmts(fn.body)
        body = tuple(self.block)
        ret = spec.ret
        multi = isinstance(ret, TupleType)
        pnames = {n for n, _ in params}
        local_types = {n: t for n, t in self.types.items() if n not in pnames}
        out = ir.Function(spec.name, tuple(params), local_types, tuple(leaf_types(ret)), multi,
                          _fold(body), source=f"{fn.qualname} {_types_text(spec.argtypes)} -> {ret}")
        return ir.prune(out)

    # -------------------------------------------------------------- helpers
    def conv(self, e: ir.Expr, t: str) -> ir.Expr:
        if e.type == t:
            return e
        if e.type == ir.I64 and t == ir.F64:
            if isinstance(e, ir.Const):
                return ir.Const(float(e.value), ir.F64)
            return ir.Cast(e)
        raise _refuse(self.fn, None, f"a value of type {e.type} used as {t}")  # the typer makes this unreachable

    def sub(self, lower: Any) -> tuple[list[ir.Stmt], Any]:
        """Lower into a block of its own: (its statements, lower's result)."""
        saved, self.block = self.block, []
        try:
            result = lower()
            return self.block, result
        finally:
            self.block = saved

    def atomic(self, e: ir.Expr) -> ir.Expr:
        """``e``, or a temporary holding it when it is not a constant or a variable (to use it several times)."""
        if _atom(e):
            return e
        name = self.temp(e.type)
        self.block.append(ir.Assign(name, e))
        return ir.Var(name, e.type)

    def type(self, node: ast.expr) -> Any:
        return self.spec.types[id(node)]

    # -------------------------------------------------------------- statements
    def stmts(self, body: Sequence[ast.stmt]) -> None:
        for s in body:
            self.stmt(s)
            if isinstance(s, ast.Return | ast.Break | ast.Continue):
                return  # what follows in this block never runs

    def block_of(self, body: Sequence[ast.stmt]) -> tuple[ir.Stmt, ...]:
        stmts, _ = self.sub(lambda: self.stmts(body))
        return tuple(stmts)

    def stmt(self, s: ast.stmt) -> None:
        if isinstance(s, ast.Assign):
            self.assign(s.targets[0], s.value)
        elif isinstance(s, ast.AugAssign):
            name = s.target.id
            (target,) = self.variable(name, self.spec.env[name])
            t = self.types[target]
            value = self.scalar(s.value)
            result = self.arith(s.op, ir.Var(target, t), value)
            self.block.append(ir.Assign(target, self.conv(result, t)))
        elif isinstance(s, ast.If):
            cond = self.scalar(s.test)
            self.block.append(ir.If(cond, self.block_of(s.body), self.block_of(s.orelse)))
        elif isinstance(s, ast.While):
            pre, cond = self.sub(lambda: self.scalar(s.test))
            body = self.block_of(s.body)
            if pre:  # the condition needs statements: evaluate them at the top of every pass
                body = (*pre, ir.If(ir.Not(cond), (ir.Break(),)), *body)
                cond = ir.Const(True, ir.BOOL)
            self.block.append(ir.While(cond, body))
        elif isinstance(s, ast.For):
            args = [self.scalar(a) for a in s.iter.args]
            start, stop = (ir.Const(0, ir.I64), args[0]) if len(args) == 1 else (args[0], args[1])
            step = _const_int(s.iter.args[2]) if len(args) == 3 else 1
            counter, limit = self.fresh("i"), self.fresh("n")
            (var,) = self.variable(s.target.id, self.spec.env[s.target.id])
            first = ir.Assign(var, self.conv(ir.Var(counter, ir.I64), self.types[var]))
            self.block.append(ir.For(counter, limit, start, stop, step, (first, *self.block_of(s.body))))
        elif isinstance(s, ast.Return):
            if isinstance(s.value, ast.Call) and id(s.value) in self.spec.calls:
                callee = self.spec.calls[id(s.value)]
                if isinstance(callee.ret, TupleType) and leaf_types(callee.ret) == leaf_types(self.spec.ret):
                    _, args = self.call_args(s.value)
                    self.block.append(ir.TailCall(callee.name, tuple(args)))
                    return
            values = self.lower(s.value)
            types = leaf_types(self.spec.ret)
            self.block.append(ir.Return(tuple(self.conv(v, t) for v, t in zip(values, types, strict=True))))
        elif isinstance(s, ast.Break):
            self.block.append(ir.Break())
        elif isinstance(s, ast.Continue):
            self.block.append(ir.Continue())
        elif isinstance(s, ast.Expr) and isinstance(s.value, ast.Call):
            self.call_args(s.value)  # refuses a call of a function with effects
            # a call of a function without effects whose value is dropped does nothing: nothing to write
        # Pass and docstrings: nothing

    def targets(self, target: ast.expr) -> list[tuple[str | None, ast.Subscript | None]]:
        """Where an assignment target's scalars go, in order: ``(IR name, None)`` for a variable's scalar,
        ``(None, element)`` for an array element."""
        if isinstance(target, ast.Name):
            return [(n, None) for n in self.variable(target.id, self.spec.env[target.id])]
        if isinstance(target, ast.Subscript):
            return [(None, target)]
        return [slot for e in target.elts for slot in self.targets(e)]

    def assign(self, target: ast.expr, value: ast.expr) -> None:
        """``target = value`` with Python's simultaneous assignment (``a, b = b, a`` swaps; the values are all
        computed before any variable or array element is assigned)."""
        slots = self.targets(target)
        start = len(self.block)
        values = self.lower(value)
        accesses = [None if node is None else self.element(node) for _, node in slots]
        values = [self.conv(v, self.types[n]) if node is None else self.to_element(v, acc[1])
                  for v, (n, node), acc in zip(values, slots, accesses, strict=True)]
        names = [n for n, _ in slots]
        # a function of several results assigned whole: its results straight into the targets
        last = self.block[-1] if len(self.block) > start else None
        if (isinstance(last, ir.CallMulti) and None not in names
                and [ir.Var(t, self.types[t]) for t in last.targets] == values and len(set(names)) == len(names)):
            self.block[-1] = ir.CallMulti(tuple(names), last.func, last.args)
            return
        written = [n if n is not None else acc[0] for n, acc in zip(names, accesses, strict=True)]
        if len(slots) > 1:
            values = self._simultaneous(written, values)
        for (n, node), acc, v in zip(slots, accesses, values, strict=True):
            if node is None:
                self.block.append(ir.Assign(n, v))
            elif acc[0] is not None:  # an element of an empty array is never assigned: nothing to write
                self.block.append(ir.Store(acc[0], tuple(self.indices(node, acc[1])), v))

    def to_element(self, v: ir.Expr, t: ArrayType) -> ir.Expr:
        """A value as an element of an array of type t: a boolean as 1 or 0 (numba's conversion)."""
        elem = _IR_TYPES[t.dtype]
        if v.type == ir.BOOL:
            return ir.Select(v, ir.Const(1 if elem == ir.I64 else 1.0, elem), ir.Const(0 if elem == ir.I64 else 0.0,
                                                                                       elem), elem)
        return self.conv(v, elem)

    def _simultaneous(self, names: list[str | None], values: list[ir.Expr]) -> list[ir.Expr]:
        """Values made safe to assign one after the other: each that reads a target assigned before it (a
        variable, or an array stored into) is taken into a temporary first."""
        out = []
        for k, v in enumerate(values):
            if any(names[j] is not None and names[j] in ir.reads(v) for j in range(k)):
                tmp = self.temp(v.type)
                self.block.append(ir.Assign(tmp, v))
                v = ir.Var(tmp, v.type)
            out.append(v)
        return out

    # -------------------------------------------------------------- expressions
    def scalar(self, node: ast.expr) -> ir.Expr:
        (out,) = self.lower(node)
        return out

    def arith(self, op: ast.operator, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        if (isinstance(a, ir.Const) and isinstance(b, ir.Const) and a.type == b.type == ir.I64
                and isinstance(op, ast.Add | ast.Sub | ast.Mult)):  # FIRST + 1: integers, exact
            value = {ast.Add: a.value + b.value, ast.Sub: a.value - b.value, ast.Mult: a.value * b.value}[type(op)]
            if -(2**63) <= value < 2**63:
                return ir.Const(value, ir.I64)
        if isinstance(op, ast.Pow):
            return ir.Intrinsic("pow", (self.conv(a, ir.F64), self.conv(b, ir.F64)), ir.F64)
        if isinstance(op, ast.Div):
            return ir.Binary("/", self.conv(a, ir.F64), self.conv(b, ir.F64), ir.F64)
        t = ir.I64 if a.type == b.type == ir.I64 else ir.F64
        return ir.Binary(_IR_BINOPS[type(op)], self.conv(a, t), self.conv(b, t), t)

    def compare(self, op: ast.cmpop, a: ir.Expr, b: ir.Expr) -> ir.Expr:
        if a.type != b.type:
            a, b = self.conv(a, ir.F64), self.conv(b, ir.F64)
        text = _CMPOPS[type(op)]
        if isinstance(a, ir.Const) and isinstance(b, ir.Const):  # arr.shape[0] == 0: decided here
            return ir.Const(bool(_COMPARE[text](a.value, b.value)), ir.BOOL)
        if any(isinstance(x, ir.Const) and x.type == ir.F64 and math.isnan(x.value) for x in (a, b)):
            return ir.Const(text == "!=", ir.BOOL)  # a load from an empty array: NaN compares unequal to all
        return ir.Compare(text, a, b)

    def lazy_and(self, parts: list[tuple[list[ir.Stmt], ir.Expr]], op: str) -> ir.Expr:
        """``p0 op p1 op ...`` (op ``and``/``or``) of parts that may need statements: those of part k run only
        when Python would evaluate it."""
        # constants decided: x and False is False, x and True is x (expressions have no effects)
        absorbing, neutral = (False, True) if op == "and" else (True, False)
        if any(isinstance(x, ir.Const) and x.value is absorbing for _, x in parts):
            return ir.Const(absorbing, ir.BOOL)
        kept = [(pre, x) for pre, x in parts if not (isinstance(x, ir.Const) and x.value is neutral)]
        if not kept:
            return ir.Const(neutral, ir.BOOL)
        parts = kept
        first_pre, first = parts[0]
        self.block.extend(first_pre)
        if all(not pre for pre, _ in parts[1:]):
            return ir.Logic(op, tuple(x for _, x in parts)) if len(parts) > 1 else first
        tmp = self.temp(ir.BOOL)
        self.block.append(ir.Assign(tmp, first))
        var = ir.Var(tmp, ir.BOOL)
        go = var if op == "and" else ir.Not(var)
        chain: tuple[ir.Stmt, ...] = ()
        for pre, x in reversed(parts[1:]):
            chain = (*pre, ir.Assign(tmp, x), *((ir.If(go, chain),) if chain else ()))
        self.block.append(ir.If(go, chain))
        return var

    def lower(self, node: ast.expr) -> list[ir.Expr]:
        """The scalars of an expression's value (one for a number or a boolean), with any statements it
        needs appended to the current block."""
        t = self.type(node)
        if isinstance(node, ast.Constant):
            v = node.value
            it = _IR_TYPES[t]
            return [ir.Const(bool(v) if it == ir.BOOL else (int(v) if it == ir.I64 else float(v)), it)]
        if isinstance(node, ast.Name):
            if isinstance(t, FuncType):
                return []
            if isinstance(t, ArrayType):
                return [] if t.empty else [ir.Var(self.names[node.id][0], leaf_types(t)[0])]
            return [ir.Var(n, self.types[n]) for n in self.variable(node.id, self.spec.env[node.id])]
        if isinstance(node, ast.Attribute):  # an array's shape
            return [ir.Const(k, ir.I64) for k in self.type(node.value).shape]
        if isinstance(node, ast.Tuple):
            return [x for e in node.elts for x in self.lower(e)]
        if isinstance(node, ast.BinOp):
            return [self.arith(node.op, self.scalar(node.left), self.scalar(node.right))]
        if isinstance(node, ast.UnaryOp):
            x = self.scalar(node.operand)
            if isinstance(node.op, ast.Not):
                return [ir.Const(not x.value, ir.BOOL) if isinstance(x, ir.Const) else ir.Not(x)]
            if isinstance(node.op, ast.USub):
                if isinstance(x, ir.Const):
                    return [ir.Const(-x.value, x.type)]
                return [ir.Neg(x, x.type)]
            return [x]  # unary +
        if isinstance(node, ast.BoolOp):
            op = "and" if isinstance(node.op, ast.And) else "or"
            return [self.lazy_and([self.sub(lambda v=v: self.scalar(v)) for v in node.values], op)]
        if isinstance(node, ast.Compare):
            terms = [self.sub(lambda v=v: self.scalar(v)) for v in [node.left, *node.comparators]]
            self.block.extend(terms[0][0])
            self.block.extend(terms[1][0])
            parts = [([], self.compare(node.ops[0], terms[0][1], terms[1][1]))]
            for k, op in enumerate(node.ops[1:], start=1):
                parts.append((terms[k + 1][0], self.compare(op, terms[k][1], terms[k + 1][1])))
            return [self.lazy_and(parts, "and")]
        if isinstance(node, ast.IfExp):
            return self.ifexp(node, t)
        if isinstance(node, ast.Call):
            return self.call(node, t)
        if isinstance(node, ast.Subscript):
            return self.subscript(node)
        raise _refuse(self.fn, node, f"the expression {type(node).__name__}")  # typed, so unreachable

    def ifexp(self, node: ast.IfExp, t: Any) -> list[ir.Expr]:
        cond = self.scalar(node.test)
        types = leaf_types(t)
        pre_a, a = self.sub(lambda: self.lower(node.body))
        pre_b, b = self.sub(lambda: self.lower(node.orelse))
        a = [self.conv(x, lt) for x, lt in zip(a, types, strict=True)]
        b = [self.conv(x, lt) for x, lt in zip(b, types, strict=True)]
        if not pre_a and not pre_b:
            if len(types) > 1:
                cond = self.atomic(cond)
            return [ir.Select(cond, x, y, lt) for x, y, lt in zip(a, b, types, strict=True)]
        temps = [self.temp(lt) for lt in types]
        self.block.append(ir.If(cond, (*pre_a, *(ir.Assign(n, x) for n, x in zip(temps, a, strict=True))),
                                (*pre_b, *(ir.Assign(n, x) for n, x in zip(temps, b, strict=True)))))
        return [ir.Var(n, lt) for n, lt in zip(temps, types, strict=True)]

    def call(self, node: ast.Call, t: Any) -> list[ir.Expr]:
        f = node.func
        if isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name) and f.value.id == _NUMPY:
            return []  # an empty array
        if isinstance(f, ast.Attribute):  # math.X
            args = tuple(self.conv(self.scalar(a), ir.F64) for a in node.args)
            return [ir.Intrinsic(f.attr, args, _IR_TYPES[t])]
        if isinstance(f, ast.Name) and f.id in self.fn.builtins and f.id not in self.fn.locals:
            args = [self.scalar(a) for a in node.args]
            it = _IR_TYPES[t]
            if f.id in ("min", "max"):
                out = self.conv(args[0], it)
                for a in args[1:]:
                    out = ir.Intrinsic(f.id, (out, self.conv(a, it)), it)
                return [out]
            if f.id == "abs":
                return [ir.Intrinsic("abs", (args[0],), it)]
            return [self.conv(args[0], ir.F64)]  # float()
        spec, args = self.call_args(node)
        if not isinstance(spec.ret, TupleType):
            return [ir.Call(spec.name, tuple(args), _IR_TYPES[spec.ret])]
        types = leaf_types(spec.ret)
        temps = [self.temp(lt, "r") for lt in types]
        self.block.append(ir.CallMulti(tuple(temps), spec.name, tuple(args)))
        return [ir.Var(n, lt) for n, lt in zip(temps, types, strict=True)]

    def call_args(self, node: ast.Call) -> tuple[_Spec, list[ir.Expr]]:
        """The callee of a call of a jit function, and the scalars it is given (functions passed in left out)."""
        spec = self.spec.calls[id(node)]
        if self.tr.effects.get(spec.name):
            raise _refuse(self.fn, node, f"a call of {spec.fn.qualname}, which assigns array elements",
                          "only a function called from outside (an entry point) may")
        args = []
        for a, at in zip(self.spec.args[id(node)], spec.argtypes, strict=True):
            if not isinstance(at, FuncType):
                args += self.lower(a)
        return spec, args

    def subscript(self, node: ast.Subscript) -> list[ir.Expr]:
        t = self.type(node.value)
        idx = node.slice
        if isinstance(t, TupleType):
            n = len(t.elems)
            k = _const_int(idx)
            if k is not None and isinstance(node.value, ast.Tuple):  # an element of a tuple display
                return self.lower(node.value.elts[k % n])
            leaves = self.lower(node.value)
            sizes = [len(leaf_types(e)) for e in t.elems]
            starts = [sum(sizes[:j]) for j in range(n)]
            if k is not None:
                j = k % n
                return leaves[starts[j]:starts[j] + sizes[j]]
            i = self.atomic(self.scalar(idx))
            m = sizes[0]  # a variable index: the elements have one type
            out = []
            for pos in range(m):
                value = leaves[starts[n - 1] + pos]  # numba raises on an index out of range; here: the last
                for j in range(n - 2, -1, -1):
                    hit = ir.Logic("or", (ir.Compare("==", i, ir.Const(j, ir.I64)),
                                          ir.Compare("==", i, ir.Const(j - n, ir.I64))))
                    value = ir.Select(hit, leaves[starts[j] + pos], value, value.type)
                out.append(value)
            return out
        array, t = self.element(node)
        if array is None:  # an empty array holds nothing: a load from it never runs (numba would read past it)
            return [ir.Const(math.nan, ir.F64) if t.dtype == FLOAT else ir.Const(0, ir.I64)]
        return [ir.Load(array, tuple(self.indices(node, t)), _IR_TYPES[t.dtype])]

    def element(self, node: ast.Subscript) -> tuple[str | None, ArrayType]:
        """The IR name of a subscripted array (None for an empty one, which has no place in the output) and
        its type."""
        t = self.type(node.value)
        if t.empty:
            return None, t
        (var,) = self.lower(node.value)
        return var.name, t

    def indices(self, node: ast.Subscript, t: ArrayType) -> list[ir.Expr]:
        """A subscript's indices, each an integer in range: Python's negative ones wrapped."""
        idx = node.slice
        parts = idx.elts if isinstance(idx, ast.Tuple) else [idx]
        index = []
        for part, size in zip(parts, t.shape, strict=True):
            i = self.scalar(part)
            if isinstance(i, ir.Const):
                index.append(ir.Const(i.value % size, ir.I64))
            else:
                i = self.atomic(i)
                index.append(ir.Select(ir.Compare("<", i, ir.Const(0, ir.I64)),
                                       ir.Binary("+", i, ir.Const(size, ir.I64), ir.I64), i, ir.I64))
        return index


def _fold(body: Sequence[ir.Stmt]) -> tuple[ir.Stmt, ...]:
    """Statements with constant conditions decided (``if True:``, ``while False:``) and code after a return,
    break or continue dropped: what no language should be asked to print (C# warns of unreachable code)."""
    out: list[ir.Stmt] = []
    for s in body:
        if isinstance(s, ir.If):
            if isinstance(s.cond, ir.Const):
                out.extend(_fold(s.then if s.cond.value else s.orelse))
                if out and isinstance(out[-1], ir.Return | ir.TailCall | ir.Break | ir.Continue):
                    break
                continue
            s = ir.If(s.cond, _fold(s.then), _fold(s.orelse))
        elif isinstance(s, ir.While):
            if isinstance(s.cond, ir.Const) and not s.cond.value:
                continue
            s = ir.While(s.cond, _fold(s.body))
        elif isinstance(s, ir.For):
            s = ir.For(s.counter, s.limit, s.start, s.stop, s.step, _fold(s.body))
        out.append(s)
        if isinstance(s, ir.Return | ir.TailCall | ir.Break | ir.Continue):
            break
    return tuple(out)


# ------------------------------------------------------------------------------------------- translation
class Translation:
    """Python functions translated to one :class:`~bouncelab.export.ir.Program`.

    ``add(kernel, argtypes)`` types a jit function for its arguments' types (:func:`value_type` of the
    values it will be given, or the types themselves), translates it and everything it calls, and returns
    its IR function; call it for each entry point of one program (they share the functions they call).
    """

    def __init__(self) -> None:
        self.program = ir.Program()
        self._functions: dict[int, _Function] = {}
        self._specs: dict[tuple[int, tuple], _Spec] = {}
        self._active: set[tuple[int, tuple]] = set()
        self._names: set[str] = set()
        self._lowered: set[int] = set()
        #: Function name -> whether it assigns array elements (then only called from outside: an entry point).
        self.effects: dict[str, bool] = {}

    def add(self, dispatcher: Any, argtypes: Sequence[Any]) -> ir.Function:
        """Translate ``dispatcher`` (a jit function) for arguments of ``argtypes``; its IR function."""
        if not is_jit_function(dispatcher):
            raise ExportError(f"{dispatcher!r} is not a jit function (numba's njit, bouncelab's jit)",
                              construct="not a jit function")
        spec = self.specialize(self.function(dispatcher), tuple(argtypes))
        if spec.ret == NONE:
            raise _refuse(spec.fn, spec.fn.fdef, "an entry point that returns nothing", "end it with a return")
        self._lower(spec)
        if spec.name not in self.program.entries:
            self.program.entries.append(spec.name)
        return self.program.function(spec.name)

    def spec_of(self, dispatcher: Any, argtypes: Sequence[Any]) -> _Spec:
        return self._specs[(id(dispatcher.py_func), tuple(argtypes))]

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
            spec.name = self._unique("f_" + fn.func.__name__.lstrip("_"))
            self._specs[key] = spec
        return spec

    def _unique(self, name: str) -> str:
        if not name.isascii() or not name.replace("_", "a").isalnum():
            name = "f_function"
        out, k = name, 2
        while out in self._names:
            out, k = f"{name}_{k}", k + 1
        self._names.add(out)
        return out

    def _lower(self, spec: _Spec) -> None:
        if id(spec) in self._lowered:
            return
        self._lowered.add(id(spec))
        for callee in spec.calls.values():
            self._lower(callee)
        fn = _Lowerer(self, spec).function()
        self.effects[spec.name] = bool(ir.stores(fn))
        if spec.ret != NONE:  # a function returning nothing is never called (its calls do nothing, or are refused)
            self.program.functions.append(fn)


def _types_text(types: Sequence[Any]) -> str:
    return "(" + ", ".join(map(str, types)) + ")"
