"""A surface's whole ground phase as a C99 header, an ES module or a C# class: the kernels of
:mod:`bouncelab.ground` translated, the surface's values baked in.

:func:`export_surface` (and ``bouncelab export SURFACE.json --lang c|js|cs``) writes one file per
surface with two entry points, in SI units (m/s, rad/s, metres, seconds), right-handed, z up, ``n``
the ground's normal:

* the 3-D bounce, :func:`bouncelab.ground.bounce`: C ``bouncelab_bounce3d(v, w, n, v_out, w_out)``,
  JavaScript ``bounce3d(v, w, n) -> [vOut, wOut]``, C# ``BouncelabSurface.Bounce3D(v, w, n, vOut, wOut)``;
* the run from the landing to rest, :func:`bouncelab.ground.run` with its defaults (bounces, flights in
  vacuum, skid and roll): C ``bouncelab_run(v, w, n, rest, &t_rest)`` returning the number of bounces
  (or a negative refusal code), JavaScript ``run(v, w, n) -> {rest, time, bounces}``, C#
  ``BouncelabSurface.Run(v, w, n, rest, out time)``; ``rest`` the ball's lowest point at rest relative
  to the touch-down point, as ``RunResult.rest_position``.

What is translated: the ground's own row kernels, ``bounce_rows`` (:func:`bouncelab.ground._kernels.bounce_loop`)
and ``run_rows`` (:func:`~bouncelab.ground._kernels.run_loop`), built around the law's compiled lift
exactly as ``ground.bounce`` and ``ground.run`` build them, with everything they call (the law's kernel,
the frames, flights, skid and roll), each specialised for one row; and the input checks and unit
conversions of this module (:func:`prepare_run`, :func:`prepare_bounce`, :func:`finish_run`,
:func:`finish_bounce`: what :func:`bouncelab.ground.run` and :func:`~bouncelab.ground.bounce` do in
NumPy around their kernels, written once as jit functions so that the three languages share them).
The front end (:mod:`bouncelab.export.frontend`) reads them into the intermediate form and each
language's emitter prints it; this module adds the entry points around them (scratch arrays, the
calls, errors), as :mod:`bouncelab.export.law` does for a law. The run's optional paths (the recorded
bounces of the path, samples, air) are empty arrays in the translation: they have no place in the output.
"""

from __future__ import annotations

import inspect
import math
import textwrap
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bouncelab.core._jit import jit
from bouncelab.core.errors import ParameterError
from bouncelab.core.landing_checks import STATE_LIMIT
from bouncelab.core.units import BALL_RADIUS_M, ball_radius
from bouncelab.export import ir
from bouncelab.export.emit import CEmitter, CSharpEmitter, JSEmitter
from bouncelab.export.emit.c import c_literal
from bouncelab.export.emit.cs import cs_literal
from bouncelab.export.emit.js import js_literal
from bouncelab.export.errors import ExportError
from bouncelab.export.frontend import FLOAT, INT, ArrayType, Translation, is_jit_function, leaf_types, value_type
from bouncelab.export.law import (
    _c_string,
    _check_cs_names,
    _check_language,
    _check_prefix,
    _cs_string,
    _guarded_header,
    _js_string,
    _nested,
    _written,
    _xml,
)
from bouncelab.export.names import DEFAULT_SURFACE_CLASS, DEFAULT_SURFACE_PREFIX
from bouncelab.ground import _kernels as gk
from bouncelab.ground.bounce3d import compiled_lift, lift_plane
from bouncelab.ground.runout import DEFAULT_MAX_BOUNCES, DEFAULT_MIN_APEX_M
from bouncelab.ground.surface import GRAVITY, Surface, preset

__all__ = ["DEFAULT_SURFACE_CLASS", "DEFAULT_SURFACE_PREFIX", "REFUSALS", "export_surface", "finish_bounce",
           "finish_run", "prepare_bounce", "prepare_run", "surface_c", "surface_cs", "surface_js"]


# Refusal codes of the entry points (bouncelab_run's result, the `code` of a JavaScript error).
NOT_FINITE, ZERO_NORMAL, NOT_UP, TOO_FAST, TOO_MUCH_SPIN, TOO_STEEP, NOT_LANDING, NO_ANSWER = range(-1, -9, -1)
#: code -> what it refuses (the entry points' messages). The same checks as bouncelab.ground's, in its order.
REFUSALS: dict[int, str] = {
    NOT_FINITE: "a component of v, w or n is not finite (NaN or infinite)",
    ZERO_NORMAL: "the normal n is the zero vector",
    NOT_UP: "the normal n does not point up (z <= 0): gravity (0, 0, -g) would not press the ball onto that ground",
    TOO_FAST: f"a velocity component is beyond {STATE_LIMIT:g} ball radii/s: no ball moves that fast (another unit?)",
    TOO_MUCH_SPIN: f"a spin component is beyond {STATE_LIMIT:g} rad/s: no ball spins that fast (another unit?)",
    TOO_STEEP: "the ground is too steep for a ball to come to rest on this surface (5/7 g sin(theta) >= mu_r g "
               "cos(theta), or tan(theta) >= 7/2 mu_s): on an endless plane it never stops",
    NOT_LANDING: "the velocity does not move into the ground: a run starts with a landing (v . n < 0) or on the "
                 "ground (v . n = 0); a bounce needs v . n < 0",
    NO_ANSWER: "the run has no finite answer (the law gave a non-finite lift-off)",
}
_RUN_TOL = 1e-9  # |v . n| <= 1e-9 |v|: a ball on the ground (bouncelab.ground.run)


