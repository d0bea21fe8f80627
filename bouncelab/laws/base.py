"""The law protocol: :class:`BounceModel`, its parameters, fitting methods, identity and JSON.

A bounce law maps the landing state ``p0 = [xdot0, ydot0, omega0]`` of a ball to
its lift-off state ``pF = [xdotF, ydotF, omegaF]`` (scaled units, see
:mod:`bouncelab.data.units`). :class:`BounceModel` does everything that is the
same for every law: keyword parameters stored as given, their validation,
input validation and broadcasting (once, at the public entry), regimes, repr,
equality, JSON and identity. A law owns everything that is law-specific:

``parameter_specs``
    its parameters, a tuple of :class:`~bouncelab.laws.parameters.Parameter`
    (scalars or arrays, with search bounds, physical range, unit, description);
``regimes``
    the names of its regimes;
``_predict(p, theta)`` and ``_regime(p, theta)``
    the maths, on a validated C-contiguous ``(n, 3)`` float64 array ``p`` and the
    flat parameter vector ``theta`` (all parameters in declaration order, arrays
    raveled in C order);
``_error_function(landing, liftoff, inv_norm)``
    the fitter's objective (a NumPy default here; compiled laws override it);
``_summary_lines()`` and ``_diagnostics(landing, liftoff)``
    what reports print about it beyond its parameters;
methods decorated with :func:`fit_method`
    its own fitting procedures, beside the generic ``"global"`` search.

Generic code (``fit``, ``FitResult``, ``compare``, ``bootstrap``,
``cross_validate``, reports, the command line) reads all of it from the law and
never names one.

Examples
--------
A new law is one small class:

>>> import numpy as np
>>> from bouncelab.laws import BounceModel, Parameter
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
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Protocol

import numpy as np

from bouncelab.data.plausibility import PLAUSIBLE_RANGES, PlausibleRanges
from bouncelab.data.validation import States, as_states, check_values
from bouncelab.errors import DataError, LawDefinitionError, NotFittedError, ParameterError
from bouncelab.laws.parameters import Parameter, Parameters

__all__ = [
    "DEFAULT_LOCAL_ALGORITHM",
    "REGIME_NAMES_WARN",
    "BounceModel",
    "FitOutcome",
    "FitProblem",
    "Parameter",
    "Parameters",
    "fit_method",
    "law_class",
    "law_from_dict",
    "law_name",
    "load_law",
    "registered_laws",
]

#: From this many landings on, ``regime`` names (rather than codes) come with a LargeResultWarning.
REGIME_NAMES_WARN = 1_000_000

#: Default local polish of the generic search (delta has kinks at regime changes, where
#: BOBYQA's quadratic models stall; see benchmarks/bench_algorithms.py).
DEFAULT_LOCAL_ALGORITHM = "NELDERMEAD"

_FIT_METHOD_ATTR = "__bouncelab_fit_method__"


# ------------------------------------------------------------------------------ fitting protocol
class FitProblem(Protocol):
    """What a law's fitting method receives from :func:`bouncelab.fit` (implemented in ``bouncelab.fitting``).

    Attributes
    ----------
    landing, liftoff
        Validated ``(n, 3)`` C-contiguous float64 arrays of the bounces to fit.
    inv_norm
        The weight of each bounce's error in the objective: ``1 / ||p0||`` of every
        landing (delta and Delta q), or ``1 / h`` from its prediction intervals for a
        ``"delta_pi"`` objective (:mod:`bouncelab.fitting.objective`).
    setting
        Launcher setting of each bounce, or None.
    n
        Number of bounces.
    weights
        Weights of ``[delta, Delta xdot, Delta ydot, Delta omega]`` in the objective.
    seed
        Seed for anything random.
    box
        Search box, parameter name -> ``(low, high)`` (arrays for array parameters),
        the law's defaults updated by the user's ``bounds``.
    fixed
        Parameters held in this fit, name -> value.
    test
        Held-out ``(landing, liftoff)`` or None (for information; never fitted).
    sample_weight
        The user's weight of each bounce (positive: bounces of weight 0 are left out; mean 1), or None. It is in
        ``inv_norm`` (so in :meth:`objective`); a method that fits anything else from the
        bounces (least squares, a classifier) must weigh them by it too.
    """

    landing: np.ndarray
    liftoff: np.ndarray
    inv_norm: np.ndarray
    setting: np.ndarray | None
    n: int
    weights: np.ndarray
    seed: int
    box: dict[str, tuple[Any, Any]]
    fixed: dict[str, Any]
    test: tuple[np.ndarray, np.ndarray] | None
    sample_weight: np.ndarray | None

    def objective(self, law: BounceModel) -> Callable[[np.ndarray], float]:
        """The weighted mean error as a function of the law's flat parameter vector."""

    def search(self, f: Callable[[np.ndarray], float], x0: np.ndarray, **options: Any) -> Any:
        """Minimise ``f`` over the unit box ``[0, 1]^d`` from ``x0`` (NLopt global stage + local polish)."""

    def run_global(self, law: BounceModel, **options: Any) -> FitOutcome:
        """The generic method: global search over the free parameters of ``law`` in ``box``."""


