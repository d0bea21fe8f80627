"""Issue 24 item 2 and issue 30 item 1: bouncelab.calibrate - hierarchical calibration (population values,
setting-to-setting and bounce-to-bounce scales, model discrepancy) sampled with emcee; the marginalisation checked
against brute force; the Posterior's predictions of measured bounces, intervals, predictive check (one code path),
saving, validation of saved files and figures; executors."""

from __future__ import annotations

import copy
import itertools
import json
import math
import os
import warnings

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core.errors import BouncelabWarning, DataError, FitError, Hint, ParameterError
from bouncelab.fitting import hierarchical as H
from bouncelab.fitting.hierarchical import ConvergenceWarning, Posterior, calibrate, load_posterior
from bouncelab.fitting.setting_integral import SettingIntegral
from bouncelab.laws import predict_per_bounce

pytest.importorskip("emcee", reason="emcee is not installed (pip install -e '.[bayes]')")

LOGIT = H._Transform.of(0.0, 1.0)


def rigid_rows(landing: np.ndarray, r: np.ndarray, mu: np.ndarray) -> np.ndarray:
    return predict_per_bounce(bl.Rigid, landing, np.column_stack([r, mu]))


# the done-when campaigns: Rigid with r logit-normal and mu log-normal, known measurement noise
R_MED, MU_MED, S_R, S_MU = 0.5, 0.4, 0.25, 0.3
SD_LAND = np.array([4.0, 4.0, 15.0])
SD_LIFT = np.array([5.0, 5.0, 20.0])


def varying_campaign(n: int, seed: int) -> xr.Dataset:
    """Landings over both regimes (about half roll at the medians), per-bounce r and mu (every bounce on its own
    spot), measured with noise."""
    rng = np.random.default_rng(seed)
    land = np.column_stack([rng.uniform(300, 1200, n), rng.uniform(-700, -200, n), rng.uniform(-300, 600, n)])
    r = LOGIT.inverse(LOGIT.forward(R_MED) + S_R * rng.standard_normal(n))
    mu = MU_MED * np.exp(S_MU * rng.standard_normal(n))
    true = rigid_rows(land, r, mu)
    return bl.make_campaign(land + SD_LAND * rng.standard_normal(land.shape),
                            true + SD_LIFT * rng.standard_normal(land.shape),
                            landing_pi=np.tile(1.96 * SD_LAND, (n, 1)), liftoff_pi=np.tile(1.96 * SD_LIFT, (n, 1)))


def spot_campaign(n_settings: int, repeats: int, seed: int, *, intervals: bool = True,
                  draws: bool = False) -> xr.Dataset | tuple[xr.Dataset, np.ndarray]:
    """The paper's design: launcher settings whose repeats land on one spot. Each setting draws its own r
    (logit-normal: median R_MED, scale S_R) and mu (log-normal: MU_MED, S_MU); the repeats' landings scatter about
    the setting's (both regimes occur); landings and lift-offs are measured with known normal errors, stated as 95 %
    intervals when ``intervals``. Settings are labelled by seed, so a fresh campaign's spots are new ones. (The
    campaigns of ``benchmarks/bench_assess.py --coverage``, draw for draw.) With ``draws`` also the settings' own
    draws (n_settings, 2) of logit r and log mu about the population's: what an estimator that saw every draw
    would know."""
    rng = np.random.default_rng(seed)
    base = np.column_stack([rng.uniform(300, 1200, n_settings), rng.uniform(-700, -200, n_settings),
                            rng.uniform(-300, 600, n_settings)])
    n = n_settings * repeats
    land = np.repeat(base, repeats, axis=0) + rng.normal(0.0, [15.0, 15.0, 30.0], (n, 3))
    z = np.column_stack([S_R * rng.standard_normal(n_settings), S_MU * rng.standard_normal(n_settings)])
    z_r, z_mu = np.repeat(z[:, 0], repeats), np.repeat(z[:, 1], repeats)
    true = rigid_rows(land, LOGIT.inverse(LOGIT.forward(R_MED) + z_r), MU_MED * np.exp(z_mu))
    pis = {"landing_pi": np.tile(1.96 * SD_LAND, (n, 1)), "liftoff_pi": np.tile(1.96 * SD_LIFT, (n, 1))} \
        if intervals else {}
    data = bl.make_campaign(land + SD_LAND * rng.standard_normal((n, 3)), true + SD_LIFT * rng.standard_normal((n, 3)),
                            setting=np.repeat(np.arange(n_settings) + 10_000 * seed, repeats), **pis)
    return (data, z) if draws else data


def coverage(post: Posterior, fresh: xr.Dataset, level: float = 0.95,
             n: int = 2000) -> tuple[np.ndarray, pd.DataFrame]:
    """The share of fresh measured lift-offs inside the default intervals: per component over all bounces, and per
    launcher setting (rows) and component."""
    lo, hi = post.interval(fresh.landing.values, level, n=n)
    pf = fresh.liftoff.values
    inside = (pf >= lo) & (pf <= hi)
    by_setting = pd.DataFrame(inside, columns=["xdot", "ydot", "omega"]).groupby(fresh.setting.values).mean()
    return inside.mean(axis=0), by_setting


def _assert_check_is_interval(post: Posterior, fresh: xr.Dataset, share: np.ndarray, n: int = 2000) -> None:
    """check() compares with interval(), by the same code: its shares are the ones computed from interval()."""
    table = post.check(fresh, n=n)
    np.testing.assert_array_equal(table.loc["all", ["xdot", "ydot", "omega"]].to_numpy(dtype=float), share)


# ------------------------------------------------------------------------------ done-when: defaults that cover
@pytest.mark.slow  # about a minute on 2 cores
def test_calibrate_recovers_population_scales_and_covers_fresh_bounces() -> None:
    """Every bounce on its own spot (no launcher settings): one level."""
    data = varying_campaign(400, seed=1)
    post = calibrate(bl.Rigid, data, vary=["r", "mu"], seed=0)
    assert post.converged, post.diagnostics["reason"]
    assert post.levels == ["bounce"]
    med = post.samples.median()
    assert med["r"] == pytest.approx(R_MED, rel=0.05)
    assert med["mu"] == pytest.approx(MU_MED, rel=0.05)
    assert med["scale_r"] == pytest.approx(S_R, rel=0.30)
    assert med["scale_mu"] == pytest.approx(S_MU, rel=0.30)
    fresh = varying_campaign(400, seed=2)
    lo, hi = post.interval(fresh.landing.values, 0.95)  # the default: a measured bounce
    inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
    for k, share in enumerate(inside.mean(axis=0)):
        assert 0.92 <= share <= 0.98, (k, share)
    check = post.check(fresh)  # the same code, by slip/roll class
    assert list(check.index) == ["all", "roll", "slip"]
    np.testing.assert_array_equal(check.loc["all", ["xdot", "ydot", "omega"]].to_numpy(dtype=float),
                                  inside.mean(axis=0))
    assert check.loc["all", "n"] == 400 == check.loc["roll", "n"] + check.loc["slip", "n"]


#: The done-when's campaigns (benchmarks/bench_assess.py --coverage measures the same). Two causes of earlier misses
#: are fixed and stay pinned by fast tests: on seed 3 the joint normal of a setting's repeats at Rigid's slip/roll
#: kink put mu's population median 8-9 % low and xdot's coverage at 0.91 (the setting level is now the
#: importance-sampling integral over its draw: test_importance_setting_likelihood_matches_brute_force_at_the_kink);
#: on seed 1 without interval columns one noise per component stood for a landing error that moves a rolling and a
#: slipping lift-off differently, and omega's interval covered 0.986 (the landing's error is now fitted:
#: test_a_fitted_landing_noise_is_a_stated_landing_error_of_that_size).
#: The coverage is a rate, measured on FRESH_CAMPAIGNS fresh campaigns of 200 new settings x 6 (12,000 bounces): on
#: one such campaign (1,200 bounces) it scatters with a standard deviation of 0.004-0.007 (measured, seed 1 without
#: interval columns), as much as the gap between a good interval and the bound: there omega's share was 0.981 on the
#: first fresh campaign and 0.967-0.983 over ten, 0.975 over all 12,000.
FRESH_CAMPAIGNS = 10


def fresh_campaigns(seed: int, intervals: bool, k: int = FRESH_CAMPAIGNS, settings: int = 200) -> list[xr.Dataset]:
    """``k`` fresh campaigns of ``settings`` new settings x 6 for the campaign of ``seed`` (seeds seed + 1000,
    + 1001, ...)."""
    return [spot_campaign(settings, 6, seed=seed + 1000 + j, intervals=intervals) for j in range(k)]


def pooled_coverage(post: Posterior, fresh: list[xr.Dataset], n: int = 2000
                    ) -> tuple[np.ndarray, pd.Series, np.ndarray]:
    """:func:`coverage` over fresh campaigns of one size: the share of all their bounces per component, its mean
    over all their settings, and each campaign's share (k, 3)."""
    shares = [coverage(post, f, n=n) for f in fresh]
    each = np.array([share for share, _ in shares])
    return each.mean(axis=0), pd.concat([by for _, by in shares]).mean(), each


@pytest.mark.long  # 1.5-3 minutes each on 2 cores; benchmarks/bench_assess.py --coverage measures the same
@pytest.mark.parametrize(("seed", "intervals"), [(1, True), (1, False), (3, True), (3, False)],
                         ids=["1-intervals", "1-no-intervals", "3-intervals", "3-no-intervals"])
