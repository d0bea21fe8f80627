"""The paper's published numbers (bouncelab.core.published), checked cell by cell.

The expected values below were typed from the paper's LaTeX source
(bounce-paper.tex: Table 1 ``tab:ic_camA``, Table 2 ``tab:disjoin_error``,
Table 3 ``tab:penner_fit``, eqs. ``disjointA``/``disjointB``), independently of
the module. When that source is available the piecewise maps are also
re-parsed from it.
"""

from __future__ import annotations

import doctest
import re
from pathlib import Path

import numpy as np
import pytest

from bouncelab.core import published
from bouncelab.core.errors import DataError, ParameterError

PAPER = Path("/work/shared/reference/bounce-paper.tex")

# --------------------------------------------------------------------------- Table 1
TABLE1_PRINTED = {
    ("A", "speed"): (6.35, 56.1), ("A", "angle"): (18.3, 76.4), ("A", "spin"): (-3750, 9100),
    ("A", "xdot"): (74.9, 2260), ("A", "ydot"): (-1880, -225), ("A", "omega"): (-392, 953),
    ("B", "speed"): (1.93, 38.7), ("B", "angle"): (16.4, 89.5), ("B", "spin"): (-3880, 16200),
    ("B", "xdot"): (1.10, 1720), ("B", "ydot"): (-1570, -90.0), ("B", "omega"): (-407, 1670),
}


@pytest.mark.parametrize("key", sorted(TABLE1_PRINTED))
def test_table1_cells(key):
    lo, hi = TABLE1_PRINTED[key]
    assert published.TABLE1.loc[key, "min"] == lo
    assert published.TABLE1.loc[key, "max"] == hi


def test_table1_units_and_size():
    t1 = published.TABLE1
    assert len(t1) == 12
    units = dict(zip(t1.index.get_level_values("quantity"), t1["unit"], strict=True))
    assert units == {"speed": "m/s", "angle": "deg", "spin": "rpm",
                     "xdot": "radius/s", "ydot": "radius/s", "omega": "rad/s"}
    assert (t1["min"] < t1["max"]).all()


# --------------------------------------------------------------------------- Table 2
# (campaign, subset): (delta, d_xdot, d_ydot, d_omega) in percent as printed
TABLE2_PRINTED = {
    ("A", "roll"): (6.79, 4.13, 2.13, 3.94),
    ("A", "slip"): (5.95, 3.36, 2.01, 3.59),
    ("B", "roll"): (8.07, 5.33, 2.52, 4.74),
    ("B", "slip"): (7.31, 3.76, 0.920, 5.41),
}


@pytest.mark.parametrize("key", sorted(TABLE2_PRINTED))
def test_table2_class_cells(key):
    row = published.TABLE2.loc[key]
    got = [row["delta"], row["delta_xdot"], row["delta_ydot"], row["delta_omega"]]
    np.testing.assert_allclose(got, np.array(TABLE2_PRINTED[key]) / 100, rtol=1e-12)
    assert np.isnan(row["mismatched"])


@pytest.mark.parametrize(("campaign", "overall", "mismatched"), [("A", 6.56, 7.27), ("B", 7.84, 9.59)])
def test_table2_overall_and_mismatched(campaign, overall, mismatched):
    row = published.TABLE2.loc[(campaign, "overall")]
    assert row["delta"] == pytest.approx(overall / 100, rel=1e-12)
    assert row["mismatched"] == pytest.approx(mismatched / 100, rel=1e-12)
    assert np.isnan(row[["delta_xdot", "delta_ydot", "delta_omega"]].astype(float)).all()


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_table2_overall_delta_lies_between_the_classes(campaign):
    t2 = published.TABLE2.loc[campaign]
    lo, hi = sorted(t2.loc[["roll", "slip"], "delta"])
    assert lo <= t2.loc["overall", "delta"] <= hi


# --------------------------------------------------------------------------- Table 3
# (campaign, law): r, mu, beta_deg, k_p, delta%, d_xdot%, d_ydot%, d_omega%
TABLE3_PRINTED = {
    ("A", "Rigid"): (0.544, 0.997, None, None, 31.9, 19.3, 4.58, 18.6),
    ("A", "PennerVarying"): (0.448, 0.969, None, 1.543e-4, 25.5, 14.6, 4.42, 16.1),
    ("A", "PennerFixed"): (0.420, 0.852, 12.9, None, 19.0, 9.58, 3.17, 14.2),
    ("B", "Rigid"): (0.260, 0.998, None, None, 35.0, 19.8, 6.32, 24.6),
    ("B", "PennerVarying"): (0.222, 0.999, None, 2.973e-4, 21.3, 9.42, 4.30, 16.4),
    ("B", "PennerFixed"): (0.147, 0.998, 18.4, None, 19.2, 9.16, 4.24, 15.1),
}