# ------------------------------------------------------------------------------ the entry points' own kernels
# What ground.run and ground.bounce do in NumPy around their row kernels (bouncelab.ground._inputs and
# runout.run), for one shot, with the same operations in the same order: these are translated with the kernels.
# (No fastmath flags: isfinite must see NaN and infinity.)
@jit(inline="always")
def _finite(a):
    return math.isfinite(a[0]) and math.isfinite(a[1]) and math.isfinite(a[2])


@jit(inline="always")
def _unit_normal(nx, ny, nz):
    """The normal divided by its largest component, then by its length (``_inputs.unit_normals``); a code."""
    big = max(abs(nx), abs(ny), abs(nz))
    if big == 0.0:
        return ZERO_NORMAL, 0.0, 0.0, 0.0
    mx = nx / big
    my = ny / big
    mz = nz / big
    s = math.sqrt(mx * mx + my * my + mz * mz)
    return 0, mx / s, my / s, mz / s


@jit(inline="always")
def _states(v, w, inv_radius, limit):
    """The velocity in radii/s (``v * (1 / R)``, as ``core.units``) and whether it and the spin are within the
    state limit (``_inputs.within_limit``): a code and the velocity."""
    vx = v[0] * inv_radius
    vy = v[1] * inv_radius
    vz = v[2] * inv_radius
    if not (abs(vx) <= limit and abs(vy) <= limit and abs(vz) <= limit):
        return TOO_FAST, vx, vy, vz
    if not (abs(w[0]) <= limit and abs(w[1]) <= limit and abs(w[2]) <= limit):
        return TOO_MUCH_SPIN, vx, vy, vz
    return 0, vx, vy, vz


@jit
def prepare_run(v, w, n, inv_radius, limit, tan_roll, tan_skid, V, W, N, LANDING):
    """One shot of ``ground.run`` in SI units (v m/s, w rad/s, n any length) as the row of its kernel.

    Refuses (a negative code, :data:`REFUSALS`) what ``run`` refuses, in its order: non-finite values, a
    zero normal or one not pointing up, states beyond the limit, a slope on which no ball stops
    (``tan >= tan_roll = 7/5 mu_r`` or ``tan >= tan_skid = 7/2 mu_s``), a velocity away from the
    ground. Else writes the scaled velocity, the spin, the unit normal and whether the shot lands
    (``v . n < -1e-9 |v|``) into row 0 of V, W, N, LANDING and returns 0.
    """
    if not (_finite(v) and _finite(w) and _finite(n)):
        return NOT_FINITE
    code, nx, ny, nz = _unit_normal(n[0], n[1], n[2])
    if code < 0:
        return code
    if nz <= 0.0:
        return NOT_UP
    code, vx, vy, vz = _states(v, w, inv_radius, limit)
    if code < 0:
        return code
    tan = math.sqrt(nx * nx + ny * ny) / nz
    if tan >= tan_roll or tan >= tan_skid:
        return TOO_STEEP
    vn = vx * nx + vy * ny + vz * nz
    tol = _RUN_TOL * math.sqrt(vx * vx + vy * vy + vz * vz)
    if vn > tol:
        return NOT_LANDING
    V[0, 0], V[0, 1], V[0, 2] = vx, vy, vz
    W[0, 0], W[0, 1], W[0, 2] = w[0], w[1], w[2]
    N[0, 0], N[0, 1], N[0, 2] = nx, ny, nz
    LANDING[0] = 1 if vn < -tol else 0
    return 0


@jit
def finish_run(OUT, COUNTS, radius, rest, time):
    """The rest position in metres (``x * R``) into rest, the time to rest into ``time[0]``; returns the number of
    bounces (:data:`NO_ANSWER` if the run has no finite answer, as ``ground.run`` refuses it)."""
    for c in range(12):
        if not math.isfinite(OUT[0, c]):
            return NO_ANSWER
    rest[0] = OUT[0, 8] * radius
    rest[1] = OUT[0, 9] * radius
    rest[2] = OUT[0, 10] * radius
    time[0] = OUT[0, 11]
    return COUNTS[0, 0]


@jit
def prepare_bounce(v, w, n, inv_radius, limit, V, W, N):
    """One landing of ``ground.bounce`` in SI units as the row of its kernel (a negative code for what ``bounce``
    refuses: non-finite values, a zero normal, states beyond the limit, ``v . n >= 0``)."""
    if not (_finite(v) and _finite(w) and _finite(n)):
        return NOT_FINITE
    code, nx, ny, nz = _unit_normal(n[0], n[1], n[2])
    if code < 0:
        return code
    code, vx, vy, vz = _states(v, w, inv_radius, limit)
    if code < 0:
        return code
    if not (vx * nx + vy * ny + vz * nz < 0.0):
        return NOT_LANDING
    V[0, 0], V[0, 1], V[0, 2] = vx, vy, vz
    W[0, 0], W[0, 1], W[0, 2] = w[0], w[1], w[2]
    N[0, 0], N[0, 1], N[0, 2] = nx, ny, nz
    return 0


@jit
def finish_bounce(VF, WF, radius, v_out, w_out):
    """The lift-off velocity in m/s (``v * (R / 1)``, as ``core.units``) and spin (rad/s) into v_out, w_out."""
    v_out[0] = VF[0, 0] * radius
    v_out[1] = VF[0, 1] * radius
    v_out[2] = VF[0, 2] * radius
    w_out[0] = WF[0, 0]
    w_out[1] = WF[0, 1]
    w_out[2] = WF[0, 2]
    return 0


# ------------------------------------------------------------------------------ the program
def _arr(*shape: int, dtype: str = FLOAT) -> ArrayType:
    return ArrayType(tuple(shape), dtype)


