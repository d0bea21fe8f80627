"""Project files: licence, citation, typing marker, and that the marker is installed with the package."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

import bouncelab

tomllib = pytest.importorskip("tomllib")  # Python 3.11+
ROOT = Path(__file__).resolve().parents[1]


def test_license_matches_pyproject():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert meta["license"] == {"text": "MIT"}
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_citation_names_software_and_reference_paper():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    assert cff["cff-version"] == "1.2.0" and cff["license"] == "MIT"
    assert cff["version"] == bouncelab.__version__
    (paper,) = cff["references"]
    assert paper["title"] == "Measurements and linearized models for golf ball bounce"
    assert [a["family-names"] for a in paper["authors"]] == ["Biber", "Jones", "Champneys", "Green", "Szalai"]


def test_py_typed_is_package_data():
    assert (Path(bouncelab.__file__).parent / "py.typed").is_file()
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]
    assert "py.typed" in data["bouncelab"]


def test_changelog_has_unreleased_section():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert "## Unreleased" in text and "### Command line and reports" in text


@pytest.mark.slow
def test_build_installs_py_typed(tmp_path):
    """setuptools' build (what a wheel holds) carries py.typed and the embedded campaigns."""
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(ROOT / "bouncelab", src / "bouncelab", ignore=shutil.ignore_patterns("__pycache__"))
    out = tmp_path / "build"
    subprocess.run([sys.executable, "-c", "from setuptools import setup; setup()", "-q", "build_py", "--build-lib",
                    str(out)], cwd=src, check=True, capture_output=True)
    assert (out / "bouncelab" / "py.typed").is_file()
    assert (out / "bouncelab" / "data" / "files" / "campaign_A.nc").is_file()
