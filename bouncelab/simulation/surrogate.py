"""Synthetic surrogate campaigns: made from the paper's published laws, or simulated from turf physics.

The paper's measured bounces are not bundled with bouncelab, so the embedded
campaigns ``"A"`` and ``"B"`` are **synthetic surrogates**. The default ones
(``surrogate="turf"``, :data:`DEFAULT_SURROGATE`) are simulated by
:func:`generate_turf_surrogate` with the calibrated turf of :data:`TURF_CALIBRATION`
(docs/simulation.md). The ``"published"`` ones are plausible data with the paper's
design, generated here from its published piecewise-affine laws (below). They let every
analysis run on a fresh machine; they are *not* measurements, and every surrogate Dataset says so in its attrs
(``data_kind = "synthetic surrogate"``). Load real files with
:func:`bouncelab.load_campaign` instead whenever you have them.

How a surrogate is made (all random draws from one seeded
:class:`numpy.random.Generator`):

1. **Launcher settings.** A grid of launcher dials spans the campaign's
   Table 1 ranges: :attr:`SurrogateSpec.speed_levels` speeds,
   ``angle_levels`` angles of incidence and ``spin_levels`` spins, evenly
   spaced between the table's minimum and maximum. Grid points whose scaled
   ``xdot0`` or ``ydot0`` fall outside Table 1's scaled ranges are dropped (the
   launcher could not reach them), and the campaign's settings are drawn
   from the rest without replacement.
2. **Repeats.** Each setting is repeated 6 times (campaign A: 55 settings,
   330 bounces) or 6 or 12 times (campaign B: 35 settings of 12 and 47 of 6,
   702 bounces, of which 9 drawn at random are "lost", leaving 693). Each
   repeat scatters about its setting: speed by ``speed_scatter`` (relative,
   1 sd), angle by ``angle_scatter_deg`` and spin by ``spin_scatter`` (relative)
   plus ``spin_scatter_abs_rpm``, as a launcher's wheels and a ball's seating vary.
3. **Turf response.** The true lift-off is the campaign's published
   piecewise-affine law (eq. disjointA or disjointB) plus turf variability:
   Gaussian, per component, with standard deviation
   ``sqrt(pi/2) * Delta_q * ||p0||`` where ``Delta_q`` is the paper's
   Table 2 error for that component (mean of the roll and slip columns), so
   that the published law scores on the surrogate about what it scored on the
   paper's data.
4. **Measurement.** Each landing and lift-off component gets a 95 %
   prediction-interval half-width of ``pi_fraction / 2`` times the campaign
   mean of ``|q|``, scattered log-normally (``pi_spread``), so that most
   interval widths are about 5 % of the mean value as the paper reports; the
   recorded value is the true one plus Gaussian noise of standard deviation
   half-width / 1.96, so the stored intervals are honest 95 % intervals.

What the surrogates do not reproduce (the noise is Gaussian and never truncated):

* Launcher scatter and measurement noise take some values past Table 1's
  printed ranges: 65 landing spins of A and 133 of B lie outside its spin
  range, and 29 near-vertical landings of B have a small negative ``xdot0``.
* The published law B itself predicts ``ydotF <= 0`` (no lift-off) for a few
  steep, high-backspin landings inside Table 1, and with turf noise 13 bounces
  of surrogate B leave with ``ydotF <= 0``.
* The slip/roll labels follow the published plane only up to noise, so the
  fraction of bounces on the "wrong" side of the plane (12 % for A, 19 % for B
  with the generating law) is higher than the paper's 7.27 % and 9.59 %; the
  paper's own data evidently had less turf scatter near the plane.
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import asdict, dataclass, field

import numpy as np
import xarray as xr

from bouncelab.core import checks, published
from bouncelab.core.errors import NonphysicalLiftoffWarning, ParameterError
from bouncelab.core.units import BALL_RADIUS_M, landing_from_speed_angle_spin
from bouncelab.data.campaign import make_campaign
from bouncelab.data.embedded import DEFAULT_SURROGATE, SURROGATES, embedded_file_name, embedded_path

__all__ = [
    "DEFAULT_SEEDS",
    "DEFAULT_SURROGATE",
    "SURROGATES",
    "TURF_CALIBRATION",
    "SurrogateSpec",
    "embedded_file_name",
    "embedded_path",
    "generate_surrogate",
    "generate_turf_surrogate",
    "turf_for_campaign",
]

#: Seeds of the embedded surrogates (``bouncelab/data/files/campaign_{A,B}.nc``).
DEFAULT_SEEDS = {"A": 330, "B": 693}

GENERATOR_VERSION = "1"


@dataclass(frozen=True)
class SurrogateSpec:
    """Design of a surrogate campaign (see the module docstring for the procedure)."""

    campaign: str
    settings: tuple[tuple[int, int], ...]  # (number of settings, repeats per setting)
    lost: int = 0
    speed_levels: int = 6
    angle_levels: int = 5
    spin_levels: int = 6
    speed_scatter: float = 0.02
    angle_scatter_deg: float = 0.6
    spin_scatter: float = 0.04
    spin_scatter_abs_rpm: float = 60.0
    pi_fraction: float = 0.05
    pi_spread: float = 0.35
    turf_delta_q: tuple[float, float, float] = field(default=(0.0, 0.0, 0.0))

    @classmethod
    def for_campaign(cls, campaign: str) -> SurrogateSpec:
        """The design used for the embedded surrogate of campaign "A" or "B"."""
        key = published.check_campaign(campaign)
        t2 = published.TABLE2.loc[key].loc[["roll", "slip"]]
        dq = tuple(float(t2[c].mean()) for c in ("delta_xdot", "delta_ydot", "delta_omega"))
        if key == "A":
            return cls(campaign="A", settings=((55, 6),), turf_delta_q=dq)
        return cls(campaign="B", settings=((35, 12), (47, 6)), lost=9, turf_delta_q=dq)


def _setting_grid(spec: SurrogateSpec) -> np.ndarray:
    """Reachable (speed m/s, angle deg, spin rpm) launcher settings spanning Table 1."""
    t1 = published.TABLE1.loc[spec.campaign]
    speeds = np.linspace(t1.loc["speed", "min"], t1.loc["speed", "max"], spec.speed_levels)
    angles = np.linspace(t1.loc["angle", "min"], t1.loc["angle", "max"], spec.angle_levels)
    spins = np.linspace(t1.loc["spin", "min"], t1.loc["spin", "max"], spec.spin_levels)
    grid = np.array(list(itertools.product(speeds, angles, spins)))
    p0 = landing_from_speed_angle_spin(grid[:, 0], grid[:, 1], grid[:, 2])
    ok = np.ones(len(grid), dtype=bool)
    for col, name in enumerate(("xdot", "ydot")):
        lo, hi = t1.loc[name, "min"], t1.loc[name, "max"]
        ok &= (p0[:, col] >= lo) & (p0[:, col] <= hi)
    return grid[ok]


def generate_surrogate(campaign: str, *, seed: int | None = None, spec: SurrogateSpec | None = None) -> xr.Dataset:
    """Generate a synthetic surrogate of the paper's campaign "A" or "B".

    Parameters
    ----------
    campaign
        "A" (artificial turf) or "B" (natural tee).
    seed
        Seed of the random generator; the embedded files use :data:`DEFAULT_SEEDS`.
    spec
        Design to use instead of :meth:`SurrogateSpec.for_campaign`.

    Returns
    -------
    xarray.Dataset
        A campaign (see :func:`bouncelab.make_campaign`) with ``setting``,
        ``landing_pi`` and ``liftoff_pi``, whose attrs say it is synthetic.
    """
    key = published.check_campaign(campaign)
    spec = spec or SurrogateSpec.for_campaign(key)
    if spec.campaign != key:
        raise ParameterError(f"spec is the design of campaign {spec.campaign!r}, not {key!r}", parameter="spec")
    seed = DEFAULT_SEEDS[key] if seed is None else checks.seed(seed)
    rng = np.random.default_rng(seed)

    grid = _setting_grid(spec)
    n_settings = sum(n for n, _ in spec.settings)
    if n_settings > len(grid):
        raise ParameterError(f"the grid has {len(grid)} reachable settings; {n_settings} were asked for",
                             parameter="settings", value=n_settings)
    chosen = grid[rng.choice(len(grid), size=n_settings, replace=False)]
    repeats = np.concatenate([np.full(n, k) for n, k in spec.settings])
    setting = np.repeat(np.arange(1, n_settings + 1), repeats)
    dial = np.repeat(chosen, repeats, axis=0)
    n = len(setting)

    speed = dial[:, 0] * (1.0 + spec.speed_scatter * rng.standard_normal(n))
    angle = np.clip(dial[:, 1] + spec.angle_scatter_deg * rng.standard_normal(n), 1.0, 90.0)
    spin = (
        dial[:, 2] * (1.0 + spec.spin_scatter * rng.standard_normal(n))
        + spec.spin_scatter_abs_rpm * rng.standard_normal(n)
    )
    landing = landing_from_speed_angle_spin(speed, angle, spin)

    from bouncelab.laws.piecewise import PiecewiseAffine

    law = PiecewiseAffine.published(key)
    norm0 = np.linalg.norm(landing, axis=1, keepdims=True)
    turf_sd = np.sqrt(np.pi / 2.0) * np.asarray(spec.turf_delta_q) * norm0
    with warnings.catch_warnings():  # the surrogate is the published law by design, warts included
        warnings.simplefilter("ignore", NonphysicalLiftoffWarning)
        liftoff = law.predict(landing, plausible=None) + turf_sd * rng.standard_normal((n, 3))

    def measured(true: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        scale = 0.5 * spec.pi_fraction * np.abs(true).mean(axis=0)
        half = scale * rng.lognormal(0.0, spec.pi_spread, size=true.shape)
        return true + half / 1.96 * rng.standard_normal(true.shape), half

    landing_meas, landing_pi = measured(landing)
    liftoff_meas, liftoff_pi = measured(liftoff)

    keep = np.ones(n, dtype=bool)
    if spec.lost:
        keep[rng.choice(n, size=spec.lost, replace=False)] = False
    table_surface = published.CAMPAIGNS[key]["surface"]
    return make_campaign(
        landing_meas[keep],
        liftoff_meas[keep],
        setting=setting[keep],
        landing_pi=landing_pi[keep],
        liftoff_pi=liftoff_pi[keep],
        campaign=key,
        surface=f"{table_surface} (synthetic surrogate)",
        ball_radius_m=BALL_RADIUS_M,
        source=f"bouncelab.simulation.surrogate.generate_surrogate({key!r}, seed={seed})",
        data_kind="synthetic surrogate",
        attrs={
            "warning": (
                "SYNTHETIC SURROGATE: generated by bouncelab from the paper's published piecewise-affine "
                f"law (eq. disjoint{key}) with modelled scatter and noise. These are NOT measured bounces."
            ),
            "generator_version": GENERATOR_VERSION,
            "generator_seed": seed,
            "generator_spec": repr(asdict(spec)),
            "citation": published.CITATION,
        },
    )


#: The calibrated turf of the ``"turf"`` surrogates: the turf law (CraterContact), its nominal
#: parameters, the spot-to-spot standard deviation of the natural log of those that vary (LogNormal
#: scatter; the others do not vary), and the seed of :func:`bouncelab.simulate_campaign`. Found by
#: ``benchmarks/calibrate_surrogates.py`` (see docs/simulation.md for the runs and how close they come
#: to the paper).
TURF_CALIBRATION: dict[str, dict] = {
    "A": {
        "law": "CraterContact",
        "nominal": {"r0": 0.51756, "v_r": 10772.0, "mu_k": 0.084598, "mu_s": 0.48538, "v_s": 500.48,
                    "lam": 0.19054, "kappa": 0.25053, "e_t": 0.30819, "beta0": 6.536, "beta_n": 0.00012378,
                    "beta_t": 3.889e-06},
        "log_sd": {"r0": 0.03534, "mu_k": 0.05948, "lam": 0.1034, "e_t": 0.1038, "beta0": 0.1677},
        "seed": 330,
    },
    "B": {
        "law": "CraterContact",
        "nominal": {"r0": 0.96751, "v_r": 260.78, "mu_k": 0.56696, "mu_s": 0.21741, "v_s": 394.23,
                    "lam": 0.23072, "kappa": 1.1012e-05, "e_t": 0.68871, "beta0": 1.6353e-05, "beta_n": 8.0456,
                    "beta_t": 13.405},
        "log_sd": {"r0": 0.0748, "mu_k": 0.03834, "lam": 0.08109, "e_t": 0.07526, "beta0": 0.1227},
        "seed": 693,
    },
}


def turf_for_campaign(campaign: str):
    """The calibrated turf (:class:`bouncelab.simulation.Turf`) of campaign "A" or "B" (:data:`TURF_CALIBRATION`)."""
    from bouncelab.laws import law_class
    from bouncelab.simulation import LogNormal, Turf

    key = published.check_campaign(campaign)
    cal = TURF_CALIBRATION[key]
    law = law_class(cal["law"])(**cal["nominal"])
    scatter = {name: LogNormal(float(sd)) for name, sd in cal["log_sd"].items() if sd > 0}
    return Turf(law, scatter, name=f"calibrated {cal['law']} (campaign {key})")


def generate_turf_surrogate(campaign: str, *, seed: int | None = None) -> xr.Dataset:
    """Simulate the ``"turf"`` surrogate of campaign "A" or "B" (the embedded ``campaign_{A,B}_turf.nc``).

    The paper's launcher design (:meth:`bouncelab.simulation.LauncherDesign.for_campaign`),
    the calibrated turf law (:data:`TURF_CALIBRATION`) with spot-to-spot scatter (:func:`turf_for_campaign`) and the
    default camera, through :func:`bouncelab.simulate_campaign` with the seed of
    :data:`TURF_CALIBRATION` (or ``seed``). The attrs say the data are simulated and hold the
    turf's parameters (``turf_calibration``, JSON) besides the simulator's own description.
    """
    import json

    from bouncelab.simulation import LauncherDesign, simulate_campaign

    key = published.check_campaign(campaign)
    cal = TURF_CALIBRATION[key]
    seed = int(cal["seed"]) if seed is None else int(seed)
    ds = simulate_campaign(LauncherDesign.for_campaign(key), turf_for_campaign(key), seed=seed)
    ds.attrs["surrogate"] = "turf"
    ds.attrs["turf_calibration"] = json.dumps({**cal, "seed": seed}, sort_keys=True)
    ds.attrs["warning"] = (
        f"SIMULATED CAMPAIGN, NOT MEASURED BOUNCES (surrogate 'turf'): the launcher design of the paper's "
        f"campaign {key}, bounces from the turf model {cal['law']} with parameters {cal['nominal']} varying "
        f"from spot to spot (sd of ln: {cal['log_sd']}), filmed by a simulated camera and measured from the "
        "frames by bouncelab's estimators (bouncelab.simulation.simulate_campaign)."
    )
    return ds


def write_embedded(directory=None, surrogates=("turf",)) -> list:
    """Regenerate the embedded surrogate files (``python -m bouncelab.simulation.surrogate --write``).

    By default only the ``"turf"`` files are rewritten (the ``"published"`` ones are unchanged
    since generator version 1); pass ``surrogates=("published", "turf")`` for both.
    """
    from pathlib import Path

    from bouncelab.core.atomic import atomic_path

    paths = []
    for surrogate in surrogates:
        for key in ("A", "B"):
            path = embedded_path(key, surrogate)
            if directory is not None:
                path = Path(directory) / path.name
            ds = generate_surrogate(key) if surrogate == "published" else generate_turf_surrogate(key)
            with atomic_path(path) as tmp:
                ds.to_netcdf(tmp, engine="scipy")
            paths.append(path)
    return paths


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description="Regenerate bouncelab's embedded surrogate campaign files.")
    ap.add_argument("--write", action="store_true", help="write the files (without it, only list them)")
    ap.add_argument("--surrogate", nargs="+", default=["turf"], choices=list(SURROGATES))
    ap.add_argument("--directory", default=None, help="write here instead of bouncelab/data/files")
    args = ap.parse_args()
    if not args.write:
        for s in args.surrogate:
            for k in ("A", "B"):
                print(embedded_path(k, s))
    else:
        for p in write_embedded(args.directory, tuple(args.surrogate)):
            print(f"wrote {p}")