@dataclass
class _Arg:
    """One argument of an entry point: a scratch array of the entry code (``scratch``), the caller's array
    (``caller``), a baked value (``value``, with its name) or a literal integer (``literal``)."""

    kind: str
    name: str = ""
    value: Any = None
    type: Any = None



def _arg_writer(value: str, literal: Callable[[Any, Any], str], caller: Mapping[str, str],
                scratch: str) -> Callable[[_Arg], str]:
    """How one language writes an entry point's argument (:meth:`_Surface.arguments`): a baked value as
    ``value`` + its name, a literal integer by ``literal``, the caller's array under its name in ``caller``
    (else its own), a scratch array as ``scratch`` + its name."""

    def text(a: _Arg) -> str:
        if a.kind == "value":
            return f"{value}{a.name}"
        if a.kind == "literal":
            return literal(a.value, leaf_types(a.type)[0])
        if a.kind == "caller":
            return caller.get(a.name, a.name)
        return f"{scratch}{a.name}"

    return text


class _Surface:
    """A surface's ground phase translated: the program, its entry points and the values baked in."""

    def __init__(self, surface: Any, *, radius_m: float | None = None, min_apex_m: float = DEFAULT_MIN_APEX_M,
                 max_bounces: int = DEFAULT_MAX_BOUNCES) -> None:
        if isinstance(surface, str):
            surface = preset(surface)
        if not isinstance(surface, Surface):
            raise ParameterError(f"export_surface takes a bouncelab.ground.Surface or a preset name, not "
                                 f"{type(surface).__name__}", parameter="surface", value=type(surface).__name__)
        self.surface = surface
        self.radius = BALL_RADIUS_M if radius_m is None else ball_radius(radius_m)
        if not (isinstance(min_apex_m, int | float) and not isinstance(min_apex_m, bool) and math.isfinite(min_apex_m)
                and min_apex_m > 0):
            raise ParameterError(f"min_apex_m must be a finite number > 0 (metres); got {min_apex_m!r}",
                                 parameter="min_apex_m", value=min_apex_m)
        if isinstance(max_bounces, bool) or not isinstance(max_bounces, int | np.integer) or max_bounces < 1:
            raise ParameterError(f"max_bounces must be a whole number >= 1; got {max_bounces!r}",
                                 parameter="max_bounces", value=max_bounces)
        self.min_apex_m = float(min_apex_m)
        self.max_bounces = int(max_bounces)
        law = surface.law
        self.law = law
        self.law_name = type(law).__name__
        compiled = compiled_lift(law)
        if compiled is None:
            raise ExportError(f"{self.law_name} has no compiled kernel: only a surface whose law's maths is a numba "
                              "kernel (every built-in law, a CompiledLaw of your own) can be exported",
                              law=self.law_name)
        self.lift, args = compiled
        self.plane = "own" if getattr(law, "kernel_3d", None) is not None else lift_plane(law)
        names = list(inspect.signature(law.kernel.py_func).parameters)[3:]
        if len(names) != len(args):
            names = [f"arg{k}" for k in range(len(args))]
        law_args = []
        for name, value in zip(names, args, strict=True):
            try:
                t = value_type(value)
            except TypeError as exc:
                raise ExportError(f"{self.law_name}: the kernel's argument {name!r} is {exc}, which the exported code "
                                  "cannot hold", law=self.law_name) from None
            if isinstance(value, np.ndarray):
                value = np.asarray(value, dtype=np.float64)
                t = value_type(value)
            law_args.append(_Arg("value", f"law_{name}", value, t))
        g = GRAVITY / self.radius  # as ground.run: scaled gravity, apex and rolling resistance
        surface_values = {"keep": surface.pivot_retention, "g": g, "hmin": self.min_apex_m / self.radius,
                          "max_bounces": self.max_bounces, "mu_s": surface.sliding_friction,
                          "mu_r": surface.rolling_resistance}
        sv = {k: _Arg("value", k, v, INT if k == "max_bounces" else FLOAT) for k, v in surface_values.items()}
        guard = {"inv_radius": _Arg("value", "inv_radius", 1.0 / self.radius, FLOAT),
                 "radius": _Arg("value", "radius", self.radius, FLOAT),
                 "limit": _Arg("value", "limit", STATE_LIMIT, FLOAT),
                 "tan_roll": _Arg("value", "tan_roll", 1.4 * surface.rolling_resistance, FLOAT),
                 "tan_skid": _Arg("value", "tan_skid", 3.5 * surface.sliding_friction, FLOAT)}

        def scratch(name: str, *shape: int, dtype: str = FLOAT) -> _Arg:
            return _Arg("scratch", name, None, _arr(*shape, dtype=dtype))

        def caller(name: str) -> _Arg:
            return _Arg("caller", name, None, _arr(3))

        def empty(*shape: int) -> _Arg:
            return _Arg("empty", "", None, _arr(*shape))

        V, W, N = scratch("V", 1, 3), scratch("W", 1, 3), scratch("N", 1, 3)
        args_tuple = _Arg("tuple", "law", law_args, value_type(tuple(a.value for a in law_args)))
        self.calls: dict[str, tuple[Any, list[_Arg]]] = {
            "prepare_run": (prepare_run, [caller("v"), caller("w"), caller("n"), guard["inv_radius"], guard["limit"],
                                          guard["tan_roll"], guard["tan_skid"], V, W, N,
                                          scratch("LANDING", 1, dtype=INT)]),
            "run_rows": (gk.run_loop(self.lift), [
                V, W, N, scratch("LANDING", 1, dtype=INT), args_tuple, sv["keep"], sv["g"], sv["hmin"],
                sv["max_bounces"], empty(0), sv["mu_s"], sv["mu_r"], scratch("OUT", 1, gk.OUT_COLUMNS),
                scratch("COUNTS", 1, 4, dtype=INT), scratch("OFFSETS", 1, dtype=INT), empty(0), empty(0, 3),
                empty(0, 3), empty(0, 3), _Arg("literal", "", 0, INT), _Arg("literal", "", 1, INT)]),
            "finish_run": (finish_run, [scratch("OUT", 1, gk.OUT_COLUMNS), scratch("COUNTS", 1, 4, dtype=INT),
                                        guard["radius"], caller("rest"), _Arg("caller", "time", None, _arr(1))]),
            "prepare_bounce": (prepare_bounce, [caller("v"), caller("w"), caller("n"), guard["inv_radius"],
                                                guard["limit"], V, W, N]),
            "bounce_rows": (gk.bounce_loop(self.lift), [
                V, W, N, sv["keep"], args_tuple, scratch("VF", 1, 3), scratch("WF", 1, 3),
                scratch("FLAGS", 1, 2, dtype=INT), _Arg("literal", "", 0, INT), _Arg("literal", "", 1, INT)]),
            "finish_bounce": (finish_bounce, [scratch("VF", 1, 3), scratch("WF", 1, 3), guard["radius"],
                                              caller("v_out"), caller("w_out")]),
        }
        self.translation = Translation()
        self.entries: dict[str, ir.Function] = {}
        for key, (func, call_args) in self.calls.items():
            if not is_jit_function(func):
                raise ExportError(f"{func!r} is not a jit function", law=self.law_name)
            try:
                self.entries[key] = self.translation.add(func, [a.type for a in call_args])
            except ExportError as exc:
                exc.law = self.law_name
                raise
        self.program = ir.reachable(self.translation.program)
        self.baked: list[_Arg] = [*law_args, *sv.values(), *guard.values()]
        self.scratch: dict[str, ArrayType] = {}
        for _, call_args in self.calls.values():
            for a in call_args:
                if a.kind == "scratch":
                    self.scratch[a.name] = a.type
        kernel = (law.kernel_3d if self.plane == "own" else law.kernel).py_func
        #: The law's kernel the lift calls (for the file's comment).
        self.kernel_name = f"{kernel.__module__}.{kernel.__qualname__}"

    def arguments(self, key: str, text: Any) -> list[str]:
        """The arguments of entry point ``key`` in the order of its IR parameters, as text: ``text(arg)`` for
        each scalar or array (tuples spread, empty arrays left out, as the front end does)."""
        out: list[str] = []

        def add(arg: _Arg) -> None:
            if arg.kind == "empty":
                return
            if arg.kind == "tuple":
                for a in arg.value:
                    add(a)
                return
            out.append(text(arg))

        for arg in self.calls[key][1]:
            add(arg)
        params = self.entries[key].params
        if len(out) != len(params):  # the front end spreads and drops as above: a mismatch is a bug here
            raise ExportError(f"internal: {key} takes {len(params)} values, {len(out)} given")
        return out


