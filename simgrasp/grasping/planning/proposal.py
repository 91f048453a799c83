"""Grasp proposals on one object's :class:`~simgrasp.grasping.cloud_view.CloudView`: the
registered proposer (:mod:`simgrasp.grasping.proposers`) and the built-in ones, a handle
detector with the planner or a baseline.

The chain (:func:`simgrasp.grasping.trials.chain.run_chain`) and the gymnasium policy
(:class:`simgrasp.envs.policy.DetectorPolicy`) both plan through :func:`plan_grasps`.
"""

from __future__ import annotations

from simgrasp.grasping.cloud_view import CloudView
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.planner import (
    GripperGeometry,
    antipodal_grasps,
    centroid_grasps,
    grasps_from_handles,
)
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grasping.proposers import proposer_entry
from simgrasp.grasping.trials.chain_config import ChainDetectorConfig
from simgrasp.handles import detect
from simgrasp.handles.core.detection import Detection
from simgrasp.seeding import rng_for

MIN_CLOUD_POINTS = 10
"""Clouds with fewer points than this get no grasp proposals."""

Proposal = tuple[list[Grasp], Detection | None]


def plan_grasps(
    view: CloudView,
    geometry: GripperGeometry,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> Proposal:
    """Ranked grasps (best first) from the proposer ``detector.kind`` names.

    Args:
        view: the object's cloud, its normals, cameras and table.
        geometry: the gripper's collision boxes; its opening is the detector's too.
        detector: which proposer, with its thresholds.
        planner: grasp sampling and ranking.
        seed: seeds the detector's sampling and the planner's approach jitter.

    Returns:
        The grasps and, for the handle detectors, their detection (None for the baselines).
    """
    proposer = proposer_entry(detector.kind).load()
    proposal: Proposal = proposer(view, geometry, detector, planner, seed)
    return proposal


def propose_on_handles(
    view: CloudView,
    geometry: GripperGeometry,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> Proposal:
    """The handle detector ``detector.kind`` (quadric, tenpas), then grasps across each
    handle (:func:`~simgrasp.grasping.planning.planner.grasps_from_handles`)."""
    rng = rng_for(seed, "chain", "plan")
    detection = detect(
        view.points_world,
        view.normals_world,
        detector.for_gripper(geometry.max_opening),
        seed,
        detector=detector.handle_detector(),
    )
    grasps = grasps_from_handles(
        detection.handles,
        view.points_world,
        view.cameras_world,
        geometry,
        view.table_top_z,
        rng,
        planner,
        detector.kind,
        view.scene_obstacles_world,
    )
    return grasps, detection


def propose_at_centroid(
    view: CloudView,
    geometry: GripperGeometry,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> Proposal:
    """Baseline: top-down grasps at the cloud's centroid (normals not used)."""
    grasps = centroid_grasps(
        view.points_world, geometry, view.table_top_z, planner, view.scene_obstacles_world
    )
    return grasps, None


def propose_antipodal(
    view: CloudView,
    geometry: GripperGeometry,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> Proposal:
    """Baseline: random antipodal point pairs of the cloud."""
    rng = rng_for(seed, "chain", "plan")
    grasps = antipodal_grasps(
        view.points_world,
        view.normals_world,
        geometry,
        view.table_top_z,
        rng,
        planner,
        view.scene_obstacles_world,
    )
    return grasps, None
