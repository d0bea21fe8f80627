"""A law as a C99 header, an ES module or a C# class: its kernel translated, its values baked in, its terms
in the comment.

:func:`export_law` (and :func:`to_c`, :func:`to_js`, :func:`to_cs`, ``bouncelab export``) writes one
self-contained file per law. The comment at its top says what the law is (its class, parameters,
options and the constants derived from them), the conventions and units of its states, where it holds
(the landings it was fitted on, when the law records them, and bouncelab's unit guard, both in scaled
units) and how to compile it so that it computes what bouncelab computes. The code below it is the law's
numba kernel read by the front end (:mod:`bouncelab.export.frontend`) into the intermediate form
(:mod:`bouncelab.export.ir`) and printed by the language's emitter (:mod:`bouncelab.export.emit`);
this module adds only each language's entry points around it.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import math
import re
import textwrap
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES
from bouncelab.core.units import BALL_RADIUS_M, CONVENTIONS
from bouncelab.export import ir
from bouncelab.export.emit import CEmitter, CSharpEmitter, JSEmitter
from bouncelab.export.emit.c import c_literal
from bouncelab.export.emit.cs import cs_literal
from bouncelab.export.emit.js import js_literal
from bouncelab.export.errors import ExportError
from bouncelab.export.frontend import FLOAT, ArrayType, Translation, TupleType, is_jit_function, value_type
from bouncelab.export.names import DEFAULT_CLASS, DEFAULT_PREFIX, LANGUAGES
from bouncelab.laws.base import BounceModel

__all__ = ["DEFAULT_CLASS", "DEFAULT_PREFIX", "LANGUAGES", "c_header", "cs_class", "export_law", "js_module", "to_c",
           "to_cs", "to_js"]


_PREFIX = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_CS_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_CS_KEYWORDS = frozenset("""
abstract as base bool break byte case catch char checked class const continue decimal default delegate do double
else enum event explicit extern false finally fixed float for foreach goto if implicit in int interface internal is
lock long namespace new null object operator out override params private protected public readonly ref return sbyte
sealed short sizeof stackalloc static string struct switch this throw true try typeof uint ulong unchecked unsafe
ushort using virtual void volatile while
""".split())
#: The members of an exported class (a class cannot take one of their names) and the namespace it uses.
_CS_MEMBERS = frozenset({"LawName", "RegimeCount", "PredictOne", "Predict", "Regime", "RegimeName", "Check", "System",
                         "Math", "BitConverter"})
_RPM = 2.0 * math.pi / 60.0
_WHAT = {"c": "a C99 header", "js": "an ES module", "cs": "a C# class"}


# Checks and output shared with the surface's export (bouncelab.export.ground).
def _check_language(lang: Any, prefix: Any, class_name: Any, namespace: Any) -> None:
    """``lang`` is a language of :data:`LANGUAGES`, and the options given belong to it."""
    if lang not in LANGUAGES:
        raise ParameterError(f"cannot export to {lang!r}: the languages are {', '.join(map(repr, LANGUAGES))}",
                             parameter="lang", value=lang)
    for name, value, owner in (("prefix", prefix, "c"), ("class_name", class_name, "cs"),
                               ("namespace", namespace, "cs")):
        if value is not None and lang != owner:
            raise ParameterError(f"{name} is for {'C headers' if owner == 'c' else 'C# classes'}, not --lang "
                                 f"{lang}", parameter=name, value=value)


def _check_prefix(prefix: Any, example: str) -> None:
    """``prefix`` is a C identifier (the error suggests ``'bouncelab_'`` or ``example``)."""
    if not isinstance(prefix, str) or not _PREFIX.match(prefix):
        raise ParameterError(f"prefix must be a C identifier such as 'bouncelab_' or '{example}'; got {prefix!r}",
                             parameter="prefix", value=prefix)


def _check_cs_names(class_name: Any, namespace: Any, members: frozenset[str], examples: str) -> None:
    """``class_name`` is a C# identifier, not a keyword nor one of the class's ``members`` (the error suggests
    ``examples``); ``namespace`` is None or C# identifiers joined by dots."""
    if (not isinstance(class_name, str) or not _CS_NAME.match(class_name) or class_name in _CS_KEYWORDS
            or class_name in members):
        raise ParameterError(f"class_name must be a C# identifier such as {examples}; got "
                             f"{class_name!r}", parameter="class_name", value=class_name)
    if namespace is not None and (not isinstance(namespace, str) or not all(
            _CS_NAME.match(part) and part not in _CS_KEYWORDS for part in namespace.split("."))):
        raise ParameterError(f"namespace must be C# identifiers joined by dots such as 'Golf.Bounce'; got "
                             f"{namespace!r}", parameter="namespace", value=namespace)


