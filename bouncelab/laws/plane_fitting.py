"""Finding the slip/roll plane of the piecewise-affine law: the paper's SVM procedure and a search for delta.

The law itself (two affine maps either side of a plane) is in
:mod:`bouncelab.laws.piecewise`; this module holds the procedures its fitting
methods use, and does not depend on the fitting package (the NLopt search is
handed in by :func:`bouncelab.fit` as a service of the fitting problem).

**The paper's procedure** (``method="svm"``; sections "Distinguishing between
slipping and rolling" and "Piecewise linear model slipping and rolling"): label
each bounce slip or roll from its contact-point velocity, train a linear
support-vector machine with SMO (scikit-learn's ``SVC``, i.e. libsvm's SMO, as
MATLAB's ``fitcsvm`` defaults to), take the plane that separates the classes,
and fit each side's affine map by least squares. The paper's words for the plane
("the boundary cases are identified using the SVM algorithm, and a plane is
fitted through the identified boundary points using least squares") allow
several readings, offered as ``svm_plane``:

``"hyperplane"`` (default)
    The SVM's own separating plane. The boundary points in the strict sense are
    the support vectors on the margin (dual coefficient strictly between 0 and
    C); they satisfy ``y_i f(x_i) = 1`` exactly, so the least-squares fit of the
    decision function through them *is* this plane.
``"support_vectors"``
    The literal reading: ``omega0 = c - a xdot0 - b ydot0`` by ordinary least
    squares through *all* support vectors, which with C = 1 include every
    bounce inside or on the wrong side of the margin (118 of the 275 training
    bounces of the surrogate A).
``"margin_support_vectors"``
    The same least-squares plane through the on-margin support vectors only
    (usually 4 or 5 points, so the plane is poorly determined).

``svm_scaling`` is ``"standardize"`` (default: each landing component scaled
to unit variance) or ``"none"`` (MATLAB ``fitcsvm``'s default, which on raw
landings needs of the order of 10^8 SMO iterations; capped at 10^6, fitcsvm's
``IterationLimit``). Measured on the paper's split of the embedded surrogates
(docs: Fitting), the hyperplane recovers the generating (published) plane best
and gives the lowest held-out delta; the literal reading gives
0.363 xdot0 + 0.625 ydot0 + omega0 = 19.7 on A, against the paper's
0.891, 0.763, 600.

**bouncelab's default** (``method="plane"``) chooses the plane that minimises
delta of the whole law directly: for a trial plane both maps are least-squares
fits, and the plane (a unit normal and an offset in standardised landing space)
is found by an NLopt global search started from the SVM hyperplane (or from the
plane of the law given), then polished. Above ``max_search_bounces`` bounces the
global stage runs on a seeded random subsample of that many and only the polish
on all bounces, so the cost grows linearly with the number of bounces.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bouncelab.core.errors import FitError
from bouncelab.core.slip_roll import _slip_codes
from bouncelab.core.validation import as_states, check_same_length

__all__ = [
    "MIN_SIDE",
    "SVM_PLANES",
    "SVM_SCALINGS",
    "PlaneFit",
    "canonical_plane",
    "fit_svm",
    "least_squares_maps",
    "mismatched_fraction",
    "orient_slip_side",
]

#: The law these procedures fit (the ``law`` of their errors; the module does not import it).
_LAW = "PiecewiseAffine"
#: Fewest bounces allowed on one side of the plane (an affine map has 4 coefficients per output).
MIN_SIDE = 8
#: Readings of the paper's plane through the support vectors (see the module notes).
SVM_PLANES = ("hyperplane", "support_vectors", "margin_support_vectors")
#: Scalings of the landings before the SVM.
SVM_SCALINGS = ("standardize", "none")
#: SMO iterations allowed without standardisation (MATLAB fitcsvm's IterationLimit).
UNSCALED_MAX_ITER = 1_000_000
#: Half-width of the offset search range, in standard deviations of the landing conditions.
T_MAX = 3.0


@dataclass
class PlaneFit:
    """The parameters of a piecewise-affine law found by :func:`fit_svm`, and how.

    Attributes
    ----------
    normal, offset
        The plane ``normal . p0 = offset``, oriented so that side 2 holds most slipping bounces.
    A1, b1, A2, b2
        The affine maps of side 1 (roll) and side 2 (slip), by least squares.
    svm_support
        Indices of all support vectors.
    margin_support
        Indices of the support vectors on the margin (0 < dual coefficient < C).
    svm_C, svm_plane, svm_scaling
        The options used.
    converged
        Whether the SMO solver converged (always with standardisation).
    notes
        What a report should say about it.
    """

    normal: np.ndarray
    offset: float
    A1: np.ndarray
    b1: np.ndarray
    A2: np.ndarray
    b2: np.ndarray
    svm_support: np.ndarray
    margin_support: np.ndarray
    svm_C: float
    svm_plane: str
    svm_scaling: str
    converged: bool = True
    notes: list[str] = field(default_factory=list)

    @property
    def parameters(self) -> dict[str, Any]:
        """The law's parameters by name: ``bouncelab.PiecewiseAffine(**fit.parameters)`` is the law."""
        return {"normal": self.normal, "offset": self.offset, "A1": self.A1, "b1": self.b1, "A2": self.A2,
                "b2": self.b2}


