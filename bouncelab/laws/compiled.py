r"""Compiled laws: write the bounce of one ball as a numba function, get fast array loops for free.

A law whose mathematics is a scalar function of one landing subclasses :class:`CompiledLaw` and sets
``kernel``, a ``numba.njit`` function of one landing and the law's parameters, by name and in
declaration order:

.. code-block:: python

    kernel(xdot0, ydot0, omega0, r, mu) -> (xdotF, ydotF, omegaF, regime_code)

``regime_code`` is an integer index into the law's ``regimes``. Any number of parameters, scalar or
array (an array parameter arrives as a read-only array of its shape), and of regimes. A law whose kernel
needs more than its parameters (an option, a constant computed from a parameter) overrides
:meth:`CompiledLaw._kernel_args`, which receives the parameters by name and returns what the kernel
takes after the landing; the constants of a law are then computed once per law, not per call.

From the kernel, :class:`CompiledLaw` builds three compiled loops (prediction, regimes, and the
fitter's one-pass sums of the error terms, :meth:`~bouncelab.BounceModel._error_function`) and
caches them on disk. The loops release the GIL and run serially over fixed chunks of :data:`CHUNK`
bounces; from :data:`PARALLEL_MIN` bounces the chunks are shared by a small thread pool. Hence:

* results are bit-identical whatever the batch size, a bounce's position in it and
  the number of threads, and on any x86-64 CPU (every bounce goes through the same
  compiled code, which allows no floating-point freedom that could change a finite
  result, :data:`bouncelab.core._jit.ROW_FLAGS`; the error sums add the bounces in row
  order and the chunks' partial sums in a fixed order);
* prediction is safe under ``fork``, ``spawn`` and threads: no OpenMP or TBB
  runtime is involved, and a forked child starts a fresh pool;
* the number of threads is the number of CPUs this process may use, or
  ``BOUNCELAB_NUM_THREADS``, or :func:`set_num_threads`.

Examples
--------
A frictionless bounce with restitution ``e``:

>>> from numba import njit
>>> import bouncelab as bl
>>> @njit
... def frictionless(xd, yd, w, e):
...     return xd, -e * yd, w, 0
>>> class Frictionless(bl.CompiledLaw):
...     '''pF = [xdot0, -e ydot0, omega0].'''
...     e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
...     regimes = ("bounce",)
...     kernel = frictionless
>>> Frictionless(e=0.5).predict([[100.0, -200.0, 30.0]])
array([[100., 100.,  30.]])
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar

import numpy as np

from bouncelab.core._parallel import CHUNK, PARALLEL_MIN, num_threads, run_chunked, run_rows, set_num_threads
from bouncelab.core.errors import LawDefinitionError
from bouncelab.core.validation import STATE_LIMIT
from bouncelab.laws.base import BounceModel
from bouncelab.laws.registry import law_name

__all__ = ["CHUNK", "PARALLEL_MIN", "CompiledLaw", "num_threads", "run_chunked", "run_rows", "set_num_threads"]


# ------------------------------------------------------------------------------ loops per kernel
class _Loops:
    """The compiled array loops built around one kernel (its arguments after the landing come as a tuple)."""

    def __init__(self, kernel: Any) -> None:
        from bouncelab.core._jit import ROW_FLAGS, jit
        from bouncelab.laws._kernels import valid_bits as _valid_bits

        # The row loops also report whether every landing in their rows is valid (finite, within
        # the limit, ydot < 0): for large arrays the public methods fuse that check into this pass
        # instead of reading the array once more (see bouncelab.core.validation, defer_check). The
        # check reads the values' bits as integers (``bits`` is a view of P), which fast-math
        # assumptions about NaN and infinity cannot touch.
        @jit(nogil=True, fastmath=ROW_FLAGS)
        def predict_rows(P, args, out, bits, limit_bits, start, stop):
            ok = True
            for i in range(start, stop):
                ok = ok & _valid_bits(bits[i, 0], bits[i, 1], bits[i, 2], limit_bits)
                a, b, c, _ = kernel(P[i, 0], P[i, 1], P[i, 2], *args)
                out[i, 0] = a
                out[i, 1] = b
                out[i, 2] = c
            return ok

        @jit(nogil=True, fastmath=ROW_FLAGS)
        def regime_rows(P, args, codes, bits, limit_bits, start, stop):
            ok = True
            for i in range(start, stop):
                ok = ok & _valid_bits(bits[i, 0], bits[i, 1], bits[i, 2], limit_bits)
                codes[i] = kernel(P[i, 0], P[i, 1], P[i, 2], *args)[3]
            return ok

        # A plain sum in row order: with no "reassoc" the compiler keeps that order, so the sums (and so
        # every fit) are the same bits on any CPU, whatever its vector width.
        @jit(nogil=True, fastmath=ROW_FLAGS)
        def error_sums(P0, PF, inv_norm, args, start, stop):
            sd = 0.0
            sx = 0.0
            sy = 0.0
            sw = 0.0
            for i in range(start, stop):
                a, b, c, _ = kernel(P0[i, 0], P0[i, 1], P0[i, 2], *args)
                ex = PF[i, 0] - a
                ey = PF[i, 1] - b
                ew = PF[i, 2] - c
                g = inv_norm[i]
                sd += math.sqrt(ex * ex + ey * ey + ew * ew) * g
                sx += abs(ex) * g
                sy += abs(ey) * g
                sw += abs(ew) * g
            return sd, sx, sy, sw

        self.predict_rows = predict_rows
        self.regime_rows = regime_rows
        self.error_sums = error_sums


def landing_bits(p: np.ndarray) -> tuple[np.ndarray, int]:
    """The landings' bits as int64 (a view) and the bits of STATE_LIMIT, for the fused value check."""
    return p.view(np.int64), int(np.float64(STATE_LIMIT).view(np.int64))


