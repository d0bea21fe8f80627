"""The reference paper's published numbers, machine-readable.

Biber, Jones, Champneys, Green & Szalai, *Measurements and linearized models
for golf ball bounce* (the reference paper of bouncelab). Every number below is
transcribed as printed in the paper; percentages are stored as fractions
(``0.319`` for 31.9 %). Units are the paper's scaled units (radii/s, rad/s)
unless a column says otherwise.

Contents
--------
``CITATION``
    The reference.
``CAMPAIGNS``
    What each campaign was: surface, bounce count, repeats per setting.
``TABLE1``
    Ranges of landing conditions (Table 1), physical and scaled.
``TABLE2``
    Errors of the piecewise-affine fit by class, and the mismatched fraction (Table 2).
``TABLE3``
    Rigid-bounce and Penner fits: parameters and errors (Table 3).
``PIECEWISE``
    The plane and affine maps of eqs. (disjointA) and (disjointB).
``DRIVER_LANDING``
    The typical driver landing marked in the paper's Fig. 3.

Examples
--------
Compare a new fit with the paper's in one line:

>>> from bouncelab.core import published
>>> float(published.TABLE3.loc[("A", "Rigid"), "delta"])
0.319
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from bouncelab.core.errors import DataError, ParameterError

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "CAMPAIGNS",
    "CITATION",
    "DRIVER_LANDING",
    "PIECEWISE",
    "TABLE1",  # noqa: F822  (built on first use, by the module's __getattr__)
    "TABLE2",  # noqa: F822
    "TABLE3",  # noqa: F822
    "check_campaign",
    "paper_by_class",
    "paper_values",
    "piecewise_parameters",
    "rigid_family_parameters",
]

CITATION = (
    "S. W. Biber, K. M. Jones, A. R. Champneys, R. Green and R. Szalai, "
    "'Measurements and linearized models for golf ball bounce'."
)

CAMPAIGNS: dict[str, dict] = {
    "A": {
        "surface": "premium artificial teeing turf, 30 mm thick, on 38 mm wood",
        "n_bounces": 330,
        "repeats_per_setting": (6,),
    },
    "B": {
        "surface": "well-maintained natural teeing area",
        "n_bounces": 693,
        "repeats_per_setting": (6, 12),
    },
}

# Table 1: (campaign, quantity) -> (min, max, unit)
_TABLE1_ROWS = [
    ("A", "speed", 6.35, 56.1, "m/s"),
    ("A", "angle", 18.3, 76.4, "deg"),
    ("A", "spin", -3750.0, 9100.0, "rpm"),
    ("A", "xdot", 74.9, 2260.0, "radius/s"),
    ("A", "ydot", -1880.0, -225.0, "radius/s"),
    ("A", "omega", -392.0, 953.0, "rad/s"),
    ("B", "speed", 1.93, 38.7, "m/s"),
    ("B", "angle", 16.4, 89.5, "deg"),
    ("B", "spin", -3880.0, 16200.0, "rpm"),
    ("B", "xdot", 1.10, 1720.0, "radius/s"),
    ("B", "ydot", -1570.0, -90.0, "radius/s"),
    ("B", "omega", -407.0, 1670.0, "rad/s"),
]
# Table 2: piecewise-affine (SVM) fit errors, as fractions.
_TABLE2_ROWS = [
    # campaign, subset, delta, d_xdot, d_ydot, d_omega, mismatched
    ("A", "overall", 0.0656, np.nan, np.nan, np.nan, 0.0727),
    ("A", "roll", 0.0679, 0.0413, 0.0213, 0.0394, np.nan),
    ("A", "slip", 0.0595, 0.0336, 0.0201, 0.0359, np.nan),
    ("B", "overall", 0.0784, np.nan, np.nan, np.nan, 0.0959),
    ("B", "roll", 0.0807, 0.0533, 0.0252, 0.0474, np.nan),
    ("B", "slip", 0.0731, 0.0376, 0.00920, 0.0541, np.nan),
]
# Table 3: rigid-bounce family, parameters and errors (fractions).
_TABLE3_ROWS = [
    # campaign, law, r, mu, beta_deg, k_p, delta, d_xdot, d_ydot, d_omega
    ("A", "Rigid", 0.544, 0.997, np.nan, np.nan, 0.319, 0.193, 0.0458, 0.186),
    ("A", "PennerVarying", 0.448, 0.969, np.nan, 1.543e-4, 0.255, 0.146, 0.0442, 0.161),
    ("A", "PennerFixed", 0.420, 0.852, 12.9, np.nan, 0.190, 0.0958, 0.0317, 0.142),
    ("B", "Rigid", 0.260, 0.998, np.nan, np.nan, 0.350, 0.198, 0.0632, 0.246),
    ("B", "PennerVarying", 0.222, 0.999, np.nan, 2.973e-4, 0.213, 0.0942, 0.0430, 0.164),
    ("B", "PennerFixed", 0.147, 0.998, 18.4, np.nan, 0.192, 0.0916, 0.0424, 0.151),
]
# Eqs. (disjointA) and (disjointB): p_F = A1 p0 + b1 if n.p0 < c (roll side), else A2 p0 + b2 (slip side),
# with the plane printed as a*xdot0 + b*ydot0 + omega0 = c.
PIECEWISE: dict[str, dict] = {
    "A": {
        "normal": (0.891, 0.763, 1.0),
        "offset": 600.0,
        "A1": ((0.536, -0.004, -0.205), (0.144, -0.407, -0.027), (-0.524, 0.091, 0.318)),
        "b1": (-111.0, 23.7, 39.4),
        "A2": ((0.674, 0.107, -0.005), (0.103, -0.390, 0.017), (-0.153, 0.277, 1.01)),
        "b2": (-154.0, 25.0, -267.0),
    },
    "B": {
        "normal": (0.377, 2.25, 1.0),
        "offset": -485.0,
        "A1": ((0.326, 0.222, -0.213), (0.185, -0.008, -0.076), (-0.333, -0.147, 0.224)),
        "b1": (175.0, 90.4, -171.0),
        "A2": ((0.606, 0.649, -0.007), (0.146, -0.089, -0.006), (-0.192, 1.01, 0.887)),
        "b2": (117.0, 49.3, 35.0),
    },
}

#: The typical tee shot with a driver marked in Fig. 3 (physical units as printed).
DRIVER_LANDING = {"speed": 93.6, "speed_unit": "ft/s", "angle_deg": 37.3, "spin": 34.9, "spin_unit": "rev/s"}


def check_campaign(campaign: str) -> str:
    """Return ``"A"`` or ``"B"`` for a campaign name, or raise :class:`~bouncelab.DataError`."""
    key = str(campaign).strip().upper() if isinstance(campaign, str) else None
    if key not in CAMPAIGNS:
        raise DataError(f"the paper has campaigns 'A' and 'B'; got {campaign!r}", option="campaign")
    return key


def rigid_family_parameters(campaign: str, law: str) -> dict[str, float]:
    """Published parameters of a rigid-family law (Table 3), keyed by the law's keyword names."""
    names = {"Rigid": ("r", "mu"), "PennerVarying": ("r", "mu", "k_p"), "PennerFixed": ("r", "mu", "beta_deg")}
    key = check_campaign(campaign)
    if law not in names:
        raise ParameterError(f"Table 3 has the laws {list(names)}; got {law!r}", law=law)
    columns = ("r", "mu", "beta_deg", "k_p")
    # read from the rows, not the DataFrame: a law's published values are asked for on predict (its
    # non-physical check), which must not import pandas
    row = next(r for r in _TABLE3_ROWS if r[:2] == (key, law))
    return {name: float(row[2 + columns.index(name)]) for name in names[law]}


