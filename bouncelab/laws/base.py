"""The law protocol: :class:`BounceModel`, its parameters, fitting methods, identity and JSON.

A bounce law maps the landing state ``p0 = [xdot0, ydot0, omega0]`` of a ball to
its lift-off state ``pF = [xdotF, ydotF, omegaF]`` (scaled units, see
:mod:`bouncelab.core.units`). :class:`BounceModel` does everything that is the
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

import copy
import inspect
import json
import keyword
import sys
import threading
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Protocol

import numpy as np

from bouncelab.core.errors import DataError, LawDefinitionError, NotFittedError, ParameterError, UnknownLawError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges
from bouncelab.core.validation import States, as_states, check_values
from bouncelab.laws.parameters import Parameter, Parameters
from bouncelab.laws.provenance import Provenance

__all__ = [
    "DEFAULT_LOCAL_ALGORITHM",
    "LAW_FORMAT_VERSION",
    "REGIME_NAMES_WARN",
    "BounceModel",
    "FitOutcome",
    "FitProblem",
    "Parameter",
    "Parameters",
    "Provenance",
    "fit_method",
    "law_class",
    "law_from_dict",
    "law_name",
    "load_law",
    "registered_laws",
]

#: What a law file says it is, and the version of its layout (1: the first, ``{"law", "parameters", "options",
#: "bouncelab_version"}``; 2: units, conventions, ball radius, the class of a user's law and provenance added).
LAW_FORMAT = "bouncelab law"
LAW_FORMAT_VERSION = 2

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


#: Module names under which Python runs a script (``python myscript.py``; multiprocessing's workers).
_MAIN_MODULES = ("__main__", "__mp_main__")


def script_module(cls: type) -> tuple[str | None, str | None]:
    """For a class defined in a script run as ``__main__``: the module name that imports that script
    (``"myscript"`` for ``python myscript.py``, ``"pkg.tool"`` for ``python -m pkg.tool``) and the
    script's file; ``(None, file or None)`` when no module name would import it (a notebook, a
    file name that is not an identifier). ``(None, None)`` for a class of an ordinary module."""
    if cls.__module__ not in _MAIN_MODULES:
        return None, None
    mod = sys.modules.get(cls.__module__)
    if mod is None or getattr(mod, cls.__qualname__.split(".")[0], None) is None:
        return None, None  # __main__ is not the script that defined it (an interactive shell's launcher)
    file = getattr(mod, "__file__", None)
    file = None if file is None else str(Path(file).resolve())
    spec_name = getattr(getattr(mod, "__spec__", None), "name", None)
    if spec_name and spec_name not in _MAIN_MODULES:
        return spec_name, file
    if file is not None:
        stem = Path(file).stem
        if stem.isidentifier() and not keyword.iskeyword(stem):
            return stem, file
    return None, file


def law_name(cls: type[BounceModel] | BounceModel) -> str:
    """The name a law is known by: the class name for bouncelab's own laws, ``module:QualName`` otherwise.

    A class defined in a script run as ``__main__`` (``python myscript.py``) is named by the
    module that imports the script (``myscript:MyLaw``): the name under which it is registered
    in any process that imports ``myscript``, so that a law file written by the script loads
    there. In a notebook (no script file) it stays ``__main__:MyLaw``.
    """
    cls = cls if isinstance(cls, type) else type(cls)
    if _is_builtin(cls):
        return cls.__name__
    module = script_module(cls)[0] or cls.__module__
    return f"{module}:{cls.__qualname__}"


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


def law_class(name: str, *, case_sensitive: bool = True, script: str | None = None) -> type[BounceModel]:
    """The law class known by ``name`` (see :func:`law_name`).

    A short name always means bouncelab's own law of that name, never a user's
    class that happens to share it. A short name that only user classes carry is
    accepted when exactly one does. A ``module:QualName`` is the class of that
    module, or the class of a script run as ``__main__`` that ``module`` names
    (see :func:`law_name`); ``__main__:QualName`` (how a script's laws were named
    before, and still are in a notebook) is the one registered user class of that
    qualified name, whatever its module.

    Parameters
    ----------
    name
        The law's name.
    case_sensitive
        Whether the spelling must match exactly (the command line is not).
    script
        The file of the script that defined the law, if a law file says so: it is named in
        the error, and among several classes of that qualified name it picks the one
        defined in that file.

    Raises
    ------
    UnknownLawError
        (a ParameterError) No law of that name is registered: the error says what to import,
        and carries ``law_name``, ``module``, ``qualname``, ``module_imported``, ``script``.
    ParameterError
        A short name shared by several user classes, or a ``__main__`` name that several
        registered classes could be (listing their qualified names).
    """
    if not isinstance(name, str) or not name:
        raise ParameterError(f"a law name must be a non-empty string; got {name!r}")
    if not case_sensitive:
        try:  # the exact spelling wins over laws whose names differ from it only in case
            return law_class(name, case_sensitive=True, script=script)
        except UnknownLawError:
            pass
    with _REGISTRY_LOCK:
        classes = list(_REGISTRY.values())

    def same(a: str, b: str) -> bool:
        return a == b if case_sensitive else a.lower() == b.lower()

    if ":" in name:
        return _qualified_class(name, classes, same, script)
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
    raise UnknownLawError(f"unknown law {name!r}; known laws: {known}", law_name=name)


def _qualified_class(name: str, classes: list[type[BounceModel]], same: Callable[[str, str], bool],
                     script: str | None) -> type[BounceModel]:
    """The class of a ``module:QualName`` name (see :func:`law_class`)."""
    module, _, qualname = name.partition(":")
    hits = [c for c in classes if same(f"{c.__module__}:{c.__qualname__}", name)]
    if not hits:  # a script's class, named by the module that imports the script
        hits = [c for c in classes if c.__module__ in _MAIN_MODULES and same(law_name(c), name)]
    if not hits and module in _MAIN_MODULES:  # a script's or a notebook's law, wherever its class lives now
        hits = [c for c in classes if not _is_builtin(c) and same(c.__qualname__, qualname)]
        if len(hits) > 1 and script is not None:
            from_script = [c for c in hits if _defined_in(c, script)]
            hits = from_script if len(from_script) == 1 else hits
    if len(hits) == 1:
        return hits[0]
    if len(hits) > 1:
        cands = sorted(f"{c.__module__}:{c.__qualname__}" for c in hits)
        raise ParameterError(f"the law name {name!r} is ambiguous: several registered laws could be it, "
                             f"{cands}; load the law in a process that imports only one of them")
    imported = module in sys.modules
    if module in _MAIN_MODULES:
        where = f"in the script {script}" if script else "in a script or notebook run as __main__"
        stem = Path(script).stem if script else None
        how = (f"import that script's module first (import {stem})" if stem and stem.isidentifier()
               else "import (or define) the module that defines it first")
        msg = (f"unknown law {name!r}: no bounce law named {qualname!r} is registered in this process; it was "
               f"defined {where}; {how} (a law description never imports code)")
    elif imported:
        laws = sorted(law_name(c) for c in classes if c.__module__ == module)
        msg = (f"unknown law {name!r}: the module {module!r} is imported but defines no bounce law {qualname!r} "
               f"(its laws: {laws})")
    else:
        script_note = f" (the script {script})" if script else ""
        msg = (f"unknown law {name!r}: no bounce law is registered as {name!r} in this process; import the module "
               f"that defines it first (import {module}{script_note}; a law description never imports code)")
    raise UnknownLawError(msg, law_name=name, module=module, qualname=qualname, module_imported=imported,
                          script=script)


def _defined_in(cls: type, script: str) -> bool:
    """Whether ``cls`` comes from the file ``script``."""
    file = getattr(sys.modules.get(cls.__module__), "__file__", None)
    try:
        return file is not None and Path(file).resolve() == Path(script).resolve()
    except (OSError, ValueError):
        return False


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
                return_flags: bool = False, plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
                warn_outside_fitted: bool = False) -> Any:
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
            of :data:`~bouncelab.core.units.SPEED_UNITS` and
            :data:`~bouncelab.core.units.SPIN_UNITS`) for both the landings and the
            lift-offs.
        form
            ``"cartesian"`` (``[xdot, ydot, omega]``) or ``"polar"``
            (``[speed, angle_deg, spin]``), or a pair (landing form, lift-off form).
            A landing angle is positive *below* the horizontal, a lift-off angle
            positive *above* it, both measured from the direction of travel +x
            (:func:`~bouncelab.core.units.state_from_polar`). DataFrames name polar
            columns ``speed``, ``angle``, ``spin``.
        radius_m
            Ball radius in metres (default 21.35 mm): of the conversion of physical units, and
            of the unit guard's limits on scaled landings (one radius/s is ``radius_m`` m/s).
        plausible
            The unit guard: every landing, in whatever form and units it is given, must be one
            a golf ball can make (:func:`~bouncelab.core.plausibility.landing_faults`): a speed
            ``sqrt(xdot0^2 + ydot0^2)`` from 1 to 90 m/s, a spin up to 20 000 rpm and an angle of
            incidence of at least 5 degrees (m/s given as radii/s, rpm as rad/s, radians as
            degrees fail them). A landing that does not is refused, naming the row, the limit
            and the unit the numbers look like. Default
            :data:`~bouncelab.core.plausibility.PLAUSIBLE_RANGES`; widen them on purpose
            (``PLAUSIBLE_RANGES.widened(min_landing_speed=0.1)``) or pass ``None`` to predict any
            state (the maths of a law, a ball rolling to rest).
        return_flags
            Also return a :class:`~bouncelab.laws.nonphysical.LiftoffFlags` marking
            non-physical lift-offs (``ydotF <= 0``, energy gain), computed in the same
            call.
        warn_outside_fitted
            Warn (:class:`~bouncelab.core.errors.OutsideFittedRangeWarning`) when some landings lie
            outside the ranges of the landings the law was fitted on (``law.provenance``: each
            of xdot0, ydot0, omega0, the speed and the angle of incidence): there the law
            extrapolates. Off by default; a law with no record of its fit warns that it cannot
            tell.

        Returns
        -------
        numpy.ndarray, pandas.DataFrame or xarray.DataArray
            Lift-off states, of the same kind and shape as ``landing`` (and the flags
            with ``return_flags=True``).

        Raises
        ------
        DataError
            Wrong shape, NaN/inf, masked or complex values, magnitudes beyond
            :data:`bouncelab.core.validation.STATE_LIMIT`, a landing with
            ``ydot0 >= 0`` (row named), an unknown unit or form, a polar angle out of range,
            landings outside ``plausible`` (naming the row, the limit and the unit they look like).
        NotFittedError
            Some parameters have no value.
        LawDefinitionError
            The law's ``_predict`` is missing or returns anything but an (n, 3) real array.

        Warns
        -----
        NonphysicalLiftoffWarning
            A law with the paper's published values predicts non-physical lift-offs.
        OutsideFittedRangeWarning
            With ``warn_outside_fitted=True``, landings outside the fitted ranges.

        Examples
        --------
        >>> import bouncelab as bl
        >>> law = bl.Rigid.published("A")
        >>> law.predict([[20.0, 30.0, 2000.0]], units={"velocity": "m/s", "spin": "rpm"}, form="polar").round(2)
        array([[   12.36,    26.12, -4962.15]])
        """
        from bouncelab.laws._physical_io import PhysicalIO, check_plausible_argument, is_lazy, radius_of
        from bouncelab.laws.nonphysical import LiftoffFlags, any_flagged, liftoff_flags, published_campaign

        theta = self._theta()
        plausible = check_plausible_argument(plausible)
        if is_lazy(landing):
            if PhysicalIO.needed(units, form) or return_flags or warn_outside_fitted:
                raise DataError("a dask-backed DataArray is predicted lazily in scaled Cartesian states only; "
                                "drop units=, form=, return_flags= and warn_outside_fitted=")
            return self._predict_lazy(landing, plausible, radius_m)
        io = PhysicalIO(units, form, radius_m, plausible) if PhysicalIO.needed(units, form) else None
        radius = radius_of(radius_m) if io is None else io.radius_m
        p, out, wrap = self._predict_flat(landing if io is None else io.landing(landing), theta,
                                          guard=_guard(plausible, radius, io, landing))
        if warn_outside_fitted:
            self._warn_outside_fitted(p)
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
        ``form``, ``radius_m`` and ``plausible`` describe and guard the landings as in :meth:`predict`.
        Names take 4 bytes per character per landing (52 MB per million landings
        for ``"slip_backward"``), codes one byte: from :data:`REGIME_NAMES_WARN`
        landings on, names come with a :class:`~bouncelab.core.errors.LargeResultWarning`.

        Raises
        ------
        DataError
            As :meth:`predict`.
        LawDefinitionError
            The law's ``_regime`` is missing, returns anything but one integer code per landing,
            or a code that is not an index into :attr:`regimes`.
        """
        from bouncelab.laws._physical_io import PhysicalIO, check_plausible_argument, is_lazy, radius_of

        theta = self._theta()
        plausible = check_plausible_argument(plausible)
        if is_lazy(landing):
            if PhysicalIO.needed(units, form):
                raise DataError("a dask-backed DataArray is classified lazily in scaled Cartesian states only")
            return self._regime_lazy(landing, codes, plausible, radius_m)
        io = PhysicalIO(units, (form, "cartesian") if isinstance(form, str) else form, radius_m, plausible) \
            if PhysicalIO.needed(units, form) else None
        radius = radius_of(radius_m) if io is None else io.radius_m
        _p, c, wrap = self._regime_flat(landing if io is None else io.landing(landing), theta,
                                        guard=_guard(plausible, radius, io, landing))
        if io is not None:
            wrap = io.per_bounce
        c = self._regime_output(c, True)  # checked codes
        if codes:
            return wrap(c)
        names = np.asarray(self.regimes)
        if len(c) >= REGIME_NAMES_WARN:
            from bouncelab.core.errors import LargeResultWarning

            warnings.warn(f"regime names for {len(c):,} landings take {len(c) * names.itemsize / 1e6:.0f} MB; "
                          f"regime(..., codes=True) gives int8 codes into law.regimes ({len(c) / 1e6:.0f} MB)",
                          LargeResultWarning, stacklevel=2)
        return wrap(names[c])

    def _predict_flat(self, landing: States, theta: np.ndarray,
                      guard: Callable[[np.ndarray], None] | None = None) -> tuple[np.ndarray, np.ndarray, Callable]:
        """Validated (n, 3) landings, their (n, 3) lift-offs, and the wrap back to the caller's kind.

        ``guard(p)`` runs on the landings before the law does (the unit guard of the public methods).
        """
        p, wrap = as_states(landing, "landing", landing=True, defer_check=self._fused_value_check)
        if guard is not None:
            guard(p)
        out, ok = self._predict_checked(p, theta)
        if not ok:
            check_values(p, "landing", landing=True)  # raises, naming the row and column
        return p, self._liftoff_array(out, len(p), "_predict"), wrap

    def _regime_flat(self, landing: States, theta: np.ndarray,
                     guard: Callable[[np.ndarray], None] | None = None) -> tuple[np.ndarray, np.ndarray, Callable]:
        """Validated (n, 3) landings, their int8 regime codes, and the wrap back to the caller's kind."""
        p, wrap = as_states(landing, "landing", landing=True, defer_check=self._fused_value_check)
        if guard is not None:
            guard(p)
        c, ok = self._regime_checked(p, theta)
        if not ok:
            check_values(p, "landing", landing=True)
        return p, self._code_array(c, len(p)), wrap

    def _warn_outside_fitted(self, p: np.ndarray) -> None:
        """The warning of ``predict(..., warn_outside_fitted=True)``."""
        from bouncelab.core.errors import OutsideFittedRangeWarning
        from bouncelab.laws.provenance import outside_ranges

        prov = self.provenance
        if prov is None or not prov.landing_ranges:
            warnings.warn(f"{law_name(self)} carries no record of the landings it was fitted on (it was not fitted "
                          "by bouncelab.fit, or was read from a law file without one), so predict cannot tell "
                          "whether these landings lie outside them", OutsideFittedRangeWarning, stacklevel=3)
            return
        out, first = outside_ranges(p, prov.landing_ranges)
        n_out = int(out.sum())
        if n_out:
            warnings.warn(f"{n_out} of {len(p)} landings lie outside the ranges {law_name(self)} was fitted on "
                          f"({prov.summary()}), where it extrapolates; {first}", OutsideFittedRangeWarning,
                          stacklevel=3)

    # ------------------------------------------------------------- checked hooks
    def _liftoff_array(self, out: Any, n: int, method: str = "_predict") -> np.ndarray:
        """``out``, which the law's ``method`` returned for ``n`` landings, as an (n, 3) float64 array.

        One shape check per call (not per row): a law author's mistake becomes a LawDefinitionError
        naming the class, the method and the shape, instead of a broadcasting error deep in a fit.
        """
        arr = out if isinstance(out, np.ndarray) else None
        if arr is None:
            try:
                arr = np.asarray(out)
            except (TypeError, ValueError) as exc:
                raise LawDefinitionError(f"{law_name(self)}.{method} returned {type(out).__name__} that is not an "
                                         f"array ({exc}); it must return an ({n}, 3) float array of lift-offs "
                                         "[xdotF, ydotF, omegaF], one row per landing row of p") from None
        if arr.shape != (n, 3) or arr.dtype.kind not in "fiu":
            what = f"an array of shape {arr.shape} and dtype {arr.dtype}"
            hint = ""
            if arr.shape == (3, n) and n != 3:
                hint = ("; it looks transposed: build it with np.column_stack([xdotF, ydotF, omegaF]) (or "
                        "np.stack(..., axis=1)), not np.array([xdotF, ydotF, omegaF])")
            raise LawDefinitionError(f"{law_name(self)}.{method} returned {what}; it must return an (n, 3) real "
                                     f"array of lift-offs [xdotF, ydotF, omegaF], one row per landing row of p "
                                     f"(here n = {n}: shape ({n}, 3)){hint}")
        return arr if arr.dtype == np.float64 else arr.astype(np.float64)

    def _code_array(self, c: Any, n: int) -> np.ndarray:
        """``c``, which the law's ``_regime`` returned for ``n`` landings, as (n,) integer codes (checked once)."""
        arr = c if isinstance(c, np.ndarray) else None
        if arr is None:
            try:
                arr = np.asarray(c)
            except (TypeError, ValueError):
                arr = np.asarray(None)
        if arr.shape != (n,) or arr.dtype.kind not in "iu":
            raise LawDefinitionError(f"{law_name(self)}._regime returned an array of shape {arr.shape} and dtype "
                                     f"{arr.dtype}; it must return ({n},) integer codes, one per landing row of p, "
                                     f"each an index into regimes {list(self.regimes)} (e.g. "
                                     "np.zeros(len(p), dtype=np.int8))")
        return arr

    def _predict_valid(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """:meth:`_predict` on validated landings, its result checked (for internal callers: fits, reports)."""
        return self._liftoff_array(self._predict(p, theta), len(p))

    def _regime_valid(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """:meth:`_regime` on validated landings, its codes checked (shape, dtype, range)."""
        return self._regime_output(self._code_array(self._regime(p, theta), len(p)), True)

    def _lazy_input(self, da: Any) -> Any:
        from bouncelab.core.units import COMPONENTS

        if "component" not in da.dims or da.sizes["component"] != 3:
            raise DataError(f"landing DataArray needs a 'component' dimension of size 3; its sizes are "
                            f"{dict(da.sizes)}")
        if "component" in da.coords:
            labels = [str(v) for v in da["component"].values]
            if sorted(labels) != sorted(COMPONENTS):
                raise DataError(f"landing component labels must be {list(COMPONENTS)}; got {labels}")
            da = da.sel(component=list(COMPONENTS))
        return da.chunk({"component": -1})

    def _predict_lazy(self, da: Any, plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
                      radius_m: float | None = None) -> Any:
        """``predict`` of a dask-backed DataArray: one task per chunk, nothing computed yet (guarded per chunk)."""
        import xarray as xr

        from bouncelab.core.units import COMPONENT_UNITS, COMPONENTS

        out = xr.apply_ufunc(lambda block: self.predict(block, plausible=plausible, radius_m=radius_m),
                             self._lazy_input(da), input_core_dims=[["component"]], output_core_dims=[["component"]],
                             dask="parallelized", output_dtypes=[np.float64])
        return out.assign_coords(component=list(COMPONENTS), unit=("component", list(COMPONENT_UNITS)))

    def _regime_lazy(self, da: Any, codes: bool, plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
                     radius_m: float | None = None) -> Any:
        import xarray as xr

        names = np.asarray(self.regimes)
        dtype = np.int8 if codes else names.dtype

        def block_codes(block: np.ndarray) -> np.ndarray:
            return self.regime(block, codes=True, plausible=plausible, radius_m=radius_m)

        return xr.apply_ufunc(lambda block: block_codes(block) if codes else names[block_codes(block)],
                              self._lazy_input(da), input_core_dims=[["component"]], dask="parallelized",
                              output_dtypes=[dtype])

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
        if codes:
            return c if c.dtype == np.int8 else c.astype(np.int8)
        return np.asarray(self.regimes)[c]

    def _predict(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The law's maths: (n, 3) lift-offs of the validated (n, 3) landings ``p`` (a law must define it)."""
        raise LawDefinitionError(
            f"{law_name(self)} defines no _predict: write the method _predict(self, p, theta) returning the "
            "(n, 3) lift-offs [xdotF, ydotF, omegaF] of the (n, 3) landings p for the parameter vector theta "
            "(or subclass bouncelab.laws.CompiledLaw and set kernel)")

    def _regime(self, p: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """The regime codes (n,) of the landings ``p``, indices into :attr:`regimes` (a law must define it)."""
        raise LawDefinitionError(
            f"{law_name(self)} defines no _regime: write the method _regime(self, p, theta) returning one integer "
            f"code per landing row of p, an index into regimes {list(self.regimes)} (for a law with one regime, "
            "np.zeros(len(p), dtype=np.int8)); or subclass bouncelab.laws.CompiledLaw and set kernel")

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
            err = liftoff - self._predict_valid(landing, theta)  # a wrong shape: LawDefinitionError, not a broadcast
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

    # ------------------------------------------------------------ provenance
    @property
    def provenance(self) -> Provenance | None:
        """What the law was fitted to (:class:`~bouncelab.laws.provenance.Provenance`), or None.

        Set by :func:`bouncelab.fit` on the law it returns and by :func:`load_law` from the
        file. It is metadata, not part of the law's value: it changes neither ``==`` nor
        ``hash``, and :meth:`replace` (a law with other values) drops it.
        """
        return self.__dict__.get("_provenance")

    def _with_provenance(self, provenance: Provenance | None) -> BounceModel:
        """A copy of this law (equal to it) that carries ``provenance``; this law is unchanged."""
        out = copy.copy(self)
        object.__setattr__(out, "_provenance", provenance)
        return out

    # ------------------------------------------------------------ serialisation
    def _value_dict(self) -> dict[str, Any]:
        """``{"law", "parameters", "options"}``: what makes the law the value it is."""

        def plain(v: Any) -> Any:
            return v.tolist() if isinstance(v, np.ndarray) else v

        d: dict[str, Any] = {"law": law_name(self),
                             "parameters": {k: plain(v) for k, v in self.parameters.items()}}
        if self.option_names():
            d["options"] = {k: plain(v) for k, v in self.options.items()}
        return d

    def to_dict(self, *, metadata: bool = True) -> dict[str, Any]:
        """JSON-safe description, the content of a law file (format :data:`LAW_FORMAT_VERSION`).

        ``metadata=False`` gives the law's value alone, in the keys of the first format
        (``law``, ``parameters``, ``options``, ``bouncelab_version``): for descriptions that embed a
        law among their own units and conventions (e.g. a simulated turf's); it loads as well.

        Keys: ``format`` and ``format_version``; ``law`` (:func:`law_name`: the class name for
        bouncelab's laws, ``module:QualName`` for others) and, for a class of yours, ``class``
        (its module, qualified name and, for a script run as ``__main__``, the script's file);
        ``parameters``, ``parameter_units`` and ``options``; ``bouncelab_version``; ``units``
        and ``conventions`` (scaled units, y up, omega anticlockwise: omega > 0 is backspin);
        ``ball_radius_m`` (the radius of the fitted campaign's scaling, else the default 21.35 mm);
        ``provenance`` (:class:`~bouncelab.laws.provenance.Provenance` of a fitted law: the data,
        synthetic or measured, the generator of synthetic data, the fit, the landing ranges
        fitted), or None.
        """
        from bouncelab.core import __version__
        from bouncelab.core.units import BALL_RADIUS_M, COMPONENT_UNITS, COMPONENTS
        from bouncelab.data.campaign import CONVENTIONS

        cls = type(self)
        if not metadata:
            return {**self._value_dict(), "bouncelab_version": __version__}
        d: dict[str, Any] = {"format": LAW_FORMAT, "format_version": LAW_FORMAT_VERSION, **self._value_dict()}
        if not _is_builtin(cls):
            d["class"] = {"module": cls.__module__, "qualname": cls.__qualname__, "script": script_module(cls)[1]}
        d["parameter_units"] = {spec.name: spec.unit for spec in self.parameter_specs}
        d["bouncelab_version"] = __version__
        d["units"] = dict(zip(COMPONENTS, COMPONENT_UNITS, strict=True))
        d["conventions"] = CONVENTIONS
        prov = self.provenance
        d["ball_radius_m"] = BALL_RADIUS_M if prov is None else prov.ball_radius_m
        d["provenance"] = None if prov is None else prov.to_dict()
        return d

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> BounceModel:
        """Rebuild a law from :meth:`to_dict` output (any registered law when called on BounceModel)."""
        return law_from_dict(d, expected=None if cls is BounceModel else cls)

    def to_json(self, path: str | Path | None = None, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` if given (atomically).

        Raises
        ------
        OutputError
            ``path`` cannot be written (a missing or read-only folder, a folder at ``path``, a
            full disk): a :class:`~bouncelab.core.errors.BouncelabError` that is also an
            :class:`OSError`, naming the path. Nothing is written; a file already there is unchanged.
        """
        text = json.dumps(self.to_dict(), indent=2, **kwargs)
        if path is not None:
            from bouncelab.core.atomic import atomic_write_text
            from bouncelab.core.errors import OutputError

            try:
                atomic_write_text(path, text + "\n")
            except OSError as exc:
                reason = exc.strerror or str(exc)
                raise OutputError(f"cannot write the law to {str(path)!r}: {reason}; nothing was written (a file "
                                  "already there is unchanged)", path=str(path), reason=reason) from None
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

    def __str__(self) -> str:
        """The repr, marked when the law was fitted to synthetic data: ``Rigid(r=0.5, mu=0.3) [fitted to
        SYNTHETIC bounces (...), not measured ones]``. One line, so that it reads in an f-string too."""
        prov = self.provenance
        tag = None if prov is None else prov.synthetic_tag()
        return repr(self) if tag is None else f"{self!r} [{tag}]"

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        a, b = self.get_params(), other.get_params()
        return all(np.array_equal(np.asarray(a[k], dtype=object), np.asarray(b[k], dtype=object)) for k in a)

    def __hash__(self) -> int:
        d = self._value_dict()
        return hash((d["law"], json.dumps([d["parameters"], d.get("options")], sort_keys=True, default=str)))


def _guard(plausible: PlausibleRanges | None, radius_m: float, io: Any,
           landing: Any) -> Callable[[np.ndarray], None] | None:
    """The unit guard of one ``predict``/``regime`` call (None when ``plausible=None``)."""
    if plausible is None:
        return None
    from bouncelab.laws._physical_io import guard_landings

    pd = sys.modules.get("pandas")
    labels = landing.index if pd is not None and isinstance(landing, pd.DataFrame) else None
    return lambda p: guard_landings(p, plausible, radius_m, io, labels)


def law_from_dict(d: Mapping[str, Any], expected: type[BounceModel] | None = None) -> BounceModel:
    """Build a law from a law description (:meth:`BounceModel.to_dict`, or a law file's JSON).

    Every format bouncelab has written loads: the current one (:data:`LAW_FORMAT_VERSION`) and
    the first (``{"law", "parameters", "options", "bouncelab_version"}``, with no format
    version). The law's :attr:`~BounceModel.provenance` is restored when the description has one.
    A law of a script run as ``__main__`` is found once the script's module is imported (see
    :func:`law_class`).

    Raises
    ------
    UnknownLawError
        No law of that name is registered (a ParameterError saying what to import).
    ParameterError
        Anything else wrong with the description: missing keys, an ambiguous law name, unknown or
        bad parameter values, a malformed provenance, a format newer than this bouncelab reads
        (never TypeError and the like).
    """
    if not isinstance(d, Mapping) or "law" not in d or "parameters" not in d:
        raise ParameterError("a law description needs the keys 'law' and 'parameters'")
    version = d.get("format_version", 1)
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise ParameterError(f"the law description's format_version must be a whole number >= 1; got {version!r}")
    if version > LAW_FORMAT_VERSION:
        raise ParameterError(f"the law description is in format {version}, written by a newer bouncelab "
                             f"({d.get('bouncelab_version', 'unknown version')}); this bouncelab reads formats up "
                             f"to {LAW_FORMAT_VERSION}: upgrade bouncelab to read it")
    name = d["law"]
    if not isinstance(name, str):
        raise ParameterError(f"the law name must be a string; got {name!r}")
    record = d.get("class")
    script = record.get("script") if isinstance(record, Mapping) else None
    if script is not None and not isinstance(script, str):
        script = None
    if isinstance(record, Mapping) and record.get("module") in _MAIN_MODULES and ":" in name:
        qualname = record.get("qualname")
        # a script's law: the name its importing module gives it, else any one class of that qualified name
        try:
            cls = law_class(name, script=script)
        except UnknownLawError as first:
            if not isinstance(qualname, str):
                raise
            try:
                cls = law_class(f"__main__:{qualname}", script=script)
            except UnknownLawError:
                raise first from None  # it names the module to import
    else:
        cls = law_class(name, script=script)
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
        law = cls(**kwargs)
    except ParameterError:
        raise
    except (TypeError, ValueError, OverflowError, RecursionError, AttributeError) as exc:
        raise ParameterError(f"{name}: bad parameter values in the description ({type(exc).__name__}: {exc})") from None
    prov = d.get("provenance")
    if prov is not None:
        law = law._with_provenance(Provenance.from_dict(prov, where=f"the description of {name}"))
    return law


def load_law(path: str | Path) -> BounceModel:
    """Read a law written by :meth:`BounceModel.to_json` (any format bouncelab has written).

    A law fitted to synthetic bounces (the embedded surrogates, a simulation) comes with a
    :class:`~bouncelab.core.errors.SyntheticDataWarning` saying so, and ``print(law)`` says it too
    (``law.provenance``).

    Raises
    ------
    DataError
        The file cannot be read: missing, a folder, not a regular file, unreadable (naming it in
        ``err.file``).
    UnknownLawError
        The law's class is not registered in this process: the error says what to import (a
        script's law: the script's module, e.g. ``import myscript``).
    ParameterError
        The file is not a law description: not JSON, too deeply nested, a number too long to
        read, bad parameter values (naming the file).

    Warns
    -----
    SyntheticDataWarning
        The law was fitted to synthetic bounces: it describes the model that generated them,
        not real turf.
    """
    if isinstance(path, str) and path.lstrip().startswith("{"):  # the JSON itself, not a file name
        raise ParameterError("load_law takes the path of a law JSON file; for JSON text use "
                             "bouncelab.laws.law_from_dict(json.loads(text))")
    try:
        file = str(Path(path))
    except TypeError:
        raise ParameterError(f"load_law takes the path of a law JSON file; got {type(path).__name__}") from None
    data = _read_law_file(Path(path).expanduser(), file)
    try:
        d = json.loads(data.decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError, RecursionError) as exc:  # JSONDecodeError, and too-long integers
        raise ParameterError(f"{file}: not a JSON law description ({type(exc).__name__}: {exc})") from None
    try:
        law = law_from_dict(d)
    except UnknownLawError as exc:
        raise UnknownLawError(f"{file}: {exc}", law_name=exc.law_name, module=exc.module, qualname=exc.qualname,
                              module_imported=exc.module_imported, script=exc.script) from None
    except ParameterError as exc:
        raise ParameterError(f"{file}: {exc}") from None
    note = None if law.provenance is None else law.provenance.synthetic_note()
    if note is not None:
        from bouncelab.core.errors import SyntheticDataWarning

        warnings.warn(f"{file}: {note}", SyntheticDataWarning, stacklevel=2)
    return law


def _read_law_file(path: Path, file: str) -> bytes:
    """The bytes of a law file (DataError naming it when it cannot be read)."""
    from bouncelab.data.io.load import _read_bytes

    if not path.exists():
        raise DataError("no such law file", file=file)
    if path.is_dir():
        raise DataError("it is a directory, not a law file (give the path of the .json file the law was written to)",
                        file=file)
    try:
        return _read_bytes(path, file)
    except OSError as exc:
        raise DataError(f"the law file cannot be read ({exc.strerror or exc})", file=file) from None