_LOOPS: dict[int, tuple[Any, _Loops]] = {}
_LOOPS_LOCK = threading.Lock()


def loops_for(kernel: Any) -> _Loops:
    """The compiled loops around ``kernel`` (built once per kernel and process)."""
    with _LOOPS_LOCK:
        hit = _LOOPS.get(id(kernel))
        if hit is None or hit[0] is not kernel:
            hit = (kernel, _Loops(kernel))
            _LOOPS[id(kernel)] = hit
        return hit[1]


# ------------------------------------------------------------------------------ the law class
class CompiledLaw(BounceModel):
    """A law evaluated by a compiled scalar ``kernel`` (see the module documentation).

    Subclasses set the class attribute ``kernel`` and, like every law, declare their parameters and
    ``regimes``. They may override :meth:`_kernel_args` to give the kernel more than the parameters.
    Prediction, regimes and the fitter's objective then run compiled; fitting, comparison, reports and
    JSON work as for any law.
    """

    #: ``numba.njit`` function ``(xdot0, ydot0, omega0, *parameters) -> (xdotF, ydotF, omegaF, code)``.
    kernel: ClassVar[Any] = None
    #: The law's own 3-D bounce for :mod:`bouncelab.ground` (default None: the 2-D ``kernel`` lifted in the law's
    #: :attr:`~bouncelab.BounceModel.lift_plane`): a ``numba.njit`` function
    #: ``kernel_3d(x, y, w, vb, wh, wn, *kernel arguments) -> (xF, yF, wF, vbF, whF, wnF)`` of the landing in the
    #: frame of the plane of travel, ``(v.h, v.n, -omega.b, v.b, omega.h, omega.n)`` (see
    #: :mod:`bouncelab.ground.bounce3d`), taking the same arguments as ``kernel``. The rigid family's is the exact
    #: 3-D rigid bounce (Penner's laws: on their tilted plane).
    kernel_3d: ClassVar[Any] = None
    _fused_value_check = True  # the row loops check the landings (see _Loops)
    _abstract_law = True  # a base for laws, not a law: not registered

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        kernel = cls.__dict__.get("kernel")
        # numba dispatchers keep the Python function; a property loads the kernel lazily (built-ins)
        if kernel is not None and not isinstance(kernel, property) and not hasattr(kernel, "py_func"):
            raise LawDefinitionError(
                f"{cls.__name__}.kernel must be a numba.njit function (kernel(xdot0, ydot0, omega0, "
                f"{', '.join(s.name for s in cls.parameter_specs)}) -> (xdotF, ydotF, omegaF, code)); got "
                f"{type(kernel).__name__}. Decorate it with @numba.njit", law=cls.__name__, method="kernel")
        cls._plain_args = cls._kernel_args is CompiledLaw._kernel_args

    def _kernel_args(self, **parameters: Any) -> tuple:
        """What the kernel takes after the landing, from the parameters by name (default: the parameters in
        declaration order). Override to add options or constants computed from the parameters."""
        return tuple(parameters.values())

    def _args(self, values: Mapping[str, Any]) -> tuple:
        """The kernel's arguments for ``values``: the law's own are computed once per law (it is immutable)."""
        if values is self.__dict__["_values"]:
            cached = self.__dict__.get("_args_cache")
            if cached is None:
                cached = self.__dict__["_args_cache"] = self._kernel_args(**values)
            return cached
        return self._kernel_args(**values)

    def _one(self, x: float, y: float, w: float) -> tuple[float, float, float]:
        """One landing: the law's compiled kernel called directly (no array, no loop). A law is immutable, so its
        kernel's arguments and the kernel's compiled entry point for them are found once (skipping numba's
        type dispatch on every call)."""
        entry = self.__dict__.get("_one_entry")
        if entry is None:
            entry = self.__dict__["_one_entry"] = self._entry_point()
        a, b, c, _ = entry(x, y, w)
        return a, b, c

    def _entry_point(self) -> Callable[[float, float, float], tuple]:
        kernel = type(self).__dict__.get("_kernel_of_class")
        if kernel is None:  # a built-in law loads its kernel on first use: keep it on the class
            self._loops()  # a law without a kernel: the LawDefinitionError saying how to write one
            kernel = type(self)._kernel_of_class = self.kernel
        args = self._args(self.__dict__["_values"])
        kernel(1.0, -1.0, 0.0, *args)  # compiled (or loaded from the cache) for these argument types
        try:
            from numba import typeof

            compiled = kernel.overloads[tuple(typeof(v) for v in (1.0, -1.0, 0.0, *args))].entry_point
            return lambda x, y, w: compiled(x, y, w, *args)
        except (AttributeError, KeyError, TypeError):  # numba's internals moved: its dispatch, a little slower
            return lambda x, y, w: kernel(x, y, w, *args)

    def _loops(self) -> _Loops:
        if self.kernel is None:
            names = ", ".join(s.name for s in self.parameter_specs)
            raise LawDefinitionError(
                f"{law_name(self)} sets no kernel: a CompiledLaw needs the class attribute kernel = a numba.njit "
                f"function kernel(xdot0, ydot0, omega0, {names}) -> (xdotF, ydotF, omegaF, regime_code)",
                law=law_name(self), method="kernel")
        return loops_for(self.kernel)

    def _predict(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        return self._evaluate_checked(p, parameters)[0]

    def _regime(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        return self._classify_checked(p, parameters)[0]

    def _evaluate_checked(self, p: np.ndarray, values: Mapping[str, Any]) -> tuple[np.ndarray, bool]:
        """Lift-off states, and whether every landing was valid (checked in the same pass)."""
        out = np.empty_like(p)
        ok = run_rows(self._loops().predict_rows, len(p), p, self._args(values), out, *landing_bits(p))
        return out, all(ok)

    def _classify_checked(self, p: np.ndarray, values: Mapping[str, Any]) -> tuple[np.ndarray, bool]:
        codes = np.empty(len(p), dtype=np.int8)
        ok = run_rows(self._loops().regime_rows, len(p), p, self._args(values), codes, *landing_bits(p))
        return codes, all(ok)

    def _error_function(self, landing: np.ndarray, liftoff: np.ndarray,
                        inv_norm: np.ndarray) -> Callable[[Sequence[Any]], Any]:
        """One compiled pass per call: the four sums of the error terms (see BounceModel)."""
        sums = self._loops().error_sums
        n = len(landing)
        names = [s.name for s in self.parameter_specs]

        def args_of(values: Sequence[Any]) -> tuple:
            if isinstance(values, np.ndarray):  # numba reads a tuple of Python floats faster than NumPy scalars
                values = values.tolist()
            if self._plain_args:
                return tuple(values)
            return self._kernel_args(**dict(zip(names, values, strict=True)))

        if n < PARALLEL_MIN:
            def f(values: Sequence[Any]) -> tuple[float, float, float, float]:
                return sums(landing, liftoff, inv_norm, args_of(values), 0, n)
            return f

        def f_chunked(values: Sequence[Any]) -> tuple[float, float, float, float]:
            parts = run_chunked(sums, n, landing, liftoff, inv_norm, args_of(values))
            if len(parts) == 1:
                return parts[0]
            return tuple(math.fsum(p[k] for p in parts) for k in range(4))

        return f_chunked
