"""What generic code may assume of a bounce law: :class:`Law`, a typing protocol.

The modules below :class:`~bouncelab.BounceModel` (the registry of law classes, law files, the fitting
protocol) handle laws without importing the class that defines them, so that the imports of
:mod:`bouncelab.laws` point one way, type hints included: they annotate with :class:`Law`, which
``BounceModel`` implements (as does every law).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, ClassVar, Protocol

from bouncelab.laws.parameters import Option, Parameter, Parameters
from bouncelab.laws.provenance import Provenance

__all__ = ["Law"]


class Law(Protocol):
    """A bounce law: landing states in, lift-off states out (see :class:`bouncelab.BounceModel`)."""

    #: The declaration: parameters and options in declaration order, and the regimes' names.
    parameter_specs: ClassVar[tuple[Parameter, ...]]
    option_specs: ClassVar[tuple[Option, ...]]
    regimes: ClassVar[tuple[str, ...]]

    @property
    def params(self) -> Parameters:
        """The parameters as objects (name, value, bounds, physical range, unit, vary, doc)."""

    @property
    def provenance(self) -> Provenance | None:
        """What the law was fitted to, or None."""

    @property
    def is_fitted(self) -> bool:
        """True when every parameter has a value."""

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The constructor's keyword arguments as stored (scikit-learn's convention)."""

    def replace(self, **changes: Any) -> Law:
        """A copy with some keyword arguments changed."""

    def predict(self, landing: Any, units: Mapping[str, str] | str | None = None, **options: Any) -> Any:
        """Lift-off states for landing states."""

    def regime(self, landing: Any, units: Mapping[str, str] | str | None = None, **options: Any) -> Any:
        """The regime of each landing."""