def _written(text: str, path: str | Path | None, what: str) -> str:
    """``text``, written first to ``path`` if one is given (``what`` names it in an error)."""
    if path is not None:
        from bouncelab.core.atomic import write_output

        write_output(path, text, what)
    return text


def export_law(law: Any, lang: str, path: str | Path | None = None, *, prefix: str | None = None,
               class_name: str | None = None, namespace: str | None = None) -> str:
    """The law as C99 (``lang="c"``), JavaScript (``"js"``) or C# (``"cs"``) source; also written to ``path``.

    Parameters
    ----------
    law
        A law with values whose maths is a compiled kernel (every built-in law; a user's
        :class:`~bouncelab.laws.CompiledLaw` whose kernel keeps to the translator's subset).
    lang
        ``"c"``, ``"js"`` or ``"cs"``.
    path
        File to write (atomically), or None.
    prefix
        C only: the prefix of every name the header defines (default ``"bouncelab_"``: the entry point is
        ``bouncelab_predict``). Give each law of one program its own.
    class_name, namespace
        C# only: the static class's name (default ``"BouncelabLaw"``) and the namespace it is declared in
        (default none: the global namespace). Give each law of one program its own class or namespace.

    Returns
    -------
    str
        The source text.

    Raises
    ------
    ParameterError
        An unknown ``lang``; a ``prefix``, ``class_name`` or ``namespace`` that is not a valid name in
        the language, or given for another language; ``law`` that is not a law.
    NotFittedError
        The law has no value for some parameter.
    ExportError
        The law has no compiled kernel, or the kernel uses a construct the translator does not know
        (a :class:`~bouncelab.core.errors.LawDefinitionError` naming the function, line and construct).
    OutputError
        ``path`` cannot be written; nothing is written then.
    """
    _check_language(lang, prefix, class_name, namespace)
    if lang == "c":
        text = c_header(law, prefix=DEFAULT_PREFIX if prefix is None else prefix)
    elif lang == "js":
        text = js_module(law)
    else:
        text = cs_class(law, class_name=DEFAULT_CLASS if class_name is None else class_name, namespace=namespace)
    return _written(text, path, "the exported law")


def to_c(law: Any, path: str | Path | None = None, *, prefix: str = DEFAULT_PREFIX) -> str:
    """The law as a self-contained C99 header, its values baked in; also written to ``path`` if given.

    Entry points ``void bouncelab_predict(const double *landing, double *liftoff, long n)`` and
    ``int bouncelab_predict_one(double xdot, double ydot, double omega, double out[3])`` (scaled units;
    ``prefix`` replaces ``bouncelab_`` so that several laws fit in one program). See :func:`export_law`
    for the errors it raises.
    """
    return export_law(law, "c", path, prefix=prefix)


def to_js(law: Any, path: str | Path | None = None) -> str:
    """The law as a self-contained JavaScript ES module, its values baked in; also written to ``path`` if given.

    Exports ``predict(landings, out?)`` (a ``Float64Array`` of three numbers a landing, ``xdot, ydot,
    omega`` in scaled units, to one of lift-offs) and ``predictOne(xdot, ydot, omega, out?)``, which
    allocates nothing; see :func:`export_law`.
    """
    return export_law(law, "js", path)


