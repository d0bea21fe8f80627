r"""The 3-D bounce: any 2-D bounce law lifted to a ball with sidespin, on any plane.

Conventions
-----------
Right-handed axes, z up on flat ground; velocities ``v`` and spins ``omega`` (the
angular-velocity *vector*) are (n, 3) arrays in scaled units (radii/s, rad/s) unless
``units=`` says otherwise. Backspin for travel in +x is a **negative** y component: the
in-plane landing :math:`(\dot x, 0, \dot z)` with spin :math:`(0, -\omega, 0)` is the 2-D
landing :math:`(\dot x, \dot z, \omega)` of the paper (its Fig. 2, y up, :math:`\omega > 0`
backspin). ``normal`` is the ground's unit normal :math:`n` (a slope); the contact point is
:math:`r_c = -R\,n`, so (per unit radius, in scaled units) its velocity is

.. math::

    u = v + \omega \times r_c = v + n \times \omega,

and its tangential part :math:`u_t = v_t + n \times \omega` (:math:`n \times \omega` is
tangential already). On flat ground, :math:`u_t = (\dot x + \omega, 0, 0)`: the paper's
:math:`v_P`.

The contact frame
-----------------
:math:`t` is the unit vector of the slip :math:`u_t`; when the contact point does not slip,
of the tangential velocity :math:`v_t`; when both vanish, the x axis projected on the plane
(the y axis if the normal is near x). Its sign is chosen so that the ball travels along
:math:`+t` (:math:`v \cdot t \ge 0`), as the paper's balls travel in +x; :math:`b = n \times t`,
so :math:`(t, b, n)` is right-handed. The 2-D law acts in the :math:`(t, n)` plane on

.. math::

    (\dot x, \dot y, \omega)_{2D} = (v \cdot t,\; v \cdot n,\; \omega \cdot (t \times n))
    = (v \cdot t,\; v \cdot n,\; -\omega \cdot b),

whose :math:`v_P = v\cdot t - \omega\cdot b = u \cdot t` is the whole slip. Its lift-off
:math:`(x_F, y_F, w_F)` goes back as

.. math::

    v_F = x_F\,t + y_F\,n + (v \cdot b)\,b,\qquad
    \omega_F = (\omega \cdot t)\,t - w_F\,b + \rho\,(\omega \cdot n)\,n .

The velocity along :math:`b` and the spin about :math:`t` are kept, and the spin about the
normal is multiplied by the surface's ``pivot_retention`` :math:`\rho` (default 1).

Why this is the exact 3-D rigid bounce
--------------------------------------
A ball (mass m, :math:`I = \tfrac25 m R^2`) receives at :math:`r_c` an impulse
:math:`J = J_n n + J_t` (per unit mass, :math:`J_t` tangential). Then
:math:`\Delta v = J` and :math:`\Delta\omega = (r_c \times J)/(\tfrac25 R^2) = -\tfrac52\,n \times J_t`
(scaled), so the slip changes by

.. math::

    \Delta u_t = J_t + n \times \Delta\omega = J_t - \tfrac52\, n \times (n \times J_t)
              = \tfrac72 J_t ,

*parallel to the impulse*. Coulomb friction opposes the slip; the slip then only shrinks
along its own line and keeps its direction until it stops (and a rigid, non-restituting
contact holds it at zero). So the whole tangential impulse lies along :math:`t`:
:math:`\Delta v` has no :math:`b` component, :math:`\Delta\omega = -\tfrac52 J_t\, n \times t`
lies along :math:`b` (spin about :math:`t` and :math:`n` unchanged), and the motion in the
:math:`(t, n)` plane is exactly the 2-D rigid bounce: :math:`\Delta\omega_{2D} = -\Delta\omega
\cdot b = \tfrac52 J_t`, as in eq. (rigid_bounce). The components left alone satisfy
:math:`u \cdot b = v \cdot b + \omega \cdot t = 0` (no slip across the plane) before and after.
Energy: :math:`|v|^2 + \tfrac25|\omega|^2` splits into the 2-D law's part
:math:`\dot x^2 + \dot y^2 + \tfrac25\omega_{2D}^2` and the kept :math:`(v\cdot b)^2 +
\tfrac25((\omega\cdot t)^2 + (\omega\cdot n)^2)`; so the 3-D bounce gains no energy when the
2-D law gains none (and :math:`\rho \le 1`). ``tests/test_ground_bounce.py`` compares with
a direct 3-D impulse computation.

The same holds for :class:`~bouncelab.CompliantImpact` (an isotropic tangential spring in
series with a Coulomb slider: loaded from rest along the slip, its displacement, force and
the slip stay on that line, so the 3-D contact is the 2-D one along :math:`t`) and for
:class:`~bouncelab.TangentialRestitution` (its impulse is along the slip by construction).

Other laws
----------
For the other laws (:class:`~bouncelab.PennerFixed`, :class:`~bouncelab.PennerVarying`,
:class:`~bouncelab.PiecewiseAffine`, :class:`~bouncelab.TurfContact`,
:class:`~bouncelab.CraterContact` and user laws) the lift is a *definition*: the in-plane law
acts in the plane of the normal and the slip, exactly as above; what they do to the
velocity across that plane and the spin about :math:`t` is not known from 2-D measurements,
and it is kept. Penner's tilt then opposes the travel along :math:`t`. Choosing the sign of
:math:`t` by the travel keeps laws fitted to balls moving in +x inside their data; a law that
is not symmetric under :math:`(\dot x, \omega) \to (-\dot x, -\omega)` (PiecewiseAffine)
treats a ball moving in -x as the mirror image of one moving in +x, as Penner's laws do.

Checks (``tests/test_ground_bounce.py``): an in-plane landing moving in +x gives the 2-D
law's lift-off bit for bit (for the mirror-symmetric laws also in -x); rotating a landing
about the normal rotates its lift-off; a landing on a slope equals the flat one in the
slope's frame; Rigid (r <= 1) and CompliantImpact gain no energy.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core.errors import DataError
from bouncelab.ground._inputs import Units, as_vectors, broadcast_rows, check_law, retention, unit_normals
from bouncelab.ground.surface import Surface

if TYPE_CHECKING:
    from bouncelab.laws import BounceModel

__all__ = ["bounce", "from_plane", "to_plane"]


def _kernels():
    from bouncelab.ground import _kernels

    return _kernels


def _run_rows(fn: Any, n: int, *args: Any) -> None:
    from bouncelab.core._parallel import run_rows

    run_rows(fn, n, *args)


def to_plane(velocity: np.ndarray, spin: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """2-D landings ``[v.t, v.n, -omega.b]`` (n, 3) and the contact frames (n, 9) of scaled 3-D states.

    The inputs are C-contiguous float (n, 3) arrays in scaled units, ``normal`` unit
    vectors. The frame rows hold ``t``, ``b``, ``v.b``, ``omega.t``, ``omega.n`` (see the module).
    """
    n = len(velocity)
    p2 = np.empty((n, 3))
    frames = np.empty((n, 9))
    _run_rows(_kernels().to_plane_rows, n, velocity, spin, normal, p2, frames)
    return p2, frames


def from_plane(liftoff2d: np.ndarray, frames: np.ndarray, normal: np.ndarray,
               pivot_retention: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """3-D lift-off velocity and spin (n, 3) from 2-D lift-offs and the frames of :func:`to_plane`."""
    n = len(liftoff2d)
    vf = np.empty((n, 3))
    wf = np.empty((n, 3))
    _run_rows(_kernels().from_plane_rows, n, np.ascontiguousarray(liftoff2d, dtype=float), frames, normal,
              pivot_retention, vf, wf)
    return vf, wf


def bounce(law: BounceModel | Surface, velocity: Any, spin: Any, normal: Any = (0.0, 0.0, 1.0),
           units: Mapping[str, str] | str | None = None, *, radius_m: float | None = None,
           pivot_retention: float | None = None, return_flags: bool = False) -> Any:
    """Lift-off velocity and spin of 3-D landings, from any 2-D bounce law.

    Parameters
    ----------
    law
        A bounce law (any :class:`~bouncelab.BounceModel`), or a
        :class:`~bouncelab.ground.Surface` (its law and its ``pivot_retention``).
    velocity, spin
        Landing velocities and spin vectors, (3,) or (n, 3) (one row is repeated for
        every landing), right-handed, z up on flat ground: backspin for travel in +x is a
        negative y spin. Each landing must move into the ground (``v . n < 0``).
    normal
        The ground's normal, (3,) or (n, 3), any non-zero length (normalised here).
    units
        None (scaled: radii/s and rad/s) or ``{"velocity": "m/s", "spin": "rpm"}`` (any units
        of :mod:`bouncelab.core.units`) for the landings and the lift-offs.
    radius_m
        Ball radius in metres for physical units (default 21.35 mm).
    pivot_retention
        Fraction of the spin about the normal kept through the bounce, in [0, 1] (default:
        the surface's, or 1 for a bare law).
    return_flags
        Also return the law's :class:`~bouncelab.laws.nonphysical.LiftoffFlags` (into the
        ground, energy gain) of the in-plane bounces.

    Returns
    -------
    (velocity, spin)
        Lift-off velocities and spins, (n, 3) (or (3,) when every input was a single vector),
        in the units of the landings (and the flags with ``return_flags=True``).

    Raises
    ------
    DataError
        Wrong shapes, non-finite values, a zero normal, a landing that does not move into the
        ground (row named), unknown units.
    ParameterError
        Not a law, or ``pivot_retention`` outside [0, 1].

    Examples
    --------
    An in-plane landing is the 2-D law's landing (spin (0, -omega, 0) is backspin in +x):

    >>> import bouncelab as bl
    >>> from bouncelab.ground import bounce
    >>> law = bl.Rigid(r=0.5, mu=0.4)
    >>> v, w = bounce(law, [1000.0, 0.0, -800.0], [0.0, -300.0, 0.0])
    >>> v.round(3), w.round(3)
    (array([628.571,   0.   , 400.   ]), array([  0.   , 628.571,   0.   ]))
    >>> law.predict([[1000.0, -800.0, 300.0]]).round(3)
    array([[ 628.571,  400.   , -628.571]])
    """
    keep = 1.0
    if isinstance(law, Surface):
        keep = law.pivot_retention
        law = law.law
    law = check_law(law)
    if pivot_retention is not None:
        keep = retention(pivot_retention)
    u = Units(units, radius_m)
    v, lead_v = as_vectors(velocity, "velocity")
    w, lead_w = as_vectors(spin, "spin")
    nrm, lead_n = unit_normals(normal, upward=False)
    n = broadcast_rows([("velocity", v), ("spin", w), ("normal", nrm)])
    v = np.ascontiguousarray(np.broadcast_to(u.velocity_in(v), (n, 3)))
    w = np.ascontiguousarray(np.broadcast_to(u.spin_in(w), (n, 3)))
    nrm = np.ascontiguousarray(np.broadcast_to(nrm, (n, 3)))
    vn = np.einsum("ij,ij->i", v, nrm)
    if not (vn < 0).all():
        row = int(np.flatnonzero(~(vn < 0))[0])
        raise DataError(f"velocity row {row + 1} does not move into the ground (v . n = {vn[row]:.6g} >= 0 in "
                        f"{u.velocity_unit}): a bounce needs a landing; the normal points out of the ground",
                        column="velocity", row=row + 1)
    p2, frames = to_plane(v, w, nrm)
    with warnings.catch_warnings(record=True) as caught:  # the law's warnings, re-issued at the caller's line
        warnings.simplefilter("always")
        out = law.predict(p2, plausible=None, return_flags=return_flags)
    for c in caught:
        warnings.warn(c.message, c.category, stacklevel=2)
    if return_flags:
        out, flags = out
    vf, wf = from_plane(out, frames, nrm, np.full(n, keep))
    vf, wf = u.velocity_out(vf), u.spin_out(wf)
    if lead_v == lead_w == lead_n == ():
        vf, wf = vf[0], wf[0]
    return (vf, wf, flags) if return_flags else (vf, wf)
