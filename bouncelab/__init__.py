"""bouncelab: golf-ball bounce laws as first-class objects.

Fit bounce laws to measured bounces, compare them and use them, following
Biber, Jones, Champneys, Green & Szalai, *Measurements and linearized models
for golf ball bounce*. All states are ``[xdot, ydot, omega]`` in the paper's
scaled units (radii/s and rad/s, y up, omega > 0 backspin); see
:mod:`bouncelab.data.units`.

>>> import bouncelab as bl
>>> law = bl.Rigid.published("A")
>>> law
Rigid(r=0.544, mu=0.997)
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

from bouncelab.data import published, units
from bouncelab.data.campaign import make_campaign, validate_campaign
from bouncelab.data.slip_roll import classify_slip_roll
from bouncelab.errors import (
    BouncelabError,
    DataError,
    FitError,
    LawDefinitionError,
    NotFittedError,
    ParameterError,
)
from bouncelab.laws import (
    BounceModel,
    CompiledLaw,
    CompliantImpact,
    CraterContact,
    Parameter,
    Parameters,
    PennerFixed,
    PennerVarying,
    PiecewiseAffine,
    Rigid,
    TangentialRestitution,
    TurfContact,
    fit_method,
    load_law,
)
from bouncelab.metrics import delta, delta_q, error_table, score

# Heavier or edge modules load on first use, to keep `import bouncelab` fast.
_LAZY = {
    "load_campaign": "bouncelab.data.io",
    "save_campaign": "bouncelab.data.io",
    "generate_surrogate": "bouncelab.data.surrogate",
    "simulate_campaign": "bouncelab.simulation",
    "fit": "bouncelab.fitting",
    "FitResult": "bouncelab.fitting",
    "compare": "bouncelab.fitting",
    "split_by_setting": "bouncelab.fitting",
    "cross_validate": "bouncelab.fitting",
    "infer_settings": "bouncelab.data.settings",
    "bootstrap": "bouncelab.fitting",
    "sweep": "bouncelab.fitting",
    "assess": "bouncelab.fitting.assessment",
    "Assessment": "bouncelab.fitting.assessment",
    "calibrate": "bouncelab.fitting.hierarchical",
    "Posterior": "bouncelab.fitting.hierarchical",
    "load_posterior": "bouncelab.fitting.hierarchical",
    "BounceRegressor": "bouncelab.estimators",
}

__all__ = [
    "BounceModel",
    "BouncelabError",
    "CompiledLaw",
    "CompliantImpact",
    "CraterContact",
    "DataError",
    "FitError",
    "LawDefinitionError",
    "NotFittedError",
    "Parameter",
    "ParameterError",
    "Parameters",
    "PennerFixed",
    "PennerVarying",
    "PiecewiseAffine",
    "Rigid",
    "TangentialRestitution",
    "TurfContact",
    "__version__",
    "classify_slip_roll",
    "delta",
    "delta_q",
    "error_table",
    "fit_method",
    "load_law",
    "make_campaign",
    "published",
    "score",
    "units",
    "validate_campaign",
    *_LAZY,
]


# Subpackages that load on first attribute access (bl.fitting, bl.analysis, bl.plots, bl.cli, bl.simulation).
_SUBPACKAGES = ("analysis", "cli", "data", "estimators", "fitting", "ground", "laws", "plots", "simulation")


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBPACKAGES:
        return importlib.import_module(f"bouncelab.{name}")
    raise AttributeError(f"module 'bouncelab' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
