"""Shared plumbing for laws whose mathematics is a compiled scalar kernel."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from bouncelab.laws.base import BounceModel


def kernels():
    """The compiled kernels module, imported (and numba with it) on first use."""
    from bouncelab.laws import _kernels

    return _kernels


class _CompiledLaw(BounceModel):
    """A law evaluated by the cached numba kernels of ``bouncelab.laws._kernels``.

    Subclasses set ``_law_id`` and, if their parameters need converting for the
    kernel (degrees to radians), override ``_kernel_args``.
    """

    _law_id: ClassVar[int]
    regimes = ("slip_forward", "roll", "slip_backward")

    #: Factors taking the parameters (in spec order) to the kernel's three arguments (e.g. deg -> rad).
    _kernel_scale: ClassVar[tuple[float, float, float]] = (1.0, 1.0, 1.0)

    @classmethod
    def _kernel_args(cls, t: list[float]) -> tuple[float, float, float]:
        """The kernel's three scalar arguments from the parameter values (a list, in spec order)."""
        s = cls._kernel_scale
        return (t[0] * s[0], t[1] * s[1], t[2] * s[2]) if len(t) == 3 else (t[0] * s[0], t[1] * s[1], 0.0)

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        out = np.empty_like(p)
        kernels().predict(self._law_id, p, *self._kernel_args(theta.tolist()), out)
        return out

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        codes = np.empty(len(p), dtype=np.int8)
        kernels().regime(self._law_id, p, *self._kernel_args(theta.tolist()), codes)
        return codes

    def _error_kernel(self, p0: np.ndarray, pf: np.ndarray, inv_norm: np.ndarray):
        """A function of the parameter values (a list) -> sums of the delta and the three Delta q terms.

        The kernel, law id and per-landing data (s * phi, used by PennerVarying) are bound once
        per fit, so each call costs one compiled pass.
        """
        k = kernels()
        error_sums, law_id, args = k.error_sums, self._law_id, self._kernel_args
        aux = k.speeds_times_angles(p0)

        def sums(theta: list[float]) -> tuple[float, float, float, float]:
            t0, t1, t2 = args(theta)
            return error_sums(law_id, p0, pf, inv_norm, aux, t0, t1, t2)

        return sums

    def _unit_objective(self, p0, pf, inv_norm, base, lo, span, free, weights):
        """The fitter's hot path: u in the unit box of the free parameters -> weighted error, one compiled call."""
        k = kernels()
        spec = np.zeros((5, 3))
        m = len(base)
        spec[0, :m], spec[1, :m], spec[2, :m] = base, lo, span
        spec[3, :] = self._kernel_scale
        spec[4, :m] = free
        aux = k.speeds_times_angles(p0)
        w = np.asarray(weights, dtype=np.float64)
        objective, law_id = k.unit_objective, self._law_id

        def f(u: np.ndarray) -> float:
            return objective(law_id, p0, pf, inv_norm, aux, u, spec, w)

        return f
