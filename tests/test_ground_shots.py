"""The reference-shot suite: regenerated, it matches the checked-in table (issue 25, item 3).

A failure here means a law, a surface or the ground model changed the outcomes: if the change is
intended, regenerate with ``python -m bouncelab.ground.shots --write docs`` and review the diff.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from bouncelab.ground import PRESET_NAMES
from bouncelab.ground.shots import CSV_NAME, SHOTS, TOLERANCE, landings, main, markdown, reference_table, write

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_the_reference_shots_match_the_checked_in_table():
    stored = pd.read_csv(DOCS / CSV_NAME)
    fresh = reference_table()
    assert list(fresh.columns) == list(stored.columns)
    assert list(fresh["surface"]) == list(stored["surface"]) and list(fresh["shot"]) == list(stored["shot"])
    for col in ("bounces", "into_ground"):
        np.testing.assert_array_equal(fresh[col], stored[col], err_msg=col)
    numbers = [c for c in fresh.columns if c not in ("surface", "shot", "bounces", "into_ground")]
    for col in numbers:
        np.testing.assert_allclose(fresh[col], stored[col], err_msg=col, **TOLERANCE)


def test_the_suite_covers_every_preset_and_the_papers_driver_landing():
    stored = pd.read_csv(DOCS / CSV_NAME)
    assert set(stored["surface"]) == set(PRESET_NAMES) and len(stored) == len(PRESET_NAMES) * len(SHOTS)
    v, w = landings()
    # 93.6 ft/s at 37.3 degrees with 34.9 rev/s of backspin: the paper's scaled [1063, -809.8, 219.3]
    np.testing.assert_allclose([v[0, 0] / 0.02135, v[0, 2] / 0.02135, -w[0, 1] * 2 * np.pi / 60 / 1],
                               [1063.0, -809.8, 219.3], atol=0.05)
    # every landing inside the paper's Table 1 ranges of both campaigns
    speed = np.linalg.norm(v, axis=1)
    angle = np.degrees(np.arctan2(-v[:, 2], v[:, 0]))
    assert ((speed >= 6.35) & (speed <= 38.7)).all() and ((angle >= 18.3) & (angle <= 76.4)).all()
    assert ((-w[:, 1] >= -3750) & (-w[:, 1] <= 9100)).all()


def test_the_markdown_table_in_the_docs_is_the_checked_in_one():
    stored = pd.read_csv(DOCS / CSV_NAME)
    text = (DOCS / "snippets" / "ground_reference_shots.md").read_text()
    assert markdown(stored) in text


def test_one_command_writes_the_table_the_markdown_and_the_plot(tmp_path, capsys):
    paths = write(tmp_path)
    assert [p.relative_to(tmp_path).as_posix() for p in paths] == [
        CSV_NAME, "snippets/ground_reference_shots.md", "img/ground_reference_paths.png"]
    assert pd.read_csv(paths[0]).shape == (len(PRESET_NAMES) * len(SHOTS), 11)
    assert paths[2].stat().st_size > 10_000
    assert main([]) == 0
    assert "green-fast" in capsys.readouterr().out
