"""Laws as files: a law's JSON description (:func:`describe`), reading one back (:func:`law_from_dict`,
:func:`load_law`).

A law file holds the law's value (its class's name, parameters and options) and what a reader needs to
trust it: the format and bouncelab versions, units and conventions, the ball radius, and the provenance of
a fitted law (what it was fitted to, synthetic or measured, the landing ranges). Every format bouncelab
has written loads; a law file never imports code (a law of your own loads once its module is imported).
"""

from __future__ import annotations

import json
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core import __version__
from bouncelab.core.errors import DataError, MissingFileError, ParameterError, SyntheticDataWarning, UnknownLawError
from bouncelab.core.files import read_regular_file
from bouncelab.core.units import BALL_RADIUS_M, COMPONENT_UNITS, COMPONENTS, CONVENTIONS
from bouncelab.laws.provenance import Provenance
from bouncelab.laws.registry import MAIN_MODULES, is_builtin, law_class, law_name, script_module

if TYPE_CHECKING:
    from bouncelab.laws.interface import Law

__all__ = ["LAW_FORMAT", "LAW_FORMAT_VERSION", "describe", "law_from_dict", "load_law", "value_dict"]

#: What a law file says it is, and the version of its layout (1: the first, ``{"law", "parameters", "options",
#: "bouncelab_version"}``; 2: units, conventions, ball radius, the class of a user's law and provenance added).
LAW_FORMAT = "bouncelab law"
LAW_FORMAT_VERSION = 2


def value_dict(law: Law) -> dict[str, Any]:
    """``{"law", "parameters", "options"}``: what makes the law the value it is."""

    def plain(v: Any) -> Any:
        return v.tolist() if isinstance(v, np.ndarray) else v

    d: dict[str, Any] = {"law": law_name(law), "parameters": {k: plain(v) for k, v in law.parameters.items()}}
    if law.option_names():
        d["options"] = {k: plain(v) for k, v in law.options.items()}
    return d


def describe(law: Law, *, metadata: bool = True) -> dict[str, Any]:
    """JSON-safe description of a law, the content of a law file (format :data:`LAW_FORMAT_VERSION`).

    ``metadata=False`` gives the law's value alone, in the keys of the first format
    (``law``, ``parameters``, ``options``, ``bouncelab_version``): for descriptions that embed a
    law among their own units and conventions (e.g. a simulated turf's); it loads as well.

    Keys: ``format`` and ``format_version``; ``law`` (:func:`~bouncelab.laws.registry.law_name`: the class
    name for bouncelab's laws, ``module:QualName`` for others) and, for a class of yours, ``class``
    (its module, qualified name and, for a script run as ``__main__``, the script's file);
    ``parameters``, ``parameter_units`` and ``options``; ``bouncelab_version``; ``units``
    and ``conventions`` (scaled units, y up, omega anticlockwise: omega > 0 is backspin);
    ``ball_radius_m`` (the radius of the fitted campaign's scaling, else the default 21.35 mm);
    ``provenance`` (:class:`~bouncelab.laws.provenance.Provenance` of a fitted law: the data,
    synthetic or measured, the generator of synthetic data, the fit, the landing ranges
    fitted), or None.
    """
    cls = type(law)
    if not metadata:
        return {**value_dict(law), "bouncelab_version": __version__}
    d: dict[str, Any] = {"format": LAW_FORMAT, "format_version": LAW_FORMAT_VERSION, **value_dict(law)}
    if not is_builtin(cls):
        d["class"] = {"module": cls.__module__, "qualname": cls.__qualname__, "script": script_module(cls)[1]}
    d["parameter_units"] = {spec.name: spec.unit for spec in law.parameter_specs}
    d["bouncelab_version"] = __version__
    d["units"] = dict(zip(COMPONENTS, COMPONENT_UNITS, strict=True))
    d["conventions"] = CONVENTIONS
    prov = law.provenance
    d["ball_radius_m"] = BALL_RADIUS_M if prov is None else prov.ball_radius_m
    d["provenance"] = None if prov is None else prov.to_dict()
    return d


