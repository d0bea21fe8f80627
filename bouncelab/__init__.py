"""bouncelab: golf-ball bounce laws as first-class objects.

Fit bounce laws to measured bounces, compare them and use them, following
Biber, Jones, Champneys, Green & Szalai, *Measurements and linearized models
for golf ball bounce*. All states are ``[xdot, ydot, omega]`` in the paper's
scaled units (radii/s and rad/s, y up, omega > 0 backspin); see
:mod:`bouncelab.core.units`.

>>> import bouncelab as bl
>>> law = bl.Rigid.published("A")
>>> law
Rigid(r=0.544, mu=0.997)
"""

from __future__ import annotations

import importlib
from typing import Any

from bouncelab.core import __version__, published, units
from bouncelab.core.errors import (
    BouncelabError,
    DataError,
    FitError,
    LawDefinitionError,
    NotFittedError,
    ParameterError,
)
from bouncelab.core.slip_roll import classify_slip_roll
from bouncelab.laws import (
    BounceModel,
    CompiledLaw,
    CompliantImpact,
    CraterContact,
    Option,
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

# Everything above the laws (campaigns, the loader, fitting, analysis) loads on first use: `import bouncelab`
# and `import bouncelab.laws` stay fast and import neither pandas nor xarray nor the loader (tested).
_LAZY = {
    "make_campaign": "bouncelab.data.campaign",
    "validate_campaign": "bouncelab.data.campaign",
    "delta": "bouncelab.metrics",
    "delta_q": "bouncelab.metrics",
    "error_table": "bouncelab.metrics",
    "score": "bouncelab.metrics",
    "load_campaign": "bouncelab.data.io",
    "save_campaign": "bouncelab.data.io",
    "generate_surrogate": "bouncelab.simulation.surrogate",
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
    "reproduce": "bouncelab.report",
    "Report": "bouncelab.report",
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
    "Option",
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
    "fit_method",
    "load_law",
    "published",
    "units",
    *_LAZY,  # (delta, fit, load_campaign...: loaded on first use)
]


# Subpackages that load on first attribute access (bl.fitting, bl.analysis, bl.plots, bl.report, bl.cli...).
_SUBPACKAGES = ("analysis", "cli", "core", "data", "estimators", "fitting", "ground", "laws", "plots", "report",
                "simulation")
#: Modules of the ground floor known by their short names: ``bl.errors.DataError``, ``bl.units.to_scaled``.
_CORE = ("errors", "plausibility", "published", "units")


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBPACKAGES:
        return importlib.import_module(f"bouncelab.{name}")
    if name in _CORE:
        return importlib.import_module(f"bouncelab.core.{name}")
    raise AttributeError(f"module 'bouncelab' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
