"""The intermediate form every exported language is printed from: typed scalar functions.

:mod:`bouncelab.export.frontend` turns a numba kernel (and everything it calls) into a
:class:`Program` of :class:`Function` s; one emitter per language
(:mod:`bouncelab.export.emit`) prints it. The form is small on purpose, so that an emitter is a
printer and never a translator:

* **Three scalar types** (:data:`F64`, :data:`I64`, :data:`BOOL`) and arrays of floats or integers
  of a fixed shape (:class:`ArrayType`, a parameter only). There are no tuples: the front end splits
  a tuple into its scalars (a tuple variable into one variable per element, a tuple parameter into
  one parameter per element), so a tuple exists only where a function returns several values.
* **Stores only at entry points.** A :class:`Store` writes into an array parameter; a function that
  stores is an entry point, called from outside the program and by none of its functions, so
  every function a translated expression calls has no effects.
* **Every conversion is written out.** An operation's operands have the type of its result
  (:class:`Cast` turns an integer into a float), comparisons compare values of one type, and a
  variable is assigned values of its own type. An emitter never promotes.
* **Expressions have no effects** (a call is of a function without effects), so an emitter may
  print them nested, in the order written, and C's unspecified order of evaluation of operands
  does not matter.
* **A function returning several values** (``Function.multi``) is called only by a
  :class:`CallMulti` statement, whose targets are distinct variables of exactly the callee's
  result types (or None for a value not needed): each language returns them its own way (C a
  struct, JavaScript a scratch ``Float64Array``, C# ``out`` parameters).
* **A function that returns what another returns** ends with a :class:`TailCall` (no copies).
* **Only live code.** Assignments whose value is never read are gone (:func:`prune`), and so are
  statements after a ``return``, ``break`` or ``continue``; conditions that are constants are folded.

Local names are valid identifiers in C, C++, JavaScript and C#, none a reserved word of any of
them, and none starts with one of :data:`EMITTER_PREFIXES`, the prefixes an emitter keeps for its
own names (functions ``f_``, helpers ``h_``, baked values ``p_``, results ``o_`` and ``r_``).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

__all__ = ["BOOL", "EMITTER_PREFIXES", "F64", "I64", "ArrayType", "Assign", "Binary", "Break", "Call", "CallMulti",
           "Cast", "Compare", "Const", "Continue", "Expr", "For", "Function", "If", "Intrinsic", "Load", "Logic",
           "Neg", "Not", "Program", "Return", "Select", "Stmt", "Store", "TailCall", "Var", "While", "calls", "dump",
           "prune", "reachable", "reads", "stores"]

# ------------------------------------------------------------------------------------------- types
F64, I64, BOOL = "f64", "i64", "bool"
#: The prefixes of the names an emitter makes; no local variable starts with one.
EMITTER_PREFIXES = ("f_", "h_", "p_", "o_", "r_")


@dataclass(frozen=True)
class ArrayType:
    """An array of a fixed shape (a function's parameter only), of :data:`F64` or :data:`I64` elements.

    Read-only unless the function stores into it (:class:`Store`, entry points only)."""

    shape: tuple[int, ...]
    elem: str = F64

    def __str__(self) -> str:
        return f"{self.elem}{list(self.shape)}"


Type = str | ArrayType

# ------------------------------------------------------------------------------------------- expressions
#: The intrinsic functions (Intrinsic.name): math's, Python's min, max and abs (min/max of two values with
#: Python's rule, ``b < a ? b : a``), of the types of their operands.
INTRINSICS = {
    **{n: 1 for n in ("sqrt", "exp", "log", "log10", "log1p", "expm1", "sin", "cos", "tan", "asin", "acos", "atan",
                      "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "fabs", "isnan", "isinf", "isfinite",
                      "abs")},
    **{n: 2 for n in ("atan2", "hypot", "pow", "copysign", "min", "max")},
}


@dataclass(frozen=True)
class Const:
    """A number or a boolean."""

    value: Any
    type: str


@dataclass(frozen=True)
class Var:
    """A variable or parameter (of an array type only as a :class:`Load`'s array)."""

    name: str
    type: Type


@dataclass(frozen=True)
class Cast:
    """An integer as a float (the only conversion there is)."""

    x: Expr
    type: str = F64


@dataclass(frozen=True)
class Binary:
    """``a op b`` for op in ``+ - * /``; a and b have the result's type (``/`` of floats only)."""

    op: str
    a: Expr
    b: Expr
    type: str


@dataclass(frozen=True)
class Neg:
    """``-x``."""

    x: Expr
    type: str


@dataclass(frozen=True)
class Not:
    """``not x`` of a boolean."""

    x: Expr
    type: str = BOOL


@dataclass(frozen=True)
class Compare:
    """``a op b`` for op in ``< <= > >= == !=``, a and b of one type (``== !=`` also of booleans)."""

    op: str
    a: Expr
    b: Expr
    type: str = BOOL


@dataclass(frozen=True)
class Logic:
    """``and`` / ``or`` of booleans, short-circuit, left to right."""

    op: str
    items: tuple[Expr, ...]
    type: str = BOOL


@dataclass(frozen=True)
class Select:
    """``a if cond else b`` (only the chosen one evaluated), a and b of the result's type."""

    cond: Expr
    a: Expr
    b: Expr
    type: str


@dataclass(frozen=True)
class Intrinsic:
    """A function of :data:`INTRINSICS` (operands of the result's type, but for isnan/isinf/isfinite)."""

    name: str
    args: tuple[Expr, ...]
    type: str


@dataclass(frozen=True)
class Call:
    """A call of a program's function that returns one value."""

    func: str
    args: tuple[Expr, ...]
    type: str


@dataclass(frozen=True)
class Load:
    """``array[i, j...]`` with each index an integer in range (wrapped from Python's negative ones), of the
    array's element type."""

    array: str
    index: tuple[Expr, ...]
    type: str = F64


Expr = Const | Var | Cast | Binary | Neg | Not | Compare | Logic | Select | Intrinsic | Call | Load


# ------------------------------------------------------------------------------------------- statements
@dataclass(frozen=True)
class Assign:
    target: str
    value: Expr


@dataclass(frozen=True)
class CallMulti:
    """``targets = func(args)`` for a function of several results; a None target drops that value."""

    targets: tuple[str | None, ...]
    func: str
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class Store:
    """``array[i, j...] = value`` into an array parameter (indices as :class:`Load`'s; value of the array's
    element type). Only an entry point stores (see the module)."""

    array: str
    index: tuple[Expr, ...]
    value: Expr


@dataclass(frozen=True)
class If:
    cond: Expr
    then: tuple[Stmt, ...]
    orelse: tuple[Stmt, ...] = ()


@dataclass(frozen=True)
class While:
    cond: Expr
    body: tuple[Stmt, ...]


@dataclass(frozen=True)
class For:
    """``for _ in range(start, stop, step)``: the integer ``counter`` runs from start while it is below (above,
    for a negative step) ``limit``, which takes the value of ``stop`` once. Both are declared by the loop
    (they are not locals); Python's loop variable is assigned ``counter`` by the body's first statement.
    ``step`` is a non-zero integer constant."""

    counter: str
    limit: str
    start: Expr
    stop: Expr
    step: int
    body: tuple[Stmt, ...]


@dataclass(frozen=True)
class Break:
    pass


@dataclass(frozen=True)
class Continue:
    pass


@dataclass(frozen=True)
class Return:
    """The function's value (one), or its values (``Function.multi``)."""

    values: tuple[Expr, ...]


@dataclass(frozen=True)
class TailCall:
    """``return func(args)`` in a function of several results: func's results, of exactly its types."""

    func: str
    args: tuple[Expr, ...]


Stmt = Assign | Store | CallMulti | If | While | For | Break | Continue | Return | TailCall


# ------------------------------------------------------------------------------------------- functions
@dataclass
class Function:
    """One function: parameters and locals typed, its result type(s), its body.

    ``multi``: it returns ``len(returns)`` values (called by :class:`CallMulti` only); else it returns
    ``returns[0]`` (called by :class:`Call`). ``source``: the Python function it comes from.
    """

    name: str
    params: tuple[tuple[str, Type], ...]
    locals: dict[str, str]
    returns: tuple[str, ...]
    multi: bool
    body: tuple[Stmt, ...]
    source: str = ""


@dataclass
class Program:
    """Functions in an order where every callee comes before its callers; ``entries`` the ones called
    from outside (by name)."""

    functions: list[Function] = field(default_factory=list)
    entries: list[str] = field(default_factory=list)

    def function(self, name: str) -> Function:
        return next(f for f in self.functions if f.name == name)

    def max_results(self) -> int:
        return max((len(f.returns) for f in self.functions if f.multi), default=0)


# ------------------------------------------------------------------------------------------- walking
def children(e: Expr) -> tuple[Expr, ...]:
    if isinstance(e, Cast | Neg | Not):
        return (e.x,)
    if isinstance(e, Binary | Compare):
        return (e.a, e.b)
    if isinstance(e, Logic):
        return e.items
    if isinstance(e, Select):
        return (e.cond, e.a, e.b)
    if isinstance(e, Intrinsic | Call):
        return e.args
    if isinstance(e, Load):
        return e.index
    return ()


def subexprs(e: Expr) -> Iterator[Expr]:
    """``e`` and every expression inside it."""
    yield e
    for c in children(e):
        yield from subexprs(c)


def stmt_exprs(s: Stmt) -> tuple[Expr, ...]:
    """The expressions a statement evaluates itself (not those of the statements inside it)."""
    if isinstance(s, Assign):
        return (s.value,)
    if isinstance(s, Store):
        return (*s.index, s.value)
    if isinstance(s, CallMulti | TailCall):
        return s.args
    if isinstance(s, If | While):
        return (s.cond,)
    if isinstance(s, For):
        return (s.start, s.stop)
    if isinstance(s, Return):
        return s.values
    return ()


def walk(body: Sequence[Stmt]) -> Iterator[Stmt]:
    """Every statement, nested ones too, in order."""
    for s in body:
        yield s
        if isinstance(s, If):
            yield from walk(s.then)
            yield from walk(s.orelse)
        elif isinstance(s, While | For):
            yield from walk(s.body)


def walk_exprs(body: Sequence[Stmt]) -> Iterator[Expr]:
    for s in walk(body):
        for e in stmt_exprs(s):
            yield from subexprs(e)


def reads(e: Expr) -> set[str]:
    """The variables an expression reads (array names of loads included)."""
    out = set()
    for x in subexprs(e):
        if isinstance(x, Var):
            out.add(x.name)
        elif isinstance(x, Load):
            out.add(x.array)
    return out


def calls(e: Expr) -> bool:
    """Whether an expression calls a program's function."""
    return any(isinstance(x, Call) for x in subexprs(e))


def stores(fn: Function) -> set[str]:
    """The arrays a function stores into (empty for a function without effects)."""
    return {s.array for s in walk(fn.body) if isinstance(s, Store)}


def reachable(program: Program) -> Program:
    """``program`` without the functions no entry point calls (directly or through others)."""
    by_name = {f.name: f for f in program.functions}
    reached: set[str] = set()

    def reach(name: str) -> None:
        if name in reached:
            return
        reached.add(name)
        body = by_name[name].body
        for s in walk(body):
            if isinstance(s, CallMulti | TailCall):
                reach(s.func)
        for e in walk_exprs(body):
            if isinstance(e, Call):
                reach(e.func)

    for entry in program.entries:
        reach(entry)
    return Program([f for f in program.functions if f.name in reached], list(program.entries))


# ------------------------------------------------------------------------------------------- pruning
def prune(fn: Function) -> Function:
    """``fn`` with only live code: assignments (and multi-calls) whose values are never read dropped, to a
    fixed point (a variable only read to compute itself is dead too); the locals left are those assigned
    and read. Expressions have no effects, so dropping an unread one changes nothing."""
    live: set[str] = set()

    def visit(body: Sequence[Stmt]) -> set[str]:
        found: set[str] = set()
        for s in body:
            if isinstance(s, Assign):
                if s.target in live:
                    found |= reads(s.value)
            elif isinstance(s, CallMulti):
                if any(t in live for t in s.targets if t):
                    found |= set().union(*map(reads, s.args)) if s.args else set()
            elif isinstance(s, Store):  # an effect: always live
                for v in stmt_exprs(s):
                    found |= reads(v)
            elif isinstance(s, If):
                found |= reads(s.cond) | visit(s.then) | visit(s.orelse)
            elif isinstance(s, While):
                found |= reads(s.cond) | visit(s.body)
            elif isinstance(s, For):
                found |= reads(s.start) | reads(s.stop) | visit(s.body)
            elif isinstance(s, Return | TailCall):
                for v in stmt_exprs(s):
                    found |= reads(v)
        return found

    while True:
        new = visit(fn.body)
        if new <= live:
            break
        live |= new

    def keep(body: Sequence[Stmt]) -> tuple[Stmt, ...]:
        out: list[Stmt] = []
        for s in body:
            if isinstance(s, Assign):
                if s.target in live:
                    out.append(s)
            elif isinstance(s, CallMulti):
                targets = tuple(t if t in live else None for t in s.targets)
                if any(targets):
                    out.append(replace(s, targets=targets))
            elif isinstance(s, If):
                then, orelse = keep(s.then), keep(s.orelse)
                if then or orelse:
                    out.append(If(s.cond, then, orelse))
            elif isinstance(s, While):
                out.append(While(s.cond, keep(s.body)))
            elif isinstance(s, For):
                out.append(replace(s, body=keep(s.body)))
            else:
                out.append(s)
        return tuple(out)

    body = keep(fn.body)
    if body != fn.body:  # an `if` left empty is gone: what only its condition read may be dead now
        return prune(replace(fn, body=body))
    assigned = set()
    for s in walk(body):
        if isinstance(s, Assign):
            assigned.add(s.target)
        elif isinstance(s, CallMulti):
            assigned.update(t for t in s.targets if t)
    params = {p for p, _ in fn.params}
    local_types = {n: t for n, t in fn.locals.items() if n in assigned and n not in params}
    return replace(fn, body=body, locals=local_types)


# ------------------------------------------------------------------------------------------- dumping
def dump_expr(e: Expr) -> str:
    """A readable one-line form of an expression (for tests and debugging)."""
    if isinstance(e, Const):
        return repr(e.value)
    if isinstance(e, Var):
        return e.name
    if isinstance(e, Cast):
        return f"f64({dump_expr(e.x)})"
    if isinstance(e, Neg):
        return f"(-{dump_expr(e.x)})"
    if isinstance(e, Not):
        return f"(not {dump_expr(e.x)})"
    if isinstance(e, Binary | Compare):
        return f"({dump_expr(e.a)} {e.op} {dump_expr(e.b)})"
    if isinstance(e, Logic):
        return "(" + f" {e.op} ".join(map(dump_expr, e.items)) + ")"
    if isinstance(e, Select):
        return f"({dump_expr(e.a)} if {dump_expr(e.cond)} else {dump_expr(e.b)})"
    if isinstance(e, Intrinsic | Call):
        name = e.name if isinstance(e, Intrinsic) else e.func
        return f"{name}({', '.join(map(dump_expr, e.args))})"
    if isinstance(e, Load):
        return f"{e.array}[{', '.join(map(dump_expr, e.index))}]"
    raise TypeError(e)


def dump(program: Program | Function) -> str:
    """The program (or one function) as indented text, one statement a line."""
    fns = program.functions if isinstance(program, Program) else [program]
    lines: list[str] = []

    def block(body: Sequence[Stmt], depth: int) -> None:
        pad = "    " * depth
        for s in body:
            if isinstance(s, Assign):
                lines.append(f"{pad}{s.target} = {dump_expr(s.value)}")
            elif isinstance(s, Store):
                lines.append(f"{pad}{s.array}[{', '.join(map(dump_expr, s.index))}] = {dump_expr(s.value)}")
            elif isinstance(s, CallMulti):
                targets = ", ".join(t or "_" for t in s.targets)
                lines.append(f"{pad}{targets} = {s.func}({', '.join(map(dump_expr, s.args))})")
            elif isinstance(s, If):
                lines.append(f"{pad}if {dump_expr(s.cond)}:")
                block(s.then, depth + 1)
                if s.orelse:
                    lines.append(f"{pad}else:")
                    block(s.orelse, depth + 1)
            elif isinstance(s, While):
                lines.append(f"{pad}while {dump_expr(s.cond)}:")
                block(s.body, depth + 1)
            elif isinstance(s, For):
                lines.append(f"{pad}for {s.counter} in range({dump_expr(s.start)}, {dump_expr(s.stop)}, {s.step}):")
                block(s.body, depth + 1)
            elif isinstance(s, Return):
                lines.append(f"{pad}return {', '.join(map(dump_expr, s.values))}")
            elif isinstance(s, TailCall):
                lines.append(f"{pad}return {s.func}({', '.join(map(dump_expr, s.args))})")
            else:
                lines.append(f"{pad}{type(s).__name__.lower()}")

    for fn in fns:
        params = ", ".join(f"{n}: {t}" for n, t in fn.params)
        ret = ", ".join(fn.returns)
        lines.append(f"def {fn.name}({params}) -> {'(' + ret + ')' if fn.multi else ret}:")
        if fn.locals:
            lines.append("    # locals: " + ", ".join(f"{n}: {t}" for n, t in fn.locals.items()))
        block(fn.body, 1)
    return "\n".join(lines)
