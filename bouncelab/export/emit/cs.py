"""The C# emitter: private static methods of one static class, plain C# 7.3 or older.

What Unity, Godot and Mono compile: no tuples (C# 7's need System.ValueTuple), no newer syntax, only
``System.Math`` functions that .NET Framework 4 has. Integers are ``long``, booleans ``bool``. A method of
several results returns them through ``out`` parameters (``o_0, o_1...``), so no call allocates. ``**``
is ``h_pow``: C's pow correctly rounded, in double-double arithmetic, the JavaScript output's (the same
on every runtime, where ``Math.Pow`` is the platform's C library's or its own). Functions System.Math
lacks are written out (``h_hypot``, ``h_log1p``, ``h_expm1``, ``h_asinh``, ``h_acosh``, ``h_atanh``:
within a few units in the last place of the C library's; ``h_copysign`` exact). ``Math.Exp``,
``Math.Sin``... are the runtime's: Mono and .NET on Linux call the C library's, so the results are the
C output's there; other platforms' may differ in the last bit.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from decimal import Decimal

from bouncelab.export import ir
from bouncelab.export.emit.base import Emitter, hypot_scaling, pow_constants
from bouncelab.export.inline import inline, size

#: Methods up to this size (statements and expression nodes) ask the JIT to inline them.
SMALL = 100

__all__ = ["CSharpEmitter", "cs_literal"]

_INTRINSICS = {**{n: f"Math.{n.capitalize()}" for n in ("sqrt", "exp", "log", "log10", "sin", "cos", "tan", "asin",
                                                        "acos", "atan", "sinh", "cosh", "tanh")},
               "atan2": "Math.Atan2", "fabs": "Math.Abs", "abs": "Math.Abs", "isnan": "double.IsNaN",
               "isinf": "double.IsInfinity", "isfinite": "h_isfinite", "pow": "h_pow", "copysign": "h_copysign",
               "hypot": "h_hypot", "log1p": "h_log1p", "expm1": "h_expm1", "asinh": "h_asinh", "acosh": "h_acosh",
               "atanh": "h_atanh"}
_NEEDS = {"asinh": ("log1p", "copysign"), "acosh": ("log1p",), "atanh": ("log1p", "copysign")}

# Python's min(a, b) is b if b < a else a, its max(a, b) b if b > a else a: not Math.Min, which treats NaN
# and -0 otherwise.
_HELPERS = {
    "min_f": "private static double h_min_f(double a, double b) { return b < a ? b : a; }",
    "max_f": "private static double h_max_f(double a, double b) { return b > a ? b : a; }",
    "min_i": "private static long h_min_i(long a, long b) { return b < a ? b : a; }",
    "max_i": "private static long h_max_i(long a, long b) { return b > a ? b : a; }",
    "isfinite": "private static bool h_isfinite(double x) { return !double.IsNaN(x) && !double.IsInfinity(x); }",
    "copysign": """private static double h_copysign(double x, double y)
{
    long m = BitConverter.DoubleToInt64Bits(x) & long.MaxValue;
    return BitConverter.Int64BitsToDouble(m | (BitConverter.DoubleToInt64Bits(y) & long.MinValue));
}""",
    # sqrt(x^2 + y^2), scaled by an exact power of two where the squares would overflow or underflow
    "hypot": f"""private static double h_hypot(double x, double y)
{{
    x = Math.Abs(x);
    y = Math.Abs(y);
    if (double.IsInfinity(x) || double.IsInfinity(y)) return double.PositiveInfinity;
    if (double.IsNaN(x) || double.IsNaN(y)) return double.NaN;
    if (x < y) {{ double t = x; x = y; y = t; }}
    double s = 1.0;  // 2^-600 or 2^600: exact
{hypot_scaling("    ")}
    return Math.Sqrt(x * x + y * y) / s;
}}""",
    # Goldberg's log1p and Kahan's expm1: a few units in the last place
    "log1p": """private static double h_log1p(double x)
{
    if (double.IsPositiveInfinity(x)) return x;
    double u = 1.0 + x;
    if (u == 1.0) return x;
    return Math.Log(u) * (x / (u - 1.0));
}""",
    "expm1": """private static double h_expm1(double x)
{
    double u = Math.Exp(x);
    if (u == 1.0) return x;
    double um1 = u - 1.0;
    if (um1 == -1.0) return -1.0;
    if (double.IsPositiveInfinity(u)) return u;
    return um1 * (x / Math.Log(u));
}""",
    # fdlibm's reductions
    "asinh": """private static double h_asinh(double x)
{
    double a = Math.Abs(x);
    double r = a > 268435456.0 ? Math.Log(a) + 0.6931471805599453
        : h_log1p(a + a * a / (1.0 + Math.Sqrt(1.0 + a * a)));
    return double.IsNaN(x) ? x : h_copysign(r, x);
}""",
    "acosh": """private static double h_acosh(double x)
{
    if (!(x >= 1.0)) return double.NaN;
    if (x > 268435456.0) return Math.Log(x) + 0.6931471805599453;
    if (x > 2.0) return Math.Log(2.0 * x - 1.0 / (x + Math.Sqrt(x * x - 1.0)));
    double t = x - 1.0;
    return h_log1p(t + Math.Sqrt(2.0 * t + t * t));
}""",
    "atanh": """private static double h_atanh(double x)
{
    double a = Math.Abs(x);
    double r = a < 0.5 ? 0.5 * h_log1p(2.0 * a + 2.0 * a * a / (1.0 - a)) : 0.5 * h_log1p(2.0 * a / (1.0 - a));
    return double.IsNaN(x) ? x : h_copysign(r, x);
}""",
}


class CSharpEmitter(Emitter):
    """C# (7.3 or older; .NET Framework 4's System.Math). The methods are private members of the class the
    caller writes around :meth:`definitions`."""

    language = "C#"
    loop_decl = "long"

    def __init__(self, program: ir.Program) -> None:
        super().__init__(inline(program))  # Mono's JIT inlines little (nothing with out parameters)
        #: The namespaces the methods use (the file's using directives).
        self.usings = ["System"]

    def type_name(self, t: ir.Type) -> str:
        if isinstance(t, ir.ArrayType):
            return self.type_name(t.elem) + "[" + "," * (len(t.shape) - 1) + "]"
        return {ir.F64: "double", ir.I64: "long", ir.BOOL: "bool"}[t]

    def literal(self, value: object, t: str) -> str:
        return cs_literal(value, t)

    def cast(self, text: str) -> str:
        return f"((double){text})"

    def load(self, array: str, index: list[str], t: ir.ArrayType) -> str:
        return f"{array}[{', '.join(index)}]"

    def index(self, e: ir.Expr) -> str:
        return str(e.value) if isinstance(e, ir.Const) else self.expr(e)

    def intrinsic(self, name: str, args: list[str], operand: str, result: str) -> str:
        if name in ("min", "max"):
            kind = f"{name}_{'i' if result == ir.I64 else 'f'}"
            self.helpers.add(kind)
            return f"h_{kind}({', '.join(args)})"
        func = _INTRINSICS[name]
        if func.startswith("h_"):
            self.helpers.update((func[2:], *_NEEDS.get(func[2:], ())))
        return f"{func}({', '.join(args)})"

    def head(self, fn: ir.Function, params: list[str]) -> str:
        if fn.multi:
            params = [*params, *(f"out {self.type_name(t)} o_{k}" for k, t in enumerate(fn.returns))]
            ret = "void"
        else:
            ret = self.type_name(fn.returns[0])
        head = f"private static {ret} {self.function_name(fn.name)}({', '.join(params)}) {{"
        if size(fn.body) <= SMALL:  # Mono honours it (about 15 % on Rigid's Predict); .NET 4.5 and later have it
            if "System.Runtime.CompilerServices" not in self.usings:
                self.usings.append("System.Runtime.CompilerServices")
            head = f"[MethodImpl(MethodImplOptions.AggressiveInlining)]\n{head}"
        return head

    def prologue(self, fn: ir.Function, read: set[str]) -> list[str]:
        # an out argument must be a variable: the results a caller does not need go to one per type
        sinks = sorted({self.program.function(s.func).returns[k] for s in ir.walk(fn.body)
                        if isinstance(s, ir.CallMulti) for k, t in enumerate(s.targets) if t is None})
        return [self.declare(f"r_{t}", t) for t in sinks]

    def return_multi(self, fn: ir.Function, values: Sequence[ir.Expr]) -> list[str]:
        return [*(f"o_{k} = {self.expr(v)};" for k, v in enumerate(values)), "return;"]

    def tail_call(self, fn: ir.Function, s: ir.TailCall) -> list[str]:
        args = [*(self.expr(a) for a in s.args), *(f"out o_{k}" for k in range(len(fn.returns)))]
        return [f"{self.function_name(s.func)}({', '.join(args)});", "return;"]

    def call_multi(self, s: ir.CallMulti) -> list[str]:
        types = self.program.function(s.func).returns
        outs = [f"out {self.local(t) if t is not None else f'r_{types[k]}'}" for k, t in enumerate(s.targets)]
        return [f"{self.function_name(s.func)}({', '.join([*(self.expr(a) for a in s.args), *outs])});"]

    def helper_text(self, name: str) -> str:
        if name == "pow":
            return cs_pow()
        return _HELPERS[name]


def cs_literal(value: object, t: str | None = None) -> str:
    """A constant in C# that every C# compiler reads back to the same double.

    A float whose shortest round-trip repr is its exact decimal value (0.5, 3.5, 1024.0) is written so;
    any other with 17 significant digits. Measured with Mono's mcs 6.8: it read about 0.2 % of shortest
    reprs one unit in the last place off (two-digit ones among them), and none of 240 000 17-digit forms
    nor of 68 000 exact decimals (tests/test_export.py checks a sample). Integers are ``long``.
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral) and t != ir.F64:
        v = int(value)
        return f"(-{abs(v)}L)" if v < 0 else f"{v}L"
    v = float(value)  # type: ignore[arg-type]
    if math.isnan(v):
        return "double.NaN"
    if math.isinf(v):
        return "double.PositiveInfinity" if v > 0 else "double.NegativeInfinity"
    text = repr(abs(v))
    if Decimal(text) != Decimal(abs(v)):
        text = f"{abs(v):.17g}"
    if not any(ch in text for ch in ".e"):
        text += ".0"
    return f"(-{text})" if math.copysign(1.0, v) < 0 else text


