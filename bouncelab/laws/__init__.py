"""Bounce laws: landing state in, lift-off state out.

=====================  =====================================================
:class:`Rigid`          restitution ``r`` and Coulomb friction ``mu`` (eq. rigid_bounce)
:class:`PennerFixed`    rigid bounce on a surface tilted by a fixed ``beta_deg``
:class:`PennerVarying`  Penner's tilt ``beta = k_p s phi`` (eq. penner_angle)
:class:`PiecewiseAffine` two affine maps split by a plane (eqs. disjointA/B)
:class:`TangentialRestitution` rigid bounce whose gripping balls reverse v_P (beyond the paper)
=====================  =====================================================
"""

from bouncelab.laws.base import BounceModel, Parameter, law_from_dict, load_law, registered_laws
from bouncelab.laws.penner import K_P_MAX, PennerFixed, PennerVarying
from bouncelab.laws.piecewise import PiecewiseAffine
from bouncelab.laws.rigid import Rigid
from bouncelab.laws.tangential import TangentialRestitution

__all__ = [
    "K_P_MAX",
    "BounceModel",
    "Parameter",
    "PennerFixed",
    "PennerVarying",
    "PiecewiseAffine",
    "Rigid",
    "TangentialRestitution",
    "law_from_dict",
    "load_law",
    "registered_laws",
]
