"""Global search with NLopt followed by a local derivative-free polish.

The paper fitted with MATLAB's genetic algorithm; here NLopt's global
algorithms stand in for it. The search runs in the unit box (each parameter
scaled by its bounds) so that r in [0, 1] and k_p in [0, 1e-3] are treated
alike. delta is piecewise smooth but not differentiable at regime changes, so
only derivative-free algorithms are offered.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import nlopt
import numpy as np

from bouncelab.core.atomic import pending_termination
from bouncelab.core.errors import FitError

__all__ = ["GLOBAL_ALGORITHMS", "LOCAL_ALGORITHMS", "SearchOutcome", "global_search", "run_nlopt"]

#: Global algorithms offered (NLopt names without the prefix).
GLOBAL_ALGORITHMS = ("CRS2_LM", "ISRES", "ESCH", "DIRECT_L", "MLSL")
#: Local polishing algorithms offered.
LOCAL_ALGORITHMS = ("BOBYQA", "SBPLX", "NELDERMEAD")

_STOP = {
    1: "success",
    2: "stopval reached",
    3: "ftol reached",
    4: "xtol reached",
    5: "maxeval reached",
    6: "maxtime reached",
    -1: "failure",
    -2: "invalid arguments",
    -3: "out of memory",
    -4: "roundoff limited",
    -5: "forced stop",
}


def _global_code(name: str) -> int:
    key = name.upper().removeprefix("GN_")
    if key not in GLOBAL_ALGORITHMS:
        raise FitError(f"unknown global algorithm {name!r}; choose from {', '.join(GLOBAL_ALGORITHMS)}",
                       option="algorithm")
    return getattr(nlopt, "GN_" + key)


def _local_code(name: str) -> int:
    key = name.upper().removeprefix("LN_")
    if key not in LOCAL_ALGORITHMS:
        raise FitError(f"unknown local algorithm {name!r}; choose from {', '.join(LOCAL_ALGORITHMS)}",
                       option="local_algorithm")
    return getattr(nlopt, "LN_" + key)


@dataclass
class SearchOutcome:
    """What a search did: best point (unit box), its value, evaluations and stop reasons."""

    x: np.ndarray
    fun: float
    n_global: int = 0
    n_local: int = 0
    global_stop: str = ""
    local_stop: str = ""
    elapsed: float = 0.0
    algorithms: tuple[str, str] = ("", "")


_NO_GRAD = np.empty(0)


class _Tracked:
    """Wrap the objective: count calls and remember the best point seen."""

    def __init__(self, f: Callable[[np.ndarray], float]) -> None:
        self.f = f
        self.raised: list[BaseException] = []  # what the objective raised (NLopt may lose it: run_nlopt)
        self.calls = 0
        self.best_x: np.ndarray | None = None
        self.best_f = np.inf
        self.xs: list[np.ndarray] = []
        self.fs: list[float] = []

    def __call__(self, x: np.ndarray, grad: np.ndarray) -> float:
        self.calls += 1
        try:
            v = float(self.f(x))
        except BaseException as exc:
            self.raised.append(exc)
            raise
        if v != v or v == np.inf:  # NaN or inf: a point the optimizer must avoid
            v = 1e300
        self.xs.append(x.copy())
        self.fs.append(v)
        if v < self.best_f:
            self.best_f = v
            self.best_x = self.xs[-1]
        return v

    def distinct_best(self, k: int, min_distance: float) -> list[np.ndarray]:
        """Up to ``k`` best points seen, pairwise at least ``min_distance`` apart (max-norm)."""
        xs = np.array(self.xs)[np.argsort(self.fs, kind="stable")]
        chosen = [xs[0]]
        for _ in range(k - 1):
            far = np.all([np.max(np.abs(xs - c), axis=1) >= min_distance for c in chosen], axis=0)
            if not far.any():
                break
            chosen.append(xs[np.argmax(far)])  # the best point far from every chosen one
        return chosen


def run_nlopt(opt: nlopt.opt, x0: np.ndarray, raised: list[BaseException]) -> None:
    """``opt.optimize(x0)``, an interrupt during it re-raised as itself.

    NLopt stops when its objective raises and re-raises the exception, but a ``KeyboardInterrupt`` (Ctrl-C)
    or a SIGTERM that lands in NLopt's own glue around the call comes out as ``nlopt.ForcedStop`` (or, from
    some algorithms, as a failure code): bouncelab never forces a stop, so a ForcedStop is an exception of
    the objective. ``raised`` is what the objective raised (its wrapper records it): an interrupt
    (any ``BaseException`` that is not an ``Exception``) there is re-raised whatever NLopt made of it; a
    ForcedStop with nothing recorded is an interrupt in the glue, re-raised as a ``KeyboardInterrupt``.
    """
    try:
        opt.optimize(x0)
    except BaseException as exc:
        interrupt = next((e for e in raised if not isinstance(e, Exception)), None)
        if interrupt is not None and exc is not interrupt:
            raise interrupt from None
        if isinstance(exc, nlopt.ForcedStop):
            if not raised and (term := pending_termination()) is not None:  # SIGTERM in the glue, not Ctrl-C
                raise term from None
            raise (raised[-1] if raised else KeyboardInterrupt("interrupted inside NLopt")) from None
        raise


def _run(opt: nlopt.opt, tracked: _Tracked, x0: np.ndarray) -> str:
    try:
        run_nlopt(opt, np.array(x0, dtype=float), tracked.raised)
        return _STOP.get(opt.last_optimize_result(), str(opt.last_optimize_result()))
    except nlopt.RoundoffLimited:
        return "roundoff limited"
    except (ValueError, RuntimeError) as exc:  # NLopt's "failure" / invalid-argument codes
        if tracked.best_x is None:
            raise FitError(f"NLopt failed: {exc}") from None
        return f"failure ({exc})"


def _scan_coordinate(tracked: _Tracked, i: int, points: int) -> None:
    """Evaluate the objective along coordinate ``i`` from the best point, and probe plateau edges.

    The best point may sit on a plateau (the objective constant in ``x[i]``) whose edge hides
    a narrow valley: just past the value of ``x[i]`` where one more bounce changes regime. Each
    change between the plateau value and another value along the scan is bisected to that
    edge, and the points just past it are evaluated.
    """
    base = tracked.best_x.copy()
    f_best = tracked.best_f
    grid = np.linspace(0.0, 1.0, points)
    values = []
    for g in grid:
        y = base.copy()
        y[i] = g
        values.append(tracked(y, _NO_GRAD))
    tol = 1e-13 * max(abs(f_best), 1e-300)
    on_plateau = [abs(v - f_best) <= tol for v in values]
    for k in range(points - 1):
        if on_plateau[k] == on_plateau[k + 1]:
            continue
        inside, outside = (grid[k], grid[k + 1]) if on_plateau[k] else (grid[k + 1], grid[k])
        for _ in range(40):  # bisect to the plateau's edge
            mid = 0.5 * (inside + outside)
            y = base.copy()
            y[i] = mid
            if abs(tracked(y, _NO_GRAD) - f_best) <= tol:
                inside = mid
            else:
                outside = mid
        for frac in (1e-9, 1e-7, 1e-5, 1e-3):  # just past the edge, where a valley may start
            y = base.copy()
            y[i] = np.clip(inside + (outside - inside) / max(abs(outside - inside), 1e-300) * frac, 0.0, 1.0)
            tracked(y, _NO_GRAD)


def global_search(
    f: Callable[[np.ndarray], float],
    x0: np.ndarray,
    *,
    algorithm: str | None = "CRS2_LM",
    local_algorithm: str = "BOBYQA",
    seed: int = 0,
    maxeval: int | None = None,
    local_maxeval: int = 4000,
    xtol_rel: float = 1e-10,
    population: int | None = None,
    polish_starts: int = 2,
    scan_points: int = 41,
    scan_rounds: int = 2,
) -> SearchOutcome:
    """Minimise ``f`` over the unit box: an NLopt global stage, then a local polish from its best point.

    Parameters
    ----------
    f
        Objective of a point in [0, 1]^d.
    x0
        Start (inside the box); included in the global stage where the algorithm allows.
    algorithm, local_algorithm
        Names from :data:`GLOBAL_ALGORITHMS` and :data:`LOCAL_ALGORITHMS`
        (``algorithm=None`` skips the global stage: ``x0`` is evaluated and polished;
        ``local_algorithm=None`` skips the polish).
    seed
        Seed of NLopt's random generator (stochastic algorithms are then repeatable).
    maxeval
        Budget of the global stage (default ``100 * d``).
    local_maxeval, xtol_rel
        Budget and relative x tolerance of the polish.
    population
        Population size of CRS2/ISRES/ESCH/MLSL (NLopt's default when None).
    polish_starts
        Number of distinct good points of the global stage to polish locally; a
        final local run restarts from the best of them.
    scan_points, scan_rounds
        After the polish, each parameter is scanned over its whole range at
        ``scan_points`` points from the best point, and the polish resumed from
        anything better, up to ``scan_rounds`` times (``scan_rounds=0`` skips it).
    """
    d = len(x0)
    start = time.perf_counter()
    nlopt.srand(int(seed))
    tracked = _Tracked(f)
    lb, ub = np.zeros(d), np.ones(d)
    x0 = np.clip(np.asarray(x0, dtype=float), 0.0, 1.0)

    if algorithm is None:
        tracked(x0, _NO_GRAD)
        global_stop = "no global stage"
    else:
        gcode = _global_code(algorithm)
        opt = nlopt.opt(gcode, d)
        opt.set_lower_bounds(lb)
        opt.set_upper_bounds(ub)
        opt.set_min_objective(tracked)
        opt.set_maxeval(int(maxeval if maxeval is not None else 100 * d))
        if population:
            opt.set_population(int(population))
        if gcode == nlopt.GN_MLSL:
            loc = nlopt.opt(nlopt.LN_BOBYQA, d)
            loc.set_xtol_rel(1e-4)
            loc.set_maxeval(200)
            opt.set_local_optimizer(loc)
        global_stop = _run(opt, tracked, x0)
    n_global = tracked.calls

    local_stop = "skipped"
    if local_algorithm is not None:

        def polish(x_start: np.ndarray, step: float) -> str:
            loc = nlopt.opt(_local_code(local_algorithm), d)
            loc.set_lower_bounds(lb)
            loc.set_upper_bounds(ub)
            loc.set_min_objective(tracked)
            loc.set_maxeval(int(local_maxeval))
            loc.set_xtol_rel(xtol_rel)
            loc.set_ftol_abs(1e-16)
            loc.set_initial_step(np.full(d, step))
            return _run(loc, tracked, x_start)

        # Polish several distinct good points of the global stage, then restart from the best:
        # delta has kinks where bounces change regime, on which a single local run can stall.
        for x_start in (tracked.distinct_best(polish_starts, 0.05) if polish_starts > 0 else []):
            local_stop = polish(x_start, 0.02)
        local_stop = polish(tracked.best_x, 0.002)
        # Scan each parameter across its whole range from the best point. Where a parameter
        # stops mattering (friction so high that every bounce grips) delta has a plateau that
        # a local search cannot leave, next to a narrow, slightly lower valley; this finds it.
        for _ in range(scan_rounds):
            before = tracked.best_f
            for i in range(d):
                _scan_coordinate(tracked, i, scan_points)
            if tracked.best_f < before:
                local_stop = polish(tracked.best_x, 0.002)
            if tracked.best_f >= before:
                break
    return SearchOutcome(
        x=tracked.best_x,
        fun=tracked.best_f,
        n_global=n_global,
        n_local=tracked.calls - n_global,
        global_stop=global_stop,
        local_stop=local_stop,
        elapsed=time.perf_counter() - start,
        algorithms=((algorithm or "").upper().removeprefix("GN_"), (local_algorithm or "").upper().removeprefix("LN_")),
    )
