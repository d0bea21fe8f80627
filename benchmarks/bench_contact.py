"""Speed of the physics-based contact laws, against solve_ivp per bounce at equal accuracy.

Run: ``python benchmarks/bench_contact.py`` (a few minutes; ``--quick``: a few landings and a fit on 40 bounces
with a small budget, a few seconds once the kernels are compiled, for CI).
Everything is timed in the same run. Prints

1. the speed-up of each law over ``scipy.integrate.solve_ivp`` integrating the same
   equations bounce by bounce (``benchmarks/contact_reference.py``), both on one thread and at a
   lift-off accuracy of 1e-6 of the landing speed: solve_ivp's ``rtol`` and TurfContact's and
   CraterContact's number of RK4 steps are each the loosest setting whose worst error over the
   sample is below 1e-6, measured against the same reference far tighter (solve_ivp at rtol 1e-12 or
   1e-13: independent of the compiled kernels) (target: at least 100x);
2. ``predict`` throughput (targets: CompliantImpact 10^6 bounces/s, TurfContact 10^5 bounces/s;
   CraterContact reported);
3. the time of a global fit of TurfContact to campaign B (693 bounces; target under 30 s).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bouncelab as bl
from benchmarks.contact_reference import compliant_reference, crater_reference, turf_reference

TOL = 1e-6
COMPLIANT = {"r": 0.5, "mu": 0.4, "kappa": 1.5}
TURF = {"log10_k": 6.8, "c": 1.0, "e_y": 0.3, "mu": 0.6, "log10_kt": 6.0, "lam": 3.0}
CRATER = {"r0": 0.6, "v_r": 2000.0, "mu_k": 0.15, "mu_s": 1.0, "v_s": 150.0, "lam": 0.25, "kappa": 0.1,
          "e_t": 0.2, "beta0": 5.0, "beta_n": 4.0, "beta_t": 3.0}


def landings(n: int, seed: int = 0) -> np.ndarray:
    """Landings spanning the paper's Table 1, in scaled units: golf landings, which predict's unit guard accepts
    (the flattest come in at 5.5 degrees: xdot0 is capped at |ydot0| / tan 5.5 deg)."""
    rng = np.random.default_rng(seed)
    xd, yd = rng.uniform(1, 2300, n), -rng.uniform(90, 1900, n)
    return np.column_stack([np.minimum(xd, -yd / np.tan(np.radians(5.5))), yd, rng.uniform(-410, 1700, n)])


def rel_err(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> float:
    return float((np.abs(a - b).max(axis=1) / np.linalg.norm(p, axis=1)).max())


def timed(f):
    t = time.perf_counter()
    out = f()
    return out, time.perf_counter() - t


def loosest_ivp(ref_fn, p, truth):
    for rtol in (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11):
        out, dt = timed(lambda rtol=rtol: np.array([ref_fn(q, rtol) for q in p]))
        err = rel_err(out, truth, p)
        if err < TOL:
            return rtol, err, dt / len(p)
    return rtol, err, dt / len(p)


def steps_loop(integrate):
    """A compiled loop over landings of ``integrate(xd, yd, w, theta, nsteps)`` (a contact law's integrator)."""
    from bouncelab.core._jit import jit  # numba.njit with a disk cache that also serves closures

    @jit(nogil=True)
    def run(P, theta, nsteps, out):
        for i in range(P.shape[0]):
            a, b, c, _ = integrate(P[i, 0], P[i, 1], P[i, 2], theta, nsteps)
            out[i, 0] = a
            out[i, 1] = b
            out[i, 2] = c
        return out

    return run


def rk4_against_ivp(name, law, integrate, reference, p, truth, step_choices, default_steps):
    """Print an RK4 law against its solve_ivp reference, both at the loosest setting within TOL of ``truth``.

    ``reference(q, rtol)`` is the solve_ivp lift-off of landing ``q``; ``integrate`` the law's kernel
    integrator, run with the kernel vector of ``law`` and each of ``step_choices`` until within TOL.
    """
    ktheta = np.array(law._args(law._fitted_values()), dtype=np.float64)  # what its kernel passes the integrator
    run = steps_loop(integrate)
    rtol, err_ivp, t_ivp = loosest_ivp(reference, p, truth)
    for nsteps in step_choices:
        o = run(p, ktheta, nsteps, np.empty_like(p))
        if rel_err(o, truth, p) < TOL:
            break
    err_bl = rel_err(o, truth, p)
    big = np.tile(p, (200, 1))
    run(big[:2], ktheta, nsteps, np.empty_like(big[:2]))
    _, dt = timed(lambda: run(big, ktheta, nsteps, np.empty_like(big)))
    t_bl = dt / len(big)
    err_default = rel_err(law.predict(p), truth, p)
    print(f"\n{name} vs solve_ivp (DOP853, rtol={rtol:g}), {len(p)} landings, accuracy target {TOL:g}:")
    print(f"  error: solve_ivp {err_ivp:.1e}, bouncelab with {nsteps} RK4 steps {err_bl:.1e} "
          f"(predict's default {default_steps} steps: {err_default:.1e})")
    print(f"  time per bounce (one thread): solve_ivp {t_ivp * 1e6:9.1f} us, bouncelab {t_bl * 1e6:7.2f} us  "
          f"-> speed-up {t_ivp / t_bl:,.0f}x")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a few bounces everywhere and no fit: checks that the "
                                                         "benchmark runs (CI)")
    args = ap.parse_args(argv)
    n_ivp = 3 if args.quick else 60
    n_big = 10_000 if args.quick else 1_000_000
    print(f"threads: {bl.laws.num_threads()}  (BOUNCELAB_NUM_THREADS)")

    # ---- 1. against solve_ivp at equal accuracy
    p = landings(n_ivp, seed=1)
    ci = bl.CompliantImpact(**COMPLIANT)
    ci.predict(p[:2])
    truth = np.array([compliant_reference(q, **COMPLIANT, rtol=1e-12, atol=1e-12) for q in p])
    rtol, err_ivp, t_ivp = loosest_ivp(lambda q, rt: compliant_reference(q, **COMPLIANT, rtol=rt, atol=rt), p, truth)
    reps = 50 if args.quick else 2000
    big = np.tile(p, (reps, 1))
    threads = bl.laws.num_threads()
    bl.laws.set_num_threads(1)  # solve_ivp runs on one thread: so does predict here
    try:
        out, dt = timed(lambda: ci.predict(big))
    finally:
        bl.laws.set_num_threads(threads)
    t_bl = dt / len(big)
    print(f"\nCompliantImpact vs solve_ivp (DOP853, rtol={rtol:g}), {n_ivp} landings, accuracy target {TOL:g}:")
    print(f"  error: solve_ivp {err_ivp:.1e}, bouncelab {rel_err(out[:n_ivp], truth, p):.1e}")
    print(f"  time per bounce (one thread): solve_ivp {t_ivp * 1e6:9.1f} us, bouncelab {t_bl * 1e6:7.3f} us  "
          f"-> speed-up {t_ivp / t_bl:,.0f}x")

    from bouncelab.laws._contact_kernels import CRATER_STEPS, crater_integrate, turf_integrate
    from bouncelab.laws.turf import TURF_STEPS

    tl = bl.TurfContact(**TURF)
    theta = np.array(list(TURF.values()))
    # the truth: the solve_ivp reference itself, far tighter (the kernel at many steps is no truth: its lift-off
    # xdot converges at first order near a mode switch and, on some landings, jumps by ~5e-7 of |p0| past 1024 steps)
    truth = np.array([turf_reference(q, theta, rtol=1e-13, atol=1e-13) for q in p])
    rk4_against_ivp("TurfContact", tl, turf_integrate, lambda q, rt: turf_reference(q, theta, rtol=rt, atol=rt),
                    p, truth, (32, 64, 128, 256, 512, 1024), TURF_STEPS)

    cl = bl.CraterContact(**CRATER)
    ctheta = np.array(list(CRATER.values()))
    # the truth: the solve_ivp reference itself, far tighter (independent of the compiled kernel)
    truth = np.array([crater_reference(q, ctheta, rtol=1e-13, atol=1e-13)[:3] for q in p])
    rk4_against_ivp("CraterContact", cl, crater_integrate,
                    lambda q, rt: crater_reference(q, ctheta, rtol=rt, atol=rt)[:3],
                    p, truth, (12, 24, 48, 96, 192, 384, 768, 1536), CRATER_STEPS)

    # ---- 2. predict throughput
    P = landings(n_big, seed=2)
    ci.predict(P[:100])
    _, dt = timed(lambda: ci.predict(P))
    print(f"\nCompliantImpact.predict: {n_big / dt / 1e6:.2f} million bounces/s ({n_big:,} bounces)")
    m = n_big // 5
    tl.predict(P[:100])
    _, dt = timed(lambda: tl.predict(P[:m]))
    print(f"TurfContact.predict:     {m / dt / 1e3:.0f} thousand bounces/s ({m:,} bounces, default 64 steps)")
    # spot-to-spot variation: 5 % on the linear parameters, 0.05 on the log10 stiffnesses
    noise = 0.05 * np.random.default_rng(3).standard_normal((m, 6))
    rows = np.tile(theta, (m, 1)) * (1 + noise)
    rows[:, [0, 4]] = theta[[0, 4]] + noise[:, [0, 4]]
    bl.TurfContact.predict_varying(P[:100], rows[:100])
    _, dt = timed(lambda: bl.TurfContact.predict_varying(P[:m], rows))
    print(f"TurfContact.predict_varying (one parameter row per bounce): {m / dt / 1e3:.0f} thousand/s")
    cl.predict(P[:100])
    _, dt = timed(lambda: cl.predict(P[:m]))
    print(f"CraterContact.predict:   {m / dt / 1e3:.0f} thousand bounces/s ({m:,} bounces, default 48 steps)")

    # ---- 3. fit time
    ds = bl.load_campaign("B", surrogate="published")
    budget = {}
    if args.quick:  # the same fit on fewer bounces with a small global budget: checks the path, times nothing
        ds, budget = ds.isel(bounce=slice(0, 40)), {"maxeval": 200}
    res, dt = timed(lambda: bl.fit(bl.TurfContact, ds, seed=0, **budget))
    print(f"\nTurfContact global fit to campaign B ({ds.sizes['bounce']} bounces"
          f"{', --quick: the first 40, global stage of 200 evaluations' if args.quick else ''}): {dt:.1f} s, "
          f"delta = {res.delta:.4f}, {res.n_evaluations} evaluations")


if __name__ == "__main__":
    main()
