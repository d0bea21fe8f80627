"""Parameters of bounce laws, as objects (in the spirit of lmfit).

A law declares its parameters once, as a tuple of :class:`Parameter` in its
``parameter_specs`` class attribute (values ``None``); ``law.params`` gives
them back with the law's values filled in, as a read-only :class:`Parameters`
mapping, and a :class:`~bouncelab.FitResult`'s ``params`` adds the standard
errors a fitting method knows.

A parameter is a scalar (``shape=()``) or an array of any fixed shape (e.g. a
3 x 3 matrix). The fitter sees every law as one flat float64 vector ``theta``:
the parameters in declaration order, arrays raveled in C order.

Examples
--------
>>> from bouncelab.laws.parameters import Parameter
>>> r = Parameter("r", (0.0, 1.0), (0.0, 1.0), "1", "coefficient of restitution")
>>> r.check(0.5, "MyLaw")
0.5
>>> A = Parameter("A", (-2.0, 2.0), (-1e6, 1e6), "1", "linear map", shape=(3, 3))
>>> A.element_names()[:2]
['A[0,0]', 'A[0,1]']
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from bouncelab.core.errors import ParameterError

__all__ = ["Parameter", "Parameters"]

Bound = Any  # a float, or an array of the parameter's shape


@dataclass(frozen=True, eq=False)
class Parameter:
    """A named parameter of a bounce law: value, bounds, physical range, unit, and what it means.

    Attributes
    ----------
    name
        Keyword name in the law's constructor.
    bounds
        Default search box ``(low, high)`` of :func:`bouncelab.fit`. For an array
        parameter each of ``low`` and ``high`` is a number (for every element) or an
        array of the parameter's shape.
    physical
        Range outside which the law is meaningless, in the same form; values and
        fit bounds outside it are refused with :class:`~bouncelab.ParameterError`
        naming the law and the parameter.
    unit
        Unit of the value (``"1"`` when dimensionless; ``""`` when it has none of its own, as the
        coefficients of a plane, which any common factor leaves the same).
    description
        One line for reports.
    shape
        ``()`` for a scalar, e.g. ``(3, 3)`` for a matrix.
    value
        The value (``None`` in a declaration, or while a law is unfitted).
    vary
        ``False``: held at the law's value by :func:`bouncelab.fit` unless freed
        (``fit(..., free=[name])``).
    stderr
        Standard error after a fit, when the fitting method knows it (else ``None``).
    """

    name: str
    bounds: tuple[Bound, Bound]
    physical: tuple[Bound, Bound]
    unit: str
    description: str
    shape: tuple[int, ...] = ()
    value: float | np.ndarray | None = None
    vary: bool = True
    stderr: float | np.ndarray | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise ParameterError(f"a parameter name must be a Python identifier; got {self.name!r}")
        object.__setattr__(self, "shape", tuple(int(s) for s in self.shape))

    # ------------------------------------------------------------------ geometry
    @property
    def size(self) -> int:
        """Number of numbers in the parameter (1 for a scalar)."""
        return math.prod(self.shape)

    @property
    def is_scalar(self) -> bool:
        return self.shape == ()

    def element_names(self) -> list[str]:
        """Names of the numbers in ``theta`` order: ``[name]`` for a scalar, ``name[i,j]`` for arrays."""
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
                f"{self.shape}; got {pair!r}"
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
        if isinstance(value, bool | np.bool_) or (isinstance(value, np.ndarray) and value.dtype == bool):
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {value!r}")
        if isinstance(value, str | bytes):
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {value!r}")
        try:
            raw = np.asarray(value)
            if np.iscomplexobj(raw):
                raise ParameterError(f"{law} parameter {self.name!r} must be real; got {value!r}")
            arr = np.array(raw, dtype=np.float64)
        except (TypeError, ValueError, OverflowError) as exc:
            if isinstance(exc, ParameterError):
                raise
            raise ParameterError(f"{law} parameter {self.name!r} must be a number; got {value!r}") from None
        if arr.shape != self.shape:
            what = "a number" if self.is_scalar else f"an array of shape {self.shape}"
            raise ParameterError(f"{law} parameter {self.name!r} must be {what}; got shape {arr.shape}")
        lo, hi = self.physical_arrays()
        flat = arr.ravel()
        bad = ~(np.isfinite(flat) & (flat >= lo) & (flat <= hi))
        if bad.any():
            i = int(np.argmax(bad))
            where = "" if self.is_scalar else f" element {self.element_names()[i]}"
            shown = value if self.is_scalar else float(flat[i])
            if not np.isfinite(flat[i]):
                raise ParameterError(f"{law} parameter {self.name!r}{where} must be finite; got {shown!r}")
            raise ParameterError(
                f"{law} parameter {self.name!r}{where} = {shown!r} is outside its physical range "
                f"[{lo[i]:g}, {hi[i]:g}] ({self.description})"
            )
        if self.is_scalar:
            return float(arr)
        arr.setflags(write=False)
        return arr

    def replace(self, **changes: Any) -> Parameter:
        """A copy with some fields changed (e.g. ``value``, ``stderr``)."""
        return dataclasses.replace(self, **changes)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Parameter):
            return NotImplemented
        for f in dataclasses.fields(self):
            a, b = getattr(self, f.name), getattr(other, f.name)
            if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
                if a is None or b is None or not np.array_equal(np.asarray(a), np.asarray(b)):
                    return False
            elif f.name in ("bounds", "physical"):
                if not all(np.array_equal(np.asarray(x), np.asarray(y)) for x, y in zip(a, b, strict=True)):
                    return False
            elif a != b:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]  # holds arrays; not hashable

    def format_value(self, value: Any = None, digits: int = 6) -> str:
        """The value (or ``value``) as short text; arrays on one line."""
        v = self.value if value is None else value
        if v is None:
            return "None"
        if self.is_scalar:
            return f"{float(v):.{digits}g}"
        return np.array2string(np.asarray(v), precision=min(digits, 4), separator=", ",
                               max_line_width=10_000).replace("\n", "")


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
        """name -> value."""
        return {k: p.value for k, p in self._params.items()}

    def pretty(self, digits: int = 6) -> str:
        """A table: name, value, stderr, bounds, unit, vary, description."""
        rows = [("name", "value", "stderr", "bounds", "unit", "vary", "description")]
        for p in self._params.values():
            stderr = "" if p.stderr is None else p.format_value(p.stderr, 3)
            lo, hi = p.bound_arrays()
            same = (lo.min() == lo.max()) and (hi.min() == hi.max())
            bounds = f"[{lo[0]:g}, {hi[0]:g}]" if same else "per element"
            rows.append((p.name, p.format_value(digits=digits), stderr, bounds, p.unit, str(p.vary), p.description))
        widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
        lines = []
        for r in rows:
            lines.append("  ".join(c.ljust(w) for c, w in zip(r[:-1], widths, strict=False)) + "  " + r[-1])
        return "\n".join(line.rstrip() for line in lines)

    def __repr__(self) -> str:
        return "Parameters(\n" + "\n".join("  " + line for line in self.pretty().splitlines()) + "\n)"
