"""Building a bench scene from its suite definition and observing it as a method would.

A scene is the chain's (:mod:`simgrasp.scenes.scene`): the object at the scene's seeded
placement, its neighbors dropped and settled, the suite's views around it, seen through the
scene's depth sensor; the target is cut by the renderer's segmentation (the same cut for every
method: the bench scores grasping, not segmentation). The same definition and scene build the
same scene on every call, so a method run in process and one scored from its files meet the
same scene. Object models and the renderer are kept in the process's worker session
(:func:`~simgrasp.grasping.session.worker_session`, closed at the end of a run's tasks here).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from simgrasp.assets.model import ObjectModel
from simgrasp.bench.observation import BenchObservation, BenchView, gripper_description
from simgrasp.bench.suites import BenchScene, SuiteDefinition
from simgrasp.grasping.session import worker_session
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.protocol import get_protocol
from simgrasp.grippers import make_gripper
from simgrasp.perception.voxel import voxel_downsample
from simgrasp.scenes.observe import CLOUD_VOXEL, observe
from simgrasp.scenes.perceive import perceive_target, world_pixels
from simgrasp.scenes.render import DepthFrame
from simgrasp.scenes.scene import Scene, build_scene


def chain_config(suite: SuiteDefinition, scene: BenchScene) -> ChainConfig:
    """The chain settings of ``scene``: the suite's gripper, views, protocol and neighbors,
    the scene's placement, clutter and sensor, the mask's cut and no added cloud noise."""
    config = ChainConfig.of(
        gripper=suite.gripper,
        perception="mask",
        scene__num_views=suite.views,
        scene__placement=scene.placement,
        scene__clutter=scene.clutter,
        scene__clutter_objects=suite.distractors,
        sensor__kind=scene.sensor,
    )
    return replace(config, trial=get_protocol(suite.protocol).config)


def object_model(name: str) -> ObjectModel:
    """The simulation model of object ``name``, built once per process (its worker
    session's)."""
    return worker_session().model(name)


def build_bench_scene(suite: SuiteDefinition, scene: BenchScene) -> Scene:
    """The compiled scene of ``scene`` (its neighbors settled), at its initial state."""
    config = chain_config(suite, scene)
    gripper = make_gripper(suite.gripper)
    return build_scene(object_model(scene.object), gripper, config.scene, scene.seed)


def observe_bench_scene(
    suite: SuiteDefinition, scene: BenchScene, built: Scene
) -> BenchObservation:
    """What a method sees of ``built`` (:class:`BenchObservation`): every view through the
    scene's sensor, the target cut by the segmentation, the neighbors' points and the whole
    scene's points (voxels of ``CLOUD_VOXEL``)."""
    config = chain_config(suite, scene)
    renderer = worker_session().renderers.renderer_for(built)
    seen = observe(built, renderer, 0.0, scene.seed, config.sensor)
    cloud = seen.cloud
    obstacles = np.zeros((0, 3))
    if scene.clutter:
        obstacles = perceive_target(built, seen, "mask", 0.0, scene.seed).obstacles_world
    geometry = built.gripper.gripper.planning_geometry()
    return BenchObservation(
        suite=suite.name,
        suite_sha256=suite.digest(),
        scene=scene.id,
        seed=scene.seed,
        cloud=np.asarray(cloud.points_world, dtype=np.float64),
        cloud_viewpoints=np.asarray(cloud.viewpoints_world, dtype=np.float64),
        scene_cloud=_scene_cloud(seen.frames),
        obstacle_cloud=np.asarray(obstacles, dtype=np.float64).reshape(-1, 3),
        views=tuple(_view(frame) for frame in seen.frames),
        table_top_z=float(config.scene.table_top_z),
        gripper=gripper_description(built.gripper.gripper.name, geometry),
    )


def _scene_cloud(frames: list[DepthFrame]) -> np.ndarray:
    """Every view's points with a depth (world frame), fused in ``CLOUD_VOXEL`` voxels."""
    points = np.concatenate([world_pixels(frame)[0] for frame in frames], axis=0)
    return voxel_downsample(points, CLOUD_VOXEL)[0] if len(points) else points.reshape(0, 3)


def _view(frame: DepthFrame) -> BenchView:
    intrinsics = frame.intrinsics
    return BenchView(
        name=frame.camera_name,
        depth=np.asarray(frame.depth, dtype=np.float32),
        intrinsics={
            "width": int(intrinsics.width),
            "height": int(intrinsics.height),
            "fx": float(intrinsics.fx),
            "fy": float(intrinsics.fy),
            "cx": float(intrinsics.cx),
            "cy": float(intrinsics.cy),
        },
        world_T_camera=np.asarray(frame.world_T_cam, dtype=np.float64),
    )