def to_cs(law: Any, path: str | Path | None = None, *, class_name: str = DEFAULT_CLASS,
          namespace: str | None = None) -> str:
    """The law as a self-contained C# file (one ``public static class``), its values baked in; also written to
    ``path`` if given.

    Methods ``int PredictOne(double xdot, double ydot, double omega, double[] liftoff)`` (and an
    ``out``-parameter overload), ``void Predict(double[] landings, double[] liftoffs)`` (three numbers
    a landing, scaled units), ``Regime``, ``RegimeName``; see :func:`export_law`.
    """
    return export_law(law, "cs", path, class_name=class_name, namespace=namespace)


# ------------------------------------------------------------------------------------------- the kernel
class _Kernel:
    """A law's kernel translated to the intermediate form, with the values its entry point is given."""

    def __init__(self, law: Any) -> None:
        if not isinstance(law, BounceModel):
            raise ParameterError(f"export takes a bounce law (a bouncelab.BounceModel), not {type(law).__name__}",
                                 parameter="law", value=type(law).__name__)
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
        self.args: list[tuple[str, Any, Any]] = []
        for name, value in zip(names[3:], args, strict=True):
            if value is None:
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is None; give the law a value "
                                  "for it", law=self.law_name)
            try:
                t = value_type(value)
            except TypeError as exc:
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is {exc}, which the "
                                  "exported code cannot hold", law=self.law_name) from None
            if not (t in (FLOAT, "int64", "bool") or isinstance(t, ArrayType)):
                what = "a tuple" if isinstance(t, TupleType) else str(t)
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is {what}; only numbers and "
                                  "float arrays can be baked in", law=self.law_name)
            if isinstance(value, np.ndarray):
                value = np.asarray(value, dtype=np.float64)
            self.args.append((name, value, t))
        self.translation = Translation()
        try:
            self.entry = self.translation.add(kernel, (FLOAT, FLOAT, FLOAT, *(t for _, _, t in self.args)))
        except ExportError as exc:
            exc.law = self.law_name
            raise
        spec = self.translation.spec_of(kernel, (FLOAT, FLOAT, FLOAT, *(t for _, _, t in self.args)))
        ret = self.entry.returns
        if not (self.entry.multi and len(ret) == 4 and all(r in (ir.F64, ir.I64) for r in ret[:3])
                and ret[3] == ir.I64 and isinstance(spec.ret, TupleType) and len(spec.ret.elems) == 4):
            raise ExportError(f"{self.law_name}'s kernel returns {spec.ret}, not (xdotF, ydotF, omegaF, regime code)",
                              law=self.law_name)
        self.program = self.translation.program
        self.regimes = [str(r) for r in getattr(law, "regimes", ())]

    def baked(self, literal: Any, name_of: Any, array: Any, scalar: Any) -> list[str]:
        """The declarations of the baked values: ``array(name, type, nested text)`` for an array,
        ``scalar(name, type, literal)`` for a number."""
        out = []
        for name, value, t in self.args:
            if isinstance(t, ArrayType):
                out.append(array(name_of(name), t, _nested(value, literal)))
            else:
                it = {FLOAT: ir.F64, "int64": ir.I64, "bool": ir.BOOL}[t]
                out.append(scalar(name_of(name), it, literal(value, it)))
        return out


# ------------------------------------------------------------------------------------------- C
def c_header(law: Any, prefix: str = DEFAULT_PREFIX) -> str:
    """The law as a self-contained C99 header (see :func:`export_law`)."""
    _check_prefix(prefix, "turf_a_")
    k = _Kernel(law)
    em = CEmitter(k.program, prefix)
    p = prefix
    definitions = em.definitions()
    consts = k.baked(c_literal, lambda n: f"{p}p_{n}",
                     lambda n, t, text: f"static const double {n}{''.join(f'[{s}]' for s in t.shape)} = {text};",
                     lambda n, t, text: f"static const {em.type_name(t)} {n} = {text};")
    call = f"{em.function_name(k.entry.name)}(xd, yd, w{''.join(f', {p}p_{name}' for name, _, _ in k.args)})"
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

/* ---- the law's kernel, translated from its Python source (bouncelab.export) ---- */

{definitions}

/* ---- entry points ---- */

