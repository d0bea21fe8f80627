"""The high-speed camera of a simulated campaign: frames of the ball's centre and rotation
before, during and after contact, with tracking noise and the turf hiding the ball (:class:`Camera`).

The paper filmed every bounce at 5,000-10,000 frames per second and tracked the
ball's centre (circle detection) and rotation (feature matching between
frames); touch-down and lift-off are where the lowest visible point of the
ball changes velocity abruptly. :meth:`Camera.film` produces those tracks for
many bounces at once, as arrays over ``(bounce, frame)``, frame by frame:

* **Flight.** Before touch-down and after lift-off the centre obeys
  ``r'' = -g y_hat - k |r'| r'`` (gravity, quadratic drag ``k`` per radius,
  :func:`bouncelab.analysis.trajectories.drag_scaled`), integrated with the
  classical 4th-order Runge-Kutta method one frame at a time, backward from
  touch-down and forward from lift-off, for all bounces together. Gravity
  alone is integrated exactly (RK4 is exact for polynomials of degree 4);
  with drag the local error per frame is of order ``(k |v| dt)^5 |v| dt``,
  below 1e-20 radii at the paper's speeds. Spin is constant in flight.
* **Contact.** The centre follows the cubic Hermite curve matching position
  and velocity at touch-down ``(0, 1)`` and lift-off ``(x_F, 1)`` (the ball
  sinks into the turf and comes back), the spin changes linearly. The
  contact lasts ``t_c`` (from the turf, :class:`~bouncelab.simulation.turf.ContactDuration`);
  touch-down falls at a uniformly random point between two frames.
* **Tracking noise.** Each tracked coordinate of the centre carries
  independent Gaussian noise of ``pixel_noise`` pixels, i.e.
  ``pixel_noise / pixels_per_radius`` radii; each per-frame spin sample is
  the rotation since the previous frame, with independent Gaussian error of
  ``angle_noise_deg``, divided by the frame period.
* **Occlusion.** During contact the turf hides the bottom of the ball: the
  lowest visible point is the surface line (plus the same pixel noise), and
  the centre and rotation are tracked with ``occluded_factor`` times more
  noise (they are not used by the estimators, which leave contact frames out).

Each clip has ``frames_before`` frames before touch-down and at least
``frames_after`` after lift-off; all clips of one call have the same number of
frames (a longer contact leaves fewer frames after lift-off in the clip, never
fewer than ``frames_after``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from bouncelab.analysis.trajectories import DRAG_SCALED, GRAVITY_SCALED, MAX_FRAMES
from bouncelab.core import checks
from bouncelab.core.errors import ParameterError

__all__ = ["Camera", "Frames"]


@dataclass(frozen=True)
class Frames:
    """Tracks of many bounces filmed by one camera, one row per bounce.

    Attributes
    ----------
    t
        (N,) frame times, s (frame ``k`` at ``k / fps``).
    x, y
        (n, N) tracked ball-centre coordinates, radii (surface at ``y = 0``).
    spin
        (n, N) spin samples from the rotation since the previous frame, rad/s.
    lowest
        (n, N) height of the lowest visible point of the ball, radii.
    in_contact
        (n, N) ground truth: True for frames during contact.
    touchdown_time, liftoff_time
        (n,) true instants of touch-down and lift-off, s.
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    spin: np.ndarray
    lowest: np.ndarray
    in_contact: np.ndarray
    touchdown_time: np.ndarray
    liftoff_time: np.ndarray

    def track(self, i: int) -> dict[str, np.ndarray]:
        """Bounce ``i`` as a mapping accepted by :func:`bouncelab.analysis.measurement.measure_bounce`."""
        return {"t": self.t, "x": self.x[i], "y": self.y[i], "spin": self.spin[i], "lowest": self.lowest[i]}


