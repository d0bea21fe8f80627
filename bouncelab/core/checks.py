"""One check per kind of argument: a finite real number, a positive one, a fraction, a count, a seed, an
array of real numbers, a text.

Every layer checks its scalar arguments (and the numbers and texts of the files it reads) with these, so
that a value is accepted or refused by the same rule everywhere, in the same words, naming the argument:

* a **number** is a real number: ``int``, ``float``, NumPy's integers and floats, a 0-d real array, or
  any other object that converts to a float (``Fraction``, ``Decimal``). Refused: ``bool`` (``True``
  is not 1.0), text (``"1"``: a number in a file is parsed by its reader, not guessed here), bytes,
  complex numbers (NumPy's too, whose ``float()`` would drop the imaginary part), ``None``, arrays of
  more than one value, and an integer beyond the range of a float (``10**400``);
* a **count** is an integer (``int`` or NumPy's, not ``bool``, not ``5.0``);
* a **text** is a ``str`` that can be written as UTF-8 (no lone surrogate such as ``"\\ud800"``, which
  would crash a write or a ``print`` far from where it came in).

The error's type is the layer's (the ``error=`` argument): :class:`~bouncelab.core.errors.ParameterError`
(``parameter`` and ``value`` set) for a law's or a surface's parameter, :class:`~bouncelab.core.errors.FitError`
or :class:`~bouncelab.core.errors.DataError` (``option`` set) for an option of a fit or of the data; all three
are ``ValueError`` s and :class:`~bouncelab.core.errors.BouncelabError` s, and code catching the layer's
error keeps working.
"""

from __future__ import annotations

import math
import numbers
import operator
from typing import Any

import numpy as np

from bouncelab.core.errors import BouncelabError, ParameterError

__all__ = ["SEED_MAX", "as_float", "count", "finite", "fraction", "generator", "positive", "real_array", "seed",
           "shown", "text"]

#: Largest seed (NumPy's generators and NLopt take seeds below 2**63).
SEED_MAX = 2**63 - 1

_SHOWN = 60  # characters of a refused value quoted in a message


def shown(value: Any) -> str:
    """``repr(value)`` for a message, shortened: an integer of thousands of digits (whose ``repr`` itself
    raises) or a long text is cut, keeping its start and its length."""
    try:
        text = repr(value)
    except (ValueError, RecursionError, TypeError):  # an int beyond sys.get_int_max_str_digits()
        bits = value.bit_length() if isinstance(value, int) else None
        return f"<an integer of {bits} bits>" if bits is not None else f"<a {type(value).__name__}>"
    if len(text) > _SHOWN:
        if isinstance(value, int):
            return f"<an integer of {len(text)} digits>"
        return f"{text[:_SHOWN - 5]}... ({len(text)} characters)"
    return text


def _refuse(error: type[BouncelabError], name: str, value: Any, message: str, **fields: Any) -> BouncelabError:
    """``error`` with the fields its kind names an argument by: ``parameter`` and ``value`` for a
    ParameterError, ``option`` for the others (DataError, FitError)."""
    if issubclass(error, ParameterError):
        return error(message, parameter=name, value=value, **fields)
    return error(message, option=name, **fields)


def _why_not(value: Any) -> str:
    """Why ``value`` is no real number, in a few words, or ``""`` if it may be one."""
    if isinstance(value, bool | np.bool_):
        return "a bool is not a number"
    if isinstance(value, str | bytes):
        return "text is not a number"
    if isinstance(value, complex | np.complexfloating):
        return "a complex number is not a real one"
    if value is None:
        return "None is not a number"
    return ""


def as_float(value: Any) -> tuple[float, str]:
    """``value`` as a float and ``""``, or NaN and why it is no real number (the rule of :func:`finite`,
    without the finiteness: NaN and infinities pass)."""
    why = _why_not(value)
    if why:
        return math.nan, why
    if isinstance(value, np.ndarray):
        if value.ndim != 0 or value.dtype.kind not in "iuf":
            return math.nan, "not a single real number"
        value = value.item()
    try:
        return float(value), ""
    except OverflowError:
        return math.nan, "too large for a floating-point number"
    except (TypeError, ValueError, ArithmeticError):  # (Decimal's InvalidOperation is an ArithmeticError)
        return math.nan, f"a {type(value).__name__} is not a number"


def finite(value: Any, name: str, *, error: type[BouncelabError] = ParameterError, low: float | None = None,
           high: float | None = None, want: str | None = None) -> float:
    """``value`` as a finite float, within ``[low, high]`` when given, or ``error`` naming ``name``.

    ``want`` words what is wanted in the message (default: "a finite number", with the bounds).
    """
    x, why = as_float(value)
    ok = math.isfinite(x) and (low is None or x >= low) and (high is None or x <= high)
    if not ok:
        if want is None:
            want = "a finite number" + (f" >= {low:g}" if low is not None else "") + \
                (f" <= {high:g}" if high is not None else "")
        raise _refuse(error, name, value, f"{name} must be {want}; got {shown(value)}" + (f" ({why})" if why else ""))
    return x


