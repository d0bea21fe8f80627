r"""The setting level of :func:`bouncelab.calibrate`'s likelihood, integrated over each setting's draw.

The repeats of a launcher setting :math:`g` share one draw :math:`\zeta_g = m + \sigma v_g` of the varying
parameters (in their transformed space). Their likelihood is the integral over that draw,

.. math::

    L_g = \int N(\zeta;\, m, \mathrm{diag}\,\sigma^2) \prod_{i \in g} \ell_i(\zeta)\, d\zeta,

with :math:`\ell_i(\zeta)` the normal density of bounce :math:`i`'s measured lift-off given the draw:
mean :math:`f(p_{0,i}, T^{-1}(\zeta))`, covariance :math:`\Sigma_{F,i} + \mathrm{diag}(\tau^2) +
G_i \Sigma_{0,i} G_i^\top + J_i \mathrm{diag}(s^2) J_i^\top` (measurement errors, discrepancy, the
landing's error pushed through the law with its derivative :math:`G_i` at the draw, and the bounce's own
variation linearised with the derivative :math:`J_i` with respect to the transformed parameters at the
draw: exact when the bounce-to-bounce scale :math:`s` is zero). Where the landing's error is fitted
(``landing_noise``) its three unit columns join :math:`J`'s, scaled by the fitted standard deviations.

Where a setting's draw moves its repeats across a kink of the law (Rigid's slip to roll) the repeats'
lift-offs are far from jointly normal, and the joint normal of :mod:`bouncelab.fitting.hierarchical`
misses the integral by up to 19 log units per setting (measured; see ``tests/test_calibrate.py``). Here it
is estimated by importance sampling, with two sets of points per setting:

* ``nodes`` fixed points drawn once from a proposal :math:`q_g` built at the mode of the joint-normal
  posterior: a multivariate t (4 degrees of freedom) about the setting's draw given its repeats, found by
  :data:`ROUNDS` rounds of adaptive importance sampling, mixed with a share :data:`DEFENSIVE` of the
  population's own distribution at that mode, widened. The law and its derivatives are evaluated at these
  points once;
* ``walker_points`` points :math:`m + \sigma v_{gl}` from each evaluated point's own population
  (fixed standard normal :math:`v_{gl}`), evaluated at every call. They carry the integral where the
  population is narrow against the repeats' information (a setting-to-setting scale near zero), where the
  fixed points cannot reach.

The estimate weighs all points by the mixture of both (the balance heuristic of multiple importance
sampling):

.. math::

    \hat L_g = \sum_{x} \frac{N(x; m, \sigma^2) \prod_i \ell_i(x)}{K q_g(x) + K' N(x; m, \sigma^2)},

unbiased for :math:`L_g`, smooth in the population values and scales (every point is fixed or moves
smoothly with them), and exact in the limit :math:`\sigma \to 0`. The fixed points need the other law
numbers fixed: :func:`~bouncelab.calibrate` uses this integral where every free parameter varies (with
``setting_integral="auto"``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.special import gammaln

from bouncelab.core._jit import jit
from bouncelab.core._parallel import run_rows

__all__ = ["NODES", "WALKER_POINTS", "SettingIntegral", "det_quad"]

#: Fixed points per setting, drawn once from the setting's proposal.
NODES = 128
#: Points per setting drawn from each evaluated point's own population, at every call.
WALKER_POINTS = 8
#: Rounds of adaptive importance sampling that place a setting's proposal, and draws per round.
ROUNDS = 5
ROUND_DRAWS = 1024
#: A round whose effective sample size is below this re-centres the proposal on its best this many draws.
RECENTRE = 20
#: Degrees of freedom of the proposal's multivariate t.
PROPOSAL_DF = 4.0
#: Share of the fixed points drawn from the population at the mode (its scales at least SCALE_FLOOR, times WIDEN).
DEFENSIVE = 0.1
#: Widening of the t's scales over the setting's estimated draw's, and of the defensive share's over the population's.
INFLATE = 1.0
WIDEN = 1.0
#: Smallest setting-to-setting scale the proposal assumes (transformed units).
SCALE_FLOOR = 0.05

_LOG2PI = math.log(2.0 * math.pi)


def det_quad(c: Any, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


def _outer_entries(cols: np.ndarray) -> np.ndarray:
    """The entries (xx, yy, ww, xy, xw, yw) of sum_c cols[c] cols[c]^T for columns (3, N, 3): (N, 6)."""
    x, y, z = cols[..., 0], cols[..., 1], cols[..., 2]
    return np.stack([(x * x).sum(0), (y * y).sum(0), (z * z).sum(0), (x * y).sum(0), (x * z).sum(0),
                     (y * z).sum(0)], axis=-1)


@jit(nogil=True, inline="always")
def _repeats(y, base, tau2, s2, F, L, J, a, b):  # pragma: no cover - compiled
    """Sum over bounces a..b-1 of the log normal density of y_i about F_i with covariance
    base_i + tau2 + L_i + sum_j s2_j J_ij J_ij^T (entries xx, yy, ww, xy, xw, yw)."""
    total = 0.0
    V = J.shape[1]
    for i in range(a, b):
        cxx = base[i, 0] + tau2[0] + L[i, 0]
        cyy = base[i, 1] + tau2[1] + L[i, 1]
        cww = base[i, 2] + tau2[2] + L[i, 2]
        cxy = L[i, 3]
        cxw = L[i, 4]
        cyw = L[i, 5]
        for j in range(V):
            jx = J[i, j, 0]
            jy = J[i, j, 1]
            jw = J[i, j, 2]
            cxx += s2[j] * jx * jx
            cyy += s2[j] * jy * jy
            cww += s2[j] * jw * jw
            cxy += s2[j] * jx * jy
            cxw += s2[j] * jx * jw
            cyw += s2[j] * jy * jw
        A = cyy * cww - cyw * cyw
        B = cxw * cyw - cxy * cww
        C = cxy * cyw - cxw * cyy
        D = cxx * cww - cxw * cxw
        E = cxy * cxw - cxx * cyw
        Fc = cxx * cyy - cxy * cxy
        det = cxx * A + cxy * B + cxw * C
        rx = y[i, 0] - F[i, 0]
        ry = y[i, 1] - F[i, 1]
        rw = y[i, 2] - F[i, 2]
        quad = (A * rx * rx + D * ry * ry + Fc * rw * rw + 2.0 * (B * rx * ry + C * rx * rw + E * ry * rw)) / det
        if not (det > 0.0 and quad == quad and quad < math.inf):
            return -math.inf
        total -= 0.5 * (math.log(det) + quad + 3.0 * 1.8378770664093453)
    return total


@jit(nogil=True)
def _setting_kernel(out, ends, y, base, FA, LA, JA, ZA, lqA, FB, LB, JB, ZB, lqB, m, sig, s2, tau2, start, stop
                    ):  # pragma: no cover - compiled
    """log L of walkers start..stop-1: the sum over settings of the log of the mixture estimate (module docs).
    s2 (w, columns of J): the squared scales of J's columns (the bounce-level scales, then a fitted landing
    noise's)."""
    G = ends.shape[0] - 1
    K = FA.shape[0]
    K2 = FB.shape[1]
    V = m.shape[1]
    log_k = math.log(K)
    log_k2 = math.log(K2) if K2 > 0 else -math.inf
    buf = np.empty(K + K2)
    for w in range(start, stop):
        lsig = 0.0
        for j in range(V):
            lsig += math.log(sig[w, j])
        total = 0.0
        for g in range(G):
            a = ends[g]
            b = ends[g + 1]
            best = -math.inf
            for k in range(K + K2):
                lp = -lsig - 0.5 * V * 1.8378770664093453
                for j in range(V):
                    z = ZA[g, k, j] if k < K else ZB[w, g, k - K, j]
                    d = (z - m[w, j]) / sig[w, j]
                    lp -= 0.5 * d * d
                if k < K:
                    ll = _repeats(y, base, tau2[w], s2[w], FA[k], LA[k], JA[k], a, b)
                    lq = lqA[g, k]
                else:
                    ll = _repeats(y, base, tau2[w], s2[w], FB[w, k - K], LB[w, k - K], JB[w, k - K], a, b)
                    lq = lqB[w, g, k - K]
                la = log_k + lq
                lb = log_k2 + lp
                hi = la if la > lb else lb
                denom = hi + math.log1p(math.exp(-abs(la - lb))) if hi > -math.inf else -math.inf
                t = lp + ll - denom if ll > -math.inf else -math.inf
                if not t == t:
                    t = -math.inf
                buf[k] = t
                if t > best:
                    best = t
            if best == -math.inf:
                total = -math.inf
                break
            acc = 0.0
            for k in range(K + K2):
                acc += math.exp(buf[k] - best)
            total += best + math.log(acc)
        out[w] = total


