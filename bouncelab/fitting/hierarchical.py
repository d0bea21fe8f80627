r"""``bouncelab.calibrate``: hierarchical calibration of a law, with spot-to-spot variation and predictive spread.

A fitted law predicts one lift-off per landing. Real turf varies from spot to spot, the
measurements have errors, and the law itself misses. :func:`calibrate` separates the three
with a hierarchical model and samples its posterior with ``emcee``; the
:class:`Posterior` it returns draws lift-offs (``predict``), gives predictive intervals
(``interval``) and checks them against a campaign (``check``).

The model
---------
For bounce :math:`i` with measured landing :math:`p_{0,i}` and measured lift-off :math:`y_i`:

* each parameter :math:`\theta_j` named in ``vary`` takes its own value at the bounce's spot,
  :math:`\theta_{ij} = T_j^{-1}(m_j + s_j u_{ij})`, :math:`u_{ij} \sim N(0, 1)`, where
  :math:`T_j` is the logit of :math:`(\theta - a)/(b - a)` for a parameter whose physical range
  :math:`[a, b]` is bounded on both sides (logit-normal), :math:`\log(\theta - a)` when only
  the lower side is (log-normal; :math:`\log(b - \theta)` when only the upper side is) and
  the identity otherwise (normal). :math:`T_j^{-1}(m_j)` is the *population median* of the
  parameter and :math:`s_j` its *spot-to-spot scale* (a standard deviation in the transformed
  space: for a log-normal parameter, about the relative spread). The other free parameters
  have one population value;
* the law may miss: the true lift-off is the law's prediction plus a *model discrepancy*
  :math:`\epsilon_i \sim N(0, \mathrm{diag}(\tau^2))` with one :math:`\tau_c` per component;
* the landing and the lift-off are measured with independent normal errors of the standard
  deviations their 95 % prediction intervals state (``landing_pi / 1.96``,
  ``liftoff_pi / 1.96``). Without intervals the measurement error of the lift-off cannot be
  told apart from the discrepancy: then :math:`\tau` is fitted as one *noise* term holding both.

The approximation
-----------------
The per-bounce parameters are marginalised, not sampled: each measured lift-off is given a
normal distribution whose mean and covariance approximate those of the model,

.. math::

    y_i \sim N\bigl(\mu_i,\; \Sigma_{\theta,i} + G_i \Sigma_{0,i} G_i^\top + \Sigma_{F,i}
    + \mathrm{diag}(\tau^2)\bigr)

where :math:`G_i` is the derivative of the prediction with respect to the landing (forward
differences), :math:`\Sigma_{0,i}`, :math:`\Sigma_{F,i}` the measurement covariances, and
:math:`\mu_i`, :math:`\Sigma_{\theta,i}` the mean and covariance of the law's prediction over
the spot-to-spot distribution of the varying parameters, computed in one of two ways
(``approximation=``):

``"unscented"`` (default)
    The unscented transform: the law at the population medians and at :math:`2V` sigma points
    :math:`m \pm \sqrt{V + \kappa}\, s_j e_j` in the transformed space (:math:`V` varying
    parameters, :math:`\kappa = \max(0, 3 - V)`), weighted to match the normal's moments. It
    carries the shift of the mean (a log-normal parameter's mean is not its median) and spreads
    across kinks of the law (slip to roll) that a derivative cannot see.
``"linear"``
    Linearisation around the medians: :math:`\mu_i = f(p_{0,i}, \bar\theta)` and
    :math:`\Sigma_{\theta,i} = J_i S^2 J_i^\top` with :math:`J_i` the derivative of the prediction
    with respect to the transformed varying parameters (forward differences) and
    :math:`S = \mathrm{diag}(s)`. Cheaper by :math:`V` law calls per evaluation, but biased
    where the law is curved or kinked on the scale of the spread: on the 15-bounce case of
    tests/test_calibrate.py (Rigid, ``r`` varying, both regimes) it puts the population median
    of ``r`` 2.6 posterior standard deviations from the brute-force answer, the unscented
    transform within a tenth of one.

Either way every evaluation calls the law on all bounces at once: :math:`2V + 1` calls
(unscented) or :math:`V + 1` (linear), plus one for the landing derivatives when the landings
have measurement errors. Both are normal approximations of a distribution that need not be
normal (a bounce that slips for some spots and rolls for others has a lumpy one); the test
compares them with a brute-force integration over the per-bounce parameters.
:meth:`Posterior.predict` does not approximate: it draws per-bounce parameters and calls the law.

Priors
------
Population values: uniform over the law's search box (``bounds=`` overrides it). Scales
:math:`s_j`: half-normal with standard deviation 1 (in the transformed space). Discrepancy
(or noise) :math:`\tau_c`: half-normal with the standard deviation of the component's
lift-offs in the data. The scales and discrepancies are sampled as logarithms.

Sampling and convergence
------------------------
``emcee``'s ensemble sampler (differential-evolution moves). Its walkers start from the normal
approximation of the posterior at its mode: the mode found by Nelder-Mead from a point fit, the
covariance from a finite-difference Hessian there (the diagonal, or a small ball, where the
Hessian is not negative definite). With ``steps=None`` it runs in blocks of 250 steps until the
chain after burn-in (five autocorrelation times, at most the first third; the first third after
a small-ball start) is at least ``tau_multiple`` (50) integrated autocorrelation times long and
the split R-hat across walkers is below 1.05, or ``max_steps`` is reached, in which case a
:class:`ConvergenceWarning` is issued. For a compiled law (every built-in law) the walkers' log
posteriors of each step are shared between the threads of :func:`bouncelab.laws.set_num_threads`
(its loops release the GIL; the samples do not depend on the number of threads); a law written in
Python is evaluated on one thread. ``chains`` independent ensembles can run on a
dask ``client``; the diagnostics then pool every walker of every chain over their common length.
"""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from bouncelab.core._parallel import ThreadMap
from bouncelab.core.errors import BouncelabWarning, DataError, FitError, Hint, ParameterError
from bouncelab.core.slip_roll import SLIP_ROLL_CLASSES, _slip_codes
from bouncelab.core.units import COMPONENTS
from bouncelab.core.validation import as_states
from bouncelab.data.campaign import interval_sds, synthetic_warning
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.fitter import check_count, check_fraction, check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.tasks import map_tasks
from bouncelab.fitting.vector import ParameterVector
from bouncelab.laws import law_from_dict, law_name
from bouncelab.laws.base import BounceModel
from bouncelab.laws.compiled import CompiledLaw

__all__ = ["ConvergenceWarning", "Posterior", "calibrate", "load_posterior"]


#: How :func:`calibrate` marginalises the per-bounce parameters (see the module documentation).
APPROXIMATIONS = ("linear", "unscented")

#: Format tag of a saved posterior.
FORMAT = "bouncelab.Posterior"
FORMAT_VERSION = 1


