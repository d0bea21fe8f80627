"""The abstract bounce law.

A bounce law maps the landing state ``p0 = [xdot0, ydot0, omega0]`` of a ball to
its lift-off state ``pF = [xdotF, ydotF, omegaF]`` (scaled units, see
:mod:`bouncelab.data.units`). :class:`BounceModel` does everything that is the
same for every law: keyword parameters stored as given, their validation and
bounds, input validation and broadcasting, regimes, repr, equality and JSON.
A subclass declares its parameters and supplies two small hooks:

``_predict(p, theta)``
    lift-off states of an (n, 3) array ``p`` of landings, given the parameter
    vector ``theta`` (in the order of ``parameter_specs``);
``_regime(p, theta)``
    the integer regime code (an index into ``regimes``) of each landing.

Both receive validated C-contiguous float64 arrays and never need to check them.

Examples
--------
A new law is one small class:

>>> import numpy as np
>>> from bouncelab.laws.base import BounceModel, Parameter
>>> class Restitution(BounceModel):
...     '''Frictionless bounce: pF = [xdot0, -e ydot0, omega0].'''
...     parameter_specs = (Parameter("e", (0.0, 1.0), (0.0, 1.0), "1", "restitution"),)
...     regimes = ("bounce",)
...     def __init__(self, e=None):
...         self.e = e
...         super().__init__()
...     def _predict(self, p, theta):
...         return p * np.array([1.0, -theta[0], 1.0])
...     def _regime(self, p, theta):
...         return np.zeros(len(p), dtype=np.int8)
>>> Restitution(e=0.5).predict([[100.0, -200.0, 30.0]])
array([[100., 100.,  30.]])
"""

from __future__ import annotations

import inspect
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from bouncelab.data.validation import States, as_states
from bouncelab.errors import NotFittedError, ParameterError

__all__ = ["BounceModel", "Parameter", "law_from_dict", "load_law", "registered_laws"]

_REGISTRY: dict[str, type[BounceModel]] = {}


@dataclass(frozen=True)
class Parameter:
    """A named scalar parameter of a bounce law.

    Attributes
    ----------
    name
        Keyword name in the law's constructor.
    bounds
        Default search box ``(low, high)`` used by :func:`bouncelab.fit`.
    physical
        Range outside which the law is meaningless; values and fit bounds
        outside it are refused with :class:`~bouncelab.ParameterError`.
    unit
        Unit of the value ("1" for dimensionless).
    description
        One line for reports.
    """

    name: str
    bounds: tuple[float, float]
    physical: tuple[float, float]
    unit: str
    description: str

    def check(self, value: Any, law: str) -> float:
        """Return ``value`` as a float, or raise ParameterError naming the law and parameter."""
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {value!r}") from None
        lo, hi = self.physical
        if not math.isfinite(v) or not lo <= v <= hi:
            raise ParameterError(
                f"{law} parameter {self.name!r} = {value!r} is outside its physical range [{lo}, {hi}] "
                f"({self.description})"
            )
        return v


