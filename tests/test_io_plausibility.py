"""Unit plausibility: bouncelab.core.plausibility and how the loader uses it (issue 7, item 3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import bouncelab as bl
from bouncelab.core.errors import DataError, Hint
from bouncelab.core.plausibility import (
    CANDIDATE_UNITS,
    PLAUSIBLE_RANGES,
    implausibility,
    plausible_units,
)

R = 0.02135
RPM = 2 * math.pi / 60
# Three bounces in m/s and rpm, within the paper's Table 1.
LAND = np.array([[20.1, -15.2, 3000.0], [12.2, -22.5, -1200.0], [30.0, -20.0, 4500.0]])
LIFT = np.array([[9.5, 5.1, 1500.0], [6.1, 7.7, 600.0], [14.0, 6.0, 2500.0]])
NAMES = ["vx0", "vy0", "w0", "vxF", "vyF", "wF"]


def scaled(state: np.ndarray) -> np.ndarray:
    return np.column_stack([state[:, 0] / R, state[:, 1] / R, state[:, 2] * RPM])


def write(path, land, lift, names=NAMES):
    rows = [",".join(names)] + [",".join(repr(float(v)) for v in (*a, *b)) for a, b in zip(land, lift, strict=True)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_the_paper_campaigns_are_plausible():
    for name in ("A", "B"):
        ds = bl.load_campaign(name)
        assert implausibility(ds.landing.values, ds.liftoff.values) is None


def test_rpm_read_as_rad_per_s_is_implausible():
    land = scaled(LAND)
    land[1, 2] = 3000.0  # 3000 rad/s = 28 648 rpm
    why = implausibility(land, scaled(LIFT))
    assert (why.state, why.component, why.row, why.kind) == ("landing", "omega", 1, "spin")
    assert "28648 rpm" in why.reason
    assert implausibility(land, scaled(LIFT), ranges=PLAUSIBLE_RANGES.widened(max_spin=30_000)) is None


def test_m_per_s_read_as_radii_per_s_is_too_slow_only_when_telling_units_apart():
    land, lift = LAND.copy(), LIFT.copy()  # m/s numbers taken as radii/s: < 1 m/s landings
    land[:, 2] *= RPM
    lift[:, 2] *= RPM
    assert implausibility(land, lift) is None
    why = implausibility(land, lift, lower=True)
    assert why.kind == "velocity" and "median landing speed" in why.reason


@pytest.mark.parametrize("unit", ["ft/s", "km/h", "mph"])
def test_loader_refuses_physical_velocities_without_a_unit(tmp_path, unit):
    """ft/s, km/h and mph numbers used to pass as radii/s; now they are called ambiguous."""
    factor = {"ft/s": 1 / 0.3048, "km/h": 3.6, "mph": 3600 / 1609.344}[unit]
    land, lift = LAND.copy(), LIFT.copy()
    land[:, :2] *= factor
    lift[:, :2] *= factor
    path = write(tmp_path / "v.csv", land, lift)
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units={"spin": "rpm"})
    hints = exc.value.hints  # several units fit, radii/s among them: bouncelab does not guess
    assert Hint("units", {"velocity": "radius/s"}) in hints and Hint("units", {"velocity": unit}) in hints
    ds = bl.load_campaign(path, units={"spin": "rpm", "velocity": unit})
    np.testing.assert_allclose(ds.landing.values, scaled(LAND), rtol=1e-12)


def test_loader_refuses_rpm_below_5000_without_a_unit(tmp_path):
    """Spins of 600..4500 rpm used to load as rad/s (up to 43 000 rpm)."""
    path = write(tmp_path / "s.csv", LAND, LIFT, ["vx0 [m/s]", "vy0 [m/s]", "w0", "vxF [m/s]", "vyF [m/s]", "wF"])
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path)
    assert (exc.value.column, exc.value.row) == ("w0", 1)  # 3000 rad/s: 28 648 rpm
    assert exc.value.hints == (Hint("units", {"spin": "rpm"}),)  # only rpm fits
    assert "'w0', 'wF'" in exc.value.message
    np.testing.assert_allclose(bl.load_campaign(path, units={"spin": "rpm"}).landing.values, scaled(LAND),
                               rtol=1e-12)


def test_loader_refuses_spins_that_fit_rad_per_s_and_rpm(tmp_path):
    land, lift = scaled(LAND), scaled(LIFT)
    path = write(tmp_path / "s.csv", land, lift)
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path)
    assert exc.value.hints == (Hint("units", {"spin": "rad/s"}), Hint("units", {"spin": "rpm"}))
    ds = bl.load_campaign(path, units={"spin": "rad/s"})
    np.testing.assert_array_equal(ds.landing.values, land)


def test_widened_ranges_accept_on_purpose(tmp_path):
    land = LAND.copy()
    land[0, 2] = 25_000.0
    path = write(tmp_path / "fast.csv", land, LIFT)
    with pytest.raises(DataError) as exc:
        bl.load_campaign(path, units={"velocity": "m/s", "spin": "rpm"})
    assert exc.value.column == "w0" and exc.value.row == 1
    assert [h.option for h in exc.value.hints] == ["units", "units", "plausible"]  # rad/s, rev/s, or wider ranges
    ds = bl.load_campaign(path, units={"velocity": "m/s", "spin": "rpm"},
                          plausible=PLAUSIBLE_RANGES.widened(max_spin=30_000))
    assert ds.landing.values[0, 2] == pytest.approx(25_000 * RPM)


def test_plausible_units_and_hint():
    land, lift = scaled(LAND), scaled(LIFT)
    verdicts = plausible_units("velocity", lambda f: (land * [f, f, 1], lift * [f, f, 1]))
    assert [u for u, why in verdicts.items() if why is None] == ["radius/s"]
    assert set(verdicts) == set(CANDIDATE_UNITS["velocity"])
