"""The paper's figures (bouncelab.plots): structure, labels, point counts, notes and input errors."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

import bouncelab as bl  # noqa: E402
from bouncelab.core.errors import DataError, Hint, NotFittedError  # noqa: E402
from bouncelab.data.campaign import make_campaign  # noqa: E402
from bouncelab.laws.plane_fitting import fit_svm  # noqa: E402
from bouncelab.plots import (  # noqa: E402
    plot_landing_space,
    plot_pi_widths,
    plot_predictions,
    plot_repeatability,
    plot_slices,
    plot_tangential,
    save_figure,
)
from bouncelab.plots._common import has_synthetic_note, pyplot  # noqa: E402
from bouncelab.plots.landing import _oblique_view, driver_landing, plane_polygon  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def ds_a() -> xr.Dataset:
    return bl.load_campaign("A")


@pytest.fixture(scope="module")
def measured(ds_a) -> xr.Dataset:
    """Campaign A's numbers relabelled as measured data (no synthetic note expected)."""
    return make_campaign(
        ds_a["landing"].values, ds_a["liftoff"].values, setting=ds_a["setting"].values,
        landing_pi=ds_a["landing_pi"].values, liftoff_pi=ds_a["liftoff_pi"].values,
        campaign="M", data_kind="measured",
    )


def _rep(n_settings: int = 4, campaign: str = "R", data_kind: str = "measured") -> xr.Dataset:
    """A small Dataset in the format of bouncelab.analysis.repeats.repeatability."""
    rng = np.random.default_rng(0)
    mean = rng.normal(0.0, 300.0, (n_settings, 2, 3))
    hw = rng.uniform(5.0, 40.0, (n_settings, 2, 3))
    dims = ("setting", "state", "component")
    return xr.Dataset(
        {"mean": (dims, mean), "half_width": (dims, hw), "ci_low": (dims, mean - hw),
         "ci_high": (dims, mean + hw), "n": ("setting", np.full(n_settings, 6))},
        coords={"setting": np.arange(1, n_settings + 1), "state": ["landing", "liftoff"],
                "component": ["xdot", "ydot", "omega"]},
        attrs={"campaign": campaign, "data_kind": data_kind, "level": 0.95},
    )


def _points(ax, gid: str) -> np.ndarray:
    """Offsets of the collections with this gid, stacked."""
    offs = [np.asarray(col.get_offsets()) for col in ax.collections if col.get_gid() == gid]
    return np.vstack(offs) if offs else np.empty((0, 2))


def _n_class_points(ax) -> int:
    return len(_points(ax, "class-roll")) + len(_points(ax, "class-slip"))


# ------------------------------------------------------------------------------------ Fig. 3
def test_landing_space_points_plane_support_driver(ds_a):
    law = bl.PiecewiseAffine.published("A")
    support = np.array([0, 5, 17, 40])
    fig = plot_landing_space(ds_a, law, support)
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    assert ax.name == "3d"
    assert "$\\dot{x}_0$" in ax.get_xlabel() and "[radii/s]" in ax.get_xlabel()
    assert "$\\dot{y}_0$" in ax.get_ylabel() and "[radii/s]" in ax.get_ylabel()
    assert "$\\omega_0$" in ax.get_zlabel() and "[rad/s]" in ax.get_zlabel()
    classes = bl.classify_slip_roll(ds_a["landing"], ds_a["liftoff"])
    assert len(_points(ax, "class-roll")) == (classes == "roll").sum()
    assert len(_points(ax, "class-slip")) == (classes == "slip").sum()
    assert len(_points(ax, "support-vectors")) == len(support)
    assert len(_points(ax, "driver-landing")) == 1
    planes = [col for col in ax.collections if col.get_gid() == "separating-plane"]
    assert len(planes) == 1 and 0 < planes[0].get_alpha() < 1
    assert "Campaign A" in fig._suptitle.get_text()
    assert has_synthetic_note(fig)