def test_setting_level_recovers_population_and_covers_fresh_bounces_on_new_spots(seed: int, intervals: bool) -> None:
    """Issue 30's done-when: r and mu vary by launcher setting, the repeats share a spot. With defaults, the population
    medians come back within 5 % (and the posterior's 95 % intervals of them hold the generating values), and the
    default 95 % intervals cover 92-98 % of fresh measured bounces on new spots, per component, overall and averaged
    over the fresh settings; check() is interval(). Without interval columns (where the default interval covered
    61 % while check() said 89 %) the same."""
    data = spot_campaign(100, 6, seed=seed, intervals=intervals)
    post = calibrate(bl.Rigid, data, vary=["r", "mu"], seed=0)
    assert post.converged, post.diagnostics["reason"]
    assert post.levels == ["setting", "bounce"]
    assert post.residual == ("discrepancy" if intervals else "noise")
    q = post.samples[["r", "mu"]].quantile([0.025, 0.5, 0.975])
    assert q.loc[0.5, "r"] == pytest.approx(R_MED, rel=0.05)
    assert q.loc[0.5, "mu"] == pytest.approx(MU_MED, rel=0.05)
    assert q.loc[0.025, "r"] <= R_MED <= q.loc[0.975, "r"] and q.loc[0.025, "mu"] <= MU_MED <= q.loc[0.975, "mu"]
    scales = post.scales()
    assert scales.loc["r", "setting"] > 5 * scales.loc["r", "bounce"]  # the spread is the settings'
    assert scales.loc["r", "new_spot_low"] <= S_R <= scales.loc["r", "new_spot_high"]
    fresh = fresh_campaigns(seed, intervals)
    share, by_setting, each = pooled_coverage(post, fresh)
    assert ((0.92 <= share) & (share <= 0.98)).all(), share
    assert by_setting.between(0.92, 0.98).all(), by_setting
    _assert_check_is_interval(post, fresh[0], each[0])
    if not intervals:
        with pytest.raises(FitError) as e:  # the noise-free lift-off: the data cannot separate it
            post.interval(fresh[0].landing.values[:3], measurement_error=False)
        assert e.value.option == "measurement_error"


def _truth() -> Posterior:
    """A Posterior whose every sample is the known process of spot_campaign (no sampling): what a perfect calibration
    would give."""
    law = bl.Rigid(r=R_MED, mu=MU_MED)
    samples = pd.DataFrame({"r": [R_MED], "mu": [MU_MED], "setting_scale_r": [S_R], "setting_scale_mu": [S_MU],
                            "scale_r": [1e-9], "scale_mu": [1e-9], "discrepancy_xdot": [1e-9],
                            "discrepancy_ydot": [1e-9], "discrepancy_omega": [1e-9]})
    return Posterior(law=law, free=["r", "mu"], vary=["r", "mu"],
                     transforms={"r": LOGIT, "mu": H._Transform.of(0.0, math.inf)}, samples=samples,
                     diagnostics={"autocorr": [1.0] * 9, "rhat": [1.0] * 9}, residual="discrepancy", with_tau=True,
                     measurement={"landing_sd": SD_LAND.tolist(), "liftoff_sd": SD_LIFT.tolist()}, n_bounces=1,
                     levels=["setting", "bounce"])


def test_default_interval_of_the_true_process_covers_fresh_measured_bounces() -> None:
    """The quick version of the done-when's coverage (no sampling): a posterior holding the true process gives default
    95 % intervals that cover 92-98 % of fresh measured bounces on new spots, and check() is interval(). Leaving out
    the setting level's spread (the old likelihood's view of repeats as spots of their own does not reach it) or the
    measurement error (the old default) covers fewer."""
    truth = _truth()
    fresh = spot_campaign(100, 6, seed=6)
    share, by_setting = coverage(truth, fresh, n=1000)
    assert ((0.92 <= share) & (share <= 0.98)).all(), share
    assert by_setting.mean().between(0.92, 0.98).all()
    _assert_check_is_interval(truth, fresh, share, n=1000)
    narrow = Posterior(**{**truth.__dict__, "samples": truth.samples.assign(setting_scale_r=0.5 * S_R,
                                                                           setting_scale_mu=0.5 * S_MU)})
    assert coverage(narrow, fresh, n=1000)[0].min() < 0.9
    lo, hi = truth.interval(fresh.landing.values, n=1000, measurement_error=False)
    inside = (fresh.liftoff.values >= lo) & (fresh.liftoff.values <= hi)
    assert (inside.mean(axis=0) < share).all()


def test_woodbury_likelihood_is_the_joint_normal_of_each_setting() -> None:
    """The setting level's likelihood (Woodbury, one small matrix per setting) is the joint normal density of each
    setting's lift-offs with covariance D + W W^T, built here in full."""
    from scipy.stats import multivariate_normal

    data = spot_campaign(4, 3, seed=8)
    p0, pf = data.landing.values, data.liftoff.values
    post = H._LogPosterior(bl.Rigid(r=0.5, mu=0.4), p0, pf, free=["r", "mu"], vary=["r", "mu"],
                           box={"r": (0.0, 1.0), "mu": (0.0, 1.5)}, landing_sd=np.tile(SD_LAND, (12, 1)),
                           liftoff_sd=np.tile(SD_LIFT, (12, 1)), with_tau=True, tau_prior=np.full(3, 100.0),
                           groups=data.setting.values)
    x = np.array([0.5, 0.4, 0.25, 0.3, 0.05, 0.08, 2.0, 2.0, 5.0])  # medians, scales, discrepancies
    mean, _, cov, shared, _ = post._moments(x[None])
    full = np.zeros((36, 36))
    xx, yy, ww, xy, xw, yw = (c[0] for c in cov)
    for i in range(12):
        full[3 * i:3 * i + 3, 3 * i:3 * i + 3] = [[xx[i], xy[i], xw[i]], [xy[i], yy[i], yw[i]], [xw[i], yw[i], ww[i]]]
    edges = [*post._starts, 12]
    for a, b in itertools.pairwise(edges):
        block = shared[0][:, a:b].reshape(shared.shape[1], -1)
        full[3 * a:3 * b, 3 * a:3 * b] += block.T @ block
    expected = multivariate_normal(mean[0].ravel(), full).logpdf(post.y.ravel())
    assert post.log_likelihood(x) == pytest.approx(expected, rel=1e-12)
    assert len(edges) - 1 == 4 and post.levels == ("setting", "bounce")


def test_nodes_are_chosen_at_the_mode() -> None:
    """nodes=None takes the fewest Hermite nodes that give the posterior's shape about the mode as 7 do: a law smooth on
    the scale of the spread (r of bounces that all slip: the lift-off is smooth in r) needs 3; mu of bounces that
    slip for some spots and roll for others (a kink) keeps 7."""
    rng = np.random.default_rng(0)
    # every bounce slips whatever its spot's r (fast, with topspin): the lift-off is smooth in r
    land = np.repeat(np.column_stack([rng.uniform(1300, 1700, 20), rng.uniform(-600, -400, 20),
                                      rng.uniform(200, 400, 20)]), 4, axis=0)
    r = np.repeat(LOGIT.inverse(0.25 * rng.standard_normal(20)), 4)
    lift = rigid_rows(land, r, np.full(80, 0.4)) + SD_LIFT * rng.standard_normal((80, 3))
    assert set(bl.Rigid(r=0.3, mu=0.4).regime(land)) == set(bl.Rigid(r=0.7, mu=0.4).regime(land)) == {"slip_forward"}
    common = {"box": {"r": (0.0, 1.0), "mu": (0.0, 1.5)}, "landing_sd": None, "liftoff_sd": np.tile(SD_LIFT, (80, 1)),
              "with_tau": False, "tau_prior": np.ones(3), "groups": np.repeat(np.arange(20), 4)}
    smooth = H._LogPosterior(bl.Rigid(r=0.5, mu=0.4), land, lift, free=["r"], vary=["r"], **common)
    mode = np.array([0.5, 0.25, 0.01])
    assert H._fewest_nodes(smooth, mode, np.diag([0.02, 0.03, 0.005]), rng).nodes == 3
    data = spot_campaign(20, 4, seed=9)
    p0, pf = data.landing.values, data.liftoff.values
    common["groups"] = data.setting.values
    kinked = H._LogPosterior(bl.Rigid(r=0.5, mu=0.4), p0, pf, free=["r", "mu"], vary=["r", "mu"], **common)
    mode = np.array([0.5, 0.4, 0.25, 0.3, 0.01, 0.01])
    chosen = H._fewest_nodes(kinked, mode, np.diag([0.02, 0.03, 0.03, 0.03, 0.005, 0.005]), rng)
    assert chosen.nodes == 7 and chosen is kinked
    assert kinked.with_nodes(3).nodes == 3 and kinked.nodes == 7  # a copy: the original keeps its rule


def test_shared_part_matches_monte_carlo() -> None:
    """The split of a bounce's spread into the part the repeats of its setting share (Mehler: order k of the Hermite
    expansion correlates as rho^2k) against Monte Carlo draws of the two-level model: two repeats' covariance and
    each one's variance."""
    rng = np.random.default_rng(0)
    land = np.array([[900.0, -450.0, 100.0], [880.0, -470.0, 130.0]])  # near the slip/roll boundary: a kink
    post = H._LogPosterior(bl.Rigid(r=0.5, mu=0.4), land, np.zeros((2, 3)), free=["r", "mu"], vary=["r", "mu"],
                           box={"r": (0.0, 1.0), "mu": (0.0, 1.5)}, landing_sd=None, liftoff_sd=np.ones((2, 3)),
                           with_tau=False, tau_prior=np.ones(3), groups=np.array([1, 1]), nodes=9)
    sigma, s = np.array([0.25, 0.3]), np.array([0.1, 0.15])
    x = np.r_[0.5, 0.4, sigma, s]
    mean, _, cov, shared, _ = post._moments(x[None])
    n = 400_000
    v = rng.standard_normal((n, 1, 2))
    z = v * sigma + rng.standard_normal((n, 2, 2)) * s
    out = rigid_rows(np.tile(land, (n, 1)), LOGIT.inverse(LOGIT.forward(0.5) + z[..., 0]).ravel(),
                     (0.4 * np.exp(z[..., 1])).ravel()).reshape(n, 2, 3)
    cross_mc = ((out[:, 0] - out[:, 0].mean(0))[:, :, None] * (out[:, 1] - out[:, 1].mean(0))[:, None, :]).mean(0)
    W = shared[0]
    cross = W[:, 0].T @ W[:, 1]
    var = np.array([cov[0][0, 0] - 1.0, cov[1][0, 0] - 1.0, cov[2][0, 0] - 1.0]) + np.diag(W[:, 0].T @ W[:, 0])
    scale = np.sqrt(np.diag(np.cov(out[:, 0], rowvar=False)))
    assert np.abs(cross - cross_mc).max() / scale.max() ** 2 < 0.05  # the axes' interaction is left out
    np.testing.assert_allclose(var, out[:, 0].var(axis=0), rtol=0.06)
    np.testing.assert_allclose(mean[0], out.mean(axis=0), atol=0.02 * scale.max())


