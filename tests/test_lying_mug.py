"""The YCB mug lying on its side, strap up (stable placement, seed 0): the camera_cloud()
detector settings hold it by the strap where the defaults find no strap."""

from __future__ import annotations

import pytest

from simgrasp.grasping.chain import ChainConfig, model_for, run_chain
from simgrasp.handles import QuadricDetectorConfig


@pytest.fixture(scope="module")
def mug(ycb_dir: str):
    return model_for("025_mug", ycb_dir)


def test_lying_mug_is_held_by_its_strap_with_camera_cloud_settings(mug) -> None:
    config = ChainConfig(quadric=QuadricDetectorConfig.camera_cloud())
    result = run_chain(mug, config, seed=0)
    assert result.handle_recall
    assert result.success and result.on_handle, result.to_json()["failure"]


def test_default_settings_miss_the_lying_strap(mug) -> None:
    result = run_chain(mug, ChainConfig(), seed=0)
    assert not result.on_handle
    assert ChainConfig().quadric == QuadricDetectorConfig()