@dataclass
class FitOutcome:
    """What a fitting method returns to :func:`bouncelab.fit`.

    Attributes
    ----------
    model
        The fitted law.
    objective_value
        The objective at the fitted parameters, on the fitted data.
    algorithm
        The procedure, in words (e.g. ``"DIRECT_L + NELDERMEAD"``).
    n_global, n_local
        Objective evaluations per stage.
    stop_reason
        Why the optimizer(s) stopped.
    at_bounds
        Parameters (element names for arrays) that ended on a bound, name -> "lower"/"upper".
    insensitive
        Parameters the objective does not depend on near the optimum, name -> the
        range over which it stays the same.
    stderr
        Standard errors the method knows, parameter name -> value (array for arrays).
    notes
        Anything a user should know about this fit.
    extras
        Method-specific results (e.g. support-vector indices), for programs.
    """

    model: BounceModel
    objective_value: float
    algorithm: str
    n_global: int = 0
    n_local: int = 0
    stop_reason: str = ""
    at_bounds: dict[str, str] = field(default_factory=dict)
    insensitive: dict[str, tuple[float, float]] = field(default_factory=dict)
    stderr: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    extras: dict[str, Any] = field(default_factory=dict)


def fit_method(name: str) -> Callable[[Callable], Callable]:
    """Register a method of a law class as the fitting method ``name`` of :func:`bouncelab.fit`.

    The method is called as ``method(law, problem, **options)`` with a
    :class:`FitProblem` and returns a :class:`FitOutcome`; its keyword-only
    arguments are its options (``bouncelab.fit`` refuses any other).

    Examples
    --------
    >>> class MyLaw(BounceModel):  # doctest: +SKIP
    ...     @fit_method("closed_form")
    ...     def _fit_closed_form(self, problem, *, damping: float = 0.0) -> FitOutcome: ...
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise ParameterError(f"a fitting method name must be an identifier; got {name!r}")

    def mark(func: Callable) -> Callable:
        setattr(func, _FIT_METHOD_ATTR, name)
        return func

    return mark


# ------------------------------------------------------------------------------ identity
_REGISTRY: dict[str, type[BounceModel]] = {}
_REGISTRY_LOCK = threading.Lock()


def _is_builtin(cls: type) -> bool:
    return cls.__module__ == "bouncelab" or cls.__module__.startswith("bouncelab.")


def law_name(cls: type[BounceModel] | BounceModel) -> str:
    """The name a law is known by: the class name for bouncelab's own laws, ``module:QualName`` otherwise."""
    cls = cls if isinstance(cls, type) else type(cls)
    return cls.__name__ if _is_builtin(cls) else f"{cls.__module__}:{cls.__qualname__}"


def registered_laws() -> dict[str, type[BounceModel]]:
    """Every concrete law class known, by :func:`law_name`; user laws also by class name when unambiguous."""
    with _REGISTRY_LOCK:
        classes = list(_REGISTRY.values())
    out = {law_name(c): c for c in classes}
    short: dict[str, list[type[BounceModel]]] = {}
    for c in classes:
        short.setdefault(c.__name__, []).append(c)
    for name, cands in short.items():
        if name not in out and len(cands) == 1:
            out[name] = cands[0]
    return out