# ------------------------------------------------------------------------------ the approximation vs brute force
@pytest.fixture(scope="module")
def small_case():
    """15 bounces over both regimes, r varying (logit-normal, scale 0.3), mu known, lift-offs measured with noise."""
    rng = np.random.default_rng(5)
    n = 15
    land = np.column_stack([rng.uniform(300, 1200, n), rng.uniform(-700, -200, n), rng.uniform(-300, 600, n)])
    r = LOGIT.inverse(LOGIT.forward(0.5) + 0.3 * rng.standard_normal(n))
    sd = np.array([3.0, 3.0, 10.0])
    lift = rigid_rows(land, r, np.full(n, 0.4)) + sd * rng.standard_normal(land.shape)
    data = bl.make_campaign(land, lift, landing_pi=np.zeros((n, 3)), liftoff_pi=np.tile(1.96 * sd, (n, 1)))
    return data, land, lift, sd


def _grid_posterior(loglike, mr: np.ndarray, ls: np.ndarray) -> tuple[float, float, float]:
    """Posterior median of the population median of r and of the scale, and the sd of the former, on a grid
    (uniform prior on the median, half-normal(1) prior on the scale, as calibrate's)."""
    grid = getattr(loglike, "grid", None)  # a whole grid in one batched call, where the log likelihood offers it
    values = grid(mr, ls) if grid is not None else np.array([[loglike(a, b) for b in ls] for a in mr])
    table = values + (ls - 0.5 * np.exp(ls) ** 2)[None, :]
    p = np.exp(table - table.max())
    p /= p.sum()
    pm, ps = p.sum(axis=1), p.sum(axis=0)
    sd = math.sqrt(float((pm * mr ** 2).sum() - (pm * mr).sum() ** 2))
    return float(np.interp(0.5, np.cumsum(pm), mr)), float(np.exp(np.interp(0.5, np.cumsum(ps), ls))), sd


def _brute_loglike(land: np.ndarray, lift: np.ndarray, sd: np.ndarray):
    """Log-likelihood of (median, log scale) integrating each bounce's own r exactly (80-point Gauss-Hermite):
    no linearisation, the law called at every node."""
    nodes, weights = np.polynomial.hermite_e.hermegauss(80)
    weights = weights / weights.sum()
    n = len(land)

    def loglike(m_r: float, log_s: float) -> float:
        r = LOGIT.inverse(LOGIT.forward(m_r) + math.exp(log_s) * nodes)
        pred = rigid_rows(np.repeat(land, len(r), axis=0), np.tile(r, n), np.full(n * len(r), 0.4))
        res = (lift[:, None, :] - pred.reshape(n, len(r), 3)) / sd
        logn = -0.5 * (res ** 2).sum(-1) - np.log(sd).sum() - 1.5 * math.log(2 * math.pi)
        top = logn.max(axis=1, keepdims=True)
        return float((top[:, 0] + np.log((np.exp(logn - top) * weights).sum(axis=1))).sum())

    def grid(mr: np.ndarray, ls: np.ndarray) -> np.ndarray:  # the same, every grid point in one law call
        z = LOGIT.forward(mr)[:, None, None] + np.exp(ls)[None, :, None] * nodes[None, None, :]  # (a, b, node)
        r = LOGIT.inverse(z).ravel()
        pred = rigid_rows(np.tile(land, (len(r), 1)), np.repeat(r, n), np.full(n * len(r), 0.4))
        res = (lift[None, :, :] - pred.reshape(len(r), n, 3)) / sd
        logn = (-0.5 * (res ** 2).sum(-1) - np.log(sd).sum() - 1.5 * math.log(2 * math.pi)).reshape(
            len(mr), len(ls), len(nodes), n)
        top = logn.max(axis=2, keepdims=True)
        return (top[:, :, 0] + np.log((np.exp(logn - top) * weights[:, None]).sum(axis=2))).sum(axis=-1)

    loglike.grid = grid  # type: ignore[attr-defined]
    return loglike


def _approx_loglike(land, lift, sd, approximation):
    post = H._LogPosterior(bl.Rigid(r=0.5, mu=0.4), land, lift, free=["r"], vary=["r"], box={"r": (0.0, 1.0)},
                           landing_sd=None, liftoff_sd=np.tile(sd, (len(land), 1)), with_tau=False,
                           tau_prior=np.ones(3), approximation=approximation)
    def loglike(a: float, b: float) -> float:  # b: the scale's logarithm
        return post.log_likelihood(np.array([a, math.exp(b)]))

    def grid(mr: np.ndarray, ls: np.ndarray) -> np.ndarray:
        a, b = np.meshgrid(mr, ls, indexing="ij")
        return post.log_likelihoods(np.column_stack([a.ravel(), np.exp(b.ravel())])).reshape(len(mr), len(ls))

    loglike.grid = grid  # type: ignore[attr-defined]
    return loglike


def test_marginal_likelihood_against_brute_force(small_case) -> None:
    """On 15 bounces with r varying (one level), against a brute-force integration over each bounce's own r: the
    Hermite rule (default; its moments converge with the nodes: 5, 7, 9 and 11 nodes give the same) puts the posterior
    median of the population median of r 0.42 posterior sd from the brute force and the scale within 2 %: what is
    left is the normal shape of the approximation. The 3-point rule (unscented) lands within a tenth of a sd (its
    errors cancel here; on settings with repeats near a kink they do not: see the module documentation), the plain
    linearisation 2.6 sd off."""
    _, land, lift, sd = small_case
    assert set(bl.Rigid(r=0.5, mu=0.4).regime(land)) == {"roll", "slip_forward"}
    mr = np.linspace(0.40, 0.60, 61)
    ls = np.linspace(math.log(0.05), math.log(1.2), 61)
    m_b, s_b, sd_b = _grid_posterior(_brute_loglike(land, lift, sd), mr, ls)
    m_u, s_u, _ = _grid_posterior(_approx_loglike(land, lift, sd, "unscented"), mr, ls)
    m_h, s_h, _ = _grid_posterior(_approx_loglike(land, lift, sd, "hermite"), mr, ls)
    m_l, _, _ = _grid_posterior(_approx_loglike(land, lift, sd, "linear"), mr, ls)
    assert abs(m_u - m_b) < 0.1 * sd_b
    assert s_u == pytest.approx(s_b, rel=0.10)
    assert abs(m_h - m_b) < 0.5 * sd_b
    assert s_h == pytest.approx(s_b, rel=0.05)
    assert abs(m_l - m_b) > 2 * sd_b


@pytest.mark.slow  # about 10 s
def test_sampler_reproduces_the_grid_posterior(small_case) -> None:
    data, land, lift, sd = small_case
    mr = np.linspace(0.40, 0.60, 61)
    ls = np.linspace(math.log(0.05), math.log(1.2), 61)
    m_u, s_u, sd_u = _grid_posterior(_approx_loglike(land, lift, sd, "hermite"), mr, ls)
    m_b, s_b, _ = _grid_posterior(_brute_loglike(land, lift, sd), mr, ls)
    # nodes=7: the grid's rule (nodes=None may choose fewer at the mode, which is another posterior)
    post = calibrate(bl.Rigid(r=0.5, mu=0.4), data, vary=["r"], fixed={"mu": 0.4}, discrepancy=False, seed=1,
                     nodes=7)
    assert post.converged
    med = post.samples.median()
    assert abs(med["r"] - m_u) < 0.15 * sd_u  # emcee samples the posterior it is given
    assert med["scale_r"] == pytest.approx(s_u, rel=0.05)
    assert abs(med["r"] - m_b) < 0.6 * sd_u  # and that posterior is the brute-force one, within the tolerance above
    assert med["scale_r"] == pytest.approx(s_b, rel=0.15)


