"""The JavaScript emitter (an ES module's functions).

Every generated name starts with ``$`` (a Python name cannot), so the module's own names are free.
Numbers are IEEE doubles, integers among them (exact below 2^53), booleans ``true``/``false``. A
function's numbers go in through the module's scratch ``$A`` and its results come out through ``$R``
(``Float64Array`` s), never as arguments or return values, so that no call allocates (see
:class:`JSEmitter`). The math is ``Math``'s, but ``**`` is
``$pow``: C's pow correctly rounded, in double-double arithmetic (Node's ``Math.pow`` differs from the
C library's pow in the last bit for about 8 % of arguments, enough for TurfContact's event location to
amplify); ``Math.exp``, ``Math.sin``... may differ from the C library's in the last bit. ``math.hypot`` is
the C# output's ``h_hypot`` (``Math.hypot`` allocates its arguments in V8).
"""

from __future__ import annotations

import functools
import math
import numbers
from collections.abc import Sequence
from typing import ClassVar

from bouncelab.export import ir
from bouncelab.export.emit.base import Emitter, hypot_scaling, pow_constants, strip_parens
from bouncelab.export.inline import inline, size

__all__ = ["JSEmitter", "js_literal", "js_pow"]

_INTRINSICS = {**{n: f"Math.{n}" for n in ("sqrt", "exp", "log", "log10", "log1p", "expm1", "sin", "cos", "tan",
                                           "asin", "acos", "atan", "sinh", "cosh", "tanh", "asinh", "acosh",
                                           "atanh", "atan2")},
               "fabs": "Math.abs", "abs": "Math.abs", "isnan": "Number.isNaN", "isfinite": "Number.isFinite",
               "pow": "$pow", "copysign": "$copysign", "isinf": "$isinf", "min": "$min", "max": "$max",
               "hypot": "$hypot"}
# Python's min(a, b) is b if b < a else a, its max(a, b) b if b > a else a: not Math.min, which treats NaN
# and -0 otherwise.
_HELPERS = {
    "min": "function $min(a, b) { return b < a ? b : a; }",
    "max": "function $max(a, b) { return b > a ? b : a; }",
    "copysign": "function $copysign() {\n  const ax = Math.abs($D[0]), y = $D[1];\n"
                "  $D[0] = (y < 0 || (y === 0 && 1 / y < 0)) ? -ax : ax;\n}",
    "isinf": "function $isinf(x) { return x === Infinity || x === -Infinity; }",
    # Math.hypot is variadic: V8 allocates its arguments. The C# output's hypot (the same operations, the same bits)
    "hypot": f"""function $hypot() {{
  let x = Math.abs($D[0]), y = Math.abs($D[1]);
  if (x === Infinity || y === Infinity) {{ $D[0] = Infinity; return; }}
  if (Number.isNaN(x) || Number.isNaN(y)) {{ $D[0] = NaN; return; }}
  if (x < y) {{ const t = x; x = y; y = t; }}
  let s = 1.0;  // 2^-600 or 2^600: exact
{hypot_scaling("  ")}
  $D[0] = Math.sqrt(x * x + y * y) / s;
}}""",
    "scratch": "// The numbers of pow, hypot and copysign: ($D[0] = x, $D[1] = y, $pow(), $D[0]).\n"
               "const $D = new Float64Array(4);",
}
#: Helpers of two numbers that take them from $D and leave their result in $D[0] (not as arguments: V8 boxes a
#: double given to a function it does not inline, and it does not inline these in a large kernel).
_SCRATCH = frozenset({"pow", "hypot", "copysign"})


#: Entry points up to this size (statements and expression nodes) take their numbers as arguments.
DIRECT = 100


def _numeric(t: ir.Type) -> bool:
    return t in (ir.F64, ir.I64)