def _declare_baked(s: _Surface, name_of: Any, scalar: Any, array: Any, literal: Any) -> list[str]:
    out = []
    for a in s.baked:
        if isinstance(a.type, ArrayType):
            out.append(array(name_of(a.name), a.type, _nested(a.value, literal)))
        else:
            it = leaf_types(a.type)[0]
            out.append(scalar(name_of(a.name), it, literal(a.value, it)))
    return out


# ------------------------------------------------------------------------------------------- public
def export_surface(surface: Any, lang: str, path: str | Path | None = None, *, prefix: str | None = None,
                   class_name: str | None = None, namespace: str | None = None, radius_m: float | None = None,
                   min_apex_m: float = DEFAULT_MIN_APEX_M, max_bounces: int = DEFAULT_MAX_BOUNCES) -> str:
    """A surface's ground phase as C99 (``lang="c"``), JavaScript (``"js"``) or C# (``"cs"``); also written to
    ``path``.

    Parameters
    ----------
    surface
        A :class:`~bouncelab.ground.Surface` (e.g. from :func:`~bouncelab.ground.load_surface`) or a
        preset's name (:data:`bouncelab.ground.surface.PRESET_NAMES`); its law needs a compiled kernel.
    lang
        ``"c"``, ``"js"`` or ``"cs"``.
    path
        File to write (atomically), or None.
    prefix
        C only: the prefix of every name the header defines (default ``"bouncelab_"``).
    class_name, namespace
        C# only: the static class (default ``"BouncelabSurface"``) and its namespace (default: the
        global namespace).
    radius_m
        Ball radius in metres (default 21.35 mm), as ``run(..., radius_m=)``.
    min_apex_m, max_bounces
        The run's options, baked in (defaults: :func:`bouncelab.ground.run`'s). Flights are in vacuum,
        as ``run``'s default (``air=None``); a run with :class:`~bouncelab.ground.Air` is not exported.

    Returns
    -------
    str
        The source text.

    Raises
    ------
    ParameterError
        An unknown ``lang``, surface or preset, a bad name for the language, or a bad option.
    ExportError
        The law has no compiled kernel, or a kernel uses what the translator does not know.
    OutputError
        ``path`` cannot be written; nothing is written then.
    """
    _check_language(lang, prefix, class_name, namespace)
    options = {"radius_m": radius_m, "min_apex_m": min_apex_m, "max_bounces": max_bounces}
    if lang == "c":
        text = surface_c(surface, prefix=DEFAULT_SURFACE_PREFIX if prefix is None else prefix, **options)
    elif lang == "js":
        text = surface_js(surface, **options)
    else:
        text = surface_cs(surface, class_name=DEFAULT_SURFACE_CLASS if class_name is None else class_name,
                          namespace=namespace, **options)
    return _written(text, path, "the exported surface")


