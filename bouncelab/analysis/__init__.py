"""Analyses of bounce data: measurement error, repeatability and contact-point velocities.

Submodules
----------
trajectories
    Synthetic high-speed-camera tracks of a bounce (:func:`simulate_tracked_bounce`).
measurement
    The paper's extraction of landing and lift-off states with their 95 %
    intervals from tracked frames (:func:`measure_bounce`).
repeats
    Per-launcher-setting means and Student-t confidence intervals of the mean
    at landing and lift-off (:func:`repeatability`, the paper's Appendix
    Fig. 9) and how often lift-off intervals are wider
    (:func:`repeatability_summary`).
impulse
    Where the horizontal impulse acts: per-bounce lever arm Δω/Δẋ
    (:func:`impulse_lever_arm`, 2.5 for an impulse at the contact point) and its
    median for data and laws (:func:`lever_arm_summary`).
contact_velocity
    Contact-point velocity ``v_P = xdot + omega`` at landing and lift-off
    (:func:`tangential_velocities`, the paper's Fig. 7) and counts of slip,
    roll, ``v_P`` and spin reversals and near-rolling lift-offs
    (:func:`tangential_summary`, :func:`tangential_crosstab`).
"""

from __future__ import annotations

from bouncelab.analysis.contact_velocity import (
    tangential_crosstab,
    tangential_summary,
    tangential_velocities,
)
from bouncelab.analysis.impulse import impulse_lever_arm, lever_arm_summary
from bouncelab.analysis.measurement import (
    ContactDetection,
    SpinEstimate,
    VelocityEstimate,
    detect_contact,
    estimate_spin,
    estimate_velocity,
    interval_coverage,
    measure_bounce,
)
from bouncelab.analysis.repeats import repeatability, repeatability_summary
from bouncelab.analysis.trajectories import simulate_tracked_bounce

__all__ = [
    "ContactDetection",
    "SpinEstimate",
    "VelocityEstimate",
    "detect_contact",
    "estimate_spin",
    "estimate_velocity",
    "impulse_lever_arm",
    "interval_coverage",
    "lever_arm_summary",
    "measure_bounce",
    "repeatability",
    "repeatability_summary",
    "simulate_tracked_bounce",
    "tangential_crosstab",
    "tangential_summary",
    "tangential_velocities",
]