class JSEmitter(Emitter):
    """JavaScript (ES2015 and later).

    Numbers cross a call in the module's scratch arrays, never as arguments or return values: a caller
    writes a function's numeric arguments into ``$A`` (booleans and arrays are passed as arguments) and
    reads its numeric results from ``$R``. V8 passes arguments and results as tagged values, so a double
    given to or returned by a function it does not inline is boxed on the heap; through the typed arrays
    nothing is allocated. A callee copies ``$A`` into its locals first thing; a caller that computes an
    argument by another call does so before it writes any.
    """

    language = "JavaScript"
    loop_decl = "let"
    equality: ClassVar[dict[str, str]] = {"==": "===", "!=": "!=="}

    def __init__(self, program: ir.Program) -> None:
        super().__init__(inline(program))
        # A small entry point takes its numbers as arguments: V8 inlines it into its caller (the module's
        # predict loop), where they are not boxed, and the scratch's stores and loads would cost more. (Larger
        # ones, which V8 may leave out of line, take them through $A: tests/test_export.py checks that
        # predictOne allocates nothing for every built-in law.)
        self.direct = {f.name for f in self.program.functions
                       if f.name in self.program.entries and size(f.body) <= DIRECT}

    def numeric(self, fn: ir.Function) -> list[tuple[int, str]]:
        """The parameters (position, name) a function takes through $A."""
        if fn.name in self.direct:
            return []
        return [(k, n) for k, (n, t) in enumerate(fn.params) if _numeric(t)]

    def function_name(self, name: str) -> str:
        return "$" + name

    def type_name(self, t: ir.Type) -> str:
        return "let"

    def param(self, name: str, t: ir.Type) -> str:
        return name

    def declare(self, name: str, t: str) -> str:
        return f"let {name} = {self.literal(False if t == ir.BOOL else 0, t)};"

    def literal(self, value: object, t: str) -> str:
        return js_literal(value, t)

    def cast(self, text: str) -> str:
        return text  # integers are doubles already

    def intrinsic(self, name: str, args: list[str], operand: str, result: str) -> str:
        func = _INTRINSICS[name]
        if func.startswith("$"):
            self.helpers.add(func[1:])
        return f"{func}({', '.join(args)})"

    def head(self, fn: ir.Function, params: list[str]) -> str:
        through = {k for k, _ in self.numeric(fn)}
        passed = [self.local(n) for k, (n, _) in enumerate(fn.params) if k not in through]
        return f"function {self.function_name(fn.name)}({', '.join(passed)}) {{"

    def prologue(self, fn: ir.Function, read: set[str]) -> list[str]:
        numeric = self.numeric(fn)
        if numeric:
            self.helpers.add("arguments")
        return [f"let {self.local(n)} = $A[{j}];" for j, (_, n) in enumerate(numeric)]

    def invoke(self, func: str, args: Sequence[ir.Expr]) -> list[str]:
        """The steps of a call, to run in order: the numeric arguments into $A (those that call a function
        first, into temporaries), then the call with the others."""
        callee = self.program.function(func)
        params = callee.params
        texts = [self.expr(a) for a in args]
        steps = []
        numeric = [k for k, _ in self.numeric(callee)]
        for k, a in enumerate(args):
            if ir.calls(a):  # a call writes $A and $R itself: before this call writes any
                tmp = self.temp(a.type)
                steps.append(f"{tmp} = {strip_parens(texts[k])}")
                texts[k] = tmp
        if numeric:
            self.helpers.add("arguments")
        steps += [f"$A[{j}] = {strip_parens(texts[k])}" for j, k in enumerate(numeric)]
        passed = [texts[k] for k in range(len(params)) if k not in numeric]
        steps.append(f"{self.function_name(func)}({', '.join(passed)})")
        return steps

    def expr(self, e: ir.Expr) -> str:
        if isinstance(e, ir.Intrinsic) and e.name in _SCRATCH:  # through $D
            self.helpers.update((e.name, "scratch"))
            steps = []
            texts = []
            for a in e.args:
                text = strip_parens(self.expr(a))
                if any(isinstance(x, ir.Call) or (isinstance(x, ir.Intrinsic) and x.name in _SCRATCH)
                       for x in ir.subexprs(a)):  # it writes $D itself (or may): before this one writes it
                    tmp = self.temp(a.type)
                    steps.append(f"{tmp} = {text}")
                    text = tmp
                texts.append(text)
            call = f"${e.name}()"
            return f"({', '.join([*steps, f'$D[0] = {texts[0]}', f'$D[1] = {texts[1]}', call, '$D[0]'])})"
        return super().expr(e)

    def call(self, e: ir.Call) -> str:
        steps = self.invoke(e.func, e.args)
        if _numeric(e.type):  # its value is in $R[0]
            self.helpers.add("results")
            steps.append("$R[0]")
        return steps[0] if len(steps) == 1 else f"({', '.join(steps)})"

    def entry_call(self, func: str, args: Sequence[str]) -> list[str]:
        """Statements that call ``func`` with arguments given as text (the entry points' calls)."""
        numeric = [k for k, _ in self.numeric(self.program.function(func))]
        self.helpers.add("results")
        if numeric:
            self.helpers.add("arguments")
        steps = [f"$A[{j}] = {args[k]};" for j, k in enumerate(numeric)]
        passed = [a for k, a in enumerate(args) if k not in numeric]
        return [*steps, f"{self.function_name(func)}({', '.join(passed)});"]

    def stmt(self, s: ir.Stmt, depth: int) -> list[str]:
        fn = self._fn
        if isinstance(s, ir.Return) and fn is not None and not fn.multi and _numeric(fn.returns[0]):
            self.helpers.add("results")
            pad = self.indent * depth
            return [f"{pad}$R[0] = {strip_parens(self.expr(s.values[0]))};", f"{pad}return;"]
        return super().stmt(s, depth)

    def return_multi(self, fn: ir.Function, values: Sequence[ir.Expr]) -> list[str]:
        self.helpers.add("results")
        lines, texts = [], []
        for v in values:  # a call uses $R itself: values that call a function are taken before any is written
            text = strip_parens(self.expr(v))
            if ir.calls(v):
                tmp = self.temp(v.type)
                lines.append(f"{tmp} = {text};")
                text = tmp
            texts.append(text)
        lines += [f"$R[{k}] = {f'({text} ? 1 : 0)' if v.type == ir.BOOL else text};"
                  for k, (v, text) in enumerate(zip(values, texts, strict=True))]
        return [*lines, "return;"]

    def temp(self, t: str) -> str:
        name = f"r_{len(self.extra) + 1}"
        self.extra[name] = t
        return name

    def tail_call(self, fn: ir.Function, s: ir.TailCall) -> list[str]:
        return [f"{step};" for step in self.invoke(s.func, s.args)] + ["return;"]  # its results are in $R already

    def call_multi(self, s: ir.CallMulti) -> list[str]:
        self.helpers.add("results")
        types = self.program.function(s.func).returns
        lines = [f"{step};" for step in self.invoke(s.func, s.args)]
        lines += [f"{self.local(t)} = {f'$R[{k}] !== 0' if types[k] == ir.BOOL else f'$R[{k}]'};"
                  for k, t in enumerate(s.targets) if t is not None]
        return lines

    def helper_text(self, name: str) -> str:
        if name == "pow":
            return js_pow()
        if name == "results":
            return ("// The numbers a function returns, copied out by its caller at once.\n"
                    f"const $R = new Float64Array({max(self.program.max_results(), 1)});")
        if name == "arguments":
            count = max((len(self.numeric(f)) for f in self.program.functions), default=1)
            return ("// The numbers a function is given, copied in by it at once.\n"
                    f"const $A = new Float64Array({max(count, 1)});")
        return _HELPERS[name]


