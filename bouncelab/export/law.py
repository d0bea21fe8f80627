"""A law as a C99 header or an ES module: its kernel translated, its values baked in, its terms in the comment.

:func:`export_law` (and ``law.to_c()`` / ``law.to_js()``, ``bouncelab export``) writes one self-contained
file per law. The comment at its top says what the law is (its class, parameters, options and the
constants derived from them), the conventions and units of its states, where it holds (the landings it
was fitted on, when the law records them, and bouncelab's unit guard, both in scaled units) and how to
compile it so that it computes what bouncelab computes. The code below it is the law's numba kernel,
translated by :mod:`bouncelab.export.translate`.

This module reads a law through its public protocol only (its kernel, ``_kernel_args``, parameter
declarations and provenance); it imports nothing from :mod:`bouncelab.laws`, so the laws can call it.
"""

from __future__ import annotations

import hashlib
import inspect
import math
import re
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.core.units import BALL_RADIUS_M, CONVENTIONS
from bouncelab.export.translate import (
    FLOAT,
    INT,
    ArrayType,
    ExportError,
    Program,
    TupleType,
    is_jit_function,
    value_type,
)

__all__ = ["DEFAULT_PREFIX", "LANGUAGES", "c_header", "export_law", "js_module"]

#: The languages :func:`export_law` writes: C99 (a header; C++ compilers accept it) and JavaScript (an ES module).
LANGUAGES = ("c", "js")
#: The prefix of every name an exported C header defines, unless told another.
DEFAULT_PREFIX = "bouncelab_"

_PREFIX = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_RPM = 2.0 * math.pi / 60.0


def export_law(law: Any, lang: str, path: str | Path | None = None, *, prefix: str = DEFAULT_PREFIX) -> str:
    """The law as C99 (``lang="c"``) or JavaScript (``"js"``) source; also written to ``path`` if given.

    Parameters
    ----------
    law
        A law with values whose maths is a compiled kernel (every built-in law; a user's
        :class:`~bouncelab.laws.CompiledLaw` whose kernel keeps to the translator's subset).
    lang
        ``"c"`` or ``"js"``.
    path
        File to write (atomically), or None.
    prefix
        C only: the prefix of every name the header defines (default ``"bouncelab_"``: the entry point is
        ``bouncelab_predict``). Give each law of one program its own.

    Returns
    -------
    str
        The source text.

    Raises
    ------
    ParameterError
        An unknown ``lang``, or a ``prefix`` that is not a C identifier (or given for JavaScript).
    NotFittedError
        The law has no value for some parameter.
    ExportError
        The law has no compiled kernel, or the kernel uses a construct the translator does not know
        (a :class:`~bouncelab.core.errors.LawDefinitionError` naming the function, line and construct).
    OutputError
        ``path`` cannot be written; nothing is written then.
    """
    if lang not in LANGUAGES:
        raise ParameterError(f"cannot export to {lang!r}: the languages are {', '.join(map(repr, LANGUAGES))}",
                             parameter="lang", value=lang)
    if lang == "js" and prefix != DEFAULT_PREFIX:
        raise ParameterError("prefix is for C headers: an ES module's names are its own (import it under any name)",
                             parameter="prefix", value=prefix)
    text = c_header(law, prefix=prefix) if lang == "c" else js_module(law)
    if path is not None:
        from bouncelab.core.atomic import write_output

        write_output(path, text, "the exported law")
    return text