def _setting_loglikes(post: H._LogPosterior, x: np.ndarray, *, importance: bool = False
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Per launcher setting of a Rigid two-level posterior, at ``x`` with both bounce-level scales zero: the log
    likelihood of the approximation (the joint normal per setting, or with ``importance`` the importance-sampling
    integral over the setting's draw built at ``x``) and a brute-force one, the product of the repeats' normal
    densities (the model's own per-bounce covariance D_i) integrated over the setting's draw on a grid: in r over
    +-12 sd about the value the setting's ydot pins (ydot_F = -r ydot_0), in mu over +-7 setting scales in steps of
    0.01 (the brute force agrees with a grid twice as fine). The brute force holds the landing error's derivative
    where ``post`` holds it, so a posterior with landing errors is compared with the joint normal only."""
    from scipy.special import logsumexp

    assert x[4] == x[5] == 0.0
    assert not (importance and post.landing_sd is not None)
    r_med, mu_med, sig_r, sig_mu = x[:4]
    land = post.landing_entries(x[None]) if post.landing_columns() is not None else [np.zeros(post.n)] * 6
    d = [c.copy() for c in land]
    for c in range(3):
        d[c] = d[c] + post.liftoff_var[:, c] + x[6 + c] ** 2 + post.jitter[c]
    vm = np.linspace(-7.0, 7.0, 1401)
    approx, brute = [], []
    for a, b in itertools.pairwise([*post._starts, post.n]):
        one = copy.copy(post)  # the same posterior on this setting's repeats only
        one.p0, one.y, one.n, one._starts = post.p0[a:b], post.y[a:b], b - a, np.array([0])
        one.liftoff_var, one.h_land = post.liftoff_var[a:b], post.h_land[a:b]
        one._land_cols = None if post.landing_columns() is None else post.landing_columns()[:, a:b]
        if importance:
            one.setting_integral = SettingIntegral(one, x)
        approx.append(one.log_likelihood(x))
        p, y = post.p0[a:b], post.y[a:b]
        r_hat = -(y[:, 1] @ p[:, 1]) / (p[:, 1] @ p[:, 1])
        half = 12 * math.sqrt(d[1][a:b].max() / (p[:, 1] @ p[:, 1]))
        zr = np.linspace(LOGIT.forward(max(r_hat - half, 1e-6)), LOGIT.forward(min(r_hat + half, 1 - 1e-6)), 81)
        vr = (zr - LOGIT.forward(r_med)) / sig_r
        r, mu = np.meshgrid(LOGIT.inverse(zr), mu_med * np.exp(sig_mu * vm), indexing="ij")
        log_w = (-0.5 * vr ** 2 + math.log((vr[1] - vr[0]) / (2 * math.pi)))[:, None] + \
            (-0.5 * vm ** 2 + math.log(vm[1] - vm[0]))[None, :]
        f = rigid_rows(np.repeat(p, r.size, axis=0), np.tile(r.ravel(), b - a), np.tile(mu.ravel(), b - a))
        det, quad = H._det_quad([c[a:b, None, None] for c in d], y[:, None, None, :] - f.reshape(b - a, *r.shape, 3))
        repeats = (-0.5 * (np.log(det) + quad + 3 * math.log(2 * math.pi))).sum(axis=0)
        brute.append(float(logsumexp(repeats + log_w)))
    return np.array(approx), np.array(brute)


def _two_level(landing: np.ndarray, liftoff: np.ndarray, setting: np.ndarray, *, landing_error: bool = True
               ) -> H._LogPosterior:
    n = len(landing)
    return H._LogPosterior(bl.Rigid(r=R_MED, mu=MU_MED), landing, liftoff, free=["r", "mu"], vary=["r", "mu"],
                           box={"r": (0.0, 1.0), "mu": (0.0, 1.5)},
                           landing_sd=np.tile(SD_LAND, (n, 1)) if landing_error else None,
                           liftoff_sd=np.tile(SD_LIFT, (n, 1)), with_tau=True, tau_prior=np.full(3, 100.0),
                           groups=setting)


#: The process of spot_campaign, its bounce-level scales and discrepancy zero (1e-3: the covariance stays proper).
_TRUE_X = np.array([R_MED, MU_MED, S_R, S_MU, 0.0, 0.0, 1e-3, 1e-3, 1e-3])


def test_setting_likelihood_matches_brute_force_away_from_the_kink() -> None:
    """Settings whose repeats roll whatever their draw (contact point at rest: the lift-off is r-linear in ydot and
    does not depend on mu): the joint normal of each setting's repeats is the brute-force integral over the setting's
    draw, within 0.05 per setting (measured: at most 0.03). The check of the brute force the kink tests rest on."""
    rng = np.random.default_rng(4)
    xy = np.repeat(np.column_stack([rng.uniform(300, 1200, 8), rng.uniform(-700, -200, 8)]), 6, axis=0)
    xy = xy + rng.normal(0.0, 15.0, xy.shape)
    land = np.column_stack([xy, -xy[:, 0]])
    assert set(bl.Rigid(r=0.01, mu=0.02).regime(land)) == set(bl.Rigid(r=1.0, mu=5.0).regime(land)) == {"roll"}
    true = rigid_rows(land, np.repeat(LOGIT.inverse(S_R * rng.standard_normal(8)), 6), np.full(48, MU_MED))
    post = _two_level(land + SD_LAND * rng.standard_normal(land.shape), true + SD_LIFT * rng.standard_normal((48, 3)),
                      np.repeat(np.arange(8), 6))
    approx, brute = _setting_loglikes(post, _TRUE_X)
    assert np.abs(approx - brute).max() < 0.05, approx - brute


def _kink_case(landing_error: bool) -> H._LogPosterior:
    data = spot_campaign(8, 6, seed=9)
    p0 = data.landing.values
    lo, hi = bl.Rigid(r=R_MED, mu=MU_MED * math.exp(-2 * S_MU)), bl.Rigid(r=R_MED, mu=MU_MED * math.exp(2 * S_MU))
    assert np.mean(lo.regime(p0) != hi.regime(p0)) > 0.3  # many repeats change regime within +-2 setting scales
    return _two_level(p0, data.liftoff.values, data.setting.values, landing_error=landing_error)


def test_joint_normal_misses_the_setting_likelihood_at_the_kink() -> None:
    """Why the setting level is integrated by importance sampling (calibrate's default where it applies): on
    settings whose repeats slip for some of the setting's draws and roll for others, the joint normal of a setting's
    repeats is not their distribution. Measured on spot_campaign(8, 6, seed=9) at the true process, joint normal
    minus brute force per setting: -2.24, -2.19, -2.21, +0.59, -18.59, +1.34, -0.79, -0.33 (on the 100-setting
    campaign of seed 3 it is 137 in all, and puts mu's population median 8-9 % low)."""
    approx, brute = _setting_loglikes(_kink_case(True), _TRUE_X)
    assert (approx - brute).min() < -10.0, approx - brute


@pytest.mark.parametrize("x", [_TRUE_X, np.array([0.45, 0.5, 0.35, 0.2, 0.0, 0.0, 2.0, 1.0, 6.0])],
                         ids=["truth", "elsewhere"])
def test_importance_setting_likelihood_matches_brute_force_at_the_kink(x) -> None:
    """The importance-sampling integral over each setting's draw is the brute-force integral on the settings where
    the joint normal misses by up to 18.6: within 0.3 per setting (measured at the truth: at most 0.11 over four
    seeds of the points; the joint normal on the same settings without landing errors: -19.1 at worst)."""
    approx, brute = _setting_loglikes(_kink_case(False), x, importance=True)
    assert np.abs(approx - brute).max() < 0.3, approx - brute


@pytest.mark.slow  # about 20 s: a brute-force integral over 100 settings at three scales
def test_importance_likelihood_of_a_whole_campaign_matches_brute_force() -> None:
    """Over the 100 settings of the done-when's campaign of seed 1 (the one whose coverage sits at the edge), the
    importance-sampling likelihood, placed once as calibrate places it, is the brute-force one within 0.5 log units
    in all (measured 0.07-0.31) at mu's setting scale 0.28-0.42; both rise from the generating 0.3 to 0.37: this
    campaign's data point to the larger scale (its 100 draws of mu have sd 0.340), so its intervals for settings
    drawn with 0.3 are wide by the data, not by the integral."""
    data = spot_campaign(100, 6, seed=1)
    post = _two_level(data.landing.values, data.liftoff.values, data.setting.values, landing_error=False)
    placed = _TRUE_X.copy()
    placed[3] = 0.37
    post.setting_integral = SettingIntegral(post, placed, seed=0)
    approx, brute = {}, {}
    for s_mu in (0.28, 0.30, 0.37, 0.42):
        x = _TRUE_X.copy()
        x[3] = s_mu
        approx[s_mu] = post.log_likelihood(x)
        integral, post.setting_integral = post.setting_integral, None
        brute[s_mu] = _setting_loglikes(post, x)[1].sum()
        post.setting_integral = integral
        assert abs(approx[s_mu] - brute[s_mu]) < 0.5, (s_mu, approx[s_mu] - brute[s_mu])
    for ll in (approx, brute):
        assert ll[0.37] > ll[0.30] + 1.0 and ll[0.37] > max(ll[0.28], ll[0.42])


def test_importance_setting_likelihood_at_a_vanishing_setting_scale() -> None:
    """As the setting scales go to zero every repeat of a setting takes the population values: the integral is the
    product of the repeats' densities there (the points drawn from each evaluated population carry it; the fixed
    points cannot), to 1e-8 relative."""
    post = _kink_case(False)
    x = _TRUE_X.copy()
    post.setting_integral = SettingIntegral(post, x)
    x[2:4] = 1e-9
    f = rigid_rows(post.p0, np.full(post.n, x[0]), np.full(post.n, x[1]))
    var = post.liftoff_var + x[6:9] ** 2 + post.jitter
    direct = (-0.5 * ((post.y - f) ** 2 / var + np.log(2 * math.pi * var))).sum()
    assert post.log_likelihood(x) == pytest.approx(direct, rel=1e-8)


@pytest.mark.parametrize("importance", [False, True], ids=["joint-normal", "importance"])
def test_a_negative_scale_has_no_likelihood(importance) -> None:
    """Scales, discrepancies and landing noises are standard deviations: a row with a negative one has log
    likelihood -inf in both paths (not the likelihood of its square, nor of zero), as one with NaN does."""
    post = _kink_case(True)
    if importance:
        post.setting_integral = SettingIntegral(post, _TRUE_X)
    X = np.tile(_TRUE_X, (5, 1))
    X[1, 2], X[2, 4], X[3, 6], X[4, 0] = -0.1, -0.01, -1.0, np.nan
    out = post.log_likelihoods(X)
    assert np.isfinite(out[0]) and (out[1:] == -math.inf).all(), out


def test_effective_fixed_points_say_where_the_fixed_points_reach() -> None:
    """The diagnostic of the fixed points (Kish's effective number per setting): many at the process they were
    placed for (measured 17-73 of 128), one where the population is far narrower than the proposal, where the
    points drawn from each evaluated population carry the integral (the vanishing-scale test checks that)."""
    post = _kink_case(False)
    integral = SettingIntegral(post, _TRUE_X)
    placed = integral.effective_sizes(post, _TRUE_X)
    assert placed.shape == (8,) and (placed > 10).all() and (placed <= integral.nodes).all(), placed
    narrow = _TRUE_X.copy()
    narrow[2:4] = 1e-3
    np.testing.assert_allclose(integral.effective_sizes(post, narrow), 1.0, atol=0.01)


def test_importance_setting_likelihood_does_not_depend_on_threads() -> None:
    """Walkers are independent rows of the compiled estimate: the same bits on one thread as on two."""
    from bouncelab.core import _parallel

    post = _kink_case(True)
    post.setting_integral = SettingIntegral(post, _TRUE_X)
    X = _TRUE_X + np.abs(np.random.default_rng(0).normal(0.0, 0.02, (6, len(_TRUE_X))))
    before = _parallel.num_threads()
    try:
        _parallel.set_num_threads(1)
        one = post.log_likelihoods(X)
        _parallel.set_num_threads(2)
        two = post.log_likelihoods(X)
    finally:
        _parallel.set_num_threads(before)
    assert np.isfinite(one).all()
    np.testing.assert_array_equal(one, two)


def test_calibrate_chooses_the_setting_integral() -> None:
    """setting_integral="auto" integrates by importance sampling where every free parameter varies, else the joint
    normal (named in the diagnostics); "importance" where it cannot apply is a FitError naming the option."""
    data = spot_campaign(6, 3, seed=11)
    with pytest.warns(ConvergenceWarning):
        auto = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=20, seed=0)
    assert auto.diagnostics["setting_integral"].startswith("importance sampling (128 fixed points")
    with pytest.warns(ConvergenceWarning):
        some = calibrate(bl.Rigid, data, vary=["r"], steps=10, walkers=20, seed=0)
    assert some.diagnostics["setting_integral"] == "joint normal"
    with pytest.warns(ConvergenceWarning):
        normal = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=20, seed=0, setting_integral="normal")
    assert normal.diagnostics["setting_integral"] == "joint normal"
    with pytest.raises(FitError) as e:
        calibrate(bl.Rigid, data, vary=["r"], steps=10, seed=0, setting_integral="importance")
    assert e.value.option == "setting_integral" and "['mu'] do not vary" in str(e.value)
    with pytest.raises(FitError) as e:
        calibrate(bl.Rigid, data, vary=["r"], setting_integral="exact")
    assert e.value.option == "setting_integral"
    # a rule chosen for the joint normal keeps it under "auto", and conflicts with "importance"
    with pytest.warns(ConvergenceWarning):
        chosen = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=20, seed=0, nodes=5)
    assert chosen.diagnostics["setting_integral"] == "joint normal" and chosen.diagnostics["approximation"] == \
        "hermite (5 nodes)"
    with pytest.raises(FitError, match="approximation= and nodes="):
        calibrate(bl.Rigid, data, vary=["r", "mu"], approximation="linear", setting_integral="importance")
    # no setting level: nothing to integrate, said as such
    with pytest.warns(ConvergenceWarning):
        one = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=20, seed=0, by="bounce")
    assert one.diagnostics["setting_integral"] == "none (one level)"
    with pytest.raises(FitError, match="no setting level"):
        calibrate(bl.Rigid, data, vary=["r", "mu"], by="bounce", setting_integral="importance")


# ------------------------------------------------------------------------------ the Posterior
@pytest.fixture(scope="module")
def quick_posterior():
    """A short run (not converged: it warns) - enough to test what a Posterior does with its samples."""
    data = varying_campaign(60, seed=7).assign_coords(setting=("bounce", np.repeat(np.arange(12), 5)))
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        post = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=60, walkers=20, seed=2)
    return post, data


