"""The planner's narrow openings (``PlannerConfig.fallback_opening_margins`` and the root
grasp's ``root_opening_margin``) on a generated mug lying on its side with its strap flat on
the table, through the real renderer, detector and simulator (no ../shared data)."""

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
    lands on the mug's body, so no grasp is clear. Opened to the strap's width plus 1 cm a
    side, the inner finger fits in the loop and the grasp lifts the mug by its strap: both
    as the narrow-opening fallback across the strap's axis, and (the default, found in the
    first pass) as the grasp at the strap's root."""
    mug, seed = model_for("gen_mug"), 29
    config = ChainConfig.of(gripper="builtin", sensor__kind="kinect", scene__clutter=0)
    scene = build_scene(mug, make_gripper(config.gripper), config.scene, seed)
    cloud = observe(scene, renderers.renderer_for(scene), 0.0, seed, config.sensor).cloud
    max_opening = scene.gripper.gripper.max_opening
    # a root margin of half the open jaws or more leaves the root grasp fully open
    wide_root = replace(config.planner, root_opening_margin=max_opening / 2)
    wide_only = replace(config, planner=replace(wide_root, fallback_opening_margins=()))
    assert propose_grasps(scene, cloud, wide_only, seed)[0] == []

    fallback = replace(config, planner=wide_root)
    grasps, detection = propose_grasps(scene, cloud, fallback, seed)
    assert grasps and detection is not None
    strap = detection.handles[0]
    assert abs(strap.axis[2]) < 0.3 and strap.center[2] - scene.config.table_top_z < 0.02
    narrow = strap.width + 2 * config.planner.fallback_opening_margins[0]
    for grasp in grasps:
        assert grasp.width == min(max_opening, narrow) < max_opening
        assert abs(grasp.world_T_tcp[:3, 1] @ strap.axis) < 1e-9  # the jaws close across it
        assert grasp.approach_world[2] < -0.5  # from above
    trial = run_trial(scene, grasps[0], fallback.trial)
    assert trial.success and trial.on_handle
    assert np.isclose(trial.to_json()["grasp_width"], grasps[0].width)

    rooted, _ = propose_grasps(scene, cloud, config, seed)
    assert rooted
    root_width = strap.width + 2 * config.planner.root_opening_margin
    assert all(g.width == min(max_opening, root_width) for g in rooted)
    trial = run_trial(scene, rooted[0], config.trial)
    assert trial.success and trial.on_handle