def positive(value: Any, name: str, *, allow_zero: bool = False,
             error: type[BouncelabError] = ParameterError) -> float:
    """``value`` as a finite float > 0 (>= 0 with ``allow_zero``), or ``error`` naming ``name``."""
    x, why = as_float(value)
    if not (math.isfinite(x) and (x >= 0 if allow_zero else x > 0)):
        want = "a finite number >= 0" if allow_zero else "a finite number > 0"
        raise _refuse(error, name, value, f"{name} must be {want}; got {shown(value)}" + (f" ({why})" if why else ""))
    return x


def fraction(value: Any, name: str, *, closed: bool = False, error: type[BouncelabError] = ParameterError) -> float:
    """``value`` as a float in (0, 1) (a level, a share), in [0, 1] with ``closed``, or ``error`` naming ``name``."""
    x, why = as_float(value)
    if not ((0.0 <= x <= 1.0) if closed else (0.0 < x < 1.0)):
        want = "a number in [0, 1]" if closed else "a number in (0, 1)"
        raise _refuse(error, name, value, f"{name} must be {want}; got {shown(value)}" + (f" ({why})" if why else ""))
    return x


def _whole(value: Any) -> int | None:
    """``value`` as an int if it is one (``int`` or NumPy's, by ``operator.index``; not a bool), else None."""
    if isinstance(value, bool | np.bool_):
        return None
    try:
        return operator.index(value)
    except TypeError:
        return None


def count(value: Any, name: str, minimum: int = 0, *, maximum: int | None = None,
          error: type[BouncelabError] = ParameterError) -> int:
    """``value`` as an int in ``[minimum, maximum]`` (a count: ``int`` or NumPy's, not a bool, not ``5.0``),
    or ``error`` naming ``name``."""
    n = _whole(value)
    if n is None or n < minimum or (maximum is not None and n > maximum):
        want = f"an integer of at least {minimum}" + ("" if maximum is None else f" and at most {maximum:,}")
        why = _why_not(value) or ("" if n is not None or not isinstance(value, numbers.Real) else
                                  "a count is a whole number: an int, not a float")
        raise _refuse(error, name, value, f"{name} must be {want}; got {shown(value)}" + (f" ({why})" if why else ""))
    return n


def seed(value: Any, name: str = "seed", *, error: type[BouncelabError] = ParameterError) -> int:
    """``value`` as an int in [0, 2**63) (a random seed), or ``error`` naming ``name``."""
    n = _whole(value)
    if n is None or not 0 <= n <= SEED_MAX:
        raise _refuse(error, name, value, f"{name} must be an integer in [0, 2**63); got {shown(value)}")
    return n


#: Array kinds that are not real numbers, though NumPy would turn some of them into floats.
_NOT_REAL = {"c": "complex", "b": "boolean", "U": "text", "S": "bytes", "V": "structured", "M": "dates",
             "m": "time spans"}


def real_array(value: Any, name: str, what: str = "real numbers", *, error: type[BouncelabError] = ParameterError,
               **fields: Any) -> np.ndarray:
    """``value`` as a float64 array (any shape; the caller checks shape and finiteness), or ``error`` naming
    ``name`` (``what`` words what the numbers are; ``fields``: more fields of the error, e.g. ``file``).

    Refused: what is not numbers, and what ``astype(float)`` would silently turn into numbers: complex,
    boolean, text, bytes, dates; in an array of Python objects, any element that is no real number
    (:func:`finite`'s rule: ``"1"``, ``True``, ``None``, ``10**400``).
    """
    def refused(why: str) -> BouncelabError:
        return _refuse(error, name, value, f"{name} must be numeric: {what}; {why}", **fields)

    try:
        raw = np.asarray(value)
    except (TypeError, ValueError, OverflowError, RecursionError) as exc:
        raise refused(str(exc)) from None
    kind = _NOT_REAL.get(raw.dtype.kind)
    if kind is not None:
        raise refused(f"got {kind} values")
    if raw.dtype == object:
        for i, v in enumerate(raw.flat):
            why = as_float(v)[1]
            if why:
                raise refused(f"element {i} is {shown(v)} ({why})")
    try:
        return raw.astype(np.float64) if raw.dtype != np.float64 else raw
    except (TypeError, ValueError, OverflowError) as exc:
        raise refused(str(exc)) from None


def generator(value: Any, name: str = "seed", *, error: type[BouncelabError] = ParameterError) -> np.random.Generator:
    """A NumPy random generator from ``value``: a ``Generator`` as it is, None a fresh one (unseeded), else
    a seed checked by :func:`seed`."""
    if isinstance(value, np.random.Generator):
        return value
    return np.random.default_rng(None if value is None else seed(value, name, error=error))


def text(value: Any, name: str, *, error: type[BouncelabError] = ParameterError, empty: bool = True) -> str:
    """``value`` if it is a ``str`` that can be written as UTF-8 (no lone surrogate, which a file or a
    terminal cannot hold; ``empty=False``: with something in it besides spaces), or ``error`` naming ``name``."""
    if not isinstance(value, str):
        raise _refuse(error, name, value, f"{name} must be text; got {type(value).__name__}")
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise _refuse(error, name, value, f"{name} holds a character that is not text ({value[exc.start]!r} at "
                      f"position {exc.start}: a lone UTF-16 surrogate, which no file or terminal can hold)") from None
    if not empty and not value.strip():
        raise _refuse(error, name, value, f"{name} must be non-empty text; got {shown(value)}")
    return value