def law_class(name: str, *, case_sensitive: bool = True) -> type[BounceModel]:
    """The law class known by ``name`` (see :func:`law_name`).

    A short name always means bouncelab's own law of that name, never a user's
    class that happens to share it. A short name that only user classes carry is
    accepted when exactly one does.

    Raises
    ------
    ParameterError
        Unknown name (with the known ones), an unregistered ``module:QualName``, or
        a short name shared by several user classes (listing their qualified names).
    """
    if not isinstance(name, str) or not name:
        raise ParameterError(f"a law name must be a non-empty string; got {name!r}")
    if not case_sensitive:
        try:  # the exact spelling wins over laws whose names differ from it only in case
            return law_class(name, case_sensitive=True)
        except ParameterError:
            pass
    with _REGISTRY_LOCK:
        classes = list(_REGISTRY.values())

    def same(a: str, b: str) -> bool:
        return a == b if case_sensitive else a.lower() == b.lower()

    if ":" in name:
        hits = [c for c in classes if same(f"{c.__module__}:{c.__qualname__}", name)]
        if len(hits) == 1:
            return hits[0]
        if len(hits) > 1:
            cands = sorted(f"{c.__module__}:{c.__qualname__}" for c in hits)
            raise ParameterError(f"the law name {name!r} is ambiguous; use one of the qualified names {cands}")
        raise ParameterError(
            f"unknown law {name!r}: no bounce law is registered as module:QualName {name!r} in this process (e.g. "
            "'bouncelab.laws.rigid:Rigid'); import the module that defines it first (a law description never "
            "imports code)"
        )
    builtin = [c for c in classes if _is_builtin(c) and same(c.__name__, name)]
    if len(builtin) == 1:
        return builtin[0]
    users = [c for c in classes if not _is_builtin(c) and same(c.__name__, name)]
    if len(users) == 1 and not builtin:
        return users[0]
    if len(builtin) + len(users) > 1:
        cands = sorted(f"{c.__module__}:{c.__qualname__}" for c in builtin + users)
        raise ParameterError(f"the law name {name!r} is ambiguous; use one of the qualified names {cands}")
    known = sorted(law_name(c) for c in classes)
    raise ParameterError(f"unknown law {name!r}; known laws: {known}")


