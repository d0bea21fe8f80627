"""The documentation builds offline with ``mkdocs build --strict`` and its API pages list the key names."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SNIPPETS = DOCS / "snippets"

# API page -> identifiers (mkdocstrings anchors) that must be on it.
API_NAMES = {
    "api/laws": ["bouncelab.laws.BounceModel", "bouncelab.laws.Rigid", "bouncelab.laws.PennerFixed",
                 "bouncelab.laws.PennerVarying", "bouncelab.laws.PiecewiseAffine",
                 "bouncelab.laws.TangentialRestitution", "bouncelab.laws.load_law", "bouncelab.laws.Parameter",
                 "bouncelab.laws.CompiledLaw", "bouncelab.laws.fit_method", "bouncelab.laws.FitProblem",
                 "bouncelab.laws.FitOutcome", "bouncelab.laws.Parameters", "bouncelab.laws.plane_fitting.fit_svm",
                 "bouncelab.laws.nonphysical.LiftoffFlags", "bouncelab.estimators.BounceRegressor"],
    "api/fitting": ["bouncelab.fitting.fitter.fit", "bouncelab.fitting.FitResult",
                    "bouncelab.fitting.comparison.compare",
                    "bouncelab.fitting.Comparison", "bouncelab.fitting.split_by_setting",
                    "bouncelab.fitting.cross_validate", "bouncelab.fitting.map_tasks",
                    "bouncelab.fitting.sweep.sweep"],
    "api/data": ["bouncelab.data.io.load_campaign", "bouncelab.data.io.save_campaign",
                 "bouncelab.core.units.to_scaled", "bouncelab.core.units.landing_from_speed_angle_spin",
                 "bouncelab.data.campaign.make_campaign", "bouncelab.simulation.surrogate.generate_surrogate",
                 "bouncelab.core.published", "bouncelab.core.errors.DataError",
                 "bouncelab.data.settings.infer_settings"],
    "api/metrics": ["bouncelab.metrics.delta", "bouncelab.metrics.delta_q", "bouncelab.metrics.error_table",
                    "bouncelab.metrics.score"],
    "api/analysis": ["bouncelab.analysis.measurement.measure_bounce",
                     "bouncelab.analysis.measurement.interval_coverage",
                     "bouncelab.analysis.repeats.repeatability",
                     "bouncelab.analysis.contact_velocity.tangential_summary",
                     "bouncelab.analysis.trajectories.simulate_tracked_bounce"],
    "api/plots": ["bouncelab.plots.plot_tangential", "bouncelab.plots.plot_landing_space",
                  "bouncelab.plots.plot_predictions", "bouncelab.plots.save_figure"],
    "api/cli": ["bouncelab.cli.main.main", "bouncelab.report.pipeline.reproduce", "bouncelab.report.model.Report"],
    "api": ["bouncelab"],
}


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install -e '.[docs]')")
    pytest.importorskip("mkdocstrings", reason="mkdocstrings is not installed (pip install -e '.[docs]')")
    out = tmp_path_factory.mktemp("site")
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"), "-d", str(out)],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stdout}\n{proc.stderr}"
    return out


@pytest.mark.slow  # mkdocs build: about 5 s
def test_build_is_strict_clean(site: Path) -> None:
    for page in ("", "quickstart", "conventions", "laws", "fitting", "data", "analysis", "cli", "examples", "api",
                 "simulators", "sklearn", "cluster"):
        assert (site / page / "index.html").is_file(), f"page {page or 'index'} was not built"


@pytest.mark.slow  # mkdocs build: about 5 s
@pytest.mark.parametrize("page", sorted(API_NAMES))
def test_api_pages_list_key_names(site: Path, page: str) -> None:
    html = (site / page / "index.html").read_text(encoding="utf-8")
    ids = set(re.findall(r'id="([^"]+)"', html))
    missing = [name for name in API_NAMES[page] if name not in ids]
    assert not missing, f"{page}: not documented: {missing}"


@pytest.mark.slow  # mkdocs build: about 5 s
def test_no_network_assets(site: Path) -> None:
    for path in site.rglob("*.html"):
        text = path.read_text(encoding="utf-8")
        remote = re.findall(r'<(?:script|link)[^>]*(?:src|href)="(https?://[^"]+)"', text)
        assert not remote, f"{path.relative_to(site)} loads {remote}: the docs must work offline"


def test_snippet_outputs_are_present_and_included() -> None:
    sources = {p.stem for p in SNIPPETS.iterdir() if p.suffix in (".py", ".sh") and p.name != "run.py"}
    outputs = {p.stem for p in SNIPPETS.glob("*.out")}
    assert sources - outputs == set(), "snippets never run: python docs/snippets/run.py"
    assert outputs - sources == set(), "outputs without a snippet"
    pages = "\n".join(p.read_text(encoding="utf-8") for p in DOCS.rglob("*.md"))
    included = set(re.findall(r'--8<-- "([^"]+)"', pages))
    unused = sorted(s for s in sources if not ({f"{s}.py", f"{s}.sh", f"{s}.out"} & included))
    assert not unused, f"snippets not used on any page: {unused}"


def test_figures_are_small() -> None:
    for png in (DOCS / "img").glob("*.png"):
        assert png.stat().st_size < 200_000, f"{png.name} is {png.stat().st_size} bytes; keep figures < 200 kB"