class ConvergenceWarning(BouncelabWarning):
    """The sampler did not reach the convergence criteria of :func:`calibrate` within ``max_steps``."""


# ------------------------------------------------------------------------------ transforms
@dataclass(frozen=True)
class _Transform:
    """Map of a parameter to the unbounded space where its spot-to-spot variation is normal."""

    kind: str  # "logit", "log", "neglog" or "identity"
    a: float
    b: float

    @classmethod
    def of(cls, low: float, high: float) -> _Transform:
        if np.isfinite(low) and np.isfinite(high):
            return cls("logit", float(low), float(high))
        if np.isfinite(low):
            return cls("log", float(low), math.inf)
        if np.isfinite(high):
            return cls("neglog", -math.inf, float(high))
        return cls("identity", -math.inf, math.inf)

    def forward(self, theta: Any) -> Any:
        t = np.asarray(theta, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.kind == "logit":
                u = (t - self.a) / (self.b - self.a)
                return np.log(u) - np.log1p(-u)
            if self.kind == "log":
                return np.log(t - self.a)
            if self.kind == "neglog":
                return np.log(self.b - t)
        return t

    def inverse(self, z: Any) -> Any:
        z = np.asarray(z, dtype=float)
        if self.kind == "logit":
            return self.a + (self.b - self.a) * (0.5 * (1.0 + np.tanh(0.5 * z)))  # a stable logistic
        with np.errstate(over="ignore"):  # a sampler's wild proposal: inf, whose likelihood is then zero
            if self.kind == "log":
                return self.a + np.exp(z)
            if self.kind == "neglog":
                return self.b - np.exp(z)
        return z

    def inside(self, theta: float) -> bool:
        """Strictly inside the open range where the transform is finite."""
        return (self.kind in ("identity", "neglog") or theta > self.a) and \
               (self.kind in ("identity", "log") or theta < self.b)

    def describe(self) -> str:
        return {"logit": f"logit-normal within [{self.a:g}, {self.b:g}]", "log": f"log-normal above {self.a:g}",
                "neglog": f"log-normal below {self.b:g}", "identity": "normal"}[self.kind]

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "a": _finite_or_text(self.a), "b": _finite_or_text(self.b)}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> _Transform:
        return cls(str(d["kind"]), float(d["a"]), float(d["b"]))


def _finite_or_text(v: float) -> Any:
    """A number for JSON: infinities and NaN as text (``float`` reads them back)."""
    if np.isfinite(v):
        return v
    return "nan" if np.isnan(v) else ("inf" if v > 0 else "-inf")


def _json_number(v: Any) -> Any:
    """A diagnostic for JSON: NumPy scalars as Python numbers, non-finite floats as text (lists element-wise)."""
    if isinstance(v, list):
        return [_json_number(x) for x in v]
    if isinstance(v, np.generic):
        v = v.item()
    return _finite_or_text(v) if isinstance(v, float) else v


