"""A whole simulated campaign: launcher, turf and camera together (:func:`simulate_campaign`)."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import xarray as xr

from bouncelab.core import published
from bouncelab.core.errors import DataError, ParameterError
from bouncelab.core.units import BALL_RADIUS_M
from bouncelab.data.campaign import make_campaign
from bouncelab.simulation.camera import Camera
from bouncelab.simulation.launcher import LauncherDesign
from bouncelab.simulation.measure import measure_frames
from bouncelab.simulation.turf import Turf

__all__ = ["SIMULATOR_VERSION", "simulate_campaign"]

#: Version of the simulation procedure, stored in every simulated campaign. "2": the launcher's reachable
#: dial settings are bounded by Table 1 up to the launcher's own scatter (``GRID_TOLERANCE_SD``), not by
#: 5 % of each range's width, which had let in slow, shallow landings the paper never had.
SIMULATOR_VERSION = "2"

#: Times a bounce that cannot be measured is fired again before the simulation gives up.
MAX_REFIRES = 20


def simulate_campaign(
    design: LauncherDesign | str,
    turf: Turf,
    camera: Camera | None = None,
    seed: int = 0,
) -> xr.Dataset:
    """Simulate a campaign: launch, bounce on a varying turf, film and measure every bounce.

    Parameters
    ----------
    design
        The launcher design, or ``"A"`` / ``"B"`` for the paper's
        (:meth:`LauncherDesign.for_campaign`).
    turf
        The turf: a bounce law, the spot-to-spot scatter of its parameters
        and the contact duration (:class:`~bouncelab.simulation.turf.Turf`).
    camera
        The camera and tracker (default :class:`~bouncelab.simulation.camera.Camera`).
    seed
        Seed of all random draws: the same seed, design, turf and camera
        give the same campaign, bit for bit.

    Returns
    -------
    xarray.Dataset
        A campaign (:func:`bouncelab.make_campaign`) with ``landing``,
        ``liftoff``, ``landing_pi``, ``liftoff_pi`` (measured through frames
        by the paper's estimators, :func:`~bouncelab.simulation.measure.measure_frames`)
        and coordinate ``setting``, plus the truth behind them:
        ``true_landing`` and ``true_liftoff`` (bounce, component; the states
        at the true touch-down and lift-off instants), ``spot_parameters``
        (bounce, parameter; the turf law's parameters at each bounce's spot),
        ``contact_time`` (s), ``regime`` (the law's regime code, names in
        attrs ``regimes``), ``refired`` (how often the bounce was fired again
        because it could not be measured) and ``dials`` (bounce, dial; the
        setting's speed m/s, angle deg, spin rpm). attrs say that the data
        are simulated and hold the design, turf and camera as JSON.

    Notes
    -----
    The random draws come from independent streams of one
    :class:`numpy.random.SeedSequence` (plan, launcher scatter, turf spots,
    contact time, camera), so that changing, say, the camera noise does not
    change which settings or spots are drawn. A bounce that cannot be
    measured (no lift-off, ``ydot_F <= 0``; contact not detected; or a measured
    landing with ``ydot_0 >= 0`` or lift-off with ``ydot_F <= 0``, which happens
    when a late detection lets an occluded contact frame into a flight fit of a
    slow bounce) is fired again at the same setting, with new launcher scatter, spot and noise, up
    to ``MAX_REFIRES`` times; lost bounces (``design.lost``) are dropped at
    the end.

    Examples
    --------
    >>> import bouncelab as bl
    >>> from bouncelab.simulation import LauncherDesign, LogNormal, Turf
    >>> turf = Turf(bl.Rigid(r=0.45, mu=0.5), {"r": LogNormal(0.08)})
    >>> ds = simulate_campaign(LauncherDesign.for_campaign("A"), turf, seed=1)
    >>> ds.sizes["bounce"], ds.attrs["data_kind"]
    (330, 'synthetic surrogate')
    """
    if isinstance(design, str):
        design = LauncherDesign.for_campaign(design)
    if not isinstance(design, LauncherDesign):
        raise ParameterError(f"design must be a LauncherDesign or 'A'/'B'; got {type(design).__name__}",
                             parameter="design")
    if not isinstance(turf, Turf):
        raise ParameterError(f"turf must be a bouncelab.simulation.Turf; got {type(turf).__name__}", parameter="turf")
    camera = Camera() if camera is None else camera
    if not isinstance(camera, Camera):
        raise ParameterError(f"camera must be a bouncelab.simulation.Camera; got {type(camera).__name__}",
                             parameter="camera")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ParameterError(f"seed must be a non-negative integer; got {seed!r}", parameter="seed")
    streams = [np.random.default_rng(s) for s in np.random.SeedSequence(int(seed)).spawn(5)]
    rng_plan, rng_launch, rng_spot, rng_contact, rng_camera = streams

    plan = design.plan(rng_plan)
    n = plan.n_planned
    dials = plan.dials[plan.setting - 1]
    k = turf.nominal.size
    names = ("true_landing", "true_liftoff", "landing", "liftoff", "landing_pi", "liftoff_pi")
    res = {name: np.full((n, 3), np.nan) for name in names}
    fired = np.full((n, 3), np.nan)
    spots = np.full((n, k), np.nan)
    contact = np.full(n, np.nan)
    regime = np.zeros(n, dtype=np.int8)
    refired = np.full(n, -1, dtype=np.int64)
    todo = np.arange(n)
    for attempt in range(MAX_REFIRES + 1):
        m = todo.size
        p0, fired_now = design.landings(dials[todo], rng_launch.standard_normal((m, 4)))
        theta = turf.spot_parameters(rng_spot.standard_normal((m, k)))
        pf, codes = turf.liftoff(p0, theta)
        tc = turf.contact.duration(p0, rng_contact.standard_normal(m))
        lifts = np.isfinite(pf).all(axis=1) & (pf[:, 1] > 0)
        good = np.zeros(m, dtype=bool)
        if lifts.any():
            frames = camera.film(p0[lifts], pf[lifts], tc[lifts], rng_camera)
            meas = measure_frames(frames)
            # A measured landing moving up or lift-off moving down is a failed measurement (e.g. a late
            # detection lets an occluded contact frame into a flight fit): the experimenter films again.
            usable = meas.ok & (meas.landing[:, 1] < 0) & (meas.liftoff[:, 1] > 0)
            good[lifts] = usable
            rows = todo[lifts][usable]
            for name in ("landing", "liftoff", "landing_pi", "liftoff_pi"):
                res[name][rows] = getattr(meas, name)[usable]
        done = todo[good]
        res["true_landing"][done] = p0[good]
        res["true_liftoff"][done] = pf[good]
        fired[done] = fired_now[good]
        spots[done] = theta[good]
        contact[done] = tc[good]
        regime[done] = codes[good]
        refired[done] = attempt
        todo = todo[~good]
        if todo.size == 0:
            break
    if todo.size:
        raise DataError(
            f"{todo.size} bounce(s) could not be measured after {MAX_REFIRES} refires (no lift-off or no "
            f"detectable contact), e.g. at setting {int(plan.setting[todo[0]])}: dials "
            f"{plan.dials[plan.setting[todo[0]] - 1].tolist()} (speed m/s, angle deg, spin rpm)",
            column="setting", row=int(todo[0]) + 1
        )

    keep = ~plan.lost
    key = design.campaign
    description = {
        "design": design.to_dict(),
        "turf": turf.to_dict(),
        "camera": camera.to_dict(),
        "seed": int(seed),
        "simulator_version": SIMULATOR_VERSION,
    }
    law_name = turf.to_dict()["law"]["law"]
    ds = make_campaign(
        res["landing"][keep],
        res["liftoff"][keep],
        setting=plan.setting[keep],
        landing_pi=res["landing_pi"][keep],
        liftoff_pi=res["liftoff_pi"][keep],
        campaign=key,
        surface=f"{published.CAMPAIGNS[key]['surface']} (simulated: {turf.name or law_name} turf)",
        ball_radius_m=BALL_RADIUS_M,
        source=f"bouncelab.simulation.simulate_campaign(seed={int(seed)})",
        data_kind="synthetic surrogate",
        # Scaled by construction: the unit guard catches a person's unit mistakes, and would only
        # refuse the turf model's own physics (a stiff turf can spin a ball off beyond 20 000 rpm).
        plausible=None,
        attrs={
            "simulated": "yes",
            "warning": (
                "SIMULATED CAMPAIGN, NOT MEASURED BOUNCES: launcher design of the paper's campaign "
                f"{key}, bounces from the turf model {law_name} with spot-to-spot parameter scatter, "
                "filmed by a simulated camera and measured from the frames by bouncelab's estimators."
            ),
            "simulator": "bouncelab.simulation.simulate_campaign",
            "simulator_version": SIMULATOR_VERSION,
            "simulator_seed": int(seed),
            "turf_law": law_name,
            "simulation_json": json.dumps(description, sort_keys=True),
            "regimes": json.dumps(list(turf.law.regimes)),
            "citation": published.CITATION,
        },
    )
    dims = ("bounce", "component")
    extra: dict[str, Any] = {
        "true_landing": (dims, res["true_landing"][keep], {
            "long_name": "true state at touch-down (before measurement)", "units": "scaled"}),
        "true_liftoff": (dims, res["true_liftoff"][keep], {
            "long_name": "true state at lift-off (before measurement)", "units": "scaled"}),
        "spot_parameters": (("bounce", "parameter"), spots[keep], {
            "long_name": f"parameters of the turf law {law_name} at the bounce's spot"}),
        "contact_time": ("bounce", contact[keep], {"long_name": "duration of contact", "units": "s"}),
        "regime": ("bounce", regime[keep], {"long_name": "regime code of the turf law (names: attrs regimes)"}),
        "refired": ("bounce", refired[keep], {
            "long_name": "times the bounce was fired again because it could not be measured"}),
        "dials": (("bounce", "dial"), dials[keep], {
            "long_name": "launcher dials of the bounce's setting", "units": "m/s, deg, rpm"}),
        "fired": (("bounce", "dial"), fired[keep], {
            "long_name": "speed, angle and spin actually fired (dials plus launcher scatter)",
            "units": "m/s, deg, rpm"}),
    }
    ds = ds.assign(extra).assign_coords(
        parameter=("parameter", list(turf.parameter_names)), dial=("dial", ["speed", "angle", "spin"])
    )
    return ds
