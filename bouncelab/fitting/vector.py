"""The flat parameter vector: how the fitting machinery sees a law's parameters.

Optimisers, bootstraps and samplers move through a vector of numbers; a law has named parameters, scalars
or arrays. :class:`ParameterVector` maps between the two for one law class: every parameter in declaration
order, arrays raveled in C order. It lives here, in the fitting machinery, and nowhere else: laws and
their authors see parameters by name only.

Examples
--------
>>> import bouncelab as bl
>>> vec = ParameterVector(bl.Rigid)
>>> vec.names, vec.of(bl.Rigid(r=0.5, mu=0.3)).tolist()
(['r', 'mu'], [0.5, 0.3])
>>> vec.law(bl.Rigid(), [0.4, 0.2])
Rigid(r=0.4, mu=0.2)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError
from bouncelab.laws.base import BounceModel
from bouncelab.laws.registry import law_name

__all__ = ["ParameterVector"]


class ParameterVector:
    """The map between a law class's parameters and one flat float64 vector.

    Attributes
    ----------
    specs
        The law's parameters, in declaration order.
    names
        Every number's name (``"r"``, ``"A1[0,2]"``), in vector order.
    size
        Length of the vector.
    """

    def __init__(self, law: type[BounceModel] | BounceModel) -> None:
        cls = law if isinstance(law, type) else type(law)
        self.specs = cls.parameter_specs
        self.keys = [s.name for s in self.specs]
        self.slices: list[slice] = []
        start = 0
        for spec in self.specs:
            self.slices.append(slice(start, start + spec.size))
            start += spec.size
        self.size = start
        self.names = [n for s in self.specs for n in s.element_names()]
        self.scalar = all(s.is_scalar for s in self.specs)

    def of(self, law: BounceModel) -> np.ndarray:
        """The vector of a fitted law (NotFittedError when a parameter has no value)."""
        values = law._fitted_values()
        if not self.keys:
            return np.empty(0)
        return np.ascontiguousarray(np.concatenate(
            [np.ravel(np.asarray(values[k], dtype=np.float64)) for k in self.keys]))

    def values(self, theta: Any) -> list[Any]:
        """The parameter values of ``theta``, in declaration order: floats for scalars, arrays of their shape."""
        if self.scalar:
            return np.asarray(theta, dtype=np.float64).tolist()
        t = np.asarray(theta, dtype=np.float64)
        return [float(t[sl][0]) if s.is_scalar else t[sl].reshape(s.shape)
                for s, sl in zip(self.specs, self.slices, strict=True)]

    def named(self, theta: Any) -> dict[str, Any]:
        """The parameter values of ``theta`` by name."""
        return dict(zip(self.keys, self.values(theta), strict=True))

    def law(self, like: BounceModel, theta: Any) -> BounceModel:
        """A law like ``like`` (its options kept) with the parameters of ``theta`` (validated)."""
        theta = np.asarray(theta, dtype=np.float64)
        if theta.shape != (self.size,):
            raise ParameterError(f"{law_name(like)} needs {self.size} numbers; got shape {theta.shape}",
                                 law=law_name(like))
        return like.replace(**{k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in self.named(theta).items()})

    def predict(self, law: BounceModel, landing: np.ndarray, theta: Any) -> np.ndarray:
        """``law``'s lift-offs of validated landings with the parameters of ``theta`` (no law is built)."""
        return law._evaluate(landing, self.named(theta))
