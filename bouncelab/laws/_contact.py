"""Shared machinery of the contact laws: prediction with a different parameter vector per bounce, restitution.

:func:`predict_per_bounce` evaluates a compiled law's kernel on ``n`` landings
with ``n`` parameter rows (spot-to-spot variation of a surface, simulated
campaigns). The kernel is the law's own, so each row gives exactly what
``law.replace(**row).predict(landing_row)`` gives, without building ``n`` laws.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from bouncelab.core._parallel import run_rows
from bouncelab.core.errors import DataError, ParameterError, row_text
from bouncelab.core.validation import as_states

__all__ = ["check_speeds", "kernel_rows", "predict_per_bounce", "restitution_line", "run_kernel_rows",
           "vertical_restitution"]

_ROW_LOOPS: dict[int, tuple[Any, Any]] = {}


def _numbers(values: Any, what: str) -> np.ndarray:
    """``values`` as a float array, or a ParameterError naming ``what`` (text, None, objects)."""
    arr = np.asarray(values)
    if arr.dtype.kind not in "iuf":
        raise ParameterError(f"{what} must be numbers; got values of type {arr.dtype}")
    return arr.astype(float)


def _row_loop(kernel: Any) -> Any:
    """The compiled loop calling ``kernel`` on landing row ``i`` with kernel-vector row ``i`` (cached per kernel)."""
    hit = _ROW_LOOPS.get(id(kernel))
    if hit is not None and hit[0] is kernel:
        return hit[1]
    from bouncelab.core._jit import jit

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


def kernel_rows(law: Any, theta: np.ndarray) -> np.ndarray:
    """The kernel's vector of each row of parameter vectors ``theta`` (n, k): ``law._kt`` row by row.

    Unchanged (as contiguous float64) for a law (class or instance) whose kernel takes its
    parameters as they are; a law that converts them must be an instance (its options are used).
    """
    from bouncelab.laws.compiled import CompiledLaw

    theta = np.ascontiguousarray(theta, dtype=np.float64)
    cls = law if isinstance(law, type) else type(law)
    if cls._kernel_theta is CompiledLaw._kernel_theta or not len(theta):
        return theta
    return np.ascontiguousarray(np.stack([law._kt(row) for row in theta]))


def run_kernel_rows(kernel: Any, landing: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lift-offs (n, 3) and regime codes (n,) of ``kernel`` on each landing with its own kernel vector.

    Rows are independent: large calls are shared by the thread pool, and the results do not depend on it.
    """
    out = np.empty_like(landing)
    codes = np.empty(len(landing), dtype=np.int8)
    if len(landing):
        run_rows(_row_loop(kernel), len(landing), landing, rows, out, codes)
    return out, codes


def check_speeds(values: Any, name: str, *, positive: bool) -> np.ndarray:
    """``values`` as a 1-d float array of finite speeds (radii/s), or a DataError naming ``name``."""
    arr = np.atleast_1d(np.asarray(values))
    if arr.dtype.kind not in "iuf":
        raise DataError(f"{name} must be numbers of radii/s; got values of type {arr.dtype}")
    arr = arr.astype(float).reshape(-1)
    bad = ~np.isfinite(arr) | ((arr <= 0) if positive else False)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        need = "a positive, finite" if positive else "a finite"
        raise DataError(f"{name} must be {need} number of radii/s; element {i} is {arr[i]}")
    return arr


def vertical_restitution(law: Any, speed: Any) -> np.ndarray:
    """Normal restitution |ydotF / ydot0| of ``law`` for vertical, spinless landings at ``speed`` radii/s.

    Raises
    ------
    DataError
        A speed that is not a positive, finite number (element named).
    """
    s = check_speeds(speed, "speed", positive=True)
    land = np.column_stack([np.zeros_like(s), -s, np.zeros_like(s)])
    return law.predict(land, plausible=None)[:, 1] / s  # the law's maths at any speed asked


def restitution_line(law: Any) -> str:
    """The fit report's line on a contact law's restitution at 200 / 500 / 900 radii/s."""
    r = vertical_restitution(law, [200.0, 500.0, 900.0])
    return f"restitution of vertical landings at 200 / 500 / 900 radii/s: {r[0]:.3f} / {r[1]:.3f} / {r[2]:.3f}"


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
        kernel = getattr(law, "kernel", None)  # an instance's own; a class's only if it is class-level
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
    frame = params if hasattr(params, "columns") and hasattr(params, "index") else landing

    def row(i: int) -> str:  # 1-based, as DataError's rows; with the caller's index label for a DataFrame
        return row_text(i + 1, frame.index[i] if hasattr(frame, "columns") and len(frame.index) == n else None)

    for j, s in enumerate(specs):
        col = T[:, j]
        lo, hi = s.physical
        if not np.isfinite(col).all():
            i = int(np.flatnonzero(~np.isfinite(col))[0])
            raise ParameterError(f"{cls.__name__}: parameter {s.name!r} of {row(i)} must be finite; got {col[i]}")
        bad = (col < lo) | (col > hi)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise ParameterError(f"{cls.__name__}: parameter {s.name!r} of {row(i)} is {col[i]:g}, "
                                 f"outside its physical range [{lo}, {hi}]")
    out, c = run_kernel_rows(kernel, p, kernel_rows(law, T))
    return (out, c) if codes else out