# ------------------------------------------------------------------------------------------- C
def surface_c(surface: Any, prefix: str = DEFAULT_SURFACE_PREFIX, **options: Any) -> str:
    """The surface's ground phase as a self-contained C99 header (see :func:`export_surface`)."""
    _check_prefix(prefix, "green_")
    s = _Surface(surface, **options)
    p = prefix
    em = CEmitter(s.program, prefix)
    definitions = em.definitions()
    consts = _declare_baked(s, lambda n: f"{p}p_{n}",
                            lambda n, t, text: f"static const {em.type_name(t)} {n} = {text};",
                            lambda n, t, text: f"static const double {n}{''.join(f'[{k}]' for k in t.shape)} = {text};",
                            c_literal)

    text = _arg_writer(f"{p}p_", c_literal, {"time": "t_rest"}, "")  # a scratch array: a local of the entry point

    def call(key: str) -> str:
        fn = s.entries[key]
        args = s.arguments(key, text)
        written = ir.stores(fn)
        out = []  # a local array given to a read-only parameter of several dimensions: C needs the cast
        for (pname, t), a in zip(fn.params, args, strict=True):
            if isinstance(t, ir.ArrayType) and len(t.shape) > 1 and pname not in written:
                dims = "".join(f"[{k}]" for k in t.shape[1:])
                a = f"(const {em.type_name(t.elem)} (*){dims}){a}"
            out.append(a)
        return f"{em.function_name(fn.name)}({', '.join(out)})"

    def locals_(*names: str) -> str:
        lines = []
        for name in names:
            t = s.scratch[name]
            ctype = "double" if t.dtype == FLOAT else "long long"
            lines.append(f"    {ctype} {name}{''.join(f'[{k}]' for k in t.shape)};")
        return "\n".join(lines)

    codes = ", ".join(f"{p}refused_{_CODE_NAMES[c]} = {c}" for c in REFUSALS)
    refusal_text = "\n".join(f'    case {c}: return "{_c_string(t)}";' for c, t in REFUSALS.items())
    body = f"""#include <math.h>
#include <stdlib.h>

#ifndef BOUNCELAB_API  /* define it as nothing before including to give the entry points external linkage */
#define BOUNCELAB_API static inline
#endif

/* The refusal codes {p}run returns (negative; {p}refusal(code) says what each refuses). */
enum {{ {codes} }};

/* The surface's values, baked in (scaled units inside: ball radii, radii/s, rad/s, seconds). */
{chr(10).join(consts)}

/* ---- the ground phase's kernels, translated from their Python source (bouncelab.export) ---- */

{definitions}

/* ---- entry points ---- */

/* The 3-D bounce of one landing (bouncelab.ground.bounce): velocity v (m/s), spin w (rad/s), ground normal n (any
   length) in; the lift-off's velocity and spin into v_out, w_out. A landing bouncelab.ground.bounce refuses
   (not finite, a zero normal, absurd magnitudes, v . n >= 0) gives NaN in both. */
BOUNCELAB_API void {p}bounce3d(const double v[3], const double w[3], const double n[3], double v_out[3],
                                double w_out[3]) {{
{locals_("V", "W", "N", "VF", "WF", "FLAGS")}
    if ({call("prepare_bounce")} < 0) {{
        v_out[0] = v_out[1] = v_out[2] = NAN;
        w_out[0] = w_out[1] = w_out[2] = NAN;
        return;
    }}
    (void){call("bounce_rows")};
    (void){call("finish_bounce")};
}}

/* One shot from its landing (or from the ground) to rest (bouncelab.ground.run): v (m/s), w (rad/s), n (any
   length) in; the rest position of the ball's lowest point relative to the touch-down point (m) into rest and
   the time from the landing to rest (s) into *t_rest. Returns the number of bounces ({s.max_bounces} means the
   shot was still bouncing after max_bounces and was put on the ground), or a negative refusal code (rest and
   *t_rest are then NaN; {p}refusal(code) says why). */
BOUNCELAB_API int {p}run(const double v[3], const double w[3], const double n[3], double rest[3],
                          double *t_rest) {{
{locals_("V", "W", "N", "LANDING", "OUT", "COUNTS", "OFFSETS")}
    long long code;
    OFFSETS[0] = 0;
    code = {call("prepare_run")};
    if (code == 0) {{
        (void){call("run_rows")};
        code = {call("finish_run")};
    }}
    if (code < 0) {{
        rest[0] = rest[1] = rest[2] = NAN;
        *t_rest = NAN;
    }}
    return (int)code;
}}

/* What a refusal code of {p}run refuses ("" for a number of bounces). */
static inline const char *{p}refusal(int code) {{
    switch (code) {{
{refusal_text}
    default: return "";
    }}
}}
"""
    return _guarded_header(_comment(s, "c", prefix=p), body, p, "SURFACE")


_CODE_NAMES = {NOT_FINITE: "not_finite", ZERO_NORMAL: "zero_normal", NOT_UP: "normal_not_up",
               TOO_FAST: "too_fast", TOO_MUCH_SPIN: "too_much_spin", TOO_STEEP: "too_steep",
               NOT_LANDING: "not_landing", NO_ANSWER: "no_answer"}


