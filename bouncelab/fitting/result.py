"""What a fit found and how: :class:`FitResult`."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import pandas as pd

from bouncelab.data.slip_roll import classify_slip_roll
from bouncelab.laws.base import BounceModel
from bouncelab.metrics import error_table

__all__ = ["FitResult"]


@dataclass
class FitResult:
    """The outcome of :func:`bouncelab.fit`.

    Attributes
    ----------
    model
        The fitted law (a new object; the law passed to ``fit`` is unchanged).
    method
        ``"global"``, ``"structured"``, ``"svm"`` or ``"plane"``.
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
        Search box used, name -> (low, high); a parameter with low == high was held fixed.
    at_bounds
        Parameters that ended within 1e-6 of the box width of a bound, name -> "lower"/"upper".
    insensitive
        Parameters the objective does not depend on near the optimum (a 1 % change of the
        box width changes it by less than 1e-9 of its value), mapped to the range
        ``(low, high)`` over which the objective stays the same: within it the data do not
        determine the parameter.
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
    mismatched, test_mismatched
        Piecewise law only: fraction of bounces whose measured slip/roll class differs
        from their side of the plane (the paper's Table 2).
    notes
        Anything a user should know about this fit.
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
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    at_bounds: dict[str, str] = field(default_factory=dict)
    insensitive: dict[str, tuple[float, float]] = field(default_factory=dict)
    n_evaluations: int = 0
    n_global: int = 0
    n_local: int = 0
    elapsed: float = 0.0
    stop_reason: str = ""
    algorithm: str = ""
    seed: int | None = None
    mismatched: float | None = None
    test_mismatched: float | None = None
    notes: list[str] = field(default_factory=list)

    @cached_property
    def errors(self) -> pd.DataFrame:
        """delta and Delta q overall and per measured slip/roll class, on the fitted and held-out data."""
        tables = {
            name: error_table(p0, pf, self.model.predict(p0), classify_slip_roll(p0, pf))
            for name, (p0, pf) in self.data.items()
        }
        return pd.concat(tables, names=["data", "subset"])

    @property
    def parameters(self) -> dict[str, float | None]:
        """Fitted parameters, name -> value."""
        return self.model.parameters

    def report(self) -> str:
        """A readable account of the fit: parameters, errors, and what the optimizer did."""
        law = type(self.model).__name__
        lines = [f"[[Fit]] {law} by {self.method} ({self.algorithm}), minimising {self.objective}"]
        lines.append(
            f"    bounces: {self.n_train} fitted" + (f", {self.n_test} held out" if self.n_test else "")
        )
        lines.append(
            f"    evaluations: {self.n_evaluations} ({self.n_global} global + {self.n_local} local), "
            f"{self.elapsed * 1e3:.1f} ms, seed {self.seed}"
        )
        lines.append(f"    stopped: {self.stop_reason}")
        lines.append("[[Parameters]]")
        if hasattr(self.model, "plane_equation"):
            lines.append(f"    plane: {self.model.plane_equation()}")
            lines.append(f"    side 1 (roll): A1 = {np.array2string(self.model.A1, precision=3)}".replace("\n", ""))
            lines.append(f"                   b1 = {np.array2string(self.model.b1, precision=3)}")
            lines.append(f"    side 2 (slip): A2 = {np.array2string(self.model.A2, precision=3)}".replace("\n", ""))
            lines.append(f"                   b2 = {np.array2string(self.model.b2, precision=3)}")
        else:
            specs = {s.name: s for s in self.model.parameter_specs}
            for name, value in self.model.parameters.items():
                lo, hi = self.bounds.get(name, (np.nan, np.nan))
                flag = ""
                if lo == hi:
                    flag = "  (fixed)"
                elif name in self.at_bounds:
                    flag = f"  (at {self.at_bounds[name]} bound)"
                if name in self.insensitive:
                    lo_f, hi_f = self.insensitive[name]
                    flag += f"  (not determined by the data: same fit for {lo_f:.4g} to {hi_f:.4g})"
                unit = specs[name].unit if name in specs else ""
                unit = "" if unit == "1" else f" {unit}"
                lines.append(f"    {name:<9} = {value:.6g}{unit:<10} bounds [{lo:g}, {hi:g}]{flag}")
        lines.append("[[Errors]] (fractions; the paper prints them as %)")
        lines.append(_indent(self.errors.to_string(float_format=lambda v: f"{v:.4f}")))
        if self.mismatched is not None:
            text = f"    mismatched (measured class vs side of plane): {self.mismatched:.2%} fitted"
            if self.test_mismatched is not None:
                text += f", {self.test_mismatched:.2%} held out"
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
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "at_bounds": dict(self.at_bounds),
            "insensitive": {k: list(v) for k, v in self.insensitive.items()},
            "n_evaluations": self.n_evaluations,
            "elapsed_s": self.elapsed,
            "stop_reason": self.stop_reason,
            "algorithm": self.algorithm,
            "seed": self.seed,
            "mismatched": self.mismatched,
            "test_mismatched": self.test_mismatched,
            "notes": list(self.notes),
        }


def _indent(text: str, pad: str = "    ") -> str:
    return "\n".join(pad + line for line in text.splitlines())
