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
    the maths, on a validated C-contiguous ``(n, 3)`` float64 array ``p``, the parameters by name;
    or a compiled ``kernel`` (:class:`~bouncelab.laws.CompiledLaw`);
``_summary_lines()`` and ``_diagnostics(landing, liftoff)``
    what reports print about it beyond its parameters;
methods decorated with :func:`~bouncelab.laws.protocol.fit_method`
    its own fitting procedures, beside the generic ``"global"`` search.

:class:`BounceModel` does everything that is the same for every law: the constructor (keywords in
declaration order, validated), immutability, ``replace``, repr, equality, JSON, and the public
``predict`` and ``regime``, which check their input once and call the law's maths, in the manner of
scipy.stats' ``pdf`` → ``_argcheck`` → ``_pdf``. Physical units and polar forms, lazy dask arrays and
the non-physical-lift-off flags are layers around that core (:mod:`bouncelab.laws._physical_io`,
:mod:`bouncelab.laws.nonphysical`). Generic code (``fit``, ``compare``, reports, the command line) reads
everything from the law and never names one.

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

from bouncelab.core.errors import DataError, LawDefinitionError, NotFittedError, ParameterError
from bouncelab.core.plausibility import PLAUSIBLE_RANGES, PlausibleRanges, landing_limits
from bouncelab.core.units import BALL_RADIUS_M
from bouncelab.core.validation import STATE_LIMIT, States, as_states, check_values
from bouncelab.laws import registry
from bouncelab.laws.parameters import Option, Parameter, Parameters, collect
from bouncelab.laws.protocol import DEFAULT_LOCAL_ALGORITHM, FitOutcome, FitProblem, fit_method, fit_methods
from bouncelab.laws.provenance import Provenance
from bouncelab.laws.registry import law_name

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

    #: The law's parameters in declaration order (collected from the class attributes).
    parameter_specs: ClassVar[tuple[Parameter, ...]] = ()
    #: The law's options in declaration order.
    option_specs: ClassVar[tuple[Option, ...]] = ()
    #: Names of the regimes that :meth:`regime` returns, indexed by ``_regime``'s codes.
    regimes: ClassVar[tuple[str, ...]] = ()
    #: Method :func:`bouncelab.fit` uses when none is named.
    default_fit_method: ClassVar[str] = "global"

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
        """The constructor's keyword arguments as stored (scikit-learn convention; ``deep`` changes nothing)."""
        return {**self.__dict__["_values"], **self.__dict__["_options"]}

    def __sklearn_clone__(self) -> BounceModel:
        """scikit-learn's ``clone``: a law is an immutable value, so it is its own clone."""
        return self

    @property
    def params(self) -> Parameters:
        """The parameters as objects (name, value, bounds, physical range, unit, vary, doc)."""
        return Parameters(s.replace(value=self.__dict__["_values"][s.name]) for s in self.parameter_specs)

    @property
    def parameters(self) -> dict[str, float | np.ndarray | None]:
        """Parameter values, name -> float (array for array parameters; ``None`` where not set)."""
        return dict(self.__dict__["_values"])

    def flat_parameters(self) -> dict[str, float | None]:
        """Every number of every parameter, by element name (``A1[0,2]``); for tables of any law."""
        out: dict[str, float | None] = {}
        for spec in self.parameter_specs:
            value = self.__dict__["_values"][spec.name]
            flat = [None] * spec.size if value is None else np.ravel(value).tolist()
            out.update(zip(spec.element_names(), flat, strict=True))
        return out

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
        from bouncelab.laws import _physical_io as edge
        from bouncelab.laws import nonphysical

        values = self._fitted_values()
        plausible = edge.check_plausible_argument(plausible)
        if edge.is_lazy(landing):
            if edge.PhysicalIO.needed(units, form) or return_flags or warn_outside_fitted:
                at = edge.io_option(units, form) if edge.PhysicalIO.needed(units, form) else \
                    "return_flags" if return_flags else "warn_outside_fitted"
                raise DataError("a dask-backed DataArray is predicted lazily in scaled Cartesian states only, without "
                                "units=, form=, return_flags= or warn_outside_fitted=", option=at)
            return edge.lazy_predict(self, landing, plausible, radius_m)
        io = edge.PhysicalIO(units, form, radius_m, plausible) if edge.PhysicalIO.needed(units, form) else None
        p, wrap = self._argcheck(landing, io, plausible, radius_m)
        out, ok = self._evaluate_checked(p, values)
        if not ok:
            check_values(p, "landing", landing=True)  # raises, naming the row and column
        out = self._liftoff_array(out, len(p))
        if warn_outside_fitted:
            self._warn_outside_fitted(p)
        result = wrap(out) if io is None else io.liftoff(out)
        flags = nonphysical.flags_of(self, p, out, always=return_flags)
        if not return_flags:
            return result
        per = wrap if io is None else io.per_bounce
        return result, nonphysical.LiftoffFlags(into_ground=per(flags[0]), energy_gain=per(flags[1]))

    def predict_one(self, xdot: float, ydot: float, omega: float, *,
                    plausible: PlausibleRanges | None = PLAUSIBLE_RANGES,
                    radius_m: float | None = None) -> tuple[float, float, float]:
        """The lift-off ``(xdotF, ydotF, omegaF)`` of one landing, as floats: the fast path of a simulator's loop.

        The same law, checks and numbers as ``predict([[xdot, ydot, omega]])[0]`` (scaled units, ``ydot < 0``;
        the unit guard ``plausible`` on the one landing, ``radius_m`` the ball it refers to), without the
        array machinery: a compiled law calls its kernel directly (a few microseconds a bounce).

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
        self._fitted_values()
        x, y, w = _one_landing(xdot, ydot, omega)
        if plausible is not None and not _plausible_one(x, y, w, plausible, radius_m):
            self.predict([[x, y, w]], plausible=plausible, radius_m=radius_m)  # raises, naming the limit
        return self._one(x, y, w)

    def _one(self, x: float, y: float, w: float) -> tuple[float, float, float]:
        """One validated landing's lift-off (laws with a faster way override it)."""
        out = self._evaluate(np.array([[x, y, w]]))
        return float(out[0, 0]), float(out[0, 1]), float(out[0, 2])

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
        from bouncelab.laws import _physical_io as edge

        values = self._fitted_values()
        plausible = edge.check_plausible_argument(plausible)
        if edge.is_lazy(landing):
            if edge.PhysicalIO.needed(units, form):
                raise DataError("a dask-backed DataArray is classified lazily in scaled Cartesian states only, without "
                                "units= or form=", option=edge.io_option(units, form))
            return edge.lazy_regime(self, landing, codes, plausible, radius_m)
        io = edge.PhysicalIO(units, (form, "cartesian") if isinstance(form, str) else form, radius_m, plausible) \
            if edge.PhysicalIO.needed(units, form) else None
        p, wrap = self._argcheck(landing, io, plausible, radius_m)
        c, ok = self._classify_checked(p, values)
        if not ok:
            check_values(p, "landing", landing=True)
        c = self._codes(c, len(p))
        if io is not None:
            wrap = io.per_bounce
        if codes:
            return wrap(c)
        names = np.asarray(self.regimes)
        if len(c) >= REGIME_NAMES_WARN:
            from bouncelab.core.errors import LargeResultWarning

            warnings.warn(f"regime names for {len(c):,} landings take {len(c) * names.itemsize / 1e6:.0f} MB; "
                          f"regime(..., codes=True) gives int8 codes into law.regimes ({len(c) / 1e6:.0f} MB)",
                          LargeResultWarning, stacklevel=2)
        return wrap(names[c])

    def _argcheck(self, landing: Any, io: Any, plausible: PlausibleRanges | None,
                  radius_m: float | None) -> tuple[np.ndarray, Callable]:
        """The public methods' one check: (n, 3) scaled Cartesian landings and the wrap back to the caller's kind.

        Shapes and types are checked here; the values (finite, ``ydot0 < 0``) of a large array are checked by a
        compiled law in the same pass as its maths (:attr:`_fused_value_check`); the unit guard runs here.
        """
        from bouncelab.laws._physical_io import guard_landings, radius_of

        p, wrap = as_states(landing if io is None else io.landing(landing), "landing", landing=True,
                            defer_check=self._fused_value_check)
        if plausible is not None:
            radius = radius_of(radius_m) if io is None else io.radius_m
            labels = landing.index if io is None and hasattr(landing, "columns") else None  # a DataFrame's rows
            guard_landings(p, plausible, radius, io, labels)
        return p, wrap

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

    # ------------------------------------------------------------- the law's maths, checked
    #: Whether :meth:`_evaluate_checked` checks the landings' values in its own pass, so that the public
    #: methods skip a separate pass over large arrays (compiled laws).
    _fused_value_check: ClassVar[bool] = False

    def _evaluate_checked(self, p: np.ndarray, values: Mapping[str, Any]) -> tuple[Any, bool]:
        """The law's lift-offs of ``p``, and whether every landing was valid if checked in the same pass."""
        return self._predict(p, **values), True

    def _classify_checked(self, p: np.ndarray, values: Mapping[str, Any]) -> tuple[Any, bool]:
        """The law's regime codes of ``p`` (as :meth:`_evaluate_checked`)."""
        return self._regime(p, **values), True

    def _evaluate(self, p: np.ndarray, values: Mapping[str, Any] | None = None) -> np.ndarray:
        """(n, 3) lift-offs of validated landings ``p`` with ``values`` (default: the law's own), checked.

        For the fitting machinery and analyses: no unit guard, no flags, no conversion.
        """
        out, _ = self._evaluate_checked(p, self._fitted_values() if values is None else values)
        return self._liftoff_array(out, len(p))

    def _classify(self, p: np.ndarray, values: Mapping[str, Any] | None = None) -> np.ndarray:
        """(n,) int8 regime codes of validated landings ``p`` with ``values`` (default: the law's own), checked."""
        c, _ = self._classify_checked(p, self._fitted_values() if values is None else values)
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
        from bouncelab.laws.varying import predict_per_bounce

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
        from bouncelab.laws.files import describe

        return describe(self, metadata=metadata)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> BounceModel:
        """Rebuild a law from :meth:`to_dict` output (any registered law when called on BounceModel)."""
        from bouncelab.laws.files import law_from_dict

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
            from bouncelab.core.atomic import write_output

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

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        a, b = self.get_params(), other.get_params()
        return all(np.array_equal(np.asarray(a[k], dtype=object), np.asarray(b[k], dtype=object)) for k in a)

    def __hash__(self) -> int:
        from bouncelab.laws.files import value_dict

        d = value_dict(self)
        return hash((d["law"], json.dumps([d["parameters"], d.get("options")], sort_keys=True, default=str)))


