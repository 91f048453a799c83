"""Captures made worse (:mod:`simgrasp.evaluation.capture_degradations`) and
``scripts/real_robustness.py``'s run on the real manifest (rows kept across a rerun)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from script_modules import load_script

from simgrasp.errors import SimgraspError
from simgrasp.evaluation.capture_degradations import DEGRADATIONS, degraded
from simgrasp.evaluation.sim_views import SimView, score_view


@pytest.fixture(scope="module")
def script() -> ModuleType:
    return load_script("real_robustness")


def test_each_degradation_does_what_it_says() -> None:
    """On 4,000 points of a sphere 0.5 m in front of the viewpoint: the subsamples keep a half
    and a quarter of the points, range noise moves points only along their rays (by about
    sigma), holes remove the points near three centers, the viewpoint moves by 10 cm."""
    rng = np.random.default_rng(0)
    directions = rng.normal(size=(4000, 3))
    points = np.array([0.0, 0.0, 0.5]) + 0.05 * directions / np.linalg.norm(
        directions, axis=1, keepdims=True
    )
    eye = np.zeros(3)

    def worse(kind: str) -> tuple[np.ndarray, np.ndarray]:
        return degraded(points, eye, kind, np.random.default_rng(1))

    assert len(worse("half")[0]) == 2000 and len(worse("quarter")[0]) == 1000
    noisy, _ = worse("noise2mm")
    moved = noisy - points
    rays = points / np.linalg.norm(points, axis=1, keepdims=True)
    along = np.einsum("ij,ij->i", moved, rays)
    assert np.allclose(moved, along[:, None] * rays) and 0.0015 < along.std() < 0.0025
    holed, _ = worse("holes")
    assert 3000 < len(holed) < 4000 and set(map(tuple, holed)) <= set(map(tuple, points))
    same, moved_eye = worse("viewpoint10cm")
    assert same is points and np.isclose(np.linalg.norm(moved_eye - eye), 0.1)
    assert worse("as captured")[0] is points
    with pytest.raises(ValueError, match="unknown degradation 'blur'"):
        worse("blur")


def test_a_simulated_view_is_scored_degraded() -> None:
    """A kinect view of the generated hammer scored with a quarter of its points: the row
    counts the points left; as captured it is the view's own row."""
    view = SimView("gen_hammer", "upright", 0.6, 45.0, "kinect")
    whole = score_view(view, "default", 0)
    quarter = score_view(view, "default", 0, degradation="quarter")
    assert quarter.points == whole.points // 4 and quarter.candidates > 0
    same = score_view(view, "default", 0, degradation="as captured")
    assert replace(same, detect_s=0.0) == replace(whole, detect_s=0.0)


def test_run_on_the_real_manifest_keeps_its_rows(
    script: ModuleType, real_dir: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """One seed over the manifest's clouds: a row per cloud and degradation, and a rerun
    measures nothing again and reads no cloud."""
    options = script.Options(real_dir=real_dir, seeds=1, out=tmp_path, sim=False)
    text = script.run(options)
    rows = (tmp_path / "rows.jsonl").read_text().splitlines()
    clouds = {json.loads(row)["cloud"] for row in rows}
    assert len(rows) == len(clouds) * len(DEGRADATIONS) and "gpd_table_mug" in clouds
    assert "| gpd_table_mug (holdout) |" in text

    def unread(cloud: object) -> None:
        raise AssertionError(f"{cloud} read again")

    monkeypatch.setattr(script, "load_real_cloud", unread)
    assert script.run(options) == text
    assert (tmp_path / "rows.jsonl").read_text().splitlines() == rows
    with pytest.raises(SimgraspError, match="body_wall"):  # one setting's rows a folder
        script.run(replace(options, body_wall=False))
    assert (tmp_path / "rows.jsonl").read_text().splitlines() == rows


def test_a_folder_of_rows_of_another_default_is_refused(
    script: ModuleType, real_dir: Path, tmp_path: Path
) -> None:
    """Rows scored by an earlier default (here: its classifier threshold recorded as 0.6)
    are not resumed under today's: the rerun refuses in one line naming the changed value,
    before anything is measured."""
    options = script.Options(real_dir=real_dir, seeds=1, out=tmp_path, sim=False)
    earlier = script.identity(options)
    earlier["default"]["single_view"]["classifier_threshold"] = 0.6
    (tmp_path / "run.json").write_text(json.dumps(earlier))
    (tmp_path / "rows.jsonl").write_text("")
    with pytest.raises(SimgraspError, match="classifier_threshold") as refused:
        script.run(options)
    assert "\n" not in str(refused.value)
    assert (tmp_path / "rows.jsonl").read_text() == ""