def c_header(law: Any, prefix: str = DEFAULT_PREFIX) -> str:
    """The law as a self-contained C99 header (see :func:`export_law`)."""
    if not isinstance(prefix, str) or not _PREFIX.match(prefix):
        raise ParameterError(f"prefix must be a C identifier such as 'bouncelab_' or 'turf_a_'; got {prefix!r}",
                             parameter="prefix", value=prefix)
    k = _Kernel(law, "c", prefix)
    p = prefix
    consts = []
    for name, value, t in k.args:
        if isinstance(t, ArrayType):
            consts.append(f"static const double {p}p_{name}{''.join(f'[{s}]' for s in t.shape)} = "
                          f"{_nested(value, k.program, '{', '}')};")
        else:
            ctype = {FLOAT: "double", INT: "long long"}.get(t, "int")
            consts.append(f"static const {ctype} {p}p_{name} = {k.program.literal(value, t)};")
    call = f"{k.spec.name}(xd, yd, w{''.join(f', {p}p_{name}' for name, _, _ in k.args)})"
    regimes = [f"{p}regime_{r} = {code}" for code, r in enumerate(k.regimes)
               if _PREFIX.match(r) and r != "count" and k.regimes.index(r) == code]
    names = "\n".join(f"    case {code}: return \"{_c_string(r)}\";" for code, r in enumerate(k.regimes))
    body = f"""#include <math.h>
#include <stdlib.h>

#ifndef BOUNCELAB_API  /* define it as nothing before including to give the entry points external linkage */
#define BOUNCELAB_API static inline
#endif

/* The regime codes that {p}predict_one and {p}regime give (the law's regimes, in order). */
enum {{ {', '.join([*regimes, f'{p}regime_count = {len(k.regimes)}'])} }};

/* The law's values, baked in (parameters, options and the constants derived from them). */
{chr(10).join(consts) or '/* (none) */'}

/* ---- the law's kernel, translated from its Python source (bouncelab.export.translate) ---- */

{k.program.definitions()}

/* ---- entry points ---- */

/* One bounce: the lift-off [xdot, ydot, omega] of landing (xd, yd, w) into out; returns the regime code. */
BOUNCELAB_API int {p}predict_one(double xd, double yd, double w, double out[3]) {{
    {k.program.ctype(k.spec.ret)} t = {call};
    out[0] = t.v0;
    out[1] = t.v1;
    out[2] = t.v2;
    return (int)t.v3;
}}

/* n bounces: landing and liftoff are row-major n x 3 arrays [xdot, ydot, omega] (they may be the same array). */
BOUNCELAB_API void {p}predict(const double *landing, double *liftoff, long n) {{
    for (long i = 0; i < n; i++) {{
        const double *in = landing + 3 * (size_t)i;
        {p}predict_one(in[0], in[1], in[2], liftoff + 3 * (size_t)i);
    }}
}}

/* The regime codes of n landings (row-major n x 3) into regime[0..n-1]. */
BOUNCELAB_API void {p}regime(const double *landing, int *regime, long n) {{
    double out[3];
    for (long i = 0; i < n; i++) {{
        const double *in = landing + 3 * (size_t)i;
        regime[i] = {p}predict_one(in[0], in[1], in[2], out);
    }}
}}

/* The name of a regime code ("?" for a code the law does not have). */
static inline const char *{p}regime_name(int code) {{
    switch (code) {{
{names}
    default: return "?";
    }}
}}
"""
    guard = f"{p.upper().strip('_')}_LAW_H_{hashlib.sha256(body.encode()).hexdigest()[:12].upper()}"
    comment = _comment(k, "c", prefix)
    # The guard names the content: the same file included twice is read once, while two different laws
    # exported with the same prefix collide loudly (redefinitions) instead of one silently hiding the other.
    return f"{comment}\n#ifndef {guard}\n#define {guard}\n\n{body}\n#endif /* {guard} */\n"