def standardise(p0: np.ndarray, weights: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Landings scaled to zero (weighted) mean and unit (weighted) variance per component, with the mean and scale."""
    mean = np.average(p0, axis=0, weights=weights)
    scale = np.sqrt(np.average((p0 - mean) ** 2, axis=0, weights=weights))
    scale[scale == 0] = 1.0
    return (p0 - mean) / scale, mean, scale


def canonical_plane(normal: np.ndarray, offset: float) -> tuple[np.ndarray, float]:
    """The plane ``normal . p0 = offset`` scaled so that its largest coefficient is +-1.

    A plane has no natural scale; this one always lies in :class:`~bouncelab.PiecewiseAffine`'s
    search box (every coefficient in [-1, 1]) and keeps its sides (the scale is positive). When
    the omega coefficient is the largest it is the paper's printed form
    ``a xdot0 + b ydot0 + omega0 = c``. Coefficients below 1e-12 of the largest are rounding
    (a search that ends on the edge of its box gives cos(pi/2) = 6e-17, not 0) and become 0: so a plane
    parallel to the omega axis is stored as such, not as ``[6e+15, 1.3e+16, 1]``.

    Raises
    ------
    FitError
        A normal that is zero or not finite, or an offset that is not finite.
    """
    n = np.asarray(normal, dtype=np.float64).copy()
    c = float(offset)
    if n.shape != (3,) or not (np.all(np.isfinite(n)) and np.isfinite(c)):
        raise FitError(f"the plane search gave a plane that is not finite (normal {n!r}, offset {c!r})", law=_LAW)
    scale = float(np.max(np.abs(n)))
    if scale == 0.0:
        raise FitError("the plane search gave a zero normal; the plane is undetermined", law=_LAW)
    n /= scale
    n[np.abs(n) < 1e-12] = 0.0
    return n, c / scale


def least_squares_maps(p0: np.ndarray, pf: np.ndarray, normal: np.ndarray, offset: float, *,
                       min_side: int = MIN_SIDE, sample_weight: np.ndarray | None = None) -> dict[str, Any]:
    """The parameters of the piecewise law with the given plane and a least-squares affine map
    ``pF = A p0 + b`` on each side, by name (``PiecewiseAffine(**maps)``).

    ``sample_weight`` (one non-negative weight per bounce) makes the least squares weighted.

    Raises
    ------
    FitError
        When a side has fewer than ``min_side`` bounces or its landings do not
        span 3-D space (the map would be undetermined).
    """
    side2 = p0 @ normal >= offset
    maps = []
    for name, mask in (("side 1 (roll)", ~side2), ("side 2 (slip)", side2)):
        m = int(mask.sum())
        if m < min_side:
            raise FitError(
                f"the plane leaves {m} bounce(s) on {name}; an affine map needs at least {min_side} "
                "(4 coefficients per lift-off component)", law=_LAW
            )
        X = np.column_stack([p0[mask], np.ones(m)])
        Y = pf[mask]
        if sample_weight is not None:  # weighted least squares: rows scaled by sqrt(w)
            root = np.sqrt(sample_weight[mask])[:, None]
            X, Y = X * root, Y * root
        coef, _, rank, _ = np.linalg.lstsq(X, Y, rcond=None)
        if rank < 4:
            raise FitError(f"the landings on {name} do not span 3-D space; its affine map is undetermined", law=_LAW)
        maps.append((coef[:3].T, coef[3]))
    (A1, b1), (A2, b2) = maps
    return {"normal": normal, "offset": float(offset), "A1": A1, "b1": b1, "A2": A2, "b2": b2}


def orient_slip_side(p0: np.ndarray, slip: np.ndarray, normal: np.ndarray, offset: float):
    """Flip the plane's sign if needed so that side 2 (``n . p0 >= c``) holds most slipping bounces.

    ``slip`` is a boolean mask (or an array of "slip"/"roll" labels).
    """
    slip = np.asarray(slip)
    if slip.dtype != bool:
        slip = slip == "slip"
    side2 = p0 @ normal >= offset
    if slip.any() and (side2 & slip).sum() < (~side2 & slip).sum():
        return -normal + 0.0, -offset + 0.0  # + 0.0: a zero coefficient stays 0, not -0
    return normal, offset


def mismatched_fraction(model: Any, landing: Any, liftoff: Any) -> float:
    """Fraction of bounces whose measured slip/roll class differs from the side of the plane (Table 2)."""
    p0, _ = as_states(landing, "landing", landing=True)
    pf, _ = as_states(liftoff, "liftoff")
    check_same_length(p0, pf, "landing", "liftoff")
    return _mismatched(model, p0, pf)


def _mismatched(model: Any, p0: np.ndarray, pf: np.ndarray) -> float:
    # regime codes of the piecewise law: 0 roll (side 1), 1 slip (side 2), as the slip/roll codes
    return float(np.mean(model._classify(p0) != _slip_codes(p0, pf)))


def _ols_omega_plane(points: np.ndarray, what: str) -> tuple[np.ndarray, float]:
    """omega0 = c - a xdot0 - b ydot0 by ordinary least squares, as ``normal = (a, b, 1)``, ``offset = c``."""
    X = np.column_stack([points[:, 0], points[:, 1], np.ones(len(points))])
    if len(points) < 3 or np.linalg.matrix_rank(X) < 3:
        raise FitError(f"{len(points)} {what} do not determine a plane (need 3 not on one line)", law=_LAW)
    (alpha, beta, gamma), *_ = np.linalg.lstsq(X, points[:, 2], rcond=None)
    return np.array([-alpha, -beta, 1.0]), float(gamma)


def fit_svm(p0: np.ndarray, pf: np.ndarray, *, C: float = 1.0, min_side: int = MIN_SIDE,
            plane: str = "hyperplane", scaling: str = "standardize", max_bounces: int | None = None,
            seed: int = 0, sample_weight: np.ndarray | None = None) -> PlaneFit:
    """The paper's procedure: linear SVM on the slip/roll labels, a plane, and least-squares maps.

    Parameters
    ----------
    p0, pf
        Landing and lift-off states, (n, 3) float64, scaled units (validated by the caller).
    C
        Box constraint of the SVM (scikit-learn ``SVC(kernel="linear", C=C)``).
    min_side
        Fewest bounces per class and per side.
    plane
        One of :data:`SVM_PLANES` (see the module notes).
    scaling
        One of :data:`SVM_SCALINGS`.
    max_bounces
        Train the SVM on a seeded random subsample of at most this many bounces
        (an SVM's cost grows faster than the number of bounces); None: all.
    seed
        Seed of that subsample.
    sample_weight
        One non-negative weight per bounce, for the SVM (scikit-learn's per-sample ``C``
        scaling) and the least-squares maps; None: all equal (the paper's procedure).

    Raises
    ------
    FitError
        A class with fewer than ``min_side`` bounces, a bad option, or a plane that
        leaves a side too small.
    """
    from sklearn.exceptions import ConvergenceWarning
    from sklearn.svm import SVC

    if plane == "all_support_vectors":
        plane = "support_vectors"
    if plane not in SVM_PLANES:
        raise FitError(f"svm_plane must be one of {list(SVM_PLANES)}; got {plane!r}", law=_LAW, option="svm_plane")
    if scaling not in SVM_SCALINGS:
        raise FitError(f"svm_scaling must be one of {list(SVM_SCALINGS)}; got {scaling!r}", law=_LAW,
                       option="svm_scaling")
    try:
        C = float(C)
    except (TypeError, ValueError):
        raise FitError(f"svm_C must be a positive number; got {C!r}", law=_LAW, option="svm_C") from None
    if not (np.isfinite(C) and C > 0):
        raise FitError(f"svm_C must be a positive number; got {C!r}", law=_LAW, option="svm_C")
    slip = _slip_codes(p0, pf).astype(bool)
    counts = {"roll": int((~slip).sum()), "slip": int(slip.sum())}
    if min(counts.values()) < min_side:
        raise FitError(
            f"the SVM needs both classes with at least {min_side} bounces; the data have {counts} "
            "(slip/roll from the contact-point velocity at landing and lift-off)", law=_LAW
        )
    notes: list[str] = []
    train = np.arange(len(p0))
    if max_bounces is not None and len(p0) > max_bounces:
        train = np.sort(np.random.default_rng(seed).choice(len(p0), int(max_bounces), replace=False))
        notes.append(f"SVM trained on a random subsample of {len(train)} of the {len(p0)} bounces")
    x, y = p0[train], slip[train]
    sw = None if sample_weight is None else sample_weight[train]
    if scaling == "standardize":
        _, mean, scale = standardise(x, sw)
    else:
        mean, scale = np.zeros(3), np.ones(3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ConvergenceWarning)
        svc = SVC(kernel="linear", C=C, max_iter=-1 if scaling == "standardize" else UNSCALED_MAX_ITER)
        svc.fit((x - mean) / scale, y, sample_weight=sw)
    converged = not any(issubclass(w.category, ConvergenceWarning) for w in caught)
    if not converged:
        notes.append(f"the SMO solver stopped at its iteration limit ({UNSCALED_MAX_ITER}) without converging")
    support = train[svc.support_]
    alpha = np.abs(svc.dual_coef_[0])
    margin = train[svc.support_[alpha < C * (1 - 1e-8)]]
    if plane == "hyperplane":
        # w . (p - mean) / scale + b = 0  <=>  (w / scale) . p = (w / scale) . mean - b
        normal = svc.coef_[0] / scale
        offset = float(normal @ mean - svc.intercept_[0])
        notes.append(f"plane = the SVM's decision boundary (C = {C:g}, {scaling} landings; {len(support)} support "
                     f"vectors, {len(margin)} on the margin)")
    elif plane == "support_vectors":
        normal, offset = _ols_omega_plane(p0[support], "support vectors")
        notes.append(f"plane through all {len(support)} support vectors by least squares on omega0 "
                     f"(C = {C:g}, {scaling} landings)")
    else:
        normal, offset = _ols_omega_plane(p0[margin], "on-margin support vectors")
        notes.append(f"plane through the {len(margin)} on-margin support vectors by least squares on omega0 "
                     f"(C = {C:g}, {scaling} landings)")
    normal, offset = orient_slip_side(p0, slip, *canonical_plane(normal, offset))
    maps = least_squares_maps(p0, pf, normal, offset, min_side=min_side, sample_weight=sample_weight)
    return PlaneFit(**maps, svm_support=support, margin_support=margin, svm_C=C, svm_plane=plane,
                    svm_scaling=scaling, converged=converged, notes=notes)


# ------------------------------------------------------------------------------ the delta plane
def plane_to_unit(normal: np.ndarray, offset: float, mean: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """(theta, phi, t) in [0, 1]^3 of a plane, for the search box (upper hemisphere of normals)."""
    u = normal * scale  # n . p = c  <=>  (n * scale) . z = c - n . mean
    t = offset - normal @ mean
    norm = np.linalg.norm(u)
    u, t = u / norm, t / norm
    if u[2] < 0:
        u, t = -u, -t
    theta = np.arccos(np.clip(u[2], -1.0, 1.0))
    phi = np.arctan2(u[1], u[0])
    return np.clip([theta / (np.pi / 2), (phi + np.pi) / (2 * np.pi), (t + T_MAX) / (2 * T_MAX)], 0.0, 1.0)


def unit_to_plane(x: np.ndarray) -> tuple[np.ndarray, float]:
    """The unit normal and offset (standardised space) at a point of the search box."""
    theta = x[0] * np.pi / 2
    phi = x[1] * 2 * np.pi - np.pi
    t = x[2] * 2 * T_MAX - T_MAX
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)]), float(t)


@dataclass
class SearchedPlane:
    """Result of :func:`search_plane`."""

    normal: np.ndarray
    offset: float
    outcomes: list[Any]
    notes: list[str]


def search_plane(p0: np.ndarray, pf: np.ndarray, inv_norm: np.ndarray, search: Any, *, start: Any,
                 seed: int, algorithm: str, local_algorithm: str | None, maxeval: int, min_side: int,
                 max_search_bounces: int, sample_weight: np.ndarray | None = None) -> SearchedPlane:
    """The plane minimising delta of the least-squares piecewise law (see the module notes).

    ``sample_weight`` weighs the bounces in the maps' least squares (None: unweighted); ``inv_norm``
    weighs their errors in delta.

    ``search(f, x0, **options)`` is the fitting problem's NLopt service; ``start`` a
    ``(normal, offset)`` pair in landing units, or None for the centre of the box.
    """
    from bouncelab.laws import _plane_kernel as kernel

    z, mean, scale = standardise(p0)
    n = len(p0)
    w = np.ones(n) if sample_weight is None else np.ascontiguousarray(sample_weight, dtype=np.float64)
    notes = []
    x0 = np.array([0.5, 0.5, 0.5]) if start is None else plane_to_unit(start[0], start[1], mean, scale)

    def objective_on(idx: np.ndarray | None):
        zz = z if idx is None else np.ascontiguousarray(z[idx])
        ff = pf if idx is None else np.ascontiguousarray(pf[idx])
        ii = inv_norm if idx is None else np.ascontiguousarray(inv_norm[idx])
        ww = w if idx is None else np.ascontiguousarray(w[idx])

        def f(x: np.ndarray) -> float:
            u, t = unit_to_plane(x)
            return kernel.plane_delta(zz, ff, ww, ii, u, t, min_side)

        return f

    outcomes = []
    if n <= max_search_bounces:
        outcome = search(objective_on(None), x0, algorithm=algorithm, local_algorithm=local_algorithm,
                         maxeval=maxeval, xtol_rel=1e-8, local_maxeval=600)
        outcomes.append(outcome)
    else:
        sub = np.sort(np.random.default_rng(seed).choice(n, max_search_bounces, replace=False))
        coarse = search(objective_on(sub), x0, algorithm=algorithm, local_algorithm=local_algorithm,
                        maxeval=maxeval, xtol_rel=1e-8, local_maxeval=600)
        full = search(objective_on(None), coarse.x, algorithm=None, local_algorithm=local_algorithm or "NELDERMEAD",
                      xtol_rel=1e-8, local_maxeval=300, polish_starts=0, scan_rounds=0)
        outcomes += [coarse, full]
        notes.append(f"global stage on a random subsample of {max_search_bounces} of the {n} bounces, "
                     "then a local polish on all of them")
    best = outcomes[-1]
    if best.fun >= kernel.INFEASIBLE:
        raise FitError(f"no plane leaves at least {min_side} bounces on each side; too few bounces to fit", law=_LAW)
    u, t = unit_to_plane(best.x)
    normal = u / scale  # back to landing units: (u / scale) . p0 = t + (u / scale) . mean
    offset = float(t + normal @ mean)
    normal, offset = canonical_plane(normal, offset)  # largest coefficient +-1: inside the law's search box
    return SearchedPlane(normal=normal, offset=offset, outcomes=outcomes, notes=notes)

