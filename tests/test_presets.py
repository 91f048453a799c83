"""The detector presets registry: every preset builds, says what it is for and links a results
page that names it; the defaults built on presets are those presets; an unknown name or a
preset of another detector is one line; a registered preset is a ``--real-configs`` choice."""

from __future__ import annotations

import csv
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from simgrasp.autolabel.config import AutoLabelConfig
from simgrasp.cli import main
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.presets import (
    PRESETS,
    Preset,
    preset,
    preset_names,
    quadric_preset,
    single_view_preset,
)
from simgrasp.handles.single_view.detector import SingleViewConfig

from shapes import mug_like

RESULTS = Path(__file__).parents[1] / "docs" / "results"


def results_page(folder: str) -> str:
    """The text of a results folder's pages: its Markdown files, else its section of the
    results README (from its heading to the next)."""
    own = "\n".join(p.read_text(encoding="utf-8") for p in (RESULTS / folder).glob("*.md"))
    sections = (RESULTS / "README.md").read_text(encoding="utf-8").split("\n## ")
    return own + next((s for s in sections if s.startswith(f"`{folder}/`")), "")


@pytest.mark.parametrize("name", preset_names())
def test_every_preset_builds_and_links_a_results_page_that_names_it(name: str) -> None:
    entry = PRESETS[name]
    assert entry.name == name and entry.purpose and preset(name) == preset(name)
    assert (RESULTS / entry.results).is_dir(), entry.results
    assert name in results_page(entry.results)


def test_the_defaults_built_on_presets_are_those_presets() -> None:
    assert ChainConfig().detector.quadric == quadric_preset("two_scales")
    learned = single_view_preset()
    assert learned == preset("learned") and learned.classifier
    assert learned.fallback == quadric_preset("real_depth")
    noisy = quadric_preset("noisy_camera_cloud")
    assert SingleViewConfig().quadric == replace(noisy, fine_half_size=0.012)
    label = AutoLabelConfig().detector
    assert label == quadric_preset("two_scales", gripper_max_opening=0.08, min_relative_score=0)
    assert preset("default") == preset("multi_view") == QuadricDetectorConfig()


def test_an_unknown_or_mistyped_preset_is_one_line() -> None:
    with pytest.raises(SimgraspError, match="unknown detector preset 'learned_bars'; choose"):
        preset("learned_bars")
    with pytest.raises(SimgraspError, match="'learned' is no QuadricDetectorConfig"):
        quadric_preset("learned")
    with pytest.raises(SimgraspError, match="'two_scales' is no SingleViewConfig"):
        single_view_preset("two_scales")


def test_a_registered_preset_runs_in_detect_eval_real(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """One entry in the registry is all a new preset needs: ``--real-configs`` takes it and
    the run records its values."""
    coarse = Preset("coarse", lambda: QuadricDetectorConfig(voxel_size=0.005), "a test", "x")
    monkeypatch.setitem(PRESETS, "coarse", coarse)
    np.savetxt(tmp_path / "mug.xyz", mug_like(seed=0, density=1e6).points)
    box = {"type": "box", "center": [0.06, 0.0, 0.045], "half_extents": [0.03, 0.012, 0.04]}
    labels = {"objects": {"mug": {"whole_object": False, "regions": [box]}}}
    (tmp_path / "labels.json").write_text(json.dumps(labels))
    manifest = tmp_path / "manifest.toml"
    manifest.write_text(
        '[[cloud]]\nname = "mug"\ndataset = "synthetic"\nlabels = "labels.json"\n'
        f'viewpoint = [0.3, 0.0, 0.05]\npath = "{tmp_path}/mug.xyz"\nsplit = "tune"\n'
    )
    out = tmp_path / "out"
    argv = ["detect-eval", "--real", str(manifest), "--seeds", "1", "--out", str(out)]
    assert main([*argv, "--real-configs", "coarse"]) == 0
    rows = list(csv.DictReader((out / "real_detect.csv").open()))
    assert [(r["config"], r["seed"]) for r in rows] == [("coarse", "0")]
    recorded = json.loads((out / "real_settings.json").read_text())
    assert "0.005" in json.dumps(recorded["coarse"])
