"""Prediction with different parameter values for each bounce (spot-to-spot variation of a surface).

:func:`predict_per_bounce` evaluates a law on ``n`` landings with ``n`` rows of parameter values, each row
giving exactly what ``law.replace(**row).predict(landing_row)`` gives, without building ``n`` laws: for a
compiled law with scalar parameters in one compiled loop (its own kernel, a row of arguments per bounce);
for any other law one evaluation per distinct row. Every law has it as ``Law.predict_varying`` (on the class:
the options' defaults; on a law: its options).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.core._jit import ROW_FLAGS, jit
from bouncelab.core._parallel import run_rows
from bouncelab.core.errors import ParameterError, row_text
from bouncelab.core.validation import as_states
from bouncelab.laws.registry import law_name

__all__ = ["predict_per_bounce"]

_ROW_LOOPS: dict[tuple[int, int], tuple[Any, Any]] = {}


def _numbers(values: Any, what: str, law: str, parameter: str | None = None) -> np.ndarray:
    """``values`` as a float array, or a ParameterError naming ``what`` (text, None, objects)."""
    arr = np.asarray(values)
    if arr.dtype.kind not in "iuf":
        raise ParameterError(f"{what} must be numbers; got values of type {arr.dtype}", law=law, parameter=parameter)
    return arr.astype(float)


def _row_loop(kernel: Any, m: int) -> Any:
    """The compiled loop calling ``kernel`` on landing row ``i`` with the ``m`` arguments of row ``i`` of K."""
    hit = _ROW_LOOPS.get((id(kernel), m))
    if hit is not None and hit[0] is kernel:
        return hit[1]
    from numba.np.unsafe.ndarray import to_fixed_tuple  # (numba: imported when a loop is first built)

    @jit(nogil=True, fastmath=ROW_FLAGS)
    def loop(P, K, out, codes, start, stop):  # pragma: no cover - compiled
        for i in range(start, stop):
            a, b, c, k = kernel(P[i, 0], P[i, 1], P[i, 2], *to_fixed_tuple(K[i], m))
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
            codes[i] = k

    _ROW_LOOPS[(id(kernel), m)] = (kernel, loop)
    return loop


def _carrier(law: Any) -> Any:
    """An instance of ``law`` whose options are used (a class: placeholder values inside the search box)."""
    if not isinstance(law, type):
        return law
    values = {}
    for s in law.parameter_specs:
        lo, hi = s.bound_arrays()
        mid = 0.5 * (lo + hi)
        values[s.name] = float(mid[0]) if s.is_scalar else mid.reshape(s.shape)
    return law(**values)


def predict_per_bounce(law: Any, landing: Any, params: Any, *, codes: bool = False) -> Any:
    """Lift-off states of ``n`` landings, each with its own parameter values.

    Parameters
    ----------
    law : law class or instance
        The law; an instance's options (e.g. CraterContact's ``fade_xdot``) are used, its parameter values
        are not; a class's options are their defaults.
    landing : array-like, shape (n, 3)
        Landing states ``[xdot0, ydot0, omega0]`` in scaled units (validated as by ``predict``, with no unit
        guard: these are a simulation's states).
    params : array-like, shape (n, k) or (k,), or a mapping name -> array of length n
        One row of the law's ``k`` numbers per landing, in declaration order (array parameters by element,
        in C order; a single row is broadcast); or a mapping (a dict, a DataFrame) naming exactly the law's
        parameters, each one value or one per landing, read by name. Each value must be a finite number
        within its parameter's physical range.
    codes : bool
        Also return the int8 regime code of each bounce.

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        Lift-off states (and the regime codes if ``codes``).

    Raises
    ------
    ParameterError
        Parameters missing, unknown, of the wrong shape, not finite or outside their physical ranges (naming
        the parameter and the row, with a DataFrame's row label).
    """
    carrier = _carrier(law)
    cls = type(carrier)
    name = law_name(cls)
    specs = cls.parameter_specs
    p, _ = as_states(landing, "landing", landing=True)
    p = np.ascontiguousarray(p.reshape(-1, 3), dtype=np.float64)
    n = len(p)
    keys = [s.name for s in specs]
    elements = [e for s in specs for e in s.element_names()]
    if isinstance(params, Mapping) or hasattr(params, "columns"):  # by name: a dict, a DataFrame, ...
        given = list(params.keys())
        missing = [k for k in keys if k not in given]
        unknown = [k for k in given if k not in keys]
        if missing or unknown:
            raise ParameterError(f"{name}: params must name exactly its parameters {keys}"
                                 + (f"; missing {missing}" if missing else "")
                                 + (f"; unknown {unknown} (options are not per bounce)" if unknown else ""),
                                 law=name, parameter=(missing or unknown)[0])
        cols = []
        for s in specs:
            col = _numbers(params[s.name], f"{name}: parameter {s.name!r}", name, s.name)
            if not s.is_scalar:
                col = col.reshape(-1, s.size) if col.size != s.size else col.reshape(1, s.size)
            elif col.ndim > 1 or col.size not in (1, n):
                raise ParameterError(f"{name}: parameter {s.name!r} needs one value or one per landing ({n}); "
                                     f"got shape {col.shape}", law=name, parameter=s.name)
            cols.append(np.broadcast_to(col.reshape(len(col) if col.ndim else 1, -1), (n, s.size)))
        T = np.concatenate(cols, axis=1) if n else np.empty((0, len(elements)))
    else:
        T = _numbers(params, f"{name}: params", name, "params")
        if T.ndim == 1:
            T = np.broadcast_to(T, (n, T.shape[0]))
        if T.ndim != 2 or T.shape != (n, len(elements)):
            raise ParameterError(f"{name}: params must have shape ({n}, {len(elements)}) in the order "
                                 f"{elements}; got {T.shape}", law=name, parameter="params")
    T = np.ascontiguousarray(T, dtype=np.float64)
    frame = params if hasattr(params, "columns") and hasattr(params, "index") else landing

    def row(i: int) -> str:  # 1-based, as DataError's rows; with the caller's index label for a DataFrame
        return row_text(i + 1, frame.index[i] if hasattr(frame, "columns") and len(frame.index) == n else None)

    col = 0
    for s in specs:
        lo, hi = s.physical_arrays()
        for k, element in enumerate(s.element_names()):
            values = T[:, col]
            if not np.isfinite(values).all():
                i = int(np.flatnonzero(~np.isfinite(values))[0])
                raise ParameterError(f"{name}: parameter {element!r} of {row(i)} must be finite; got {values[i]}",
                                     law=name, parameter=element, value=float(values[i]))
            bad = (values < lo[k]) | (values > hi[k])
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                raise ParameterError(f"{name}: parameter {element!r} of {row(i)} is {values[i]:g}, outside its "
                                     f"physical range [{lo[k]:g}, {hi[k]:g}]", law=name, parameter=element,
                                     value=float(values[i]))
            col += 1
    out = np.empty_like(p)
    code = np.empty(n, dtype=np.int8)
    kernel = getattr(carrier, "kernel", None)  # a compiled law's (a numba function keeps its Python one)
    if n and hasattr(kernel, "py_func") and all(s.is_scalar for s in specs):
        # the kernel's arguments of every row at once (a law's _kernel_args works on columns too)
        args = carrier._kernel_args(**{k: T[:, j] for j, k in enumerate(keys)})
        K = np.ascontiguousarray(np.column_stack([np.broadcast_to(np.asarray(a, dtype=np.float64), (n,))
                                                  for a in args]))
        run_rows(_row_loop(kernel, K.shape[1]), n, p, K, out, code)
    elif n:
        sizes = np.cumsum([0] + [s.size for s in specs])
        uniq, inverse = np.unique(T, axis=0, return_inverse=True)
        for j, numbers in enumerate(uniq):  # one evaluation per distinct row of values
            rows = np.flatnonzero(inverse.ravel() == j)
            values = {s.name: float(numbers[a]) if s.is_scalar else numbers[a:b].reshape(s.shape)
                      for s, a, b in zip(specs, sizes[:-1], sizes[1:], strict=True)}
            out[rows] = carrier._evaluate(p[rows], values)
            code[rows] = carrier._classify(p[rows], values)
    return (out, code) if codes else out