def cs_pow() -> str:
    """``h_pow``: the JavaScript output's correctly rounded pow, in C# (no state: ``out`` parameters)."""
    ln2, atanh, fact = pow_constants()

    def arr(pairs: list[tuple[float, float]]) -> str:
        return "{ " + ", ".join(f"{cs_literal(h)}, {cs_literal(lo)}" for h, lo in pairs) + " }"

    return f"""// pow(x, y) correctly rounded (but for near-ties and |y ln x| > 700), in double-double arithmetic:
// the same results on every runtime (Math.Pow is the platform's), within the last bit of the C library's.
private const double h_LN2H = {cs_literal(ln2[0])}, h_LN2L = {cs_literal(ln2[1])};
private static readonly double[] h_ATANH = {arr(atanh)};
private static readonly double[] h_INVFACT = {arr(fact)};
private static void h_dd_add(double ah, double al, double bh, double bl, out double h, out double l)
{{
    double s = ah + bh, v = s - ah, e = (ah - (s - v)) + (bh - v);
    double t = al + bl, w = t - al, f = (al - (t - w)) + (bl - w);
    double g = e + t, hh = s + g, k = f + (g - (hh - s));
    h = hh + k;
    l = k - (h - hh);
}}
private static void h_dd_mul(double ah, double al, double bh, double bl, out double h, out double l)
{{
    double p = ah * bh;
    double ca = 134217729.0 * ah, ahh = ca - (ca - ah), alo = ah - ahh;
    double cb = 134217729.0 * bh, bhh = cb - (cb - bh), blo = bh - bhh;
    double e = ((ahh * bhh - p) + ahh * blo + alo * bhh) + alo * blo + (ah * bl + al * bh);
    h = p + e;
    l = e - (h - p);
}}
private static double h_pow(double x, double y)
{{
    if (!(x > 0.0) || double.IsPositiveInfinity(x) || double.IsNaN(y) || double.IsInfinity(y) || y == 0.0 || x == 1.0)
    {{
        if (x == 1.0 || y == 0.0) return 1.0;  // as C's pow, also for NaN
        if (x == -1.0 && double.IsInfinity(y)) return 1.0;
        return Math.Pow(x, y);  // C's other special values
    }}
    int e = 0;
    long bits = BitConverter.DoubleToInt64Bits(x < 2.2250738585072014e-308 ? x * 18014398509481984.0 : x);
    if (x < 2.2250738585072014e-308) e = -54;  // a subnormal x scaled by 2^54
    e += (int)((bits >> 52) & 0x7ff) - 1023;
    double m = BitConverter.Int64BitsToDouble((bits & 0x000fffffffffffffL) | 0x3ff0000000000000L);
    if (m > 1.4142135623730951) {{ m *= 0.5; e += 1; }}
    // ln m = 2 atanh(s), s = (m - 1) / (m + 1): a series in s^2 <= 0.0295
    double d = m + 1.0, dv = d - m, dl = (m - (d - dv)) + (1.0 - dv);
    double q1 = (m - 1.0) / d;
    double h, l;
    h_dd_mul(q1, 0.0, d, dl, out h, out l);
    h_dd_add(m - 1.0, 0.0, -h, -l, out h, out l);
    double q2 = h / d, sh = q1 + q2, sl = q2 - (sh - q1);
    h_dd_mul(sh, sl, sh, sl, out h, out l);
    double zh = h, zl = l;
    double ph = h_ATANH[42], pl = h_ATANH[43];
    for (int k = 40; k >= 0; k -= 2)
    {{
        h_dd_mul(ph, pl, zh, zl, out h, out l);
        h_dd_add(h, l, h_ATANH[k], h_ATANH[k + 1], out ph, out pl);
    }}
    h_dd_mul(ph, pl, sh, sl, out h, out l);
    double ah = 2.0 * h, al = 2.0 * l;
    h_dd_mul(e, 0.0, h_LN2H, h_LN2L, out h, out l);
    h_dd_add(h, l, ah, al, out h, out l);
    h_dd_mul(h, l, y, 0.0, out h, out l);  // t = y ln x
    double th = h, tl = l;
    if (!(Math.Abs(th) < 700.0)) return Math.Pow(x, y);
    // exp(t) = 2^k exp(r), |r| <= ln2 / 2, exp(r) = exp(r / 256)^256
    double kk = Math.Floor(th / h_LN2H + 0.5);
    h_dd_mul(kk, 0.0, h_LN2H, h_LN2L, out h, out l);
    h_dd_add(th, tl, -h, -l, out h, out l);
    double rh = h / 256.0, rl = l / 256.0;
    ph = h_INVFACT[20];
    pl = h_INVFACT[21];
    for (int j = 18; j >= 0; j -= 2)
    {{
        h_dd_mul(ph, pl, rh, rl, out h, out l);
        h_dd_add(h, l, h_INVFACT[j], h_INVFACT[j + 1], out ph, out pl);
    }}
    for (int i = 0; i < 8; i++) h_dd_mul(ph, pl, ph, pl, out ph, out pl);
    return ph * BitConverter.Int64BitsToDouble((long)(kk + 1023.0) << 52);
}}"""