@dataclass(frozen=True)
class Camera:
    """A high-speed camera and ball tracker.

    Parameters
    ----------
    fps
        Frame rate, frames/s (the paper: 5,000-10,000).
    frames_before
        Frames recorded before touch-down.
    frames_after
        Fewest frames recorded after lift-off.
    pixels_per_radius
        Image scale: pixels per ball radius (55 px: a 21.35 mm ball radius at 0.39 mm/px).
    pixel_noise
        Standard deviation of each tracked centre coordinate, pixels.
    angle_noise_deg
        Standard deviation of the rotation measured between two consecutive frames, degrees.
    occluded_factor
        Noise multiplier for the centre and rotation while the turf hides the ball.
    drag
        Quadratic-drag coefficient, per radius (:data:`~bouncelab.analysis.trajectories.DRAG_SCALED`).
    gravity
        Gravitational acceleration, radii/s^2.

    Examples
    --------
    >>> cam = Camera()
    >>> round(cam.position_noise, 5)  # radii
    0.00273
    """

    fps: float = 5000.0
    frames_before: int = 40
    frames_after: int = 40
    pixels_per_radius: float = 55.0
    pixel_noise: float = 0.15
    angle_noise_deg: float = 0.46
    occluded_factor: float = 10.0
    drag: float = DRAG_SCALED
    gravity: float = GRAVITY_SCALED

    def __post_init__(self) -> None:
        for name in ("fps", "pixels_per_radius"):
            checks.positive(getattr(self, name), name)
        for name in ("pixel_noise", "angle_noise_deg", "occluded_factor", "drag", "gravity"):
            checks.positive(getattr(self, name), name, allow_zero=True)
        for name in ("frames_before", "frames_after"):
            checks.count(getattr(self, name), name, 8, maximum=MAX_FRAMES)

    @property
    def dt(self) -> float:
        """Frame period, s."""
        return 1.0 / float(self.fps)

    @property
    def position_noise(self) -> float:
        """Standard deviation of a tracked centre coordinate, radii."""
        return float(self.pixel_noise) / float(self.pixels_per_radius)

    @property
    def angle_noise(self) -> float:
        """Standard deviation of the rotation between two frames, rad."""
        return float(np.deg2rad(self.angle_noise_deg))

    def to_dict(self) -> dict:
        """JSON-safe description."""
        return {k: (float(v) if isinstance(v, float) else v) for k, v in asdict(self).items()}

    def film(
        self, landing: np.ndarray, liftoff: np.ndarray, contact_time: np.ndarray, rng: np.random.Generator
    ) -> Frames:
        """Film n bounces: frames of landings (n, 3) leaving as ``liftoff`` (n, 3) after ``contact_time`` (n,) s.

        Each lift-off needs ``ydot > 0`` (the ball leaves the surface). Random
        draws, in order: the touch-down phase within a frame (n,), then the
        noise of ``x``, ``y``, ``spin`` and ``lowest`` (each (n, N)).
        """
        p0 = np.asarray(landing, dtype=float)
        pf = np.asarray(liftoff, dtype=float)
        tc = np.asarray(contact_time, dtype=float)
        n = len(p0)
        if p0.shape != (n, 3) or pf.shape != (n, 3) or tc.shape != (n,):
            raise ParameterError(
                f"Camera.film needs (n, 3) landings and lift-offs and (n,) contact times; got {p0.shape}, "
                f"{pf.shape}, {tc.shape}"
            )
        if n and (not (p0[:, 1] < 0).all() or not (pf[:, 1] > 0).all() or not (tc > 0).all()):
            raise ParameterError("Camera.film needs landings with ydot < 0, lift-offs with ydot > 0 and t_c > 0")
        dt = self.dt
        fb, fa = int(self.frames_before), int(self.frames_after)
        offset = rng.uniform(0.0, 1.0, size=n)
        t0 = (fb - offset) * dt
        tf = t0 + tc
        # Frames fb .. first_after-1 are in contact (t_k <= t_F), as in simulate_tracked_bounce.
        n_contact = np.floor((tf - fb * dt) / dt + 1e-12).astype(np.int64) + 1
        first_after = fb + n_contact
        n_frames = int(first_after.max(initial=fb + 1)) + fa
        t = np.arange(n_frames) * dt
        x = np.empty((n, n_frames))
        y = np.empty((n, n_frames))

        # Flight before touch-down: RK4 backward from (0, 1) at t0, one frame at a time.
        state = np.column_stack([np.zeros(n), np.ones(n), p0[:, 0], p0[:, 1]])
        for m in range(fb):
            h = (offset - 1.0) * dt if m == 0 else np.full(n, -dt)
            state = self._rk4(state, h)
            x[:, fb - 1 - m] = state[:, 0]
            y[:, fb - 1 - m] = state[:, 1]

        # Flight after lift-off: forward from (x_F, 1) at t_F.
        x_f = tc * (p0[:, 0] + pf[:, 0]) / 2.0
        state = np.column_stack([x_f, np.ones(n), pf[:, 0], pf[:, 1]])
        rows = np.arange(n)
        for m in range(n_frames - int(first_after.min(initial=n_frames))):
            h = first_after * dt - tf if m == 0 else np.full(n, dt)
            state = self._rk4(state, h)
            col = first_after + m
            ok = col < n_frames
            x[rows[ok], col[ok]] = state[ok, 0]
            y[rows[ok], col[ok]] = state[ok, 1]

        # Contact: cubic Hermite between the touch-down and lift-off states.
        cols = np.arange(n_frames)[None, :]
        in_contact = (cols >= fb) & (cols < first_after[:, None])
        s = np.clip((t[None, :] - t0[:, None]) / tc[:, None], 0.0, 1.0)
        h10, h01, h11 = s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
        h00 = 2 * s**3 - 3 * s**2 + 1
        T = tc[:, None]
        xc = h10 * T * p0[:, :1] + h01 * x_f[:, None] + h11 * T * pf[:, :1]
        yc = h00 + h10 * T * p0[:, 1:2] + h01 + h11 * T * pf[:, 1:2]
        x = np.where(in_contact, xc, x)
        y = np.where(in_contact, yc, y)

        # Rotation angle since touch-down; spin linear in time during contact.
        def theta(tt: np.ndarray) -> np.ndarray:
            rel = tt[None, :] - t0[:, None]
            inside = np.clip(rel, 0.0, T)
            ang = p0[:, 2:3] * np.minimum(rel, 0.0) + p0[:, 2:3] * inside
            ang = ang + (pf[:, 2:3] - p0[:, 2:3]) * inside**2 / (2.0 * T)
            return ang + pf[:, 2:3] * np.clip(rel - T, 0.0, None)

        spin_true = (theta(t) - theta(t - dt)) / dt

        noise = np.where(in_contact, self.occluded_factor, 1.0)
        pos_sd = noise * self.position_noise
        spin_sd = noise * self.angle_noise / dt
        x_obs = x + pos_sd * rng.standard_normal((n, n_frames))
        y_obs = y + pos_sd * rng.standard_normal((n, n_frames))
        spin_obs = spin_true + spin_sd * rng.standard_normal((n, n_frames))
        surface = self.position_noise * rng.standard_normal((n, n_frames))
        lowest = np.where(in_contact, surface, y_obs - 1.0)
        return Frames(t=t, x=x_obs, y=y_obs, spin=spin_obs, lowest=lowest, in_contact=in_contact,
                      touchdown_time=t0, liftoff_time=tf)

    def _rk4(self, s: np.ndarray, h: np.ndarray) -> np.ndarray:
        """One classical Runge-Kutta step of size ``h`` (n,) for states (n, 4) = (x, y, xdot, ydot)."""
        hh = h[:, None]
        k1 = self._rhs(s)
        k2 = self._rhs(s + 0.5 * hh * k1)
        k3 = self._rhs(s + 0.5 * hh * k2)
        k4 = self._rhs(s + hh * k3)
        return s + hh / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)

    def _rhs(self, s: np.ndarray) -> np.ndarray:
        u, v = s[:, 2], s[:, 3]
        speed = np.hypot(u, v)
        return np.column_stack([u, v, -self.drag * speed * u, -self.gravity - self.drag * speed * v])