@pytest.mark.parametrize("key", sorted(TABLE3_PRINTED))
def test_table3_cells(key):
    r, mu, beta, k_p, *errs = TABLE3_PRINTED[key]
    row = published.TABLE3.loc[key]
    assert row["r"] == r
    assert row["mu"] == mu
    for col, want in (("beta_deg", beta), ("k_p", k_p)):
        if want is None:
            assert np.isnan(row[col])
        else:
            assert row[col] == pytest.approx(want, rel=1e-12)
    got = [row["delta"], row["delta_xdot"], row["delta_ydot"], row["delta_omega"]]
    np.testing.assert_allclose(got, np.array(errs) / 100, rtol=1e-12)


def test_table3_has_exactly_six_rows():
    assert sorted(published.TABLE3.index) == sorted(TABLE3_PRINTED)


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_table3_error_ordering_matches_the_papers_text(campaign):
    """Section Results: fixed beta beats Penner's varying beta, which beats the plain rigid bounce."""
    d = published.TABLE3.loc[campaign, "delta"]
    assert d["PennerFixed"] < d["PennerVarying"] < d["Rigid"]
    # and the piecewise fit is several times better than all of them (Discussion)
    assert published.TABLE2.loc[(campaign, "overall"), "delta"] * 2.4 < d.min()


# --------------------------------------------------------------------------- piecewise maps
PIECEWISE_PRINTED = {
    "A": {
        "normal": (0.891, 0.763, 1.0), "offset": 600.0,
        "A1": ((0.536, -0.004, -0.205), (0.144, -0.407, -0.027), (-0.524, 0.091, 0.318)),
        "b1": (-111.0, 23.7, 39.4),
        "A2": ((0.674, 0.107, -0.005), (0.103, -0.390, 0.017), (-0.153, 0.277, 1.01)),
        "b2": (-154.0, 25.0, -267.0),
    },
    "B": {
        "normal": (0.377, 2.25, 1.0), "offset": -485.0,
        "A1": ((0.326, 0.222, -0.213), (0.185, -0.008, -0.076), (-0.333, -0.147, 0.224)),
        "b1": (175.0, 90.4, -171.0),
        "A2": ((0.606, 0.649, -0.007), (0.146, -0.089, -0.006), (-0.192, 1.01, 0.887)),
        "b2": (117.0, 49.3, 35.0),
    },
}


@pytest.mark.parametrize("campaign", ["A", "B"])
@pytest.mark.parametrize("key", ["normal", "offset", "A1", "b1", "A2", "b2"])
def test_piecewise_entries(campaign, key):
    np.testing.assert_array_equal(np.array(published.PIECEWISE[campaign][key]),
                                  np.array(PIECEWISE_PRINTED[campaign][key]))


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_piecewise_sample_entries(campaign):
    """A few single entries, spelled out (row, column as printed)."""
    p = published.PIECEWISE[campaign]
    if campaign == "A":
        assert p["A1"][0][2] == -0.205 and p["A1"][2][0] == -0.524
        assert p["A2"][2][2] == 1.01 and p["A2"][1][1] == -0.390
        assert p["b2"][2] == -267.0
    else:
        assert p["A1"][1][1] == -0.008 and p["A1"][2][1] == -0.147
        assert p["A2"][0][1] == 0.649 and p["A2"][2][1] == 1.01
        assert p["b1"][1] == 90.4


def _numbers(text: str) -> list[float]:
    text = re.sub(r"_[0F]\b|_\{?[0F]\}?", "", text)  # drop subscripts such as \dot{x}_0
    return [float(t) for t in re.findall(r"-?\d+(?:\.\d+)?", text)]