def law_from_dict(d: Mapping[str, Any], expected: type[Law] | None = None) -> Law:
    """Build a law from a law description (:meth:`~bouncelab.BounceModel.to_dict`, or a law file's JSON).

    Every format bouncelab has written loads: the current one (:data:`LAW_FORMAT_VERSION`) and
    the first (``{"law", "parameters", "options", "bouncelab_version"}``, with no format
    version). The law's :attr:`~bouncelab.BounceModel.provenance` is restored when the description has one.
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
        key = "law" if not isinstance(d, Mapping) or "law" not in d else "parameters"
        raise ParameterError("a law description needs the keys 'law' and 'parameters'", parameter=key,
                             law=d.get("law") if isinstance(d, Mapping) and isinstance(d.get("law"), str) else None)
    version = d.get("format_version", 1)
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise ParameterError(f"the law description's format_version must be a whole number >= 1; got {version!r}",
                             parameter="format_version", value=version)
    if version > LAW_FORMAT_VERSION:
        raise ParameterError(f"the law description is in format {version}, written by a newer bouncelab "
                             f"({d.get('bouncelab_version', 'unknown version')}); this bouncelab reads formats up "
                             f"to {LAW_FORMAT_VERSION}: upgrade bouncelab to read it", parameter="format_version",
                             value=version)
    name = d["law"]
    if not isinstance(name, str):
        raise ParameterError(f"the law name must be a string; got {name!r}", parameter="law", value=name)
    record = d.get("class")
    script = record.get("script") if isinstance(record, Mapping) else None
    if script is not None and not isinstance(script, str):
        script = None
    if isinstance(record, Mapping) and record.get("module") in MAIN_MODULES and ":" in name:
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
        raise ParameterError(f"the description is of a {name}, not a {expected.__name__}", law=law_name(cls),
                             parameter="law", value=name)
    kwargs: dict[str, Any] = {}
    for key in ("parameters", "options"):
        part = d.get(key, {})
        if part is None:
            part = {}
        if not isinstance(part, Mapping) or not all(isinstance(k, str) for k in part):
            raise ParameterError(f"{name}: {key!r} must be a mapping of names to values; got {type(part).__name__}",
                                 law=law_name(cls), parameter=key)
        kwargs.update(part)
    unknown = set(kwargs) - set(cls._keyword_names())
    if unknown:
        raise ParameterError(f"{name} has no parameter(s) {sorted(unknown)}; it has {list(cls._keyword_names())}",
                             law=law_name(cls), parameter=sorted(unknown)[0])
    try:
        law = cls(**kwargs)
    except ParameterError:
        raise
    except (TypeError, ValueError, OverflowError, RecursionError, AttributeError) as exc:
        raise ParameterError(f"{name}: bad parameter values in the description ({type(exc).__name__}: {exc})",
                             law=law_name(cls)) from None
    prov = d.get("provenance")
    if prov is not None:
        law = law._with_provenance(Provenance.from_dict(prov, where=f"the description of {name}", law=law_name(cls)))
    return law


def load_law(path: str | Path) -> Law:
    """Read a law written by :meth:`~bouncelab.BounceModel.to_json` (any format bouncelab has written).

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
                             "bouncelab.laws.law_from_dict(json.loads(text))", parameter="path", value=path)
    try:
        file = str(Path(path))
    except TypeError:
        raise ParameterError(f"load_law takes the path of a law JSON file; got {type(path).__name__}",
                             parameter="path", value=path) from None
    data = _read_law_file(Path(path).expanduser(), file)
    try:
        d = json.loads(data.decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError, RecursionError) as exc:  # JSONDecodeError, and too-long integers
        raise ParameterError(f"{file}: not a JSON law description ({type(exc).__name__}: {exc})", parameter="path",
                             value=file) from None
    try:
        law = law_from_dict(d)
    except UnknownLawError as exc:
        raise UnknownLawError(f"{file}: {exc}", law_name=exc.law_name, module=exc.module, qualname=exc.qualname,
                              module_imported=exc.module_imported, script=exc.script) from None
    except ParameterError as exc:  # the file named, the facts kept
        raise ParameterError(f"{file}: {exc.message}", law=exc.law, parameter=exc.parameter, value=exc.value,
                             hints=exc.hints) from None
    note = None if law.provenance is None else law.provenance.synthetic_note()
    if note is not None:
        warnings.warn(f"{file}: {note}", SyntheticDataWarning, stacklevel=2)
    return law


def _read_law_file(path: Path, file: str) -> bytes:
    """The bytes of a law file (DataError naming it when it cannot be read)."""
    if not path.exists():
        raise MissingFileError("no such law file", file=file)
    if path.is_dir():
        raise DataError("it is a directory, not a law file (give the path of the .json file the law was written to)",
                        file=file)
    try:
        return read_regular_file(path, file)
    except OSError as exc:
        raise DataError(f"the law file cannot be read ({exc.strerror or exc})", file=file) from None