def _one_landing(xdot: Any, ydot: Any, omega: Any) -> tuple[float, float, float]:
    """Three finite floats of one landing moving down, or the array check's DataError naming the component."""
    try:
        x, y, w = float(xdot), float(ydot), float(omega)
    except (TypeError, ValueError):
        x = y = w = math.nan
    if not (abs(x) <= STATE_LIMIT and abs(y) <= STATE_LIMIT and abs(w) <= STATE_LIMIT and y < 0.0):
        as_states(np.array([[xdot, ydot, omega]], dtype=object), "landing", landing=True)  # raises, naming it
        raise DataError(f"landing ({xdot!r}, {ydot!r}, {omega!r}) is not three finite numbers with ydot < 0")
    return x, y, w


#: Entries of a law's __dict__ that are caches, not state (see BounceModel.__getstate__).
_CACHES = ("_args_cache", "_one_entry")

#: (id of the ranges, radius) -> (the ranges, their limits). Holding the ranges keeps their id from being reused
#: by another object while cached; keying by id keeps the lookup cheap on the single-bounce path.
_LIMITS: dict[tuple[int, float], tuple[PlausibleRanges, tuple[float, float, float, float]]] = {}


def _plausible_one(x: float, y: float, w: float, ranges: PlausibleRanges, radius_m: float | None) -> bool:
    """Whether one landing passes the unit guard (the comparisons of plausibility.landing_faults, in floats)."""
    radius = BALL_RADIUS_M if radius_m is None else radius_m
    key = (id(ranges), radius)
    cached = _LIMITS.get(key)
    if cached is not None:
        limits = cached[1]
    else:
        if radius_m is not None:
            from bouncelab.laws._physical_io import radius_of

            radius = radius_of(radius_m)
        limits = landing_limits(radius, ranges)
        _LIMITS[key] = (ranges, limits)
        if len(_LIMITS) > 64:  # a few ranges and balls in a program: keep the cache small
            _LIMITS.pop(next(iter(_LIMITS)))
    min_s2, max_s2, max_w, tan_a = limits
    s2 = x * x + y * y
    return min_s2 <= s2 <= max_s2 and abs(w) <= max_w and -y >= abs(x) * tan_a