def js_literal(value: object, t: str | None = None) -> str:
    """A constant in JavaScript (exact: a float by its shortest round-trip repr)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral) and t != ir.F64:
        v = int(value)
        return f"(-{abs(v)})" if v < 0 else str(v)
    v = float(value)  # type: ignore[arg-type]
    if math.isnan(v):
        return "NaN"
    text = "Infinity" if math.isinf(v) else repr(abs(v))
    return f"(-{text})" if math.copysign(1.0, v) < 0 else text


@functools.cache
def js_pow() -> str:
    """JavaScript's ``$pow``: C's pow correctly rounded, in double-double arithmetic (constants exact from Python).

    Its numbers pass through the scratch ``$D`` (x and y in, the result out; the double-double helpers'
    operands and results too), as the translated functions' pass through ``$A`` and ``$R``: nothing is
    allocated."""
    ln2, atanh, fact = pow_constants()

    def arr(pairs: list[tuple[float, float]]) -> str:
        return "new Float64Array([" + ", ".join(f"{h!r}, {lo!r}" for h, lo in pairs) + "])"

    def dd(op: str, ah: str, al: str, bh: str, bl: str) -> str:  # (ah, al) op (bh, bl) into $D[0], $D[1]
        return f"$D[2] = {bh}; $D[3] = {bl}; $D[0] = {ah}; $D[1] = {al}; ${op}();"  # b may read $D[0], $D[1]

    return f"""// pow(x, y) correctly rounded (but for near-ties and |y ln x| > 700), in double-double arithmetic.