# ------------------------------------------------------------------------------ the law
class BounceModel:
    """Abstract bounce law: landing state in, lift-off state out.

    Subclasses set ``parameter_specs`` and ``regimes``, store their keyword
    arguments as attributes of the same names in ``__init__`` and then call
    ``super().__init__()``, and implement ``_predict`` and ``_regime`` (or set a
    compiled ``kernel``, see :class:`~bouncelab.laws.CompiledLaw`).
    Constructor keywords that are not parameters are *options*: stored,
    serialised and printed, never fitted.

    A law is a value: it is immutable once built; :meth:`replace` makes a
    changed copy. A law built without arguments is *unfitted*: its parameters
    are ``None`` and :meth:`predict` raises :class:`~bouncelab.NotFittedError`
    until it is fitted (:func:`bouncelab.fit`) or given values.
    """

    #: The law's parameters, in the order of the ``theta`` vector.
    parameter_specs: ClassVar[tuple[Parameter, ...]] = ()
    #: Names of the regimes that :meth:`regime` returns, indexed by ``_regime``'s codes.
    regimes: ClassVar[tuple[str, ...]] = ()
    #: Method :func:`bouncelab.fit` uses when none is named.
    default_fit_method: ClassVar[str] = "global"

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.__name__.startswith("_") or cls.__dict__.get("_abstract_law", False):
            return
        names = [s.name for s in cls.parameter_specs]
        if len(set(names)) != len(names):
            raise ParameterError(f"{cls.__name__} declares a parameter twice: {names}")
        with _REGISTRY_LOCK:
            _REGISTRY[f"{cls.__module__}:{cls.__qualname__}"] = cls

    def __init__(self) -> None:
        self._validate_parameters()
        object.__setattr__(self, "_frozen", True)

    def _validate_parameters(self) -> None:
        # Validate every parameter that was given; None means "not fitted yet".
        for spec in self.parameter_specs:
            value = getattr(self, spec.name)
            if value is not None:
                object.__setattr__(self, spec.name, spec.check(value, law_name(self)))

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

    @classmethod
    def option_names(cls) -> tuple[str, ...]:
        """Constructor keywords that are not parameters (stored, serialised, never fitted)."""
        params = {s.name for s in cls.parameter_specs}
        return tuple(k for k in cls._keyword_names() if k not in params)

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """The constructor's keyword arguments as stored (scikit-learn convention; ``deep`` changes nothing)."""
        return {name: getattr(self, name) for name in self._keyword_names()}

    def __sklearn_clone__(self) -> BounceModel:
        """scikit-learn's ``clone``: a law is an immutable value, so it is its own clone."""
        return self

    @property
    def params(self) -> Parameters:
        """The parameters as objects (name, value, bounds, physical range, unit, vary, description)."""
        return Parameters(s.replace(value=getattr(self, s.name)) for s in self.parameter_specs)

    @property
    def parameters(self) -> dict[str, float | np.ndarray | None]:
        """Parameter values, name -> float (array for array parameters; ``None`` where not set)."""
        return {spec.name: getattr(self, spec.name) for spec in self.parameter_specs}

    def flat_parameters(self) -> dict[str, float | None]:
        """Every number of every parameter, by element name (``A1[0,2]``); for tables of any law."""
        out: dict[str, float | None] = {}
        for spec in self.parameter_specs:
            value = getattr(self, spec.name)
            flat = [None] * spec.size if value is None else np.ravel(value).tolist()
            out.update(zip(spec.element_names(), flat, strict=True))
        return out

    @property
    def options(self) -> dict[str, Any]:
        """The non-parameter constructor options, as stored."""
        return {k: getattr(self, k) for k in self.option_names()}

    @classmethod
    def default_bounds(cls) -> dict[str, tuple[Any, Any]]:
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

    @classmethod
    def _theta_slices(cls) -> list[tuple[Parameter, slice]]:
        out, start = [], 0
        for spec in cls.parameter_specs:
            out.append((spec, slice(start, start + spec.size)))
            start += spec.size
        return out

    @classmethod
    def theta_size(cls) -> int:
        """Length of the flat parameter vector."""
        return sum(s.size for s in cls.parameter_specs)

    def _theta(self) -> np.ndarray:
        """Flat float64 vector of every parameter in spec order (arrays raveled in C order)."""
        missing = [k for k, v in self.parameters.items() if v is None]
        if missing:
            raise NotFittedError(
                f"{law_name(self)} has no value for {missing}; pass them to the constructor "
                f"or fit the law with bouncelab.fit({type(self).__name__}(), data)"
            )
        parts = [np.ravel(np.asarray(getattr(self, s.name), dtype=np.float64)) for s in self.parameter_specs]
        return np.ascontiguousarray(np.concatenate(parts)) if parts else np.empty(0)

    def _with_theta(self, theta: np.ndarray) -> BounceModel:
        """A new law with the parameters of the flat vector ``theta`` (options kept)."""
        theta = np.asarray(theta, dtype=np.float64)
        if theta.shape != (self.theta_size(),):
            raise ParameterError(f"{law_name(self)} needs {self.theta_size()} numbers; got shape {theta.shape}")
        values: dict[str, Any] = {}
        for spec, sl in self._theta_slices():
            values[spec.name] = float(theta[sl][0]) if spec.is_scalar else theta[sl].reshape(spec.shape).copy()
        return self.replace(**values)

    # ---------------------------------------------------------------- prediction
    def predict(self, landing: States, units: Mapping[str, str] | str | None = None, *,
                form: str | tuple[str, str] = "cartesian", radius_m: float | None = None,
                return_flags: bool = False, plausible: PlausibleRanges | None = PLAUSIBLE_RANGES) -> Any:
        """Lift-off states for landing states.

        Parameters
        ----------
        landing
            By default ``[xdot0, ydot0, omega0]`` in scaled units (radii/s, radii/s,
            rad/s) with ``ydot0 < 0``: an array-like of shape (..., 3), a DataFrame
            with columns named ``xdot``, ``ydot``, ``omega`` (any order), or an
            :class:`xarray.DataArray` with a ``component`` dimension. A DataArray
            backed by dask is predicted lazily, chunk by chunk (scaled Cartesian
            states only).
        units
            None (scaled units) or ``{"velocity": "m/s", "spin": "rpm"}`` (any unit
            of :data:`~bouncelab.data.units.SPEED_UNITS` and
            :data:`~bouncelab.data.units.SPIN_UNITS`) for both the landings and the
            lift-offs.
        form
            ``"cartesian"`` (``[xdot, ydot, omega]``) or ``"polar"``
            (``[speed, angle_deg, spin]``), or a pair (landing form, lift-off form).
            A landing angle is positive *below* the horizontal, a lift-off angle
            positive *above* it, both measured from the direction of travel +x
            (:func:`~bouncelab.data.units.state_from_polar`). DataFrames name polar
            columns ``speed``, ``angle``, ``spin``.
        radius_m
            Ball radius in metres for physical units (default 21.35 mm).
        plausible
            The unit guard of landings given with ``units=`` or ``form="polar"``: numbers that
            only a unit mistake makes (2000 "m/s", 30 000 "rpm", an angle in radians given as
            degrees) are refused, as by the file loader. Default
            :data:`~bouncelab.data.plausibility.PLAUSIBLE_RANGES`; widen them on purpose
            (``PLAUSIBLE_RANGES.widened(max_speed=...)``) or pass ``None``. Scaled Cartesian
            landings (the default) are not checked: the law predicts any physical state.
        return_flags
            Also return a :class:`~bouncelab.laws.nonphysical.LiftoffFlags` marking
            non-physical lift-offs (``ydotF <= 0``, energy gain), computed in the same
            call.

        Returns
        -------
        numpy.ndarray, pandas.DataFrame or xarray.DataArray
            Lift-off states, of the same kind and shape as ``landing`` (and the flags
            with ``return_flags=True``).

        Raises
        ------
        DataError
            Wrong shape, NaN/inf, masked or complex values, magnitudes beyond
            :data:`bouncelab.data.validation.STATE_LIMIT`, a landing with
            ``ydot0 >= 0`` (row named), an unknown unit or form, a polar angle out of range,
            physical landings outside ``plausible`` (naming the row, the column and the unit they look like).
        NotFittedError
            Some parameters have no value.

        Warns
        -----
        NonphysicalLiftoffWarning
            A law with the paper's published values predicts non-physical lift-offs.

        Examples
        --------
        >>> import bouncelab as bl
        >>> law = bl.Rigid.published("A")
        >>> law.predict([[20.0, 30.0, 2000.0]], units={"velocity": "m/s", "spin": "rpm"}, form="polar").round(2)
        array([[   12.36,    26.12, -4962.15]])
        """
        from bouncelab.laws._physical_io import PhysicalIO, is_lazy
        from bouncelab.laws.nonphysical import LiftoffFlags, any_flagged, liftoff_flags, published_campaign

        theta = self._theta()
        if is_lazy(landing):
            if PhysicalIO.needed(units, form) or return_flags:
                raise DataError("a dask-backed DataArray is predicted lazily in scaled Cartesian states only; "
                                "drop units=, form= and return_flags=")
            return self._predict_lazy(landing)
        io = PhysicalIO(units, form, radius_m, plausible) if PhysicalIO.needed(units, form) else None
        p, out, wrap = self._predict_flat(landing if io is None else io.landing(landing), theta)
        flags = None
        if return_flags or (published_campaign(self) is not None and any_flagged(p, out)):
            from bouncelab.laws.nonphysical import warn_if_published_nonphysical

            flags = liftoff_flags(p, out)
            warn_if_published_nonphysical(self, p, out, flags)
        result = wrap(out) if io is None else io.liftoff(out)
        if not return_flags:
            return result
        per = wrap if io is None else io.per_bounce
        return result, LiftoffFlags(into_ground=per(flags[0]), energy_gain=per(flags[1]))

    def regime(self, landing: States, units: Mapping[str, str] | str | None = None, *, codes: bool = False,
               form: str | tuple[str, str] = "cartesian", radius_m: float | None = None,
               plausible: PlausibleRanges | None = PLAUSIBLE_RANGES) -> Any:
        """Regime of each landing: names from :attr:`regimes`, or int8 codes into it with ``codes=True``.

        Returns an array with the leading shape of ``landing`` (a labelled
        DataArray for a DataArray input; lazy for a dask-backed one). ``units``,
        ``form``, ``radius_m`` and ``plausible`` describe and check the landings as in :meth:`predict`.
        Names take 4 bytes per character per landing (52 MB per million landings
        for ``"slip_backward"``), codes one byte: from :data:`REGIME_NAMES_WARN`
        landings on, names come with a :class:`~bouncelab.errors.LargeResultWarning`.
        """
        from bouncelab.laws._physical_io import PhysicalIO, is_lazy

        theta = self._theta()
        if is_lazy(landing):
            if PhysicalIO.needed(units, form):
                raise DataError("a dask-backed DataArray is classified lazily in scaled Cartesian states only")
            return self._regime_lazy(landing, codes)
        io = PhysicalIO(units, (form, "cartesian") if isinstance(form, str) else form, radius_m, plausible) \
            if PhysicalIO.needed(units, form) else None
        _p, c, wrap = self._regime_flat(landing if io is None else io.landing(landing), theta)
        if io is not None:
            wrap = io.per_bounce
        c = self._regime_output(c, True)  # checked codes
        if codes:
            return wrap(c)
        names = np.asarray(self.regimes)
        if len(c) >= REGIME_NAMES_WARN:
            import warnings

            from bouncelab.errors import LargeResultWarning

            warnings.warn(f"regime names for {len(c):,} landings take {len(c) * names.itemsize / 1e6:.0f} MB; "
                          f"regime(..., codes=True) gives int8 codes into law.regimes ({len(c) / 1e6:.0f} MB)",
                          LargeResultWarning, stacklevel=2)
        return wrap(names[c])

    def _predict_flat(self, landing: States, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, Callable]:
        """Validated (n, 3) landings, their (n, 3) lift-offs, and the wrap back to the caller's kind."""
        p, wrap = as_states(landing, "landing", landing=True, defer_check=self._fused_value_check)
        out, ok = self._predict_checked(p, theta)
        if not ok:
            check_values(p, "landing", landing=True)  # raises, naming the row and column
        return p, out, wrap

    def _regime_flat(self, landing: States, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, Callable]:
        """Validated (n, 3) landings, their int8 regime codes, and the wrap back to the caller's kind."""
        p, wrap = as_states(landing, "landing", landing=True, defer_check=self._fused_value_check)
        c, ok = self._regime_checked(p, theta)
        if not ok:
            check_values(p, "landing", landing=True)
        return p, c, wrap

    def _lazy_input(self, da: Any) -> Any:
        from bouncelab.data.units import COMPONENTS

        if "component" not in da.dims or da.sizes["component"] != 3:
            raise DataError(f"landing DataArray needs a 'component' dimension of size 3; its sizes are "
                            f"{dict(da.sizes)}")
        if "component" in da.coords:
            labels = [str(v) for v in da["component"].values]
            if sorted(labels) != sorted(COMPONENTS):
                raise DataError(f"landing component labels must be {list(COMPONENTS)}; got {labels}")
            da = da.sel(component=list(COMPONENTS))
        return da.chunk({"component": -1})

    def _predict_lazy(self, da: Any) -> Any:
        """``predict`` of a dask-backed DataArray: one task per chunk, nothing computed yet."""
        import xarray as xr

        from bouncelab.data.units import COMPONENT_UNITS, COMPONENTS

        out = xr.apply_ufunc(lambda block: self.predict(block), self._lazy_input(da),
                             input_core_dims=[["component"]], output_core_dims=[["component"]],
                             dask="parallelized", output_dtypes=[np.float64])
        return out.assign_coords(component=list(COMPONENTS), unit=("component", list(COMPONENT_UNITS)))

    def _regime_lazy(self, da: Any, codes: bool) -> Any:
        import xarray as xr

        names = np.asarray(self.regimes)
        dtype = np.int8 if codes else names.dtype
        return xr.apply_ufunc(lambda block: self.regime(block, codes=True) if codes else names[
            self.regime(block, codes=True)], self._lazy_input(da), input_core_dims=[["component"]],
            dask="parallelized", output_dtypes=[dtype])

    #: Whether :meth:`_predict_checked` and :meth:`_regime_checked` check the landings' values in their
    #: own pass, so that the public methods can skip a separate pass over large arrays (compiled laws).
    _fused_value_check: ClassVar[bool] = False

    def _predict_checked(self, p: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, bool]:
        """:meth:`_predict`, and whether every landing was valid if this law checks them in the same pass."""
        return self._predict(p, theta), True

    def _regime_checked(self, p: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, bool]:
        """:meth:`_regime`, and whether every landing was valid (as :meth:`_predict_checked`)."""
        return self._regime(p, theta), True

    def _regime_output(self, c: np.ndarray, codes: bool) -> np.ndarray:
        """Codes or names, after checking the law's codes index its regimes (a law author's bug otherwise)."""
        if c.size and (int(c.min()) < 0 or int(c.max()) >= len(self.regimes)):
            bad = int(c.min()) if int(c.min()) < 0 else int(c.max())
            raise LawDefinitionError(f"{law_name(self)} gave regime code {bad}, but its regimes are "
                                     f"{list(self.regimes)} (codes 0..{len(self.regimes) - 1})")
        return c if codes else np.asarray(self.regimes)[c]

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    # --------------------------------------------------------------- the objective
    def _error_function(self, landing: np.ndarray, liftoff: np.ndarray,
                        inv_norm: np.ndarray) -> Callable[[np.ndarray], Any]:
        """The fitter's objective hook: a function of ``theta`` giving four sums over the bounces.

        ``[sum ||e_i|| / ||p0_i||, sum |ex_i| / ||p0_i||, sum |ey_i| / ||p0_i||,
        sum |ew_i| / ||p0_i||]`` with ``e_i = pF_i - predicted_i``; divided by n they
        are delta (eq. error) and the three Delta q (eq. error_individual). The
        arguments are validated ``(n, 3)`` arrays and ``1 / ||p0_i||``, fixed for a
        fit. This default predicts with :meth:`_predict` and sums with NumPy; a
        compiled law computes the same in one compiled pass.
        """

        def sums(theta: np.ndarray) -> np.ndarray:
            err = liftoff - self._predict(landing, theta)
            terms = np.column_stack([np.sqrt(np.einsum("ij,ij->i", err, err)), np.abs(err)])
            return inv_norm @ terms

        return sums

    # --------------------------------------------------------------- reports
    def _summary_lines(self) -> list[str]:
        """Law-specific lines for reports, beyond the parameter table (default: none)."""
        return []

    def _diagnostics(self, landing: np.ndarray, liftoff: np.ndarray) -> dict[str, float]:
        """Law-specific figures on some bounces, for FitResult, compare and reports (default: none)."""
        return {}

    # --------------------------------------------------------------- fitting methods
    @fit_method("global")
    def _fit_global(self, problem: FitProblem, *, algorithm: str | None = None,
                    local_algorithm: str | None = DEFAULT_LOCAL_ALGORITHM,
                    maxeval: int | None = None) -> FitOutcome:
        """NLopt global search over the unit box of the free parameters, then a local polish.

        Options: ``algorithm`` (CRS2_LM, ISRES, ESCH, DIRECT_L, MLSL; default DIRECT_L),
        ``local_algorithm`` (NELDERMEAD default, BOBYQA, SBPLX; None skips it),
        ``maxeval`` (evaluations of the global stage).
        """
        return problem.run_global(self, algorithm=algorithm, local_algorithm=local_algorithm, maxeval=maxeval)

    @classmethod
    def fit_methods(cls) -> dict[str, Callable]:
        """The fitting methods of this law, name -> function (``"global"`` first, then the class's own)."""
        out: dict[str, Callable] = {}
        for klass in reversed(cls.__mro__):
            for value in vars(klass).values():
                name = getattr(value, _FIT_METHOD_ATTR, None)
                if name is not None:
                    out[name] = value
        return {"global": out.pop("global"), **out} if "global" in out else out

    # ------------------------------------------------------------- published laws
    @classmethod
    def published(cls, campaign: str) -> BounceModel:
        """The law with the reference paper's published values for campaign "A" or "B"."""
        raise ParameterError(f"the paper publishes no values for {law_name(cls)}")

    # ------------------------------------------------------------ serialisation
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description: ``{"law": name, "parameters": {...}, "options": {...}}``.

        ``law`` is :func:`law_name` (the class name for bouncelab's laws,
        ``module:QualName`` for others).
        """
        from bouncelab import __version__

        def plain(v: Any) -> Any:
            return v.tolist() if isinstance(v, np.ndarray) else v

        d: dict[str, Any] = {"law": law_name(self),
                             "parameters": {k: plain(v) for k, v in self.parameters.items()}}
        if self.option_names():
            d["options"] = {k: plain(v) for k, v in self.options.items()}
        d["bouncelab_version"] = __version__
        return d

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> BounceModel:
        """Rebuild a law from :meth:`to_dict` output (any registered law when called on BounceModel)."""
        return law_from_dict(d, expected=None if cls is BounceModel else cls)

    def to_json(self, path: str | Path | None = None, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` if given (atomically)."""
        text = json.dumps(self.to_dict(), indent=2, **kwargs)
        if path is not None:
            from bouncelab.atomic import atomic_write_text

            atomic_write_text(path, text + "\n")
        return text

    # ------------------------------------------------------------ dunder methods
    def __repr__(self) -> str:
        parts = []
        sig = inspect.signature(type(self).__init__).parameters
        options = set(self.option_names())
        for k, v in self.get_params().items():
            if k in options and v is sig[k].default:  # options at their default are not shown
                continue
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
        d = self.to_dict()
        return hash((law_name(self), json.dumps([d["parameters"], d.get("options")], sort_keys=True, default=str)))


