"""Parameters and options of bounce laws, declared once, as class attributes (in the spirit of lmfit and attrs).

A law declares each parameter as a class attribute; the parameter takes its name from the attribute:

.. code-block:: python

    class SpeedRestitution(bl.BounceModel):
        r0 = bl.Parameter(bounds=(0, 1), physical=(0, 1), unit="1", doc="restitution of a slow impact")
        v_c = bl.Parameter(bounds=(10, 5000), physical=(1e-6, 1e9), unit="radius/s", doc="speed at which r halves")

On the class, ``SpeedRestitution.r0`` is the :class:`Parameter` (its bounds, physical range, unit, doc);
on a law, ``law.r0`` is its value (``None`` while the law is unfitted). ``law.params`` gives every
parameter with the law's value filled in, as a read-only :class:`Parameters` mapping, and a
:class:`~bouncelab.FitResult`'s ``params`` adds the standard errors a fitting method knows.

An :class:`Option` is a constructor keyword that is not fitted (e.g. Penner's ``fade_xdot``): stored,
serialised and printed with the law.

A parameter is a scalar (``shape=()``) or an array of any fixed shape (e.g. a 3 x 3 matrix).

Examples
--------
>>> from bouncelab.laws.parameters import Parameter
>>> r = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="coefficient of restitution", name="r")
>>> r.check(0.5, "MyLaw")
0.5
>>> A = Parameter(bounds=(-2.0, 2.0), shape=(3, 3), doc="linear map", name="A")
>>> A.element_names()[:2]
['A[0,0]', 'A[0,1]']
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any

import numpy as np

from bouncelab.core import checks
from bouncelab.core.errors import Code, Hint, LawDefinitionError, ParameterError

__all__ = ["Option", "Parameter", "Parameters"]

Bound = Any  # a float, or an array of the parameter's shape

_INF = float("inf")

_HOW = ("declare it as a class attribute with keyword fields, e.g. "
        "r = bl.Parameter(bounds=(0, 1), physical=(0, 1), unit='1', doc='coefficient of restitution')")


class Parameter:
    """A parameter of a bounce law: name, bounds, physical range, unit, what it means, and (on a law) its value.

    Declared as a class attribute of a law, whose name it takes; on a law instance the attribute reads the
    law's value, on the class the declaration itself.

    Parameters
    ----------
    bounds
        Default search box ``(low, high)`` of :func:`bouncelab.fit`. For an array parameter each of ``low``
        and ``high`` is a number (for every element) or an array of the parameter's shape.
    physical
        Range outside which the law is meaningless, in the same form (default: any finite number); values
        and fit bounds outside it are refused with :class:`~bouncelab.ParameterError` naming the law and
        the parameter.
    unit
        Unit of the value (``"1"`` when dimensionless).
    doc
        What the parameter means, in one line (reports print it).
    shape
        ``()`` for a scalar, e.g. ``(3, 3)`` for a matrix.
    default
        The value a law takes when the constructor is not given one (default ``None``: unfitted).
    vary
        ``False``: held at the law's value by :func:`bouncelab.fit` unless freed
        (``fit(..., free=[name])``).
    name
        Set from the attribute the parameter is declared as (give it only for a parameter made outside a
        law, as in the examples).
    value, stderr
        The value and its standard error, in the copies ``law.params`` and a fit result's ``params`` hold.
    """

    __slots__ = ("bounds", "default", "doc", "name", "physical", "shape", "stderr", "unit", "value", "vary")

    def __init__(self, *args: Any, bounds: tuple[Bound, Bound] | None = None,
                 physical: tuple[Bound, Bound] = (-_INF, _INF),
                 unit: str = "1", doc: str = "", shape: Iterable[int] = (), default: Any = None,
                 vary: bool = True, name: str | None = None, value: Any = None, stderr: Any = None) -> None:
        if args:
            raise LawDefinitionError(f"Parameter takes keyword fields only (bounds=, physical=, unit=, doc=); got "
                                     f"{len(args)} positional value(s) {args!r}: {_HOW}", method="Parameter")
        if bounds is None:
            raise LawDefinitionError(f"a Parameter needs its search box: {_HOW}", method="Parameter",
                                     hints=[Hint("bounds", Code("(low, high)"))])
        set_ = object.__setattr__
        set_(self, "bounds", tuple(bounds))
        set_(self, "physical", tuple(physical))
        set_(self, "unit", str(unit))
        set_(self, "doc", str(doc))
        set_(self, "shape", tuple(int(s) for s in shape))
        set_(self, "default", default)
        set_(self, "vary", bool(vary))
        set_(self, "name", None)
        set_(self, "value", value)
        set_(self, "stderr", stderr)
        if len(self.bounds) != 2 or len(self.physical) != 2:
            raise LawDefinitionError(f"a Parameter's bounds and physical range are (low, high) pairs; got bounds="
                                     f"{bounds!r}, physical={physical!r}", method="Parameter")
        if name is not None:
            self._name(name)

    def _name(self, name: str) -> None:
        if not isinstance(name, str) or not name.isidentifier():
            raise ParameterError(f"a parameter name must be a Python identifier; got {name!r}", value=name)
        object.__setattr__(self, "name", name)

    # ------------------------------------------------------------------ declaration on a law class
    def __set_name__(self, owner: type, name: str) -> None:
        if self.name is not None and self.name != name:
            raise LawDefinitionError(f"{owner.__name__}.{name}: this Parameter is already declared as {self.name!r}; "
                                     "declare one Parameter per name (copy it with .replace(name=...))",
                                     law=owner.__name__, method=name)
        self._name(name)

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        if obj is None:
            return self  # on the class: the declaration
        return obj.__dict__["_values"][self.name]

    def __set__(self, obj: Any, value: Any) -> None:
        raise AttributeError(f"{type(obj).__name__} is immutable; use .replace({self.name}=...) for a changed copy")

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("a Parameter is immutable; use .replace(...) for a changed copy")

    # ------------------------------------------------------------------ geometry
    @property
    def description(self) -> str:
        """The same as :attr:`doc`."""
        return self.doc

    @property
    def size(self) -> int:
        """Number of numbers in the parameter (1 for a scalar)."""
        return math.prod(self.shape)

    @property
    def is_scalar(self) -> bool:
        return self.shape == ()

    def element_names(self) -> list[str]:
        """Names of the parameter's numbers: ``[name]`` for a scalar, ``name[i,j]`` for arrays (C order)."""
        if self.is_scalar:
            return [self.name]
        return [f"{self.name}[{','.join(map(str, idx))}]" for idx in np.ndindex(*self.shape)]

    def _pair(self, pair: tuple[Bound, Bound], what: str) -> tuple[np.ndarray, np.ndarray]:
        try:
            lo, hi = pair
            lo = np.broadcast_to(np.asarray(lo, dtype=np.float64), self.shape).ravel()
            hi = np.broadcast_to(np.asarray(hi, dtype=np.float64), self.shape).ravel()
        except (TypeError, ValueError):
            raise ParameterError(
                f"{what} of parameter {self.name!r} must be a (low, high) pair of numbers or arrays of shape "
                f"{self.shape}; got {pair!r}", parameter=self.name, value=pair
            ) from None
        return lo, hi

    def bound_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The default search box as two flat float64 arrays of length :attr:`size`."""
        return self._pair(self.bounds, "bounds")

    def physical_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """The physical range as two flat float64 arrays of length :attr:`size`."""
        return self._pair(self.physical, "the physical range")

    # ------------------------------------------------------------------ values
    def check(self, value: Any, law: str) -> float | np.ndarray:
        """``value`` as a float (scalar) or a read-only float64 array, or ParameterError naming law and parameter."""
        bad_type = isinstance(value, bool | np.bool_ | str | bytes) or (
            isinstance(value, np.ndarray) and value.dtype == bool)
        if bad_type:
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {checks.shown(value)}",
                                 law=law, parameter=self.name, value=value)
        try:
            raw = np.asarray(value)
            if np.iscomplexobj(raw):
                raise ParameterError(f"{law} parameter {self.name!r} must be real; got {checks.shown(value)}",
                                     law=law, parameter=self.name, value=value)
            # (text, bools, None or 10**400 inside a list are no numbers either: checks.real_array)
            arr = np.array(checks.real_array(raw if raw.dtype != object else value, self.name), dtype=np.float64)
        except (TypeError, ValueError, OverflowError) as exc:
            if isinstance(exc, ParameterError) and exc.law is not None:
                raise
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {checks.shown(value)}",
                                 law=law, parameter=self.name, value=value) from None
        if arr.shape != self.shape:
            what = "a number" if self.is_scalar else f"an array of shape {self.shape}"
            raise ParameterError(f"{law} parameter {self.name!r} must be {what}; got shape {arr.shape}", law=law,
                                 parameter=self.name, value=value)
        lo, hi = self.physical_arrays()
        flat = arr.ravel()
        bad = ~(np.isfinite(flat) & (flat >= lo) & (flat <= hi))
        if bad.any():
            i = int(np.argmax(bad))
            element = self.name if self.is_scalar else self.element_names()[i]
            where = "" if self.is_scalar else f" element {element}"
            shown = value if self.is_scalar else float(flat[i])
            if not np.isfinite(flat[i]):
                raise ParameterError(f"{law} parameter {self.name!r}{where} must be finite; got {shown!r}", law=law,
                                     parameter=element, value=shown)
            raise ParameterError(
                f"{law} parameter {self.name!r}{where} = {shown!r} is outside its physical range "
                f"[{lo[i]:g}, {hi[i]:g}] ({self.doc})", law=law, parameter=element, value=shown)
        if self.is_scalar:
            return float(arr)
        arr.setflags(write=False)
        return arr

    def replace(self, **changes: Any) -> Parameter:
        """A copy with some fields changed (e.g. ``value``, ``stderr``, ``bounds``)."""
        fields = {k: getattr(self, k) for k in self.__slots__}
        fields.update(changes)
        return Parameter(**fields)

    def __reduce__(self) -> tuple:  # pickled by its fields (it is immutable, and its slots are set once)
        return _rebuild, ({k: getattr(self, k) for k in self.__slots__},)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Parameter):
            return NotImplemented
        for f in self.__slots__:
            a, b = getattr(self, f), getattr(other, f)
            if f in ("bounds", "physical"):
                if not all(np.array_equal(np.asarray(x), np.asarray(y)) for x, y in zip(a, b, strict=True)):
                    return False
            elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
                if a is None or b is None or not np.array_equal(np.asarray(a), np.asarray(b)):
                    return False
            elif a != b:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]  # holds arrays; not hashable

    def __repr__(self) -> str:
        value = "" if self.value is None else f", value={self.format_value()}"
        return (f"Parameter(name={self.name!r}, bounds={self.bounds!r}, physical={self.physical!r}, "
                f"unit={self.unit!r}{value})")

    def format_value(self, value: Any = None, digits: int = 6) -> str:
        """The value (or ``value``) as short text; arrays on one line."""
        v = self.value if value is None else value
        if v is None:
            return "None"
        if self.is_scalar:
            return f"{float(v):.{digits}g}"
        return np.array2string(np.asarray(v), precision=min(digits, 4), separator=", ",
                               max_line_width=10_000).replace("\n", "")


def _rebuild(fields: dict[str, Any]) -> Parameter:
    return Parameter(**fields)


class Option:
    """A constructor keyword of a law that is not a parameter: stored, serialised and printed, never fitted.

    Parameters
    ----------
    default
        The value when the constructor is not given one.
    check
        ``check(value, law_name) -> value``: validates (raising :class:`~bouncelab.ParameterError`) and
        normalises a given value; the default is not checked.
    doc
        What the option means, in one line.
    """

    __slots__ = ("check", "default", "doc", "name")

    def __init__(self, *, default: Any = None, check: Callable[[Any, str], Any] | None = None, doc: str = "") -> None:
        self.default = default
        self.check = check
        self.doc = doc
        self.name: str | None = None

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, owner: type | None = None) -> Any:
        if obj is None:
            return self
        return obj.__dict__["_options"][self.name]

    def __set__(self, obj: Any, value: Any) -> None:
        raise AttributeError(f"{type(obj).__name__} is immutable; use .replace({self.name}=...) for a changed copy")

    def validate(self, value: Any, law: str) -> Any:
        """The value as the law stores it (checked unless it is the default)."""
        if self.check is None or value is self.default:
            return value
        return self.check(value, law)


def fade_speed(value: Any, law: str, *, optional: bool = False) -> float | None:
    """The ``fade_xdot`` option of the tilted-surface laws: a positive, finite number of radii/s (or None
    when ``optional``), else a ParameterError naming the law and the option. An ``Option(check=...)``."""
    if value is None and optional:
        return None
    what = "a positive number of radii/s" + (" or None" if optional else "")
    try:
        return checks.positive(value, "fade_xdot")
    except ParameterError as exc:
        raise ParameterError(f"{law} option 'fade_xdot' must be {what}; got {checks.shown(value)}", law=law,
                             parameter="fade_xdot", value=value) from exc


class Parameters(Mapping[str, Parameter]):
    """Read-only ordered mapping name -> :class:`Parameter`, printed as a table.

    Examples
    --------
    >>> import bouncelab as bl
    >>> bl.Rigid(r=0.5, mu=0.4).params.valuesdict()
    {'r': 0.5, 'mu': 0.4}
    """

    def __init__(self, params: Iterable[Parameter]) -> None:
        self._params = {p.name: p for p in params}

    def __getitem__(self, name: str) -> Parameter:
        return self._params[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._params)

    def __len__(self) -> int:
        return len(self._params)

    def valuesdict(self) -> dict[str, float | np.ndarray | None]:
        """name -> value (a float, an array for an array parameter; ``None`` where not set)."""
        return {k: p.value for k, p in self._params.items()}

    def flat(self) -> dict[str, float | None]:
        """Every number of every parameter by element name (``A1[0,2]``), in declaration order: for tables of
        any law.

        Examples
        --------
        >>> import bouncelab as bl
        >>> list(bl.PiecewiseAffine.published("A").params.flat())[:4]
        ['normal[0]', 'normal[1]', 'normal[2]', 'offset']
        """
        out: dict[str, float | None] = {}
        for p in self._params.values():
            flat = [None] * p.size if p.value is None else np.ravel(p.value).tolist()
            out.update(zip(p.element_names(), flat, strict=True))
        return out

    def pretty(self, digits: int = 6) -> str:
        """A table: name, value, stderr, bounds, unit, vary, doc."""
        rows = [("name", "value", "stderr", "bounds", "unit", "vary", "doc")]
        for p in self._params.values():
            stderr = "" if p.stderr is None else p.format_value(p.stderr, 3)
            lo, hi = p.bound_arrays()
            same = (lo.min() == lo.max()) and (hi.min() == hi.max())
            bounds = f"[{lo[0]:g}, {hi[0]:g}]" if same else "per element"
            rows.append((p.name, p.format_value(digits=digits), stderr, bounds, p.unit, str(p.vary), p.doc))
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
        lines = []
        for r in rows:
            lines.append("  ".join(c.ljust(w) for c, w in zip(r[:-1], widths, strict=False)) + "  " + r[-1])
        return "\n".join(line.rstrip() for line in lines)

    def __repr__(self) -> str:
        return "Parameters(\n" + "\n".join("  " + line for line in self.pretty().splitlines()) + "\n)"


def collect(cls: type, kind: type) -> dict[str, Any]:
    """The ``kind`` (:class:`Parameter` or :class:`Option`) declared by ``cls`` and its bases, by name, in
    declaration order (a base's first; a subclass may redeclare one, or remove it with ``name = None``)."""
    out: dict[str, Any] = {}
    for klass in reversed(cls.__mro__):
        for name, value in vars(klass).items():
            if isinstance(value, kind):
                out.pop(name, None)
                out[name] = value
            elif name in out and not isinstance(value, Parameter | Option):
                del out[name]
    return out