def piecewise_parameters(campaign: str) -> dict:
    """Published piecewise-affine law (eqs. disjointA/B) as keyword arguments of ``PiecewiseAffine``."""
    p = PIECEWISE[check_campaign(campaign)]
    return {
        "normal": np.array(p["normal"]),
        "offset": p["offset"],
        "A1": np.array(p["A1"]),
        "b1": np.array(p["b1"]),
        "A2": np.array(p["A2"]),
        "b2": np.array(p["b2"]),
    }


def paper_values(campaign: str, law: str) -> dict[str, float]:
    """What the paper published for a law (by class name) fitted to all bounces of a campaign.

    Table 3's parameters and errors for the rigid family; Table 2's overall delta
    for the piecewise-affine law (Table 2 has no overall Delta q); ``{}`` for any
    other law.
    """
    key = check_campaign(campaign)
    if law in _table("TABLE3").loc[key].index:
        row = _table("TABLE3").loc[(key, law)]
        return {k: float(v) for k, v in row.items() if np.isfinite(v)}
    if law == "PiecewiseAffine":
        return {"delta": float(_table("TABLE2").loc[(key, "overall"), "delta"]),
                "mismatched": float(_table("TABLE2").loc[(key, "overall"), "mismatched"])}
    return {}


def paper_by_class(campaign: str, law: str) -> pd.DataFrame | None:
    """The paper's errors by slip/roll class for a law (Table 2, the piecewise-affine law), or None."""
    key = check_campaign(campaign)
    if law == "PiecewiseAffine":
        return _table("TABLE2").loc[key]
    return None


# The tables are pandas DataFrames, built on first use so that this module (below the laws) does not import
# pandas: ``published.TABLE1`` works as a module attribute.
_TABLES: dict[str, Any] = {}


def _table(name: str) -> pd.DataFrame:
    if name not in _TABLES:
        import pandas as pd

        if name == "TABLE1":
            t = pd.DataFrame(_TABLE1_ROWS, columns=["campaign", "quantity", "min", "max", "unit"]).set_index(
                ["campaign", "quantity"])
            t.attrs["caption"] = "Table 1: range of initial conditions for Campaigns A and B"
        elif name == "TABLE2":
            t = pd.DataFrame(_TABLE2_ROWS, columns=["campaign", "subset", "delta", "delta_xdot", "delta_ydot",
                                                    "delta_omega", "mismatched"]).set_index(["campaign", "subset"])
            t.attrs["caption"] = (
                "Table 2: error of the disjoint (piecewise) affine fits, eqs. (disjointA/B), on the test set; "
                "'mismatched' is the fraction of test bounces the plane puts in the wrong class")
        else:
            t = pd.DataFrame(_TABLE3_ROWS, columns=["campaign", "law", "r", "mu", "beta_deg", "k_p", "delta",
                                                    "delta_xdot", "delta_ydot", "delta_omega"]).set_index(
                ["campaign", "law"])
            t.attrs["caption"] = "Table 3: best fit of the rigid-bounce models, with their errors"
        _TABLES[name] = t
    return _TABLES[name]


def __getattr__(name: str) -> Any:
    if name in ("TABLE1", "TABLE2", "TABLE3"):
        return _table(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
