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
draw: exact when the bounce-to-bounce scale :math:`s` is zero). Both are columns of one matrix
:math:`C_i = [J_i, G_i]` with squared scales :math:`(s^2, \lambda^2)`: :math:`G_i`'s columns scaled by the
data's landing errors (then :math:`\lambda = 1`), or for a unit error with :math:`\lambda` the fitted
``landing_noise``.

Where a setting's draw moves its repeats across a kink of the law (Rigid's slip to roll) the repeats'
lift-offs are far from jointly normal, and the joint normal of :mod:`bouncelab.fitting.hierarchical`
misses the integral by up to 19 log units per setting (measured; see ``tests/test_calibrate.py``). Here it
is estimated by importance sampling, with two sets of points per setting:

* ``nodes`` fixed points drawn once from a proposal :math:`q_g` built at the mode of the joint-normal
  posterior: a multivariate t (4 degrees of freedom) about the setting's draw given its repeats, found by
  :data:`ROUNDS` rounds of adaptive importance sampling, mixed with a share :data:`DEFENSIVE` of the
  population's own distribution at that mode (its scales at least :data:`SCALE_FLOOR`). The points are
  scrambled Sobol draws. The law and its derivatives are evaluated at these points once;
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

__all__ = ["NODES", "WALKER_POINTS", "SettingIntegral"]

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
#: Share of the fixed points drawn from the population at the mode (its scales at least SCALE_FLOOR).
DEFENSIVE = 0.1
#: Smallest setting-to-setting scale the proposal assumes (transformed units).
SCALE_FLOOR = 0.05

_LOG2PI = math.log(2.0 * math.pi)


def _log_normal(Z: np.ndarray, mean: np.ndarray, sd: np.ndarray) -> np.ndarray:
    """Log density of independent normals (mean, sd per axis) at points Z (..., V): (...)."""
    return (-0.5 * ((Z - mean) / sd) ** 2 - np.log(sd) - 0.5 * _LOG2PI).sum(-1)


@jit(nogil=True, inline="always")
def _repeats(y, base, tau2, s2, F, C, a, b):  # pragma: no cover - compiled
    """Sum over bounces a..b-1 of the log normal density of y_i about F_i with covariance
    diag(base_i + tau2) + sum_j s2_j C_ij C_ij^T."""
    total = 0.0
    for i in range(a, b):
        cxx = base[i, 0] + tau2[0]
        cyy = base[i, 1] + tau2[1]
        cww = base[i, 2] + tau2[2]
        cxy = 0.0
        cxw = 0.0
        cyw = 0.0
        for j in range(C.shape[1]):
            jx = C[i, j, 0]
            jy = C[i, j, 1]
            jw = C[i, j, 2]
            cxx += s2[j] * jx * jx
            cyy += s2[j] * jy * jy
            cww += s2[j] * jw * jw
            cxy += s2[j] * jx * jy
            cxw += s2[j] * jx * jw
            cyw += s2[j] * jy * jw
        # determinant and quadratic form by cofactors (as hierarchical._det_quad does for arrays)
        A = cyy * cww - cyw * cyw
        B = cxw * cyw - cxy * cww
        D = cxy * cyw - cxw * cyy
        det = cxx * A + cxy * B + cxw * D
        rx = y[i, 0] - F[i, 0]
        ry = y[i, 1] - F[i, 1]
        rw = y[i, 2] - F[i, 2]
        quad = (A * rx * rx + (cxx * cww - cxw * cxw) * ry * ry + (cxx * cyy - cxy * cxy) * rw * rw
                + 2.0 * (B * rx * ry + D * rx * rw + (cxy * cxw - cxx * cyw) * ry * rw)) / det
        if not (det > 0.0 and quad == quad and quad < math.inf):
            return -math.inf
        total -= 0.5 * (math.log(det) + quad + 3.0 * 1.8378770664093453)
    return total


