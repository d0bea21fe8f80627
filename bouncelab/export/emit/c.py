"""The C99 emitter (C++ compilers accept its output too).

Functions are ``static inline``; a function of several results returns a struct (``PREFIXtupleN``, made
by ``PREFIXtupleN_make``, since C++ has no compound literals). Integers are ``long long``, booleans
``int``. Every name the output defines at file scope starts with the prefix, so that several programs
fit in one translation unit. The math is ``<math.h>``'s: with the C library numba uses and without
contracted multiply-adds (``-ffp-contract=off``) the results are numba's to the bit.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

from bouncelab.export import ir
from bouncelab.export.emit.base import Emitter

__all__ = ["CEmitter"]

_INTRINSICS = {n: n for n in ("sqrt", "exp", "log", "log10", "log1p", "expm1", "sin", "cos", "tan", "asin", "acos",
                              "atan", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "atan2", "hypot", "pow",
                              "copysign", "fabs")}
# Python's min(a, b) is b if b < a else a, its max(a, b) b if b > a else a (numba's too): neither fmin nor
# fmax, which treat NaN and -0 otherwise.
_HELPERS = {
    "min_f": "static inline double $Ph_min_f(double a, double b) { return b < a ? b : a; }",
    "max_f": "static inline double $Ph_max_f(double a, double b) { return b > a ? b : a; }",
    "min_i": "static inline long long $Ph_min_i(long long a, long long b) { return b < a ? b : a; }",
    "max_i": "static inline long long $Ph_max_i(long long a, long long b) { return b > a ? b : a; }",
}


class CEmitter(Emitter):
    """C99. ``prefix`` starts every file-scope name."""

    language = "C"
    loop_decl = "long long"

    def __init__(self, program: ir.Program, prefix: str = "bouncelab_") -> None:
        super().__init__(program)
        self.prefix = prefix
        self.structs: dict[tuple[str, ...], str] = {}

    def function_name(self, name: str) -> str:
        return self.prefix + name

    def local_clashes(self, name: str) -> bool:
        return name.startswith(self.prefix)

    def struct(self, types: Sequence[str]) -> str:
        """The struct type of a function's results of these types (defined once)."""
        key = tuple(types)
        if key not in self.structs:
            self.structs[key] = f"{self.prefix}tuple{len(self.structs)}"
        return self.structs[key]

    def type_name(self, t: ir.Type) -> str:
        return {ir.F64: "double", ir.I64: "long long", ir.BOOL: "int"}[t]

    def param(self, name: str, t: ir.Type) -> str:
        if isinstance(t, ir.ArrayType):  # const unless the function stores into it
            written = self._fn is not None and name in {self.local(a) for a in ir.stores(self._fn)}
            return (f"{'' if written else 'const '}{self.type_name(t.elem)} {name}"
                    + "".join(f"[{s}]" for s in t.shape))
        return f"{self.type_name(t)} {name}"

    def literal(self, value: object, t: str) -> str:
        return c_literal(value, t)

    def cast(self, text: str) -> str:
        return f"((double){text})"

    def intrinsic(self, name: str, args: list[str], operand: str, result: str) -> str:
        if name in ("min", "max"):
            kind = f"{name}_{'i' if result == ir.I64 else 'f'}"
            self.helpers.add(kind)
            return f"{self.prefix}h_{kind}({', '.join(args)})"
        if name == "abs":
            return f"{'llabs' if operand == ir.I64 else 'fabs'}({args[0]})"
        if name in ("isnan", "isinf", "isfinite"):  # 0 or 1, as a boolean is (isinf may give -1)
            return f"({name}({args[0]}) != 0)"
        return f"{_INTRINSICS[name]}({', '.join(args)})"

    def head(self, fn: ir.Function, params: list[str]) -> str:
        ret = self.struct(fn.returns) if fn.multi else self.type_name(fn.returns[0])
        return f"static inline {ret} {self.function_name(fn.name)}({', '.join(params) or 'void'}) {{"

    def prologue(self, fn: ir.Function, read: set[str]) -> list[str]:
        return [f"(void){self.local(n)};" for n, _ in fn.params if n not in read]

    def return_multi(self, fn: ir.Function, values: Sequence[ir.Expr]) -> list[str]:
        return [f"return {self.struct(fn.returns)}_make({', '.join(self.expr(v) for v in values)});"]

    def tail_call(self, fn: ir.Function, s: ir.TailCall) -> list[str]:
        return [f"return {self.function_name(s.func)}({', '.join(self.expr(a) for a in s.args)});"]

    def call_multi(self, s: ir.CallMulti) -> list[str]:
        r = f"{self.prefix}r"
        types = self.program.function(s.func).returns
        args = ", ".join(self.expr(a) for a in s.args)
        lines = [f"{{ const {self.struct(types)} {r} = {self.function_name(s.func)}({args});"]
        lines += [f"  {self.local(t)} = {r}.v{k};" for k, t in enumerate(s.targets) if t is not None]
        return [*lines, "}"]

    def helper_text(self, name: str) -> str:
        return _HELPERS[name].replace("$P", self.prefix)

    def definitions(self) -> str:
        text = super().definitions()  # the structs are known once the functions are printed
        structs = []
        for types, name in self.structs.items():
            fields = "; ".join(f"{self.type_name(t)} v{k}" for k, t in enumerate(types))
            params = ", ".join(f"{self.type_name(t)} a{k}" for k, t in enumerate(types))
            sets = " ".join(f"t.v{k} = a{k};" for k in range(len(types)))
            structs.append(f"typedef struct {{ {fields}; }} {name};\n"
                           f"static inline {name} {name}_make({params}) {{ {name} t; {sets} return t; }}")
        return "\n\n".join([*structs, text])


def c_literal(value: object, t: str | None = None) -> str:
    """A constant in C (exact: a float by its shortest round-trip repr; negative ones parenthesised)."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, numbers.Integral) and t != ir.F64:
        v = int(value)
        text = str(abs(v)) + ("LL" if abs(v) > 2**31 - 1 else "")
        return f"(-{text})" if v < 0 else text
    v = float(value)  # type: ignore[arg-type]
    if math.isnan(v):
        return "NAN"
    if math.isinf(v):
        text = "INFINITY"
    else:
        text = repr(abs(v))
        if not any(ch in text for ch in ".e"):
            text += ".0"
    return f"(-{text})" if math.copysign(1.0, v) < 0 else text
