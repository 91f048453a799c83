"""The planner's narrow-opening fallback (``PlannerConfig.fallback_opening_margins``) on a
generated mug lying on its side with its strap flat on the table, through the real renderer,
detector and simulator (no ../shared data)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from simgrasp.assets.model import model_for
from simgrasp.grasping.trials.chain import propose_grasps
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grippers import make_gripper
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import observe
from simgrasp.scenes.scene import build_scene


def test_a_strap_lying_flat_is_grasped_with_a_finger_inside_its_loop(
    renderers: RendererKeeper,
) -> None:
    """Seed 29 lays gen_mug on its side, the strap's loop flat on the table (Kinect depth):
    with the jaws fully open (8.5 cm) the inner finger of every approach across the strap
    lands on the mug's body, so no grasp is clear; opened to the strap's width plus 1 cm a
    side, the inner finger fits in the loop, and the grasp lifts the mug by its strap."""
    mug, seed = model_for("gen_mug"), 29
    config = ChainConfig.of(gripper="builtin", sensor__kind="kinect", scene__clutter=0)
    scene = build_scene(mug, make_gripper(config.gripper), config.scene, seed)
    cloud = observe(scene, renderers.renderer_for(scene), 0.0, seed, config.sensor).cloud
    wide_only = replace(config, planner=replace(config.planner, fallback_opening_margins=()))
    assert propose_grasps(scene, cloud, wide_only, seed)[0] == []
    grasps, detection = propose_grasps(scene, cloud, config, seed)
    assert grasps and detection is not None
    strap = detection.handles[0]
    assert abs(strap.axis[2]) < 0.3 and strap.center[2] - scene.config.table_top_z < 0.02
    max_opening = scene.gripper.gripper.max_opening
    margin = config.planner.fallback_opening_margins[0]
    for grasp in grasps:
        assert grasp.width == min(max_opening, strap.width + 2 * margin) < max_opening
        assert abs(grasp.world_T_tcp[:3, 1] @ strap.axis) < 1e-9  # the jaws close across it
        assert grasp.approach_world[2] < -0.5  # from above
    trial = run_trial(scene, grasps[0], config.trial)
    assert trial.success and trial.on_handle
    assert np.isclose(trial.to_json()["grasp_width"], grasps[0].width)
