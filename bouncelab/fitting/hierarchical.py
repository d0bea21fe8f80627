r"""``bouncelab.calibrate``: hierarchical calibration of a law, with spot-to-spot variation and predictive spread.

A fitted law predicts one lift-off per landing. Real turf varies from spot to spot, the
measurements have errors, and the law itself misses. :func:`calibrate` separates the three
with a hierarchical model and samples its posterior with ``emcee``; the
:class:`Posterior` it returns draws lift-offs of new bounces as they would be measured
(``predict``), gives predictive intervals (``interval``) and checks them against a campaign
(``check``, by the same code).

The model
---------
For bounce :math:`i` of launcher setting :math:`g` with measured landing :math:`p_{0,i}` and
measured lift-off :math:`y_i`:

* each parameter :math:`\theta_j` named in ``vary`` takes its own value at the bounce,
  :math:`\theta_{ij} = T_j^{-1}(m_j + \sigma_j v_{gj} + s_j u_{ij})` with :math:`v_{gj}` and
  :math:`u_{ij}` independent standard normals: :math:`v_{gj}` is shared by every repeat of
  setting :math:`g` (the repeats of a setting land on one spot) and :math:`u_{ij}` is the
  bounce's own. :math:`T_j` is the logit of :math:`(\theta - a)/(b - a)` for a parameter whose
  physical range :math:`[a, b]` is bounded on both sides (logit-normal), :math:`\log(\theta - a)`
  when only the lower side is (log-normal; :math:`\log(b - \theta)` when only the upper side
  is) and the identity otherwise (normal). :math:`T_j^{-1}(m_j)` is the *population median*,
  :math:`\sigma_j` the *setting-to-setting scale* (``setting_scale_<name>``) and :math:`s_j` the
  *bounce-to-bounce scale* (``scale_<name>``), standard deviations in the transformed space (for
  a log-normal parameter, about the relative spread). A bounce on a new spot varies by
  :math:`\sqrt{\sigma_j^2 + s_j^2}`. Data without launcher settings, or whose settings have one
  bounce each, cannot tell the two levels apart: the model then has the bounce level only (every
  bounce on its own spot), as has ``by="bounce"``. The other free parameters have one
  population value;
* the law may miss: the true lift-off is the law's prediction plus a *model discrepancy*
  :math:`\epsilon_i \sim N(0, \mathrm{diag}(\tau^2))` with one :math:`\tau_c` per component,
  independent from bounce to bounce;
* the landing and the lift-off are measured with independent normal errors of the standard
  deviations their 95 % prediction intervals state (``landing_pi / 1.96``,
  ``liftoff_pi / 1.96``). Without landing intervals the landing's standard deviations are fitted
  (``landing_noise_<component>``, one per component; ``landing_noise=``): pushed through the law, the
  landing's error moves a rolling bounce's lift-off otherwise than a slipping one's. Without lift-off
  intervals the measurement error of the lift-off cannot be told apart from the discrepancy: then
  :math:`\tau` is fitted as one *noise* term holding both.

The approximation
-----------------
The per-bounce and per-setting parameters are marginalised, not sampled. The lift-offs of one
setting are given a joint normal distribution whose mean and covariance approximate the model's,

.. math::

    y_g \sim N\bigl(\mu_g,\; D_g + W_g W_g^\top\bigr),\qquad
    D_g = \mathrm{blockdiag}_i\bigl(\Sigma_{u,i} + G_i \Sigma_{0,i} G_i^\top + \Sigma_{F,i}
    + \mathrm{diag}(\tau^2)\bigr),

where :math:`\mu_i` and the spread of the prediction over the varying parameters come from one of
three rules (``approximation=``), computed with the total scale
:math:`t_j = \sqrt{\sigma_j^2 + s_j^2}`; the spread is split into the part a setting's repeats
share (:math:`W_g`, one column per direction of :math:`v_g`) and each bounce's own
(:math:`\Sigma_{u,i}`): of the order-:math:`k` Hermite part of each direction the fraction
:math:`\rho_j^k` is shared, :math:`\rho_j = \sigma_j / t_j` (Mehler's formula: the order-:math:`k`
parts of two repeats correlate as :math:`\rho_j^{2k}`; exact for a law polynomial in the
transformed parameter). :math:`G_i` is the derivative of
the prediction with respect to the landing (forward differences at the population values where
the sampler starts, held fixed: it changes little over the posterior of the population values
and costs three law calls per bounce), :math:`\Sigma_{0,i}`, :math:`\Sigma_{F,i}` the
measurement covariances. The likelihood of a setting is evaluated with the Woodbury identity (one
small matrix per setting); with one level the settings are single bounces.

``"hermite"`` (default)
    Gauss-Hermite quadrature along each varying parameter's axis: the law at the population
    medians and at ``nodes - 1`` nodes :math:`m + t_j z_k e_j` per axis (``nodes=None``: the
    fewest of 3, 5 and 7 that give the posterior's shape about the mode as 7 do), whose Hermite
    coefficients give the mean, the spread and its split between the levels. The axes' parts are
    added (their interaction is left out).
``"unscented"``
    The unscented transform: the law at the population medians and at :math:`2V` sigma points
    :math:`m \pm \sqrt{V + \kappa}\, t_j e_j` in the transformed space (:math:`V` varying
    parameters, :math:`\kappa = \max(0, 3 - V)`), weighted to match the normal's moments. It
    carries the shift of the mean (a log-normal parameter's mean is not its median) and spreads
    across kinks of the law (slip to roll) that a derivative cannot see.
``"linear"``
    Linearisation around the medians: :math:`\mu_i = f(p_{0,i}, \bar\theta)` and the spread
    :math:`J_i T^2 J_i^\top` with :math:`J_i` the derivative of the prediction with respect to the
    transformed varying parameters (forward differences) and :math:`T = \mathrm{diag}(t)`.
    Cheaper by :math:`V` law calls per bounce, but biased where the law is curved or kinked on the
    scale of the spread: on the 15-bounce case of tests/test_calibrate.py (Rigid, ``r`` varying,
    both regimes) it puts the population median of ``r`` 2.6 posterior standard deviations from
    the brute-force answer, the unscented transform within a tenth of one.

Each evaluation of the log posterior, for all the walkers it is asked about at once, is one
law call on all their points and bounces (:math:`1 + (q - 1)V` rows per bounce and walker for
:math:`q` Hermite nodes, :math:`2V + 1` unscented, :math:`V + 1` linear), its rows shared between the
threads of :func:`bouncelab.laws.set_num_threads` for a compiled law (every built-in law); a law
written in Python is called once per walker and point, on one thread. All three are normal
approximations of a distribution that need not be normal; the tests compare them with a
brute-force integration over the per-bounce parameters, and the setting level with one over each
setting's draw. Where a setting's draw moves its repeats across a kink of the law (Rigid's slip
to roll: for some of the setting's draws they slip, for others they roll), the joint normal of
the repeats is not their distribution: on the 100-setting campaign of
``benchmarks/bench_assess.py --coverage`` (seed 3), at the true process, the log likelihood is 137
below the brute-force integral over the settings' draws (21 nodes: 118), nearly all of it on the 84
settings that straddle the kink, and the population median of ``mu`` comes out 8-9 % low (the
brute force's maximum: 3 % low). So where it can, :func:`calibrate` does not use the joint normal for the
setting level (``setting_integral="auto"``): where every free parameter varies, the law is compiled and
neither ``approximation`` nor ``nodes`` is given, each setting's likelihood is the integral over its draw,
estimated by importance sampling
(:mod:`bouncelab.fitting.setting_integral`: within 0.1 of the brute force per setting on those settings), with
each bounce's own variation linearised at the draw (exact when the bounce-to-bounce scale is zero). Elsewhere
(some free parameter held the same for every bounce, a law written in Python) the joint normal remains, and
``posterior.diagnostics["setting_integral"]`` says which was used.
:meth:`Posterior.predict` does not approximate: it draws per-bounce parameters and calls the law.

Priors
------
Population values: uniform over the law's search box (``bounds=`` overrides it). Scales
:math:`\sigma_j, s_j`: half-normal with standard deviation 1 (in the transformed space).
Discrepancy (or noise) :math:`\tau_c`: half-normal with the standard deviation of the
component's lift-offs in the data. The scales and discrepancies are sampled as they are (not as logarithms:
one the data cannot tell from zero has a posterior with a long exponential tail in the logarithm, which no move
of the sampler crosses quickly; on its own scale it is a bounded, smooth density).

Sampling and convergence
------------------------
``emcee``'s ensemble sampler, its walkers evaluated together (``vectorize=True``), with three
moves: differential evolution (40 % of the steps), its snooker variant (10 %) and an
independence proposal (50 %): a multivariate t (4 degrees of freedom) about the normal
approximation of the posterior, from the Hessian at the start, then after every block of steps
from the mean and covariance of the second half of the chain so far. Every move leaves the
posterior invariant, whatever its proposal; a good proposal makes successive samples nearly
independent. The walkers start from the normal approximation of the posterior at its mode: the
mode found by L-BFGS-B (batched central differences; Nelder-Mead where that fails) from a point fit, the
covariance from a finite-difference Hessian there
(the diagonal, or a small ball, where the Hessian is not negative definite; no independence move
then until the first block has run). The sampler runs in blocks of :data:`BLOCK` steps; with
``steps=None`` until the chain after burn-in (five autocorrelation times, at most the first
third; the first third after a small-ball start) is at least ``tau_multiple`` (50) integrated
autocorrelation times long and the split R-hat across walkers is below 1.05, or ``max_steps``
is reached, in which case a :class:`ConvergenceWarning` is issued. The samples do not depend on
the number of threads. ``chains`` independent ensembles can run on an ``executor``; the
diagnostics then pool every walker of every chain over their common length.
"""

from __future__ import annotations

import copy
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

from bouncelab.core._parallel import num_threads, run_rows
from bouncelab.core.errors import BouncelabWarning, Code, DataError, FitError, Hint, ParameterError
from bouncelab.core.slip_roll import SLIP_ROLL_CLASSES, _slip_codes
from bouncelab.core.units import COMPONENTS
from bouncelab.core.validation import as_states
from bouncelab.data.campaign import interval_sds, synthetic_warning
from bouncelab.data.inputs import campaign_arrays
from bouncelab.fitting.fitter import check_count, check_fraction, check_seed, fit, law_instance, refuse_sample_weight
from bouncelab.fitting.problem import resolve_fixed
from bouncelab.fitting.setting_integral import SettingIntegral
from bouncelab.fitting.tasks import map_tasks, resolve_executor
from bouncelab.fitting.vector import ParameterVector
from bouncelab.laws import law_from_dict, law_name
from bouncelab.laws.base import BounceModel
from bouncelab.laws.compiled import CompiledLaw

__all__ = ["ConvergenceWarning", "Posterior", "calibrate", "load_posterior"]


#: How :func:`calibrate` marginalises the per-bounce parameters (see the module documentation).
APPROXIMATIONS = ("hermite", "linear", "unscented")
#: How :func:`calibrate` integrates the setting level over a setting's draw.
SETTING_INTEGRALS = ("auto", "importance", "normal")

#: The levels of the population model: launcher setting (a spot shared by its repeats) and bounce.
LEVELS = ("setting", "bounce")

#: A batched law call is shared between threads when its rows are expected to take at least this long (seconds).
PARALLEL_SECONDS = 0.02

#: Format tag of a saved posterior (version 1: one level, read as the bounce level).
FORMAT = "bouncelab.Posterior"
FORMAT_VERSION = 2

#: Most draws :meth:`Posterior.predict` returns (``n`` times the landings) and :meth:`Posterior.interval` takes
#: per landing: 10^7 draws of three numbers are 240 MB.
MAX_DRAWS = 10_000_000


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
def _outer6(cols: np.ndarray) -> list[np.ndarray]:
    """The six distinct entries (xx, yy, ww, xy, xw, yw) of the sum over axis -3 of the outer products of the
    (..., K, n, 3) columns: each (..., n)."""
    x, y, z = cols[..., 0], cols[..., 1], cols[..., 2]
    return [(x * x).sum(-2), (y * y).sum(-2), (z * z).sum(-2), (x * y).sum(-2), (x * z).sum(-2), (y * z).sum(-2)]


