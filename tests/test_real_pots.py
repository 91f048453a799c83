"""Real single-view clouds: the side handles of the pot in osd-learn, labeled by us. Needs the
real data (``$SIMGRASP_REAL_DIR`` or ``../shared/real``); skipped cleanly without it."""

from __future__ import annotations

import numpy as np
import pytest

from simgrasp.assets.real import default_real_dir, osd_scene_file, read_labeled_scene
from simgrasp.assets.scene_labels import load_scene_labels
from simgrasp.evaluation.real_pots import POT_SEGMENTATION, labeled_pot, score_pot
from simgrasp.handles import QuadricDetectorConfig
from simgrasp.handles.presets import quadric_preset
from simgrasp.labels import Box

REAL_DIR = default_real_dir()
needs_real = pytest.mark.real  # skipped without the scenes (tests/data_needs.py)


def test_pot_labels_load_in_the_sensor_frame() -> None:
    labels = load_scene_labels()
    assert sorted(labels) == [f"learn{i}" for i in range(33, 42)]
    assert sum(len(v.label.regions) for v in labels.values()) == 12
    for label in labels.values():
        for region in label.label.regions:  # a pot on a table 0.6-1.2 m in front of the sensor
            assert isinstance(region, Box)
            assert 0.5 < region.center[2] < 1.2
            assert np.all(region.half_extents < 0.05)


@needs_real
def test_labels_hold_the_pot_tabs_and_little_else() -> None:
    label = load_scene_labels()["learn39"]
    scene = read_labeled_scene(osd_scene_file("learn39", REAL_DIR))
    pot = labeled_pot(scene, label)
    for region in label.label.regions:
        assert region.contains(pot).sum() >= 200  # each tab is seen
    assert label.label.contains(pot).mean() < 0.1
    valid = np.isfinite(scene.points).all(axis=1)
    others = scene.points[valid & (scene.labels // 10 != label.object_id)]
    assert label.label.contains(others).mean() < 0.002  # barely any table or other object


@needs_real
def test_pot_handle_is_found_on_a_real_scene() -> None:
    label = load_scene_labels()["learn39"]
    pot = labeled_pot(read_labeled_scene(osd_scene_file("learn39", REAL_DIR)), label)
    result = score_pot(pot, label, quadric_preset("real_depth"), seed=0)
    assert result.candidates >= 10
    assert result.accuracy >= 0.8
    assert result.top_on_handle
    # The mesh-cloud defaults centre the handle on the fitted axis, centimetres behind the tab.
    assert not score_pot(pot, label, QuadricDetectorConfig(), seed=0).top_on_handle


@needs_real
def test_labels_command_draws_a_scene(tmp_path) -> None:
    from simgrasp.cli import main

    assert main(["labels", "--osd", "learn39", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "learn39.png").stat().st_size > 10_000


def test_unknown_scene_is_a_clear_error(tmp_path) -> None:
    with pytest.raises(ValueError, match="learn"):
        osd_scene_file("scene39", tmp_path)
    with pytest.raises(FileNotFoundError, match="learn99"):
        osd_scene_file("learn99", tmp_path)


def test_the_committed_real_depth_preset_file_is_the_real_depth_preset() -> None:
    """docs/results/README.md runs `detect --segment --config` with this file: the detector's
    real_depth() preset and the pots' segmentation (rim joins)."""
    from pathlib import Path

    from simgrasp.config import build
    from simgrasp.config.files import read_config_file
    from simgrasp.handles.detector_config import DetectorConfig
    from simgrasp.perception.segmentation.segment_config import SegmentConfig

    preset = Path(__file__).parents[1] / "docs" / "results" / "real-pots" / "real_depth.toml"
    settings = read_config_file(preset)
    assert {k.split(".")[0] for k in settings} == {"single_view", "detector", "segmentation"}
    assert settings["single_view"] is False
    detector = build(DetectorConfig, section(settings, "detector"))
    assert detector.quadric == quadric_preset("real_depth")
    assert build(SegmentConfig, section(settings, "segmentation")) == POT_SEGMENTATION


def section(settings: dict[str, object], name: str) -> dict[str, object]:
    """The settings of one section of a config file, without its name."""
    return {k.removeprefix(f"{name}."): v for k, v in settings.items() if k.startswith(f"{name}.")}
