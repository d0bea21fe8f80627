"""Slip/roll classification of measured bounces (section "Distinguishing between slipping and rolling")."""

from __future__ import annotations

import numpy as np

from bouncelab.core.checks import positive
from bouncelab.core.errors import DataError
from bouncelab.core.validation import States, as_states, check_same_length

__all__ = ["SLIP_ROLL_CLASSES", "classify_slip_roll"]

#: Class names, in the order of the integer codes returned with ``codes=True``.
SLIP_ROLL_CLASSES = ("roll", "slip")


def classify_slip_roll(landing: States, liftoff: States, *, tol: float = 0.0, codes: bool = False) -> np.ndarray:
    """Label each measured bounce "slip" or "roll" from its contact-point velocity.

    A bounce *slipped* throughout when ``v_P = xdot + omega`` has the same,
    non-zero sign at touch-down and at lift-off; in every other case the ball
    must have entered rolling at some point, so it is labelled *roll*. Note
    that a topspin landing with ``v_P < 0`` at both ends counts as slip.

    Parameters
    ----------
    landing, liftoff
        (n, 3) states in scaled units.
    tol
        ``|v_P| <= tol`` (radii/s) counts as zero, i.e. as rolling; the paper uses 0.
    codes
        Return int8 codes (0 roll, 1 slip, indexing :data:`SLIP_ROLL_CLASSES`)
        instead of names.

    Returns
    -------
    numpy.ndarray
        (n,) array of "slip"/"roll" (or codes).
    """
    p0, _ = as_states(landing, "landing", landing=True)
    pf, _ = as_states(liftoff, "liftoff")
    check_same_length(p0, pf, "landing", "liftoff")
    tol = positive(tol, "tol", allow_zero=True, error=DataError)
    c = _slip_codes(p0, pf, tol)
    return c if codes else np.asarray(SLIP_ROLL_CLASSES)[c]


def _slip_codes(p0: np.ndarray, pf: np.ndarray, tol: float = 0.0) -> np.ndarray:
    """int8 codes (0 roll, 1 slip) of validated (n, 3) arrays; the internal form of :func:`classify_slip_roll`."""
    v0 = p0[:, 0] + p0[:, 2]
    vf = pf[:, 0] + pf[:, 2]
    slip = (np.abs(v0) > tol) & (np.abs(vf) > tol) & (np.sign(v0) == np.sign(vf))
    return slip.astype(np.int8)