def test_posterior_summary_report_and_population(quick_posterior) -> None:
    post, _ = quick_posterior
    assert isinstance(post, Posterior) and not post.converged
    assert post.levels == ["setting", "bounce"]  # 12 launcher settings of 5 repeats: both levels
    assert list(post.samples.columns) == ["r", "mu", "setting_scale_r", "setting_scale_mu", "scale_r", "scale_mu",
                                          "discrepancy_xdot", "discrepancy_ydot", "discrepancy_omega"]
    assert (post.samples[["setting_scale_r", "scale_r", "scale_mu", "discrepancy_xdot"]] > 0).all().all()  # values
    table = post.summary()
    assert list(table.columns) == ["median", "mean", "sd", "low", "high", "autocorr", "rhat"]
    assert (table["low"] <= table["median"]).all() and (table["median"] <= table["high"]).all()
    d = post.diagnostics
    assert d["steps"] == 60 and d["burn"] == 20 and d["walkers"] == 20 and 0 < d["acceptance"] < 1
    assert len(d["autocorr"]) == len(d["rhat"]) == 9
    # every free parameter varies: the setting level is the importance-sampling integral over its draw
    assert d["approximation"].startswith("importance sampling over each setting's draw")
    assert d["setting_integral"].startswith("importance sampling (128 fixed points per setting")
    scales = post.scales()
    assert list(scales.index) == ["r", "mu"]
    assert list(scales.columns) == [f"{k}{e}" for k in ("setting", "bounce", "new_spot") for e in ("", "_low", "_high")]
    new_spot = np.hypot(post.samples["setting_scale_r"], post.samples["scale_r"]).median()
    assert scales.loc["r", "new_spot"] == pytest.approx(new_spot)  # a new spot varies by both levels
    pop = post.population
    assert isinstance(pop, bl.Rigid)
    assert pop.r == pytest.approx(post.samples["r"].median()) and pop.mu == pytest.approx(post.samples["mu"].median())
    text = str(post)
    for part in ("[[Calibration]] Rigid on 60 bounces", "logit-normal within [0, 1]", "log-normal above 0",
                 "[[Posterior]]", "NOT CONVERGED", "from setting to setting", "[[Scales]]", "a bounce on a new spot",
                 "setting_scale_mu"):
        assert part in text
    assert issubclass(ConvergenceWarning, BouncelabWarning)


def test_predict_draws_from_the_law(quick_posterior) -> None:
    post, data = quick_posterior
    land = data.landing.values[:5]
    draws = post.predict(land, n=300, seed=3)
    assert draws.shape == (300, 5, 3)
    np.testing.assert_array_equal(draws, post.predict(land, n=300, seed=3))  # seeded
    assert not np.array_equal(draws, post.predict(land, n=300, seed=4))
    # with all scales and the discrepancy at zero, every noise-free draw is the law at a sampled population value
    zero = {c: 0.0 for c in post.samples.columns if "scale" in c or c.startswith("discrepancy")}
    still = Posterior(**{**post.__dict__, "samples": post.samples.assign(**zero).iloc[:1]})
    one = still.predict(land, n=4, seed=0, measurement_error=False)
    expected = bl.Rigid(r=still.samples["r"].iloc[0], mu=still.samples["mu"].iloc[0]).predict(land)
    np.testing.assert_allclose(one, np.broadcast_to(expected, one.shape), rtol=1e-12)
    # the default is the measured bounce: the measurement errors (the calibration data's typical ones) spread the
    # draws of that one law, and larger ones more
    measured = still.predict(land, n=300, seed=0)
    assert (measured.std(axis=0) > 0.8 * SD_LIFT).all()
    wide = still.predict(land, n=300, seed=0, measurement_sd=(np.full(3, 30.0), np.full(3, 60.0)))
    assert (wide.std(axis=0) > 1.5 * measured.std(axis=0)).all()
    lift_only = still.predict(land, n=300, seed=0, measurement_sd=(None, np.full(3, 60.0)))  # None: the typical one
    assert (lift_only.std(axis=0) > 1.5 * measured.std(axis=0)).all()


def test_repeats_on_one_spot_share_its_draw(quick_posterior) -> None:
    """spots=: landings with one label share the setting-level draw, so the spread of repeats on one spot is
    smaller than that of bounces on spots of their own."""
    post, data = quick_posterior
    known = {"setting_scale_r": 0.3, "setting_scale_mu": 0.3, "scale_r": 0.02, "scale_mu": 0.02,
             "discrepancy_xdot": 1e-9, "discrepancy_ydot": 1e-9, "discrepancy_omega": 1e-9}
    post = Posterior(**{**post.__dict__, "samples": post.samples.assign(**known)})
    land = np.repeat(data.landing.values[:1], 40, axis=0)
    alone = post.predict(land, n=400, seed=1, measurement_error=False)
    shared = post.predict(land, n=400, seed=1, measurement_error=False, spots=np.zeros(40, int))
    assert shared.var(axis=1).mean() < 0.1 * alone.var(axis=1).mean()
    with pytest.raises(DataError) as e:
        post.predict(land, spots=[0, 1])
    assert e.value.option == "spots"


