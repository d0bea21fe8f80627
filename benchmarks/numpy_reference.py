"""Straightforward NumPy versions of the rigid-family laws and of delta.

They are written directly from the paper's equations, independently of
bouncelab's compiled kernels, and serve twice: as the peer that the benchmarks
measure bouncelab against, and as the independent reference that the tests
compare the kernels with.
"""

from __future__ import annotations

import numpy as np


def rigid(p: np.ndarray, r: float, mu: float, e_t: float = 0.0) -> np.ndarray:
    """Eq. (rigid_bounce) (and, with e_t > 0, the tangential-restitution variant)."""
    x, y, w = p.T
    k = mu * (1 + r)
    vp = x + w
    lim = 3.5 * k * np.abs(y) / (1 + e_t)
    fwd, back = vp > lim, vp < -lim
    j = -(1 + e_t) * vp / 3.5
    xf = np.where(fwd, x + k * y, np.where(back, x - k * y, x + j))
    wf = np.where(fwd, w + 2.5 * k * y, np.where(back, w - 2.5 * k * y, w + 2.5 * j))
    return np.column_stack([xf, -r * y, wf])


def penner(p: np.ndarray, r: float, mu: float, beta: np.ndarray | float) -> np.ndarray:
    """Rotate into the tilted frame (beta in radians), bounce rigidly, rotate back; mirror -x balls."""
    sgn = np.where(p[:, 0] >= 0, 1.0, -1.0)
    m = p * np.column_stack([sgn, np.ones_like(sgn), sgn])
    c, s = np.cos(beta), np.sin(beta)
    rot = np.column_stack([c * m[:, 0] + s * m[:, 1], -s * m[:, 0] + c * m[:, 1], m[:, 2]])
    out = rigid(rot, r, mu)
    back = np.column_stack([c * out[:, 0] - s * out[:, 1], s * out[:, 0] + c * out[:, 1], out[:, 2]])
    return back * np.column_stack([sgn, np.ones_like(sgn), sgn])


def penner_angle(p: np.ndarray, k_p: float) -> np.ndarray:
    """beta = k_p s phi (radians), capped at pi/2."""
    s = np.hypot(p[:, 0], p[:, 1])
    phi = np.arctan2(-p[:, 1], np.abs(p[:, 0]))
    return np.minimum(k_p * s * phi, np.pi / 2)


def predict(law: str, p: np.ndarray, theta) -> np.ndarray:
    """Lift-off of ``law`` ("Rigid", "PennerFixed", "PennerVarying", "TangentialRestitution")."""
    if law == "Rigid":
        return rigid(p, *theta)
    if law == "PennerFixed":
        return penner(p, theta[0], theta[1], np.radians(theta[2]))
    if law == "PennerVarying":
        return penner(p, theta[0], theta[1], penner_angle(p, theta[2]))
    if law == "TangentialRestitution":
        return rigid(p, *theta)
    raise ValueError(law)


def delta(p0: np.ndarray, pf: np.ndarray, pred: np.ndarray) -> float:
    """Eq. (error)."""
    return float(np.mean(np.linalg.norm(pf - pred, axis=1) / np.linalg.norm(p0, axis=1)))
