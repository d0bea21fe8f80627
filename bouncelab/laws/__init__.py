"""Bounce laws: landing state in, lift-off state out.

==============================  =====================================================
:class:`Rigid`                  restitution ``r`` and Coulomb friction ``mu`` (eq. rigid_bounce)
:class:`PennerFixed`            rigid bounce on a surface tilted by a fixed ``beta_deg``
:class:`PennerVarying`          Penner's tilt ``beta = k_p s phi`` (eq. penner_angle)
:class:`PiecewiseAffine`        two affine maps split by a plane (eqs. disjointA/B)
:class:`TangentialRestitution`  Walton's hard-sphere law: gripping balls reverse v_P (beyond the paper)
:class:`CompliantImpact`        spring-dashpot with a tangential spring and Coulomb slider (Stronge)
:class:`TurfContact`            elasto-plastic, rate-dependent turf with ploughing and a bristle, integrated
:class:`CraterContact`          crater-wall tilt, velocity-weakening friction, ploughing and bristle recoil
==============================  =====================================================

Writing a law: subclass :class:`BounceModel` (NumPy maths in ``_predict``) or
:class:`CompiledLaw` (a numba scalar ``kernel``); declare each parameter as a class attribute
(:class:`Parameter`) and options as :class:`Option` s;
register extra fitting procedures with :func:`fit_method`. See docs/laws.md.
"""

from bouncelab.laws.base import BounceModel
from bouncelab.laws.compiled import CompiledLaw, num_threads, set_num_threads
from bouncelab.laws.compliant import CompliantImpact
from bouncelab.laws.crater import CraterContact
from bouncelab.laws.files import law_from_dict, load_law
from bouncelab.laws.parameters import Option, Parameter, Parameters
from bouncelab.laws.penner import K_P_MAX, PennerFixed, PennerVarying
from bouncelab.laws.piecewise import PiecewiseAffine
from bouncelab.laws.protocol import FitOutcome, FitProblem, fit_method
from bouncelab.laws.provenance import Provenance
from bouncelab.laws.registry import law_class, law_name, registered_laws
from bouncelab.laws.rigid import Rigid
from bouncelab.laws.tangential_restitution import TangentialRestitution
from bouncelab.laws.turf import TurfContact
from bouncelab.laws.varying import predict_per_bounce

__all__ = [
    "K_P_MAX",
    "BounceModel",
    "CompiledLaw",
    "CompliantImpact",
    "CraterContact",
    "FitOutcome",
    "FitProblem",
    "Option",
    "Parameter",
    "Parameters",
    "PennerFixed",
    "PennerVarying",
    "PiecewiseAffine",
    "Provenance",
    "Rigid",
    "TangentialRestitution",
    "TurfContact",
    "fit_method",
    "law_class",
    "law_from_dict",
    "law_name",
    "load_law",
    "num_threads",
    "predict_per_bounce",
    "registered_laws",
    "set_num_threads",
]