@pytest.mark.skipif(not PAPER.exists(), reason="the paper's LaTeX source is not available")
@pytest.mark.parametrize("campaign", ["A", "B"])
def test_piecewise_reparsed_from_the_paper(campaign):
    tex = PAPER.read_text()
    start = tex.index(rf"\label{{eq:disjoint{campaign}}}")
    block = tex[start + len(rf"\label{{eq:disjoint{campaign}}}"): tex.index(r"\end{equation}", start)]
    nums = _numbers(block)
    p = published.PIECEWISE[campaign]
    a, b, _ = p["normal"]
    expected = [*np.ravel(p["A1"]), *p["b1"], a, b, p["offset"], *np.ravel(p["A2"]), *p["b2"], a, b, p["offset"]]
    assert nums == expected


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_piecewise_plane_puts_strong_backspin_on_the_slip_side(campaign):
    """Side 2 (n.p0 > offset) is the slip side: a shallow landing with strong backspin slips throughout,
    a steep fast landing with little spin rolls (paper: v_P > 0 cases come from high backspin)."""
    p = published.PIECEWISE[campaign]
    assert np.dot(p["normal"], [500.0, -300.0, 900.0]) > p["offset"]
    assert np.dot(p["normal"], [300.0, -1200.0, 0.0]) < p["offset"]


# --------------------------------------------------------------------------- other constants
def test_campaigns():
    assert published.CAMPAIGNS["A"]["n_bounces"] == 330
    assert published.CAMPAIGNS["B"]["n_bounces"] == 693
    assert published.CAMPAIGNS["A"]["repeats_per_setting"] == (6,)
    assert published.CAMPAIGNS["B"]["repeats_per_setting"] == (6, 12)
    assert "artificial" in published.CAMPAIGNS["A"]["surface"]
    assert "30 mm" in published.CAMPAIGNS["A"]["surface"]
    assert "natural" in published.CAMPAIGNS["B"]["surface"]


def test_driver_landing():
    assert published.DRIVER_LANDING == {"speed": 93.6, "speed_unit": "ft/s", "angle_deg": 37.3,
                                        "spin": 34.9, "spin_unit": "rev/s"}


def test_citation():
    for name in ("Biber", "Jones", "Champneys", "Green", "Szalai", "golf ball bounce"):
        assert name in published.CITATION


# --------------------------------------------------------------------------- helpers
@pytest.mark.parametrize(("name", "key"), [("A", "A"), ("a", "A"), (" b ", "B"), ("B", "B")])
def test_check_campaign(name, key):
    assert published.check_campaign(name) == key


@pytest.mark.parametrize("bad", ["C", "", "AB", None, 1])
def test_unknown_campaign(bad):
    for call in (lambda: published.check_campaign(bad), lambda: published.piecewise_parameters(bad),
                 lambda: published.rigid_family_parameters(bad, "Rigid")):
        with pytest.raises(DataError) as e:  # the library's own error type
            call()
        assert e.value.option == "campaign"


def test_rigid_family_parameters():
    assert published.rigid_family_parameters("A", "Rigid") == {"r": 0.544, "mu": 0.997}
    assert published.rigid_family_parameters("b", "PennerVarying") == {"r": 0.222, "mu": 0.999, "k_p": 2.973e-4}
    assert published.rigid_family_parameters("A", "PennerFixed") == {"r": 0.420, "mu": 0.852, "beta_deg": 12.9}
    out = published.rigid_family_parameters("B", "PennerFixed")
    assert all(type(v) is float for v in out.values())


def test_rigid_family_parameters_unknown_law():
    with pytest.raises(ParameterError) as e:
        published.rigid_family_parameters("A", "Piecewise")
    assert e.value.law == "Piecewise" and "PennerFixed" in e.value.message  # the laws it has are listed


def test_piecewise_parameters():
    kw = published.piecewise_parameters("b")
    assert set(kw) == {"normal", "offset", "A1", "b1", "A2", "b2"}
    assert kw["A1"].shape == kw["A2"].shape == (3, 3)
    assert kw["b1"].shape == kw["b2"].shape == kw["normal"].shape == (3,)
    assert kw["offset"] == -485.0
    np.testing.assert_array_equal(kw["A2"][2], [-0.192, 1.01, 0.887])
    kw["A1"][0, 0] = 99.0  # the caller's copy; the published table is unchanged
    assert published.PIECEWISE["B"]["A1"][0][0] == 0.326
    assert published.piecewise_parameters("B")["A1"][0, 0] == 0.326


def test_docstring_examples():
    result = doctest.testmod(published)
    assert result.attempted >= 1
    assert result.failed == 0
