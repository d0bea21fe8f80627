"""The law protocol: :class:`BounceModel`, a law declared by its parameters, and its public methods.

A bounce law maps the landing state ``p0 = [xdot0, ydot0, omega0]`` of a ball to its lift-off state
``pF = [xdotF, ydotF, omegaF]`` (scaled units, see :mod:`bouncelab.core.units`). A law is declared once:

``r = Parameter(bounds=..., physical=..., unit=..., doc=...)``
    each parameter, a class attribute that takes its name from the attribute
    (:class:`~bouncelab.laws.parameters.Parameter`; scalars or arrays); ``fade = Option(default=...)`` a
    constructor keyword that is not fitted;
``regimes``
    the names of its regimes;
``_predict(self, p, **parameters)`` and ``_regime(self, p, **parameters)``
    the maths, on a validated C-contiguous ``(n, 3)`` float64 array ``p``, the parameters by name
    (checked against the declaration when the class is defined); or a compiled ``kernel``
    (:class:`~bouncelab.laws.CompiledLaw`);
``_summary_lines()`` and ``_diagnostics(landing, liftoff)``
    what reports print about it beyond its parameters;
methods decorated with :func:`~bouncelab.laws.protocol.fit_method`
    its own fitting procedures, beside the generic ``"global"`` search.

:class:`BounceModel` does everything that is the same for every law: the constructor (keywords in
declaration order, validated), immutability, ``replace``, repr, equality, JSON, and the public
``predict``, ``regime`` and ``predict_one``, in the manner of scipy.stats' ``pdf`` → ``_argcheck`` →
``_pdf``: one path takes the landings once (:class:`~bouncelab.laws._physical_io.Landings`: their kind,
units, form and shape), calls the law's hook (:meth:`~BounceModel._evaluate_checked`,
:meth:`~BounceModel._classify_checked`, or for one landing :meth:`~BounceModel._one_entry_point`), which
checks the values and the unit guard in the pass that computes (a compiled law's loops; a NumPy law's hook
scans them first), and words a failed verdict; the results go back in the caller's kind, with the
non-physical-lift-off flags (:mod:`bouncelab.laws.nonphysical`). Generic code (``fit``, ``compare``,
reports, the command line) reads everything from the law and never names one.

Examples
--------
A new law is one small class:

>>> import numpy as np
>>> import bouncelab as bl
>>> class Restitution(bl.BounceModel):
...     '''Frictionless bounce: pF = [xdot0, -e ydot0, omega0].'''
...     e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
...     regimes = ("bounce",)
...     def _predict(self, p, e):
...         return p * np.array([1.0, -e, 1.0])
...     def _regime(self, p, e):
...         return np.zeros(len(p), dtype=np.int8)
>>> Restitution(e=0.5).predict([[100.0, -200.0, 30.0]])
array([[100., 100.,  30.]])
"""

from __future__ import annotations

import copy
import functools
import inspect
import json
import math
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from bouncelab.core import checks
from bouncelab.core.atomic import write_output
from bouncelab.core.errors import (
    DataError,
    LargeResultWarning,
    LawDefinitionError,
    NotFittedError,
    OutsideFittedRangeWarning,
    ParameterError,
)
from bouncelab.core.landing_checks import INVALID, is_landing, landing_fault
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, guard_limits, landing_limits, landing_status
from bouncelab.core.units import BALL_RADIUS_M, COMPONENTS
from bouncelab.core.validation import States, check_values
from bouncelab.laws import nonphysical, registry
from bouncelab.laws._physical_io import (
    Landings,
    PhysicalIO,
    check_plausible_argument,
    io_option,
    is_lazy,
    lazy_predict,
    lazy_regime,
    radius_of,
)
from bouncelab.laws.files import describe, law_from_dict, value_dict
from bouncelab.laws.parameters import Option, Parameter, Parameters, collect
from bouncelab.laws.protocol import DEFAULT_LOCAL_ALGORITHM, FitOutcome, FitProblem, fit_method, fit_methods
from bouncelab.laws.provenance import Provenance, outside_ranges
from bouncelab.laws.registry import law_name
from bouncelab.laws.varying import predict_per_bounce

__all__ = ["REGIME_NAMES_WARN", "BounceModel"]

#: From this many landings on, ``regime`` names (rather than codes) come with a LargeResultWarning.
REGIME_NAMES_WARN = 1_000_000

