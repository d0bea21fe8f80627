"""Synthetic surrogate campaigns (bouncelab.simulation.surrogate) and the embedded files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import bouncelab
from bouncelab.core import published
from bouncelab.core.errors import ParameterError
from bouncelab.core.units import speed_angle_spin
from bouncelab.metrics import delta
from bouncelab.simulation.surrogate import DEFAULT_SEEDS, SurrogateSpec, generate_surrogate

FILES = Path(bouncelab.__file__).parent / "data" / "files"
VARS = ("landing", "liftoff", "landing_pi", "liftoff_pi")


@pytest.fixture(scope="module")
def fresh():
    return {k: generate_surrogate(k) for k in "AB"}


@pytest.fixture(scope="module")
def embedded():
    out = {}
    for k in "AB":
        with xr.open_dataset(FILES / f"campaign_{k}.nc", engine="scipy") as ds:
            out[k] = ds.load()
    return out


# --------------------------------------------------------------------------- embedded files
@pytest.mark.parametrize("campaign", ["A", "B"])
def test_embedded_file_equals_fresh_generation(campaign, fresh, embedded):
    f, g = embedded[campaign], fresh[campaign]
    assert dict(f.sizes) == dict(g.sizes)
    for var in VARS:
        assert f[var].dims == ("bounce", "component")
        np.testing.assert_allclose(f[var].values, g[var].values, rtol=1e-12, atol=1e-9, err_msg=var)
    np.testing.assert_array_equal(f["setting"].values, g["setting"].values)  # exactly
    np.testing.assert_array_equal(f["bounce"].values, g["bounce"].values)
    assert list(f["component"].values) == list(g["component"].values)
    assert list(f["unit"].values) == list(g["unit"].values)
    assert set(f.attrs) == set(g.attrs)
    for key, value in g.attrs.items():
        assert f.attrs[key] == value, key


def test_embedded_files_validate(embedded):
    for k in "AB":
        out = bouncelab.validate_campaign(embedded[k])
        np.testing.assert_array_equal(out["landing"].values, embedded[k]["landing"].values)


# --------------------------------------------------------------------------- design
@pytest.mark.parametrize(("campaign", "n"), [("A", 330), ("B", 693)])
def test_counts(campaign, n, fresh):
    ds = fresh[campaign]
    assert ds.sizes["bounce"] == n == published.CAMPAIGNS[campaign]["n_bounces"]
    assert ds.sizes["component"] == 3
    assert set(ds.data_vars) == set(VARS)


def test_campaign_a_settings_repeated_six_times(fresh):
    labels, counts = np.unique(fresh["A"]["setting"].values, return_counts=True)
    assert len(labels) == 55
    assert set(counts) == {6}
    np.testing.assert_array_equal(labels, np.arange(1, 56))


def test_campaign_b_settings_repeated_six_or_twelve_times_but_nine_lost(fresh):
    labels, counts = np.unique(fresh["B"]["setting"].values, return_counts=True)
    assert len(labels) == 82
    np.testing.assert_array_equal(labels, np.arange(1, 83))
    nominal = np.where(counts > 6, 12, 6)
    assert (nominal == 12).sum() == 35 and (nominal == 6).sum() == 47
    assert (nominal - counts).sum() == 9  # the lost bounces
    assert (counts == nominal).sum() >= 82 - 9
    assert counts.max() <= 12 and counts.min() >= 1


def test_repeats_of_a_setting_are_contiguous(fresh):
    for k in "AB":
        s = fresh[k]["setting"].values
        assert np.all(np.diff(s) >= 0)


def test_repeats_of_a_setting_scatter_about_one_landing(fresh):
    """Repeats share a launcher setting: their landings are far closer to each other than to other settings."""
    ds = fresh["A"]
    p0 = ds["landing"].values
    s = ds["setting"].values
    within = np.mean([np.linalg.norm(p0[s == k] - p0[s == k].mean(0), axis=1).mean() for k in np.unique(s)])
    overall = np.linalg.norm(p0 - p0.mean(0), axis=1).mean()
    assert within < 0.1 * overall


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_table1_scaled_ranges_roughly_respected(campaign, fresh):
    p0 = fresh[campaign]["landing"].values
    t1 = published.TABLE1.loc[campaign]
    for col, q in enumerate(("xdot", "ydot", "omega")):
        lo, hi = t1.loc[q, "min"], t1.loc[q, "max"]
        widen = 0.15 * max(abs(lo), abs(hi))  # launcher scatter and measurement noise
        span = hi - lo
        assert lo - widen <= p0[:, col].min() <= lo + 0.25 * span, q
        assert hi - 0.25 * span <= p0[:, col].max() <= hi + widen, q
    assert (p0[:, 1] < 0).all()


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_table1_physical_ranges_roughly_respected(campaign, fresh):
    phys = speed_angle_spin(fresh[campaign]["landing"].values)  # m/s, degrees, rpm
    t1 = published.TABLE1.loc[campaign]
    for q, key in (("speed", "speed"), ("angle", "angle_deg"), ("spin", "spin")):
        lo, hi = t1.loc[q, "min"], t1.loc[q, "max"]
        widen = 0.15 * max(abs(lo), abs(hi))
        span = hi - lo
        assert lo - widen <= phys[key].min() <= lo + 0.25 * span, q
        assert hi - 0.25 * span <= phys[key].max() <= hi + widen, q
    assert phys["angle_deg"].max() <= 90.0


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_attrs_say_synthetic(campaign, fresh):
    a = fresh[campaign].attrs
    assert a["data_kind"] == "synthetic surrogate"
    assert "SYNTHETIC SURROGATE" in a["warning"] and "NOT measured" in a["warning"]
    assert a["surface"].endswith("(synthetic surrogate)")
    assert a["campaign"] == campaign
    assert a["generator_seed"] == DEFAULT_SEEDS[campaign]
    assert f"generate_surrogate({campaign!r}, seed={DEFAULT_SEEDS[campaign]})" in a["source"]
    assert a["citation"] == published.CITATION
    assert a["ball_radius_m"] == 0.02135


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_prediction_intervals_are_about_five_percent(campaign, fresh):
    ds = fresh[campaign]
    for state in ("landing", "liftoff"):
        width = 2.0 * ds[f"{state}_pi"].values
        mean_abs = np.abs(ds[state].values).mean(axis=0)
        ratio = np.median(width / mean_abs, axis=0)
        assert np.all((ratio > 0.04) & (ratio < 0.06)), (state, ratio)
        assert (width > 0).all()


@pytest.mark.parametrize("campaign", ["A", "B"])
def test_published_law_scores_about_table2_delta(campaign, fresh):
    ds = fresh[campaign]
    law = bouncelab.PiecewiseAffine.published(campaign)
    d = delta(ds["landing"], ds["liftoff"], law.predict(ds["landing"].values))
    target = published.TABLE2.loc[(campaign, "overall"), "delta"]
    assert abs(d - target) <= 0.015, (d, target)


def test_other_laws_score_worse_on_the_surrogate(fresh):
    """The surrogate is made from the piecewise law: the published rigid law must be far worse on it."""
    ds = fresh["A"]
    pw = bouncelab.PiecewiseAffine.published("A")
    rigid = bouncelab.Rigid.published("A")
    p0 = ds["landing"].values
    assert delta(p0, ds["liftoff"], rigid.predict(p0)) > 2 * delta(p0, ds["liftoff"], pw.predict(p0))


# --------------------------------------------------------------------------- seeds and specs
def test_same_seed_same_data():
    xr.testing.assert_identical(generate_surrogate("A", seed=7), generate_surrogate("A", seed=7))


def test_default_seed_is_the_documented_one(fresh):
    xr.testing.assert_identical(generate_surrogate("b", seed=DEFAULT_SEEDS["B"]), fresh["B"])


def test_different_seed_different_data(fresh):
    other = generate_surrogate("A", seed=DEFAULT_SEEDS["A"] + 1)
    assert other.sizes == fresh["A"].sizes
    assert not np.allclose(other["landing"].values, fresh["A"]["landing"].values)
    assert not np.allclose(other["liftoff"].values, fresh["A"]["liftoff"].values)
    assert other.attrs["generator_seed"] == DEFAULT_SEEDS["A"] + 1


def test_spec_for_campaign():
    a = SurrogateSpec.for_campaign("A")
    assert a.settings == ((55, 6),) and a.lost == 0
    np.testing.assert_allclose(a.turf_delta_q, [(0.0413 + 0.0336) / 2, (0.0213 + 0.0201) / 2,
                                                (0.0394 + 0.0359) / 2], rtol=1e-12)
    b = SurrogateSpec.for_campaign("b")
    assert b.settings == ((35, 12), (47, 6)) and b.lost == 9
    assert sum(n * k for n, k in b.settings) - b.lost == 693
    assert b.pi_fraction == 0.05


def test_custom_spec():
    from dataclasses import replace

    spec = replace(SurrogateSpec.for_campaign("A"), settings=((4, 3),), lost=2)
    ds = generate_surrogate("A", seed=1, spec=spec)
    assert ds.sizes["bounce"] == 10
    assert len(np.unique(ds["setting"].values)) == 4


def test_spec_of_another_campaign_is_refused():
    with pytest.raises(ParameterError) as e:  # a spec of campaign B for campaign A
        generate_surrogate("A", spec=SurrogateSpec.for_campaign("B"))
    assert e.value.parameter == "spec"


def test_too_many_settings():
    from dataclasses import replace

    spec = replace(SurrogateSpec.for_campaign("A"), settings=((10_000, 6),))
    with pytest.raises(ParameterError) as e:  # more than the reachable settings
        generate_surrogate("A", spec=spec)
    assert (e.value.parameter, e.value.value) == ("settings", 10_000)


def test_unknown_campaign():
    with pytest.raises(ValueError) as e:
        generate_surrogate("C")
    assert e.value.option == "campaign"



# --------------------------------------------------------------------------- surrogate="turf" (issue 10 item 3)
@pytest.mark.parametrize(("campaign", "n"), [("A", 330), ("B", 693)])
def test_load_turf_surrogate_is_the_shipped_simulated_campaign(campaign, n):
    import json

    from bouncelab.simulation.surrogate import TURF_CALIBRATION

    ds = bouncelab.load_campaign(campaign, surrogate="turf")
    assert ds.sizes["bounce"] == n
    assert {"landing", "liftoff", "landing_pi", "liftoff_pi"} <= set(ds.data_vars)
    assert "setting" in ds.coords and np.isfinite(ds["liftoff_pi"].values).all()
    assert ds.attrs["surrogate"] == "turf"
    assert ds.attrs["data_kind"] == "synthetic surrogate" and ds.attrs["simulated"] == "yes"
    law = TURF_CALIBRATION[campaign]["law"]
    assert "NOT MEASURED" in ds.attrs["warning"] and law in ds.attrs["warning"]
    # the attrs hold the parameters the file was simulated with, and they are the calibrated ones
    assert json.loads(ds.attrs["turf_calibration"]) == TURF_CALIBRATION[campaign]
    turf = json.loads(ds.attrs["simulation_json"])["turf"]
    assert turf["law"]["law"] == law
    # a different campaign from the published surrogate
    pub = bouncelab.load_campaign(campaign, surrogate="published")
    assert pub.attrs["surrogate"] == "published"
    assert not np.allclose(pub["liftoff"].values, ds["liftoff"].values)


def test_load_campaign_default_is_turf_and_unknown_surrogate_is_refused():
    from bouncelab.core.errors import DataError
    from bouncelab.simulation.surrogate import DEFAULT_SURROGATE

    assert DEFAULT_SURROGATE == "turf"  # the one the calibration measures closer to the paper (docs/simulation.md)
    default = bouncelab.load_campaign("B")
    turf = bouncelab.load_campaign("B", surrogate="turf")
    xr.testing.assert_identical(default, turf)
    assert default.attrs["surrogate"] == "turf"
    assert bouncelab.load_campaign(" b ", surrogate=None).attrs["surrogate"] == "turf"
    assert "surrogate 'turf'" in default.attrs["warning"]  # what `bouncelab reproduce` prints
    assert "surrogate 'published'" in bouncelab.load_campaign("B", surrogate="published").attrs["warning"]
    with pytest.raises(DataError, match=r"'published', 'turf'.*'paper'"):
        bouncelab.load_campaign("A", surrogate="paper")


def test_surrogate_for_a_file_is_refused_not_ignored(tmp_path):
    from bouncelab.core.errors import DataError

    ds = bouncelab.load_campaign("A")
    path = bouncelab.save_campaign(ds, tmp_path / "a.nc")
    for surrogate in ("turf", "published"):  # any surrogate named for a file or a DataFrame is a mistake
        with pytest.raises(DataError) as exc:
            bouncelab.load_campaign(path, surrogate=surrogate)
        assert exc.value.file == str(path) and repr(surrogate) in exc.value.message
        frame = pd.DataFrame(ds["landing"].values, columns=["vx0", "vy0", "w0"])
        with pytest.raises(DataError) as exc:
            bouncelab.load_campaign(frame, surrogate=surrogate)
        assert exc.value.file == "<DataFrame>" and repr(surrogate) in exc.value.message
    assert bouncelab.load_campaign(path).sizes["bounce"] == 330


def test_cli_surrogate_option_chooses_the_embedded_campaign(capsys):
    from bouncelab.cli.main import main
    from bouncelab.simulation.surrogate import TURF_CALIBRATION

    assert main(["info", "A"]) == 0
    turf = capsys.readouterr()
    assert main(["info", "A", "--surrogate", "turf"]) == 0
    assert capsys.readouterr().out == turf.out  # turf is the default
    assert main(["info", "A", "--surrogate", "published"]) == 0
    pub = capsys.readouterr()
    law = TURF_CALIBRATION["A"]["law"]
    assert "surrogate 'turf'" in turf.out + turf.err and law in turf.out + turf.err
    assert "surrogate 'published'" in pub.out + pub.err and law not in pub.out + pub.err
    with pytest.raises(SystemExit) as bad:  # argparse refuses an unknown name, and lists the known ones
        main(["info", "A", "--surrogate", "paper"])
    assert bad.value.code == 2 and "'published', 'turf'" in capsys.readouterr().err


#: What a regenerated file promises on another machine: its compiled laws give the same bits on any x86-64
#: CPU (tests/test_bits.py), but NumPy's vectorised exp/log and BLAS differ in the last bits between
#: CPUs (measured: spot parameters 1 ulp apart between AVX-512 and AVX2 NumPy), and the simulated camera
#: and measurement carry that on. Integers, strings, labels and attrs are exact; numbers agree to this.
REGENERATION_RTOL = 1e-10


def assert_regenerates(shipped: xr.Dataset, fresh: xr.Dataset) -> None:
    """A fresh generation equals the shipped file: exactly but for floating-point numbers (REGENERATION_RTOL)."""
    assert dict(shipped.sizes) == dict(fresh.sizes)
    assert set(shipped.variables) == set(fresh.variables)
    for var in fresh.variables:
        a, b = shipped[var].values, fresh[var].values
        if a.dtype.kind == "f":
            scale = np.nanmax(np.abs(a)) if np.isfinite(a).any() else 1.0
            np.testing.assert_allclose(b, a, rtol=REGENERATION_RTOL, atol=REGENERATION_RTOL * scale, err_msg=var)
        else:
            np.testing.assert_array_equal(a, b, err_msg=var)
    assert shipped.attrs == fresh.attrs


@pytest.mark.slow
@pytest.mark.parametrize("campaign", ["A", "B"])
def test_shipped_turf_files_equal_a_fresh_simulation(campaign, tmp_path):
    """Regenerate the shipped turf files (python -m bouncelab.simulation.surrogate --write) and compare."""
    from bouncelab.simulation.surrogate import embedded_path, generate_turf_surrogate

    with xr.open_dataset(embedded_path(campaign, "turf"), engine="scipy") as f:
        shipped = f.load()
    fresh = generate_turf_surrogate(campaign)
    fresh.to_netcdf(tmp_path / "fresh.nc", engine="scipy")
    with xr.open_dataset(tmp_path / "fresh.nc", engine="scipy") as g:
        assert_regenerates(shipped, g.load())


def test_the_regeneration_check_catches_a_changed_number_or_label():
    """The tolerance of assert_regenerates is about last bits, not a licence: a real change still fails."""
    ds = xr.Dataset({"x": ("bounce", np.array([1.0, 2.0, 3.0])), "setting": ("bounce", np.array([0, 0, 1]))},
                    attrs={"generator_version": 2})
    assert_regenerates(ds, ds.copy(deep=True))
    ulp = ds.copy(deep=True)
    ulp["x"].values[1] = np.nextafter(2.0, 3.0)
    assert_regenerates(ds, ulp)
    for change in (lambda d: d["x"].values.__setitem__(1, 2.0 + 1e-6), lambda d: d["setting"].values.__setitem__(2, 0),
                   lambda d: d.attrs.__setitem__("generator_version", 3)):
        bad = ds.copy(deep=True)
        change(bad)
        with pytest.raises(AssertionError):
            assert_regenerates(ds, bad)


def test_embedded_file_names_and_paths_agree_with_the_loader():
    from bouncelab.simulation.surrogate import SURROGATES, embedded_file_name, embedded_path

    assert embedded_file_name("B", "published") == "campaign_B.nc"
    assert embedded_file_name("B") == embedded_file_name("B", "turf") == "campaign_B_turf.nc"
    for surrogate in SURROGATES:
        for key in "AB":
            path = embedded_path(key, surrogate)
            assert path.is_file() and path.name == embedded_file_name(key, surrogate)
