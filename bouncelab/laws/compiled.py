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

from bouncelab.core._jit import ROW_FLAGS, jit
from bouncelab.core._parallel import CHUNK, PARALLEL_MIN, num_threads, run_chunked, run_rows, set_num_threads
from bouncelab.core.errors import LawDefinitionError
from bouncelab.core.landing_checks import INVALID, STATE_LIMIT
from bouncelab.core.plausibility import OPEN_LIMITS
from bouncelab.laws.base import _DEFAULT_LIMITS, BounceModel
from bouncelab.laws.registry import law_name

__all__ = ["CHUNK", "PARALLEL_MIN", "CompiledLaw", "num_threads", "run_chunked", "run_rows", "set_num_threads"]


# ------------------------------------------------------------------------------ loops per kernel
class _Loops:
    """The compiled array loops built around one kernel (its arguments after the landing come as a tuple)."""

    def __init__(self, kernel: Any) -> None:
        from bouncelab.core._scans import is_landing_, landing_fault_
        from bouncelab.laws._kernels import add_errors, row_status

        # The row loops also give the unit guard's verdict on their rows (0: every landing valid and
        # plausible; see row_status), so that the public methods check the landings in the pass that
        # predicts them instead of reading the array once or twice more.
        @jit(nogil=True, fastmath=ROW_FLAGS)
        def predict_rows(P, args, out, bits, guard, start, stop):
            status = 0
            for i in range(start, stop):
                x = P[i, 0]
                y = P[i, 1]
                w = P[i, 2]
                found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
                status |= found
                if found & INVALID:  # not a landing: the maths never sees it (refused)
                    continue
                a, b, c, _ = kernel(x, y, w, *args)
                out[i, 0] = a
                out[i, 1] = b
                out[i, 2] = c
            return status

        @jit(nogil=True, fastmath=ROW_FLAGS)
        def regime_rows(P, args, codes, bits, guard, start, stop):
            status = 0
            for i in range(start, stop):
                x = P[i, 0]
                y = P[i, 1]
                w = P[i, 2]
                found = row_status(x, y, w, bits[i, 0], bits[i, 1], bits[i, 2], guard)
                status |= found
                if found & INVALID:  # not a landing: the maths never sees it (refused)
                    continue
                codes[i] = kernel(x, y, w, *args)[3]
            return status

        # One landing (predict_one): the same checks and kernel, on floats. No fast-math here, so the
        # comparisons see NaN as NaN; the kernel is a compiled function of its own, the same bits as in the loops.
        @jit
        def one(x, y, w, min_s2, max_s2, max_w, tan_a, args):
            if not is_landing_(x, y, w, STATE_LIMIT):
                return 0.0, 0.0, 0.0, INVALID
            a, b, c, _ = kernel(x, y, w, *args)
            return a, b, c, landing_fault_(x, y, w, min_s2, max_s2, max_w, tan_a)

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
                sd, sx, sy, sw = add_errors(sd, sx, sy, sw, PF, i, a, b, c, inv_norm[i])
            return sd, sx, sy, sw

        self.predict_rows = predict_rows
        self.regime_rows = regime_rows
        self.one = one
        self.error_sums = error_sums


#: The bits of STATE_LIMIT as an int64, for the row loops' value check on the landings' bits.
_LIMIT_BITS = int(np.float64(STATE_LIMIT).view(np.int64))


def row_checks(p: np.ndarray, limits: tuple[float, float, float, float] | None) -> tuple[np.ndarray, tuple]:
    """What a row loop takes to check the landings ``p`` as it predicts them: their bits (an int64 view of
    ``p``) and the guard ``(limit bits, *limits)`` of :func:`bouncelab.laws._kernels.row_status` (``limits``
    None: the value check alone)."""
    return p.view(np.int64), (_LIMIT_BITS, *(OPEN_LIMITS if limits is None else limits))


def verdict(parts: list[int]) -> int:
    """The status of a whole pass from its parts' (or'ed)."""
    status = 0
    for part in parts:
        status |= part
    return status


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

    def _one_entry_point(self) -> tuple[Callable[..., tuple[float, float, float, int]], tuple]:
        """The compiled one-landing function and its last arguments under the default guard (see BounceModel),
        found once per law (it is immutable): its compiled entry point, skipping numba's type dispatch."""
        self._fitted_values()
        args = self._args(self.__dict__["_values"])
        one = self._loops().one
        one(1000.0, -800.0, 0.0, *OPEN_LIMITS, args)  # compiled (or loaded from the cache) for these types
        try:
            from numba import typeof

            entry = one.overloads[(*(typeof(1.0),) * 7, typeof(args))].entry_point
        except (AttributeError, KeyError, TypeError):  # numba's internals moved: its dispatch, a little slower
            entry = one
        self.__dict__["_one_entry"] = found = (entry, (*_DEFAULT_LIMITS, args))
        return found

    def _loops(self) -> _Loops:
        if self.kernel is None:
            names = ", ".join(s.name for s in self.parameter_specs)
            raise LawDefinitionError(
                f"{law_name(self)} sets no kernel: a CompiledLaw needs the class attribute kernel = a numba.njit "
                f"function kernel(xdot0, ydot0, omega0, {names}) -> (xdotF, ydotF, omegaF, regime_code)",
                law=law_name(self), method="kernel")
        return loops_for(self.kernel)

    def _predict(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        return self._evaluate_checked(p, parameters, None)[0]

    def _regime(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        return self._classify_checked(p, parameters, None)[0]

    def _row_loops(self, values: Mapping[str, Any]) -> tuple[Callable, Callable, tuple]:
        """The compiled loops of prediction and regimes, and what they take after the landings: by default the
        loops built around the kernel and its arguments. A law with loops of its own (the same kernel's maths,
        arranged for speed) overrides it; each loop is ``f(P, *args, out, bits, guard, start, stop) -> status``
        (see :func:`row_checks`)."""
        loops = self._loops()
        return loops.predict_rows, loops.regime_rows, (self._args(values),)

    def _evaluate_checked(self, p: np.ndarray, values: Mapping[str, Any],
                          limits: tuple[float, float, float, float] | None) -> tuple[np.ndarray, int]:
        """Lift-off states, and the unit guard's verdict on the landings (checked in the same pass)."""
        rows, _, args = self._row_loops(values)
        out = np.empty_like(p)
        return out, verdict(run_rows(rows, len(p), p, *args, out, *row_checks(p, limits)))

    def _classify_checked(self, p: np.ndarray, values: Mapping[str, Any],
                          limits: tuple[float, float, float, float] | None) -> tuple[np.ndarray, int]:
        _, rows, args = self._row_loops(values)
        codes = np.empty(len(p), dtype=np.int8)
        return codes, verdict(run_rows(rows, len(p), p, *args, codes, *row_checks(p, limits)))

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