# ------------------------------------------------------------------------------------------- JavaScript
def surface_js(surface: Any, **options: Any) -> str:
    """The surface's ground phase as a self-contained ES module (see :func:`export_surface`)."""
    s = _Surface(surface, **options)
    em = JSEmitter(s.program)
    consts = _declare_baked(s, lambda n: f"$p_{n}", lambda n, t, text: f"const {n} = {text};",
                            lambda n, t, text: f"const {n} = {text};", js_literal)

    text = _arg_writer("$p_", js_literal, {"time": "$TIME", "v_out": "vOut", "w_out": "wOut"}, "$")

    def call(key: str, indent: str = "  ") -> str:
        return f"\n{indent}".join(em.entry_call(s.entries[key].name, s.arguments(key, text)))

    scratch = []
    for name, t in s.scratch.items():
        inner = f"new Float64Array({t.shape[-1]})"
        scratch.append(f"const ${name} = {inner if len(t.shape) == 1 else '[' + inner + ']'};")
    prep_run, rows_run, fin_run = call("prepare_run"), call("run_rows"), call("finish_run")
    prep_bounce, rows_bounce, fin_bounce = call("prepare_bounce"), call("bounce_rows"), call("finish_bounce")
    definitions = em.definitions()  # after the calls: the helpers they use are printed too
    refusals = ",\n  ".join(f'"{c}": {_js_string(t)}' for c, t in REFUSALS.items())
    law = s.law
    body = f"""/* The surface's values, baked in (scaled units inside: ball radii, radii/s, rad/s, seconds). */
{chr(10).join(consts)}

/* ---- the ground phase's kernels, translated from their Python source (bouncelab.export) ---- */

{definitions}

/* ---- entry points ---- */

/** The surface's name, its law's class and representation. */
export const SURFACE = {_js_string(s.surface.name)};
export const LAW = {_js_string(type(law).__name__)};
export const LAW_REPR = {_js_string(repr(law))};
/** What each refusal code means (the `code` of the RangeError run and bounce3d throw). */
export const REFUSALS = Object.freeze({{
  {refusals}
}});

// The rows the kernels read and write (one shot; JavaScript runs one call at a time).
{chr(10).join(scratch)}
const $TIME = new Float64Array(1);

function $vector(x, what) {{
  if (x === null || typeof x !== "object" || x.length !== 3) {{
    throw new TypeError(`${{what}} must be an array of 3 numbers (x, y, z); got ${{x}}`);
  }}
}}

function $refused(code, what) {{
  const e = new RangeError(`${{what}} refused (code ${{code}}): ${{REFUSALS[code]}}`);
  e.code = code;
  return e;
}}

/**
 * The 3-D bounce of one landing (bouncelab.ground.bounce): velocity v (m/s), spin w (rad/s) and ground normal n
 * (any length), arrays of 3 numbers, right-handed, z up. Returns [vOut, wOut], the lift-off's velocity (m/s) and
 * spin (rad/s). Throws a RangeError (its `code` a key of REFUSALS) for a landing bouncelab refuses.
 */
export function bounce3d(v, w, n) {{
  $vector(v, "v");
  $vector(w, "w");
  $vector(n, "n");
  {prep_bounce}
  if ($R[0] < 0) throw $refused($R[0], "the landing");
  {rows_bounce}
  const vOut = [0, 0, 0], wOut = [0, 0, 0];
  {fin_bounce}
  return [vOut, wOut];
}}

/**
 * One shot from its landing (or from the ground) to rest (bouncelab.ground.run): v (m/s), w (rad/s), n (any
 * length). Returns {{rest, time, bounces}}: the rest position of the ball's lowest point relative to the
 * touch-down point (m), the time from the landing to rest (s) and the number of bounces ({s.max_bounces}: still
 * bouncing after max_bounces, put on the ground). Throws a RangeError (its `code` a key of REFUSALS) for a
 * shot bouncelab refuses.
 */
export function run(v, w, n) {{
  $vector(v, "v");
  $vector(w, "w");
  $vector(n, "n");
  {prep_run}
  if ($R[0] < 0) throw $refused($R[0], "the shot");
  {rows_run}
  const rest = [0, 0, 0];
  {fin_run}
  if ($R[0] < 0) throw $refused($R[0], "the shot");
  return {{rest, time: $TIME[0], bounces: $R[0]}};
}}
"""
    return f"{_comment(s, 'js')}\n{body}"


# ------------------------------------------------------------------------------------------- C#
_CS_MEMBERS = frozenset({"SurfaceName", "LawName", "MaxBounces", "Bounce3D", "Run", "RefusalText", "Check", "Scratch",
                         "System", "Math", "BitConverter"})