def test_landing_space_without_law_has_no_plane(ds_a):
    fig = plot_landing_space(ds_a, driver=False)
    ax = fig.axes[0]
    assert _n_class_points(ax) == ds_a.sizes["bounce"]
    assert not [col for col in ax.collections if col.get_gid() in ("separating-plane", "driver-landing")]


def test_landing_space_accepts_fit_results_and_svm_fits(ds_a):
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    svm = fit_svm(p0, pf)
    ax = plot_landing_space(ds_a, svm).axes[0]  # the PlaneFit brings its own support vectors
    assert len(_points(ax, "support-vectors")) == len(svm.svm_support)
    mask = np.zeros(len(p0), dtype=bool)
    mask[svm.svm_support] = True
    ax = plot_landing_space(ds_a, bl.PiecewiseAffine(**svm.parameters), mask).axes[0]
    assert len(_points(ax, "support-vectors")) == mask.sum()


def test_landing_space_bad_inputs(ds_a):
    with pytest.raises(TypeError, match="PiecewiseAffine"):
        plot_landing_space(ds_a, bl.Rigid.published("A"))
    with pytest.raises(NotFittedError):
        plot_landing_space(ds_a, bl.PiecewiseAffine())
    for support in ([0, 10_000], np.ones(3, dtype=bool)):  # an index beyond the bounces; a mask of another length
        with pytest.raises(DataError) as e:
            plot_landing_space(ds_a, support=support)
        assert e.value.option == "support"
    with pytest.raises(bl.ParameterError) as e:  # not a 3-D axes
        plot_landing_space(ds_a, ax=plt.figure().add_subplot())
    assert e.value.parameter == "ax"
    with pytest.raises(DataError):
        plot_landing_space("not a campaign")


def test_landing_space_on_a_given_3d_axes(ds_a):
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    out = plot_landing_space(ds_a, bl.PiecewiseAffine.published("A"), ax=ax, title="mine")
    assert out is fig and ax.get_title() == "mine" and has_synthetic_note(fig)


def test_plane_polygon_clips_to_the_box():
    hexagon = plane_polygon([1.0, 1.0, 1.0], 1.5, [0, 0, 0], [1, 1, 1])
    assert hexagon.shape == (6, 3)
    np.testing.assert_allclose(hexagon.sum(axis=1), 1.5)
    assert (hexagon >= -1e-12).all() and (hexagon <= 1 + 1e-12).all()
    # consecutive corners are joined by box faces: each edge keeps one coordinate at 0 or 1
    for a, b in zip(hexagon, np.roll(hexagon, -1, axis=0), strict=True):
        assert any(np.isclose(a[k], b[k]) and (np.isclose(a[k], 0) or np.isclose(a[k], 1)) for k in range(3))
    box = plane_polygon([0.9, 0.7, 1.0], 600.0, [0, -1700, -450], [2300, -200, 1060])
    assert box is not None and np.allclose(box @ [0.9, 0.7, 1.0], 600.0)
    assert plane_polygon([1.0, 0.0, 0.0], 5.0, [0, 0, 0], [1, 1, 1]) is None


def test_default_view_never_sees_the_plane_edge_on():
    span, aspect = np.array([2200.0, 1500.0, 2300.0]), np.array([4.0, 4.0, 3.0])
    normal = np.array([0.269, 1.0, 1.0])
    elev, azim = _oblique_view(normal, span, aspect)
    e, a = np.deg2rad([elev, azim])
    eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    n = normal * span / aspect
    assert abs(eye @ n) / np.linalg.norm(n) > 0.15


def test_driver_landing_matches_the_paper():
    np.testing.assert_allclose(driver_landing(), [1063.0, -809.8, 219.3], atol=0.1)