_OLD_FORM = (
    "declare each parameter once, as a class attribute, and write no __init__: e.g.\n"
    "    class MyLaw(bl.BounceModel):\n"
    "        r = bl.Parameter(bounds=(0, 1), physical=(0, 1), unit='1', doc='restitution')\n"
    "        regimes = ('bounce',)\n"
    "        def _predict(self, p, r): ...\n"
    "        def _regime(self, p, r): ...\n"
    "(the constructor takes the parameters by keyword or in declaration order; options that are not fitted are "
    "bl.Option(default=...), by keyword)"
)


class _class_or_instance:
    """A method that receives the class when called on it and the instance when called on one."""

    def __init__(self, func: Callable) -> None:
        self.func = func
        self.__doc__ = func.__doc__

    def __get__(self, obj: Any, cls: type) -> Any:
        return functools.partial(self.func, cls if obj is None else obj)


class _class_or_instance_property(_class_or_instance):
    """A read-only property of the class when read on it and of the instance when read on one."""

    def __get__(self, obj: Any, cls: type) -> Any:
        return self.func(cls if obj is None else obj)

    def __set__(self, obj: Any, value: Any) -> None:  # a data descriptor: an instance cannot shadow it
        raise AttributeError("params is read-only; use .replace(...) for a law with other values")