def js_module(law: Any) -> str:
    """The law as a self-contained ES module (see :func:`export_law`)."""
    k = _Kernel(law, "js", "$")
    consts = [f"const $p_{name} = "
              f"{_nested(value, k.program, '[', ']') if isinstance(t, ArrayType) else k.program.literal(value, t)};"
              for name, value, t in k.args]
    args = "".join(f", $p_{name}" for name, _, _ in k.args)
    params = ", ".join(f"{_js_string(name)}: {_js_value(value, k.program)}" for name, value in k.parameters)
    regimes = ", ".join(_js_string(r) for r in k.regimes)
    body = f"""/* The law's values, baked in (parameters, options and the constants derived from them). */
{chr(10).join(consts) or '/* (none) */'}

/* ---- the law's kernel, translated from its Python source (bouncelab.export.translate) ---- */

{k.program.definitions()}

/* ---- entry points ---- */

/** The law's name and parameter values (scaled units), and its regimes (index = regime code). */
export const LAW = {_js_string(k.law_name)};
export const PARAMETERS = Object.freeze({{{params}}});
export const REGIMES = Object.freeze([{regimes}]);

/** One bounce: [xdotF, ydotF, omegaF, regimeCode] of the landing (xdot, ydot, omega). */
export function predictOne(xdot, ydot, omega) {{
  const t = {k.spec.name}(xdot, ydot, omega{args});
  return [t[0], t[1], t[2], t[3]];
}}

/** Lift-offs [[xdotF, ydotF, omegaF], ...] of landings [[xdot, ydot, omega], ...]. */
export function predict(landings) {{
  const out = new Array(landings.length);
  for (let i = 0; i < landings.length; i++) {{
    const p = landings[i];
    if (p.length !== 3) throw new RangeError(`landing ${{i}} has ${{p.length}} values, not 3 (xdot, ydot, omega)`);
    const t = {k.spec.name}(p[0], p[1], p[2]{args});
    out[i] = [t[0], t[1], t[2]];
  }}
  return out;
}}

/** The regime codes of landings [[xdot, ydot, omega], ...] (names: REGIMES[code]). */
export function regime(landings) {{
  const out = new Array(landings.length);
  for (let i = 0; i < landings.length; i++) {{
    const p = landings[i];
    if (p.length !== 3) throw new RangeError(`landing ${{i}} has ${{p.length}} values, not 3 (xdot, ydot, omega)`);
    out[i] = {k.spec.name}(p[0], p[1], p[2]{args})[3];
  }}
  return out;
}}
"""
    return f"{_comment(k, 'js', None)}\n{body}"


# ------------------------------------------------------------------------------------------- the kernel
class _Kernel:
    """A law's kernel, its arguments and its translation."""

    def __init__(self, law: Any, lang: str, prefix: str) -> None:
        self.law = law
        self.law_name = type(law).__name__
        kernel = getattr(law, "kernel", None)
        if not is_jit_function(kernel):
            raise ExportError(f"{self.law_name} has no compiled kernel: only a law whose maths is a numba kernel "
                              "(every built-in law, a CompiledLaw of your own) can be exported; a law written with "
                              "NumPy in _predict cannot be translated", law=self.law_name)
        self.kernel = kernel
        values = law._fitted_values()  # NotFittedError naming what is missing
        self.parameters = [(name, values[name]) for name in values]
        args = tuple(law._kernel_args(**values))
        names = list(inspect.signature(kernel.py_func).parameters)
        if len(names) != 3 + len(args):
            raise ExportError(f"{self.law_name}'s kernel takes {len(names)} arguments, but the landing and "
                              f"_kernel_args give {3 + len(args)}", law=self.law_name)
        self.args = []
        for name, value in zip(names[3:], args, strict=True):
            if value is None:
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is None; give the law a value "
                                  "for it", law=self.law_name)
            try:
                t = value_type(value)
            except TypeError as exc:
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is {exc}, which the "
                                  "exported code cannot hold", law=self.law_name) from None
            if isinstance(t, TupleType):
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is a tuple; only numbers and "
                                  "float arrays can be baked in", law=self.law_name)
            if isinstance(value, np.ndarray):
                value = np.asarray(value, dtype=np.float64)
            self.args.append((name, value, t))
        self.program = Program(lang, prefix)
        try:
            self.spec = self.program.entry(kernel, (FLOAT, FLOAT, FLOAT, *(t for _, _, t in self.args)))
        except ExportError as exc:
            exc.law = self.law_name
            raise
        ret = self.spec.ret
        if not (isinstance(ret, TupleType) and len(ret.elems) == 4 and all(e in (FLOAT, INT) for e in ret.elems[:3])
                and ret.elems[3] == INT):
            raise ExportError(f"{self.law_name}'s kernel returns {ret}, not (xdotF, ydotF, omegaF, regime code)",
                              law=self.law_name)
        self.regimes = [str(r) for r in getattr(law, "regimes", ())]