# ------------------------------------------------------------------------------------ Fig. 6
def test_pi_widths_histograms(ds_a):
    fig = plot_pi_widths(ds_a, bins=20)
    assert len(fig.axes) == 3
    n = ds_a.sizes["bounce"]
    for ax, sym in zip(fig.axes, ("\\dot{x}", "\\dot{y}", "\\omega"), strict=True):
        assert "PI width" in ax.get_xlabel() and sym in ax.get_xlabel()
        for state, colour in (("landing", "tab:green"), ("liftoff", "tab:red")):
            bars = [p for p in ax.patches if p.get_gid() == f"hist-{state}"]
            assert len(bars) == 20 and sum(b.get_height() for b in bars) == n
            assert np.allclose(bars[0].get_facecolor()[:3], to_rgba(colour)[:3])
    # one panel's widths: 2 x half-width / mean |q| of that state
    w = 2 * ds_a["liftoff_pi"].values[:, 2] / np.abs(ds_a["liftoff"].values[:, 2]).mean()
    assert fig.axes[2].get_xlim()[1] >= w.max()


def test_pi_widths_needs_intervals(ds_a):
    with pytest.raises(DataError) as e:
        plot_pi_widths(ds_a.drop_vars(["landing_pi", "liftoff_pi"]))
    assert e.value.column == "landing_pi"


# ------------------------------------------------------------------------------------ Fig. 7
def test_tangential(ds_a):
    fig = plot_tangential(ds_a, near_zero=20.0)
    (ax,) = fig.axes
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    pts = np.vstack([_points(ax, "class-roll"), _points(ax, "class-slip")])
    assert len(pts) == len(p0)
    expected = np.column_stack([p0[:, 0] + p0[:, 2], pf[:, 0] + pf[:, 2]])
    np.testing.assert_allclose(np.sort(pts, axis=0), np.sort(expected, axis=0))
    zero = [ln for ln in ax.lines if ln.get_gid() == "zero-liftoff"]
    assert len(zero) == 1 and zero[0].get_linestyle() == "--" and list(zero[0].get_ydata()) == [0, 0]
    assert "v_{P,0}" in ax.get_xlabel() and "v_{P,F}" in ax.get_ylabel() and "[radii/s]" in ax.get_ylabel()
    assert [p for p in ax.patches if p.get_gid() == "near-zero"]
    with pytest.raises(bl.ParameterError) as e:
        plot_tangential(ds_a, near_zero=-1)
    assert e.value.parameter == "near_zero"


def test_tangential_on_a_given_axes(measured):
    fig, ax = plt.subplots()
    assert plot_tangential(measured, ax=ax) is fig
    assert "Campaign M" in ax.get_title() and not has_synthetic_note(fig)


# ------------------------------------------------------------------------------------ Fig. 8
def test_predictions_grid_markers_and_test_rings(ds_a):
    _train, test = bl.split_by_setting(ds_a, seed=0)
    laws = {"rigid": bl.Rigid.published("A"), "piecewise": bl.PiecewiseAffine.published("A")}
    fig = plot_predictions(ds_a, laws, test=test)
    assert len(fig.axes) == 6
    n = ds_a.sizes["bounce"]
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    for r, law in enumerate(laws.values()):
        dq = bl.delta_q(p0, pf, law.predict(p0))
        for k, (comp, unit) in enumerate((("\\dot{x}", "radii/s"), ("\\dot{y}", "radii/s"), ("\\omega", "rad/s"))):
            ax = fig.axes[3 * r + k]
            assert _n_class_points(ax) == n
            assert len(_points(ax, "test")) == test.sizes["bounce"]
            roll = next(col for col in ax.collections if col.get_gid() == "class-roll")
            slip = next(col for col in ax.collections if col.get_gid() == "class-slip")
            assert len(roll.get_paths()[0].vertices) != len(slip.get_paths()[0].vertices)  # triangle vs circle
            assert f"{comp}_F$" in ax.get_xlabel() and "observed" in ax.get_xlabel() and unit in ax.get_xlabel()
            assert "predicted" in ax.get_ylabel()
            (note,) = [t for t in ax.texts if t.get_gid() == "delta-q"]
            assert f"{dq[k]:.1%}" in note.get_text() and "test" in note.get_text()
            assert any(np.allclose(ln.get_xdata(), ln.get_ydata()) for ln in ax.lines)  # identity line
    assert has_synthetic_note(fig)