@jit(nogil=True)
def _node_kernel(out, ends, y, base, FA, LA, JA, tau2, s2):  # pragma: no cover - compiled
    """out[g, k]: the sum over setting g's repeats of log l_i at its fixed point k."""
    for g in range(ends.shape[0] - 1):
        for k in range(FA.shape[0]):
            out[g, k] = _repeats(y, base, tau2, s2, FA[k], LA[k], JA[k], ends[g], ends[g + 1])


class _Proposal:
    """Per setting: a multivariate t (mean, Cholesky factor) mixed with a normal (mean, sd) of weight DEFENSIVE."""

    def __init__(self, mean: np.ndarray, chol: np.ndarray, wide_mean: np.ndarray, wide_sd: np.ndarray) -> None:
        self.mean, self.chol = mean, chol  # (G, V), (G, V, V)
        self.wide_mean, self.wide_sd = wide_mean, wide_sd  # (V,), (V,)

    def draw(self, rng: np.random.Generator, k: int) -> np.ndarray:
        """k points per setting, (G, k, V): round(DEFENSIVE k) from the normal, the rest from the t."""
        from scipy.stats import chi2, norm, qmc

        G, V = self.mean.shape
        n_wide = round(DEFENSIVE * k)
        # scrambled Sobol points (one sequence per setting): a more even cover than independent draws
        u = np.stack([qmc.Sobol(V + 1, seed=rng).random(k) for _ in range(G)])  # (G, k, V + 1)
        u = np.clip(u, 1e-12, 1 - 1e-12)
        wide = self.wide_mean + self.wide_sd * norm.ppf(u[:, :n_wide, :V])
        z = norm.ppf(u[:, n_wide:, :V])
        scale = np.sqrt(chi2.ppf(u[:, n_wide:, V:], PROPOSAL_DF) / PROPOSAL_DF)
        t = self.mean[:, None, :] + np.einsum("gab,gkb->gka", self.chol, z) / scale
        return np.concatenate([wide, t], axis=1)

    def log_density(self, Z: np.ndarray) -> np.ndarray:
        """The mixture's log density at points (..., G, k, V) of each setting: (..., G, k)."""
        V = Z.shape[-1]
        wide = (-0.5 * ((Z - self.wide_mean) / self.wide_sd) ** 2 - np.log(self.wide_sd) - 0.5 * _LOG2PI).sum(-1)
        d = Z - self.mean[:, None, :]
        sol = np.linalg.solve(self.chol[:, None, :, :], d[..., None])[..., 0] if Z.ndim == 3 else \
            np.linalg.solve(self.chol[None, :, None, :, :], d[..., None])[..., 0]
        maha = (sol ** 2).sum(-1)
        logdet = np.log(np.abs(np.diagonal(self.chol, axis1=-2, axis2=-1))).sum(-1)[:, None]
        nu = PROPOSAL_DF
        t = gammaln((nu + V) / 2) - gammaln(nu / 2) - 0.5 * V * math.log(nu * math.pi) - logdet \
            - 0.5 * (nu + V) * np.log1p(maha / nu)
        return np.logaddexp(math.log(DEFENSIVE) + wide, math.log1p(-DEFENSIVE) + t)