# ------------------------------------------------------------------------------------------- the comment
def _comment(k: _Kernel, lang: str, prefix: str | None) -> str:
    from bouncelab.core import __version__

    law = k.law
    func = k.kernel.py_func
    lines: list[str] = []

    def para(text: str = "", indent: str = "") -> None:
        if not text:
            lines.append("")
            return
        lines.extend(textwrap.wrap(text, 100, initial_indent=indent, subsequent_indent=indent + "  ",
                                   break_on_hyphens=False, break_long_words=False))

    what = "a C99 header" if lang == "c" else "an ES module"
    para(f"{k.law_name} bounce law, exported as {what} by bouncelab {__version__} (bouncelab.export).")
    para(f"Law: {law!r}")
    para(f"The code is the law's compiled kernel, {func.__module__}.{func.__qualname__}, translated operation by "
         "operation from its Python source (bouncelab.export.translate); the values below are baked in.")
    para()
    para("CONVENTIONS")
    para(f"{CONVENTIONS}.", "  ")
    para("Units: a landing and a lift-off are rows [xdot, ydot, omega]: xdot and ydot in ball radii per second "
         "(radius/s), omega in rad/s. From physical units: v[radius/s] = v[m/s] / R with R the ball's radius in "
         f"metres (bouncelab's default R = {BALL_RADIUS_M} m), omega[rad/s] = rpm * 2 pi / 60.", "  ")
    para()
    para("PARAMETERS (scaled units)")
    specs = {s.name: s for s in getattr(type(law), "parameter_specs", ())}
    for name, value in k.parameters:
        spec = specs.get(name)
        unit = f" [{spec.unit}]" if spec is not None and getattr(spec, "unit", None) else ""
        doc = f": {spec.doc}" if spec is not None and getattr(spec, "doc", None) else ""
        para(f"{name} = {_text_value(value)}{unit}{doc}", "  ")
    options = dict(getattr(law, "options", {}) or {})
    for name, value in options.items():
        para(f"option {name} = {value!r}", "  ")
    derived = [(n, v) for n, v, _ in k.args if n not in dict(k.parameters)]
    if derived:
        para("Kernel arguments baked in besides the parameters (options and constants derived from them): "
             + ", ".join(f"{n} = {_text_value(v)}" for n, v in derived), "  ")
    para("Regime codes: " + ", ".join(f"{c} {r}" for c, r in enumerate(k.regimes)), "  ")
    para()
    para("VALIDITY DOMAIN")
    prov = getattr(law, "provenance", None)
    if prov is not None:
        note = prov.synthetic_note()  # it says what the law was fitted to, too
        para(f"NOTE: {note}." if note else f"Fitted to {prov.summary()}.", "  ")
        d = prov.to_dict()
        ranges, units = d.get("landing_ranges") or {}, d.get("landing_range_units") or {}
        if ranges:
            para("The landings it was fitted on (scaled units):", "  ")
            for name, (lo, hi) in ranges.items():
                para(f"{name} from {lo:.6g} to {hi:.6g} {units.get(name, '')}".rstrip(), "    ")
        else:
            para("The law file records no ranges of the landings it was fitted on.", "  ")
    else:
        para("The law carries no record of the landings it was fitted on (published values, or values given by "
             "hand): only the unit guard's limits below bound it.", "  ")
    g = PLAUSIBLE_RANGES
    r = BALL_RADIUS_M
    para(f"bouncelab's unit guard (bouncelab.core.plausibility.PLAUSIBLE_RANGES) for a ball of radius {r * 1000:g} mm: "
         f"ydot0 < 0; landing speed sqrt(xdot0^2 + ydot0^2) from {g.min_landing_speed / r:.6g} to "
         f"{g.max_speed / r:.6g} radius/s ({g.min_landing_speed:g} to {g.max_speed:g} m/s); |omega0| up to "
         f"{g.max_spin * _RPM:.6g} rad/s ({g.max_spin:g} rpm); angle of incidence atan(-ydot0 / |xdot0|) at least "
         f"{g.min_landing_angle:g} degrees.", "  ")
    para("Outside these the law extrapolates. bouncelab refuses landings outside the unit guard (unless told "
         "plausible=None) and warns outside the fitted ranges when asked (warn_outside_fitted=True); this code checks "
         "nothing: give it finite landings with ydot0 < 0.", "  ")
    para()
    para("FLOATING POINT")
    if lang == "c":
        para("Compile with -ffp-contract=off and without -ffast-math (e.g. cc -std=c99 -O2 -ffp-contract=off "
             "main.c -lm): the results are then within 1e-12 (relative to the landing's norm) of bouncelab's "
             "law.predict, as bouncelab's tests check on 10^5 landings covering every regime. Contracted "
             "multiply-adds (-ffp-contract=fast, GCC's default, with FMA instructions such as -march=native "
             "enables) change the last bits, and -ffast-math more.", "  ")
    else:
        para("JavaScript numbers are IEEE doubles and engines do not fuse operations, so the arithmetic is "
             "bouncelab's; Math.exp, Math.sin, Math.cos... may differ from the C library's in the last bit. ** is "
             "$pow below, correctly rounded (Node 20's Math.pow differs from the C library's pow for about 8 % of "
             "arguments, which TurfContact's stick/slip events amplified up to 1e-6 for rare landings). "
             "bouncelab's tests check the results under Node against law.predict to 1e-12 (relative to the "
             "landing's norm) on 10^5 landings covering every regime.", "  ")
    para("Where numba raises (a division by zero), the code follows IEEE arithmetic (inf or NaN).", "  ")
    para()
    para("ENTRY POINTS")
    if lang == "c":
        p = prefix
        para(f"int {p}predict_one(double xdot, double ydot, double omega, double out[3]): one bounce, the lift-off "
             "into out, returns the regime code.", "  ")
        para(f"void {p}predict(const double *landing, double *liftoff, long n): n landings, row-major (three "
             "values a row).", "  ")
        para(f"void {p}regime(const double *landing, int *regime, long n): their regime codes; "
             f"{p}regime_name(code) names one.", "  ")
        para(f"Every name this header defines starts with {p!r}: export each law of one program with its own "
             "prefix (bouncelab export --prefix NAME, law.to_c(prefix=NAME)). C99; C++ compilers accept it too. "
             "The entry points are static inline unless BOUNCELAB_API is defined (e.g. as nothing) first.", "  ")
    else:
        para("predictOne(xdot, ydot, omega) -> [xdotF, ydotF, omegaF, regimeCode]; predict(landings) -> lift-offs "
             "(arrays of [xdot, ydot, omega] rows); regime(landings) -> codes; REGIMES (names by code), "
             "PARAMETERS, LAW.", "  ")
    text = "\n".join(" *" + (" " + line if line else "") for line in lines).replace("*/", "* /")
    return f"/*\n{text}\n */"


def _text_value(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return repr(np.asarray(value, dtype=float).tolist())
    if isinstance(value, float | np.floating):
        return repr(float(value))
    return repr(value)


def _nested(value: np.ndarray, program: Program, open_: str, close: str) -> str:
    if value.ndim == 1:
        return open_ + ", ".join(program.literal(float(v), FLOAT) for v in value) + close
    return open_ + ", ".join(_nested(v, program, open_, close) for v in value) + close


def _js_value(value: Any, program: Program) -> str:
    if isinstance(value, np.ndarray):
        return _nested(np.asarray(value, dtype=float), program, "[", "]")
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    return program.literal(value, FLOAT if isinstance(value, float | np.floating) else None)


def _js_string(text: str) -> str:
    import json

    return json.dumps(str(text))


def _c_string(text: str) -> str:
    return "".join(ch if ch.isascii() and ch.isprintable() and ch not in '"\\?' else f"\\{ord(ch) & 0xFF:03o}"
                   for ch in str(text))