@jit(nogil=True)
def _setting_kernel(out, ends, y, base, FA, CA, ZA, lqA, FB, CB, ZB, lqB, m, sig, s2, tau2, start, stop
                    ):  # pragma: no cover - compiled
    """log L of walkers start..stop-1: the sum over settings of the log of the mixture estimate (module docs).
    s2 (w, columns of C): the squared scales of C's columns."""
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
                    ll = _repeats(y, base, tau2[w], s2[w], FA[k], CA[k], a, b)
                    lq = lqA[g, k]
                else:
                    ll = _repeats(y, base, tau2[w], s2[w], FB[w, k - K], CB[w, k - K], a, b)
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
def _point_kernel(out, ends, y, base, F, C, tau2, s2):  # pragma: no cover - compiled
    """out[g, k]: the sum over setting g's repeats of log l_i at point k (F (K, n, 3), C (K, n, columns, 3))."""
    for g in range(ends.shape[0] - 1):
        for k in range(F.shape[0]):
            out[g, k] = _repeats(y, base, tau2, s2, F[k], C[k], ends[g], ends[g + 1])


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
        d = Z - self.mean[:, None, :]
        chol = self.chol[:, None, :, :] if Z.ndim == 3 else self.chol[None, :, None, :, :]
        maha = (np.linalg.solve(chol, d[..., None])[..., 0] ** 2).sum(-1)
        logdet = np.log(np.abs(np.diagonal(self.chol, axis1=-2, axis2=-1))).sum(-1)[:, None]
        nu = PROPOSAL_DF
        t = gammaln((nu + V) / 2) - gammaln(nu / 2) - 0.5 * V * math.log(nu * math.pi) - logdet \
            - 0.5 * (nu + V) * np.log1p(maha / nu)
        wide = _log_normal(Z, self.wide_mean, self.wide_sd)
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
        self.V = V = len(post.vary)
        self.nodes = int(nodes)
        self.walker_points = int(walker_points)
        self.ends = np.r_[post._starts, post.n].astype(np.int64)
        self.setting_of = np.repeat(np.arange(len(post._starts)), np.diff(self.ends))
        self.base = np.ascontiguousarray((post.liftoff_var if post.liftoff_var is not None else 0.0)
                                         + post.jitter[None, :] * np.ones((post.n, 1)))
        G = len(post._starts)
        x = np.asarray(x, dtype=float)[None, :]
        m, sig, _, tau = self.split(post, x)
        pop_sd = np.maximum(sig[0], SCALE_FLOOR)
        # rounds of adaptive importance sampling of each setting's draw given its repeats, from the population
        # (its scale at least SCALE_FLOOR); the landing's error at x, no bounce-level spread: enough to place them
        landing = post.landing_columns()
        columns = np.zeros((post.n, 0, 3)) if landing is None else np.ascontiguousarray(landing.transpose(1, 0, 2))
        scales2 = self._scales2(post, np.zeros((1, 0)), x)[0]
        Z = m[0] + pop_sd * rng.standard_normal((G, ROUND_DRAWS, V))
        log_q = _log_normal(Z, m[0], pop_sd)
        for _ in range(ROUNDS):
            repeats = self._at_draws(post, Z, columns, tau[0], scales2)
            lw = _log_normal(Z, m[0], pop_sd) + repeats - log_q
            w, ess = _weights(lw)
            mean = np.einsum("gk,gkv->gv", w, Z)
            d = Z - mean[:, None, :]
            cov = np.einsum("gk,gka,gkb->gab", w, d, d)
            # a setting whose weights sit on a few draws (its draw far in the population's tail): the best
            # RECENTRE draws, unweighted, move the proposal towards it without collapsing it on one point
            few = np.flatnonzero(ess < RECENTRE)
            if few.size:
                best = np.argsort(lw[few], axis=1)[:, -RECENTRE:]
                top = np.take_along_axis(Z[few], best[:, :, None], axis=1)
                mean[few] = top.mean(axis=1)
                dt = top - mean[few][:, None, :]
                cov[few] = np.einsum("gka,gkb->gab", dt, dt) / (RECENTRE - 1)
            # never narrower than a tenth of the population's sd along an axis (a proposal, not an estimate)
            cov = cov + np.eye(V) * (1e-2 * pop_sd ** 2)[None, :, None]
            self.proposal = _Proposal(mean, np.linalg.cholesky(cov), m[0], pop_sd)
            Z = self.proposal.draw(rng, ROUND_DRAWS)
            log_q = self.proposal.log_density(Z)
        self.ZA = np.ascontiguousarray(self.proposal.draw(rng, self.nodes))  # (G, K, V)
        self.lqA = np.ascontiguousarray(self.proposal.log_density(self.ZA))
        F, C = self._points(post, self.ZA[None], post.theta0[None, :])
        self.FA, self.CA = F[0], C[0]
        self.v = rng.standard_normal((G, self.walker_points, V))  # the walker points' standard normals

    # ------------------------------------------------------------------ pieces
    @staticmethod
    def split(post: Any, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Per row of X: transformed population medians m, setting scales sigma, bounce scales s, tau: (w, .)."""
        sigma, s, tau = post.scales_and_tau(X)
        m = np.column_stack([post.transforms[v].forward(X[:, post.free.index(v)]) for v in post.vary])
        return m, sigma, s, tau

    @staticmethod
    def _scales2(post: Any, s: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Squared scales of the columns of C per row of X: the bounce-level scales', then the landing columns'
        (1 where the data state the error: the columns carry it; the fitted noise's otherwise)."""
        lam = post.landing_noise(X)
        if lam is None and post.landing_sd is not None:
            lam = np.ones((len(X), 3))
        return np.ascontiguousarray(s ** 2 if lam is None else np.hstack([s ** 2, lam ** 2]))

    def _points(self, post: Any, Z: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """At points Z (W, G, k, V) of each setting, the law's numbers of row w of ``theta`` (W, P) elsewhere: for
        every bounce of the setting the lift-off (W, k, n, 3) and the columns C (W, k, n, columns, 3) (the
        derivatives with respect to the transformed varying parameters, then the landing's error pushed through
        the law), in one law call."""
        W, k, V, n, step = Z.shape[0], Z.shape[2], self.V, post.n, post.step
        zeta = Z[:, self.setting_of].transpose(0, 2, 1, 3).reshape(-1, V)  # (W k n, V): bounce i's setting's point
        numbers = _with_draws(post, np.repeat(theta, k * n, axis=0), zeta)
        land = np.tile(post.p0, (W * k, 1))
        rows, landings = [numbers], [land]
        for j in range(V):  # forward steps along each varying parameter (transformed)
            rows.append(_with_draws(post, numbers.copy(), zeta + step * np.eye(V)[j]))
            landings.append(land)
        error = post.landing_sd is not None or post.landing_prior is not None
        if error:  # and along each landing component
            h = np.tile(post.h_land, (W * k, 1))
            for c in range(3):
                moved = land.copy()
                moved[:, c] += h[:, c]
                rows.append(numbers)
                landings.append(moved)
        out = _finite_rows(post, np.concatenate(landings), np.concatenate(rows)).reshape(len(rows), -1, 3)
        F = out[0]
        C = (out[1:1 + V] - F) / step
        if error:
            sd = post.landing_sd if post.landing_sd is not None else np.ones((n, 3))
            C = np.concatenate([C, (out[1 + V:] - F) * (np.tile(sd, (W * k, 1)) / h).T[:, :, None]])
        return F.reshape(W, k, n, 3), np.ascontiguousarray(C.transpose(1, 0, 2).reshape(W, k, n, -1, 3))

    def _at_draws(self, post: Any, Z: np.ndarray, columns: np.ndarray, tau: np.ndarray, scales2: np.ndarray
                  ) -> np.ndarray:
        """Sum over each setting's repeats of log l_i at draws Z (G, M, V) with the columns held (the landing's
        error at the mode): (G, M)."""
        M = Z.shape[1]
        zeta = Z[self.setting_of].transpose(1, 0, 2).reshape(-1, self.V)
        numbers = _with_draws(post, np.repeat(post.theta0[None, :], len(zeta), axis=0), zeta)
        F = _finite_rows(post, np.tile(post.p0, (M, 1)), numbers).reshape(M, post.n, 3)
        out = np.empty((len(self.ends) - 1, M))
        _point_kernel(out, self.ends, post.y, self.base, F, np.broadcast_to(columns, (M, *columns.shape)),
                      tau ** 2, scales2)
        return out

    # ------------------------------------------------------------------ the likelihood
    def log_likelihoods(self, post: Any, X: np.ndarray) -> np.ndarray:
        """The log likelihood of each row of X (w, ndim), summed over settings; -inf where it cannot be evaluated."""
        W = len(X)
        m, sig, s, tau = self.split(post, X)
        s2 = self._scales2(post, s, X)
        ok = np.isfinite(m).all(1) & np.isfinite(sig).all(1) & np.isfinite(s2).all(1) & np.isfinite(tau).all(1)
        m = np.where(ok[:, None], m, 0.0)
        sig = np.where(ok[:, None], np.maximum(sig, 1e-12), 1.0)
        ZB = np.ascontiguousarray(m[:, None, None, :] + sig[:, None, None, :] * self.v[None])  # (W, G, K2, V)
        FB, CB = self._points(post, ZB, post._theta(X))
        lqB = np.ascontiguousarray(self.proposal.log_density(ZB))
        out = np.empty(W)
        args = (post.y, self.base, self.FA, self.CA, self.ZA, self.lqA, FB, CB, ZB, lqB, np.ascontiguousarray(m),
                np.ascontiguousarray(sig), s2, np.ascontiguousarray(tau ** 2))

        def part(start: int, stop: int) -> None:
            _setting_kernel(out, self.ends, *args, start, stop)

        run_rows(part, W, min_rows=2, min_part=1)
        return np.where(ok & np.isfinite(out), out, -math.inf)

    def effective_sizes(self, post: Any, x: np.ndarray) -> np.ndarray:
        """Per setting, the effective number of the fixed points at ``x`` (Kish's, from their weights)."""
        x = np.asarray(x, dtype=float)[None, :]
        m, sig, s, tau = self.split(post, x)
        ll = np.empty((len(self.ends) - 1, self.nodes))
        _point_kernel(ll, self.ends, post.y, self.base, self.FA, self.CA, tau[0] ** 2, self._scales2(post, s, x)[0])
        return _weights(_log_normal(self.ZA, m[0], np.maximum(sig[0], 1e-12)) + ll - self.lqA)[1]


def _weights(lw: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Importance weights from log weights (G, k), normalised per setting (a non-finite one counts as zero), and
    their effective number per setting (Kish's, 1 / sum w^2)."""
    lw = np.where(np.isfinite(lw), lw, -np.inf)
    w = np.exp(lw - lw.max(axis=1, keepdims=True))
    w /= w.sum(axis=1, keepdims=True)
    return w, 1.0 / (w ** 2).sum(axis=1)


def _with_draws(post: Any, numbers: np.ndarray, zeta: np.ndarray) -> np.ndarray:
    """``numbers`` (rows of the law's numbers) with the varying parameters set from the transformed draws ``zeta``."""
    for j, name in enumerate(post.vary):
        numbers[:, post.index[name]] = post.transforms[name].inverse(zeta[:, j])
    return numbers


def _finite_rows(post: Any, landing: np.ndarray, numbers: np.ndarray) -> np.ndarray:
    """The law on each landing with its own numbers (``post.rows``); NaN where a number is not finite (a draw far
    out in a transform's tail)."""
    good = np.isfinite(numbers).all(axis=1)
    if good.all():
        return post.rows(landing, numbers)
    out = np.full((len(landing), 3), np.nan)
    if good.any():
        out[good] = post.rows(np.ascontiguousarray(landing[good]), np.ascontiguousarray(numbers[good]))
    return out