def test_predictions_adds_test_bounces_missing_from_data_and_accepts_masks(ds_a):
    train, test = bl.split_by_setting(ds_a, seed=0)
    fit = bl.fit(bl.Rigid, train, method="structured")
    fig = plot_predictions(train, [fit, bl.Rigid.published("A")], test=test)
    assert len(fig.axes) == 6
    assert fig.axes[0].get_title().startswith("Rigid:") and fig.axes[3].get_title().startswith("Rigid (2):")
    assert _n_class_points(fig.axes[0]) == ds_a.sizes["bounce"]
    assert len(_points(fig.axes[0], "test")) == test.sizes["bounce"]
    mask = np.zeros(ds_a.sizes["bounce"], dtype=bool)
    mask[:7] = True
    fig = plot_predictions(ds_a, bl.Rigid.published("A"), test=mask)
    assert len(fig.axes) == 3 and len(_points(fig.axes[0], "test")) == 7


def test_predictions_bad_inputs(ds_a):
    with pytest.raises(NotFittedError):
        plot_predictions(ds_a, {"unfitted": bl.Rigid()})
    with pytest.raises(TypeError, match="bounce laws"):
        plot_predictions(ds_a, ["Rigid"])
    with pytest.raises(bl.ParameterError) as e:  # no laws
        plot_predictions(ds_a, {})
    assert e.value.parameter == "laws"
    with pytest.raises(DataError) as e:  # not a boolean mask
        plot_predictions(ds_a, bl.Rigid.published("A"), test=np.arange(5))
    assert e.value.option == "test"


# ------------------------------------------------------------------------------------ Fig. 9
def test_repeatability_error_bars():
    rep = _rep(5)
    fig = plot_repeatability(rep)
    assert len(fig.axes) == 3
    for k, ax in enumerate(fig.axes):
        (container,) = ax.containers
        x, y = container.lines[0].get_data()
        np.testing.assert_allclose(x, rep["mean"].values[:, 0, k])
        np.testing.assert_allclose(y, rep["mean"].values[:, 1, k])
        assert len(container.lines[2]) == 2  # horizontal and vertical bars
        hbars = container.lines[2][0].get_segments()
        widths = np.array([s[1][0] - s[0][0] for s in hbars])
        np.testing.assert_allclose(widths, 2 * rep["half_width"].values[:, 0, k])
        sym = ("\\dot{x}", "\\dot{y}", "\\omega")[k]
        assert f"{sym}_0$" in ax.get_xlabel() and f"{sym}_F$" in ax.get_ylabel() and "mean" in ax.get_xlabel()
    assert "Campaign R" in fig._suptitle.get_text() and "95%" in fig._suptitle.get_text()
    assert not has_synthetic_note(fig)
    assert has_synthetic_note(plot_repeatability(_rep(3, data_kind="synthetic surrogate")))


def test_repeatability_from_half_width_only_and_bad_inputs():
    rep = _rep(3).drop_vars(["ci_low", "ci_high"])
    assert len(plot_repeatability(rep).axes) == 3
    with pytest.raises(DataError) as e:
        plot_repeatability(_rep(3).drop_vars("mean"))
    assert e.value.option == "rep" and "['mean']" in e.value.message  # the missing variable is named
    with pytest.raises(DataError):
        plot_repeatability(_rep(3).rename({"state": "when"}))
    with pytest.raises(DataError):
        plot_repeatability(np.zeros((3, 2, 3)))


def test_repeatability_from_a_campaign(ds_a):
    pytest.importorskip("bouncelab.analysis.repeats")
    fig = plot_repeatability(ds_a)
    n_settings = len(np.unique(ds_a["setting"].values))
    assert all(len(ax.containers[0].lines[0].get_xdata()) == n_settings for ax in fig.axes)
    assert "Campaign A" in fig._suptitle.get_text() and has_synthetic_note(fig)