def test_predict_refuses_too_many_draws_before_allocating(quick_posterior) -> None:
    """Posterior.predict(n=10**9) ended in numpy's MemoryError after allocating; now a FitError first."""
    import time

    post, data = quick_posterior
    start = time.perf_counter()
    for n in (10**9, H.MAX_DRAWS // 2 + 1):
        with pytest.raises(FitError) as e:
            post.predict(data.landing.values[:2], n=n)
        assert e.value.option == "n"
    with pytest.raises(FitError) as e:
        post.interval(data.landing.values[:2], n=10**9)
    assert e.value.option == "n"
    assert time.perf_counter() - start < 5.0  # refused, not computed
    for bad in (0, 2.5, True, "10"):
        with pytest.raises(FitError):
            post.predict(data.landing.values[:2], n=bad)


def test_interval_shapes_and_levels(quick_posterior) -> None:
    post, data = quick_posterior
    land = data.landing.values[:7]
    lo, hi = post.interval(land, 0.95, n=500)
    assert lo.shape == hi.shape == (7, 3) and (lo < hi).all()
    lo50, hi50 = post.interval(land, 0.5, n=500)
    assert (lo50 >= lo).all() and (hi50 <= hi).all()
    np.testing.assert_array_equal(np.quantile(post.predict(land, 500), [(1 - 0.95) / 2, (1 + 0.95) / 2], axis=0),
                                  [lo, hi])  # the quantiles of predict()'s draws
    with pytest.raises(FitError) as e:
        post.interval(land, 1.0)
    assert e.value.option == "level"
    for bad in (0, 1.5, True, "0.9"):
        with pytest.raises(FitError) as e:
            post.summary(bad)
        assert e.value.option == "level"
    with pytest.raises(DataError) as e:
        post.predict([[100.0, 50.0, 0.0]])
    assert (e.value.column, e.value.row) == ("landing.ydot", 1)
    with pytest.raises(DataError) as e:
        post.predict(land, measurement_error=True, measurement_sd=np.ones(3))
    assert e.value.option == "measurement_sd"


def test_check_by_slip_roll_class(quick_posterior) -> None:
    post, data = quick_posterior
    table = post.check(data, n=300)
    assert list(table.columns) == ["n", "xdot", "ydot", "omega", "all3"]
    assert table.loc["all", "n"] == 60
    shares = table[["xdot", "ydot", "omega", "all3"]]
    assert ((shares >= 0) & (shares <= 1)).all().all()
    classes = bl.classify_slip_roll(data.landing.values, data.liftoff.values)
    assert table.loc["slip", "n"] == int((classes == "slip").sum())
    # one definition: the shares are those of interval() with each bounce's own measurement errors
    lo, hi = post.interval(data.landing.values, n=300, measurement_sd=post.measurement_sd_of(data))
    inside = (data.liftoff.values >= lo) & (data.liftoff.values <= hi)
    np.testing.assert_array_equal(table.loc["all", ["xdot", "ydot", "omega"]].to_numpy(dtype=float),
                                  inside.mean(axis=0))


def test_save_and_load(quick_posterior, tmp_path) -> None:
    post, data = quick_posterior
    path = tmp_path / "post.json"
    post.to_json(path)
    back = load_posterior(path)
    pd.testing.assert_frame_equal(back.samples, post.samples, check_exact=True)
    assert back.law == post.law and back.vary == post.vary and back.transforms == post.transforms
    assert back.diagnostics["converged"] is False
    land = data.landing.values[:4]
    np.testing.assert_array_equal(back.predict(land, n=50, seed=1), post.predict(land, n=50, seed=1))
    assert back.levels == post.levels == ["setting", "bounce"]
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(DataError) as e:
        load_posterior(bad)
    assert "not a JSON posterior" in e.value.message and e.value.file == str(bad)  # names the file
    law_file = tmp_path / "law.json"
    bl.Rigid(r=0.5, mu=0.4).to_json(law_file)
    with pytest.raises(DataError) as e:  # a law file, not a posterior
        load_posterior(law_file)
    assert (e.value.file, e.value.column) == (str(law_file), "format")
    d = post.to_dict()
    del d["samples"]["scale_r"]
    with pytest.raises(DataError) as e:  # samples, parameters and transforms do not fit together
        Posterior.from_dict(d)
    assert e.value.column == "samples" and "scale_r" in e.value.message
    with pytest.raises(DataError) as e:
        load_posterior(tmp_path / "missing.json")
    assert e.value.file == str(tmp_path / "missing.json")
    with pytest.raises(DataError) as e:
        load_posterior(tmp_path)
    assert e.value.file == str(tmp_path)
    with pytest.raises(ParameterError) as e:
        load_posterior(3)
    assert e.value.parameter == "path"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_load_posterior_refuses_a_fifo_without_waiting(tmp_path) -> None:
    """load_posterior read with Path.read_text: a FIFO hung it. Now it is refused at once."""
    fifo = tmp_path / "post.json"
    os.mkfifo(fifo)
    with pytest.raises(DataError) as e:
        load_posterior(fifo)
    assert e.value.file == str(fifo) and "regular file" in e.value.message


def test_version_1_posterior_reads_as_one_level(quick_posterior) -> None:
    """A posterior saved before the setting level (format_version 1) reads as the bounce level alone."""
    post, data = quick_posterior
    d = json.loads(post.to_json())
    d["format_version"] = 1
    del d["levels"]
    for c in [c for c in d["samples"] if c.startswith("setting_scale_")]:
        del d["samples"][c]
    for key in ("autocorr", "rhat"):
        d["diagnostics"][key] = d["diagnostics"][key][:2] + d["diagnostics"][key][4:]
    old = Posterior.from_dict(d)
    assert old.levels == ["bounce"] and list(old.scales().columns) == [
        f"{k}{e}" for k in ("bounce", "new_spot") for e in ("", "_low", "_high")]
    assert old.predict(data.landing.values[:2], n=20).shape == (20, 2, 3)
    assert "from bounce to bounce (every bounce on its own spot)" in old.report()


def _forgeries(d: dict) -> list[tuple[str, dict]]:
    """Saved posteriors with one field forged: missing, of another type, not finite, huge, out of range."""
    out = []

    def copy() -> dict:
        return json.loads(json.dumps(d))

    for key in ("format_version", "law", "free", "vary", "levels", "transforms", "residual", "with_tau", "n_bounces",
                "measurement", "samples", "diagnostics", "notes", "mode", "data_kind"):
        for value in (None, "x", 1e300, 10**400, [], {}, True, -1, "\ud800", [["r"]]):
            forged = copy()
            forged[key] = value
            out.append((key, forged))
        missing = copy()
        del missing[key]
        out.append((key, missing))
    for column in d["samples"]:
        for value in (float("nan"), float("inf"), -1.0, 10**400, "0.5", None, True, 1e9):
            forged = copy()
            forged["samples"][column][3] = value
            out.append((f"samples.{column}", forged))
        short = copy()
        short["samples"][column] = short["samples"][column][:-1]
        out.append(("samples", short))
    for key in ("converged", "reason", "steps", "burn", "walkers", "chains", "acceptance", "autocorr", "rhat",
                "kept_steps", "elapsed_s", "chain_steps", "thin"):
        for value in (None, "x", -5, 10**400, [1.0], {"a": 1}, float("nan")):
            forged = copy()
            forged["diagnostics"][key] = value
            out.append((f"diagnostics.{key}", forged))
    for name, value in (("transforms.r", {"kind": "log", "a": 0.0, "b": "inf"}),
                        ("transforms.r", {"kind": "logit", "a": 0.0, "b": 2.0}),
                        ("measurement.landing_sd", [1.0, -1.0, 2.0]), ("measurement.landing_sd", [1.0, 2.0]),
                        ("law", {"law": "Rigid", "parameters": {"r": 0.5}}), ("law", {"law": "NoSuchLaw"}),
                        ("notes", ["ok", 3]), ("mode", {"r": "x"})):
        forged = copy()
        top, _, rest = name.partition(".")
        if rest:
            forged[top][rest] = value
        else:
            forged[top] = value
        out.append((name, forged))
    return out


#: Fields whose forgery, valid on its own, can show as an inconsistency with these others (which the error names).
_RELATED = {"free": ("vary",), "vary": ("levels", "transforms", "samples"), "levels": ("samples",),
            "residual": ("measurement", "samples", "with_tau"), "with_tau": ("samples",), "measurement": (),
            "diagnostics": (), "samples": ()}


def test_forged_posterior_files_are_refused_at_load_naming_the_field(quick_posterior) -> None:
    """Issue 30: 74 of 600 forged posterior files loaded and then crashed on use (44 distinct exceptions). Every
    field is now checked at load: a forged file is a DataError naming the field, or loads and works."""
    post, data = quick_posterior
    d = json.loads(post.to_json())
    land = data.landing.values[:2]
    refused = loaded = 0
    for field, forged in _forgeries(d):
        try:
            back = Posterior.from_dict(forged)
        except DataError as exc:
            refused += 1
            top = field.split(".")[0]
            assert exc.column is not None and exc.column.split(".")[0] in {top, *_RELATED.get(top, ())}, (field, exc)
            continue
        loaded += 1  # what loads must work: report, summary, scales, prediction, interval, saving again
        back.report()
        back.summary()
        back.scales()
        assert np.isfinite(back.predict(land, n=5)).all()
        back.interval(land, n=5)
        Posterior.from_dict(json.loads(back.to_json()))
    assert refused > 300 and loaded > 0, (refused, loaded)
    for bad in ([1, 2], None, "posterior"):
        with pytest.raises(DataError) as e:
            Posterior.from_dict(bad)
        assert e.value.column == "format"


def test_figures(quick_posterior) -> None:
    pytest.importorskip("matplotlib")
    from bouncelab.plots.posterior import plot_corner, plot_spread, spread_table

    post, data = quick_posterior
    fig = plot_corner(post, columns=["r", "mu", "scale_r"])
    assert len([ax for ax in fig.axes if ax.get_visible()]) == 6
    with pytest.raises(ParameterError) as e:
        plot_corner(post, columns=["nope"])
    assert e.value.parameter == "columns"
    table = spread_table(post, data, n=200)
    assert len(table) == 12 and (table["n"] == 5).all()
    assert (table.filter(like="predicted_") > 0).all().all()
    fig = plot_spread(post, data, n=100)
    assert len(fig.axes) == 3
    with pytest.raises(DataError) as e:
        plot_spread(post, data.drop_vars("setting"))
    assert e.value.column == "setting"
    with pytest.raises(ParameterError) as e:  # not a Posterior
        plot_corner(object())
    assert e.value.parameter == "posterior"


def test_without_intervals_noise_is_fitted() -> None:
    data = varying_campaign(40, seed=9)
    pair = (data.landing.values, data.liftoff.values)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        post = calibrate(bl.Rigid, pair, vary="r", steps=30, walkers=20, discrepancy=False)
    assert post.residual == "noise" and post.with_tau
    assert [c for c in post.samples.columns if c.startswith("noise_")] == ["noise_xdot", "noise_ydot", "noise_omega"]
    assert any("no lift-off prediction intervals" in n for n in post.notes)
    assert post.measurement == {"landing_sd": None, "liftoff_sd": None}
    land = data.landing.values[:3]
    # the noise holds measurement error and discrepancy alike: predictions are of measured lift-offs only
    noisy = post.predict(land, 200)
    zero = post.samples.assign(noise_xdot=0.0, noise_ydot=0.0, noise_omega=0.0)
    quiet = Posterior(**{**post.__dict__, "samples": zero}).predict(land, 200)
    assert noisy.std(axis=0).mean() > quiet.std(axis=0).mean()
    for kwargs, option in (({"measurement_error": False}, "measurement_error"),
                           ({"measurement_sd": (None, np.ones(3))}, "measurement_sd"),  # the noise holds it
                           ({"measurement_sd": (np.ones(3), None)}, "measurement_sd"),  # and the landing's
                           ({"measurement_error": "yes"}, "measurement_error")):
        with pytest.raises(FitError) as e:
            post.predict(land, 20, **kwargs)
        assert e.value.option == option
    with pytest.raises(FitError) as e:
        post.interval(land, measurement_error=False)
    assert e.value.option == "measurement_error"


def test_a_fitted_landing_noise_is_a_stated_landing_error_of_that_size() -> None:
    """Without landing intervals the landing's measurement error is fitted (landing_noise_<component>); at any value
    the likelihood is the one of data stating that error, in the joint normal and in the importance-sampling
    integral over each setting's draw alike, and predict() draws it as it draws a stated one."""
    data = spot_campaign(6, 4, seed=12)
    p0, pf, setting, n = data.landing.values, data.liftoff.values, data.setting.values, 24
    common = {"free": ["r", "mu"], "vary": ["r", "mu"], "box": {"r": (0.0, 1.0), "mu": (0.0, 1.5)},
              "liftoff_sd": np.tile(SD_LIFT, (n, 1)), "with_tau": True, "tau_prior": np.full(3, 100.0),
              "groups": setting}
    stated = H._LogPosterior(bl.Rigid(r=R_MED, mu=MU_MED), p0, pf, landing_sd=np.tile(SD_LAND, (n, 1)), **common)
    fitted = H._LogPosterior(bl.Rigid(r=R_MED, mu=MU_MED), p0, pf, landing_sd=None,
                             landing_prior=np.full(3, 300.0), **common)
    assert fitted.columns[-3:] == ["landing_noise_xdot", "landing_noise_ydot", "landing_noise_omega"]
    x = np.array([0.52, 0.38, 0.2, 0.3, 0.05, 0.02, 2.0, 1.0, 6.0])
    xl = np.r_[x, SD_LAND]
    assert fitted.log_likelihood(xl) == pytest.approx(stated.log_likelihood(x), rel=1e-10)
    stated.setting_integral = SettingIntegral(stated, x)
    fitted.setting_integral = SettingIntegral(fitted, xl)
    assert fitted.log_likelihood(xl) == pytest.approx(stated.log_likelihood(x), rel=1e-9)
    assert fitted.log_likelihood(np.r_[x, 2 * SD_LAND]) != pytest.approx(fitted.log_likelihood(xl), rel=1e-6)
    # predict: a fitted landing noise of the stated size draws the same bounces
    truth = _truth()
    noisy = Posterior(**{**truth.__dict__, "samples": truth.samples.assign(
        **{f"landing_noise_{c}": v for c, v in zip(("xdot", "ydot", "omega"), SD_LAND, strict=True)}),
        "measurement": {"landing_sd": None, "liftoff_sd": SD_LIFT.tolist()}, "landing_noise": True})
    land = p0[:5]
    np.testing.assert_array_equal(noisy.predict(land, 50, seed=3), truth.predict(land, 50, seed=3))
    assert not np.array_equal(noisy.predict(land, 50, seed=3, measurement_error=False),
                              noisy.predict(land, 50, seed=3))
    with pytest.raises(FitError, match="the fitted landing noise already") as e:
        noisy.predict(land, 5, measurement_sd=(np.ones(3), None))
    assert e.value.option == "measurement_sd"


def test_calibrate_fits_the_landing_noise_only_where_the_data_do_not_state_it(tmp_path) -> None:
    """landing_noise=None fits it where the data have no landing intervals (a note says so), False leaves it out; a
    saved posterior keeps it, and a file claiming it beside stated landing errors is refused."""
    data = spot_campaign(6, 3, seed=13, intervals=False)
    with pytest.warns(ConvergenceWarning):
        post = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=30, seed=0)
    assert post.landing_noise and "landing_noise_omega" in post.samples.columns
    assert any("landing's measurement error is fitted" in note for note in post.notes)
    assert "landing's measurement error fitted" in post.report()
    back = load_posterior(post.to_json(tmp_path / "p.json") and tmp_path / "p.json")
    assert back.landing_noise and list(back.samples.columns) == list(post.samples.columns)
    forged = json.loads(post.to_json())
    forged["measurement"]["landing_sd"] = [1.0, 1.0, 1.0]
    with pytest.raises(DataError) as e:
        Posterior.from_dict(forged)
    assert e.value.column == "landing_noise"
    with pytest.warns(ConvergenceWarning):
        off = calibrate(bl.Rigid, data, vary=["r", "mu"], steps=10, walkers=24, seed=0, landing_noise=False)
    assert not off.landing_noise and "landing_noise_omega" not in off.samples.columns


