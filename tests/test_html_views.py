"""Issue 32, item 2: results that show themselves in a notebook (``_repr_html_``).

A law, a FitResult, a Comparison, an Assessment, a Posterior, a Surface, a RunResult and a SurfaceFit each have
an HTML view: valid HTML (the tags balance), every text from data escaped, the numbers the object holds, figures
inline as PNGs with matplotlib and a line saying why not without it. And the Done-when of the issue:
``bouncelab.reproduce(out=...)`` works from Python and its result, a law, a FitResult and a Comparison show
themselves.
"""

from __future__ import annotations

import base64
import builtins
import dataclasses
import re
import sys
import warnings
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import bouncelab as bl
from bouncelab.core._html import escape
from bouncelab.core._inline import NO_MATPLOTLIB
from bouncelab.core.errors import BouncelabWarning
from bouncelab.ground import Surface, fit_surface, predict_shots, preset, run
from bouncelab.laws.provenance import Provenance

REPO = Path(__file__).resolve().parents[1]
HOSTILE = "<script>alert('x')</script>"
VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


class _Balance(HTMLParser):
    """Every tag closed in order (void elements excepted); what is inside <style> is not markup."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.tags: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.append(tag)

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'}")
        else:
            self.stack.pop()


def check_html(text: str) -> list[str]:
    """Parse ``text``; fail unless its tags balance and it is one scoped fragment. Returns the tags seen."""
    assert isinstance(text, str) and text.startswith("<div class='bouncelab'>") and text.endswith("</div>")
    parser = _Balance()
    parser.feed(text)
    parser.close()
    assert not parser.errors and not parser.stack, (parser.errors, parser.stack)
    assert "script" not in parser.tags  # nothing from data became markup
    return parser.tags


def pngs(text: str) -> list[bytes]:
    return [base64.b64decode(m) for m in re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", text)]


@pytest.fixture
def no_matplotlib(monkeypatch):
    """``import matplotlib`` (and any of its modules) fails, as on a machine without the plot extra."""
    real = builtins.__import__

    def fake(name, *args, **kwargs):
        if name == "matplotlib" or name.startswith("matplotlib."):
            raise ImportError(f"No module named {name!r}")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", fake)


# ------------------------------------------------------------------------------------------------ objects
@pytest.fixture(scope="module")
def data():
    return bl.load_campaign("A").isel(bounce=slice(0, 150))


@pytest.fixture(scope="module")
def fitted(data):
    return bl.fit(bl.Rigid(), data.isel(bounce=slice(30, None)), test=data.isel(bounce=slice(0, 30)))


@pytest.fixture(scope="module")
def comparison(data):
    return bl.compare(data, ["Rigid", "PennerFixed"], k=3)


@pytest.fixture(scope="module")
def assessment(data):
    return bl.assess(bl.Rigid, data, k=3, n_bootstrap=8, starts=2, profile_points=5, local_points=1)


@pytest.fixture(scope="module")
def posterior(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BouncelabWarning)  # a short chain (not converged): a view, not an estimate
        return bl.calibrate(bl.Rigid, data.isel(bounce=slice(0, 80)), vary=["r"], steps=200, seed=0)


@pytest.fixture(scope="module")
def runs():
    a = np.radians(np.linspace(30.0, 50.0, 4))
    v = np.column_stack([25.0 * np.cos(a), np.zeros(4), -25.0 * np.sin(a)])
    w = np.column_stack([np.zeros(4), -np.linspace(1000.0, 4000.0, 4), np.zeros(4)])
    si = {"velocity": "m/s", "spin": "rpm"}
    many = np.repeat(v, 20, axis=0) * np.random.default_rng(0).normal(1.0, 0.03, (80, 3))
    return run(v, w, preset("turf-A"), units=si), run(many, np.repeat(w, 20, axis=0), preset("turf-A"), units=si)


@pytest.fixture(scope="module")
def surface_fit():
    rng = np.random.default_rng(1)
    n = 40
    var = {"landing_speed": (rng.normal(27.6, 2.0, n), "m/s"), "landing_angle": (rng.normal(37.7, 3.0, n), "deg"),
           "spin": (rng.normal(2440.0, 500.0, n), "rpm"), "carry": (rng.normal(230.0, 20.0, n), "m")}
    shots = xr.Dataset({k: ("shot", x, {"units": u}) for k, (x, u) in var.items()}, coords={"shot": np.arange(n)},
                       attrs={"spin_at": "landing"})
    rest = predict_shots(shots, Surface("hidden", bl.Rigid(r=0.3, mu=0.6), sliding_friction=0.35, stimp_m=1.2))
    shots["total"] = ("shot", rest["total"].to_numpy() + rng.normal(0.0, 1.0, n), {"units": "m"})
    return fit_surface(shots, law="Rigid", seed=0, folds=2)


@pytest.fixture
def views(fitted, comparison, assessment, posterior, runs, surface_fit):
    """Every kind of object with a view, by name."""
    return {"law": bl.Rigid.published("A"), "fitted law": fitted.model, "FitResult": fitted,
            "Comparison": comparison, "Assessment": assessment, "Posterior": posterior,
            "Surface": preset("green-fast"), "RunResult": runs[0], "RunResult of many": runs[1],
            "SurfaceFit": surface_fit}


# ------------------------------------------------------------------------------------------------ every view
NAMES = ["law", "fitted law", "FitResult", "Comparison", "Assessment", "Posterior", "Surface", "RunResult",
         "RunResult of many", "SurfaceFit"]
WITH_FIGURES = {"FitResult", "Comparison", "Assessment", "Posterior", "RunResult", "RunResult of many", "SurfaceFit"}


@pytest.mark.parametrize("name", NAMES)
def test_each_view_is_valid_html_with_its_tables_and_figures(views, name):
    html = views[name]._repr_html_()
    tags = check_html(html)
    assert "table" in tags and "style" in tags
    shown = pngs(html)
    if name in WITH_FIGURES:
        assert len(shown) == 1 and shown[0].startswith(b"\x89PNG\r\n\x1a\n") and len(shown[0]) < 200_000
        assert escape(NO_MATPLOTLIB) not in html
    else:
        assert not shown


@pytest.mark.parametrize("name", NAMES)
def test_each_view_works_without_matplotlib(views, name, no_matplotlib):
    with pytest.raises(ImportError):
        import matplotlib.figure  # noqa: F401  (the fixture works)
    html = views[name]._repr_html_()
    check_html(html)
    assert not pngs(html) and "<img" not in html
    assert (escape(NO_MATPLOTLIB) in html) == (name in WITH_FIGURES)


def test_the_views_draw_without_pyplot_and_leave_no_figure_open(views):
    plt = pytest.importorskip("matplotlib.pyplot")
    before = plt.get_fignums()
    for name in WITH_FIGURES:
        views[name]._repr_html_()
    assert plt.get_fignums() == before


# ------------------------------------------------------------------------------------------------ a law
def test_a_law_shows_its_equation_parameters_and_where_they_come_from():
    law = bl.Rigid.published("A")
    html = law._repr_html_()
    assert "<h3>Rigid</h3>" in html and "Instantaneous rigid bounce with restitution r and Coulomb friction mu" in html
    assert "ẏ_F = -r ẏ_0" in html and "ω_F = ω_0 + 5/2 k ẏ_0" in html and "\\dot" not in html  # Unicode, no TeX
    assert "<td>r</td><td>0.544</td>" in html and "<td>mu</td><td>0.997</td>" in html
    assert "<td>[0, 1.5]</td>" in html and "Coulomb friction coefficient" in html  # bounds and meaning
    assert "<th>identifiability</th>" not in html and "bouncelab.assess" in html  # not known from a law alone
    assert "slip_forward, roll, slip_backward" in html and "Provenance: none recorded" in html
    unfitted = bl.PennerVarying()._repr_html_()
    assert "unfitted" in unfitted and "<td>k_p</td><td>–</td>" in unfitted and "s/radius" in unfitted
    piecewise = bl.PiecewiseAffine.published("A")._repr_html_()
    assert "plane (paper&#x27;s form): 0.891·xdot0 + 0.763·ydot0 + omega0 = 600" in piecewise
    assert "<td>normal</td><td>[0.891, 0.763, 1]</td>" in piecewise
    assert re.search(r"<td>A1</td><td>\[\[0.536, -0.004, -0.205\], .*?\]\]</td><td></td><td>\[-3, 3\]</td>", piecewise)


def test_a_law_of_ones_own_shows_its_equation_attribute_and_escapes_everything():
    class Hostile(bl.BounceModel):
        """A law <script>alert(1)</script> named badly.

        .. math::

            \\dot y_F = -e \\dot y_0 < 0
        """

        e = bl.Parameter(bounds=(0.0, 1.0), physical=(0.0, 1.0), unit="<i>", doc="restitution <b>bold</b>")
        regimes = ("<bounce>",)

        def _predict(self, p, e):
            return p * np.array([1.0, -e, 1.0])

        def _regime(self, p, e):
            return np.zeros(len(p), dtype=np.int8)

    prov = Provenance(n_bounces=3, data_kind="synthetic surrogate", campaign=HOSTILE, source=HOSTILE,
                      landing_ranges={"speed": (100.0, 200.0)})
    law = Hostile(e=0.25)._with_provenance(prov)
    html = law._repr_html_()
    check_html(html)
    assert "<script>" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    assert "&lt;i&gt;" in html and "restitution &lt;b&gt;bold&lt;/b&gt;" in html and "&lt;bounce&gt;" in html
    assert "ẏ_F = -e ẏ_0 &lt; 0" in html  # from the docstring's math block
    assert "class='warning'" in html and "synthetic bounces" in html  # what it was fitted to, said first
    assert "<td>speed</td><td>100</td><td>200</td>" in html
    Hostile.equation = "pF = [xdot0, -e ydot0, omega0]"
    try:
        assert "pF = [xdot0, -e ydot0, omega0]" in Hostile(e=0.25)._repr_html_()
    finally:
        del Hostile.equation


# ------------------------------------------------------------------------------------------------ fitting
def test_a_fit_result_shows_what_the_fit_did(fitted):
    html = fitted._repr_html_()
    p = fitted.params
    for name in ("r", "mu"):
        assert f"<td>{name}</td><td>{p[name].value:.6g}</td>" in html
    assert f"{fitted.n_evaluations} ({fitted.n_global} global + {fitted.n_local} local)" in html
    assert f"<dd>{fitted.stop_reason}</dd>" in html and f"<dd>{fitted.algorithm}</dd>" in html
    errors = fitted.errors
    for (which, label) in (("train", "fitted"), ("test", "held out")):
        for subset in errors.loc[which].index:
            d = 100 * errors.loc[(which, subset), "delta"]
            assert f"<td>{label}, {subset}</td><td>{int(errors.loc[(which, subset), 'n'])}</td><td>{d:.4g}</td>" in html
    assert "class='warning'" in html and "synthetic bounces" in html  # the surrogate is synthetic, said first
    with_stderr = dataclasses.replace(fitted, stderr={"r": 0.0123})
    assert "<th>uncertainty</th>" in with_stderr._repr_html_() and "<td>0.0123</td>" in with_stderr._repr_html_()
    hostile = dataclasses.replace(fitted, notes=[HOSTILE], stop_reason=HOSTILE,
                                  model=fitted.model._with_provenance(Provenance(n_bounces=1, source=HOSTILE)))
    html = hostile._repr_html_()
    check_html(html)
    assert "<script>" not in html and html.count("&lt;script&gt;") >= 2


def test_a_comparison_shows_its_tables_and_escapes_its_notes(comparison):
    html = comparison._repr_html_()
    t = comparison.table
    for law in ("Rigid", "PennerFixed"):
        assert f"{100 * t.loc[law, 'train_delta']:.3g} %" in html  # the paper's layout, as to_markdown prints it
        assert f"{100 * t.loc[law, 'heldout_delta']:.3g} %" in html
    assert "<th>Rigid</th><th>PennerFixed</th>" in html and "These bounces are synthetic" in html
    html = dataclasses.replace(comparison, notes=[HOSTILE], skipped={"<b>Law</b>": HOSTILE})._repr_html_()
    check_html(html)
    assert "<script>" not in html and "&lt;b&gt;Law&lt;/b&gt; was not fitted" in html


def test_an_assessment_shows_identifiability(assessment):
    html = assessment._repr_html_()
    assert "<th>identifiability</th>" in html
    for name, verdict in assessment.verdicts.items():
        est = assessment.parameters.loc[name, "estimate"]
        assert f"<td>{name}</td><td>{est:.4g}" in html and f"<b>{name}</b> {verdict}:" in html
    held = 100 * assessment.scores.loc["held-out", "delta"]
    assert f"<td>held-out</td><td>{int(assessment.scores.loc['held-out', 'n'])}</td><td>{held:.4g}</td>" in html
    html = dataclasses.replace(assessment, notes=[HOSTILE], law=HOSTILE)._repr_html_()
    check_html(html)
    assert "<script>" not in html


def test_a_posterior_shows_its_summary_and_says_it_did_not_converge(posterior):
    html = posterior._repr_html_()
    summary = posterior.summary()
    assert f"<td>r</td><td>{summary.loc['r', 'median']:.4g}</td>" in html
    assert "scale_r" in html and "r (logit-normal within [0, 1])" in html
    assert posterior.converged is False and "NOT converged" in html  # 200 steps: a demonstration
    html = dataclasses.replace(posterior, notes=[HOSTILE])._repr_html_()
    check_html(html)
    assert "<script>" not in html


def test_a_posterior_missing_fields_still_shows_what_it_has(posterior):
    """The view reads a Posterior through fallbacks (its fields may be renamed): a missing one costs a row."""

    class Bare:
        law = posterior.law
        samples = posterior.samples
        notes = ("kept",)

        def summary(self):
            raise AttributeError("no summary here")

    from bouncelab.fitting._display import posterior_html

    html = posterior_html(Bare())
    check_html(html)
    assert "Rigid" in html and "kept" in html and "NOT converged" in html and len(pngs(html)) <= 1


# ------------------------------------------------------------------------------------------------ ground
def test_a_surface_shows_its_numbers_provenance_and_law():
    s = preset("green-fast")
    html = s._repr_html_()
    assert f"{s.stimp_m:.4g} m ({s.stimp_ft:.3g} ft)" in html and "Not a measurement of any real green" in html
    assert "<h4>PennerVarying</h4>" in html and "<td>k_p</td><td>0.0002973</td>" in html
    hostile = Surface(HOSTILE, bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_m=3.0, description=HOSTILE)
    html = hostile._repr_html_()
    check_html(html)
    assert "<script>" not in html and html.count("&lt;script&gt;") == 2


def test_a_run_shows_each_shot_or_the_range_of_many(runs):
    few, many = runs
    html = few._repr_html_()
    t = few.totals
    assert "<th>total_run (m)</th>" in html and "<th>liftoff_backspin (rpm)</th>" in html
    for i in range(len(few)):
        assert f"<td>{i}</td><td>{t['liftoff_speed'][i]:.4g}</td>" in html
        assert f"<td>{t['total_run'][i]:.4g}</td>" in html
    assert "side view" in html
    html = many._repr_html_()
    assert "The 80 shots" in html and f"<td>max</td><td>{many.totals['liftoff_speed'].max():.4g}</td>" in html
    assert "plan view" in html
    hostile = run([10.0, 0.0, -10.0], [0.0, -100.0, 0.0],
                  Surface(HOSTILE, bl.Rigid(r=0.3, mu=0.5), sliding_friction=0.4, stimp_m=3.0))
    html = hostile._repr_html_()
    check_html(html)
    assert "<script>" not in html


def test_a_surface_fit_shows_which_parameters_the_shots_determine(surface_fit):
    html = surface_fit._repr_html_()
    assert f"{surface_fit.mean_error:.3f} m" in html and "<th>identifiability</th>" in html
    for name, determined in surface_fit.identifiable.items():
        word = "determined" if determined else "NOT determined by these shots"
        assert f"<td>{name}</td><td>{surface_fit.parameters.loc[name, 'value']:.5g}</td>" in html
        assert re.search(f"<td>{name}</td>(<td>[^<]*</td>){{4}}<td>{word}</td>", html), name
    e = surface_fit.errors.loc["all"]
    assert f"<td>all</td><td>{int(e['shots'])}</td><td>{e['observed_median_roll']:.4g}</td>" in html
    html = dataclasses.replace(surface_fit, notes=[HOSTILE], law=HOSTILE)._repr_html_()
    check_html(html)
    assert "<script>" not in html


# ------------------------------------------------------------------------------------------------ layers
def test_each_display_module_sits_in_its_layer():
    sys.path.insert(0, str(REPO / "tests"))
    from test_layers import import_graph

    edges = import_graph()
    allowed = {"bouncelab.laws._display": ("core", "laws"), "bouncelab.fitting._display": ("core", "laws", "metrics",
                                                                                           "fitting"),
               "bouncelab.ground._display": ("core", "laws", "fitting", "ground")}
    for module, layers in allowed.items():
        assert edges[module], module
        assert all(t.split(".")[1] in layers for t in edges[module]), (module, edges[module])


# ------------------------------------------------------------------------------------------------ Done when
def test_reproduce_from_python_and_its_result_a_law_a_fit_and_a_comparison_show_themselves(tmp_path, monkeypatch):
    """Issue 32's Done-when: ``bouncelab.reproduce(out=...)`` works from Python and its result, a law, a FitResult
    and a Comparison each have an HTML view."""
    from bouncelab.report import steps as rs

    monkeypatch.setattr(rs, "BEYOND_PAPER_LAWS", ())
    monkeypatch.setattr(rs, "ASSESS_OPTIONS", {"k": 3, "starts": 2, "profile_points": 5, "local_points": 1})
    part = bl.save_campaign(bl.load_campaign("A").isel(bounce=slice(0, 120)), tmp_path / "part.nc")
    report = bl.reproduce(data=[part], out=tmp_path / "report", progress=False, figures=False,
                          law_set=["Rigid", "PennerFixed"], bootstrap=0)
    assert report.index == tmp_path / "report" / "index.html" and report.index.is_file()
    check_html(report._repr_html_())
    cmp = report.sections["part"].comparison
    res = cmp.results["Rigid"]
    for obj in (res.model, res, cmp):
        check_html(obj._repr_html_())
    assert f"<td>r</td><td>{res.model.r:.6g}</td>" in res.model._repr_html_()
    assert f"<td>r</td><td>{res.model.r:.6g}</td>" in res._repr_html_()
    assert "<th>Rigid</th><th>PennerFixed</th>" in cmp._repr_html_()