class _LogPosterior:
    """The approximate log posterior of the population values, scales and discrepancies (picklable).

    The vector it takes: the free parameters' population values (medians for the varying ones),
    then ``sigma`` of each varying parameter (with the setting level), ``s`` of each,
    then ``tau`` of each component (when sampled), then the landing noise of each component (when fitted).
    :meth:`batch` evaluates many vectors in one
    law call; calling the object evaluates one.
    """

    def __init__(self, law: BounceModel, landing: np.ndarray, liftoff: np.ndarray, *, free: Sequence[str],
                 vary: Sequence[str], box: Mapping[str, tuple[float, float]], landing_sd: np.ndarray | None,
                 liftoff_sd: np.ndarray | None, with_tau: bool, tau_prior: np.ndarray, scale_prior: float = 1.0,
                 step: float = 1e-4, approximation: str = "hermite", nodes: int = 7,
                 groups: np.ndarray | None = None, landing_prior: np.ndarray | None = None) -> None:
        if approximation not in APPROXIMATIONS:
            raise FitError(f"approximation must be one of {APPROXIMATIONS}; got {approximation!r}",
                           option="approximation")
        self._rule(approximation, nodes)
        self.law = law
        p0 = np.ascontiguousarray(landing, dtype=np.float64)
        y = np.ascontiguousarray(liftoff, dtype=np.float64)
        n = len(p0)
        # With the setting level the bounces are put in setting order (each setting's rows together): the
        # likelihood is a sum over settings, whatever the order of the data.
        self.levels = LEVELS if groups is not None else ("bounce",)
        if groups is not None:
            codes = pd.factorize(np.asarray(groups))[0]
            order = np.argsort(codes, kind="stable")
            codes = codes[order]
            self._starts = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
        else:
            order = np.arange(n)
            self._starts = None
        self.p0 = np.ascontiguousarray(p0[order])
        self.y = np.ascontiguousarray(y[order])
        landing_sd = None if landing_sd is None else np.asarray(landing_sd, dtype=float)[order]
        liftoff_sd = None if liftoff_sd is None else np.asarray(liftoff_sd, dtype=float)[order]
        self.free = list(free)
        self.vary = list(vary)
        names = [s.name for s in law.parameter_specs]
        self._vec = ParameterVector(law)
        self.theta0 = self._vec.of(law)
        self.index = {n_: names.index(n_) for n_ in self.free}
        self._free_idx = np.array([self.index[f] for f in self.free], dtype=int)
        specs = {s.name: s for s in law.parameter_specs}
        self.transforms = {n_: _Transform.of(*(float(v[0]) for v in specs[n_].physical_arrays())) for n_ in self.vary}
        self.box = {n_: (float(box[n_][0]), float(box[n_][1])) for n_ in self.free}
        self.landing_sd = None if landing_sd is None or not np.any(landing_sd > 0) else landing_sd
        self.liftoff_var = None if liftoff_sd is None else liftoff_sd ** 2
        self.with_tau = with_tau
        self.tau_prior = np.asarray(tau_prior, dtype=float)
        # the landing's measurement error fitted (one sd per component) where the data do not state it
        if landing_prior is not None and self.landing_sd is not None:
            raise FitError("a landing noise is fitted only where the data have no landing intervals",
                           option="landing_noise")
        self.landing_prior = None if landing_prior is None else [float(v) for v in landing_prior]
        self.scale_prior = float(scale_prior)
        self.step = float(step)
        self.n = n
        # forward steps of the landing: small against each component, and never across ydot = 0
        self.h_land = 1e-6 * np.maximum(np.abs(self.p0), 1.0)
        self.jitter = 1e-10 * (1.0 + np.mean(self.y ** 2, axis=0))
        self._bounds = [self.box[f] for f in self.free]
        varying = [(j, self.transforms[f]) for j, f in enumerate(self.free) if f in self.transforms]
        self._open_lo = [(j, t.a) for j, t in varying if t.kind in ("logit", "log")]
        self._open_hi = [(j, t.b) for j, t in varying if t.kind in ("logit", "neglog")]
        self._tau_prior = self.tau_prior.tolist()
        self._n_scales = len(self.vary) * len(self.levels)
        # prior sds of the numbers after the free parameters: the scales, tau, the landing noise
        self._prior_sds = [self.scale_prior] * self._n_scales + (self._tau_prior if with_tau else []) + \
            (self.landing_prior or [])
        # a compiled law with scalar parameters takes one parameter row per landing: every walker and sigma point
        # in one call, shared between threads; any other law is called once per row of parameter values
        self._rows = isinstance(law, CompiledLaw) and all(s.is_scalar for s in law.parameter_specs)
        self._row_seconds: list[float] = []  # the law's time per row, from calls on this thread
        self._land_cols: np.ndarray | None = None
        self.fix_landing(None)
        #: the setting level by importance sampling over each setting's draw (None: the joint normal)
        self.setting_integral: SettingIntegral | None = None

    def _rule(self, approximation: str, nodes: int) -> None:
        """The points along each varying parameter's axis, in units of its total scale (of the step for "linear"),
        and for Hermite quadrature the matrix from the nodes' values to the scaled Hermite coefficients."""
        self.approximation = approximation
        self.nodes = {"hermite": int(nodes), "unscented": 3, "linear": 1}[approximation]
        if approximation == "linear":
            self._offsets, self._centre, self._hermite = np.ones(1), 0, np.empty((0, 0))
            return
        q = self.nodes
        z, wq = np.polynomial.hermite_e.hermegauss(q)
        if approximation == "unscented":  # the unscented transform's points on one axis: +-sqrt(3)
            z, wq = np.array([-math.sqrt(3.0), 0.0, math.sqrt(3.0)]), np.array([1.0, 4.0, 1.0]) / 6.0
        wq = wq / wq.sum()
        self._centre = q // 2
        self._offsets = np.delete(z, self._centre)
        basis = np.array([np.polynomial.hermite_e.hermeval(z, np.eye(q)[k]) / math.sqrt(math.factorial(k))
                          for k in range(q)])
        self._hermite = basis * wq[None, :]

    def with_nodes(self, nodes: int) -> _LogPosterior:
        """The same log posterior with another number of Hermite nodes (a shallow copy: the data are shared)."""
        other = copy.copy(self)
        other._rule("hermite", nodes)
        return other

    # -------------------------------------------------------------- layout
    @property
    def columns(self) -> list[str]:
        noise = "discrepancy" if self.liftoff_var is not None else "noise"
        setting = [f"setting_scale_{v}" for v in self.vary] if "setting" in self.levels else []
        return [*self.free, *setting, *(f"scale_{v}" for v in self.vary),
                *((f"{noise}_{c}" for c in COMPONENTS) if self.with_tau else ()),
                *((f"landing_noise_{c}" for c in COMPONENTS) if self.landing_prior is not None else ())]

    @property
    def ndim(self) -> int:
        return len(self.free) + self._n_scales + (3 if self.with_tau else 0) + \
            (3 if self.landing_prior is not None else 0)

    def landing_noise(self, X: np.ndarray) -> np.ndarray | None:
        """The fitted landing noise of each row of X (w, 3), or None where the data state the landing's error."""
        return None if self.landing_prior is None else X[:, self.ndim - 3:]

    def _theta(self, X: np.ndarray) -> np.ndarray:
        theta = np.repeat(self.theta0[None, :], len(X), axis=0)
        theta[:, self._free_idx] = X[:, :len(self.free)]
        return theta

    def scales_and_tau(self, X: np.ndarray) -> tuple[np.ndarray | None, np.ndarray, np.ndarray]:
        """Per row of X: the setting scales (None without the setting level), the bounce scales and tau (zeros
        when not sampled)."""
        nf, nv = len(self.free), len(self.vary)
        scales = X[:, nf:nf + self._n_scales]
        tau = X[:, nf + self._n_scales:nf + self._n_scales + 3] if self.with_tau else np.zeros((len(X), 3))
        if "setting" in self.levels:
            return scales[:, :nv], scales[:, nv:], tau
        return None, scales, tau

    def _split(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per row of X: the law's numbers, the total scales t, the setting level's share rho^2 of t^2, tau."""
        theta = self._theta(X)
        sigma, s, tau = self.scales_and_tau(X)
        if sigma is not None:
            t = np.hypot(sigma, s)
            with np.errstate(invalid="ignore", divide="ignore"):
                rho2 = np.where(t > 0, (sigma / np.where(t > 0, t, 1.0)) ** 2, 0.0)
        else:
            t, rho2 = s, np.zeros_like(s)
        return theta, t, rho2, tau

    # -------------------------------------------------------------- prior
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
        nf = len(self.free)
        lp = 0.0
        for j, sd in enumerate(self._prior_sds, start=nf):
            # half-normal priors on the scales, tau and the landing noise (zero or more; a thousand prior sds
            # is no value)
            if not 0.0 <= v[j] <= 1e3 * sd:
                return -math.inf
            lp -= 0.5 * (v[j] / sd) ** 2
        return lp

    def zero_piles(self, x: np.ndarray) -> np.ndarray:
        """Which numbers of ``x`` are scales or discrepancies within a tenth of their prior sd of zero."""
        out = np.zeros(len(x), bool)
        out[len(self.free):] = np.asarray(x[len(self.free):]) < 0.1 * np.asarray(self._prior_sds)
        return out

    def pile_widths(self, x: np.ndarray) -> np.ndarray:
        """Spread of walkers over a pile at zero: the value, at least a tenth of the prior sd (others: zero)."""
        out = np.zeros(len(x))
        out[len(self.free):] = np.maximum(np.abs(x[len(self.free):]), 0.1 * np.asarray(self._prior_sds))
        return out

    def widths(self, x: np.ndarray) -> np.ndarray:
        """Small steps of each sampled number about ``x`` (for finite differences): a thousandth of the search box
        of a population value; of a scale or discrepancy a thousandth of its value, at least 1e-5 of its prior sd."""
        rest = [1e-3 * max(abs(float(v)), 1e-2 * sd) for v, sd in zip(x[len(self.free):], self._prior_sds, strict=True)]
        return np.array([1e-3 * (self.box[f][1] - self.box[f][0]) for f in self.free] + rest)

    # -------------------------------------------------------------- the law on many parameter rows
    def _law_rows(self, params: np.ndarray) -> np.ndarray:
        """The law's lift-offs of every bounce for each row of ``params`` (k, numbers): (k, n, 3)."""
        k, n = len(params), self.n
        if not self._rows:  # a law written in Python (or with array parameters): one call per row, one thread
            return np.stack([self._vec.predict(self.law, self.p0, th) for th in params]) if k else \
                np.empty((0, n, 3))
        return self.rows(np.tile(self.p0, (k, 1)), np.repeat(params, n, axis=0)).reshape(k, n, 3)

    def rows(self, landing: np.ndarray, numbers: np.ndarray) -> np.ndarray:
        """The law on each landing (N, 3) with its own row of numbers (N, P): (N, 3); one call of a compiled law,
        its rows shared between threads where they take long enough to pay."""
        if not self._rows:
            return np.stack([self._vec.predict(self.law, p[None, :], th)[0] for p, th in zip(landing, numbers,
                                                                                             strict=True)]) \
                if len(landing) else np.empty((0, 3))
        from bouncelab.laws.varying import predict_per_bounce

        total = len(landing)
        out = np.empty((total, 3))

        def part(start: int, stop: int) -> None:
            out[start:stop] = predict_per_bounce(self.law, landing[start:stop], numbers[start:stop])

        # Threads pay where the law's rows take long (an integrated contact: microseconds a row); for a law of
        # a few tens of nanoseconds a row, handing the parts between threads costs more than the rows. The first
        # calls run on this thread and time the rows (the fastest of three: the first may compile); where the
        # cuts fall never changes a row's result.
        if len(self._row_seconds) < 3 or min(self._row_seconds) * total < PARALLEL_SECONDS:
            start = time.perf_counter()
            part(0, total)
            if len(self._row_seconds) < 3:
                self._row_seconds.append((time.perf_counter() - start) / max(total, 1))
        else:
            run_rows(part, total, min_rows=2, min_part=max(64, -(-total // (2 * num_threads()))))
        return out

    def fix_landing(self, x: np.ndarray | None) -> None:
        """Hold the landing derivative G at the law's numbers of ``x`` (None: the point fit's): keep its columns
        G_c sigma_c for each landing component c (sigma the data's landing error, or 1 where a landing noise is
        fitted: the noise scales them at each evaluation)."""
        if self.landing_sd is None and self.landing_prior is None:
            self._land_cols = None
            return
        theta = self.theta0 if x is None else self._theta(np.asarray(x, dtype=float)[None, :])[0]
        n = self.n
        moved = [self.p0.copy() for _ in range(3)]
        for c in range(3):
            moved[c][:, c] += self.h_land[:, c]
        out = self._vec.predict(self.law, np.ascontiguousarray(np.concatenate([self.p0, *moved])), theta)
        mean = out[:n]
        sd = self.landing_sd if self.landing_sd is not None else np.ones((n, 3))
        self._land_cols = np.stack([(out[(c + 1) * n:(c + 2) * n] - mean) * (sd[:, c] / self.h_land[:, c])[:, None]
                                    for c in range(3)])

    def landing_columns(self) -> np.ndarray | None:
        """The columns (3, n, 3) :meth:`fix_landing` holds (None without a landing error)."""
        return self._land_cols

    def landing_entries(self, X: np.ndarray) -> list[np.ndarray] | None:
        """The six entries (each (n,) when the data state the error, (w, n) when it is fitted) of each bounce's
        landing-error covariance pushed through the law, G Sigma_0 G^T, for each row of X; None without one."""
        if self._land_cols is None:
            return None
        lam = self.landing_noise(X)
        return _outer6(self._land_cols if lam is None else lam[:, :, None, None] * self._land_cols[None])

    # -------------------------------------------------------------- moments and likelihood
    def _moments(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[np.ndarray], np.ndarray | None, np.ndarray]:
        """Per row of X: mean (w, n, 3), whether the row could be evaluated (w,), the six entries of each bounce's
        own covariance (each (w, n)) and the shared columns (w, K, n, 3) of the setting level (None without it)."""
        theta, t, rho2, tau = self._split(X)
        w, nv = len(X), len(self.vary)
        offsets = self._offsets  # the points of each axis, in units of its total scale
        points = np.repeat(theta[:, None, :], 1 + nv * len(offsets), axis=1)
        for j, name in enumerate(self.vary):
            k, tr = self.index[name], self.transforms[name]
            z = tr.forward(theta[:, k])
            for q, off in enumerate(offsets):
                step = off * self.step if self.approximation == "linear" else off * t[:, j]
                points[:, 1 + j * len(offsets) + q, k] = tr.inverse(z + step)
        ok = np.isfinite(points).all(axis=(1, 2)) & np.isfinite(t).all(axis=1) & np.isfinite(tau).all(axis=1)
        F = np.full((w, points.shape[1], self.n, 3), np.nan)
        if ok.any():
            F[ok] = self._law_rows(points[ok].reshape(-1, points.shape[2])).reshape(int(ok.sum()), -1, self.n, 3)
        F0 = F[:, 0]
        mean = F0.copy()
        own_parts, shared_parts = [], []
        rho = np.sqrt(rho2)
        for j in range(nv):
            Fj = F[:, 1 + j * len(offsets):1 + (j + 1) * len(offsets)]  # (w, points, n, 3)
            if self.approximation == "linear":
                cols = (Fj - F0[:, None]) * (t[:, j] / self.step)[:, None, None, None]  # J_j t_j: order 1
                orders = np.ones(1)
            else:  # the axis's values at every node, the centre among them, in Hermite coefficients
                nodes = np.concatenate([Fj[:, :self._centre], F0[:, None], Fj[:, self._centre:]], axis=1)
                coef = np.einsum("kq,wqnc->wknc", self._hermite, nodes)  # (w, q, n, 3): sqrt(k!) a_k
                mean += coef[:, 0] - F0
                cols, orders = coef[:, 1:], np.arange(1.0, len(self._hermite))
            # Mehler: the order-k part of two bounces of one setting correlates as rho^(2k)
            share = rho[:, j, None] ** orders[None, :]  # (w, K)
            own_parts.append(cols * np.sqrt(np.maximum(1.0 - share ** 2, 0.0))[:, :, None, None])
            shared_parts.append(cols * share[:, :, None, None])
        own = np.concatenate(own_parts, axis=1) if own_parts else np.zeros((w, 0, self.n, 3))
        shared = np.concatenate(shared_parts, axis=1) if shared_parts and "setting" in self.levels else None
        cov = _outer6(own)
        diag = tau ** 2 + self.jitter  # (w, 3)
        for c in range(3):
            cov[c] = cov[c] + diag[:, c:c + 1]
            if self.liftoff_var is not None:
                cov[c] = cov[c] + self.liftoff_var[:, c]
        land = self.landing_entries(X)
        if land is not None:
            cov = [a + b for a, b in zip(cov, land, strict=True)]
        return mean, ok, cov, shared, tau

    def log_likelihoods(self, X: np.ndarray) -> np.ndarray:
        """The log likelihood of each row of X (k, ndim); -inf where it cannot be evaluated."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        # scales, discrepancies and noises are standard deviations: a negative one is no model (not its square's)
        negative = (X[:, len(self.free):] < 0).any(axis=1)
        if self.setting_integral is not None:
            return np.where(negative, -math.inf, self.setting_integral.log_likelihoods(self, X))
        mean, ok, cov, shared, _ = self._moments(X)
        r = self.y[None] - mean
        det, quad = _det_quad(cov, r)
        with np.errstate(invalid="ignore", divide="ignore"):
            value = (np.log(np.where(det > 0, det, np.nan)) + quad).sum(axis=1)
        if shared is not None and shared.shape[1]:
            value = value + _woodbury(cov, det, shared, r, self._starts)
        out = -0.5 * (value + 3 * self.n * math.log(2 * math.pi))
        good = ok & np.isfinite(out) & (det > 0).all(axis=1) & ~negative
        return np.where(good, out, -math.inf)

    def log_likelihood(self, x: np.ndarray) -> float:
        return float(self.log_likelihoods(np.asarray(x, dtype=float)[None, :])[0])

    def batch(self, X: np.ndarray) -> np.ndarray:
        """The log posterior of each row of X (k, ndim), in one law call (emcee's ``vectorize=True``)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        out = np.full(len(X), -math.inf)
        lp = np.array([self.log_prior(x) for x in X], dtype=float)
        inside = np.isfinite(lp)
        if inside.any():
            out[inside] = lp[inside] + self.log_likelihoods(X[inside])
        return np.where(np.isfinite(out), out, -math.inf)

    def __call__(self, x: np.ndarray) -> float:
        return float(self.batch(np.asarray(x, dtype=float)[None, :])[0])


def _det_quad(c: Sequence[np.ndarray], r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    x, y, z = r[..., 0], r[..., 1], r[..., 2]
    adj = A * x * x + D * y * y + F * z * z + 2.0 * (B * x * y + C * x * z + E * y * z)
    with np.errstate(divide="ignore", invalid="ignore"):
        return det, adj / det


def _woodbury(c: Sequence[np.ndarray], det: np.ndarray, W: np.ndarray, r: np.ndarray, starts: np.ndarray
              ) -> np.ndarray:
    """What the shared columns add to ``sum(log det + quad)`` of each row: for each setting g (rows
    ``starts[g]:starts[g+1]``) the lift-offs' covariance is D_g + W_g W_g^T, so (Woodbury)
    log det gains log det M_g and the quadratic form loses b_g^T M_g^-1 b_g, with
    M_g = I + sum_i W_i^T D_i^-1 W_i and b_g = sum_i W_i^T D_i^-1 r_i. ``c`` and ``det`` are the entries and
    determinants of the D_i (w, n), W is (w, K, n, 3), r (w, n, 3); returns (w,)."""
    a, d, f, b, cc, e = c
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = [(d * f - e * e) / det, (a * f - cc * cc) / det, (a * d - b * b) / det,  # xx, yy, ww
               (cc * e - b * f) / det, (b * e - cc * d) / det, (b * cc - a * e) / det]  # xy, xw, yw
    ixx, iyy, iww, ixy, ixw, iyw = (v[:, None, :] for v in inv)
    W0, W1, W2 = W[..., 0], W[..., 1], W[..., 2]  # (w, K, n) each
    U0 = ixx * W0 + ixy * W1 + ixw * W2  # D_i^-1 W_i, component by component
    U1 = ixy * W0 + iyy * W1 + iyw * W2
    U2 = ixw * W0 + iyw * W1 + iww * W2
    # sum_i over each setting of W_i^T D_i^-1 W_i (K x K) and W_i^T D_i^-1 r_i (K): elementwise products of whole
    # arrays, then sums over each setting's rows (tiny batched matrix products are slower)
    A = U0[:, :, None, :] * W0[:, None, :, :] + U1[:, :, None, :] * W1[:, None, :, :] + \
        U2[:, :, None, :] * W2[:, None, :, :]  # (w, K, K, n)
    bvec = U0 * r[:, None, :, 0] + U1 * r[:, None, :, 1] + U2 * r[:, None, :, 2]  # (w, K, n)
    M = np.add.reduceat(A, starts, axis=3).transpose(0, 3, 1, 2)  # (w, G, K, K)
    B = np.add.reduceat(bvec, starts, axis=2).transpose(0, 2, 1)  # (w, G, K)
    M = M + np.eye(W.shape[1])
    good = np.isfinite(M).all(axis=(1, 2, 3)) & np.isfinite(B).all(axis=(1, 2))
    M[~good] = np.eye(W.shape[1])  # (its row is refused by the caller: a NaN already sits in its determinants)
    B[~good] = 0.0
    L = np.linalg.cholesky(M)  # M = I + a positive semi-definite matrix: always positive definite
    logdet = 2.0 * np.log(np.diagonal(L, axis1=-2, axis2=-1)).sum(axis=-1)
    sol = np.linalg.solve(M, B[..., None])[..., 0]
    out = (logdet - (B * sol).sum(axis=-1)).sum(axis=1)
    return np.where(good, out, np.nan)


# ------------------------------------------------------------------------------ the function
def calibrate(
    model: Any,
    data: Any,
    vary: Sequence[str] | str,
    *,
    by: str | None = None,
    discrepancy: bool = True,
    landing_noise: bool | None = None,
    approximation: str = "hermite",
    nodes: int | None = None,
    setting_integral: str = "auto",
    walkers: int | None = None,
    steps: int | None = None,
    max_steps: int = 20_000,
    tau_multiple: float = 50.0,
    chains: int = 1,
    seed: int = 0,
    executor: Any = None,
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
        measurement errors; its ``setting`` coordinate the launcher settings, whose repeats share
        a spot) or a ``(landing, liftoff)`` or ``(landing, liftoff, setting)`` tuple.
    vary
        Names of the scalar parameters that vary from spot to spot (a name or a list of names;
        an empty list for none).
    by
        The levels of the variation: ``"setting"`` (a level per launcher setting, whose repeats
        share its draw, beside the bounce-to-bounce level), ``"bounce"`` (every bounce on its own
        spot: one level), or None (the default): ``"setting"`` when the data have launcher settings
        and one of them has two bounces or more, else ``"bounce"``.
    discrepancy
        Fit a model discrepancy (one standard deviation per component). Without lift-off
        prediction intervals in the data a noise term is always fitted, holding measurement error
        and discrepancy alike.
    landing_noise
        Fit the landing's measurement error (one standard deviation per component, pushed through the law by
        its derivative with respect to the landing, like a stated one). None (default): where the data have no
        landing prediction intervals. Its effect on a lift-off differs by regime (a rolling bounce's spin
        follows the landing's speed, a slipping one's its spin), which one residual term per component cannot
        carry. Landing intervals that are all zero state no error: the noise is then fitted. True where the data
        have landing intervals is a FitError.
    approximation
        ``"hermite"`` (default), ``"unscented"`` or ``"linear"``: how the per-bounce and per-setting
        parameters are marginalised (see the module documentation).
    nodes
        Gauss-Hermite nodes per varying parameter of ``approximation="hermite"`` (odd, from 3 to 21;
        the law is called on ``1 + (nodes - 1) V`` points per bounce). None (default): chosen at the
        mode, the fewest of 3, 5 and 7 that give the posterior's shape near the mode as 7 do (see
        :data:`NODES_TOLERANCE`).
    setting_integral
        How the setting level is integrated over a setting's draw: ``"importance"`` (importance sampling,
        :mod:`bouncelab.fitting.setting_integral`: its fixed points need every free parameter to vary and a
        compiled law), ``"normal"`` (the joint normal of the setting's repeats, by ``approximation``; biased where
        a setting's draw moves its repeats across a kink of the law) or ``"auto"`` (default): importance sampling
        where it applies and neither ``approximation`` nor ``nodes`` is given, else the joint normal.
        ``posterior.diagnostics["setting_integral"]`` says which was used.
    walkers
        Walkers of the ensemble (default: two per sampled number plus two, at least 24; even).
    steps
        Steps per walker; None runs until converged or ``max_steps``.
    max_steps
        Most steps per walker with ``steps=None``.
    tau_multiple
        Convergence needs the chain after burn-in to be this many autocorrelation times long.
    chains
        Independent ensembles, each with its own seed (run on ``executor`` when given).
    seed
        Seed of the point fit, the start and the sampler.
    executor
        A :class:`concurrent.futures.Executor` (or anything :func:`~bouncelab.fitting.tasks.map_tasks`
        takes) to run the chains on; the result is the same as serially.
    client
        Deprecated alias of ``executor`` (a :class:`DeprecationWarning`); it will be removed.
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
    ParameterError
        ``vary`` that is not a name or a list of names.
    FitError
        A name in ``vary`` that is not a free scalar parameter of the law, bad counts, a bad ``by``,
        ``sample_weight``, a ``bounds`` outside the physical range, ``landing_noise=True`` beside the data's
        landing intervals, ``setting_integral="importance"`` where it cannot apply (named in the message).
    DataError
        Bad data, or prediction intervals with non-finite values.

    Warns
    -----
    ConvergenceWarning
        The chain did not meet the convergence criteria within ``max_steps``.
    """

    start_time = time.perf_counter()
    vary = _check_vary(vary)
    executor = resolve_executor(executor, client, "calibrate")
    law = law_instance(model)
    refuse_sample_weight(fit_kwargs, "calibrate", "its likelihood treats every bounce alike")
    seed = check_seed(seed)
    chains = check_count(chains, "chains", 1)
    max_steps = check_count(max_steps, "max_steps", 10)
    if steps is not None:
        steps = check_count(steps, "steps", 10)
    if not (isinstance(tau_multiple, int | float) and not isinstance(tau_multiple, bool) and tau_multiple > 0):
        raise FitError(f"tau_multiple must be a positive number; got {tau_multiple!r}", option="tau_multiple")
    if by not in (None, "setting", "bounce"):
        raise FitError(f"by must be 'setting', 'bounce' or None; got {by!r}", option="by")
    if approximation not in APPROXIMATIONS:
        raise FitError(f"approximation must be one of {APPROXIMATIONS}; got {approximation!r}",
                       option="approximation")
    if nodes is not None and (isinstance(nodes, bool) or not isinstance(nodes, int | np.integer) or nodes < 3
                              or nodes % 2 == 0 or nodes > 21):
        raise FitError(f"nodes must be None or an odd whole number from 3 to 21; got {nodes!r}", option="nodes")
    if setting_integral not in SETTING_INTEGRALS:
        raise FitError(f"setting_integral must be one of {SETTING_INTEGRALS}; got {setting_integral!r}",
                       option="setting_integral")
    p0, pf, setting = campaign_arrays(data)
    repeated = setting is not None and pd.Series(setting).value_counts().max() >= 2
    if by == "setting" and not repeated:
        raise FitError("by='setting' needs launcher settings with repeats (a 'setting' coordinate on which two "
                       "bounces or more share a value); " + ("the data have none" if setting is None else
                                                             "every setting of the data has one bounce"),
                       option="by", hints=[Hint("by", "bounce")])
    landing_sd, liftoff_sd = interval_sds(data, len(p0))
    stated = landing_sd is not None and bool(np.any(np.asarray(landing_sd) > 0))
    if landing_noise is not None and not isinstance(landing_noise, bool | np.bool_):
        raise FitError(f"landing_noise must be None, True or False; got {landing_noise!r}", option="landing_noise")
    if landing_noise and stated:
        raise FitError("landing_noise=True: the data state the landing's measurement error (landing intervals); "
                       "it is not fitted as well", option="landing_noise",
                       hints=[Hint("landing_noise", Code("None"), "the data's own landing errors are used")])
    fit_landing = (not stated) if landing_noise is None else bool(landing_noise)
    held = resolve_fixed(law, fit_kwargs.get("fixed"), fit_kwargs.get("free"))
    arrays = [s.name for s in law.parameter_specs if not s.is_scalar]
    if any(name not in held for name in arrays):  # before the point fit, which may take long
        raise FitError(f"calibrate samples scalar parameters only; the array parameter(s) {arrays} must be held",
                       law=law_name(law), option="fixed", hints=[Hint("fixed", arrays)])
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
    two_levels = bool(vary) and by != "bounce" and repeated
    with_tau = discrepancy or liftoff_sd is None
    tau_prior = np.maximum(pf.std(axis=0), 1e-6)
    landing_prior = np.maximum(p0.std(axis=0), 1e-6) if fit_landing else None
    post = _LogPosterior(fitted, p0, pf, free=free, vary=vary, box=point.bounds, landing_sd=landing_sd,
                         liftoff_sd=liftoff_sd, with_tau=with_tau, tau_prior=tau_prior, approximation=approximation,
                         nodes=AUTO_NODES[-1] if nodes is None else int(nodes),
                         groups=setting if two_levels else None, landing_prior=landing_prior)
    # start: the point fit, small scales, the fit's residual spread as discrepancy; then the mode
    resid = pf - fitted._evaluate(p0)
    x0 = np.r_[[getattr(fitted, n) for n in free], np.full(post._n_scales, 0.1),
               np.maximum(0.5 * resid.std(axis=0), 1e-3 * tau_prior) if with_tau else [],
               0.02 * landing_prior if fit_landing else []]
    for j, name in enumerate(free):  # a median on the edge of its transform's range cannot start the search
        if name in post.transforms and not post.transforms[name].inside(x0[j]):
            lo, hi = post.box[name]
            x0[j] = lo + 1e-3 * (hi - lo) if x0[j] <= lo else hi - 1e-3 * (hi - lo)
    mode = _mode(post, x0)
    post.fix_landing(mode)  # the landing derivative at the mode, held while sampling
    importance = _use_importance(setting_integral, post, two_levels, law_name(fitted),
                                 rule_chosen=approximation != "hermite" or nodes is not None)
    if importance:
        # the proposals are placed at the joint normal's mode, the mode is found again with the integral, and the
        # proposals are placed once more there (the sampler then runs on that fixed likelihood)
        for _ in range(2):
            post.setting_integral = SettingIntegral(post, mode, seed=seed)
            mode = _mode(post, mode)
    ndim = post.ndim
    walkers = max(24, 2 * ndim + 2) if walkers is None else check_count(walkers, "walkers", 2 * ndim + 2)
    walkers += walkers % 2
    spread, start_kind = _laplace(post, mode)
    if approximation == "hermite" and nodes is None and post.vary and not importance:
        post = _fewest_nodes(post, mode, spread, np.random.default_rng([seed, 1 << 20]))
    proposal = (mode, spread) if start_kind == "laplace" else None
    tasks = []
    for c in range(chains):
        rng = np.random.default_rng([seed, c])
        start = _start(post, mode, spread, walkers, rng)
        burn_taus = BURN_TAUS if start_kind != "ball" else math.inf  # a start in a small ball needs to spread out
        tasks.append((post, start, steps, max_steps, tau_multiple, burn_taus, int(rng.integers(2**32 - 1)),
                      progress, proposal))
    runs = map_tasks(_run_chain, tasks, executor)
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
        notes.append("the data carry no lift-off prediction intervals: the fitted noise holds measurement error and "
                     "model discrepancy alike, and predictions are of measured lift-offs only")
    if fit_landing:
        notes.append("the landing's measurement error is fitted (landing_noise_<component>)" + (
            "" if landing_noise else ": the data carry no landing prediction intervals (or only zero ones)"))
    if vary and not two_levels:
        notes.append("one level of variation: every bounce on its own spot" + (
            " (by='bounce')" if by == "bounce" else " (the data have no launcher settings with repeats)"))
    if not diagnostics["converged"]:
        warnings.warn(f"calibrate of {law_name(fitted)}: the sampler did not converge within {diagnostics['steps']} "
                      f"steps ({diagnostics['reason']}); run longer (steps=, max_steps=) before trusting the "
                      "posterior", ConvergenceWarning, stacklevel=2)
        notes.append(f"NOT CONVERGED: {diagnostics['reason']}")
    diagnostics["start"] = start_kind
    diagnostics["approximation"] = approximation + (
        f" ({post.nodes} nodes{', chosen at the mode' if nodes is None else ''})" if approximation == "hermite" else "")
    if importance:  # the rule above then marginalises nothing: say what did
        diagnostics["approximation"] = "importance sampling over each setting's draw, each bounce's own variation " \
            "linearised at the draw"
    integral = post.setting_integral
    if not two_levels:
        diagnostics["setting_integral"] = "none (one level)"
    else:
        diagnostics["setting_integral"] = "joint normal" if integral is None else (
            f"importance sampling ({integral.nodes} fixed points per setting, {integral.walker_points} from each "
            f"point's population; effective fixed points at the mode: smallest "
            f"{integral.effective_sizes(post, mode).min():.1f})")
    diagnostics["elapsed_s"] = time.perf_counter() - start_time
    measurement = {
        "landing_sd": None if post.landing_sd is None else np.median(landing_sd, axis=0).tolist(),
        "liftoff_sd": None if liftoff_sd is None else np.median(liftoff_sd, axis=0).tolist(),
    }
    return Posterior(law=fitted, free=free, vary=vary, transforms={v: post.transforms[v] for v in vary},
                     samples=samples, diagnostics=diagnostics, measurement=measurement,
                     residual="discrepancy" if liftoff_sd is not None else "noise", with_tau=with_tau,
                     n_bounces=len(p0), mode=dict(zip(columns, mode.tolist(), strict=True)), notes=notes,
                     data_kind=_data_kind(data), levels=list(post.levels), landing_noise=fit_landing)


def _use_importance(choice: str, post: _LogPosterior, two_levels: bool, name: str, rule_chosen: bool = False
                    ) -> bool:
    """Whether the setting level is integrated by importance sampling: it needs the setting level, every free
    parameter varying (its fixed points hold all the law's numbers) and a compiled law (its rows). With "auto" a
    marginalisation rule the caller chose (``approximation``, ``nodes``) keeps the joint normal it builds;
    "importance" where it cannot apply, or beside such a rule, is a FitError."""
    if choice == "normal":
        return False
    why = None
    if not two_levels:
        why = ("there is no setting level (it needs launcher settings with repeats, varying parameters and "
               "by='setting' or None)")
    elif set(post.free) != set(post.vary):
        why = (f"the free parameters {[f for f in post.free if f not in post.vary]} do not vary (the fixed points "
               "would need the law at every sampled value of them)")
    elif not post._rows:
        why = "the law is not compiled with scalar parameters (its rows would be called one by one)"
    elif rule_chosen:
        why = ("approximation= and nodes= choose the rule of the joint normal, which importance sampling replaces "
               "at the setting level")
    if why is not None and choice == "importance":
        raise FitError(f"setting_integral='importance' cannot be used here: {why}", law=name,
                       option="setting_integral", hints=[Hint("setting_integral", "normal")])
    return why is None


def _check_vary(vary: Any) -> list[str]:
    """``vary`` as a list of names: a name, or a list or tuple of names (ParameterError otherwise)."""
    if isinstance(vary, str):
        return [vary]
    if isinstance(vary, list | tuple) and all(isinstance(v, str) for v in vary):
        return list(vary)
    raise ParameterError(f"vary must be a parameter name or a list of names (an empty list for none); got "
                         f"{vary!r}", parameter="vary", value=vary)


def _data_kind(data: Any) -> str:
    return str(data.attrs.get("data_kind", "unknown")) if isinstance(data, xr.Dataset) else "unknown"


class _Settled(Exception):
    """Raised inside the mode search once it stops gaining."""


#: The mode search stops when its best log posterior gained less than this over the last SETTLE_EVALS x (number
#: of sampled numbers) evaluations: a start needs to be well inside the posterior's bulk (whose log density sits
#: some ndim / 2 below the mode's), not at machine precision.
SETTLE_GAIN = 0.1
SETTLE_EVALS = 25


def _mode(post: Any, x0: np.ndarray) -> np.ndarray:
    """A point near the posterior's mode, from ``x0``.

    With a batched log posterior (:class:`_LogPosterior`): L-BFGS-B within the prior's box (scales and
    discrepancies at zero or more), its gradient by central differences, all ``2 n + 1`` points in one batched
    law call; it stops once ten iterations gain less than :data:`SETTLE_GAIN`. Otherwise, or where that
    fails, Nelder-Mead, stopped once it settles (see SETTLE_GAIN). The point only starts the sampler: the walkers
    are then spread by the Hessian there and burnt in.
    """
    from scipy.optimize import minimize

    x = np.asarray(x0, dtype=float)
    if not math.isfinite(post(x)):
        raise FitError("the calibration cannot start: the point fit has zero posterior density (a parameter on "
                       "the edge of its physical range, or a degenerate covariance)", option="bounds",
                       hints=[Hint("bounds", None, "wider, or away from the edge of the physical range")])
    if hasattr(post, "batch") and hasattr(post, "widths"):
        found = _gradient_mode(post, x)
        if found is not None:
            return found
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


def _gradient_mode(post: _LogPosterior, x0: np.ndarray) -> np.ndarray | None:
    """L-BFGS-B on the batched log posterior (see :func:`_mode`); None if it found no finite point better than x0."""
    from scipy.optimize import minimize

    n = len(x0)
    lower, upper = np.full(n, -np.inf), np.full(n, np.inf)
    for j, name in enumerate(post.free):
        lo, hi = post.box[name]
        tr = post.transforms.get(name)
        span = hi - lo
        # a varying parameter's median stays inside its transform's open range
        lower[j] = lo + (1e-9 * span if tr is not None and tr.kind in ("logit", "log") and lo <= tr.a else 0.0)
        upper[j] = hi - (1e-9 * span if tr is not None and tr.kind in ("logit", "neglog") and hi >= tr.b else 0.0)
    lower[len(post.free):] = 0.0
    eye = np.eye(n)
    best: list[tuple[float, np.ndarray]] = [(-float(post(x0)), x0.copy())]
    history: list[float] = []

    def value_and_gradient(z: np.ndarray) -> tuple[float, np.ndarray]:
        h = post.widths(z)
        # central differences; one-sided (second order) against a bound
        down = z - h < lower
        up = z + h > upper
        points = [z]
        for j in range(n):
            if down[j]:
                points += [z + h[j] * eye[j], z + 2 * h[j] * eye[j]]
            elif up[j]:
                points += [z - h[j] * eye[j], z - 2 * h[j] * eye[j]]
            else:
                points += [z + h[j] * eye[j], z - h[j] * eye[j]]
        v = post.batch(np.array(points))
        f0, pairs = v[0], v[1:].reshape(n, 2)
        if not math.isfinite(f0):
            return 1e300, np.zeros(n)
        grad = np.where(down, (4 * pairs[:, 0] - pairs[:, 1] - 3 * f0) / (2 * h),
                        np.where(up, -(4 * pairs[:, 0] - pairs[:, 1] - 3 * f0) / (2 * h),
                                 (pairs[:, 0] - pairs[:, 1]) / (2 * h)))
        grad = np.where(np.isfinite(grad), grad, 0.0)
        if -f0 < best[-1][0]:
            best.append((-f0, z.copy()))
        return -f0, -grad

    def settle(_: Any) -> None:
        history.append(best[-1][0])
        if len(history) > 10 and history[-11] - history[-1] < SETTLE_GAIN:
            raise _Settled

    try:
        minimize(value_and_gradient, np.clip(x0, lower, upper), jac=True, method="L-BFGS-B",
                 bounds=list(zip(lower, upper, strict=True)), callback=settle,
                 options={"maxiter": 50 * n, "ftol": 1e-12, "gtol": 1e-8})
    except _Settled:
        pass
    f, z = best[-1]
    return z if math.isfinite(f) and f < 1e300 else None


#: The Hermite rules :func:`calibrate` chooses among with ``nodes=None`` (the last is the reference).
AUTO_NODES = (3, 5, 7)
#: A rule is taken when, at points drawn about the mode, the log posterior relative to the mode's differs from the
#: reference's by at most this (a few tenths: the posterior's shape where the sampler goes is the same).
NODES_TOLERANCE = 0.5


def _fewest_nodes(post: _LogPosterior, mode: np.ndarray, spread: np.ndarray, rng: np.random.Generator
                  ) -> _LogPosterior:
    """The log posterior with the fewest nodes of :data:`AUTO_NODES` whose shape about the mode matches the reference
    rule's: at 4 x (sampled numbers) points drawn from the normal approximation at the mode (inside the prior), the
    log posterior minus its value at the mode is within :data:`NODES_TOLERANCE` of the reference's. A law smooth
    on the scale of the spread needs few nodes; one with a kink there (slip to roll) keeps them all."""
    points = _start(post, mode, spread, 4 * len(mode), rng)
    X = np.vstack([mode, points])
    reference = post.batch(X)
    if not np.isfinite(reference).all():
        return post
    for q in AUTO_NODES[:-1]:
        cheaper = post.with_nodes(q)
        values = cheaper.batch(X)
        if np.all(np.isfinite(values)) and np.max(np.abs((values - values[0]) - (reference - reference[0]))) \
                <= NODES_TOLERANCE:
            return cheaper
    return post


def _values(post: Any, points: Sequence[np.ndarray]) -> np.ndarray:
    """The log posterior at each point: one batched call when the posterior offers it."""
    batch = getattr(post, "batch", None)
    if batch is not None:
        return np.asarray(batch(np.asarray(points, dtype=float)), dtype=float)
    return np.array([post(x) for x in points], dtype=float)


def _laplace(post: Any, mode: np.ndarray) -> tuple[np.ndarray, str]:
    """A matrix L with L L^T the covariance of the normal approximation of the posterior at ``mode``, and its kind.

    Central differences of the log posterior: first along each axis with a small step, which gives
    each number's posterior standard deviation, then the full Hessian with steps of one standard
    deviation (accurate for a near-normal posterior; all points in one batched evaluation). Where
    the Hessian is not negative definite (a mode on a bound, a flat direction) the diagonal is
    used, and where that fails too, a small ball: the sampler then spreads out on its own.
    """
    n = len(mode)
    widths = post.widths(mode) if hasattr(post, "widths") else \
        np.array([1e-3 * (post.box[f][1] - post.box[f][0]) for f in post.free] + [1e-2] * (n - len(post.free)))
    eye = np.eye(n)
    first = _values(post, [mode] + [mode + sign * widths[j] * eye[j] for j in range(n) for sign in (1.0, -1.0)])
    f0, ends = first[0], first[1:].reshape(n, 2)
    with np.errstate(invalid="ignore"):
        curv = (ends[:, 0] + ends[:, 1] - 2 * f0) / widths ** 2
    curved = np.isfinite(curv) & (curv < 0)
    # a scale or discrepancy whose posterior piles up at zero has no curvature there: its walkers spread over the
    # pile (a tenth of its prior sd, or its value) and the start is the diagonal
    piled = getattr(post, "zero_piles", lambda x: np.zeros(len(x), bool))(mode) & ~curved
    if not (math.isfinite(f0) and np.all(curved | piled)):
        return np.diag(widths), "ball"
    with np.errstate(invalid="ignore", divide="ignore"):
        h = np.where(curved, 1.0 / np.sqrt(np.where(curved, -curv, 1.0)), 0.0)  # steps of one standard deviation
    if piled.any():
        h[piled] = post.pile_widths(mode)[piled]
        return np.diag(h), "diagonal"
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


def _start(post: Any, mode: np.ndarray, spread: np.ndarray, walkers: int,
           rng: np.random.Generator) -> np.ndarray:
    """Walkers drawn from the normal approximation at the mode, each redrawn (closer) until inside the prior. A
    walker never inside after twenty redraws takes its first draw with the scales and discrepancies folded at zero
    (where several of them sit at zero a draw inside is rare; walkers piled on the mode would never spread), or
    the mode where that is outside too."""
    start = mode + rng.standard_normal((walkers, len(mode))) @ spread.T
    nf = len(getattr(post, "free", mode))
    for w in range(walkers):
        first = start[w].copy()
        shrink = 1.0
        while not math.isfinite(post.log_prior(start[w])):
            shrink *= 0.5
            if shrink < 1e-6:
                first[nf:] = np.abs(first[nf:])
                start[w] = first if math.isfinite(post.log_prior(first)) else mode
                break
            start[w] = mode + shrink * (spread @ rng.standard_normal(len(mode)))
    return start


#: Steps between convergence checks (and updates of the independence proposal).
BLOCK = 100
#: Burn-in, in autocorrelation times (at most the first third of the run).
BURN_TAUS = 5
#: Degrees of freedom of the independence proposal's multivariate t.
PROPOSAL_DF = 4.0
#: Shares of the steps taken by each move: differential evolution, its snooker variant, the independence proposal.
MOVE_WEIGHTS = (0.4, 0.1, 0.5)


class _Independence:
    """An independence proposal for emcee's ``MHMove``: a multivariate t about ``mean`` with scale ``L L^T``, its
    draws reflected into the non-negative range of the scales and discrepancies (``positive``: their indices).

    Its proposals do not depend on the walker's position, so the Metropolis-Hastings ratio carries the
    proposal's density at the old point over the new one (a reflected density: the sum over the reflections);
    any proposal leaves the posterior invariant, and one close to the posterior makes successive samples nearly
    independent. Without the reflection, a scale whose posterior piles up near zero would see half its proposals
    fall below zero and be refused.
    """

    def __init__(self, mean: np.ndarray, chol: np.ndarray, positive: Sequence[int] = (), df: float = PROPOSAL_DF
                 ) -> None:
        self.mean = np.asarray(mean, dtype=float)
        self.chol = np.asarray(chol, dtype=float)
        self.whiten = np.linalg.inv(self.chol)  # a few numbers: cheaper than a triangular solve per call
        self.df = float(df)
        self.positive = np.asarray(positive, dtype=int)
        # every sign pattern of the reflected coordinates (2^k of them; k is at most a handful)
        k = len(self.positive)
        self._signs = 1.0 - 2.0 * ((np.arange(2 ** k)[:, None] >> np.arange(k)[None, :]) & 1)

    def log_density(self, x: np.ndarray) -> np.ndarray:
        """The log density of the reflected proposal, up to its constant."""
        x = np.atleast_2d(x)
        flipped = np.repeat(x[None], len(self._signs), axis=0)  # (patterns, points, ndim)
        flipped[:, :, self.positive] *= self._signs[:, None, :]
        z = (flipped - self.mean) @ self.whiten.T
        log_t = -0.5 * (self.df + len(self.mean)) * np.log1p((z ** 2).sum(axis=-1) / self.df)
        top = log_t.max(axis=0)
        return top + np.log(np.exp(log_t - top).sum(axis=0))

    def __call__(self, coords: np.ndarray, random: np.random.RandomState) -> tuple[np.ndarray, np.ndarray]:
        k, d = coords.shape
        z = random.standard_normal((k, d))
        g = random.chisquare(self.df, k)
        proposed = self.mean + (z @ self.chol.T) * np.sqrt(self.df / g)[:, None]
        proposed[:, self.positive] = np.abs(proposed[:, self.positive])
        return proposed, self.log_density(coords) - self.log_density(proposed)

    @classmethod
    def of_chain(cls, chain: np.ndarray, positive: Sequence[int] = ()) -> _Independence | None:
        """About the mean and covariance of a (steps, walkers, ndim) chain; None if the covariance is singular."""
        flat = chain.reshape(-1, chain.shape[-1])
        try:
            return cls(flat.mean(axis=0), np.linalg.cholesky(np.atleast_2d(np.cov(flat, rowvar=False))), positive)
        except np.linalg.LinAlgError:
            return None


def _run_chain(task: tuple) -> dict[str, Any]:
    """One emcee ensemble (module level, so that executors can pickle it): its kept chain and diagnostics.

    The run goes in blocks of :data:`BLOCK` steps; after each, the independence proposal is set to the
    second half of the chain so far. The state, its log posteriors and the random state carry over.
    """
    import emcee

    post, start, steps, max_steps, tau_multiple, burn_taus, seed, progress, proposal = task
    walkers, ndim = start.shape
    positive = list(range(len(getattr(post, "free", [])), ndim)) if hasattr(post, "widths") else []
    independence = None if proposal is None else _Independence(*proposal, positive=positive)
    random_state = np.random.RandomState(seed).get_state()
    state: Any = start
    parts: list[np.ndarray] = []
    accepted = np.zeros(walkers)
    total, burn = 0, 0
    limit = steps if steps is not None else max_steps
    while total < limit:
        n = min(BLOCK, limit - total)
        moves: list[tuple[Any, float]] = [(emcee.moves.DEMove(), MOVE_WEIGHTS[0]),
                                          (emcee.moves.DESnookerMove(), MOVE_WEIGHTS[1])]
        if independence is not None:
            moves.append((emcee.moves.MHMove(independence), MOVE_WEIGHTS[2]))
        sampler = emcee.EnsembleSampler(walkers, ndim, post.batch if hasattr(post, "batch") else post,
                                        moves=moves, vectorize=hasattr(post, "batch"))
        sampler.random_state = random_state
        state = sampler.run_mcmc(state, n, progress=progress, skip_initial_state_check=total > 0)
        random_state = sampler.random_state
        parts.append(sampler.get_chain())
        accepted += sampler.backend.accepted
        total += n
        chain = np.concatenate(parts)
        burn, done = _burn(chain, tau_multiple, burn_taus)
        if steps is None and done:
            break
        independence = _Independence.of_chain(chain[len(chain) // 2:], positive) or independence
    chain = np.concatenate(parts)
    return {"chain": chain[burn:], "acceptance": accepted / total, "steps": total, "burn": burn}


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
    return frame


# ------------------------------------------------------------------------------ the posterior
#: Draws (times landings) computed at once inside :meth:`Posterior.predict` and :meth:`Posterior.interval`.
CHUNK_DRAWS = 2_000_000


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
        Parameters that vary from spot to spot.
    transforms
        Per varying parameter, the space where its variation is normal.
    samples
        Posterior samples after burn-in (thinned): the population values (medians for the varying
        parameters) by parameter name, ``setting_scale_<name>`` (setting-to-setting standard
        deviation in the transformed space; with the setting level only), ``scale_<name>``
        (bounce-to-bounce standard deviation, within a setting when there is a setting level), and
        ``discrepancy_<component>`` or ``noise_<component>`` (scaled units), and ``landing_noise_<component>``
        where the landing's measurement error was fitted (scaled units).
    diagnostics
        ``converged``, ``reason``, ``steps`` and ``burn`` (the most over the chains; per chain in
        ``chain_steps`` and ``chain_burn``), ``kept_steps`` (per walker after burn-in: the chains'
        common tail), ``walkers`` (all chains), ``chains``, ``acceptance`` (mean fraction), ``autocorr``
        (infinite for a column in which some walker never moved) and ``rhat`` (per column of
        ``samples``), ``thin``, ``start`` (how the walkers started: ``"laplace"``, ``"diagonal"`` or
        ``"ball"``; see the module documentation), ``approximation`` (the marginalisation rule, and for
        ``"hermite"`` its number of nodes and whether they were chosen at the mode), ``elapsed_s``.
    measurement
        Typical measurement standard deviations of the calibration data (medians per component of
        ``landing_sd`` and ``liftoff_sd``), used by :meth:`predict` for new landings; None where the
        data had no intervals (their error is then in the fitted noise).
    residual
        ``"discrepancy"`` (the data had lift-off prediction intervals) or ``"noise"`` (measurement
        error and discrepancy together).
    with_tau
        Whether a discrepancy (or noise) term was sampled.
    n_bounces
        Bounces of the calibration data.
    mode
        The point near the posterior's mode that the sampler started from: where the mode search
        settled, not the exact mode.
    notes
        Anything a reader should know (synthetic data, no convergence ...).
    data_kind
        The calibration data's ``data_kind`` attribute (``"synthetic surrogate"`` marks figures).
    levels
        The levels of the variation: ``["setting", "bounce"]`` or ``["bounce"]`` (every bounce on its own spot).
    landing_noise
        Whether the landing's measurement error was fitted (``landing_noise_<component>`` in ``samples``, scaled
        units): where the calibration data had no landing intervals. :meth:`predict` then draws the true landing
        about the measured one with it, as it does with the data's own landing errors.
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
    levels: list[str] = field(default_factory=lambda: ["bounce"])
    landing_noise: bool = False

    # ------------------------------------------------------------------ summaries
    @property
    def converged(self) -> bool:
        """Whether the sampler met the convergence criteria."""
        return bool(self.diagnostics.get("converged", False))

    def summary(self, level: float = 0.95) -> pd.DataFrame:
        """Per sampled number: median, mean, sd, equal-tailed interval at ``level``, autocorrelation time, R-hat.

        The scales of both levels are rows (``setting_scale_<name>``, ``scale_<name>``); :meth:`scales` adds
        the spread of a bounce on a new spot, which holds both.
        """
        level = check_fraction(level, "level")
        lo, hi = 100 * (1 - level) / 2, 100 * (1 + level) / 2
        table = pd.DataFrame({
            "median": self.samples.median(), "mean": self.samples.mean(), "sd": self.samples.std(ddof=1),
            "low": np.percentile(self.samples, lo, axis=0), "high": np.percentile(self.samples, hi, axis=0),
            "autocorr": self.diagnostics["autocorr"], "rhat": self.diagnostics["rhat"]})
        table.index.name = "quantity"
        table.attrs["level"] = level
        return table

    def scales(self, level: float = 0.95) -> pd.DataFrame:
        """Per varying parameter: median and equal-tailed interval at ``level`` of the scale of each level and of
        a bounce on a new spot, :math:`\\sqrt{\\sigma^2 + s^2}` (columns ``<level>``, ``<level>_low``,
        ``<level>_high`` for ``setting`` (when fitted), ``bounce`` and ``new_spot``; in the transformed space)."""
        level = check_fraction(level, "level")
        q = [(1 - level) / 2, 0.5, (1 + level) / 2]
        rows = {}
        for v in self.vary:
            s = self.samples[f"scale_{v}"].to_numpy()
            sigma = self.samples[f"setting_scale_{v}"].to_numpy() if "setting" in self.levels else np.zeros_like(s)
            row: dict[str, float] = {}
            for name, values in (("setting", sigma), ("bounce", s), ("new_spot", np.hypot(sigma, s))):
                if name == "setting" and "setting" not in self.levels:
                    continue
                low, mid, high = np.quantile(values, q)
                row.update({name: mid, f"{name}_low": low, f"{name}_high": high})
            rows[v] = row
        table = pd.DataFrame.from_dict(rows, orient="index")
        table.index.name = "parameter"
        table.attrs["level"] = level
        return table

    @property
    def population(self) -> BounceModel:
        """The law at the posterior medians of the population values."""
        med = self.samples[self.free].median()
        return self.law.replace(**{n: float(med[n]) for n in self.free})

    def report(self) -> str:
        """A readable account: the model, the posterior summary, the scales, the diagnostics, the notes."""
        d = self.diagnostics
        levels = "from setting to setting (repeats share a spot) and from bounce to bounce" \
            if "setting" in self.levels else "from bounce to bounce (every bounce on its own spot)"
        lines = [f"[[Calibration]] {law_name(self.law)} on {self.n_bounces} bounces, hierarchical (emcee)",
                 f"    varying {levels}: " + (", ".join(
                     f"{v} ({self.transforms[v].describe()})" for v in self.vary) or "none"),
                 f"    residual term: {self.residual}" + ("" if self.with_tau else " (none fitted)")
                 + ("; the landing's measurement error fitted (landing_noise)" if self.landing_noise else "")
                 + (f"; marginalised by {d['approximation']}" if "approximation" in d else ""),
                 f"    sampler: {d['chains']} chain(s) x {d['walkers'] // d['chains']} walkers x {_span(d, 'steps')} "
                 f"steps, burn-in {_span(d, 'burn')}, {d['kept_steps']} kept per walker, acceptance "
                 f"{d['acceptance']:.2f}, {d['elapsed_s']:.1f} s",
                 f"    convergence: {d['reason']} (max autocorrelation time {max(d['autocorr']):.1f} steps, "
                 f"max split R-hat {max(d['rhat']):.3f})",
                 "[[Posterior]] (medians of the population values; scales in the transformed space)"]
        table = self.summary()
        lines.extend("    " + line for line in table.to_string(float_format=lambda v: f"{v:.4g}").splitlines())
        if self.vary:
            lines.append("[[Scales]] (medians and 95 % intervals; a bounce on a new spot varies by both levels)")
            sc = self.scales()
            names = {"setting": "setting to setting", "bounce": "bounce to bounce",
                     "new_spot": "a bounce on a new spot"}
            shown = ("setting", "bounce", "new_spot") if "setting" in self.levels else ("bounce",)
            for v in self.vary:
                parts = [f"{names[k]} {sc.loc[v, k]:.4g} [{sc.loc[v, k + '_low']:.4g}, {sc.loc[v, k + '_high']:.4g}]"
                         for k in shown]
                lines.append(f"    {v}: " + "; ".join(parts))
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
    def predict(self, landing: Any, n: int = 1000, *, measurement_error: bool = True, measurement_sd: Any = None,
                spots: Any = None, seed: int = 0) -> np.ndarray:
        """Draws of the lift-off of a new bounce on a new spot for each landing, as it would be measured.

        Each draw takes one posterior sample (population values, scales, discrepancy or noise),
        draws the landing's own varying parameters from the population (a new spot: both levels
        of the variation), feeds the law the landing with its measurement error (no
        linearisation), adds the model discrepancy and the lift-off's measurement error; where the
        calibration data had no lift-off intervals, the fitted noise holds both and is added
        instead. This is what a measurement of the bounce would show, and what :meth:`interval` and
        :meth:`check` use.

        Parameters
        ----------
        landing
            (m, 3) landing states in scaled units (as measured).
        n
            Number of draws; ``n`` times the landings at most :data:`MAX_DRAWS`.
        measurement_error
            True (default): the measured lift-off. False: the lift-off itself, without the
            measurement errors of the landing and of the lift-off (population and spot-to-spot
            spread and the model discrepancy only): narrower than measured data, and not to be
            compared with them. Offered only where the calibration data separated measurement error
            from discrepancy (lift-off prediction intervals); otherwise a FitError.
        measurement_sd
            ``(landing_sd, liftoff_sd)``, each None (the calibration data's typical values,
            :attr:`measurement`) or broadcastable to (m, 3), in scaled units. Only the errors the
            calibration separated can be given: a lift-off error where the posterior has a noise
            term, or a landing error where the calibration data had no landing intervals, is refused
            (the fitted noise already holds it).
        spots
            Optional labels, one per landing: landings with the same label are on the same spot
            (e.g. the repeats of one launcher setting) and share its setting-level draw. Default:
            each landing on a new spot of its own. Without a setting level it changes nothing.
        seed
            Seed of the draws.

        Returns
        -------
        numpy.ndarray
            Shape (n, m, 3).

        Raises
        ------
        FitError
            ``n`` not a count or too many draws (checked before anything is allocated),
            ``measurement_error=False`` where it is not offered, a refused ``measurement_sd``.
        DataError
            Bad landings, ``measurement_sd`` or ``spots`` of the wrong shape.
        """
        p = self._landings(landing)
        n = check_count(n, "n", 1)
        if n * len(p) > MAX_DRAWS:
            raise FitError(f"n = {n} draws of {len(p)} landing(s) are {n * len(p):.3g} draws, more than "
                           f"{MAX_DRAWS:.0e} (bouncelab.fitting.hierarchical.MAX_DRAWS); ask for fewer, or use "
                           "interval(), which summarises the draws landing by landing", option="n")
        out = np.empty((n, len(p), 3))
        for sl, draws in self._draws(p, n, measurement_error, measurement_sd, spots, seed):
            out[:, sl] = draws
        return out

    def _landings(self, landing: Any) -> np.ndarray:
        p, _ = as_states(landing, "landing", landing=True)
        return np.ascontiguousarray(p.reshape(-1, 3), dtype=np.float64)

    def _draws(self, p: np.ndarray, n: int, measurement_error: Any, measurement_sd: Any, spots: Any, seed: Any):
        """The draws of :meth:`predict`, a block of landings at a time: (slice, (n, k, 3) array) pairs."""
        seed = check_seed(seed)
        m = len(p)
        land_sd, lift_sd = self._measurement(measurement_error, measurement_sd, m)
        codes = None
        if spots is not None:
            labels = np.asarray(spots)
            if labels.shape != (m,):
                raise DataError(f"spots must hold one label per landing ({m}); got shape {labels.shape}",
                                option="spots")
            codes = pd.factorize(labels)[0]
        rng = np.random.default_rng(seed)
        rows = self.samples.to_numpy()[rng.integers(0, len(self.samples), n)]
        col = {c: i for i, c in enumerate(self.samples.columns)}
        two = "setting" in self.levels
        shared = None
        if codes is not None and two and self.vary:  # one setting-level draw per spot and posterior sample
            shared = rng.standard_normal((n, int(codes.max()) + 1, len(self.vary)))
        specs = [s.name for s in self.law.parameter_specs]
        base = ParameterVector(self.law).of(self.law)
        tau = rows[:, [col[f"{self.residual}_{c}"] for c in COMPONENTS]] if self.with_tau else None
        # a fitted landing noise is the landing's measurement error (measured bounces only)
        lam = rows[:, [col[f"landing_noise_{c}"] for c in COMPONENTS]] \
            if self.landing_noise and measurement_error else None
        per = max(1, CHUNK_DRAWS // n)
        for block, start in enumerate(range(0, m, per)):
            sl = slice(start, min(m, start + per))
            k = sl.stop - sl.start
            brng = np.random.default_rng([seed, block + 1])
            theta = np.broadcast_to(base, (n, k, len(base))).copy()
            for name in self.free:
                j = specs.index(name)
                if name in self.transforms:
                    v = self.vary.index(name)
                    tr = self.transforms[name]
                    z = tr.forward(rows[:, col[name]])[:, None] + rows[:, col[f"scale_{name}"]][:, None] * \
                        brng.standard_normal((n, k))
                    if two:
                        spot = shared[:, codes[sl], v] if shared is not None else brng.standard_normal((n, k))
                        z = z + rows[:, col[f"setting_scale_{name}"]][:, None] * spot
                    theta[:, :, j] = tr.inverse(z)
                else:
                    theta[:, :, j] = rows[:, col[name]][:, None]
            land = np.broadcast_to(p[sl], (n, k, 3)).copy()
            if land_sd is not None or lam is not None:
                land += (land_sd[sl] if land_sd is not None else lam[:, None, :]) * brng.standard_normal((n, k, 3))
                land[:, :, 1] = np.minimum(land[:, :, 1], -1e-9)  # a measured landing error never turns it upward
            out = _predict_rows(self.law, land.reshape(-1, 3), theta.reshape(-1, len(base))).reshape(n, k, 3)
            if tau is not None:  # the discrepancy (part of the lift-off) or the noise (measured only)
                out += tau[:, None, :] * brng.standard_normal((n, k, 3))
            if lift_sd is not None:
                out += lift_sd[sl] * brng.standard_normal((n, k, 3))
            yield sl, out

    def _measurement(self, measurement_error: Any, measurement_sd: Any, m: int
                     ) -> tuple[np.ndarray | None, np.ndarray | None]:
        """The landing's and the lift-off's measurement standard deviations, each (m, 3) or None."""
        if not isinstance(measurement_error, bool | np.bool_):
            raise FitError(f"measurement_error must be True or False; got {measurement_error!r}",
                           option="measurement_error")
        if not measurement_error:
            if self.residual == "noise":
                raise FitError("measurement_error=False (the lift-off without measurement error) needs a calibration "
                               "that separates measurement error from discrepancy: these calibration data had no "
                               "lift-off prediction intervals, so the fitted noise holds both and only measured "
                               "lift-offs can be predicted", option="measurement_error",
                               hints=[Hint("measurement_error", True)])
            if measurement_sd is not None:
                raise FitError("measurement_sd is for measured lift-offs; it has no use with measurement_error=False",
                               option="measurement_sd")
            return None, None
        given: tuple[Any, Any] = (None, None)
        if measurement_sd is not None:
            try:
                land, lift = measurement_sd
            except (TypeError, ValueError):
                raise DataError("measurement_sd must be a pair (landing_sd, liftoff_sd), each None or broadcastable "
                                f"to ({m}, 3)", option="measurement_sd") from None
            given = (land, lift)
        if given[0] is not None and self.measurement.get("landing_sd") is None:
            raise FitError("measurement_sd gives a landing error, but the calibration data had no landing prediction "
                           "intervals: the landing's measurement error is " + (
                               "the fitted landing noise" if self.landing_noise else "inside the fitted residual")
                           + " already", option="measurement_sd")
        if given[1] is not None and self.residual == "noise":
            raise FitError("measurement_sd gives a lift-off error, but the calibration data had no lift-off "
                           "prediction intervals: the fitted noise holds the lift-off's measurement error already",
                           option="measurement_sd")
        out: list[np.ndarray | None] = []
        for name, v, default in (("landing_sd", given[0], self.measurement.get("landing_sd")),
                                 ("liftoff_sd", given[1], self.measurement.get("liftoff_sd"))):
            v = default if v is None else v
            if v is None:
                out.append(None)
                continue
            try:
                arr = np.broadcast_to(np.asarray(v, dtype=float), (m, 3))
            except (TypeError, ValueError, OverflowError):
                raise DataError(f"{name} must be numbers broadcastable to ({m}, 3); got shape {np.shape(v)}",
                                option="measurement_sd") from None
            if not np.isfinite(arr).all() or (arr < 0).any():
                raise DataError(f"{name} must hold finite standard deviations >= 0", option="measurement_sd")
            out.append(arr)
        return out[0], out[1]

    def interval(self, landing: Any, level: float = 0.95, *, n: int = 2000, measurement_error: bool = True,
                 measurement_sd: Any = None, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Equal-tailed predictive interval of the lift-off of a new bounce on a new spot, for each landing.

        The quantiles of :meth:`predict`'s draws (with the same arguments): by default of the
        *measured* lift-off, which is what a campaign's lift-offs are compared with (:meth:`check`).

        Returns
        -------
        lower, upper
            Each of shape (m, 3).
        """
        level = check_fraction(level, "level")
        p = self._landings(landing)
        n = check_count(n, "n", 2)
        if n > MAX_DRAWS:
            raise FitError(f"n = {n} draws per landing are more than {MAX_DRAWS:.0e} "
                           "(bouncelab.fitting.hierarchical.MAX_DRAWS)", option="n")
        lo, hi = np.empty((len(p), 3)), np.empty((len(p), 3))
        for sl, draws in self._draws(p, n, measurement_error, measurement_sd, None, seed):
            lo[sl], hi[sl] = np.quantile(draws, [(1 - level) / 2, (1 + level) / 2], axis=0)
        return lo, hi

    def measurement_sd_of(self, data: Any) -> tuple[np.ndarray | None, np.ndarray | None] | None:
        """The ``measurement_sd`` of :meth:`predict` for a campaign's own bounces: each bounce's standard deviations
        from the data's prediction intervals, for the errors this posterior separates (the landing's where the
        calibration data had landing intervals, the lift-off's where they had lift-off intervals); None where the
        data have none of them (the posterior's typical values are then used)."""
        p0, _, _ = campaign_arrays(data)
        land_sd, lift_sd = interval_sds(data, len(p0))
        sd = (land_sd if self.measurement.get("landing_sd") is not None else None,
              lift_sd if self.residual == "discrepancy" else None)
        return None if sd[0] is None and sd[1] is None else sd

    def check(self, data: Any, level: float = 0.95, *, n: int = 2000, seed: int = 0) -> pd.DataFrame:
        """Posterior predictive check: the share of a campaign's bounces inside their predictive intervals.

        Each measured lift-off is compared with :meth:`interval` at ``level`` for its measured
        landing (a new bounce on a new spot, as measured: the same code and defaults), with each
        bounce's own measurement errors from the data's prediction intervals where the
        posterior separates them (the posterior's typical ones otherwise). Rows: ``all`` and each
        measured slip/roll class (:func:`bouncelab.classify_slip_roll`); columns: ``n``, the share
        inside for each component, and ``all3`` (inside for all three).
        """
        p0, pf, _ = campaign_arrays(data)
        lo, hi = self.interval(p0, level, n=n, measurement_sd=self.measurement_sd_of(data), seed=seed)
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

    # ------------------------------------------------------------------ saving
    def to_dict(self) -> dict[str, Any]:
        """JSON-safe description: the law, the model, the samples (column-wise) and the diagnostics."""
        from bouncelab.core import __version__

        return {
            "format": FORMAT, "format_version": FORMAT_VERSION, "bouncelab_version": __version__,
            "law": self.law.to_dict(), "free": list(self.free), "vary": list(self.vary),
            "levels": list(self.levels),
            "transforms": {k: t.to_dict() for k, t in self.transforms.items()},
            "residual": self.residual, "with_tau": self.with_tau, "landing_noise": self.landing_noise,
            "n_bounces": self.n_bounces,
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
    def from_dict(cls, d: Any, *, file: str | None = None) -> Posterior:
        """Rebuild a posterior from :meth:`to_dict` output, checking every field first.

        Raises
        ------
        DataError
            Not a saved posterior, or a field that is missing, of the wrong type, not finite, out of
            range or inconsistent with the others: ``column`` names the field (``"samples.scale_r"``,
            ``"diagnostics.autocorr"`` ...) and ``file`` the file when read by :func:`load_posterior`.
        """
        return _read_posterior(cls, d, file)

    def _repr_html_(self) -> str:
        from bouncelab.fitting._display import posterior_html  # the notebook view

        return posterior_html(self)


def load_posterior(path: str | Path) -> Posterior:
    """Read a posterior written by :meth:`Posterior.to_json`, checking every field.

    Raises
    ------
    DataError
        The file cannot be read (missing, a directory, a FIFO or device, too large), is not JSON,
        or is not a valid saved posterior (``column`` names the field at fault, ``file`` the file).
    ParameterError
        ``path`` is not a path.
    """
    from bouncelab.core.files import read_regular_file

    if not isinstance(path, str | Path):
        raise ParameterError(f"load_posterior takes the path of a posterior JSON file; got {type(path).__name__}",
                             parameter="path")
    file = str(path)
    try:
        raw = read_regular_file(Path(path), file)
    except FileNotFoundError:
        raise DataError("no such posterior file", file=file) from None
    except OSError as exc:
        raise DataError(f"the posterior file cannot be read ({exc.strerror or exc})", file=file) from None
    try:
        d = json.loads(raw.decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError) as exc:
        raise DataError(f"not a JSON posterior ({type(exc).__name__}: {exc})", file=file) from None
    return _read_posterior(Posterior, d, file)


def _predict_rows(law: BounceModel, landing: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """The law on each landing with its own parameter numbers (:func:`bouncelab.laws.predict_per_bounce`)."""
    from bouncelab.laws.varying import predict_per_bounce

    return predict_per_bounce(law, landing, theta)


# ------------------------------------------------------------------------------ reading a saved posterior
class _Fields:
    """Checks of a saved posterior's fields: each failure a DataError naming the field (and the file)."""

    def __init__(self, file: str | None) -> None:
        self.file = file

    def fail(self, name: str, message: str) -> DataError:
        return DataError(f"saved posterior: {name}: {message}", file=self.file, column=name)

    def get(self, d: Mapping[str, Any], key: str, name: str | None = None) -> Any:
        if key not in d:
            raise self.fail(name or key, "missing")
        return d[key]

    def mapping(self, v: Any, name: str) -> Mapping[str, Any]:
        if not isinstance(v, Mapping):
            raise self.fail(name, f"must be a JSON object; got {type(v).__name__}")
        return v

    def text(self, v: Any, name: str) -> str:
        if not isinstance(v, str):
            raise self.fail(name, f"must be text; got {type(v).__name__}")
        try:
            v.encode("utf-8")
        except UnicodeEncodeError:
            raise self.fail(name, "holds a lone surrogate, not text") from None
        return v

    def names(self, v: Any, name: str) -> list[str]:
        if not isinstance(v, list):
            raise self.fail(name, f"must be a list of names; got {type(v).__name__}")
        out = [self.text(x, name) for x in v]
        if len(set(out)) != len(out):
            raise self.fail(name, f"names a parameter twice: {out}")
        return out

    def integer(self, v: Any, name: str, minimum: int = 0) -> int:
        if isinstance(v, bool) or not isinstance(v, int) or v < minimum or v > 2**62:
            raise self.fail(name, f"must be a whole number of at least {minimum}; got {_short(v)}")
        return int(v)

    def flag(self, v: Any, name: str) -> bool:
        if not isinstance(v, bool):
            raise self.fail(name, f"must be true or false; got {_short(v)}")
        return v

    def number(self, v: Any, name: str, *, finite: bool = True, low: float = -math.inf, high: float = math.inf
               ) -> float:
        """A real number; with ``finite=False`` also "inf", "-inf", "nan" as text (the diagnostics' non-finite)."""
        if isinstance(v, str) and not finite and v in ("inf", "-inf", "nan"):
            return float(v)
        if isinstance(v, bool) or not isinstance(v, int | float):
            raise self.fail(name, f"must be a number; got {_short(v)}")
        try:
            x = float(v)
        except OverflowError:
            raise self.fail(name, f"is a number too large for a float ({len(str(abs(v)))} digits)") from None
        if finite and not math.isfinite(x):
            raise self.fail(name, f"must be finite; got {x}")
        if not (math.isnan(x) or low <= x <= high):
            raise self.fail(name, f"must be within [{low:g}, {high:g}]; got {x:g}")
        return x

    def numbers(self, v: Any, name: str, *, length: int | None = None, **kwargs: Any) -> list[float]:
        if not isinstance(v, list) or (length is not None and len(v) != length):
            raise self.fail(name, "must be a list of " + (f"{length} " if length is not None else "") + "numbers")
        return [self.number(x, name, **kwargs) for x in v]


def _short(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def _read_posterior(cls: type[Posterior], d: Any, file: str | None) -> Posterior:
    """A Posterior from a saved description, every field checked (see :meth:`Posterior.from_dict`)."""
    from bouncelab.core.errors import BouncelabError

    f = _Fields(file)
    if not isinstance(d, Mapping) or d.get("format") != FORMAT:
        raise DataError(f"not a saved bouncelab posterior (its 'format' must be {FORMAT!r}; got "
                        f"{_short(d.get('format')) if isinstance(d, Mapping) else type(d).__name__})",
                        file=file, column="format")
    version = d.get("format_version")
    if isinstance(version, bool) or version not in (1, FORMAT_VERSION):
        raise f.fail("format_version", f"this bouncelab reads versions 1 and {FORMAT_VERSION}; got {_short(version)}")
    try:
        law = law_from_dict(f.mapping(f.get(d, "law"), "law"))
        theta = ParameterVector(law).of(law)
    except DataError:
        raise
    except BouncelabError as exc:
        raise f.fail("law", exc.message) from None
    specs = {s.name: s for s in law.parameter_specs}
    free = f.names(f.get(d, "free"), "free")
    for name in free:
        if name not in specs or not specs[name].is_scalar:
            raise f.fail("free", f"{name!r} is not a scalar parameter of {law_name(law)} ({list(specs)})")
    vary = f.names(f.get(d, "vary"), "vary")
    if any(v not in free for v in vary):
        raise f.fail("vary", f"names a parameter that is not free: {[v for v in vary if v not in free]}")
    levels = ["bounce"] if version == 1 else f.names(f.get(d, "levels"), "levels")
    if levels not in (["bounce"], ["setting", "bounce"]) or (levels != ["bounce"] and not vary):
        raise f.fail("levels", f"must be ['setting', 'bounce'] or ['bounce'] (the latter without varying "
                               f"parameters); got {_short(levels)}")
    saved = f.mapping(f.get(d, "transforms"), "transforms")
    if set(saved) != set(vary):
        raise f.fail("transforms", f"must have one entry per varying parameter {vary}; got {sorted(map(str, saved))}")
    transforms = {}
    for name in vary:  # each must be the one calibrate derives from the parameter's physical range
        expected = _Transform.of(*(float(v[0]) for v in specs[name].physical_arrays()))
        entry = f.mapping(saved[name], f"transforms.{name}")
        given = (f.text(f.get(entry, "kind", f"transforms.{name}.kind"), f"transforms.{name}.kind"),
                 f.number(f.get(entry, "a", f"transforms.{name}.a"), f"transforms.{name}.a", finite=False),
                 f.number(f.get(entry, "b", f"transforms.{name}.b"), f"transforms.{name}.b", finite=False))
        if given != (expected.kind, expected.a, expected.b):
            raise f.fail(f"transforms.{name}", f"must be {expected.to_dict()} (from {name}'s physical range); got "
                                               f"{_short(dict(entry))}")
        transforms[name] = expected
    residual = f.text(f.get(d, "residual"), "residual")
    if residual not in ("discrepancy", "noise"):
        raise f.fail("residual", f"must be 'discrepancy' or 'noise'; got {_short(residual)}")
    with_tau = f.flag(f.get(d, "with_tau"), "with_tau")
    if residual == "noise" and not with_tau:
        raise f.fail("with_tau", "a posterior with a noise term must have sampled it (true)")
    n_bounces = f.integer(f.get(d, "n_bounces"), "n_bounces", 1)
    measurement = {}
    raw_meas = f.mapping(f.get(d, "measurement"), "measurement")
    for key in ("landing_sd", "liftoff_sd"):
        v = raw_meas.get(key)
        measurement[key] = None if v is None else f.numbers(v, f"measurement.{key}", length=3, low=0.0)
    if (measurement["liftoff_sd"] is None) != (residual == "noise"):
        raise f.fail("measurement.liftoff_sd", "must be given exactly when the residual is a discrepancy")
    landing_noise = f.flag(d.get("landing_noise", False), "landing_noise")
    if landing_noise and measurement["landing_sd"] is not None:
        raise f.fail("landing_noise", "a landing noise is fitted only where the data had no landing intervals "
                                      "(measurement.landing_sd is given)")
    # the samples: exactly the columns calibrate writes, equally long, finite, in range
    columns = [*free, *(f"setting_scale_{v}" for v in vary if "setting" in levels), *(f"scale_{v}" for v in vary),
               *((f"{residual}_{c}" for c in COMPONENTS) if with_tau else ()),
               *((f"landing_noise_{c}" for c in COMPONENTS) if landing_noise else ())]
    raw = f.mapping(f.get(d, "samples"), "samples")
    if set(raw) != set(columns):
        raise f.fail("samples", f"must have the columns {columns}; got {sorted(map(str, raw))}")
    lengths = {len(v) if isinstance(v, list) else -1 for v in raw.values()}
    if len(lengths) != 1 or min(lengths) < 1:
        raise f.fail("samples", "must hold lists of numbers, all of one length of at least 1")
    data = {}
    for c in columns:
        low, high = 0.0, math.inf
        if c in specs:
            lo, hi = specs[c].physical_arrays()
            low, high = float(lo[0]), float(hi[0])
        data[c] = f.numbers(raw[c], f"samples.{c}", low=low, high=high)
    samples = pd.DataFrame(data, columns=columns, dtype=float)
    diag = f.mapping(f.get(d, "diagnostics"), "diagnostics")
    diagnostics: dict[str, Any] = dict(diag)
    diagnostics["converged"] = f.flag(f.get(diag, "converged", "diagnostics.converged"), "diagnostics.converged")
    diagnostics["reason"] = f.text(f.get(diag, "reason", "diagnostics.reason"), "diagnostics.reason")
    for key, minimum in (("steps", 0), ("burn", 0), ("walkers", 1), ("chains", 1), ("kept_steps", 0)):
        diagnostics[key] = f.integer(f.get(diag, key, f"diagnostics.{key}"), f"diagnostics.{key}", minimum)
    for key in ("acceptance", "elapsed_s"):
        diagnostics[key] = f.number(f.get(diag, key, f"diagnostics.{key}"), f"diagnostics.{key}", low=0.0)
    for key in ("autocorr", "rhat"):
        diagnostics[key] = f.numbers(f.get(diag, key, f"diagnostics.{key}"), f"diagnostics.{key}",
                                     length=len(columns), finite=False)
    for key in ("chain_steps", "chain_burn"):
        if key in diag:
            v = diag[key]
            if not isinstance(v, list) or not v:
                raise f.fail(f"diagnostics.{key}", "must be a list of whole numbers, one per chain")
            diagnostics[key] = [f.integer(x, f"diagnostics.{key}") for x in v]
    if "thin" in diag:
        diagnostics["thin"] = f.integer(diag["thin"], "diagnostics.thin", 1)
    if "start" in diag:
        diagnostics["start"] = f.text(diag["start"], "diagnostics.start")
    mode = {}
    for k, v in f.mapping(d.get("mode", {}), "mode").items():
        mode[f.text(k, "mode")] = f.number(v, f"mode.{k}")
    notes = d.get("notes", [])
    if not isinstance(notes, list):
        raise f.fail("notes", "must be a list of text")
    notes = [f.text(x, "notes") for x in notes]
    data_kind = f.text(d.get("data_kind", "unknown"), "data_kind")
    del theta
    return cls(law=law, free=free, vary=vary, transforms=transforms, samples=samples, diagnostics=diagnostics,
               measurement=measurement, residual=residual, with_tau=with_tau, n_bounces=n_bounces, mode=mode,
               notes=notes, data_kind=data_kind, levels=levels, landing_noise=landing_noise)
