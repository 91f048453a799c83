"""The chain in clutter: the target cut by our segmenter, neighbors scored, clutter 0 unchanged."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial import cKDTree

from simgrasp.assets.model import model_for
from simgrasp.grasping.grasp import Grasp, tcp_pose
from simgrasp.grasping.trials.chain import propose_grasps, run_chain
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.clutter_scoring import NeighborWatch, score_in_clutter
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.perception.segmentation.segment import segment_scene
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import observe
from simgrasp.scenes.perceive import organized_cloud, perceive_target
from simgrasp.scenes.scene import build_scene

CLUTTER_KEYS = {"clutter", "distractors", "perception", "target_iou", "neighbors_disturbed"}


@pytest.fixture(scope="module")
def hammer():
    return model_for("gen_hammer")


def test_under_segment_the_target_is_cut_by_the_segmenter_not_the_mask(
    renderers: RendererKeeper, hammer
) -> None:
    config = SceneConfig(num_views=2, clutter=3, clutter_objects="generated")
    scene = build_scene(hammer, make_gripper("builtin"), config, seed=0)
    observation = observe(scene, renderers.renderer_for(scene), 0.0, 0)
    segmented = perceive_target(scene, observation, "segment", 0.0, 0)
    masked = perceive_target(scene, observation, "mask", 0.0, 0)
    assert masked.cloud is observation.cloud and masked.target_iou == 1.0
    assert 0.8 < segmented.target_iou < 1.0  # the segmenter's cut, close to the truth
    assert len(segmented.obstacles_world) > 500  # the neighbors stay in as obstacles
    # Every point of the cut lies within a voxel of one segment of the segmenter's labels.
    frame = observation.frames[0]
    labels = segment_scene(organized_cloud(frame)).labels.reshape(frame.depth.shape)
    truth = frame.body_ids == scene.object_body
    chosen = np.bincount(labels[truth & (labels >= 2)]).argmax()
    segment_points = organized_cloud(frame).points[(labels == chosen).reshape(-1)]
    cut = segmented.cloud.points_world
    seen_first = (segmented.cloud.viewpoints_world == frame.camera_position_world).all(axis=1)
    distance, _ = cKDTree(segment_points).query(cut[seen_first])
    assert np.quantile(distance, 0.95) < 0.005
    assert not np.array_equal(np.sort(cut, axis=0), np.sort(masked.cloud.points_world, axis=0))


def test_a_crowded_table_keeps_its_own_plane(renderers: RendererKeeper, hammer) -> None:
    """Twenty generated objects on the table, seen by the kinect model, cut with the chain's
    settings: flat ones (pans, spatula blades) lie within the plane RANSAC's 12 mm band, and a
    fit of all its inliers tilted toward them (no table found in the first view: 72 % of the
    inliers within ``table_distance``). The table's own points must decide its plane."""
    config = ChainConfig.of(
        scene__clutter=19, scene__clutter_objects="generated", sensor__kind="kinect"
    )
    scene = build_scene(hammer, make_gripper("builtin"), config.scene, 0)
    observation = observe(scene, renderers.renderer_for(scene), 0.0, 0, config.sensor)
    for frame in observation.frames:
        cloud = organized_cloud(frame)
        result = segment_scene(cloud, config.segment)
        table = (frame.geom_ids == scene.table_geom).reshape(-1) & cloud.valid
        height = cloud.points[table] @ result.plane[:3] + result.plane[3]
        assert np.mean(np.abs(height) <= config.segment.table_distance) > 0.95
        assert np.mean(result.labels[table] == 1) > 0.9


def test_a_neighbor_lifted_is_wrong_object(hammer) -> None:
    config = SceneConfig(clutter=1, clutter_objects="gen_fruit")
    gripper = make_gripper("builtin")
    scene = build_scene(hammer, gripper, config, seed=0)
    neighbor = scene.distractors[0]
    mesh = neighbor.model.asset.mesh.copy().apply_transform(neighbor.world_T_object)
    center = mesh.bounds.mean(axis=0)
    on_neighbor = tcp_pose(center, np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0]))
    grasp = Grasp(world_T_tcp=on_neighbor, width=gripper.max_opening, score=1.0, source="given")
    watch = NeighborWatch.of(scene)
    trial = run_trial(scene, grasp, TrialConfig(), watch)
    assert trial.success is False and trial.failure == "missed"  # the target was never touched
    fields = score_in_clutter(scene, trial, watch, TrialConfig())
    assert fields["failure"] == "wrong_object"
    assert fields["neighbors_disturbed"] == 1
    lifted = scene.data.xpos[scene.model.body(neighbor.body).id][2] - neighbor.world_T_object[2, 3]
    assert lifted > 0.1


def test_clutter_zero_records_are_todays(hammer) -> None:
    today = run_chain(hammer, ChainConfig(), seed=0).to_json()
    zero = run_chain(hammer, ChainConfig.of(scene__clutter=0, perception="mask"), 0).to_json()
    assert not CLUTTER_KEYS & set(today) and "segment" not in today["timings_s"]
    today.pop("timings_s"), zero.pop("timings_s")
    assert today == zero


def test_a_clutter_trial_records_its_scene_and_cut(hammer) -> None:
    config = ChainConfig.of(
        scene__clutter=2, scene__clutter_objects="generated", scene__num_views=2
    )
    record = run_chain(hammer, config, seed=1).to_json()
    assert record["perception"] == "segment" and record["clutter"] == 2
    assert len(record["distractors"]) == 2 and "gen_hammer_s0" not in record["distractors"]
    assert record["target_iou"] > 0.8
    assert record["timings_s"]["segment"] > 0
    assert isinstance(record["neighbors_disturbed"], int)


def test_a_mug_hemmed_in_by_a_neighbor_is_grasped_from_above_its_strap(
    renderers: RendererKeeper, ycb_dir: str
) -> None:
    """Seed 105 stands the YCB mug (Kinect depth) with its strap facing a neighbor: the
    12 cm palm behind every approach to the strap up to 30 degrees down meets the neighbor,
    so the usual pitches leave no grasp; the fallback's steeper ones pass over the neighbor,
    still close across the strap and lift the mug by it."""
    mug, seed = model_for("025_mug", ycb_dir), 105
    config = ChainConfig.of(scene__clutter=5, sensor__kind="kinect")
    scene = build_scene(mug, make_gripper(config.gripper), config.scene, seed)
    observation = observe(scene, renderers.renderer_for(scene), 0.0, seed, config.sensor)
    cut = perceive_target(scene, observation, config.perception_mode, 0.0, seed)
    usual = replace(config, planner=replace(config.planner, fallback_pitches=()))
    assert propose_grasps(scene, cut.cloud, usual, seed, cut.obstacles_world)[0] == []
    grasps, detection = propose_grasps(scene, cut.cloud, config, seed, cut.obstacles_world)
    assert grasps and detection is not None
    axis = detection.handles[0].axis
    assert abs(axis[2]) > 0.95  # the standing strap
    for grasp in grasps:
        assert grasp.approach_world @ axis < -np.sin(np.pi / 4) + 1e-9  # 45+ degrees down the strap
        assert abs(grasp.world_T_tcp[:3, 1] @ axis) < 1e-9  # the jaws close across it
    trial = run_trial(scene, grasps[0], config.trial)
    assert trial.success and trial.on_handle
