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
:math:`u = v + \omega \times r_c = v + n \times \omega`, and its tangential part (the slip)
:math:`u_t = v_t + n \times \omega`. On flat ground, :math:`u_t = (\dot x + \omega, 0, 0)`:
the paper's :math:`v_P`.

Each law states its lift
------------------------
A 2-D law knows the plane of a ball's travel only; how it acts on a ball with sidespin is a
property of the law, which it states (generic code never names a law):

* **its own 3-D bounce** (:attr:`CompiledLaw.kernel_3d <bouncelab.laws.CompiledLaw.kernel_3d>`):
  the rigid family, for which the physics is known in 3-D (below);
* **the plane of travel** (:attr:`~bouncelab.BounceModel.lift_plane` ``= "travel"``, the
  default): the 2-D law acts in the vertical plane of the ball's velocity along the ground;
* **the plane of the slip** (``lift_plane = "slip"``): the 2-D law acts in the plane of the
  normal and the contact point's slip; exact for a law whose tangential contact is isotropic.

The frame of the plane of travel: :math:`h` is the unit vector of the velocity along the
ground :math:`v_t = v - (v\cdot n)\,n` (when there is none, a landing along the normal, the x
axis projected on the plane, or the y axis if the normal is near x), :math:`b = n \times h`,
so :math:`(h, b, n)` is right-handed. The landing in it is

.. math::

    (x, y, w, v_b, \omega_h, \omega_n) = (v\cdot h,\; v\cdot n,\; -\omega\cdot b,\;
    v\cdot b,\; \omega\cdot h,\; \omega\cdot n),

where :math:`(x, y, w)` is the paper's 2-D landing (:math:`w = \omega\cdot(h\times n)`;
:math:`x = |v_t| \ge 0`: in its frame every ball travels in +x, so a law that is not
mirror-symmetric, such as PiecewiseAffine, sees a ball moving in -x of the lab as the mirror
image of one moving in +x, as Penner's laws do by construction) and :math:`v_b = 0` up to
rounding. A lift-off :math:`(x_F, y_F, w_F, v_{bF}, \omega_{hF}, \omega_{nF})` goes back as

.. math::

    v_F = x_F\,h + y_F\,n + v_{bF}\,b,\qquad
    \omega_F = \omega_{hF}\,h - w_F\,b + \rho\,\omega_{nF}\,n ,

the spin about the normal multiplied by the surface's ``pivot_retention`` :math:`\rho`
(default 1). An in-plane landing (:math:`v_b = \omega_h = \omega_n = 0`) gives the 2-D law's
lift-off bit for bit, with every lift.

The rigid bounce in 3-D
-----------------------
A ball (mass m, :math:`I = \tfrac25 m R^2`) receives at the contact point :math:`-R\,n'` of a
plane of normal :math:`n'` an impulse :math:`J = J_n n' + J_t` (per unit mass, :math:`J_t`
along the plane). Then :math:`\Delta v = J` and :math:`\Delta\omega = -\tfrac52\,n' \times J_t`
(scaled), so the slip changes by

