"""Inlining on the intermediate form: calls of small functions replaced by their bodies.

Engines without an inliner as thorough as a C compiler's gain from it: V8 passes a double to a function
it does not inline boxed on the heap, and Mono's JIT inlines little. :func:`inline` rewrites a
:class:`~bouncelab.export.ir.Program` so that each call of a function small enough (at most ``limit``
expression nodes and statements, its own calls inlined first) and with its returns in tail position
(none inside a loop, after lifting ``if c: return a`` into ``if c: ... else: ...``) becomes the
function's statements, its parameters and locals renamed apart, its returns assignments to the call's
targets. A call inside an expression is taken out before the statement when the expression evaluates it
in every case (not in a branch of ``a if c else b``, nor after the first operand of ``and``/``or``, nor
in a ``while`` condition); expressions have no effects, so this changes nothing. The arithmetic is the
same operations in the same order: the numbers do not change.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import fields, replace

from bouncelab.export import ir

__all__ = ["inline", "size"]

#: Functions up to this size (expression nodes and statements) are inlined by default.
LIMIT = 200


def size(body: Sequence[ir.Stmt]) -> int:
    """Statements and expression nodes of a body."""
    return sum(1 for _ in ir.walk(body)) + sum(1 for _ in ir.walk_exprs(body))


def map_expr(e: ir.Expr, f: Callable[[ir.Expr], ir.Expr | None]) -> ir.Expr:
    """``e`` with every subexpression x replaced by ``f(x)`` when that is not None (else rebuilt from its
    children, mapped)."""
    out = f(e)
    if out is not None:
        return out
    changes = {}
    for fld in fields(e):
        value = getattr(e, fld.name)
        if isinstance(value, tuple) and value and not isinstance(value[0], str | int | float | bool):
            changes[fld.name] = tuple(map_expr(x, f) for x in value)
        elif fld.name in ("x", "a", "b", "cond"):
            changes[fld.name] = map_expr(value, f)
    return replace(e, **changes) if changes else e


def _map_stmt(s: ir.Stmt, f: Callable[[ir.Expr], ir.Expr], name: Callable[[str], str]) -> ir.Stmt:
    """A statement (and those inside it) with its expressions mapped by f and the names it assigns by name."""
    if isinstance(s, ir.Assign):
        return ir.Assign(name(s.target), f(s.value))
    if isinstance(s, ir.Store):
        return ir.Store(name(s.array), tuple(map(f, s.index)), f(s.value))
    if isinstance(s, ir.CallMulti):
        return ir.CallMulti(tuple(None if t is None else name(t) for t in s.targets), s.func, tuple(map(f, s.args)))
    if isinstance(s, ir.TailCall):
        return ir.TailCall(s.func, tuple(map(f, s.args)))
    if isinstance(s, ir.If):
        return ir.If(f(s.cond), tuple(_map_stmt(x, f, name) for x in s.then),
                     tuple(_map_stmt(x, f, name) for x in s.orelse))
    if isinstance(s, ir.While):
        return ir.While(f(s.cond), tuple(_map_stmt(x, f, name) for x in s.body))
    if isinstance(s, ir.For):
        return ir.For(name(s.counter), name(s.limit), f(s.start), f(s.stop), s.step,
                      tuple(_map_stmt(x, f, name) for x in s.body))
    if isinstance(s, ir.Return):
        return ir.Return(tuple(map(f, s.values)))
    return s


# ------------------------------------------------------------------------------------------- tail returns
def _returns(body: Sequence[ir.Stmt]) -> bool:
    return any(isinstance(s, ir.Return | ir.TailCall) for s in ir.walk(body))


def _ends(body: Sequence[ir.Stmt]) -> bool:
    """Whether every path through the body ends with a return."""
    if not body:
        return False
    last = body[-1]
    if isinstance(last, ir.Return | ir.TailCall):
        return True
    return isinstance(last, ir.If) and _ends(last.then) and _ends(last.orelse)


def tails(body: Sequence[ir.Stmt]) -> tuple[ir.Stmt, ...] | None:
    """The body with every return in tail position (what follows an ``if`` one branch of which returns moved
    into the other), or None if a return is inside a loop."""
    out: list[ir.Stmt] = []
    for k, s in enumerate(body):
        if isinstance(s, ir.Return | ir.TailCall):
            out.append(s)
            return tuple(out)
        if isinstance(s, ir.While | ir.For):
            if _returns(s.body):
                return None
            out.append(s)
        elif isinstance(s, ir.If) and (_returns(s.then) or _returns(s.orelse)):
            rest = list(body[k + 1:])
            then = tails([*s.then, *([] if _ends(s.then) else rest)])
            orelse = tails([*s.orelse, *([] if _ends(s.orelse) else rest)])
            if then is None or orelse is None:
                return None
            out.append(ir.If(s.cond, then, orelse))
            return tuple(out)
        else:
            out.append(s)
    return tuple(out)


# ------------------------------------------------------------------------------------------- inlining
class _Inliner:
    """Inlines into one function the calls of the functions in ``small`` (already inlined themselves)."""

    def __init__(self, fn: ir.Function, small: dict[str, tuple[ir.Function, tuple[ir.Stmt, ...]]]) -> None:
        self.fn = fn
        self.small = small
        self.locals = dict(fn.locals)
        self.taken = {n for n, _ in fn.params} | set(fn.locals) | {
            n for s in ir.walk(fn.body) if isinstance(s, ir.For) for n in (s.counter, s.limit)}

    def fresh(self, base: str) -> str:
        for k in itertools.count(1):
            name = f"{base}_{k}"
            if name.startswith(ir.EMITTER_PREFIXES):  # r_1 from r: an emitter's
                name = "v" + name
            if name not in self.taken:
                self.taken.add(name)
                return name
        raise AssertionError

    def run(self) -> ir.Function:
        return replace(self.fn, body=self.block(self.fn.body), locals=self.locals)

    def block(self, body: Sequence[ir.Stmt]) -> tuple[ir.Stmt, ...]:
        out: list[ir.Stmt] = []
        for s in body:
            out += self.stmt(s)
        return tuple(out)

    def stmt(self, s: ir.Stmt) -> list[ir.Stmt]:
        pre: list[ir.Stmt] = []  # filled by hoist: the statement is built first, then put after them
        if isinstance(s, ir.CallMulti) and s.func in self.small:
            args = [self.hoist(a, pre) for a in s.args]
            return pre + self.body_of(s.func, args, list(s.targets))
        if isinstance(s, ir.TailCall) and s.func in self.small:
            args = [self.hoist(a, pre) for a in s.args]
            return pre + self.body_of(s.func, args, None)
        new: ir.Stmt
        if isinstance(s, ir.Assign):
            new = ir.Assign(s.target, self.hoist(s.value, pre))
        elif isinstance(s, ir.Store):
            new = ir.Store(s.array, tuple(self.hoist(i, pre) for i in s.index), self.hoist(s.value, pre))
        elif isinstance(s, ir.CallMulti):
            new = ir.CallMulti(s.targets, s.func, tuple(self.hoist(a, pre) for a in s.args))
        elif isinstance(s, ir.TailCall):
            new = ir.TailCall(s.func, tuple(self.hoist(a, pre) for a in s.args))
        elif isinstance(s, ir.Return):
            new = ir.Return(tuple(self.hoist(v, pre) for v in s.values))
        elif isinstance(s, ir.If):
            new = ir.If(self.hoist(s.cond, pre), self.block(s.then), self.block(s.orelse))
        elif isinstance(s, ir.While):  # its condition is evaluated on every pass: its calls stay
            new = ir.While(s.cond, self.block(s.body))
        elif isinstance(s, ir.For):
            start, stop = self.hoist(s.start, pre), self.hoist(s.stop, pre)
            new = ir.For(s.counter, s.limit, start, stop, s.step, self.block(s.body))
        else:
            new = s
        return [*pre, new]

    def hoist(self, e: ir.Expr, pre: list[ir.Stmt]) -> ir.Expr:
        """``e`` with the calls it always evaluates of small functions inlined into ``pre`` (results in
        temporaries)."""
        if isinstance(e, ir.Call):
            args = [self.hoist(a, pre) for a in e.args]
            if e.func not in self.small:
                return ir.Call(e.func, tuple(args), e.type)
            tmp = self.fresh("v")
            self.locals[tmp] = e.type
            pre += self.body_of(e.func, args, [tmp])
            return ir.Var(tmp, e.type)
        if isinstance(e, ir.Select):
            return ir.Select(self.hoist(e.cond, pre), e.a, e.b, e.type)
        if isinstance(e, ir.Logic):
            return ir.Logic(e.op, (self.hoist(e.items[0], pre), *e.items[1:]))
        return map_expr(e, lambda x: None if x is e else self.hoist(x, pre))

    def body_of(self, func: str, args: Sequence[ir.Expr], targets: list[str | None] | None) -> list[ir.Stmt]:
        """The statements of ``func(args)``: results into ``targets`` (None: returned by this function)."""
        callee, body = self.small[func]
        names: dict[str, str] = {}
        out: list[ir.Stmt] = []
        arrays: dict[str, str] = {}
        for (p, t), a in zip(callee.params, args, strict=True):
            if isinstance(t, ir.ArrayType):
                assert isinstance(a, ir.Var)
                arrays[p] = a.name
                continue
            names[p] = self.fresh(p)
            self.locals[names[p]] = t
            out.append(ir.Assign(names[p], a))
        for n, t in callee.locals.items():
            names[n] = self.fresh(n)
            self.locals[names[n]] = t
        for s in ir.walk(body):
            if isinstance(s, ir.For):
                names[s.counter], names[s.limit] = self.fresh(s.counter), self.fresh(s.limit)
        names.update(arrays)

        def rename(x: ir.Expr) -> ir.Expr | None:
            if isinstance(x, ir.Var):
                return ir.Var(names[x.name], x.type)
            if isinstance(x, ir.Load):
                return ir.Load(names[x.array], tuple(map_expr(i, rename) for i in x.index), x.type)
            return None

        renamed = [_map_stmt(s, lambda x: map_expr(x, rename), names.__getitem__) for s in body]
        return out + (renamed if targets is None else self.results(renamed, targets))

    def results(self, body: Sequence[ir.Stmt], targets: list[str | None]) -> list[ir.Stmt]:
        """A body whose tail returns become assignments to targets."""
        out: list[ir.Stmt] = []
        for s in body:
            if isinstance(s, ir.Return):
                out += [ir.Assign(t, v) for t, v in zip(targets, s.values, strict=True) if t is not None]
            elif isinstance(s, ir.TailCall):
                out.append(ir.CallMulti(tuple(targets), s.func, s.args))
            elif isinstance(s, ir.If):
                out.append(ir.If(s.cond, tuple(self.results(s.then, targets)), tuple(self.results(s.orelse, targets))))
            else:
                out.append(s)
        return out


def inline(program: ir.Program, limit: int = LIMIT) -> ir.Program:
    """A copy of ``program`` with the calls of its small functions inlined (see the module); the functions
    no entry reaches any more are left out."""
    small: dict[str, tuple[ir.Function, tuple[ir.Stmt, ...]]] = {}
    done: dict[str, ir.Function] = {}
    for fn in program.functions:  # callees come first
        new = ir.prune(_Inliner(fn, small).run())
        done[fn.name] = new
        body = tails(new.body)
        if body is not None and size(body) <= limit and new.name not in program.entries:
            small[fn.name] = (new, body)
    return ir.reachable(ir.Program([done[f.name] for f in program.functions], list(program.entries)))