def test_a_landing_noise_that_cannot_be_fitted_is_refused_before_the_point_fit(monkeypatch) -> None:
    """landing_noise=True beside the data's own landing intervals, or not None/True/False: a FitError naming the
    option, before any fitting."""
    monkeypatch.setattr(H, "fit", lambda *a, **k: pytest.fail("fitted before refusing"))
    with pytest.raises(FitError) as e:
        calibrate(bl.Rigid, spot_campaign(6, 3, seed=13), vary=["r"], landing_noise=True)
    assert e.value.option == "landing_noise" and "state the landing's measurement error" in e.value.message
    assert "landing_noise=None" in str(e.value)
    with pytest.raises(FitError) as e:
        calibrate(bl.Rigid, spot_campaign(6, 3, seed=13, intervals=False), vary=["r"], landing_noise="yes")
    assert e.value.option == "landing_noise"


def test_noise_free_lift_off_where_the_data_separate_it(quick_posterior) -> None:
    """With lift-off intervals the lift-off itself (no measurement error) is offered: narrower than the measured
    one; measurement_sd has no use with it."""
    post, data = quick_posterior
    small = {c: 1e-3 for c in post.samples.columns if "scale" in c or c.startswith("discrepancy")}
    post = Posterior(**{**post.__dict__, "samples": post.samples.assign(**small)})  # little spread but the errors
    land = data.landing.values[:4]
    lo, hi = post.interval(land, n=400, measurement_error=False)
    mlo, mhi = post.interval(land, n=400)
    assert ((hi - lo) < (mhi - mlo)).all()
    with pytest.raises(FitError) as e:
        post.predict(land, measurement_error=False, measurement_sd=(np.ones(3), np.ones(3)))
    assert e.value.option == "measurement_sd"


@pytest.mark.parametrize("kwargs, option", [
    ({"vary": ["nope"]}, "vary"),  # not a parameter of Rigid
    ({"vary": ["r", "r"]}, "vary"),  # twice
    ({"vary": ["r"], "fixed": ["r"]}, "vary"),  # held in the fit
    ({"vary": ["r"], "steps": 0}, "steps"),
    ({"vary": ["r"], "chains": 0}, "chains"),
    ({"vary": ["r"], "walkers": 3}, "walkers"),
    ({"vary": ["r"], "max_steps": 5}, "max_steps"),
    ({"vary": ["r"], "tau_multiple": 0}, "tau_multiple"),
    ({"vary": ["r"], "tau_multiple": "50"}, "tau_multiple"),
    ({"vary": ["r"], "approximation": "exact"}, "approximation"),
    ({"vary": ["r"], "nodes": 4}, "nodes"),
    ({"vary": ["r"], "nodes": 1}, "nodes"),
    ({"vary": ["r"], "nodes": 7.0}, "nodes"),
    ({"vary": ["r"], "by": "spot"}, "by"),
    ({"vary": ["r"], "by": "setting"}, "by"),  # these data have no launcher settings
    ({"vary": ["r"], "sample_weight": np.ones(40)}, "sample_weight"),
    ({"vary": ["r"], "executor": object()}, "executor"),
])
def test_bad_options_are_refused(kwargs, option) -> None:
    data = varying_campaign(40, seed=9)
    with pytest.raises(FitError) as e:
        calibrate(bl.Rigid(r=0.5, mu=0.4), data, **kwargs)
    assert e.value.option == option
    if option == "vary":
        assert e.value.law == "Rigid" and repr(kwargs["vary"][0]) in e.value.message  # the name at fault


@pytest.mark.parametrize("vary", [None, 3, ["r", 2], {"r"}, b"r"])
def test_vary_that_is_not_names_is_a_parameter_error(vary) -> None:
    """calibrate(vary=None) was a bare TypeError."""
    with pytest.raises(ParameterError) as e:
        calibrate(bl.Rigid, varying_campaign(40, seed=9), vary=vary)
    assert e.value.parameter == "vary"


def test_array_parameters_not_held_are_refused_before_the_point_fit(monkeypatch) -> None:
    """PiecewiseAffine's maps are arrays, which calibrate does not sample: refused, naming them, before a point fit
    (which took 10 s on PiecewiseAffine before it was refused)."""
    monkeypatch.setattr(H, "fit", lambda *a, **k: pytest.fail("fitted before refusing"))
    with pytest.raises(FitError) as e:
        calibrate(bl.PiecewiseAffine, varying_campaign(40, seed=9), vary=["offset"])
    assert e.value.option == "fixed" and "must be held" in e.value.message
    assert {"A1", "b1", "A2", "b2", "normal"} <= set(e.value.hints[0].value)