class BounceModel:
    """Abstract bounce law: landing state in, lift-off state out.

    Subclasses set ``parameter_specs`` and ``regimes``, store their keyword
    arguments as attributes of the same names in ``__init__`` and then call
    ``super().__init__()``, and implement ``_predict`` and ``_regime``.

    A law is a value: it is immutable once built; :meth:`replace` makes a
    changed copy. A law built without arguments is *unfitted*: its parameters
    are ``None`` and :meth:`predict` raises :class:`~bouncelab.NotFittedError`
    until it is fitted (:func:`bouncelab.fit`) or given values.
    """

    #: The law's scalar parameters, in the order of the ``theta`` vector.
    parameter_specs: ClassVar[tuple[Parameter, ...]] = ()
    #: Names of the regimes that :meth:`regime` returns, indexed by ``_regime``'s codes.
    regimes: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if not cls.__name__.startswith("_"):
            _REGISTRY[cls.__name__] = cls

    def __init__(self) -> None:
        self._validate_parameters()
        object.__setattr__(self, "_frozen", True)

    def _validate_parameters(self) -> None:
        # Validate every parameter that was given; None means "not fitted yet".
        for spec in self.parameter_specs:
            value = getattr(self, spec.name)
            if value is not None:
                object.__setattr__(self, spec.name, spec.check(value, type(self).__name__))

    def __setattr__(self, name: str, value: Any) -> None:
        if getattr(self, "_frozen", False):
            raise AttributeError(
                f"{type(self).__name__} is immutable; use .replace({name}=...) for a changed copy"
            )
        object.__setattr__(self, name, value)

    # ----------------------------------------------------------------- parameters
    @classmethod
    def _keyword_names(cls) -> tuple[str, ...]:
        sig = inspect.signature(cls.__init__)
        return tuple(p for p in sig.parameters if p != "self")

    def get_params(self) -> dict[str, Any]:
        """The constructor's keyword arguments as stored (scikit-learn convention)."""
        return {name: getattr(self, name) for name in self._keyword_names()}

    @property
    def parameters(self) -> dict[str, float | None]:
        """Scalar parameters as a name -> float mapping (``None`` where not set)."""
        return {spec.name: getattr(self, spec.name) for spec in self.parameter_specs}

    @classmethod
    def default_bounds(cls) -> dict[str, tuple[float, float]]:
        """Default fitting bounds, name -> (low, high)."""
        return {spec.name: spec.bounds for spec in cls.parameter_specs}

    @property
    def is_fitted(self) -> bool:
        """True when every parameter has a value."""
        return all(v is not None for v in self.parameters.values())

    def replace(self, **changes: Any) -> BounceModel:
        """A copy with some keyword arguments changed (validated like the constructor)."""
        unknown = set(changes) - set(self._keyword_names())
        if unknown:
            raise ParameterError(
                f"{type(self).__name__} has no parameter(s) {sorted(unknown)}; it has {list(self._keyword_names())}"
            )
        return type(self)(**{**self.get_params(), **changes})

    def _theta(self) -> np.ndarray:
        missing = [k for k, v in self.parameters.items() if v is None]
        if missing:
            raise NotFittedError(
                f"{type(self).__name__} has no value for {missing}; pass them to the constructor "
                f"or fit the law with bouncelab.fit({type(self).__name__}(), data)"
            )
        return np.array([getattr(self, s.name) for s in self.parameter_specs], dtype=np.float64)

    # ---------------------------------------------------------------- prediction
    def predict(self, landing: States) -> Any:
        """Lift-off states ``[xdotF, ydotF, omegaF]`` for landing states ``[xdot0, ydot0, omega0]``.

        Parameters
        ----------
        landing
            Array-like of shape (..., 3) in scaled units (radii/s, radii/s,
            rad/s) with ``ydot0 < 0``, or an :class:`xarray.DataArray` with a
            ``component`` dimension.

        Returns
        -------
        numpy.ndarray or xarray.DataArray
            Lift-off states, of the same kind and shape as ``landing``.

        Raises
        ------
        DataError
            Wrong shape, NaN/inf, or a landing with ``ydot0 >= 0`` (row named).
        NotFittedError
            Some parameters have no value.
        """
        theta = self._theta()
        p, wrap = as_states(landing, "landing", landing=True)
        return wrap(self._predict(p, theta))

    def regime(self, landing: States) -> np.ndarray:
        """Name of the regime each landing falls in (one of :attr:`regimes`).

        Returns an array of strings with the leading shape of ``landing``
        (a labelled DataArray for a DataArray input).
        """
        theta = self._theta()
        p, wrap = as_states(landing, "landing", landing=True)
        return wrap(np.asarray(self.regimes)[self._regime(p, theta)])

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    # ------------------------------------------------------------- published laws
    @classmethod
    def published(cls, campaign: str) -> BounceModel:
        """The law with the reference paper's published values for campaign "A" or "B"."""
        raise NotImplementedError(f"the paper publishes no values for {cls.__name__}")

    # ------------------------------------------------------------ serialisation
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description: ``{"law": name, "parameters": {keyword: value}}``."""
        params = {k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in self.get_params().items()}
        from bouncelab import __version__

        return {"law": type(self).__name__, "parameters": params, "bouncelab_version": __version__}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> BounceModel:
        """Rebuild a law from :meth:`to_dict` output (any registered law when called on BounceModel)."""
        return law_from_dict(d, expected=None if cls is BounceModel else cls)

    def to_json(self, path: str | Path | None = None, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` if given."""
        text = json.dumps(self.to_dict(), indent=2, **kwargs)
        if path is not None:
            Path(path).write_text(text + "\n")
        return text

    # ------------------------------------------------------------ dunder methods
    def __repr__(self) -> str:
        parts = []
        for k, v in self.get_params().items():
            if isinstance(v, np.ndarray):
                v = np.array2string(v, precision=4, separator=", ", max_line_width=200).replace("\n", "")
                parts.append(f"{k}={v}")
            elif isinstance(v, float):
                parts.append(f"{k}={v:.6g}")
            else:
                parts.append(f"{k}={v!r}")
        return f"{type(self).__name__}({', '.join(parts)})"

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        a, b = self.get_params(), other.get_params()
        return all(np.array_equal(np.asarray(a[k], dtype=object), np.asarray(b[k], dtype=object)) for k in a)

    def __hash__(self) -> int:
        return hash((type(self).__name__, json.dumps(self.to_dict()["parameters"], sort_keys=True)))


def registered_laws() -> dict[str, type[BounceModel]]:
    """Every concrete law class known by name (built-in and user-defined)."""
    return dict(_REGISTRY)


def law_from_dict(d: Mapping[str, Any], expected: type[BounceModel] | None = None) -> BounceModel:
    """Build a law from ``{"law": name, "parameters": {...}}``."""
    if not isinstance(d, Mapping) or "law" not in d or "parameters" not in d:
        raise ParameterError("a law description needs the keys 'law' and 'parameters'")
    name = d["law"]
    if name not in _REGISTRY:
        raise ParameterError(f"unknown law {name!r}; known laws: {sorted(_REGISTRY)}")
    cls = _REGISTRY[name]
    if expected is not None and not issubclass(cls, expected):
        raise ParameterError(f"the description is of a {name}, not a {expected.__name__}")
    params = dict(d["parameters"])
    unknown = set(params) - set(cls._keyword_names())
    if unknown:
        raise ParameterError(f"{name} has no parameter(s) {sorted(unknown)}")
    return cls(**params)


def load_law(path: str | Path) -> BounceModel:
    """Read a law written by :meth:`BounceModel.to_json`."""
    try:
        d = json.loads(Path(path).read_text())
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{path}: not a JSON law description ({exc})") from None
    return law_from_dict(d)