/* One bounce: the lift-off [xdot, ydot, omega] of landing (xd, yd, w) into out; returns the regime code. */
BOUNCELAB_API int {p}predict_one(double xd, double yd, double w, double out[3]) {{
    {em.struct(k.entry.returns)} t = {call};
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
    return _guarded_header(_comment(k, "c", prefix=prefix), body, p, "LAW")


# ------------------------------------------------------------------------------------------- JavaScript
def js_module(law: Any) -> str:
    """The law as a self-contained ES module (see :func:`export_law`)."""
    k = _Kernel(law)
    em = JSEmitter(k.program)
    consts = k.baked(js_literal, lambda n: f"$p_{n}", lambda n, t, text: f"const {n} = {text};",
                     lambda n, t, text: f"const {n} = {text};")
    baked = [f"$p_{name}" for name, _, _ in k.args]

    def call(indent: str, *landing: str) -> str:  # the kernel's call: its results are then in $R
        return f"\n{indent}".join(em.entry_call(k.entry.name, [*landing, *baked]))

    call_one = call("  ", "xdot", "ydot", "omega")
    call_flat = call("    ", "landings[i]", "landings[i + 1]", "landings[i + 2]")
    call_regime = call("    ", "landings[3 * i]", "landings[3 * i + 1]", "landings[3 * i + 2]")
    call_row = call("    ", "p[0]", "p[1]", "p[2]")
    definitions = em.definitions()  # after the calls: the helpers they use are printed too
    params = ", ".join(f"{_js_string(name)}: {_js_value(value)}" for name, value in k.parameters)
    regimes = ", ".join(_js_string(r) for r in k.regimes)
    body = f"""/* The law's values, baked in (parameters, options and the constants derived from them). */
{chr(10).join(consts) or '/* (none) */'}

/* ---- the law's kernel, translated from its Python source (bouncelab.export) ---- */

{definitions}

/* ---- entry points ---- */

/** The law's name and parameter values (scaled units), and its regimes (index = regime code). */
export const LAW = {_js_string(k.law_name)};
export const PARAMETERS = Object.freeze({{{params}}});
export const REGIMES = Object.freeze([{regimes}]);

/** predictOne's lift-off when it is given no array of its own: overwritten by the next such call. */
export const LIFTOFF = new Float64Array(3);

/**
 * One bounce, allocating nothing: the lift-off [xdotF, ydotF, omegaF] of the landing (xdot, ydot, omega)
 * into out (a Float64Array(3) or any array; LIFTOFF if not given); returns the regime code (REGIMES[code]).
 */
export function predictOne(xdot, ydot, omega, out = LIFTOFF) {{
  {call_one}
  out[0] = $R[0];
  out[1] = $R[1];
  out[2] = $R[2];
  return $R[3];
}}

function $landings(landings, what) {{
  if (landings === null || typeof landings !== "object" || typeof landings.length !== "number") {{
    throw new TypeError(`${{what}} must be a Float64Array (or an array of numbers), three a landing: ` +
                        "xdot, ydot, omega");
  }}
  if (landings.length > 0 && typeof landings[0] !== "number") {{
    throw new TypeError(`${{what}} holds ${{typeof landings[0]}}s, not numbers: give the landings flat, ` +
                        "three numbers a landing (a Float64Array); for an array of [xdot, ydot, omega] rows " +
                        "call predictRows(rows)");
  }}
  if (landings.length % 3 !== 0) {{
    throw new RangeError(`${{what}} has ${{landings.length}} numbers, not three a landing (xdot, ydot, omega)`);
  }}
  return landings.length / 3;
}}

/**
 * Lift-offs of landings: landings holds three numbers a landing (xdot, ydot, omega; a Float64Array or an
 * array of numbers), the lift-offs go to out in the same layout (a new Float64Array if not given; it may be
 * landings itself), which is returned.
 */
export function predict(landings, out) {{
  const n = $landings(landings, "landings");
  if (out === undefined) out = new Float64Array(3 * n);
  else if (out.length < 3 * n) {{
    throw new RangeError(`out holds ${{out.length}} numbers, fewer than the ${{3 * n}} of landings`);
  }}
  for (let i = 0; i < 3 * n; i += 3) {{
    {call_flat}
    out[i] = $R[0];
    out[i + 1] = $R[1];
    out[i + 2] = $R[2];
  }}
  return out;
}}

/** The regime codes of landings (three numbers a landing) into out (a new Int32Array if not given). */
export function regime(landings, out) {{
  const n = $landings(landings, "landings");
  if (out === undefined) out = new Int32Array(n);
  else if (out.length < n) throw new RangeError(`out holds ${{out.length}} codes, fewer than the ${{n}} landings`);
  for (let i = 0; i < n; i++) {{
    {call_regime}
    out[i] = $R[3];
  }}
  return out;
}}

/** Lift-offs [[xdotF, ydotF, omegaF], ...] of landings [[xdot, ydot, omega], ...] (arrays of rows; slower). */
export function predictRows(rows) {{
  const out = new Array(rows.length);
  for (let i = 0; i < rows.length; i++) {{
    const p = rows[i];
    if (p === null || typeof p !== "object" || p.length !== 3) {{
      throw new RangeError(`landing ${{i}} is not a row of 3 numbers (xdot, ydot, omega)`);
    }}
    {call_row}
    out[i] = [$R[0], $R[1], $R[2]];
  }}
  return out;
}}
"""
    return f"{_comment(k, 'js')}\n{body}"


# ------------------------------------------------------------------------------------------- C#
def cs_class(law: Any, class_name: str = DEFAULT_CLASS, namespace: str | None = None) -> str:
    """The law as a self-contained C# file (see :func:`export_law`)."""
    _check_cs_names(class_name, namespace, _CS_MEMBERS, "'BouncelabLaw' or 'TurfA'")
    k = _Kernel(law)
    em = CSharpEmitter(k.program)
    definitions = em.definitions()
    consts = k.baked(cs_literal, lambda n: f"p_{n}",
                     lambda n, t, text: f"private static readonly {em.type_name(ir.ArrayType(t.shape))} {n} = {text};",
                     lambda n, t, text: f"private const {em.type_name(t)} {n} = {text};")
    kernel = em.function_name(k.entry.name)
    args = "".join(f", p_{name}" for name, _, _ in k.args)
    rt = [em.type_name(t) for t in k.entry.returns]
    decl = f"{rt[0]} r0; {rt[1]} r1; {rt[2]} r2; {rt[3]} r3;"
    call = f"{kernel}(%s{args}, out r0, out r1, out r2, out r3);"
    names = "\n".join(f"            case {code}: return {_cs_string(r)};" for code, r in enumerate(k.regimes))
    inner = f"""/// <summary>{_xml(k.law_name)} bounce law exported by bouncelab: its compiled kernel in C#, its values
/// baked in (scaled units: radii/s and rad/s; see the comment at the top of the file).</summary>
public static class {class_name} {{
    /// <summary>The law's class in bouncelab.</summary>
    public const string LawName = {_cs_string(k.law_name)};
    /// <summary>The number of regime codes (0 to RegimeCount - 1; RegimeName names them).</summary>
    public const int RegimeCount = {len(k.regimes)};

    // The law's values, baked in (parameters, options and the constants derived from them).
{textwrap.indent(chr(10).join(consts) or '// (none)', '    ')}

    // ---- the law's kernel, translated from its Python source (bouncelab.export) ----

{textwrap.indent(definitions, '    ')}

    // ---- entry points ----

    /// <summary>One bounce: the lift-off [xdotF, ydotF, omegaF] of landing (xdot, ydot, omega) into
    /// liftoff[0..2]; returns the regime code. Allocates nothing.</summary>
    public static int PredictOne(double xdot, double ydot, double omega, double[] liftoff) {{
        if (liftoff == null || liftoff.Length < 3) {{
            throw new ArgumentException("liftoff must hold 3 numbers (xdotF, ydotF, omegaF)", "liftoff");
        }}
        {decl}
        {call % "xdot, ydot, omega"}
        liftoff[0] = r0;
        liftoff[1] = r1;
        liftoff[2] = r2;
        return (int)r3;
    }}

    /// <summary>One bounce: the lift-off (xdotF, ydotF, omegaF) of landing (xdot, ydot, omega); returns the
    /// regime code. Allocates nothing.</summary>
    public static int PredictOne(double xdot, double ydot, double omega, out double xdotF, out double ydotF,
                                 out double omegaF) {{
        {decl}
        {call % "xdot, ydot, omega"}
        xdotF = r0;
        ydotF = r1;
        omegaF = r2;
        return (int)r3;
    }}

    /// <summary>Lift-offs of landings: three numbers a landing (xdot, ydot, omega) in landings, the
    /// lift-offs in the same layout into liftoffs (at least as long; it may be landings itself).</summary>
    public static void Predict(double[] landings, double[] liftoffs) {{
        Check(landings, liftoffs == null ? -1 : liftoffs.Length, 3, "liftoffs");
        {decl}
        for (int i = 0; i < landings.Length; i += 3) {{
            {call % "landings[i], landings[i + 1], landings[i + 2]"}
            liftoffs[i] = r0;
            liftoffs[i + 1] = r1;
            liftoffs[i + 2] = r2;
        }}
    }}

    /// <summary>The regime codes of landings (three numbers a landing) into regimes (one a landing).</summary>
    public static void Regime(double[] landings, int[] regimes) {{
        Check(landings, regimes == null ? -1 : regimes.Length, 1, "regimes");
        {decl}
        for (int i = 0; i < landings.Length / 3; i++) {{
            {call % "landings[3 * i], landings[3 * i + 1], landings[3 * i + 2]"}
            regimes[i] = (int)r3;
        }}
    }}

    /// <summary>The name of a regime code ("?" for a code the law does not have).</summary>
    public static string RegimeName(int code) {{
        switch (code) {{
{names}
            default: return "?";
        }}
    }}

    private static void Check(double[] landings, int outLength, int perLanding, string outName) {{
        if (landings == null) throw new ArgumentNullException("landings");
        if (outLength < 0) throw new ArgumentNullException(outName);
        if (landings.Length % 3 != 0) {{
            throw new ArgumentException("landings has " + landings.Length + " numbers, not three a landing "
                                        + "(xdot, ydot, omega)", "landings");
        }}
        if (outLength < landings.Length / 3 * perLanding) {{
            throw new ArgumentException(outName + " holds " + outLength + " numbers, fewer than the "
                                        + (landings.Length / 3 * perLanding) + " the landings need", outName);
        }}
    }}
}}
"""
    code = inner if namespace is None else f"namespace {namespace} {{\n\n{textwrap.indent(inner, '    ')}}}\n"
    code = "\n".join(line.rstrip() for line in code.split("\n"))
    usings = "".join(f"using {u};\n" for u in em.usings)
    return f"{_comment(k, 'cs', class_name=class_name)}\n{usings}\n{code}"


# ------------------------------------------------------------------------------------------- the comment
def _guarded_header(comment: str, body: str, prefix: str, kind: str) -> str:
    """A C header: ``comment``, then ``body`` inside an include guard named by the prefix, the kind ("LAW",
    "SURFACE") and the body's hash. The guard names the content: the same file included twice is read once,
    while two different exports with the same prefix collide loudly (redefinitions) instead of one silently
    hiding the other."""
    guard = f"{prefix.upper().strip('_')}_{kind}_H_{hashlib.sha256(body.encode()).hexdigest()[:12].upper()}"
    return f"{comment}\n#ifndef {guard}\n#define {guard}\n\n{body}\n#endif /* {guard} */\n"


def _comment(k: _Kernel, lang: str, *, prefix: str = DEFAULT_PREFIX, class_name: str = DEFAULT_CLASS) -> str:
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

    para(f"{k.law_name} bounce law, exported as {_WHAT[lang]} by bouncelab {__version__} (bouncelab.export).")
    para(f"Law: {law!r}")
    para(f"The code is the law's compiled kernel, {func.__module__}.{func.__qualname__}, translated operation by "
         "operation from its Python source (bouncelab.export); the values below are baked in.")
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
    elif lang == "cs":
        para("C# doubles are IEEE doubles; the code assumes that the runtime does not fuse multiply-adds or keep "
             "extended precision (.NET and Mono on x86-64 and ARM64 do neither; in an IL2CPP build keep the C++ "
             "compiler from contracting, as for the C header). ** is h_pow below, correctly rounded, the same on "
             "every runtime; hypot, log1p, expm1, asinh, acosh and atanh, which System.Math lacks, are written out "
             "(within a few units in the last place). Math.Exp, Math.Sin, Math.Cos... are the runtime's: Mono "
             "and .NET on Linux call the C library's, elsewhere they may differ from it in the last bit. "
             "bouncelab's tests compile the file with Mono's mcs and check the results under mono against "
             "law.predict to 1e-12 (relative to the landing's norm) on 10^5 landings covering every regime.", "  ")
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
             "prefix (bouncelab export --prefix NAME, bouncelab.export.to_c(law, prefix=NAME)). C99; C++ compilers "
             "accept it too. "
             "The entry points are static inline unless BOUNCELAB_API is defined (e.g. as nothing) first.", "  ")
    elif lang == "cs":
        c = class_name
        para(f"int {c}.PredictOne(double xdot, double ydot, double omega, double[] liftoff): one bounce, the "
             "lift-off into liftoff[0..2], returns the regime code; an overload gives it in out double xdotF, "
             "ydotF, omegaF. Neither allocates.", "  ")
        para(f"void {c}.Predict(double[] landings, double[] liftoffs): three numbers a landing; "
             f"{c}.Regime(double[] landings, int[] regimes): their regime codes; {c}.RegimeName(code) names one.",
             "  ")
        para(f"One public static class, {c} (bouncelab export --class-name NAME, --namespace NAME), in plain C# "
             "7.3 with System.Math only: Unity, Godot and Mono compile it (e.g. mcs -target:library Law.cs).", "  ")
    else:
        para("predictOne(xdot, ydot, omega, out = LIFTOFF) -> regimeCode, the lift-off [xdotF, ydotF, omegaF] "
             "written into out (a Float64Array(3): nothing is allocated); predict(landings, out?) -> lift-offs, "
             "three numbers a landing in a Float64Array; regime(landings, out?) -> an Int32Array of codes; "
             "predictRows(rows) for arrays of [xdot, ydot, omega] rows; REGIMES (names by code), PARAMETERS, "
             "LAW.", "  ")
    text = "\n".join(" *" + (" " + line if line else "") for line in lines).replace("*/", "* /")
    return f"/*\n{text}\n */"


def _text_value(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return repr(np.asarray(value, dtype=float).tolist())
    if isinstance(value, float | np.floating):
        return repr(float(value))
    return repr(value)


def _nested(value: np.ndarray, literal: Any) -> str:
    """An array's values as nested braces (C, C#) or brackets (JavaScript), by the literal printer's language."""
    open_, close = ("[", "]") if literal is js_literal else ("{", "}")
    if value.ndim == 1:
        return open_ + ", ".join(literal(float(v), ir.F64) for v in value) + close
    return open_ + ", ".join(_nested(v, literal) for v in value) + close


def _js_value(value: Any) -> str:
    if isinstance(value, np.ndarray):
        return _nested(np.asarray(value, dtype=float), js_literal)
    if isinstance(value, bool | np.bool_):
        return "true" if value else "false"
    return js_literal(value, ir.F64 if isinstance(value, float | np.floating) else ir.I64)


def _js_string(text: str) -> str:
    return json.dumps(str(text))


def _cs_string(text: str) -> str:
    return '"' + "".join(ch if ch.isascii() and ch.isprintable() and ch not in '"\\' else f"\\u{ord(ch):04x}"
                         for ch in str(text)) + '"'


def _xml(text: str) -> str:
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _c_string(text: str) -> str:
    return "".join(ch if ch.isascii() and ch.isprintable() and ch not in '"\\?' else f"\\{ord(ch) & 0xFF:03o}"
                   for ch in str(text))