class BounceModel:
    """Abstract bounce law: landing state in, lift-off state out.

    Subclasses declare their parameters as class attributes (:class:`~bouncelab.laws.Parameter`), their
    ``regimes``, and implement ``_predict`` and ``_regime`` (or set a compiled ``kernel``, see
    :class:`~bouncelab.laws.CompiledLaw`). Constructor keywords that are not parameters are options
    (:class:`~bouncelab.laws.Option`): stored, serialised and printed, never fitted.

    A law is a value: it is immutable once built; :meth:`replace` makes a changed copy. A law built
    without values is *unfitted*: its parameters are ``None`` and :meth:`predict` raises
    :class:`~bouncelab.NotFittedError` until it is fitted (:func:`bouncelab.fit`) or given values.
    """

    #: The law's parameters in declaration order (collected from the class attributes); the declaration that
    #: :attr:`params` shows with the values, read by bouncelab's generic code.
    parameter_specs: ClassVar[tuple[Parameter, ...]] = ()
    #: The law's options in declaration order.
    option_specs: ClassVar[tuple[Option, ...]] = ()
    #: Names of the regimes that :meth:`regime` returns, indexed by ``_regime``'s codes.
    regimes: ClassVar[tuple[str, ...]] = ()
    #: Method :func:`bouncelab.fit` uses when none is named.
    default_fit_method: ClassVar[str] = "global"
    #: How :func:`bouncelab.ground.bounce` lifts the law to a 3-D landing (see :mod:`bouncelab.ground.bounce3d`):
    #: the plane in which its 2-D maths acts, ``"travel"`` (the normal and the velocity along the ground: the
    #: default, continuous in the spin wherever the 2-D law is) or ``"slip"`` (the normal and the contact point's
    #: slip: exact for a law whose tangential contact is isotropic). A compiled law may instead give its own 3-D
    #: bounce (:attr:`CompiledLaw.kernel_3d <bouncelab.laws.CompiledLaw.kernel_3d>`).
    lift_plane: ClassVar[str] = "travel"

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for old in ("__init__", "parameter_specs"):
            if old in cls.__dict__:
                raise LawDefinitionError(f"{cls.__name__} defines {old}, the form of bouncelab before 0.2; "
                                         f"{_OLD_FORM}", law=cls.__name__, method=old)
        params, options = collect(cls, Parameter), collect(cls, Option)
        both = sorted(set(params) & set(options))
        if both:
            raise LawDefinitionError(f"{cls.__name__} declares {both} both as parameters and options",
                                     law=cls.__name__, method=both[0])
        cls.parameter_specs = tuple(params.values())
        cls.option_specs = tuple(options.values())
        either, kw = inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY
        cls.__signature__ = inspect.Signature(
            [inspect.Parameter(s.name, either, default=s.default) for s in cls.parameter_specs]
            + [inspect.Parameter(o.name, kw, default=o.default) for o in cls.option_specs])
        for hook in ("_predict", "_regime"):
            _check_hook_signature(cls, hook)
        if not (cls.__name__.startswith("_") or cls.__dict__.get("_abstract_law", False)):
            registry.register(cls)

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        name = law_name(self)
        if args:  # the parameters in declaration order (options by keyword only)
            names = [s.name for s in self.parameter_specs]
            if len(args) > len(names):
                raise ParameterError(f"{name} takes {len(names)} parameters {names} (options by keyword); got "
                                     f"{len(args)} positional values", law=name)
            both = [k for k in names[:len(args)] if k in kwargs]
            if both:
                raise ParameterError(f"{name} got {both} both by position and by keyword", law=name, parameter=both[0])
            kwargs = {**dict(zip(names, args, strict=False)), **kwargs}
        unknown = [k for k in kwargs if k not in self._keyword_names()]
        if unknown:
            raise ParameterError(f"{name} has no parameter(s) {unknown}; it has {list(self._keyword_names())}",
                                 law=name, parameter=unknown[0])
        values: dict[str, Any] = {}
        for spec in self.parameter_specs:
            value = kwargs.get(spec.name, spec.default)
            values[spec.name] = None if value is None else spec.check(value, name)
        options = {o.name: o.validate(kwargs[o.name], name) if o.name in kwargs else o.default
                   for o in self.option_specs}
        self.__dict__["_values"] = values
        self.__dict__["_options"] = options
        self.__dict__["_missing"] = [k for k, v in values.items() if v is None]  # a law is immutable: once
        self._check()

    def _check(self) -> None:
        """A hook for checks that involve several parameters (default: none); raise ParameterError."""

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"{type(self).__name__} is immutable; use .replace({name}=...) for a changed copy")

    # ----------------------------------------------------------------- parameters
    @classmethod
    def _keyword_names(cls) -> tuple[str, ...]:
        return tuple(s.name for s in cls.parameter_specs) + tuple(o.name for o in cls.option_specs)

    @classmethod
    def option_names(cls) -> tuple[str, ...]:
        """Constructor keywords that are not parameters (stored, serialised, never fitted)."""
        return tuple(o.name for o in cls.option_specs)

    def get_params(self, deep: bool = True) -> dict[str, Any]:
        """scikit-learn's convention: the constructor's keyword arguments as stored, parameters and options
        (``deep`` changes nothing). To read the parameters, use :attr:`params`."""
        return {**self.__dict__["_values"], **self.__dict__["_options"]}

    def __sklearn_clone__(self) -> BounceModel:
        """scikit-learn's ``clone``: a law is an immutable value, so it is its own clone."""
        return self

    @_class_or_instance_property
    def params(owner: Any) -> Parameters:
        """The parameters as objects, in declaration order: **the** way to read a law's parameters.

        A read-only mapping name -> :class:`~bouncelab.laws.Parameter` (value, default search bounds,
        physical range, unit, doc, whether it varies): ``law.params["r"].value``,
        ``law.params.valuesdict()`` (name -> value), ``law.params.flat()`` (every number by element name,
        ``A1[0,2]``). On the class, the declarations (``Rigid.params["mu"].bounds``; values ``None``).
        """
        if isinstance(owner, type):
            return Parameters(owner.parameter_specs)
        return Parameters(s.replace(value=owner.__dict__["_values"][s.name]) for s in owner.parameter_specs)

    @property
    def parameters(self) -> dict[str, float | np.ndarray | None]:
        """``params.valuesdict()``: the values by name (bouncelab's layers above the laws read it; prefer
        :attr:`params`)."""
        return dict(self.__dict__["_values"])

    def flat_parameters(self) -> dict[str, float | None]:
        """``params.flat()``: every number by element name (bouncelab's layers above the laws read it; prefer
        :attr:`params`)."""
        return self.params.flat()

    @property
    def options(self) -> dict[str, Any]:
        """The non-parameter constructor options, as stored."""
        return dict(self.__dict__["_options"])

    @classmethod
    def default_bounds(cls) -> dict[str, tuple[Any, Any]]:
        """Default fitting bounds, name -> (low, high)."""
        return {spec.name: spec.bounds for spec in cls.parameter_specs}

    @property
    def is_fitted(self) -> bool:
        """True when every parameter has a value."""
        return not self.__dict__["_missing"]

    def replace(self, **changes: Any) -> BounceModel:
        """A copy with some keyword arguments changed (validated like the constructor)."""
        unknown = sorted(set(changes) - set(self._keyword_names()))
        if unknown:
            raise ParameterError(f"{type(self).__name__} has no parameter(s) {unknown}; it has "
                                 f"{list(self._keyword_names())}", law=law_name(self), parameter=unknown[0])
        return type(self)(**{**self.get_params(), **changes})

    def _fitted_values(self) -> dict[str, Any]:
        """The parameter values by name, or NotFittedError naming the missing ones."""
        values = self.__dict__["_values"]
        missing = self.__dict__["_missing"]
        if missing:
            raise NotFittedError(f"{law_name(self)} has no value for {missing}; pass them to the constructor "
                                 f"or fit the law with bouncelab.fit({type(self).__name__}(), data)",
                                 law=law_name(self), missing=missing)
        return values

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
        if is_lazy(landing):
            self._lazy_refusal(units, form, return_flags=return_flags, warn_outside_fitted=warn_outside_fitted)
            return lazy_predict(self, landing, check_plausible_argument(plausible), radius_m)
        out, call = self._checked(self._evaluate_checked, landing, units, form, radius_m, plausible)
        out = self._liftoff_array(out, len(call.p))
        if warn_outside_fitted:
            self._warn_outside_fitted(call.p)
        result = call.liftoff(out)
        flags = nonphysical.flags_of(self, call.p, out, always=return_flags)
        if not return_flags:
            return result
        return result, nonphysical.LiftoffFlags(into_ground=call.per_bounce(flags[0]),
                                                energy_gain=call.per_bounce(flags[1]))

    def predict_one(self, xdot: float, ydot: float, omega: float, *,
                    plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
                    radius_m: float | None = None) -> tuple[float, float, float]:
        """The lift-off ``(xdotF, ydotF, omegaF)`` of one landing, as floats: the fast path of a simulator's loop.

        The same law, checks and numbers as ``predict([[xdot, ydot, omega]])[0]`` (scaled units, ``ydot < 0``;
        the unit guard ``plausible`` on the one landing, ``radius_m`` the ball it refers to), without the
        array machinery: a compiled law checks and predicts the landing in one compiled call (well under a
        microsecond for the closed-form laws).

        Raises
        ------
        DataError
            A value that is not a finite number, ``ydot >= 0``, a landing outside ``plausible``.
        NotFittedError
            Some parameters have no value.

        Examples
        --------
        >>> import bouncelab as bl
        >>> [round(v, 3) for v in bl.Rigid(r=0.5, mu=0.4).predict_one(1000.0, -800.0, 300.0)]
        [628.571, 400.0, -628.571]
        """
        if not type(xdot) is type(ydot) is type(omega) is float:  # (three floats go straight to the compiled check)
            xdot, ydot, omega = _one_landing(xdot, ydot, omega)
        one, rest = self.__dict__.get("_one_entry") or self._one_entry_point()
        if not (plausible is PLAUSIBLE_RANGES and radius_m is None):  # (rest: the default limits, then the law's)
            rest = (*_limits_of(plausible, radius_m), rest[-1])
        try:
            a, b, c, status = one(xdot, ydot, omega, *rest)
        except (TypeError, ValueError, OverflowError):  # not a number (the conversion to a float refused it)
            status = INVALID
        if status:
            self._refuse_one(xdot, ydot, omega, plausible, radius_m)
        return a, b, c

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
        if is_lazy(landing):
            self._lazy_refusal(units, form, classify=True)
            return lazy_regime(self, landing, codes, check_plausible_argument(plausible), radius_m)
        c, call = self._checked(self._classify_checked, landing, units, form, radius_m, plausible)
        c = self._codes(c, len(call.p))
        if codes:
            return call.per_bounce(c)
        names = np.asarray(self.regimes)
        if len(c) >= REGIME_NAMES_WARN:
            warnings.warn(f"regime names for {len(c):,} landings take {len(c) * names.itemsize / 1e6:.0f} MB; "
                          f"regime(..., codes=True) gives int8 codes into law.regimes ({len(c) / 1e6:.0f} MB)",
                          LargeResultWarning, stacklevel=2)
        return call.per_bounce(names[c])

    # ----------------------------------------------------------------- the public methods' one path
    def _checked(self, hook: Callable, landing: Any, units: Any, form: Any, radius_m: Any,
                 plausible: Any) -> tuple[Any, Landings]:
        """What ``predict`` and ``regime`` share: the landings taken once (:class:`Landings`: kind, units,
        form, shape), then the law's hook (:meth:`_evaluate_checked` or :meth:`_classify_checked`), which
        checks the values and the unit guard in its pass over them; a failed verdict is refused, naming the
        row. Returns the hook's result and the landings (to give results back in the caller's kind)."""
        values = self._fitted_values()
        call = Landings(landing, units, form, radius_m, plausible)
        out, status = hook(call.p, values, call.limits)
        if status:
            call.refuse(status)
        return out, call

    @staticmethod
    def _lazy_refusal(units: Any, form: Any, *, return_flags: bool = False, warn_outside_fitted: bool = False,
                      classify: bool = False) -> None:
        """DataError for what a dask-backed DataArray cannot be asked for (it is predicted chunk by chunk)."""
        io = PhysicalIO.needed(units, form)
        if not (io or return_flags or warn_outside_fitted):
            return
        if classify:
            raise DataError("a dask-backed DataArray is classified lazily in scaled Cartesian states only, without "
                            "units= or form=", option=io_option(units, form))
        at = io_option(units, form) if io else "return_flags" if return_flags else "warn_outside_fitted"
        raise DataError("a dask-backed DataArray is predicted lazily in scaled Cartesian states only, without "
                        "units=, form=, return_flags= or warn_outside_fitted=", option=at)

    def _refuse_one(self, xdot: Any, ydot: Any, omega: Any, plausible: Any, radius_m: Any) -> None:
        """The error of ``predict_one`` for a landing its check refused: that of ``predict`` on it."""
        self.predict(np.array([[xdot, ydot, omega]], dtype=object), plausible=plausible, radius_m=radius_m)
        raise DataError(f"landing ({xdot!r}, {ydot!r}, {omega!r}) is not three finite numbers with ydot < 0",
                        option="landing")  # (predict refuses it first)

    def _one_entry_point(self) -> tuple[Callable[..., tuple[float, float, float, int]], tuple]:
        """The law's one-landing hook and the arguments it takes after the landing under the default guard,
        built once per law (it is immutable) and kept as a cache.

        ``f(xdot, ydot, omega, min_s2, max_s2, max_w, tan_a, law) -> (xdotF, ydotF, omegaF, status)``: the
        value check and the guard of :mod:`bouncelab.core.landing_checks` on the floats, then the law's maths
        (here :meth:`_evaluate` of one row; a compiled law calls its kernel in the same compiled call,
        ``law`` its kernel's arguments). A status other than 0 is the verdict of
        :func:`~bouncelab.core.plausibility.landing_status`; a value that is not a number raises TypeError,
        ValueError or OverflowError.
        """
        values = self._fitted_values()

        def one(xdot: Any, ydot: Any, omega: Any, min_s2: float, max_s2: float, max_w: float, tan_a: float,
                law: BounceModel) -> tuple[float, float, float, int]:
            x, y, w = float(xdot), float(ydot), float(omega)
            if not is_landing(x, y, w):
                return math.nan, math.nan, math.nan, INVALID
            status = landing_fault(x, y, w, min_s2, max_s2, max_w, tan_a)
            if status:
                return math.nan, math.nan, math.nan, status
            out = law._evaluate(np.array([[x, y, w]]), values)
            return float(out[0, 0]), float(out[0, 1]), float(out[0, 2]), 0

        self.__dict__["_one_entry"] = found = (one, (*_DEFAULT_LIMITS, self))
        return found

    def _warn_outside_fitted(self, p: np.ndarray) -> None:
        """The warning of ``predict(..., warn_outside_fitted=True)``."""
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

    # ------------------------------------------------------------- the law's maths, checked
    def _evaluate_checked(self, p: np.ndarray, values: Mapping[str, Any],
                          limits: tuple[float, float, float, float] | None) -> tuple[Any, int]:
        """The hook of ``predict``: the law's lift-offs of ``p`` and the unit guard's verdict on the landings
        (:func:`~bouncelab.core.plausibility.landing_status` under ``limits``; 0: all valid and plausible).

        ``limits`` None: the landings are known to be valid, check nothing. This default checks the landings
        first, then calls ``_predict``; a compiled law checks them in the pass that predicts them.
        """
        if limits is not None:
            status = landing_status(p, limits)
            if status:
                return None, status
        return self._predict(p, **values), 0

    def _classify_checked(self, p: np.ndarray, values: Mapping[str, Any],
                          limits: tuple[float, float, float, float] | None) -> tuple[Any, int]:
        """The hook of ``regime``: the law's regime codes of ``p`` and the verdict (as :meth:`_evaluate_checked`)."""
        if limits is not None:
            status = landing_status(p, limits)
            if status:
                return None, status
        return self._regime(p, **values), 0

    def _evaluate(self, p: np.ndarray, values: Mapping[str, Any] | None = None) -> np.ndarray:
        """(n, 3) lift-offs of validated landings ``p`` with ``values`` (default: the law's own), checked.

        For the fitting machinery and analyses: no unit guard, no flags, no conversion (a landing that is not
        one, which a compiled law's loop does not predict, is still refused).
        """
        out, status = self._evaluate_checked(p, self._fitted_values() if values is None else values, None)
        if status:
            check_values(p, "landing", landing=True)
        return self._liftoff_array(out, len(p))

    def _classify(self, p: np.ndarray, values: Mapping[str, Any] | None = None) -> np.ndarray:
        """(n,) int8 regime codes of validated landings ``p`` with ``values`` (default: the law's own), checked."""
        c, status = self._classify_checked(p, self._fitted_values() if values is None else values, None)
        if status:
            check_values(p, "landing", landing=True)
        return self._codes(c, len(p))

    def _liftoff_array(self, out: Any, n: int) -> np.ndarray:
        """``out``, which the law's ``_predict`` returned for ``n`` landings, as an (n, 3) float64 array.

        One shape check per call (not per row): a law author's mistake becomes a LawDefinitionError
        naming the class, the method and the shape, instead of a broadcasting error deep in a fit.
        """
        arr = out if isinstance(out, np.ndarray) else None
        if arr is None:
            try:
                arr = np.asarray(out)
            except (TypeError, ValueError) as exc:
                raise LawDefinitionError(f"{law_name(self)}._predict returned {type(out).__name__} that is not an "
                                         f"array ({exc}); it must return an ({n}, 3) float array of lift-offs "
                                         "[xdotF, ydotF, omegaF], one row per landing row of p",
                                         law=law_name(self), method="_predict") from None
        if arr.shape != (n, 3) or arr.dtype.kind not in "fiu":
            what = f"an array of shape {arr.shape} and dtype {arr.dtype}"
            hint = ""
            if arr.shape == (3, n) and n != 3:
                hint = ("; it looks transposed: build it with np.column_stack([xdotF, ydotF, omegaF]) (or "
                        "np.stack(..., axis=1)), not np.array([xdotF, ydotF, omegaF])")
            raise LawDefinitionError(f"{law_name(self)}._predict returned {what}; it must return an (n, 3) real "
                                     f"array of lift-offs [xdotF, ydotF, omegaF], one row per landing row of p "
                                     f"(here n = {n}: shape ({n}, 3)){hint}", law=law_name(self), method="_predict")
        return arr if arr.dtype == np.float64 else arr.astype(np.float64)

    def _codes(self, c: Any, n: int) -> np.ndarray:
        """``c``, which the law's ``_regime`` returned for ``n`` landings, as (n,) int8 codes into :attr:`regimes`."""
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
                                     "np.zeros(len(p), dtype=np.int8))", law=law_name(self), method="_regime")
        if arr.size and (int(arr.min()) < 0 or int(arr.max()) >= len(self.regimes)):
            bad = int(arr.min()) if int(arr.min()) < 0 else int(arr.max())
            raise LawDefinitionError(f"{law_name(self)} gave regime code {bad}, but its regimes are "
                                     f"{list(self.regimes)} (codes 0..{len(self.regimes) - 1})",
                                     law=law_name(self), method="_regime")
        return arr if arr.dtype == np.int8 else arr.astype(np.int8)

    def _predict(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        """The law's maths: (n, 3) lift-offs of the validated (n, 3) landings ``p`` (a law must define it)."""
        names = ", ".join(s.name for s in self.parameter_specs)
        raise LawDefinitionError(
            f"{law_name(self)} defines no _predict: write the method _predict(self, p, {names}) returning the "
            "(n, 3) lift-offs [xdotF, ydotF, omegaF] of the (n, 3) landings p (or subclass "
            "bouncelab.laws.CompiledLaw and set kernel)", law=law_name(self), method="_predict")

    def _regime(self, p: np.ndarray, **parameters: Any) -> np.ndarray:
        """The regime codes (n,) of the landings ``p``, indices into :attr:`regimes` (a law must define it)."""
        names = ", ".join(s.name for s in self.parameter_specs)
        raise LawDefinitionError(
            f"{law_name(self)} defines no _regime: write the method _regime(self, p, {names}) returning one "
            f"integer code per landing row of p, an index into regimes {list(self.regimes)} (for a law with one "
            "regime, np.zeros(len(p), dtype=np.int8)); or subclass bouncelab.laws.CompiledLaw and set kernel",
            law=law_name(self), method="_regime")

    @_class_or_instance
    def predict_varying(owner: Any, landing: Any, params: Any, *, codes: bool = False) -> Any:
        """Lift-off of ``n`` landings with parameter values per landing (spot-to-spot variation of a surface).

        ``params`` is an ``(n, k)`` array of the law's numbers in declaration order (a single row
        broadcasts) or a mapping (dict, DataFrame) naming the law's parameters; each row gives what
        ``Law(**row).predict(landing_row)`` gives, without building ``n`` laws (a compiled law runs one
        compiled loop). On the class the options are their defaults; on a law, its options (its parameter
        values are not used). No unit guard: these are a simulation's states. ``codes=True`` also returns
        the regime codes. See :func:`bouncelab.laws.varying.predict_per_bounce`.
        """
        return predict_per_bounce(owner, landing, params, codes=codes)

    # --------------------------------------------------------------- the objective
    def _error_function(self, landing: np.ndarray, liftoff: np.ndarray,
                        inv_norm: np.ndarray) -> Callable[[Sequence[Any]], Any]:
        """The fitter's objective hook: a function of the parameter values (in declaration order) giving four
        sums over the bounces.

        ``[sum ||e_i|| / ||p0_i||, sum |ex_i| / ||p0_i||, sum |ey_i| / ||p0_i||, sum |ew_i| / ||p0_i||]`` with
        ``e_i = pF_i - predicted_i``; divided by n they are delta (eq. error) and the three Delta q (eq.
        error_individual). The arguments are validated ``(n, 3)`` arrays and ``1 / ||p0_i||``, fixed for a
        fit. This default predicts with ``_predict`` and sums with NumPy; a compiled law computes the same in
        one compiled pass.
        """
        names = [s.name for s in self.parameter_specs]

        def sums(values: Sequence[Any]) -> np.ndarray:
            err = liftoff - self._evaluate(landing, dict(zip(names, values, strict=True)))
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
        return fit_methods(cls)

    # ------------------------------------------------------------- published laws
    @classmethod
    def published(cls, campaign: str) -> BounceModel:
        """The law with the reference paper's published values for campaign "A" or "B"."""
        raise ParameterError(f"the paper publishes no values for {law_name(cls)}", law=law_name(cls))

    # ------------------------------------------------------------ provenance
    @property
    def provenance(self) -> Provenance | None:
        """What the law was fitted to (:class:`~bouncelab.laws.provenance.Provenance`), or None.

        Set by :func:`bouncelab.fit` on the law it returns and by :func:`bouncelab.load_law` from the
        file. It is metadata, not part of the law's value: it changes neither ``==`` nor
        ``hash``, and :meth:`replace` (a law with other values) drops it.
        """
        return self.__dict__.get("_provenance")

    def _with_provenance(self, provenance: Provenance | None) -> BounceModel:
        """A copy of this law (equal to it) that carries ``provenance``; this law is unchanged."""
        out = copy.copy(self)
        out.__dict__["_provenance"] = provenance
        return out

    # ------------------------------------------------------------ serialisation
    def to_dict(self, *, metadata: bool = True) -> dict[str, Any]:
        """JSON-safe description, the content of a law file (see :func:`bouncelab.laws.files.describe`)."""
        return describe(self, metadata=metadata)

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
            write_output(path, text + "\n", "the law")
        return text

    # ------------------------------------------------------------ dunder methods
    def __getstate__(self) -> dict[str, Any]:
        # the per-law caches (a compiled entry point, kernel arguments) are rebuilt on use: a compiled
        # function cannot be pickled, and a copy with other provenance should not share them
        return {k: v for k, v in self.__dict__.items() if k not in _CACHES}

    def __repr__(self) -> str:
        parts = []
        defaults = {o.name: o.default for o in self.option_specs}
        for k, v in self.get_params().items():
            if k in defaults and v is defaults[k]:  # options at their default are not shown
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

    def _repr_html_(self) -> str:
        from bouncelab.laws._display import law_html  # what a notebook shows (bouncelab.laws._display)

        return law_html(self)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        a, b = self.get_params(), other.get_params()
        return all(np.array_equal(np.asarray(a[k], dtype=object), np.asarray(b[k], dtype=object)) for k in a)

    def __hash__(self) -> int:
        d = value_dict(self)
        return hash((d["law"], json.dumps([d["parameters"], d.get("options")], sort_keys=True, default=str)))


def _check_hook_signature(cls: type, hook: str) -> None:
    """LawDefinitionError, at class definition, for a ``_predict`` or ``_regime`` that cannot take what the
    public methods pass it: the landings ``p`` by position, then every declared parameter by name (and
    nothing else it requires)."""
    for klass in cls.__mro__:
        if hook in vars(klass):
            raw = vars(klass)[hook]
            break
    else:
        return
    if klass is BounceModel:  # the default: it says, when called, that the law must define the hook
        return
    func = raw.__func__ if isinstance(raw, staticmethod | classmethod) else raw
    try:
        params = list(inspect.signature(func).parameters.values())
    except (TypeError, ValueError):  # not introspectable (a builtin, a C function): called as it is
        return
    if not isinstance(raw, staticmethod):
        params = params[1:]  # self (or cls)
    names = [s.name for s in cls.parameter_specs]
    kinds = inspect.Parameter
    positional = [q for q in params if q.kind in (kinds.POSITIONAL_ONLY, kinds.POSITIONAL_OR_KEYWORD)]
    takes_p = bool(positional) or any(q.kind is kinds.VAR_POSITIONAL for q in params)
    rest = params[1:] if positional and params[0] is positional[0] else params
    by_name = {q.name for q in rest if q.kind in (kinds.POSITIONAL_OR_KEYWORD, kinds.KEYWORD_ONLY)}
    any_name = any(q.kind is kinds.VAR_KEYWORD for q in rest)
    missing = [] if any_name else [n for n in names if n not in by_name]
    unknown = [q.name for q in rest if q.default is q.empty and q.name not in names
               and q.kind not in (kinds.VAR_POSITIONAL, kinds.VAR_KEYWORD)]
    if takes_p and not missing and not unknown:
        return
    faults = (["it takes no landings p"] if not takes_p else []) + \
        ([f"it does not take {missing}"] if missing else []) + \
        ([f"it requires {unknown}, which the law does not declare"] if unknown else [])
    raise LawDefinitionError(
        f"{cls.__name__}.{hook}{inspect.signature(func)} does not match the law's parameters {names}: it is "
        f"called as {hook}(p, {', '.join(f'{n}=...' for n in names)}), but {' and '.join(faults)}; write "
        f"def {hook}(self, p, {', '.join(names)}): ...", law=cls.__name__, method=hook)


#: Entries of a law's __dict__ that are caches, not state (see BounceModel.__getstate__).
_CACHES = ("_args_cache", "_one_entry")

#: The unit guard's limits of the default ranges and ball, for predict_one.
_DEFAULT_LIMITS = landing_limits(BALL_RADIUS_M, PLAUSIBLE_RANGES)

#: (id of the ranges, radius) -> (the ranges, their limits). Holding the ranges keeps their id from being reused
#: by another object while cached; keying by id keeps the lookup cheap on the single-bounce path.
_LIMITS: dict[tuple[int, Any], tuple[Any, tuple[float, float, float, float]]] = {}


def _one_landing(xdot: Any, ydot: Any, omega: Any) -> tuple[float, float, float]:
    """``predict_one``'s landing as three floats, each a real number by :func:`bouncelab.core.checks.finite`'s
    rule (not text, a bool, a complex number or an integer beyond a float: a DataError naming the component);
    NaN and infinities pass, for the landing check to refuse as ``predict`` does."""
    out = []
    for name, v in zip(COMPONENTS, (xdot, ydot, omega), strict=True):
        x, why = checks.as_float(v)
        if why:
            raise DataError(f"landing {name} must be a real number; got {checks.shown(v)} ({why})",
                            column=f"landing.{name}", row=1, option="landing")
        out.append(x)
    return out[0], out[1], out[2]


def _limits_of(plausible: Any, radius_m: Any) -> tuple[float, float, float, float]:
    """The guard's limits of ``plausible=`` and ``radius_m=`` (as :class:`Landings` makes them), cached."""
    key = (id(plausible), radius_m)
    try:
        cached = _LIMITS.get(key)
    except TypeError:  # an unhashable radius: not cached (radius_of refuses it when the guard needs it)
        key = cached = None
    if cached is not None:
        return cached[1]
    ranges = check_plausible_argument(plausible)
    limits = guard_limits(ranges, None if ranges is None else radius_of(radius_m))
    if key is not None:
        _LIMITS[key] = (plausible, limits)
        if len(_LIMITS) > 64:  # a few ranges and balls in a program: keep the cache small
            _LIMITS.pop(next(iter(_LIMITS)))
    return limits