def test_one_bounce_per_setting_is_the_one_level_model() -> None:
    """Settings of one bounce each cannot separate the levels: every bounce is on its own spot, and the notes say so."""
    data = varying_campaign(40, seed=9).assign_coords(setting=("bounce", np.arange(40)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        post = calibrate(bl.Rigid, data, vary="r", steps=20, walkers=16)
    assert post.levels == ["bounce"] and "setting_scale_r" not in post.samples
    assert any("one level" in n for n in post.notes)


def test_array_parameters_must_be_held() -> None:
    data = varying_campaign(40, seed=9)
    with pytest.raises(FitError) as e:  # scalar parameters only
        calibrate(bl.PiecewiseAffine, data, vary=["offset"], method="plane")
    assert (e.value.law, e.value.option) == ("PiecewiseAffine", "fixed")
    assert e.value.hints == (Hint("fixed", ["normal", "A1", "b1", "A2", "b2"]),)  # every array parameter


def test_transforms_round_trip() -> None:
    for tr, values in ((H._Transform.of(0.0, 1.0), [1e-6, 0.3, 0.999]), (H._Transform.of(0.0, math.inf), [1e-4, 3.0]),
                       (H._Transform.of(-math.inf, 2.0), [-5.0, 1.9]), (H._Transform.of(-math.inf, math.inf), [-3.0])):
        np.testing.assert_allclose(tr.inverse(tr.forward(np.array(values))), values, rtol=1e-9)
    assert H._Transform.of(0.0, 1.0).kind == "logit" and H._Transform.of(0.0, math.inf).kind == "log"


def _chains(executor=None, client=None, seed: int = 6) -> Posterior:
    data = varying_campaign(30, seed=11)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return calibrate(bl.Rigid, data, vary=["r"], steps=25, walkers=14, chains=2, seed=seed, executor=executor,
                         client=client)


def test_chains_on_an_executor_equal_serial() -> None:
    from concurrent.futures import ThreadPoolExecutor

    serial = _chains()
    with ThreadPoolExecutor(max_workers=2) as pool:
        pooled = _chains(executor=pool)
        with pytest.warns(DeprecationWarning, match=r"calibrate\(client=...\) is deprecated"):
            alias = _chains(client=pool)  # the old name still works, for one release
    pd.testing.assert_frame_equal(pooled.samples, serial.samples, check_exact=True)
    pd.testing.assert_frame_equal(alias.samples, serial.samples, check_exact=True)
    assert serial.diagnostics["chains"] == 2 and serial.diagnostics["walkers"] == 28
    assert not _chains(seed=7).samples.equals(serial.samples)


def test_chains_on_dask_equal_serial() -> None:
    distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")
    serial = _chains()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cl, distributed.Client(cl) as client:
        remote = _chains(executor=client.get_executor())
    pd.testing.assert_frame_equal(remote.samples, serial.samples, check_exact=True)


# ------------------------------------------------------------------------------ the sampler's start and stop
class _Quadratic:
    """A stand-in log posterior: a normal density with covariance ``cov`` about ``centre`` (plus ``bend``,
    an extra quadratic form), a uniform prior on x[0] >= ``floor``."""

    def __init__(self, cov: np.ndarray, centre: np.ndarray, bend: np.ndarray | None = None, floor: float = -np.inf):
        self.prec = np.linalg.inv(cov) + (0 if bend is None else bend)
        self.centre, self.floor = centre, floor
        self.free = ["a"]
        self.box = {"a": (-10.0, 10.0)}

    def log_prior(self, x: np.ndarray) -> float:
        return 0.0 if x[0] >= self.floor else -math.inf

    def __call__(self, x: np.ndarray) -> float:
        d = np.asarray(x) - self.centre
        return self.log_prior(x) - 0.5 * float(d @ self.prec @ d)


def test_laplace_start_recovers_a_normal_posterior() -> None:
    """The walkers' start: the covariance of a normal posterior from the Hessian (exact for a quadratic up to
    rounding); an indefinite Hessian falls back to the diagonal, a non-concave axis to a small ball."""
    cov = np.array([[0.04, 0.018, 0.0], [0.018, 0.09, -0.01], [0.0, -0.01, 0.0025]])
    centre = np.array([1.0, -2.0, 0.5])
    spread, kind = H._laplace(_Quadratic(cov, centre), centre)
    assert kind == "laplace"
    np.testing.assert_allclose(spread @ spread.T, cov, rtol=1e-6, atol=1e-10)
    saddle = _Quadratic(np.eye(3), centre, bend=np.array([[0.0, 3.0, 0.0], [3.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    spread, kind = H._laplace(saddle, centre)  # each axis curves down, the Hessian is indefinite
    assert kind == "diagonal"
    np.testing.assert_allclose(np.diag(spread), 1.0, rtol=1e-6)
    upward = _Quadratic(np.eye(3), centre, bend=np.diag([0.0, -2.0, 0.0]))
    assert H._laplace(upward, centre)[1] == "ball"


def test_start_keeps_every_walker_inside_the_prior() -> None:
    post = _Quadratic(np.eye(2), np.zeros(2), floor=0.0)  # the mode on the prior's edge: half the draws outside
    spread, _ = H._laplace(post, np.array([0.5, 0.0]))
    start = H._start(post, np.array([0.05, 0.0]), spread, 40, np.random.default_rng(0))
    assert start.shape == (40, 2)
    assert np.all(start[:, 0] >= 0.0)
    assert len(np.unique(start[:, 1])) > 30  # redrawn, not piled on the mode


def _ar1(steps: int, walkers: int, phi: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    chain = np.zeros((steps, walkers, 2))
    chain[0] = rng.standard_normal((walkers, 2))
    for t in range(1, steps):
        chain[t] = phi * chain[t - 1] + math.sqrt(1 - phi ** 2) * rng.standard_normal((walkers, 2))
    return chain


def test_burn_in_and_stopping_rule() -> None:
    """Burn-in: BURN_TAUS autocorrelation times (an AR(1) chain with phi 0.8 has tau = 9), at most a third; the run
    stops once the rest is tau_multiple autocorrelation times long."""
    long = _ar1(2000, 20, 0.8, seed=1)
    burn, done = H._burn(long, 50.0, H.BURN_TAUS)
    tau = float(np.max(H._autocorr(long[2000 // 3:])))
    assert 7 < tau < 11
    assert burn == math.ceil(H.BURN_TAUS * tau) and done
    assert H._burn(long, 50.0, math.inf)[0] == 2000 // 3  # a start in a small ball: the first third
    burn, done = H._burn(long[:300], 50.0, H.BURN_TAUS)
    assert burn <= 100 and not done  # 300 steps are not 50 autocorrelation times


def test_threads_do_not_change_the_samples(monkeypatch) -> None:
    """The rows of the walkers' batched law call are shared between threads (forced here: Rigid is too cheap to be
    shared otherwise): the samples are the same bits."""
    from bouncelab.core._parallel import num_threads, set_num_threads

    monkeypatch.setattr(H, "PARALLEL_SECONDS", 0.0)

    data = varying_campaign(40, seed=13)
    before = num_threads()
    runs = []
    try:
        for n in (1, 2):
            set_num_threads(n)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                runs.append(calibrate(bl.Rigid, data, vary=["r", "mu"], steps=40, walkers=16, seed=4))
    finally:
        set_num_threads(before)
    pd.testing.assert_frame_equal(runs[0].samples, runs[1].samples, check_exact=True)
    assert runs[0].diagnostics["start"] in ("laplace", "diagonal")  # (diagonal: a discrepancy piled at zero)


def test_chains_that_stop_apart_are_pooled_over_their_common_tail(monkeypatch) -> None:
    data = varying_campaign(30, seed=11)
    run = H._run_chain
    calls = []

    def uneven(task):
        out = run(task)
        calls.append(len(out["chain"]))
        if len(calls) == 2:  # the second chain stopped 7 steps earlier
            out = {**out, "chain": out["chain"][7:], "steps": out["steps"] - 7}
        return out

    monkeypatch.setattr(H, "_run_chain", uneven)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        post = calibrate(bl.Rigid, data, vary=["r"], steps=30, walkers=14, chains=2, seed=6)
    assert post.diagnostics["kept_steps"] == min(calls) - 7
    assert post.diagnostics["walkers"] == 28
    assert post.diagnostics["chain_steps"] == [30, 23]  # each chain's own count, and the report says both
    assert "x 23-30 steps" in post.report() and f"{min(calls) - 7} kept per walker" in post.report()


def test_mode_search_settles_inside_the_bulk() -> None:
    """The start of the sampler: from 4 sd away in each of 6 numbers, a point within a few tenths of a unit of log
    density of the mode (the bulk of a 6-dimensional normal lies about 3 units below it), in far fewer than the
    search's most evaluations."""
    cov = np.diag([0.04, 0.09, 0.0025, 1.0, 0.25, 4.0])
    cov[0, 1] = cov[1, 0] = 0.03
    centre = np.array([1.0, -2.0, 0.5, 3.0, 0.0, -1.0])
    post = _Quadratic(cov, centre)
    calls = []
    counted = type("Counted", (), {"__call__": lambda self, x: (calls.append(1), post(x))[1],
                                   "box": post.box, "free": post.free})()
    x = H._mode(counted, centre + 4 * np.sqrt(np.diag(cov)))
    assert post(x) > -0.5
    assert len(calls) < 400 * 6


def test_a_law_written_in_python_is_not_run_on_threads(monkeypatch) -> None:
    """Only compiled laws (thread-safe, GIL released) share the walkers between threads (here forced: a law as cheap
    as Rigid would not be shared otherwise); a user's Python law, which need not be thread-safe, runs on the calling
    thread."""
    from bouncelab.core import _parallel
    from bouncelab.core._parallel import num_threads, set_num_threads

    monkeypatch.setattr(H, "PARALLEL_SECONDS", 0.0)

    class PythonRigid(bl.BounceModel):
        r = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), doc="restitution")
        mu = bl.Parameter(bounds=(0.0, 1.5), physical=(0.0, float("inf")), doc="friction")
        regimes = bl.Rigid.regimes

        def _predict(self, p, r, mu):
            return bl.Rigid(r=0.5, mu=0.5)._predict(p, r=r, mu=mu)

        def _regime(self, p, r, mu):
            return bl.Rigid(r=0.5, mu=0.5)._regime(p, r=r, mu=mu)

    shared = []
    share = _parallel._share
    monkeypatch.setattr(_parallel, "_share", lambda *a: (shared.append(1), share(*a))[1])
    data = varying_campaign(30, seed=14)
    before = num_threads()
    set_num_threads(2)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            python_law = calibrate(PythonRigid(r=0.5, mu=0.4), data, vary=["r"], steps=20, walkers=14, seed=3)
            assert not shared
            compiled = calibrate(bl.Rigid(r=0.5, mu=0.4), data, vary=["r"], steps=20, walkers=14, seed=3)
            assert shared
    finally:
        set_num_threads(before)
    # the same law either way: the same samples
    pd.testing.assert_frame_equal(python_law.samples, compiled.samples, check_exact=False, rtol=1e-9)


def test_a_short_run_with_a_walker_that_never_moved_ends_unconverged() -> None:
    """A walker that does not move in the kept steps has no variance: its autocorrelation time is infinite, not
    NaN (which crashed the thinning); the run ends with a ConvergenceWarning, saves and loads."""
    chain = _ar1(60, 12, 0.5, seed=2)
    chain[:, 3, 0] = 0.5  # one walker stuck in the first number (its mean exactly 0.5: zero variance)
    tau = H._autocorr(chain)
    assert tau[0] == np.inf and np.isfinite(tau[1])
    assert H._burn(chain, 50.0, H.BURN_TAUS) == (20, False)  # an infinite time: the first third, not converged
    data = varying_campaign(30, seed=3)
    for steps, seed in ((10, 1), (20, 4)):  # each crashed with "cannot convert float NaN to integer"
        with pytest.warns(ConvergenceWarning):
            post = calibrate(bl.Rigid, data, vary=["r"], steps=steps, seed=seed)
        assert not post.converged and post.diagnostics["thin"] >= 1
        again = Posterior.from_dict(__import__("json").loads(post.to_json()))
        assert again.diagnostics["autocorr"] == post.diagnostics["autocorr"]
        assert "walkers x" in again.report()


def test_diagnostics_in_json_keep_non_finite_values_as_text() -> None:
    """NaN was written as "-inf" by the transform's helper; every non-finite float reads back as itself."""
    written = H._json_number([np.float64(np.nan), np.inf, -np.inf, np.float64(1.5), 3])
    assert written == ["nan", "inf", "-inf", 1.5, 3]
    back = [float(x) if isinstance(x, str) else x for x in written]
    assert math.isnan(back[0]) and back[1:] == [np.inf, -np.inf, 1.5, 3]