# ----------------------------------------------------------------------------------- Fig. 10
def test_slices(ds_a):
    fig = plot_slices(ds_a)
    assert len(fig.axes) == 9
    n = ds_a.sizes["bounce"]
    syms = ("\\dot{x}", "\\dot{y}", "\\omega")
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    for i in range(3):
        for j in range(3):
            ax = fig.axes[3 * i + j]
            pts = np.vstack([_points(ax, "class-roll"), _points(ax, "class-slip")])
            assert len(pts) == n
            np.testing.assert_allclose(np.sort(pts[:, 0]), np.sort(p0[:, j]))
            np.testing.assert_allclose(np.sort(pts[:, 1]), np.sort(pf[:, i]))
            if i == 2:
                assert f"{syms[j]}_0$" in ax.get_xlabel()
            if j == 0:
                assert f"{syms[i]}_F$" in ax.get_ylabel()
    assert "[rad/s]" in fig.axes[8].get_xlabel() and "[rad/s]" in fig.axes[6].get_ylabel()


# ----------------------------------------------------------------------------------- common
ALL = {
    "landing": lambda d: plot_landing_space(d),
    "pi": lambda d: plot_pi_widths(d),
    "tangential": lambda d: plot_tangential(d),
    "predictions": lambda d: plot_predictions(d, bl.Rigid.published("A")),
    "slices": lambda d: plot_slices(d),
}


@pytest.mark.parametrize("name", list(ALL))
def test_synthetic_note_only_for_surrogate_data(name, ds_a, measured):
    fig = ALL[name](ds_a)
    assert isinstance(fig, Figure) and has_synthetic_note(fig)
    assert "Campaign A" in fig._suptitle.get_text()
    fig = ALL[name](measured)
    assert not has_synthetic_note(fig) and "Campaign M" in fig._suptitle.get_text()


def test_multi_panel_figures_draw_into_a_given_empty_figure(ds_a):
    fig = plt.figure(layout="constrained")
    assert plot_slices(ds_a, fig=fig) is fig and len(fig.axes) == 9
    with pytest.raises(bl.ParameterError) as e:  # not an empty figure
        plot_pi_widths(ds_a, fig=fig)
    assert e.value.parameter == "fig"
    with pytest.raises(TypeError, match="Figure"):
        plot_pi_widths(ds_a, fig="figure")


def test_save_figure(ds_a, tmp_path):
    fig = plot_tangential(ds_a)
    out = save_figure(fig, tmp_path / "sub" / "fig7.png", dpi=40)
    assert out.exists() and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(bl.ParameterError) as e:  # no suffix
        save_figure(fig, tmp_path / "nosuffix")
    assert (e.value.parameter, e.value.value) == ("path", str(tmp_path / "nosuffix"))


def test_missing_matplotlib_gives_install_hint(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=r"pip install bouncelab\[plot\]"):
        pyplot()


def _run(code: str, **env: str) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MPLBACKEND")}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env={**clean, **env},
                         timeout=60, check=True)
    return out.stdout.strip()


def test_import_is_lazy_and_headless_backend_is_agg():
    code = (
        "import sys, bouncelab as bl, bouncelab.plots as p\n"
        "print('matplotlib' in sys.modules)\n"
        "p.plot_slices(bl.load_campaign('B'))\n"
        "import matplotlib; print(matplotlib.get_backend().lower())"
    )
    assert _run(code).split() == ["False", "agg"]
    code = "import bouncelab.plots._common as c; c.pyplot(); import matplotlib; print(matplotlib.get_backend())"
    assert _run(code, MPLBACKEND="svg") == "svg"  # a backend the user chose is kept


def test_predictions_refuse_fitted_bounces_ringed_as_held_out(ds_a):
    """Held out must mean held out: a law fitted to a ringed bounce is refused (issue 8)."""
    train, test = bl.split_by_setting(ds_a, seed=0)
    with pytest.raises(DataError) as e:  # bounces ringed as held out were fitted
        plot_predictions(ds_a, {"Rigid": bl.fit(bl.Rigid, ds_a)}, test=test)
    assert e.value.option == "test"
    fig = plot_predictions(ds_a, {"Rigid": bl.fit(bl.Rigid, train, test=test)}, test=test)
    assert len(fig.axes) >= 3