# ------------------------------------------------------------------------------ the log posterior
class _LogPosterior:
    """The linearised log posterior of the population values, scales and discrepancies (picklable).

    The vector it takes: the free parameters' population values (medians for the varying ones),
    then ``log s`` of each varying parameter, then ``log tau`` of each component (when sampled).
    """

    def __init__(self, law: BounceModel, landing: np.ndarray, liftoff: np.ndarray, *, free: Sequence[str],
                 vary: Sequence[str], box: Mapping[str, tuple[float, float]], landing_sd: np.ndarray | None,
                 liftoff_sd: np.ndarray | None, with_tau: bool, tau_prior: np.ndarray, scale_prior: float = 1.0,
                 step: float = 1e-4, approximation: str = "unscented") -> None:
        self.law = law
        self.p0 = np.ascontiguousarray(landing, dtype=np.float64)
        self.y = np.ascontiguousarray(liftoff, dtype=np.float64)
        self.free = list(free)
        self.vary = list(vary)
        names = [s.name for s in law.parameter_specs]
        self._vec = ParameterVector(law)
        self.theta0 = self._vec.of(law)
        self.index = {n: names.index(n) for n in self.free}
        specs = {s.name: s for s in law.parameter_specs}
        self.transforms = {n: _Transform.of(*(float(v[0]) for v in specs[n].physical_arrays())) for n in self.vary}
        self.box = {n: (float(box[n][0]), float(box[n][1])) for n in self.free}
        self.landing_sd = None if landing_sd is None or not np.any(landing_sd > 0) else landing_sd
        self.liftoff_var = None if liftoff_sd is None else liftoff_sd ** 2
        self.with_tau = with_tau
        self.tau_prior = np.asarray(tau_prior, dtype=float)
        self.scale_prior = float(scale_prior)
        self.step = float(step)
        n = len(self.p0)
        # forward steps of the landing: small against each component, and never across ydot = 0
        self.h_land = 1e-6 * np.maximum(np.abs(self.p0), 1.0)
        self.jitter = 1e-10 * (1.0 + np.mean(self.y ** 2, axis=0))
        self.n = n
        if approximation not in APPROXIMATIONS:
            raise FitError(f"approximation must be one of {APPROXIMATIONS}; got {approximation!r}",
                           option="approximation")
        self.approximation = approximation
        if self.landing_sd is not None:
            moved = [self.p0.copy() for _ in range(3)]
            for c in range(3):
                moved[c][:, c] += self.h_land[:, c]
            self._stacked = np.ascontiguousarray(np.concatenate([self.p0, *moved]))
            self._land_scale = [(self.landing_sd[:, c] / self.h_land[:, c])[:, None] for c in range(3)]
        self._bounds = [self.box[f] for f in self.free]
        varying = [(j, self.transforms[f]) for j, f in enumerate(self.free) if f in self.transforms]
        self._open_lo = [(j, t.a) for j, t in varying if t.kind in ("logit", "log")]
        self._open_hi = [(j, t.b) for j, t in varying if t.kind in ("logit", "neglog")]
        self._tau_prior = self.tau_prior.tolist()

    @property
    def columns(self) -> list[str]:
        noise = "discrepancy" if self.liftoff_var is not None else "noise"
        return [*self.free, *(f"scale_{v}" for v in self.vary),
                *((f"{noise}_{c}" for c in COMPONENTS) if self.with_tau else ())]

    @property
    def ndim(self) -> int:
        return len(self.free) + len(self.vary) + (3 if self.with_tau else 0)

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        nf, nv = len(self.free), len(self.vary)
        theta = self.theta0.copy()
        for j, name in enumerate(self.free):
            theta[self.index[name]] = x[j]
        s = np.exp(x[nf:nf + nv])
        tau = np.exp(x[nf + nv:]) if self.with_tau else np.zeros(3)
        return theta, s, tau

    def log_prior(self, x: np.ndarray) -> float:
        # plain Python on a handful of numbers: NumPy's per-call overhead would dominate here
        v = x.tolist()
        for j, (lo, hi) in enumerate(self._bounds):
            if not lo <= v[j] <= hi:
                return -math.inf
        for j, a in self._open_lo:
            if v[j] <= a:
                return -math.inf  # a varying parameter's median must be inside its transform's open range
        for j, b in self._open_hi:
            if v[j] >= b:
                return -math.inf
        nf, nv = len(self.free), len(self.vary)
        lp = 0.0
        for j in range(nf, len(v)):
            if not abs(v[j]) < 50:
                return -math.inf
            # half-normal priors on s and tau, sampled as logarithms (hence the + log s, + log tau)
            sd = self.scale_prior if j < nf + nv else self._tau_prior[j - nf - nv]
            lp += v[j] - 0.5 * (math.exp(v[j]) / sd) ** 2
        return lp

    def moments(self, x: np.ndarray) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
        """The approximate mean (n, 3) of the measured lift-offs and the six distinct entries of their
        covariances (xx, yy, ww, xy, xw, yw), each (n,)."""
        theta, s, tau = self.split(x)
        law, p0, n = self.law, self.p0, self.n
        if self.landing_sd is not None:  # the landing steps share the parameters: one call for all four
            out = self._vec.predict(law, self._stacked, theta)
            mean = out[:n]
            cols = [(out[(c + 1) * n:(c + 2) * n] - mean) * self._land_scale[c] for c in range(3)]
        else:
            mean = self._vec.predict(law, p0, theta)
            cols = []
        if self.approximation == "linear":
            for j, name in enumerate(self.vary):
                k = self.index[name]
                tr = self.transforms[name]
                shifted = theta.copy()
                shifted[k] = float(tr.inverse(float(tr.forward(theta[k])) + self.step))
                cols.append((self._vec.predict(law, p0, shifted) - mean) * (s[j] / self.step))  # J_ij s_j
        else:  # unscented: 2V + 1 sigma points in the transformed space
            nv = len(self.vary)
            if nv:
                kappa = max(0.0, 3.0 - nv)
                spread = math.sqrt(nv + kappa)
                w0, wi = kappa / (nv + kappa), 0.5 / (nv + kappa)
                points = []
                for j, name in enumerate(self.vary):
                    k = self.index[name]
                    tr = self.transforms[name]
                    z = float(tr.forward(theta[k]))
                    for sign in (1.0, -1.0):
                        shifted = theta.copy()
                        shifted[k] = float(tr.inverse(z + sign * spread * s[j]))
                        points.append(self._vec.predict(law, p0, shifted))
                centre = mean
                mean = w0 * centre + wi * sum(points)
                if w0 > 0:
                    cols.append((centre - mean) * math.sqrt(w0))
                cols.extend((pt - mean) * math.sqrt(wi) for pt in points)
        diag = tau ** 2 + self.jitter
        if cols:
            v = np.stack(cols)  # (k, n, 3)
            xx, yy, ww = (v[:, :, 0] ** 2).sum(0), (v[:, :, 1] ** 2).sum(0), (v[:, :, 2] ** 2).sum(0)
            xy = (v[:, :, 0] * v[:, :, 1]).sum(0)
            xw = (v[:, :, 0] * v[:, :, 2]).sum(0)
            yw = (v[:, :, 1] * v[:, :, 2]).sum(0)
        else:
            xx = yy = ww = xy = xw = yw = np.zeros(n)
        xx, yy, ww = xx + diag[0], yy + diag[1], ww + diag[2]
        if self.liftoff_var is not None:
            xx, yy, ww = xx + self.liftoff_var[:, 0], yy + self.liftoff_var[:, 1], ww + self.liftoff_var[:, 2]
        return mean, (xx, yy, ww, xy, xw, yw)

    def log_likelihood(self, x: np.ndarray) -> float:
        mean, cov = self.moments(x)
        det, quad = _det_quad(cov, self.y - mean)
        if not np.all(det > 0):
            return -math.inf
        value = -0.5 * float(np.sum(quad + np.log(det)) + 3 * self.n * math.log(2 * math.pi))
        return value if math.isfinite(value) else -math.inf

    def __call__(self, x: np.ndarray) -> float:
        lp = self.log_prior(x)
        if not math.isfinite(lp):
            return -math.inf
        return lp + self.log_likelihood(x)