class SettingIntegral:
    """The setting level's likelihood of a :class:`~bouncelab.fitting.hierarchical._LogPosterior` by importance
    sampling over each setting's draw (see the module documentation); picklable.

    Parameters
    ----------
    post
        The log posterior (with launcher settings; every free parameter varying).
    x
        The point (a mode of the joint-normal posterior) at which the proposals are placed.
    nodes, walker_points
        Fixed points per setting, and points per setting from each evaluated point's population.
    seed
        Seed of the proposals and the points (the likelihood is a fixed function once built).
    """

    def __init__(self, post: Any, x: np.ndarray, *, nodes: int = NODES, walker_points: int = WALKER_POINTS,
                 seed: int = 0) -> None:
        rng = np.random.default_rng([seed, 7919])
        self.V = len(post.vary)
        self._x = np.asarray(x, dtype=float)
        self.ends = np.r_[post._starts, post.n].astype(np.int64)
        self.setting_of = np.repeat(np.arange(len(post._starts)), np.diff(self.ends))
        G, V = len(post._starts), self.V
        m, sig, _, tau = self.split(post, np.asarray(x, dtype=float)[None, :])
        self.base = np.ascontiguousarray((post.liftoff_var if post.liftoff_var is not None else 0.0)
                                         + post.jitter[None, :] * np.ones((post.n, 1)))
        wide_sd = WIDEN * np.maximum(sig[0], SCALE_FLOOR)
        # rounds of adaptive importance sampling of the setting's draw given its repeats, from the widened population
        Z = m[0] + wide_sd * rng.standard_normal((G, ROUND_DRAWS, V))
        log_q = (-0.5 * ((Z - m[0]) / wide_sd) ** 2 - np.log(wide_sd) - 0.5 * _LOG2PI).sum(-1)
        self.ess = np.zeros(G)
        prior_sd = wide_sd / WIDEN
        for _ in range(ROUNDS):
            target = (-0.5 * ((Z - m[0]) / prior_sd) ** 2 - np.log(prior_sd) - 0.5 * _LOG2PI).sum(-1)
            lw = target + self._draw_loglikes(post, Z, tau[0]) - log_q
            lw = np.where(np.isfinite(lw), lw, -np.inf)
            w = np.exp(lw - lw.max(axis=1, keepdims=True))
            w /= w.sum(axis=1, keepdims=True)
            self.ess = 1.0 / (w ** 2).sum(axis=1)
            mean = np.einsum("gk,gkv->gv", w, Z)
            d = Z - mean[:, None, :]
            cov = np.einsum("gk,gka,gkb->gab", w, d, d)
            # a setting whose weights sit on a few draws (its draw far in the population's tail): the best
            # RECENTRE draws, unweighted, move the proposal towards it without collapsing it on one point
            few = np.flatnonzero(self.ess < RECENTRE)
            if few.size:
                best = np.argsort(lw[few], axis=1)[:, -RECENTRE:]
                top = np.take_along_axis(Z[few], best[:, :, None], axis=1)
                mean[few] = top.mean(axis=1)
                dt = top - mean[few][:, None, :]
                cov[few] = np.einsum("gka,gkb->gab", dt, dt) / (RECENTRE - 1)
            # never narrower than a tenth of the population's sd along an axis (a proposal, not an estimate)
            cov = cov + np.eye(V) * (1e-2 * wide_sd ** 2)[None, :, None]
            proposal = _Proposal(mean, np.linalg.cholesky(INFLATE ** 2 * cov), m[0], wide_sd)
            Z = proposal.draw(rng, ROUND_DRAWS)
            log_q = proposal.log_density(Z)
        self.proposal = proposal
        self.nodes = int(nodes)
        self.walker_points = int(walker_points)
        self.ZA = np.ascontiguousarray(proposal.draw(rng, self.nodes))  # (G, K, V)
        self.lqA = np.ascontiguousarray(proposal.log_density(self.ZA))
        idx = np.tile(np.arange(post.n), self.nodes)
        zeta = self.ZA[self.setting_of].transpose(1, 0, 2).reshape(-1, V)  # (K n, V): node k of bounce i's setting
        F, L, J = self._points(post, idx, zeta, np.repeat(post.theta0[None, :], len(idx), axis=0))
        self.FA = F.reshape(self.nodes, post.n, 3)
        self.LA = L.reshape(self.nodes, post.n, 6)
        self.JA = J.reshape(self.nodes, post.n, J.shape[1], 3)
        self.v = rng.standard_normal((G, self.walker_points, V))  # the walker points' standard normals

    # ------------------------------------------------------------------ pieces
    @staticmethod
    def split(post: Any, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per row of X: transformed population medians m, setting scales sigma, bounce scales s, tau: (w, .)."""
        nf, V = len(post.free), len(post.vary)
        m = np.column_stack([post.transforms[v].forward(X[:, post.free.index(v)]) for v in post.vary])
        sig = X[:, nf:nf + V]
        s = X[:, nf + V:nf + 2 * V]
        tau = X[:, nf + 2 * V:nf + 2 * V + 3] if post.with_tau else np.zeros((len(X), 3))
        return m, sig, s, tau

    def _numbers(self, post: Any, zeta: np.ndarray, theta: np.ndarray) -> np.ndarray:
        numbers = theta.copy()
        for j, name in enumerate(post.vary):
            numbers[:, post.index[name]] = post.transforms[name].inverse(zeta[:, j])
        return numbers

    def _rows(self, post: Any, landing: np.ndarray, numbers: np.ndarray) -> np.ndarray:
        """The law on each landing with its own numbers; NaN where a number is not finite."""
        good = np.isfinite(numbers).all(axis=1)
        if good.all():
            return post.rows(landing, numbers)
        out = np.full((len(landing), 3), np.nan)
        if good.any():
            out[good] = post.rows(np.ascontiguousarray(landing[good]), np.ascontiguousarray(numbers[good]))
        return out

    def _points(self, post: Any, idx: np.ndarray, zeta: np.ndarray, theta: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """At each (bounce, draw): the lift-off (N, 3), the landing error's covariance entries (N, 6) and the
        derivatives with respect to the transformed varying parameters (N, V, 3), in one law call."""
        V, N, step = self.V, len(idx), post.step
        base = self._numbers(post, zeta, theta)
        land = post.p0[idx]
        numbers, landings = [base], [land]
        for j, name in enumerate(post.vary):  # forward steps along each varying parameter (transformed)
            moved = base.copy()
            moved[:, post.index[name]] = post.transforms[name].inverse(zeta[:, j] + step)
            numbers.append(moved)
            landings.append(land)
        if post.landing_sd is not None or post.landing_prior is not None:  # and along each landing component
            for c in range(3):
                moved = land.copy()
                moved[:, c] += post.h_land[idx, c]
                numbers.append(base)
                landings.append(moved)
        out = self._rows(post, np.concatenate(landings), np.concatenate(numbers)).reshape(len(numbers), N, 3)
        F = out[0]
        J = ((out[1:1 + V] - F) / step).transpose(1, 0, 2)
        L = np.zeros((N, 6))
        if post.landing_sd is not None:
            cols = (out[1 + V:] - F) * (post.landing_sd[idx] / post.h_land[idx]).T[:, :, None]
            L = _outer_entries(cols)
        elif post.landing_prior is not None:  # a fitted landing noise: its unit columns beside J's, scaled per call
            cols = (out[1 + V:] - F) / post.h_land[idx].T[:, :, None]
            J = np.concatenate([J, cols.transpose(1, 0, 2)], axis=1)
        return F, L, np.ascontiguousarray(J)

    def _draw_loglikes(self, post: Any, Z: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Sum over each setting's repeats of log l_i at draws Z (G, M, V), with the landing error at the mode and
        no bounce-level spread (enough to place a proposal): (G, M)."""
        M, V = Z.shape[1], self.V
        idx = np.tile(np.arange(post.n), M)
        zeta = Z[self.setting_of].transpose(1, 0, 2).reshape(-1, V)
        F = self._rows(post, post.p0[idx], self._numbers(post, zeta, np.repeat(post.theta0[None, :], len(idx), axis=0)))
        entries = [self.base[:, c] + tau[c] ** 2 for c in range(3)] + [np.zeros(post.n)] * 3
        land = post.landing_entries(self._x[None, :])
        if land is not None:
            entries = [a + np.reshape(b, -1) for a, b in zip(entries, land, strict=True)]
        det, quad = det_quad([np.tile(e, M) for e in entries], post.y[idx] - F)
        with np.errstate(invalid="ignore", divide="ignore"):
            ll = -0.5 * (np.log(det) + quad + 3 * _LOG2PI)
        ll = np.where(np.isfinite(ll), ll, -np.inf).reshape(M, post.n)
        return np.add.reduceat(ll, self.ends[:-1], axis=1).T

    # ------------------------------------------------------------------ the likelihood
    def log_likelihoods(self, post: Any, X: np.ndarray) -> np.ndarray:
        """The log likelihood of each row of X (w, ndim), summed over settings; -inf where it cannot be evaluated."""
        W, V, K2 = len(X), self.V, self.walker_points
        m, sig, s, tau = self.split(post, X)
        lam = post.landing_noise(X)
        s2 = np.ascontiguousarray(s ** 2 if lam is None else np.hstack([s ** 2, lam ** 2]))
        ok = np.isfinite(m).all(1) & np.isfinite(sig).all(1) & np.isfinite(s2).all(1) & np.isfinite(tau).all(1)
        m = np.where(ok[:, None], m, 0.0)
        sig = np.where(ok[:, None], np.maximum(sig, 1e-12), 1.0)
        ZB = m[:, None, None, :] + sig[:, None, None, :] * self.v[None]  # (W, G, K2, V)
        idx = np.tile(np.arange(post.n), W * K2)
        zeta = ZB[:, self.setting_of].transpose(0, 2, 1, 3).reshape(-1, V)  # (W K2 n, V)
        theta = np.repeat(post._theta(X), K2 * post.n, axis=0)
        F, L, J = self._points(post, idx, zeta, theta)
        lqB = self.proposal.log_density(ZB)
        out = np.empty(W)
        args = (np.ascontiguousarray(post.y), self.base, self.FA, self.LA, self.JA, self.ZA, self.lqA,
                F.reshape(W, K2, post.n, 3), L.reshape(W, K2, post.n, 6), J.reshape(W, K2, post.n, J.shape[1], 3),
                np.ascontiguousarray(ZB), np.ascontiguousarray(lqB), np.ascontiguousarray(m), np.ascontiguousarray(sig),
                s2, np.ascontiguousarray(tau ** 2))

        def part(start: int, stop: int) -> None:
            _setting_kernel(out, self.ends, *args, start, stop)

        run_rows(part, W, min_rows=2, min_part=1)
        return np.where(ok & np.isfinite(out), out, -math.inf)

    def effective_sizes(self, post: Any, x: np.ndarray) -> np.ndarray:
        """Per setting, the effective number of the fixed points at ``x`` (Kish's, from their weights)."""
        x = np.asarray(x, dtype=float)[None, :]
        m, sig, s, tau = self.split(post, x)
        lam = post.landing_noise(x)
        s2 = s[0] ** 2 if lam is None else np.r_[s[0] ** 2, lam[0] ** 2]
        sig = np.maximum(sig, 1e-12)
        lp = (-0.5 * ((self.ZA - m[0]) / sig[0]) ** 2 - np.log(sig[0]) - 0.5 * _LOG2PI).sum(-1)
        ll = np.empty((len(self.ends) - 1, self.nodes))
        _node_kernel(ll, self.ends, np.ascontiguousarray(post.y), self.base, self.FA, self.LA, self.JA, tau[0] ** 2,
                     s2)
        lw = lp + ll - self.lqA
        lw = np.where(np.isfinite(lw), lw, -np.inf)
        w = np.exp(lw - lw.max(axis=1, keepdims=True))
        return w.sum(axis=1) ** 2 / (w ** 2).sum(axis=1)