def surface_cs(surface: Any, class_name: str = DEFAULT_SURFACE_CLASS, namespace: str | None = None,
               **options: Any) -> str:
    """The surface's ground phase as a self-contained C# file (see :func:`export_surface`)."""
    _check_cs_names(class_name, namespace, _CS_MEMBERS, "'BouncelabSurface' or 'GreenFast'")
    s = _Surface(surface, **options)
    em = CSharpEmitter(s.program)
    definitions = em.definitions()
    consts = _declare_baked(s, lambda n: f"p_{n}", lambda n, t, text: f"private const {em.type_name(t)} {n} = {text};",
                            lambda n, t, text: f"private static readonly {em.type_name(ir.ArrayType(t.shape))} {n} = "
                                               f"{text};", cs_literal)

    text = _arg_writer("p_", cs_literal, {"time": "s_time", "v_out": "vOut", "w_out": "wOut"}, "s_")

    def call(key: str) -> str:
        return f"{em.function_name(s.entries[key].name)}({', '.join(s.arguments(key, text))})"

    fields, allocs = [], []
    for name, t in s.scratch.items():
        ctype = em.type_name(ir.ArrayType(t.shape, ir.F64 if t.dtype == FLOAT else ir.I64))
        fields.append(f"[ThreadStatic] private static {ctype} s_{name};")
        allocs.append(f"s_{name} = new {ctype.split('[')[0]}[{', '.join(map(str, t.shape))}];")
    fields.append("[ThreadStatic] private static double[] s_time;")
    allocs.append("s_time = new double[1];")
    refusal_text = "\n".join(f"            case {c}: return {_cs_string(t)};" for c, t in REFUSALS.items())
    inner = f"""/// <summary>The ground phase of surface {_xml(s.surface.name)} exported by bouncelab:
/// bouncelab.ground's kernels in C#, the surface's values baked in (SI units; see the comment at the top of the
/// file).</summary>
public static class {{CLASS}} {{
    /// <summary>The surface's name in bouncelab.</summary>
    public const string SurfaceName = {_cs_string(s.surface.name)};
    /// <summary>The class of the surface's bounce law in bouncelab.</summary>
    public const string LawName = {_cs_string(s.law_name)};
    /// <summary>Bounces after which Run puts a shot on the ground whatever its lift-off.</summary>
    public const int MaxBounces = {s.max_bounces};

    // The surface's values, baked in (scaled units inside: ball radii, radii/s, rad/s, seconds).
{textwrap.indent(chr(10).join(consts), '    ')}

    // ---- the ground phase's kernels, translated from their Python source (bouncelab.export) ----

{textwrap.indent(definitions, '    ')}

    // ---- entry points ----

    // The rows the kernels read and write: one set per thread, made on a thread's first call.
{textwrap.indent(chr(10).join(fields), '    ')}

    private static void Scratch() {{
        if (s_V != null) return;
{textwrap.indent(chr(10).join(allocs), '        ')}
    }}

    private static void Check(double[] x, string name) {{
        if (x == null) throw new ArgumentNullException(name);
        if (x.Length != 3) {{
            throw new ArgumentException(name + " must hold 3 numbers (x, y, z); it holds " + x.Length, name);
        }}
    }}

    /// <summary>The 3-D bounce of one landing (bouncelab.ground.bounce): velocity v (m/s), spin w (rad/s) and
    /// ground normal n (any length) in, right-handed, z up; the lift-off's velocity (m/s) and spin (rad/s) into
    /// vOut and wOut. Throws an ArgumentException for a landing bouncelab refuses (RefusalText says
    /// why).</summary>
    public static void Bounce3D(double[] v, double[] w, double[] n, double[] vOut, double[] wOut) {{
        Check(v, "v");
        Check(w, "w");
        Check(n, "n");
        Check(vOut, "vOut");
        Check(wOut, "wOut");
        Scratch();
        long code = {call("prepare_bounce")};
        if (code < 0) throw new ArgumentException("the landing is refused: " + RefusalText((int)code), "v");
        {call("bounce_rows")};
        {call("finish_bounce")};
    }}

    /// <summary>One shot from its landing (or from the ground) to rest (bouncelab.ground.run): v (m/s), w (rad/s),
    /// n (any length) in; the rest position of the ball's lowest point relative to the touch-down point (m) into
    /// rest and the time from the landing to rest (s) into time. Returns the number of bounces (MaxBounces: the
    /// shot was still bouncing and was put on the ground), or a negative refusal code (rest and time are then
    /// NaN; RefusalText says why). Allocates nothing after a thread's first call.</summary>
    public static int Run(double[] v, double[] w, double[] n, double[] rest, out double time) {{
        Check(v, "v");
        Check(w, "w");
        Check(n, "n");
        Check(rest, "rest");
        Scratch();
        s_OFFSETS[0] = 0;
        long code = {call("prepare_run")};
        if (code == 0) {{
            {call("run_rows")};
            code = {call("finish_run")};
        }}
        if (code < 0) {{
            rest[0] = rest[1] = rest[2] = double.NaN;
            time = double.NaN;
        }} else {{
            time = s_time[0];
        }}
        return (int)code;
    }}

    /// <summary>What a refusal code of Run refuses ("" for a number of bounces).</summary>
    public static string RefusalText(int code) {{
        switch (code) {{
{refusal_text}
            default: return "";
        }}
    }}
}}
""".replace("{CLASS}", class_name)
    code = inner if namespace is None else f"namespace {namespace} {{\n\n{textwrap.indent(inner, '    ')}}}\n"
    code = "\n".join(line.rstrip() for line in code.split("\n"))
    usings = "".join(f"using {u};\n" for u in em.usings)
    return f"{_comment(s, 'cs', class_name=class_name)}\n{usings}\n{code}"


