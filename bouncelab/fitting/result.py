"""What a fit found and how: :class:`FitResult`."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import pandas as pd

from bouncelab.core.slip_roll import SLIP_ROLL_CLASSES, _slip_codes
from bouncelab.laws import law_name
from bouncelab.laws.base import BounceModel
from bouncelab.laws.parameters import Parameters
from bouncelab.metrics import _error_table, error_terms

__all__ = ["FitResult"]


@dataclass
class FitResult:
    """The outcome of :func:`bouncelab.fit`.

    Everything law-specific is read from the law: its parameters (:attr:`params`,
    with standard errors where the method knows them), its report lines and its
    diagnostics (e.g. the piecewise law's mismatched fraction).

    Attributes
    ----------
    model
        The fitted law (a new object; the law passed to ``fit`` is unchanged). Its
        ``provenance`` says what it was fitted to (see :mod:`bouncelab.laws.provenance`).
    method
        The fitting method used (``"global"``, or one of the law's own, e.g.
        ``"structured"``, ``"plane"``, ``"svm"``).
    objective
        What was minimised, e.g. ``"delta"``.
    objective_value
        Its value at the fitted parameters, on the fitted data.
    delta, delta_q
        delta and ``[Delta xdot, Delta ydot, Delta omega]`` of :attr:`model` on
        the fitted data (``delta`` is exactly :func:`bouncelab.delta` of the
        model's predictions).
    errors
        Table of delta and Delta q overall and per measured class (slip/roll),
        for the fitted data and, when given, the held-out data (index
        ``(data, subset)``); built on first access.
    test_delta, test_delta_q
        The same on held-out data, or None.
    n_train, n_test
        Numbers of bounces.
    bounds
        Search box used, name -> (low, high) (arrays for array parameters).
    fixed
        Parameters held in the fit, name -> value.
    at_bounds
        Parameters (element names for arrays) that ended within 1e-6 of the box width of a
        bound, name -> "lower"/"upper".
    insensitive
        Parameters the objective does not depend on near the optimum (a 1 % change of the
        box width changes it by less than 1e-9 of its value), mapped to the range
        ``(low, high)`` over which the objective stays the same: within it the data do not
        determine the parameter.
    diagnostics, test_diagnostics
        The law's own figures (:meth:`~bouncelab.BounceModel._diagnostics`) on the fitted
        and the held-out bounces.
    stderr
        Standard errors the fitting method knows, name -> value.
    n_evaluations, n_global, n_local
        Objective evaluations, in all and per stage.
    elapsed
        Wall time of the fit, in seconds.
    stop_reason
        Why the optimizer(s) stopped.
    algorithm
        Global and local algorithms (or the procedure) used.
    seed
        Seed of the random generator.
    notes
        Anything a user should know about this fit.
    extras
        Method-specific results for programs (e.g. ``svm_support``).
    """

    model: BounceModel
    method: str
    objective: str
    objective_value: float
    delta: float
    delta_q: np.ndarray
    n_train: int
    data: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict, repr=False)
    test_delta: float | None = None
    test_delta_q: np.ndarray | None = None
    n_test: int = 0
    bounds: dict[str, tuple[Any, Any]] = field(default_factory=dict)
    fixed: dict[str, Any] = field(default_factory=dict)
    at_bounds: dict[str, str] = field(default_factory=dict)
    insensitive: dict[str, tuple[float, float]] = field(default_factory=dict)
    diagnostics: dict[str, float] = field(default_factory=dict)
    test_diagnostics: dict[str, float] = field(default_factory=dict)
    stderr: dict[str, Any] = field(default_factory=dict)
    n_evaluations: int = 0
    n_global: int = 0
    n_local: int = 0
    elapsed: float = 0.0
    stop_reason: str = ""
    algorithm: str = ""
    seed: int | None = None
    notes: list[str] = field(default_factory=list)
    extras: dict[str, Any] = field(default_factory=dict, repr=False)

    @cached_property
    def errors(self) -> pd.DataFrame:
        """delta and Delta q overall and per measured slip/roll class, on the fitted and held-out data."""
        tables = {}
        for name, (p0, pf) in self.data.items():
            classes = np.asarray(SLIP_ROLL_CLASSES)[_slip_codes(p0, pf)]
            tables[name] = _error_table(error_terms(p0, pf, self.model._evaluate(p0)), classes)
        return pd.concat(tables, names=["data", "subset"])

    @property
    def parameters(self) -> dict[str, Any]:
        """Fitted parameters, name -> value (arrays for array parameters)."""
        return self.model.parameters

    @property
    def params(self) -> Parameters:
        """The fitted parameters as objects, with standard errors where the method knows them."""
        return Parameters(p.replace(stderr=self.stderr.get(name), vary=name not in self.fixed)
                          for name, p in self.model.params.items())

    @property
    def n_free(self) -> int:
        """The numbers the fit varied: every element of every parameter neither held nor boxed to one value."""
        n = 0
        for spec in self.model.parameter_specs:
            if spec.name in self.fixed or spec.name not in self.bounds:
                continue
            lo, hi = (np.broadcast_to(np.asarray(b, dtype=float), (spec.size,)) for b in self.bounds[spec.name])
            n += int(np.count_nonzero(hi > lo))
        return n

    @property
    def mismatched(self) -> float | None:
        """The law's ``mismatched`` diagnostic on the fitted bounces, if it has one (piecewise law)."""
        return self.diagnostics.get("mismatched")

    @property
    def test_mismatched(self) -> float | None:
        """The same on the held-out bounces."""
        return self.test_diagnostics.get("mismatched")

    # ------------------------------------------------------------------ report
    def _parameter_lines(self) -> list[str]:
        lines = []
        for name, p in self.params.items():
            unit = "" if p.unit in ("1", "") else f" {p.unit}"  # "": no unit of its own (a plane's normal)
            if p.is_scalar:
                lo, hi = self.bounds.get(name, (np.nan, np.nan))
                flag = ""
                if name in self.fixed or lo == hi:
                    flag = "  (fixed)"
                elif name in self.at_bounds:
                    flag = f"  (at {self.at_bounds[name]} bound)"
                if name in self.insensitive:
                    lo_f, hi_f = self.insensitive[name]
                    flag += f"  (not determined by the data: same fit for {lo_f:.4g} to {hi_f:.4g})"
                err = "" if p.stderr is None else f" +- {float(p.stderr):.3g}"
                bounds = f"  bounds [{lo:g}, {hi:g}]" if name in self.bounds else ""
                lines.append(f"    {name:<9} = {p.format_value()}{err}{unit:<10}{bounds}{flag}")
            else:
                flag = "  (fixed)" if name in self.fixed else ""
                lines.append(f"    {name:<9} = {p.format_value(digits=4)}{unit and '  [' + unit.strip() + ']'}"
                             f"{flag}")
                if p.stderr is not None:
                    lines.append(f"    {'':<9} +- {p.format_value(p.stderr, digits=3)}")
        return lines

    def report(self) -> str:
        """A readable account of the fit: parameters, the law's own lines, errors, diagnostics, notes."""
        lines = [f"[[Fit]] {law_name(self.model)} by {self.method} ({self.algorithm}), minimising {self.objective}"]
        lines.append(
            f"    bounces: {self.n_train} fitted" + (f", {self.n_test} held out" if self.n_test else "")
        )
        lines.append(
            f"    evaluations: {self.n_evaluations} ({self.n_global} global + {self.n_local} local), "
            f"{self.elapsed * 1e3:.1f} ms, seed {self.seed}"
        )
        lines.append(f"    stopped: {self.stop_reason}")
        lines.append("[[Parameters]]")
        lines.extend(self._parameter_lines())
        summary = self.model._summary_lines()
        if summary:
            lines.append("[[Law]]")
            lines.extend(f"    {s}" for s in summary)
        lines.append("[[Errors]] (fractions; the paper prints them as %)")
        lines.append(_indent(self.errors.to_string(float_format=lambda v: f"{v:.4f}")))
        if self.diagnostics:
            lines.append("[[Diagnostics]]")
            for key, value in self.diagnostics.items():
                text = f"    {key}: {_fmt_diag(value)} fitted"
                if key in self.test_diagnostics:
                    text += f", {_fmt_diag(self.test_diagnostics[key])} held out"
                lines.append(text)
        if self.notes:
            lines.append("[[Notes]]")
            lines.extend(f"    - {n}" for n in self.notes)
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()

    def __repr__(self) -> str:
        test = f", test_delta={self.test_delta:.4f}" if self.test_delta is not None else ""
        return f"FitResult({self.model!r}, delta={self.delta:.4f}{test}, method={self.method!r})"

    def to_dict(self) -> dict[str, Any]:
        """JSON-safe summary (the law via :meth:`BounceModel.to_dict`)."""

        def plain(v: Any) -> Any:
            if isinstance(v, np.ndarray):
                return v.tolist()
            if isinstance(v, tuple | list):
                return [plain(x) for x in v]
            if isinstance(v, np.floating | np.integer):
                return v.item()
            return v

        return {
            "law": self.model.to_dict(),
            "method": self.method,
            "objective": self.objective,
            "objective_value": self.objective_value,
            "delta": self.delta,
            "delta_q": [float(v) for v in self.delta_q],
            "test_delta": self.test_delta,
            "test_delta_q": None if self.test_delta_q is None else [float(v) for v in self.test_delta_q],
            "n_train": self.n_train,
            "n_test": self.n_test,
            "bounds": {k: plain(v) for k, v in self.bounds.items()},
            "fixed": {k: plain(v) for k, v in self.fixed.items()},
            "at_bounds": dict(self.at_bounds),
            "insensitive": {k: list(v) for k, v in self.insensitive.items()},
            "diagnostics": dict(self.diagnostics),
            "test_diagnostics": dict(self.test_diagnostics),
            "stderr": {k: plain(v) for k, v in self.stderr.items()},
            "n_evaluations": self.n_evaluations,
            "elapsed_s": self.elapsed,
            "stop_reason": self.stop_reason,
            "algorithm": self.algorithm,
            "seed": self.seed,
            "mismatched": self.mismatched,
            "test_mismatched": self.test_mismatched,
            "notes": list(self.notes),
        }

    def _repr_html_(self) -> str:
        from bouncelab.fitting._display import fit_result_html  # the notebook view

        return fit_result_html(self)


def _fmt_diag(value: float) -> str:
    return f"{value:.4g}"


def _indent(text: str, pad: str = "    ") -> str:
    return "\n".join(pad + line for line in text.splitlines())
