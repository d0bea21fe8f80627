"""Beyond the paper: Walton's three-parameter hard-sphere law (restitution, friction, tangential restitution)."""

from __future__ import annotations

from bouncelab.laws.compiled import CompiledLaw
from bouncelab.laws.parameters import Parameter
from bouncelab.laws.rigid import MU, R

__all__ = ["TangentialRestitution"]


class TangentialRestitution(CompiledLaw):
    r"""Walton's hard-sphere law: the rigid bounce whose gripping balls leave with reversed contact-point velocity.

    The paper finds that balls which enter rolling do not lift off rolling but
    slipping the other way (its Fig. 7), which no law of the paper can do. This
    is Walton's three-parameter model of an instantaneous collision of hard
    spheres (O. R. Walton, *Numerical simulation of inclined chute flows of
    monodisperse, inelastic, frictional spheres*, Mech. Mater. 16 (1993)
    239-247; measured for small spheres by S. F. Foerster, M. Y. Louge,
    H. Chang and K. Allia, Phys. Fluids 6 (1994) 1108-1115): normal restitution
    :math:`r`, Coulomb friction :math:`\mu` and a tangential coefficient of
    restitution :math:`e_t` (Walton's :math:`\beta_0`) of the contact point. A
    ball that grips leaves with :math:`v_{P,F} = -e_t v_{P,0}`. With
    :math:`k = \mu (1 + r)` and the tangential impulse per unit mass
    :math:`J` (which changes :math:`v_P` by :math:`\tfrac72 J`):

    .. math::

        \dot y_F = -r \dot y_0,\quad
        J = \operatorname{clip}\!\Big(-\frac{2 (1 + e_t)}{7} v_P,\; -k|\dot y_0|,\; k|\dot y_0|\Big),\quad
        \dot x_F = \dot x_0 + J,\; \omega_F = \omega_0 + \tfrac52 J.

    Regimes follow the paper's slip/roll rule applied to the law's own lift-off:
    the ball slips throughout (``slip_forward`` / ``slip_backward``) when friction
    cannot stop the contact point, :math:`|v_P| > \tfrac72 k |\dot y_0|` (then
    :math:`v_{P,F}` keeps the sign of :math:`v_{P,0}`); otherwise it grips
    (``roll``) and leaves with :math:`v_{P,F}` between :math:`-e_t v_{P,0}` and 0
    (reversed when :math:`e_t > 0`; the friction cap binds already from
    :math:`|v_P| > \tfrac{7 k |\dot y_0|}{2 (1 + e_t)}`).

    :math:`e_t = 0` is exactly :class:`~bouncelab.Rigid`. The law is continuous,
    mirror symmetric and, for ``r <= 1`` and ``e_t <= 1``, never gains energy.

    Parameters
    ----------
    r : float, optional
        Normal restitution, dimensionless, in [0, 1].
    mu : float, optional
        Friction coefficient, dimensionless, >= 0 (search bounds [0, 1.5]).
    e_t : float, optional
        Tangential restitution of the contact point, dimensionless, in [0, 1].

    Examples
    --------
    Friction stops the contact point and the ball leaves with it reversed (v_P,F = -280):

    >>> law = TangentialRestitution(r=0.5, mu=0.4, e_t=0.5)
    >>> out = law.predict([[1000.0, -800.0, 400.0]])
    >>> float((out[0, 0] + out[0, 2]).round(6)), str(law.regime([1000.0, -800.0, 400.0]))
    (-280.0, 'roll')
    """

    r = R
    mu = MU
    e_t = Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="1", doc="tangential restitution of the contact point")
    regimes = ("slip_forward", "roll", "slip_backward")

    @property
    def kernel(self):  # type: ignore[override]
        from bouncelab.laws._kernels import tangential_kernel

        return tangential_kernel

    @property
    def kernel_3d(self):  # type: ignore[override]  # the exact 3-D bounce, along the slip (bouncelab.ground)
        from bouncelab.laws._kernels import tangential_kernel_3d

        return tangential_kernel_3d