// Node's Math.pow differs from the C library's pow in the last bit for about 8 % of arguments; this one only
// where the C library's pow is not correctly rounded itself (about 0.1 % of arguments). Called as
// ($D[0] = x, $D[1] = y, $pow(), $D[0]).
const $LN2H = {ln2[0]!r}, $LN2L = {ln2[1]!r};
const $ATANH = {arr(atanh)};
const $INVFACT = {arr(fact)};
const $F64 = new Float64Array(1), $U32 = new Uint32Array($F64.buffer);
const $HI = new Uint8Array(new Uint16Array([1]).buffer)[0] === 1 ? 1 : 0;
function $add() {{
  const ah = $D[0], al = $D[1], bh = $D[2], bl = $D[3];
  const s = ah + bh, v = s - ah, e = (ah - (s - v)) + (bh - v);
  const t = al + bl, w = t - al, f = (al - (t - w)) + (bl - w);
  const g = e + t, h = s + g, k = f + (g - (h - s));
  const hi = h + k;
  $D[0] = hi;
  $D[1] = k - (hi - h);
}}
function $mul() {{
  const ah = $D[0], al = $D[1], bh = $D[2], bl = $D[3];
  const p = ah * bh;
  const ca = 134217729 * ah, ahh = ca - (ca - ah), alo = ah - ahh;
  const cb = 134217729 * bh, bhh = cb - (cb - bh), blo = bh - bhh;
  const e = ((ahh * bhh - p) + ahh * blo + alo * bhh) + alo * blo + (ah * bl + al * bh);
  const hi = p + e;
  $D[0] = hi;
  $D[1] = e - (hi - p);
}}
function $pow() {{
  const x = $D[0], y = $D[1];
  if (!(x > 0) || x === Infinity || !Number.isFinite(y) || y === 0 || x === 1) {{
    if (x === 1 || y === 0) $D[0] = 1;  // as C's pow, also for NaN
    else if (x === -1 && (y === Infinity || y === -Infinity)) $D[0] = 1;
    else $D[0] = Math.pow(x, y);  // C's other special values
    return;
  }}
  let e = 0;
  $F64[0] = x < 2.2250738585072014e-308 ? x * 18014398509481984 : x;  // a subnormal x scaled by 2^54
  if (x < 2.2250738585072014e-308) e = -54;
  const top = $U32[$HI];
  e += ((top >>> 20) & 0x7ff) - 1023;
  $U32[$HI] = (top & 0x000fffff) | 0x3ff00000;
  let m = $F64[0];
  if (m > 1.4142135623730951) {{ m *= 0.5; e += 1; }}
  // ln m = 2 atanh(s), s = (m - 1) / (m + 1): a series in s^2 <= 0.0295
  const d = m + 1, dv = d - m, dl = (m - (d - dv)) + (1 - dv);
  const q1 = (m - 1) / d;
  {dd("mul", "q1", "0", "d", "dl")}
  {dd("add", "m - 1", "0", "-$D[0]", "-$D[1]")}
  const q2 = $D[0] / d, sh = q1 + q2, sl = q2 - (sh - q1);
  {dd("mul", "sh", "sl", "sh", "sl")}
  const zh = $D[0], zl = $D[1];
  let ph = $ATANH[42], pl = $ATANH[43];
  for (let k = 40; k >= 0; k -= 2) {{
    {dd("mul", "ph", "pl", "zh", "zl")}
    $D[2] = $ATANH[k]; $D[3] = $ATANH[k + 1]; $add();
    ph = $D[0];
    pl = $D[1];
  }}
  {dd("mul", "ph", "pl", "sh", "sl")}
  const ah = 2 * $D[0], al = 2 * $D[1];
  {dd("mul", "e", "0", "$LN2H", "$LN2L")}
  $D[2] = ah; $D[3] = al; $add();
  $D[2] = y; $D[3] = 0; $mul();  // t = y ln x
  const th = $D[0], tl = $D[1];
  if (!(Math.abs(th) < 700)) {{ $D[0] = Math.pow(x, y); return; }}
  // exp(t) = 2^k exp(r), |r| <= ln2 / 2, exp(r) = exp(r / 256)^256
  const k = Math.round(th / $LN2H);
  {dd("mul", "k", "0", "$LN2H", "$LN2L")}
  {dd("add", "th", "tl", "-$D[0]", "-$D[1]")}
  const rh = $D[0] / 256, rl = $D[1] / 256;
  ph = $INVFACT[20]; pl = $INVFACT[21];
  for (let j = 18; j >= 0; j -= 2) {{
    {dd("mul", "ph", "pl", "rh", "rl")}
    $D[2] = $INVFACT[j]; $D[3] = $INVFACT[j + 1]; $add();
    ph = $D[0];
    pl = $D[1];
  }}
  for (let i = 0; i < 8; i++) {{ {dd("mul", "ph", "pl", "ph", "pl")} ph = $D[0]; pl = $D[1]; }}
  $U32[$HI] = (k + 1023) << 20;
  $U32[1 - $HI] = 0;
  $D[0] = ph * $F64[0];
}}"""