@pytest.mark.slow
def test_reproduce_rings_only_bounces_its_laws_did_not_fit(tmp_path, monkeypatch):
    """bouncelab 0.1's Fig. 8 ringed "held-out" bounces under laws fitted to all bounces."""
    import bouncelab.plots as plots
    from bouncelab.cli.reproduce import reproduce

    seen = []
    real = plots.plot_predictions

    def spy(data, laws, test=None, **kwargs):
        seen.append((laws, test))
        return real(data, laws, test=test, **kwargs)

    monkeypatch.setattr(plots, "plot_predictions", spy)
    reproduce(campaigns=["A"], out=tmp_path / "rep", progress=False)
    (laws, test), = seen
    assert list(laws) == ["Rigid", "PennerVarying", "PennerFixed", "PiecewiseAffine"]
    ringed = {tuple(r) for r in np.column_stack([test.landing.values, test.liftoff.values])}
    for res in laws.values():
        fitted = {tuple(r) for r in np.column_stack(res.data["train"])}
        assert not fitted & ringed and res.n_test == len(ringed)


# ------------------------------------------------------------------------------------ units
R = 0.02135  # the default ball radius, m
RPM = 60.0 / (2.0 * np.pi)  # rpm per rad/s


def test_figure_units_presets_mappings_and_errors():
    from bouncelab.plots import FigureUnits, figure_units

    assert figure_units(None) == figure_units("scaled") == FigureUnits("radius/s", "rad/s")
    lab = figure_units("LAB")
    assert (lab.velocity, lab.spin) == ("m/s", "rpm")
    np.testing.assert_allclose(lab.factors, [R, R, RPM])
    np.testing.assert_allclose(figure_units({"velocity": "ft/s", "radius_m": 0.03}).factors,
                               [0.03 / 0.3048, 0.03 / 0.3048, 1.0])
    for bad, option in (("metric", "units"), ({"velocity": "knots"}, "velocity"), ({"spin": "m/s"}, "spin"),
                        ({"speed": "m/s"}, "units"), ({"radius_m": -1}, "radius_m"), (3, "units")):
        with pytest.raises(DataError) as e:
            figure_units(bad)
        assert e.value.option == option
    with pytest.raises(DataError) as e:  # unknown figure units
        plot_slices(bl.load_campaign("A"), units="metric")
    assert e.value.option == "units" and e.value.hints == (Hint("units", {"velocity": "m/s", "spin": "rpm"}),)


def test_slices_in_lab_units(ds_a):
    """Plotted values and labels in m/s and rpm; the classification (marker split) is unchanged."""
    scaled, lab = plot_slices(ds_a), plot_slices(ds_a, units={"velocity": "m/s", "spin": "rpm"})
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    factor = np.array([R, R, RPM])
    for i in range(3):
        for j in range(3):
            ax, ax0 = lab.axes[3 * i + j], scaled.axes[3 * i + j]
            for cls in ("class-roll", "class-slip"):
                assert len(_points(ax, cls)) == len(_points(ax0, cls))
            pts = np.vstack([_points(ax, "class-roll"), _points(ax, "class-slip")])
            np.testing.assert_allclose(np.sort(pts[:, 0]), np.sort(p0[:, j] * factor[j]))
            np.testing.assert_allclose(np.sort(pts[:, 1]), np.sort(pf[:, i] * factor[i]))
    assert lab.axes[6].get_xlabel().endswith("[m/s]") and lab.axes[8].get_xlabel().endswith("[rpm]")
    assert lab.axes[0].get_ylabel().endswith("[m/s]") and lab.axes[6].get_ylabel().endswith("[rpm]")
    assert "radii" not in " ".join(ax.get_xlabel() + ax.get_ylabel() for ax in lab.axes)