def law_from_dict(d: Mapping[str, Any], expected: type[BounceModel] | None = None) -> BounceModel:
    """Build a law from ``{"law": name, "parameters": {...}, "options": {...}}``.

    Raises
    ------
    ParameterError
        Anything wrong with the description: missing keys, an unknown or ambiguous
        law name, unknown or bad parameter values (never TypeError and the like).
    """
    if not isinstance(d, Mapping) or "law" not in d or "parameters" not in d:
        raise ParameterError("a law description needs the keys 'law' and 'parameters'")
    name = d["law"]
    if not isinstance(name, str):
        raise ParameterError(f"the law name must be a string; got {name!r}")
    cls = law_class(name)
    if expected is not None and not issubclass(cls, expected):
        raise ParameterError(f"the description is of a {name}, not a {expected.__name__}")
    kwargs: dict[str, Any] = {}
    for key in ("parameters", "options"):
        part = d.get(key, {})
        if part is None:
            part = {}
        if not isinstance(part, Mapping) or not all(isinstance(k, str) for k in part):
            raise ParameterError(f"{name}: {key!r} must be a mapping of names to values; got {type(part).__name__}")
        kwargs.update(part)
    unknown = set(kwargs) - set(cls._keyword_names())
    if unknown:
        raise ParameterError(f"{name} has no parameter(s) {sorted(unknown)}; it has {list(cls._keyword_names())}")
    try:
        return cls(**kwargs)
    except ParameterError:
        raise
    except (TypeError, ValueError, OverflowError, RecursionError, AttributeError) as exc:
        raise ParameterError(f"{name}: bad parameter values in the description ({type(exc).__name__}: {exc})") from None


def load_law(path: str | Path) -> BounceModel:
    """Read a law written by :meth:`BounceModel.to_json`."""
    if isinstance(path, str) and path.lstrip().startswith("{"):  # the JSON itself, not a file name
        raise ParameterError("load_law takes the path of a law JSON file; for JSON text use "
                             "bouncelab.laws.law_from_dict(json.loads(text))")
    try:
        d = json.loads(Path(path).read_text())
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        raise ParameterError(f"{path}: not a JSON law description ({type(exc).__name__}: {exc})") from None
    return law_from_dict(d)
