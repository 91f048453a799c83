"""The YCB mug lying on its side, strap up (stable placement, seed 0): the camera_cloud()
detector settings hold it by the strap where the defaults find no strap."""

from __future__ import annotations

from pathlib import Path

import pytest

from simgrasp.assets.model import model_for
from simgrasp.config import build
from simgrasp.config.files import read_config_file
from simgrasp.grasping.chain import run_chain
from simgrasp.grasping.chain_config import ChainConfig, ChainDetectorConfig
from simgrasp.handles import QuadricDetectorConfig

PRESET = Path(__file__).parents[1] / "docs" / "results" / "lying-mug" / "camera_cloud.toml"


@pytest.fixture(scope="module")
def mug(ycb_dir: str):
    return model_for("025_mug", ycb_dir)


def test_lying_mug_is_held_by_its_strap_with_camera_cloud_settings(mug) -> None:
    config = ChainConfig(detector=ChainDetectorConfig(quadric=QuadricDetectorConfig.camera_cloud()))
    result = run_chain(mug, config, seed=0)
    assert result.handle_recall
    assert result.success and result.on_handle, result.to_json()["failure"]


def test_default_settings_miss_the_lying_strap(mug) -> None:
    result = run_chain(mug, ChainConfig(), seed=0)
    assert not result.on_handle
    assert ChainConfig().detector.quadric == QuadricDetectorConfig()


def test_the_committed_preset_file_is_the_camera_cloud_preset() -> None:
    """docs/results/lying-mug runs the CLI with this file: it must hold camera_cloud()."""
    config = build(ChainConfig, read_config_file(PRESET))
    assert config.detector.quadric == QuadricDetectorConfig.camera_cloud()