# ------------------------------------------------------------------------------------------- the comment
def _comment(s: _Surface, lang: str, *, prefix: str = DEFAULT_SURFACE_PREFIX,
             class_name: str = DEFAULT_SURFACE_CLASS) -> str:
    from bouncelab.core import __version__

    surface, law = s.surface, s.law
    lines: list[str] = []

    def para(text: str = "", indent: str = "") -> None:
        if not text:
            lines.append("")
            return
        lines.extend(textwrap.wrap(text, 100, initial_indent=indent, subsequent_indent=indent + "  ",
                                   break_on_hyphens=False, break_long_words=False))

    what = {"c": "a C99 header", "js": "an ES module", "cs": "a C# class"}[lang]
    para(f"The ground phase of surface {surface.name!r}, exported as {what} by bouncelab {__version__} "
         "(bouncelab.export): the 3-D bounce of bouncelab.ground.bounce and the run to rest of bouncelab.ground.run.")
    para(f"Surface: {surface!r}")
    if surface.description:
        para(f"Provenance: {surface.description}")
    para("The code is bouncelab.ground's own compiled kernels (bouncelab.ground._kernels: bounce_rows, run_rows and "
         f"everything they call: the law's lift to 3-D with its kernel {s.kernel_name}, flights, skid and roll) "
         "and the input checks of bouncelab.export.ground, translated operation by operation from their Python "
         "source (bouncelab.export); the values below are baked in.")
    para()
    para("CONVENTIONS")
    para("SI units: velocities in m/s, spins in rad/s (the angular-velocity vector), lengths in metres, times in "
         "seconds. Right-handed axes, z up; gravity (0, 0, -9.81 m/s^2). n is the ground's normal (any length, "
         "normalised here; z > 0 for a run). Backspin for a ball travelling in +x is a negative y spin. The ball "
         "touches the ground at the origin at time 0; positions are those of its lowest point.", "  ")
    para(f"Ball radius R = {s.radius!r} m (scaled units inside: v / R in radii/s).", "  ")
    para()
    para("THE SURFACE (baked in)")
    para(f"Law: {law!r} ({s.law_name}), lifted to 3-D as bouncelab.ground does it: "
         + {"own": "its own 3-D kernel (kernel_3d) in the plane of travel",
            "travel": "its 2-D law in the plane of travel",
            "slip": "its 2-D law in the plane of the contact point's slip"}[s.plane] + ".", "  ")
    para(f"Sliding friction mu_s = {surface.sliding_friction!r}; Stimpmeter {surface.stimp_m:.6g} m "
         f"({surface.stimp_ft:.4g} ft): rolling resistance mu_r = {surface.rolling_resistance!r} "
         f"(1.83^2 / (2 g stimp)); pivot retention {surface.pivot_retention!r} (the fraction of the spin about n a "
         "bounce keeps).", "  ")
    para(f"Run options (bouncelab.ground.run's defaults unless given to the export): min_apex_m = {s.min_apex_m!r} "
         f"(a lift-off rising less along n ends the bounces), max_bounces = {s.max_bounces}. Flights are in vacuum "
         "(run's default air=None: no drag or lift; a run with bouncelab.ground.Air is not exported).", "  ")
    para(f"Steepest slope a ball comes to rest on: {surface.max_slope_deg():.6g} degrees; steeper ground is refused.",
         "  ")
    para()
    para("REFUSALS (the same checks as bouncelab.ground's, in its order)")
    for c, t in REFUSALS.items():
        para(f"{c} {_CODE_NAMES[c]}: {t}", "  ")
    para()
    para("FLOATING POINT")
    if lang == "c":
        para("Compile with -ffp-contract=off and without -ffast-math (e.g. cc -std=c99 -O2 -ffp-contract=off main.c "
             "-lm): the results are then bouncelab's to the bit (its tests check the bounce to 1e-12 and the rest "
             "position to 1e-9 m on 2,000 landings on slopes up to 2.5 degrees, on three surfaces).", "  ")
    elif lang == "cs":
        para("C# doubles are IEEE doubles; the code assumes that the runtime does not fuse multiply-adds or keep "
             "extended precision (.NET and Mono on x86-64 and ARM64 do neither; in an IL2CPP build keep the C++ "
             "compiler from contracting). Math.Sqrt is correctly rounded; Math.Sin, Math.Cos... are the runtime's. "
             "bouncelab's tests compile the file with Mono's mcs and check it under mono against bouncelab.", "  ")
    else:
        para("JavaScript numbers are IEEE doubles and engines do not fuse operations, so the arithmetic is "
             "bouncelab's; Math.sqrt is correctly rounded. bouncelab's tests check the module under Node against "
             "bouncelab.", "  ")
    para()
    para("ENTRY POINTS")
    if lang == "c":
        p = prefix
        para(f"void {p}bounce3d(const double v[3], const double w[3], const double n[3], double v_out[3], "
             "double w_out[3]): one bounce (NaN out for a refused landing).", "  ")
        para(f"int {p}run(const double v[3], const double w[3], const double n[3], double rest[3], double *t_rest): "
             f"one shot to rest; the number of bounces, or a negative refusal code ({p}refusal(code) names it).", "  ")
        para(f"Every name this header defines starts with {p!r} (bouncelab export --prefix NAME): give each surface "
             "(and each law) of one program its own. C99; C++ compilers accept it too. Thread-safe (no state). The "
             "entry points are static inline unless BOUNCELAB_API is defined (e.g. as nothing) first.", "  ")
    elif lang == "cs":
        c = class_name
        para(f"void {c}.Bounce3D(double[] v, double[] w, double[] n, double[] vOut, double[] wOut): one bounce "
             "(an ArgumentException for a refused landing).", "  ")
        para(f"int {c}.Run(double[] v, double[] w, double[] n, double[] rest, out double time): one shot to rest; "
             f"the number of bounces, or a negative refusal code ({c}.RefusalText(code) names it).", "  ")
        para(f"One public static class, {c} (bouncelab export --class-name NAME, --namespace NAME), plain C# with "
             "System.Math only: Unity, Godot and Mono compile it. Thread-safe (scratch rows per thread).", "  ")
    else:
        para("bounce3d(v, w, n) -> [vOut, wOut]; run(v, w, n) -> {rest, time, bounces}; v, w, n arrays of 3 "
             "numbers. A refused input throws a RangeError whose code is a key of REFUSALS.", "  ")
    text = "\n".join(" *" + (" " + line if line else "") for line in lines).replace("*/", "* /")
    return f"/*\n{text}\n */"