def test_tangential_in_physical_units(ds_a):
    """v_P = xdot + R omega in m/s; near_zero is in the figure's unit."""
    fig = plot_tangential(ds_a, near_zero=0.5, units="si")
    (ax,) = fig.axes
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    pts = np.vstack([_points(ax, "class-roll"), _points(ax, "class-slip")])
    expected = R * np.column_stack([p0[:, 0] + p0[:, 2], pf[:, 0] + pf[:, 2]])
    np.testing.assert_allclose(np.sort(pts, axis=0), np.sort(expected, axis=0))
    assert ax.get_xlabel().endswith("[m/s]") and "R\\omega" in ax.get_ylabel()
    same = plot_tangential(ds_a, near_zero=0.5 / R).axes[0]  # the same tolerance in radii/s
    assert len(_points(ax, "class-roll")) == len(_points(same, "class-roll"))
    band = next(p for p in ax.patches if p.get_gid() == "near-zero")
    assert band.get_extents() is not None


def test_predictions_in_physical_units_keep_delta_q(ds_a):
    law = bl.Rigid.published("A")
    fig = plot_predictions(ds_a, law, units="imperial")
    p0, pf = ds_a["landing"].values, ds_a["liftoff"].values
    pred = law.predict(p0)
    dq = bl.delta_q(p0, pf, pred)
    mph = R / (1609.344 / 3600.0)
    for k, ax in enumerate(fig.axes):
        factor = (mph, mph, RPM)[k]
        pts = np.vstack([_points(ax, "class-roll"), _points(ax, "class-slip")])
        np.testing.assert_allclose(np.sort(pts[:, 0]), np.sort(pf[:, k] * factor))
        np.testing.assert_allclose(np.sort(pts[:, 1]), np.sort(pred[:, k] * factor))
        assert ax.get_xlabel().endswith("[mph]" if k < 2 else "[rpm]")
        (note,) = [t for t in ax.texts if t.get_gid() == "delta-q"]
        assert f"{dq[k]:.1%}" in note.get_text()  # errors are those of the scaled data


def test_repeatability_in_physical_units():
    rep = _rep(4)
    fig = plot_repeatability(rep, units="lab")
    for k, ax in enumerate(fig.axes):
        factor = (R, R, RPM)[k]
        (container,) = ax.containers
        x, y = container.lines[0].get_data()
        np.testing.assert_allclose(x, rep["mean"].values[:, 0, k] * factor)
        np.testing.assert_allclose(y, rep["mean"].values[:, 1, k] * factor)
        widths = np.array([s[1][0] - s[0][0] for s in container.lines[2][0].get_segments()])
        np.testing.assert_allclose(widths, 2 * rep["half_width"].values[:, 0, k] * factor)
        assert ax.get_xlabel().endswith("[m/s]" if k < 2 else "[rpm]")


def test_landing_space_in_physical_units(ds_a):
    law = bl.PiecewiseAffine.published("A")
    fig = plot_landing_space(ds_a, law, units="lab")
    (ax,) = fig.axes
    factor = np.array([R, R, RPM])
    roll = next(col for col in ax.collections if col.get_gid() == "class-roll")
    xs, ys, zs = (np.asarray(v) for v in roll._offsets3d)
    classes = bl.classify_slip_roll(ds_a["landing"], ds_a["liftoff"])
    np.testing.assert_allclose(np.column_stack([xs, ys, zs]), ds_a["landing"].values[classes == "roll"] * factor)
    driver = next(col for col in ax.collections if col.get_gid() == "driver-landing")
    np.testing.assert_allclose(np.ravel(driver._offsets3d), driver_landing() * factor)
    assert ax.get_xlabel().endswith("[m/s]") and ax.get_zlabel().endswith("[rpm]")
    # The plane's equation is given in the figure's units: a' = a * s_omega / s_x.
    a, b, off = law.printed_plane()
    text = next(t.get_label() for t in fig.legends[0].get_patches() if "plane" in t.get_label())
    assert f"{a * RPM / R:.3g}" in text and f"{b * RPM / R:.3g}" in text and f"{off * RPM:.3g}" in text
