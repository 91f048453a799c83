"""The target cut in clutter by the chain's segmenter: a thin tool lying flat on the table
(rendered, kinect sensor) is kept above the table band and cut whole."""

from __future__ import annotations

from simgrasp.assets.model import model_for
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers import make_gripper
from simgrasp.perception.segmentation.segment_config import SegmentConfig
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import observe
from simgrasp.scenes.perceive import perceive_target
from simgrasp.scenes.scene import build_scene


def test_a_screwdriver_lying_flat_among_five_neighbors_is_cut_with_the_simulated_table_band(
    renderers: RendererKeeper,
) -> None:
    config = ChainConfig.of(
        scene__clutter=5, scene__clutter_objects="generated", sensor__kind="kinect"
    )
    assert config.segment == SegmentConfig.simulated()
    seed = 100  # a tuning seed of SegmentConfig.simulated (not the committed run's 0-9)
    scene = build_scene(model_for("gen_screwdriver"), make_gripper("builtin"), config.scene, seed)
    observation = observe(scene, renderers.renderer_for(scene), 0.0, seed, config.sensor)
    simulated = perceive_target(scene, observation, "segment", 0.0, seed, config.segment)
    real_default = perceive_target(scene, observation, "segment", 0.0, seed, SegmentConfig())
    # The 5 mm band of real tables takes the screwdriver's low shaft: 0.86 then, 0.91 now.
    assert simulated.target_iou > 0.89
    assert simulated.target_iou > real_default.target_iou + 0.02
    assert len(simulated.cloud.points_world) > 200