def _det_quad(c: tuple[np.ndarray, ...], r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Determinants of symmetric 3 x 3 matrices given by their entries (xx, yy, ww, xy, xw, yw), and the
    quadratic forms r^T C^-1 r, in closed form (cofactors: far faster than batched LAPACK calls on 3 x 3)."""
    a, d, f, b, cc, e = c
    A = d * f - e * e
    B = cc * e - b * f
    C = b * e - cc * d
    D = a * f - cc * cc
    E = b * cc - a * e
    F = a * d - b * b
    det = a * A + b * B + cc * C
    x, y, z = r[:, 0], r[:, 1], r[:, 2]
    adj = A * x * x + D * y * y + F * z * z + 2.0 * (B * x * y + C * x * z + E * y * z)
    with np.errstate(divide="ignore", invalid="ignore"):
        return det, adj / det


# ------------------------------------------------------------------------------ the function
def calibrate(
    model: Any,
    data: Any,
    vary: Sequence[str] | str,
    *,
    discrepancy: bool = True,
    approximation: str = "unscented",
    walkers: int | None = None,
    steps: int | None = None,
    max_steps: int = 20_000,
    tau_multiple: float = 50.0,
    chains: int = 1,
    seed: int = 0,
    client: Any = None,
    method: str | None = None,
    progress: bool = False,
    **fit_kwargs: Any,
) -> Posterior:
    """Hierarchical calibration: population values, spot-to-spot scales and model discrepancy of a law.

    See the module documentation (:mod:`bouncelab.fitting.hierarchical`) for the model, the
    approximations it offers, the priors and the convergence criteria.

    Parameters
    ----------
    model
        A law class, instance or name, as for :func:`bouncelab.fit`.
    data
        A campaign Dataset (its ``landing_pi`` and ``liftoff_pi``, when present, give the
        measurement errors) or a ``(landing, liftoff)`` pair.
    vary
        Names of the scalar parameters that vary from bounce to bounce.
    discrepancy
        Fit a model discrepancy (one standard deviation per component). Without prediction
        intervals in the data a noise term is always fitted, holding measurement error and
        discrepancy alike.
    approximation
        ``"unscented"`` (default) or ``"linear"``: how the per-bounce parameters are
        marginalised (see the module documentation).
    walkers
        Walkers of the ensemble (default: two per sampled number plus two, at least 24; even).
    steps
        Steps per walker; None runs until converged or ``max_steps``.
    max_steps
        Most steps per walker with ``steps=None``.
    tau_multiple
        Convergence needs the chain after burn-in to be this many autocorrelation times long.
    chains
        Independent ensembles, each with its own seed (run on ``client`` when given).
    seed
        Seed of the point fit, the start and the sampler.
    client
        A :class:`dask.distributed.Client` or an executor of
        :func:`~bouncelab.fitting.tasks.map_tasks` to run the chains on; the result is the same.
    method
        Method of the point fit that starts the sampler (default: the law's).
    progress
        Show emcee's progress bar.
    **fit_kwargs
        ``bounds`` (the population values' prior box), ``fixed``, ``free`` and options of the point fit.

    Returns
    -------
    Posterior

    Raises
    ------
    FitError
        A name in ``vary`` that is not a free scalar parameter of the law, bad counts,
        ``sample_weight``, or a ``bounds`` outside the physical range.
    DataError
        Bad data, or prediction intervals with non-finite values.

    Warns
    -----
    ConvergenceWarning
        The chain did not meet the convergence criteria within ``max_steps``.
    """

    start_time = time.perf_counter()
    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "calibrate", "its likelihood treats every bounce alike")
    seed = check_seed(seed)
    if isinstance(vary, str):
        vary = [vary]
    vary = list(vary)
    chains = check_count(chains, "chains", 1)
    max_steps = check_count(max_steps, "max_steps", 10)
    if steps is not None:
        steps = check_count(steps, "steps", 10)
    if not (isinstance(tau_multiple, int | float) and not isinstance(tau_multiple, bool) and tau_multiple > 0):
        raise FitError(f"tau_multiple must be a positive number; got {tau_multiple!r}", option="tau_multiple")
    p0, pf, _ = campaign_arrays(data)
    point = fit(law, data, method=method, seed=seed, **fit_kwargs)
    fitted = point.model
    specs = {s.name: s for s in fitted.parameter_specs}
    free = [n for n in specs if n not in point.fixed and specs[n].is_scalar
            and point.bounds[n][0] < point.bounds[n][1]]
    for name in vary:
        if name not in specs:
            raise FitError(f"vary names {name!r}, which is not a parameter of {law_name(fitted)}; its parameters "
                           f"are {list(specs)}", law=law_name(fitted), option="vary")
        if not specs[name].is_scalar:
            raise FitError(f"vary names {name!r}, an array parameter; only scalar parameters can vary per bounce",
                           law=law_name(fitted), option="vary")
        if name not in free:
            raise FitError(f"vary names {name!r}, which is held in the fit; a varying parameter must be free",
                           law=law_name(fitted), option="vary")
    if len(set(vary)) != len(vary):
        raise FitError(f"vary names a parameter twice: {vary}", law=law_name(fitted), option="vary")
    if any(not s.is_scalar and s.name not in point.fixed for s in specs.values()):
        arrays = [s.name for s in specs.values() if not s.is_scalar]
        raise FitError(f"calibrate samples scalar parameters only; the array parameter(s) {arrays} must be held",
                       law=law_name(fitted), option="fixed", hints=[Hint("fixed", arrays)])
    landing_sd, liftoff_sd = interval_sds(data, len(p0))
    with_tau = discrepancy or liftoff_sd is None
    tau_prior = np.maximum(pf.std(axis=0), 1e-6)
    post = _LogPosterior(fitted, p0, pf, free=free, vary=vary, box=point.bounds, landing_sd=landing_sd,
                         liftoff_sd=liftoff_sd, with_tau=with_tau, tau_prior=tau_prior, approximation=approximation)
    # start: the point fit, small scales, the fit's residual spread as discrepancy; then the mode
    resid = pf - fitted._evaluate(p0)
    x0 = np.r_[[getattr(fitted, n) for n in free], np.full(len(vary), math.log(0.1)),
               np.log(np.maximum(0.5 * resid.std(axis=0), 1e-6 * tau_prior)) if with_tau else []]
    for j, name in enumerate(free):  # a median on the edge of its transform's range cannot start the search
        if name in post.transforms and not post.transforms[name].inside(x0[j]):
            lo, hi = post.box[name]
            x0[j] = lo + 1e-3 * (hi - lo) if x0[j] <= lo else hi - 1e-3 * (hi - lo)
    mode = _mode(post, x0)
    ndim = post.ndim
    walkers = max(24, 2 * ndim + 2) if walkers is None else check_count(walkers, "walkers", 2 * ndim + 2)
    walkers += walkers % 2
    spread, start_kind = _laplace(post, mode)
    tasks = []
    for c in range(chains):
        rng = np.random.default_rng([seed, c])
        start = _start(post, mode, spread, walkers, rng)
        burn_taus = BURN_TAUS if start_kind != "ball" else math.inf  # a start in a small ball needs to spread out
        tasks.append((post, start, steps, max_steps, tau_multiple, burn_taus, int(rng.integers(2**32 - 1)),
                      progress))
    runs = map_tasks(_run_chain, tasks, client)
    length = min(len(r["chain"]) for r in runs)  # chains that stopped at different steps: their common tail
    kept = np.concatenate([r["chain"][-length:] for r in runs], axis=1)  # (steps kept, all walkers, ndim)
    diagnostics = _diagnostics(kept, runs, tau_multiple)
    columns = post.columns
    samples = _thin(kept, diagnostics, columns, len(free))
    notes = []
    note = synthetic_warning(data)
    if note is not None:
        notes.append(note)
    if liftoff_sd is None:
        notes.append("the data carry no prediction intervals: the fitted noise holds measurement error and model "
                     "discrepancy alike")
    if not diagnostics["converged"]:
        warnings.warn(f"calibrate of {law_name(fitted)}: the sampler did not converge within {diagnostics['steps']} "
                      f"steps ({diagnostics['reason']}); run longer (steps=, max_steps=) before trusting the "
                      "posterior", ConvergenceWarning, stacklevel=2)
        notes.append(f"NOT CONVERGED: {diagnostics['reason']}")
    diagnostics["start"] = start_kind
    diagnostics["elapsed_s"] = time.perf_counter() - start_time
    measurement = {
        "landing_sd": None if landing_sd is None else np.median(landing_sd, axis=0).tolist(),
        "liftoff_sd": None if liftoff_sd is None else np.median(liftoff_sd, axis=0).tolist(),
    }
    return Posterior(law=fitted, free=free, vary=vary, transforms={v: post.transforms[v] for v in vary},
                     samples=samples, diagnostics=diagnostics, measurement=measurement,
                     residual="discrepancy" if liftoff_sd is not None else "noise", with_tau=with_tau,
                     n_bounces=len(p0), mode=dict(zip(columns, mode.tolist(), strict=True)), notes=notes,
                     data_kind=_data_kind(data))


def _data_kind(data: Any) -> str:
    return str(data.attrs.get("data_kind", "unknown")) if isinstance(data, xr.Dataset) else "unknown"


class _Settled(Exception):
    """Raised inside the mode search once it stops gaining."""


#: The mode search stops when its best log posterior gained less than this over the last SETTLE_EVALS x (number
#: of sampled numbers) evaluations: a start needs to be well inside the posterior's bulk (whose log density sits
#: some ndim / 2 below the mode's), not at machine precision.
SETTLE_GAIN = 0.1
SETTLE_EVALS = 25


def _mode(post: _LogPosterior, x0: np.ndarray) -> np.ndarray:
    """A point near the posterior's mode, from ``x0`` (Nelder-Mead, stopped once it settles; see SETTLE_GAIN).

    The point only starts the sampler: the walkers are then spread by the Hessian there and burnt in.
    """
    from scipy.optimize import minimize

    x = np.asarray(x0, dtype=float)
    if not math.isfinite(post(x)):
        raise FitError("the calibration cannot start: the point fit has zero posterior density (a parameter on "
                       "the edge of its physical range, or a degenerate covariance)", option="bounds",
                       hints=[Hint("bounds", None, "wider, or away from the edge of the physical range")])
    window = SETTLE_EVALS * len(x)
    best: list[tuple[float, np.ndarray]] = []  # the best (value, point) after each evaluation

    def neg(z: np.ndarray) -> float:
        v = post(z)
        f = 1e300 if not math.isfinite(v) else -v
        best.append((f, z.copy()) if not best or f < best[-1][0] else best[-1])
        if len(best) > window and best[-1 - window][0] - best[-1][0] < SETTLE_GAIN:
            raise _Settled
        return f

    try:
        minimize(neg, x, method="Nelder-Mead", options={"maxiter": 400 * len(x), "maxfev": 400 * len(x),
                                                         "xatol": 1e-6, "fatol": 1e-6, "adaptive": True})
    except _Settled:
        pass
    return best[-1][1]


def _pool(post: _LogPosterior) -> ThreadMap | None:
    """The threads that share a compiled law's evaluations (its loops release the GIL and are thread-safe); None
    for a law written in Python, which gains nothing from threads and need not be safe in them."""
    return ThreadMap() if isinstance(getattr(post, "law", None), CompiledLaw) else None


def _values(post: _LogPosterior, points: Sequence[np.ndarray]) -> np.ndarray:
    """The log posterior at each point (shared between threads by :func:`_pool`)."""
    pool = _pool(post)
    return np.array(pool.map(post, points) if pool is not None else [post(x) for x in points], dtype=float)


def _laplace(post: _LogPosterior, mode: np.ndarray) -> tuple[np.ndarray, str]:
    """A matrix L with L L^T the covariance of the normal approximation of the posterior at ``mode``, and its kind.

    Central differences of the log posterior: first along each axis with a small step, which gives
    each number's posterior standard deviation, then the full Hessian with steps of one standard
    deviation (accurate for a near-normal posterior; evaluations shared between threads). Where
    the Hessian is not negative definite (a mode on a bound, a flat direction) the diagonal is
    used, and where that fails too, a small ball: the sampler then spreads out on its own.
    """
    n = len(mode)
    widths = np.array([1e-3 * (post.box[f][1] - post.box[f][0]) for f in post.free] + [1e-2] * (n - len(post.free)))
    eye = np.eye(n)
    f0 = post(mode)
    ends = _values(post, [mode + sign * widths[j] * eye[j] for j in range(n) for sign in (1.0, -1.0)]).reshape(n, 2)
    curv = (ends[:, 0] + ends[:, 1] - 2 * f0) / widths ** 2
    if not (math.isfinite(f0) and np.all(np.isfinite(curv)) and np.all(curv < 0)):
        return np.diag(widths), "ball"
    h = 1.0 / np.sqrt(-curv)  # steps of one standard deviation
    pairs = [(j, k) for j in range(n) for k in range(j + 1, n)]
    axes = [mode + sign * h[j] * eye[j] for j in range(n) for sign in (1.0, -1.0)]
    corners = [mode + a * h[j] * eye[j] + b * h[k] * eye[k] for j, k in pairs
               for a, b in ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))]
    values = _values(post, axes + corners)
    ax, co = values[:2 * n].reshape(n, 2), values[2 * n:].reshape(-1, 4)
    with np.errstate(invalid="ignore"):  # a point outside the prior (-inf) leaves a NaN: the fallback below
        hess = np.diag((ax[:, 0] + ax[:, 1] - 2 * f0) / h ** 2)
        for (j, k), (pp, pm, mp, mm) in zip(pairs, co, strict=True):
            hess[j, k] = hess[k, j] = (pp - pm - mp + mm) / (4 * h[j] * h[k])
    if np.all(np.isfinite(hess)):
        try:
            return np.linalg.cholesky(np.linalg.inv(-hess)), "laplace"
        except np.linalg.LinAlgError:
            pass
    return np.diag(h), "diagonal"


def _start(post: _LogPosterior, mode: np.ndarray, spread: np.ndarray, walkers: int,
           rng: np.random.Generator) -> np.ndarray:
    """Walkers drawn from the normal approximation at the mode, each redrawn until inside the prior."""
    start = mode + rng.standard_normal((walkers, len(mode))) @ spread.T
    for w in range(walkers):
        shrink = 1.0
        while not math.isfinite(post.log_prior(start[w])):
            shrink *= 0.5
            if shrink < 1e-6:
                start[w] = mode
                break
            start[w] = mode + shrink * (spread @ rng.standard_normal(len(mode)))
    return start


#: Steps between convergence checks of a run with ``steps=None``.
BLOCK = 250
#: Burn-in, in autocorrelation times (at most the first third of the run).
BURN_TAUS = 5


def _run_chain(task: tuple) -> dict[str, Any]:
    """One emcee ensemble (module level, so that executors can pickle it): its kept chain and diagnostics."""
    import emcee

    post, start, steps, max_steps, tau_multiple, burn_taus, seed, progress = task
    walkers, ndim = start.shape
    moves = [(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)]
    sampler = emcee.EnsembleSampler(walkers, ndim, post, moves=moves, pool=_pool(post))
    sampler.random_state = np.random.RandomState(seed).get_state()
    if steps is not None:
        sampler.run_mcmc(start, steps, progress=progress)
        total = steps
        burn = _burn(sampler.get_chain(), tau_multiple, burn_taus)[0]
    else:
        state, total, block = start, 0, BLOCK
        while total < max_steps:
            n = min(block, max_steps - total)
            state = sampler.run_mcmc(state, n, progress=progress)
            total += n
            burn, done = _burn(sampler.get_chain(), tau_multiple, burn_taus)
            if done:
                break
    return {"chain": sampler.get_chain(discard=burn), "acceptance": sampler.acceptance_fraction.copy(),
            "steps": total, "burn": burn}


def _burn(chain: np.ndarray, tau_multiple: float, burn_taus: float) -> tuple[int, bool]:
    """Steps to discard from a (steps, walkers, ndim) chain, and whether the rest passes the convergence test.

    The burn-in is ``burn_taus`` autocorrelation times (estimated after the first third), at most
    the first third: walkers started from the normal approximation of the posterior need a few
    autocorrelation times to forget it, not a fixed share of the run.
    """
    total = len(chain)
    tau = float(np.max(_autocorr(chain[total // 3:])))
    burn = min(total // 3, math.ceil(burn_taus * tau)) if math.isfinite(burn_taus * tau) else total // 3
    kept = chain[burn:]
    tau_kept = float(np.max(_autocorr(kept)))
    return burn, bool(len(kept) >= tau_multiple * tau_kept and np.max(_split_rhat(kept)) < 1.05)


def _autocorr(chain: np.ndarray) -> np.ndarray:
    """Integrated autocorrelation time of each parameter (emcee's estimator, without its length check).

    A walker that has not moved in the chain has no variance, and the estimator gives NaN: such a
    chain has not mixed at all, so its time is taken as infinite (never converged, never thinned by).
    """
    import emcee

    with np.errstate(divide="ignore", invalid="ignore"):
        tau = np.asarray(emcee.autocorr.integrated_time(chain, tol=0, quiet=True), dtype=float)
    return np.where(np.isnan(tau), np.inf, tau)


def _split_rhat(chain: np.ndarray) -> np.ndarray:
    """Split R-hat of each parameter over the walkers of a (steps, walkers, ndim) chain (BDA3, eq. 11.4)."""
    n = chain.shape[0] // 2
    if n < 2:
        return np.full(chain.shape[2], np.inf)
    halves = np.concatenate([chain[:n], chain[n:2 * n]], axis=1)  # (n, 2 walkers, ndim)
    means = halves.mean(axis=0)
    within = halves.var(axis=0, ddof=1).mean(axis=0)
    between = n * means.var(axis=0, ddof=1)
    var = (n - 1) / n * within + between / n
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sqrt(np.where(within > 0, var / within, np.inf))


def _diagnostics(kept: np.ndarray, runs: list[dict[str, Any]], tau_multiple: float) -> dict[str, Any]:
    tau = _autocorr(kept)
    rhat = _split_rhat(kept)
    length = kept.shape[0]
    long_enough = bool(length >= tau_multiple * np.max(tau))
    mixed = bool(np.max(rhat) < 1.05)
    acceptance = float(np.mean(np.concatenate([r["acceptance"] for r in runs])))
    reasons = []
    if not long_enough:
        reasons.append(f"the chain after burn-in is {length / np.max(tau):.0f} autocorrelation times long, "
                       f"fewer than {tau_multiple:g}")
    if not mixed:
        reasons.append(f"split R-hat {np.max(rhat):.3f} >= 1.05")
    if not 0.1 <= acceptance <= 0.9:
        reasons.append(f"acceptance fraction {acceptance:.2f} outside [0.1, 0.9]")
    return {"converged": not reasons, "reason": "; ".join(reasons) or "converged",
            "steps": int(max(r["steps"] for r in runs)), "burn": int(max(r["burn"] for r in runs)),
            "chain_steps": [int(r["steps"]) for r in runs], "chain_burn": [int(r["burn"]) for r in runs],
            "walkers": int(kept.shape[1]), "chains": len(runs), "acceptance": acceptance,
            "autocorr": tau.tolist(), "rhat": rhat.tolist(), "kept_steps": int(length)}


def _span(d: Mapping[str, Any], key: str) -> str:
    """A diagnostic per chain as one number, or "low-high" when the chains stopped apart."""
    values = d.get(f"chain_{key}") or [d[key]]  # a posterior saved before the per-chain lists
    return f"{min(values)}" if min(values) == max(values) else f"{min(values)}-{max(values)}"


def _thin(kept: np.ndarray, diagnostics: dict[str, Any], columns: list[str], n_free: int,
          most: int = 4000) -> pd.DataFrame:
    """Samples after burn-in, thinned by half the shortest autocorrelation time and to at most ``most`` rows."""
    finite = [t for t in diagnostics["autocorr"] if math.isfinite(t)]
    thin = max(1, int(0.5 * min(finite))) if finite else 1
    flat = kept[::thin].reshape(-1, kept.shape[2])
    if len(flat) > most:
        flat = flat[np.linspace(0, len(flat) - 1, most).round().astype(int)]
    diagnostics["thin"] = thin
    frame = pd.DataFrame(flat, columns=columns)
    logs = columns[n_free:]
    frame[logs] = np.exp(frame[logs])  # stored as values, not logarithms
    return frame


# ------------------------------------------------------------------------------ the posterior
@dataclass
class Posterior:
    """Result of :func:`calibrate`: posterior samples of a hierarchical calibration, and predictions from them.

    Attributes
    ----------
    law
        The law fitted to the data by the point fit (its options and held values are the posterior's).
    free
        Parameters with a sampled population value.
    vary
        Parameters that vary from bounce to bounce.
    transforms
        Per varying parameter, the space where its variation is normal.
    samples
        Posterior samples after burn-in (thinned): the population values (medians for the varying
        parameters) by parameter name, ``scale_<name>`` (spot-to-spot standard deviation in the
        transformed space), and ``discrepancy_<component>`` or ``noise_<component>`` (scaled units).
    diagnostics
        ``converged``, ``reason``, ``steps`` and ``burn`` (the most over the chains; per chain in
        ``chain_steps`` and ``chain_burn``), ``kept_steps`` (per walker after burn-in: the chains'
        common tail), ``walkers`` (all chains), ``chains``, ``acceptance`` (mean fraction), ``autocorr``
        (infinite for a column in which some walker never moved) and ``rhat`` (per column of
        ``samples``), ``thin``, ``start`` (how the walkers started: ``"laplace"``, ``"diagonal"`` or
        ``"ball"``; see the module documentation), ``elapsed_s``.
    measurement
        Typical measurement standard deviations of the calibration data (medians per component of
        ``landing_sd`` and ``liftoff_sd``), used by :meth:`predict` for new landings; None without intervals.
    residual
        ``"discrepancy"`` (the data had prediction intervals) or ``"noise"`` (measurement and discrepancy together).
    with_tau
        Whether a discrepancy (or noise) term was sampled.
    n_bounces
        Bounces of the calibration data.
    mode
        The point near the posterior's mode that the sampler started from: where the mode search
        settled, not the exact mode (logarithms for scales and discrepancies).
    notes
        Anything a reader should know (synthetic data, no convergence ...).
    data_kind
        The calibration data's ``data_kind`` attribute (``"synthetic surrogate"`` marks figures).
    """

    law: BounceModel
    free: list[str]
    vary: list[str]
    transforms: dict[str, _Transform]
    samples: pd.DataFrame
    diagnostics: dict[str, Any]
    measurement: dict[str, Any]
    residual: str
    with_tau: bool
    n_bounces: int
    mode: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    data_kind: str = "unknown"

    # ------------------------------------------------------------------ summaries
    @property
    def converged(self) -> bool:
        """Whether the sampler met the convergence criteria."""
        return bool(self.diagnostics.get("converged", False))

    def summary(self, level: float = 0.95) -> pd.DataFrame:
        """Per sampled number: median, mean, sd, equal-tailed interval at ``level``, autocorrelation time, R-hat."""
        level = check_fraction(level, "level")
        lo, hi = 100 * (1 - level) / 2, 100 * (1 + level) / 2
        table = pd.DataFrame({
            "median": self.samples.median(), "mean": self.samples.mean(), "sd": self.samples.std(ddof=1),
            "low": np.percentile(self.samples, lo, axis=0), "high": np.percentile(self.samples, hi, axis=0),
            "autocorr": self.diagnostics["autocorr"], "rhat": self.diagnostics["rhat"]})
        table.index.name = "quantity"
        table.attrs["level"] = level
        return table

    @property
    def population(self) -> BounceModel:
        """The law at the posterior medians of the population values."""
        med = self.samples[self.free].median()
        return self.law.replace(**{n: float(med[n]) for n in self.free})

    def report(self) -> str:
        """A readable account: the model, the posterior summary, the diagnostics, the notes."""
        d = self.diagnostics
        lines = [f"[[Calibration]] {law_name(self.law)} on {self.n_bounces} bounces, hierarchical (emcee)",
                 "    varying from bounce to bounce: " + (", ".join(
                     f"{v} ({self.transforms[v].describe()})" for v in self.vary) or "none"),
                 f"    residual term: {self.residual}" + ("" if self.with_tau else " (none fitted)"),
                 f"    sampler: {d['chains']} chain(s) x {d['walkers'] // d['chains']} walkers x {_span(d, 'steps')} "
                 f"steps, burn-in {_span(d, 'burn')}, {d['kept_steps']} kept per walker, acceptance "
                 f"{d['acceptance']:.2f}, {d['elapsed_s']:.1f} s",
                 f"    convergence: {d['reason']} (max autocorrelation time {max(d['autocorr']):.1f} steps, "
                 f"max split R-hat {max(d['rhat']):.3f})",
                 "[[Posterior]] (medians of the population values; scales in the transformed space)"]
        table = self.summary()
        lines.extend("    " + line for line in table.to_string(float_format=lambda v: f"{v:.4g}").splitlines())
        if self.notes:
            lines.append("[[Notes]]")
            lines.extend(f"    - {n}" for n in self.notes)
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()

    def __repr__(self) -> str:
        med = self.samples.median()
        parts = ", ".join(f"{c}={med[c]:.4g}" for c in self.samples.columns)
        return f"Posterior({law_name(self.law)}: {parts}; {'converged' if self.converged else 'NOT converged'})"

    # ------------------------------------------------------------------ prediction
    def predict(self, landing: Any, n: int = 1000, *, measurement_error: bool = False,
                measurement_sd: Any = None, seed: int = 0) -> np.ndarray:
        """Draws of the lift-off for each landing: population and spot-to-spot uncertainty.

        Each draw takes one posterior sample (population values, scales, discrepancy), draws each
        landing's own varying parameters from the population, calls the law (no linearisation)
        and adds the model discrepancy.

        Parameters
        ----------
        landing
            (m, 3) landing states in scaled units.
        n
            Number of draws.
        measurement_error
            Also draw measurement errors: of the landing (fed to the law) and of the lift-off,
            i.e. what a measurement of the bounce would show. (Without prediction intervals in the
            calibration data the fitted noise is measurement error and is added only here.)
        measurement_sd
            ``(landing_sd, liftoff_sd)``, each broadcastable to (m, 3), in scaled units; default the
            calibration data's typical values (:attr:`measurement`).
        seed
            Seed of the draws.

        Returns
        -------
        numpy.ndarray
            Shape (n, m, 3).
        """
        p, _ = as_states(landing, "landing", landing=True)
        p = np.ascontiguousarray(p.reshape(-1, 3), dtype=np.float64)
        n = check_count(n, "n", 1)
        seed = check_seed(seed)
        m = len(p)
        rng = np.random.default_rng(seed)
        rows = self.samples.to_numpy()[rng.integers(0, len(self.samples), n)]
        col = {c: i for i, c in enumerate(self.samples.columns)}
        specs = [s.name for s in self.law.parameter_specs]
        base = ParameterVector(self.law).of(self.law)
        theta = np.broadcast_to(base, (n, m, len(base))).copy()
        for name in self.free:
            k = specs.index(name)
            if name in self.transforms:
                tr = self.transforms[name]
                z = tr.forward(rows[:, col[name]])[:, None] + rows[:, col[f"scale_{name}"]][:, None] * \
                    rng.standard_normal((n, m))
                theta[:, :, k] = tr.inverse(z)
            else:
                theta[:, :, k] = rows[:, col[name]][:, None]
        land = np.broadcast_to(p, (n, m, 3)).copy()
        land_sd, lift_sd = self._measurement(measurement_sd, m) if measurement_error else (None, None)
        if land_sd is not None:
            land += land_sd * rng.standard_normal((n, m, 3))
            land[:, :, 1] = np.minimum(land[:, :, 1], -1e-9)  # a measured landing error never turns it upward
        out = _predict_rows(self.law, land.reshape(-1, 3), theta.reshape(-1, len(base))).reshape(n, m, 3)
        if self.with_tau and (self.residual == "discrepancy" or measurement_error):
            tau = rows[:, [col[f"{self.residual}_{c}"] for c in COMPONENTS]]
            out += tau[:, None, :] * rng.standard_normal((n, m, 3))
        if lift_sd is not None:
            out += lift_sd * rng.standard_normal((n, m, 3))
        return out

    def _measurement(self, measurement_sd: Any, m: int) -> tuple[np.ndarray | None, np.ndarray | None]:
        if measurement_sd is None:
            land, lift = self.measurement.get("landing_sd"), self.measurement.get("liftoff_sd")
        else:
            try:
                land, lift = measurement_sd
            except (TypeError, ValueError):
                raise DataError("measurement_sd must be a pair (landing_sd, liftoff_sd) of arrays broadcastable to "
                                f"({m}, 3)", option="measurement_sd") from None
        out = []
        for name, v in (("landing_sd", land), ("liftoff_sd", lift)):
            if v is None:
                out.append(None)
                continue
            try:
                arr = np.broadcast_to(np.asarray(v, dtype=float), (m, 3))
            except ValueError:
                raise DataError(f"{name} must be broadcastable to ({m}, 3); got shape {np.shape(v)}",
                                option="measurement_sd") from None
            if not np.isfinite(arr).all() or (arr < 0).any():
                raise DataError(f"{name} must hold finite standard deviations >= 0", option="measurement_sd")
            out.append(arr)
        return out[0], out[1]

    def interval(self, landing: Any, level: float = 0.95, *, n: int = 2000, measurement_error: bool = False,
                 measurement_sd: Any = None, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Equal-tailed predictive interval of the lift-off for each landing, from :meth:`predict`'s draws.

        Returns
        -------
        lower, upper
            Each of shape (m, 3).
        """
        level = check_fraction(level, "level")
        draws = self.predict(landing, n, measurement_error=measurement_error, measurement_sd=measurement_sd,
                             seed=seed)
        lo, hi = np.quantile(draws, [(1 - level) / 2, (1 + level) / 2], axis=0)
        return lo, hi

    def check(self, data: Any, level: float = 0.95, *, n: int = 2000, seed: int = 0) -> pd.DataFrame:
        """Posterior predictive check: the share of a campaign's bounces inside their predictive intervals.

        Each measured lift-off is compared with the interval at ``level`` for its measured landing,
        with measurement error (each bounce's own, from the data's prediction intervals when it has
        them). Rows: ``all`` and each measured slip/roll class (:func:`bouncelab.classify_slip_roll`);
        columns: ``n``, the share inside for each component, and ``all3`` (inside for all three).
        """
        p0, pf, _ = campaign_arrays(data)
        land_sd, lift_sd = interval_sds(data, len(p0))
        sd = None
        if land_sd is not None or lift_sd is not None:
            sd = (land_sd if land_sd is not None else np.zeros((len(p0), 3)),
                  lift_sd if lift_sd is not None else np.zeros((len(p0), 3)))
        lo, hi = self.interval(p0, level, n=n, measurement_error=True, measurement_sd=sd, seed=seed)
        inside = (pf >= lo) & (pf <= hi)
        classes = np.asarray(SLIP_ROLL_CLASSES)[_slip_codes(p0, pf)]
        rows = {}
        for label, mask in [("all", np.ones(len(p0), bool)), *((c, classes == c) for c in SLIP_ROLL_CLASSES)]:
            if not mask.any():
                continue
            share = inside[mask].mean(axis=0)
            rows[label] = {"n": int(mask.sum()), **dict(zip(COMPONENTS, share, strict=True)),
                           "all3": float(inside[mask].all(axis=1).mean())}
        table = pd.DataFrame.from_dict(rows, orient="index")
        table.index.name = "subset"
        table.attrs["level"] = level
        return table

    # ------------------------------------------------------------------ figures

    # ------------------------------------------------------------------ saving
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description: the law, the model, the samples (column-wise) and the diagnostics."""
        from bouncelab.core import __version__

        return {
            "format": FORMAT, "format_version": FORMAT_VERSION, "bouncelab_version": __version__,
            "law": self.law.to_dict(), "free": list(self.free), "vary": list(self.vary),
            "transforms": {k: t.to_dict() for k, t in self.transforms.items()},
            "residual": self.residual, "with_tau": self.with_tau, "n_bounces": self.n_bounces,
            "measurement": self.measurement, "mode": self.mode,
            "diagnostics": {k: _json_number(v) for k, v in self.diagnostics.items()},
            "samples": {c: self.samples[c].tolist() for c in self.samples.columns},
            "notes": list(self.notes), "data_kind": self.data_kind,
        }

    def to_json(self, path: str | Path | None = None) -> str:
        """JSON text of :meth:`to_dict`; also written to ``path`` if given (atomically)."""
        text = json.dumps(self.to_dict(), indent=1)
        if path is not None:
            from bouncelab.core.atomic import write_output

            write_output(path, text + "\n", "the posterior")
        return text

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Posterior:
        """Rebuild a posterior from :meth:`to_dict` output.

        Raises
        ------
        ParameterError
            Not a saved posterior, or one whose parts do not fit together (naming the part).
        """
        if not isinstance(d, Mapping) or d.get("format") != FORMAT:
            raise ParameterError(f"not a saved bouncelab posterior (no 'format': {FORMAT!r})", parameter="format",
                                 value=d.get("format") if isinstance(d, Mapping) else None)
        if d.get("format_version") != FORMAT_VERSION:
            raise ParameterError(f"saved posterior has format_version {d.get('format_version')!r}; this bouncelab "
                                 f"reads {FORMAT_VERSION}", parameter="format_version", value=d.get("format_version"))
        try:
            law = law_from_dict(d["law"])
            free, vary = [str(x) for x in d["free"]], [str(x) for x in d["vary"]]
            transforms = {k: _Transform.from_dict(v) for k, v in d["transforms"].items()}
            samples = pd.DataFrame({k: np.asarray(v, dtype=float) for k, v in d["samples"].items()})
            # lists of numbers, with "inf" for an infinite autocorrelation time
            diagnostics = {k: ([float(x) if isinstance(x, str) else x for x in v] if isinstance(v, list) else v)
                           for k, v in d["diagnostics"].items()}
            out = cls(law=law, free=free, vary=vary, transforms=transforms, samples=samples,
                      diagnostics=diagnostics, measurement=dict(d["measurement"]),
                      residual=str(d["residual"]), with_tau=bool(d["with_tau"]), n_bounces=int(d["n_bounces"]),
                      mode=dict(d.get("mode", {})), notes=list(d.get("notes", [])),
                      data_kind=str(d.get("data_kind", "unknown")))
        except ParameterError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise ParameterError(f"saved posterior is incomplete or malformed ({type(exc).__name__}: {exc})",
                                 parameter=str(exc.args[0]) if isinstance(exc, KeyError) else None) from None
        names = [s.name for s in law.parameter_specs]
        missing = [c for c in [*free, *(f"scale_{v}" for v in vary)] if c not in samples.columns]
        if missing or any(f not in names for f in free) or any(v not in free or v not in transforms for v in vary):
            raise ParameterError(f"saved posterior's samples, parameters and transforms do not fit together "
                                 f"(missing columns {missing})", law=law_name(law), parameter="samples")
        if len(samples) == 0 or not np.isfinite(samples.to_numpy()).all():
            raise ParameterError("saved posterior has no samples, or non-finite ones", parameter="samples")
        return out

    def _repr_html_(self) -> str:
        from bouncelab.fitting._display import posterior_html  # the notebook view

        return posterior_html(self)


def load_posterior(path: str | Path) -> Posterior:
    """Read a posterior written by :meth:`Posterior.to_json`.

    Raises
    ------
    ParameterError
        The file is not JSON or not a saved posterior.
    """
    try:
        d = json.loads(Path(path).read_text())
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        raise ParameterError(f"{path}: not a JSON posterior ({type(exc).__name__}: {exc})") from None
    return Posterior.from_dict(d)


def _predict_rows(law: BounceModel, landing: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The law on each landing with its own parameter numbers (:func:`bouncelab.laws.predict_per_bounce`)."""
    from bouncelab.laws.varying import predict_per_bounce

    return predict_per_bounce(law, landing, theta)