.. math::

    \Delta u_t = J_t + n' \times \Delta\omega = J_t - \tfrac52\, n' \times (n' \times J_t)
              = \tfrac72 J_t ,

*parallel to the impulse*. Coulomb friction opposes the slip; the slip then only shrinks
along its own line and keeps its direction until it stops (and a rigid, non-restituting
contact holds it at zero). So the impulse is ``-slip / 3.5`` if that is within the
friction cone :math:`|J_t| \le \mu (1 + r)|v\cdot n'|`, and otherwise that cone's edge along
``-slip``; :math:`J_n = -(1 + r)\,v\cdot n'`. In the plane's frame :math:`(t', b, n')` the
slip is :math:`(v_{t'} + w,\; v_b + \omega_{t'})` (:func:`bouncelab.laws._kernels.impulse_3d`).
This is **Rigid** (:math:`n' = n`); **TangentialRestitution** takes :math:`(1 + e_t)` times the
stopping impulse (Walton: the gripping ball's slip reversed), along the slip. When the slip
lies in the plane of travel it is the 2-D rigid bounce of eq. (rigid_bounce), bit for bit.

**PennerFixed** and **PennerVarying** are what they describe: this rigid bounce on the ground
tilted by the law's angle :math:`\beta` *towards the incoming ball*, in the plane of travel:
:math:`t' = \cos\beta\,h + \sin\beta\,n`, :math:`n' = \cos\beta\,n - \sin\beta\,h` (:math:`b`
unchanged; :math:`\beta` from the law's 2-D landing :math:`(x, y)`, faded with :math:`x` when
``fade_xdot`` is set). Sidespin about the normal has a component along :math:`t'` on the
tilted plane and moves its contact point across the plane of travel; the friction cone
bounds the sideways impulse, as on flat ground.

Energy: :math:`|v|^2 + \tfrac25|\omega|^2` never grows in a rigid bounce with
:math:`r \le 1` (and :math:`e_t \le 1`), on any plane, and :math:`\rho \le 1` only removes spin.

Continuity: the rigid bounce is continuous in the landing (the cone's edge meets the
stopping impulse continuously). Penner's tilt direction :math:`h` depends on the velocity
only, so its 3-D lift is continuous **in the spin everywhere**, and in the velocity wherever
the ball moves along the ground; at :math:`v_t = 0` the direction of the tilt is undefined
and the law jumps there, as its 2-D law does at :math:`\dot x_0 = 0`, unless the tilt fades
(``fade_xdot``: the presets' laws do). Earlier releases took the frame along the slip, so
near zero slip Penner's tilt acted in whatever direction a rounding error pointed.

The plane of travel (the default)
---------------------------------
The 2-D law acts on :math:`(x, y, w)`; :math:`v_b`, :math:`\omega_h` and :math:`\omega_n` are
kept. What the law would do across its plane is not known from 2-D measurements: a slip
across the plane of travel (the spin about the direction of travel moves the contact point
sideways at :math:`v_b + \omega_h`) is left alone. The lift is continuous **in the spin
wherever the 2-D law is continuous in** :math:`\omega` (the frame depends on the velocity
only and :math:`w` is linear in the spin), and in the velocity wherever :math:`v_t \ne 0` and
the 2-D law is continuous; at :math:`v_t = 0` the plane is the fixed fall-back one, so a law
with spin jumps there as the direction of travel turns. The 3-D bounce gains energy exactly
when the 2-D law does (the kept part of :math:`|v|^2 + \tfrac25|\omega|^2` is unchanged, and
:math:`\rho \le 1`). The laws that use it:

* **PiecewiseAffine**: two affine maps of :math:`(\dot x, \dot y, \omega)` split by a plane.
  Continuous in the spin and the velocity within each side; it jumps across the split as
  the 2-D law does (the published maps do not meet there) and, for a ball with spin, at
  :math:`v_t = 0`.
* **TurfContact** and **CraterContact**: their ploughing, crater wall and bristle act against
  the direction of travel, which this plane is; continuous wherever their 2-D laws are.
* your own laws, unless they state another lift.

The plane of the slip
---------------------
:math:`t` is the unit vector of the slip :math:`u_t`; when the contact point does not slip,
of :math:`v_t`; when both vanish, the fall-back tangent; its sign makes the ball travel along
:math:`+t` (:math:`v\cdot t \ge 0`) and :math:`b = n\times t`. The 2-D law acts on
:math:`(v\cdot t, v\cdot n, -\omega\cdot b)` and :math:`v\cdot b`, :math:`\omega\cdot t`,
:math:`\omega\cdot n` are kept: :math:`v_F = x_F t + y_F n + (v\cdot b)\,b`,
:math:`\omega_F = (\omega\cdot t)\,t - w_F b + \rho\,(\omega\cdot n)\,n`. For a law whose
tangential force stays along the slip this is the exact 3-D contact (the argument above):
**CompliantImpact**, an isotropic tangential spring in series with a Coulomb slider, loaded
from rest along the slip, keeps its displacement, force and the slip on that line. Its 3-D
bounce is then continuous wherever the 2-D law is (near zero slip the frame turns, the
contact it describes does not) and gains no energy when the 2-D law gains none. For a law
that is not isotropic this frame would turn its action with the slip's direction: near zero
slip, with rounding errors; hence not the default.

Flags: ``return_flags=True`` (and :func:`~bouncelab.ground.run`'s totals) mark a lift-off
into the ground (:math:`v_F\cdot n \le 0`) and one gaining energy
(:math:`|v_F|^2 + \tfrac25|\omega_F|^2` above the landing's by more than
:data:`~bouncelab.laws.nonphysical.ENERGY_RTOL`), of the 3-D bounce.

Checks (``tests/test_ground_bounce.py``): an in-plane landing gives the 2-D law's lift-off
bit for bit (every law; in -x too for the mirror-symmetric ones); every law is continuous in
the spin near zero slip, travelling along an axis and at an angle, wherever its 2-D law is;
Rigid, TangentialRestitution and Penner's laws are a direct 3-D impulse computation on their
plane; no energy gain for the rigid family with :math:`r \le 1` and CompliantImpact; mirror
images and rotations about the normal give mirrored and rotated lift-offs; a landing on a
slope equals the flat one in the slope's frame.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core.errors import DataError, LawDefinitionError, NonphysicalLiftoffWarning
from bouncelab.ground._inputs import (
    Units,
    as_vectors,
    broadcast_rows,
    check_law,
    retention,
    unit_normals,
    within_limit,
)
from bouncelab.ground.surface import Surface

if TYPE_CHECKING:
    from bouncelab.laws import BounceModel

__all__ = ["LIFT_PLANES", "bounce", "compiled_lift", "flags_3d", "from_plane", "lift_plane", "to_plane"]

#: The planes a law may name as its ``lift_plane``.
LIFT_PLANES = ("travel", "slip")


def _kernels():
    from bouncelab.ground import _kernels

    return _kernels


def _run_rows(fn: Any, n: int, *args: Any) -> None:
    from bouncelab.core._parallel import run_rows

    run_rows(fn, n, *args)


def lift_plane(law: BounceModel) -> str:
    """The law's ``lift_plane``, checked (a LawDefinitionError naming the law otherwise)."""
    from bouncelab.laws import law_name

    plane = law.lift_plane
    if plane not in LIFT_PLANES:
        raise LawDefinitionError(f"{law_name(law)}.lift_plane is {plane!r}; it must be one of {list(LIFT_PLANES)} "
                                 "(the plane in which bouncelab.ground applies the 2-D law)", law=law_name(law),
                                 method="lift_plane")
    return plane


def compiled_lift(law: BounceModel) -> tuple[Any, tuple] | None:
    """The law's compiled 3-D lift and its arguments, or None for a law without a compiled kernel.

    The lift is ``kernel_3d`` if the law has one, else its 2-D ``kernel`` in its ``lift_plane``
    (:func:`bouncelab.ground._kernels.lift_of`).
    """
    from bouncelab.laws import CompiledLaw, law_name

    if not isinstance(law, CompiledLaw) or law.kernel is None:
        return None
    k = _kernels()
    args = law._args(law._fitted_values())
    own = law.kernel_3d
    if own is not None:
        if not hasattr(own, "py_func"):
            raise LawDefinitionError(f"{law_name(law)}.kernel_3d must be a numba.njit function kernel_3d(x, y, w, vb, "
                                     f"wh, wn, *kernel arguments) -> (xF, yF, wF, vbF, whF, wnF); got "
                                     f"{type(own).__name__}", law=law_name(law), method="kernel_3d")
        return k.lift_of("own", own), args
    return k.lift_of(lift_plane(law), law.kernel), args


def to_plane(velocity: np.ndarray, spin: np.ndarray, normal: np.ndarray,
             plane: str = "travel") -> tuple[np.ndarray, np.ndarray]:
    """2-D landings ``[v.t, v.n, -omega.b]`` (n, 3) and the frames (n, 9) of scaled 3-D states in ``plane``.

    ``plane`` is ``"travel"`` or ``"slip"`` (see the module). The inputs are C-contiguous float
    (n, 3) arrays in scaled units, ``normal`` unit vectors. The frame rows hold ``t``, ``b``,
    ``v.b``, ``omega.t``, ``omega.n``.
    """
    n = len(velocity)
    p2 = np.empty((n, 3))
    frames = np.empty((n, 9))
    _run_rows(_kernels().to_plane_rows, n, velocity, spin, normal, plane == "slip", p2, frames)
    return p2, frames


def from_plane(liftoff2d: np.ndarray, frames: np.ndarray, normal: np.ndarray,
               pivot_retention: float) -> tuple[np.ndarray, np.ndarray]:
    """3-D lift-off velocity and spin (n, 3) from 2-D lift-offs and the frames of :func:`to_plane`."""
    n = len(liftoff2d)
    vf = np.empty((n, 3))
    wf = np.empty((n, 3))
    _run_rows(_kernels().from_plane_rows, n, np.ascontiguousarray(liftoff2d, dtype=float), frames, normal,
              float(pivot_retention), vf, wf)
    return vf, wf


def flags_3d(v: np.ndarray, w: np.ndarray, vf: np.ndarray, wf: np.ndarray,
             normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(into_ground, energy_gain)`` of 3-D bounces, as the compiled loops compute them (same arithmetic)."""
    from bouncelab.laws.nonphysical import ENERGY_RTOL

    k = _kernels()

    def energy(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return a[:, 0] * a[:, 0] + a[:, 1] * a[:, 1] + a[:, 2] * a[:, 2] + k.INERTIA * (
            b[:, 0] * b[:, 0] + b[:, 1] * b[:, 1] + b[:, 2] * b[:, 2])

    into = vf[:, 0] * normal[:, 0] + vf[:, 1] * normal[:, 1] + vf[:, 2] * normal[:, 2] <= 0.0
    return into, energy(vf, wf) > energy(v, w) * (1.0 + ENERGY_RTOL)


def bounce(law: BounceModel | Surface, velocity: Any, spin: Any, normal: Any = (0.0, 0.0, 1.0),
           units: Mapping[str, str] | str | None = None, *, radius_m: float | None = None,
           pivot_retention: float | None = None, return_flags: bool = False) -> Any:
    """Lift-off velocity and spin of 3-D landings, from any 2-D bounce law.

    The law acts as it states (see the module): the rigid family as the exact 3-D rigid
    bounce (Penner's laws on their tilted plane), other laws in the plane of travel or of
    the slip.

    Parameters
    ----------
    law
        A bounce law (any :class:`~bouncelab.BounceModel`), or a
        :class:`~bouncelab.ground.Surface` (its law and its ``pivot_retention``).
    velocity, spin
        Landing velocities and spin vectors, (3,) or (n, 3) (one row is repeated for
        every landing), right-handed, z up on flat ground: backspin for travel in +x is a
        negative y spin. Each landing must move into the ground (``v . n < 0``); no
        component beyond :data:`~bouncelab.core.validation.STATE_LIMIT` in scaled units
        (radii/s, rad/s).
    normal
        The ground's normal, (3,) or (n, 3), any non-zero length (normalised here).
    units
        None (scaled: radii/s and rad/s) or ``{"velocity": "m/s", "spin": "rpm"}`` (any units
        of :mod:`bouncelab.core.units`) for the landings and the lift-offs.
    radius_m
        Ball radius in metres for physical units (default 21.35 mm).
    pivot_retention
        Fraction of the lift-off's spin about the normal kept, in [0, 1] (default: the
        surface's, or 1 for a bare law).
    return_flags
        Also return a :class:`~bouncelab.laws.nonphysical.LiftoffFlags` of the 3-D bounces
        (into the ground, ``vF . n <= 0``; energy gain).

    Returns
    -------
    (velocity, spin)
        Lift-off velocities and spins, (n, 3) (or (3,) when every input was a single vector),
        in the units of the landings (and the flags, (n,) each, with ``return_flags=True``).

    Raises
    ------
    DataError
        Wrong shapes, non-finite or absurdly large values (row and component named), a zero
        normal, a landing that does not move into the ground (row named), unknown units.
    ParameterError
        Not a law, or ``pivot_retention`` outside [0, 1].

    Warns
    -----
    NonphysicalLiftoffWarning
        A law with the paper's published values sends landings into the ground or gives them energy.

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
    from bouncelab.laws import nonphysical

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
    v = within_limit(u.velocity_in(v), "velocity", v, u.velocity_unit)
    w = within_limit(u.spin_in(w), "spin", w, u.spin_unit)
    v = np.ascontiguousarray(np.broadcast_to(v, (n, 3)))
    w = np.ascontiguousarray(np.broadcast_to(w, (n, 3)))
    nrm = np.ascontiguousarray(np.broadcast_to(nrm, (n, 3)))
    vn = np.einsum("ij,ij->i", v, nrm)
    if not (vn < 0).all():
        row = int(np.flatnonzero(~(vn < 0))[0])
        raise DataError(f"velocity row {row + 1} does not move into the ground (v . n = "
                        f"{u.velocity_out(vn[row]):.6g} >= 0 in {u.velocity_unit}): a bounce needs a landing; the "
                        f"normal points out of the ground", column="velocity", row=row + 1)
    compiled = compiled_lift(law)
    with warnings.catch_warnings(record=True) as caught:  # the law's warnings, re-issued at the caller's line
        warnings.simplefilter("always")
        if compiled is not None:
            lift, args = compiled
            vf, wf = np.empty((n, 3)), np.empty((n, 3))
            codes = np.empty((n, 2), dtype=np.int8)
            _run_rows(_kernels().bounce_loop(lift), n, v, w, nrm, keep, args, vf, wf, codes)
            into, gain = codes[:, 0].astype(bool), codes[:, 1].astype(bool)
        else:
            p2, frames = to_plane(v, w, nrm, lift_plane(law))
            with warnings.catch_warnings():  # its flags are those of the 3-D bounce, below
                warnings.simplefilter("ignore", NonphysicalLiftoffWarning)
                out = law.predict(p2, plausible=None)
            vf, wf = from_plane(out, frames, nrm, keep)
            into, gain = flags_3d(v, w, vf, wf, nrm)
        nonphysical.warn_if_published_nonphysical(law, v, vf, (into, gain))
    for c in caught:
        warnings.warn(c.message, c.category, stacklevel=2)
    vf, wf = u.velocity_out(vf), u.spin_out(wf)
    if lead_v == lead_w == lead_n == ():
        vf, wf = vf[0], wf[0]
    if return_flags:
        return vf, wf, nonphysical.LiftoffFlags(into_ground=into, energy_gain=gain)
    return vf, wf
