"""The full chain of one grasp trial: render -> detect -> plan -> execute -> score.

One seed fixes everything random: the object's rest pose and yaw (scene), cloud noise, the
detector's neighborhood sampling, the planner's approach jitter.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.assets.model import ObjectModel, build_object_model
from simgrasp.assets.placement import Placement
from simgrasp.assets.registry import load_object
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planner import (
    GripperGeometry,
    PlannerConfig,
    antipodal_grasps,
    centroid_grasps,
    grasps_from_handles,
)
from simgrasp.grasping.trial import Phase, TrialConfig, TrialResult, run_trial
from simgrasp.handles import DETECTORS, QuadricDetectorConfig, default_config, detect
from simgrasp.handles.accuracy import detection_accuracy, handle_recall
from simgrasp.handles.detection import Detection
from simgrasp.perception import estimate_normals, multiplicative_noise
from simgrasp.scenes.gripper import Gripper, make_gripper
from simgrasp.scenes.kept_renderer import kept_renderer
from simgrasp.scenes.observe import ObjectCloud, object_cloud
from simgrasp.scenes.render import DepthFrame, SceneRenderer
from simgrasp.scenes.scene import Scene, SceneConfig, build_scene
from simgrasp.scenes.views import CHAIN_VIEWS
from simgrasp.seeding import rng_for

ChainDetector = Literal["quadric", "tenpas", "centroid", "random"]
CHAIN_DETECTORS: tuple[str, ...] = (*DETECTORS, "centroid", "random")
CLOUD_VOXEL = 0.003
MIN_CLOUD_POINTS = 10
"""Clouds with fewer points than this get no grasp proposals."""


@dataclass(frozen=True)
class ChainConfig:
    """What one full-chain trial uses.

    ``noise`` is the paper's multiplicative noise sigma applied to the observed cloud about its
    centroid (Table II's model), so detection and grasp sweeps share one noise axis.
    """

    detector: ChainDetector = "quadric"
    gripper: str = "builtin"
    noise: float = 0.0
    scene: SceneConfig = field(default_factory=lambda: SceneConfig(num_views=CHAIN_VIEWS))
    trial: TrialConfig = field(default_factory=TrialConfig)
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    quadric: QuadricDetectorConfig = field(default_factory=QuadricDetectorConfig)
    """The quadric detector's settings (its gripper opening is replaced by the chosen
    gripper's). ``QuadricDetectorConfig.camera_cloud()`` holds the lying YCB mug by its strap
    in 7 of 10 seeds instead of 3, but costs on-handle success elsewhere (fork, drill at
    noise 0.04) and detection time: docs/results/README.md, lying-mug."""

    def __post_init__(self) -> None:
        if self.detector not in CHAIN_DETECTORS:
            raise ValueError(
                f"unknown detector {self.detector!r}; choose one of {', '.join(CHAIN_DETECTORS)}"
            )
        if not 0 <= self.noise < 1:
            raise ValueError(f"noise sigma must be in [0, 1), got {self.noise}")

    def with_placement(self, placement: Placement) -> ChainConfig:
        """This config with the scene's object ``placement`` (``"stable"`` or ``"upright"``)."""
        return replace(self, scene=replace(self.scene, placement=placement))

    def with_views(self, views: int) -> ChainConfig:
        """This config with ``views`` default cameras (1..4) fused into the object's cloud."""
        return replace(self, scene=replace(self.scene, num_views=views))


@dataclass(frozen=True)
class ChainResult:
    """A full-chain trial: what was seen, detected, chosen and what happened."""

    object: str
    detector: str
    gripper: str
    noise: float
    seed: int
    cloud_points: int
    candidates: int
    handles: int
    detection_accuracy: float | None
    handle_recall: bool | None
    grasp_candidates: int
    trial: TrialResult | None
    timings_s: dict[str, float]

    @property
    def success(self) -> bool | None:
        return False if self.trial is None else self.trial.success

    @property
    def on_handle(self) -> bool:
        return self.trial is not None and self.trial.on_handle and bool(self.trial.success)

    def to_json(self) -> dict[str, Any]:
        """One flat record: the trial's fields, the chain's fields and merged timings."""
        trial = self.trial.to_json() if self.trial else _no_grasp_record(self)
        record = {**trial, **{k: v for k, v in self.__dict__.items() if k != "trial"}}
        record["timings_s"] = {**trial.get("timings_s", {}), **self.timings_s}
        record["success"] = self.success
        record["on_handle"] = self.on_handle
        return record


def _no_grasp_record(result: ChainResult) -> dict[str, Any]:
    return {
        "object_pose": None,
        "grasp": None,
        "success": False,
        "failure": "no_grasp",
        "on_handle": False,
        "lift_height": 0.0,
        "timings_s": {},
    }


def gripper_geometry(gripper: Gripper) -> GripperGeometry:
    """The planner's collision boxes for ``gripper`` (documented approximations).

    The boxes are those of the open gripper (pre-grasp and approach). The Robotiq's pads swing
    forward as they close (tips 9.5 mm past the TCP open, 21-23 mm once closed on a handle
    narrower than 4 cm), so its grasps keep the closed fingertips above the table: closing
    tips that hit the table top stall the jaws before they squeeze the handle.
    """
    if gripper.name == "robotiq_2f85":
        from simgrasp.scenes.robotiq import OPEN_FINGER_REACH

        return GripperGeometry(
            max_opening=gripper.max_opening,
            pad_reach=OPEN_FINGER_REACH,
            closed_pad_reach=gripper.finger_reach,
            finger_length=0.06,
            finger_width=0.025,
            palm_size=(0.07, 0.14, 0.06),
        )
    return GripperGeometry(max_opening=gripper.max_opening, pad_reach=gripper.finger_reach)


def render_views(scene: Scene, renderer: SceneRenderer) -> list[DepthFrame]:
    """Depth and segmentation from every scene camera, the scene reset to its initial state."""
    scene.reset()
    return [renderer.depth(scene.data, camera) for camera in scene.cameras]


def cloud_from_views(
    scene: Scene, frames: list[DepthFrame], noise: float, seed: int
) -> ObjectCloud:
    """Fuse the object's pixels of ``frames`` into a world-frame cloud (3 mm voxels) and apply
    the multiplicative noise ``noise`` about its centroid (seeded by ``seed``)."""
    cloud = object_cloud(frames, [scene.object_body], voxel_size=CLOUD_VOXEL)
    if noise == 0 or len(cloud) == 0:
        return cloud
    centroid = cloud.points_world.mean(axis=0)
    rng = rng_for(seed, "chain", "noise")
    noisy = centroid + multiplicative_noise(cloud.points_world - centroid, noise, rng)
    return ObjectCloud(noisy, cloud.viewpoints_world, cloud.view_counts, cloud.camera_names)


def observe(scene: Scene, noise: float, seed: int) -> ObjectCloud:
    """Render every scene camera and fuse the object's pixels into a world-frame cloud (with
    the process's renderer for scenes built alike: :mod:`simgrasp.scenes.kept_renderer`)."""
    frames = render_views(scene, kept_renderer(scene))
    return cloud_from_views(scene, frames, noise, seed)


def viewpoint_normals(cloud: ObjectCloud) -> NDArray[np.float64]:
    """Normals of a fused camera cloud, each turned toward the camera that saw its point."""
    normals = estimate_normals(cloud.points_world, orient="none")
    toward = np.einsum("ij,ij->i", normals, cloud.viewpoints_world - cloud.points_world)
    normals[toward < 0] *= -1
    return normals


def plan_grasps(
    points_world: NDArray[np.float64],
    normals_world: NDArray[np.float64],
    cameras_world: NDArray[np.float64],
    geometry: GripperGeometry,
    table_top_z: float,
    config: ChainConfig,
    seed: int,
) -> tuple[list[Grasp], Detection | None]:
    """Ranked grasps (best first) from the configured detector or baseline, on plain arrays.

    The chain (:func:`propose_grasps`) and the gymnasium policy
    (:class:`simgrasp.envs.policy.DetectorPolicy`) both plan through this function.

    Args:
        points_world: (N, 3) object cloud, world frame, meters.
        normals_world: (N, 3) unit normals turned toward the camera that saw each point (as
            :func:`viewpoint_normals` makes them); the centroid baseline ignores them.
        cameras_world: (K, 3) optical centers of the cameras that saw the cloud (world frame,
            meters), for the planner's view bonus.
        geometry: the gripper's collision boxes (:func:`gripper_geometry`).
        table_top_z: world z of the table top (m).
        config: its ``detector`` and ``planner`` are used.
        seed: seeds the detector's sampling and the planner's approach jitter.

    Returns:
        The grasps and, for the handle detectors, their detection (None for the baselines).
    """
    rng = rng_for(seed, "chain", "plan")
    if config.detector == "centroid":
        return centroid_grasps(points_world, geometry, table_top_z, config.planner), None
    if config.detector == "random":
        grasps = antipodal_grasps(
            points_world, normals_world, geometry, table_top_z, rng, config.planner
        )
        return grasps, None
    detector_config = (
        replace(config.quadric, gripper_max_opening=geometry.max_opening)
        if config.detector == "quadric"
        else default_config(config.detector, geometry.max_opening)
    )
    detection = detect(points_world, normals_world, detector_config, seed, detector=config.detector)
    grasps = grasps_from_handles(
        detection.handles,
        points_world,
        cameras_world,
        geometry,
        table_top_z,
        rng,
        config.planner,
        config.detector,
    )
    return grasps, detection


def propose_grasps(
    scene: Scene,
    cloud: ObjectCloud,
    config: ChainConfig,
    seed: int,
) -> tuple[list[Grasp], Detection | None]:
    """Ranked grasps from the configured detector (or baseline) on the observed cloud."""
    return plan_grasps(
        cloud.points_world,
        viewpoint_normals(cloud),
        np.unique(cloud.viewpoints_world, axis=0),
        gripper_geometry(scene.gripper.gripper),
        scene.config.table_top_z,
        config,
        seed,
    )


def _detection_scores(
    scene: Scene, detection: Detection | None
) -> tuple[float | None, bool | None]:
    if detection is None:
        return None, None
    object_T_world = np.linalg.inv(scene.world_T_object)
    label = scene.object_model.asset.handle
    in_object = _moved(detection, object_T_world)
    accuracy = detection_accuracy(in_object, label)
    return (None if np.isnan(accuracy) else accuracy), handle_recall(in_object, label)


def _moved(detection: Detection, a_T_b: NDArray[np.float64]) -> Detection:
    """The detection's candidate and handle centers mapped by ``a_T_b`` (for label checks)."""
    rotation, translation = a_T_b[:3, :3], a_T_b[:3, 3]
    candidates = tuple(
        replace(c, center=rotation @ c.center + translation) for c in detection.candidates
    )
    handles = tuple(replace(h, center=rotation @ h.center + translation) for h in detection.handles)
    return replace(detection, candidates=candidates, handles=handles)


def model_for(object_name: str, ycb_dir: str | None = None) -> ObjectModel:
    """The simulation model of an object (CoACD decomposition from the on-disk cache)."""
    return build_object_model(load_object(object_name, ycb_dir))


def run_chain(
    object_model: ObjectModel,
    config: ChainConfig,
    seed: int,
    gripper: Gripper | None = None,
    on_phase: Callable[[Phase, Scene], None] | None = None,
) -> ChainResult:
    """Render, detect, plan and execute the best-ranked grasp on ``object_model``;
    ``on_phase`` is passed to :func:`run_trial` (e.g. to render key frames)."""
    timings: dict[str, float] = {}
    start = time.perf_counter()
    gripper = gripper or make_gripper(config.gripper)
    scene = build_scene(object_model, gripper, config.scene, seed)
    timings["scene"] = time.perf_counter() - start
    start = time.perf_counter()
    cloud = observe(scene, config.noise, seed)
    timings["render"] = time.perf_counter() - start
    start = time.perf_counter()
    grasps, detection = (
        ([], None) if len(cloud) < MIN_CLOUD_POINTS else propose_grasps(scene, cloud, config, seed)
    )
    timings["detect_and_plan"] = time.perf_counter() - start
    accuracy, recall = _detection_scores(scene, detection)
    trial = run_trial(scene, grasps[0], config.trial, on_phase) if grasps else None
    return ChainResult(
        object=object_model.asset.name,
        detector=config.detector,
        gripper=gripper.name,
        noise=config.noise,
        seed=seed,
        cloud_points=len(cloud),
        candidates=len(detection.candidates) if detection else 0,
        handles=len(detection.handles) if detection else 0,
        detection_accuracy=accuracy,
        handle_recall=recall,
        grasp_candidates=len(grasps),
        trial=trial,
        timings_s=timings,
    )
