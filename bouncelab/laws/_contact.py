"""Shared machinery of the contact laws: prediction with a different parameter vector per bounce.

:func:`predict_per_bounce` evaluates a compiled law's kernel on ``n`` landings
with ``n`` parameter rows (spot-to-spot variation of a surface, simulated
campaigns). The kernel is the law's own, so each row gives exactly what
``law.replace(**row).predict(landing_row)`` gives, without building ``n`` laws.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab._parallel import run_rows
from bouncelab.data.validation import as_states
from bouncelab.errors import ParameterError

__all__ = ["predict_per_bounce"]


def _numbers(values: Any, what: str) -> np.ndarray:
    """``values`` as a float array, or a ParameterError naming ``what`` (text, None, objects)."""
    arr = np.asarray(values)
    if arr.dtype.kind not in "iuf":
        raise ParameterError(f"{what} must be numbers; got values of type {arr.dtype}")
    return arr.astype(float)

_ROW_LOOPS: dict[int, tuple[Any, Any]] = {}


def _row_loop(kernel: Any) -> Any:
    hit = _ROW_LOOPS.get(id(kernel))
    if hit is not None and hit[0] is kernel:
        return hit[1]
    from bouncelab._jit import jit

    @jit(nogil=True)
    def loop(P, T, out, codes, start, stop):  # pragma: no cover - compiled
        for i in range(start, stop):
            a, b, c, k = kernel(P[i, 0], P[i, 1], P[i, 2], T[i])
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
            codes[i] = k

    _ROW_LOOPS[id(kernel)] = (kernel, loop)
    return loop


def predict_per_bounce(law: Any, landing: Any, params: Any, *, codes: bool = False, kernel: Any = None) -> Any:
    """Lift-off states of ``n`` landings, each with its own parameter values.

    Parameters
    ----------
    law : CompiledLaw subclass or instance
        A law with scalar parameters whose kernel takes its parameter vector as
        is (e.g. :class:`~bouncelab.laws.turf.TurfContact`), or an instance of one that
        converts them first (its options, e.g. CraterContact's ``fade_xdot``, are used).
        An instance's parameter values are not used.
    landing : array-like, shape (n, 3)
        Landing states ``[xdot0, ydot0, omega0]`` in scaled units (validated as by ``predict``).
    params : array-like, shape (n, k) or (k,), or a mapping name -> array of length n
        One row of the law's ``k`` parameters per landing, in the order of
        ``parameter_specs`` (a single row is broadcast); or a mapping (a dict, a
        DataFrame) naming exactly the law's parameters, each one value or one per
        landing, read by name. Each value must be a finite number within its
        parameter's physical range.
    codes : bool
        Also return the int8 regime code of each bounce.
    kernel : numba function, optional
        The law's kernel, when the class loads it lazily (a property).

    Returns
    -------
    numpy.ndarray, shape (n, 3)
        Lift-off states (and the regime codes if ``codes``).
    """
    from bouncelab.laws.compiled import CompiledLaw

    cls = law if isinstance(law, type) else type(law)
    converts = cls._kernel_theta is not CompiledLaw._kernel_theta
    if converts and isinstance(law, type):
        # its options (e.g. CraterContact's fade_xdot) live on an instance, which converts each row
        raise ParameterError(f"{cls.__name__} converts its parameters before its kernel; pass an instance, "
                             "whose options are used")
    if kernel is None:
        kernel = law.kernel if converts else getattr(cls, "kernel", None)
    if kernel is None or isinstance(kernel, property):
        raise ParameterError(f"{cls.__name__} has no class-level compiled kernel; predict_per_bounce needs one")
    specs = cls.parameter_specs
    if any(s.shape != () for s in specs):
        raise ParameterError(f"{cls.__name__} has array parameters; predict_per_bounce takes scalar ones")
    p, _ = as_states(landing, "landing", landing=True)
    p = np.ascontiguousarray(p.reshape(-1, 3), dtype=np.float64)
    n = len(p)
    names = [s.name for s in specs]
    if isinstance(params, Mapping) or hasattr(params, "columns"):  # by name: a dict, a DataFrame, ...
        keys = list(params.keys())
        missing = [k for k in names if k not in keys]
        unknown = [k for k in keys if k not in names]
        if missing or unknown:
            raise ParameterError(f"{cls.__name__}: params must name exactly its parameters {names}"
                                 + (f"; missing {missing}" if missing else "")
                                 + (f"; unknown {unknown} (options are not per bounce)" if unknown else ""))
        cols = []
        for k in names:
            col = _numbers(params[k], f"{cls.__name__}: parameter {k!r}")
            if col.ndim > 1 or col.size not in (1, n):
                raise ParameterError(f"{cls.__name__}: parameter {k!r} needs one value or one per landing ({n}); "
                                     f"got shape {col.shape}")
            cols.append(np.broadcast_to(col.reshape(-1), (n,)))
        T = np.column_stack(cols) if n else np.empty((0, len(specs)))
    else:
        T = _numbers(params, f"{cls.__name__}: params")
        if T.ndim == 1:
            T = np.broadcast_to(T, (n, T.shape[0]))
        if T.ndim != 2 or T.shape != (n, len(specs)):
            raise ParameterError(f"{cls.__name__}: params must have shape ({n}, {len(specs)}) in the order "
                                 f"{names}; got {T.shape}")
    T = np.ascontiguousarray(T, dtype=np.float64)
    for j, s in enumerate(specs):
        col = T[:, j]
        lo, hi = s.physical
        if not np.isfinite(col).all():
            i = int(np.flatnonzero(~np.isfinite(col))[0])
            raise ParameterError(f"{cls.__name__}: parameter {s.name!r} of row {i} must be finite; got {col[i]}")
        bad = (col < lo) | (col > hi)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ParameterError(f"{cls.__name__}: parameter {s.name!r} of row {i} is {col[i]:g}, "
                                 f"outside its physical range [{lo}, {hi}]")
    if converts and n:
        T = np.ascontiguousarray(np.stack([law._kt(row) for row in T]))
    out = np.empty_like(p)
    c = np.empty(n, dtype=np.int8)
    if n:  # rows are independent: large calls are shared by the thread pool (results do not depend on it)
        run_rows(_row_loop(kernel), n, p, T, out, c)
    return (out, c) if codes else out
