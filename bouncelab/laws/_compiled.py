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

    @classmethod
    def _kernel_args(cls, theta: np.ndarray) -> tuple[float, float, float]:
        t = [float(x) for x in theta] + [0.0] * (3 - len(theta))
        return t[0], t[1], t[2]

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        out = np.empty_like(p)
        kernels().predict(self._law_id, p, *self._kernel_args(theta), out)
        return out

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        codes = np.empty(len(p), dtype=np.int8)
        kernels().regime(self._law_id, p, *self._kernel_args(theta), codes)
        return codes

    def _error_sums(self, p0: np.ndarray, pf: np.ndarray, inv_norm: np.ndarray, theta: np.ndarray):
        """Sums of the delta and Delta-q terms over bounces (used by the fitter's objective)."""
        return kernels().error_sums(self._law_id, p0, pf, inv_norm, *self._kernel_args(theta))
