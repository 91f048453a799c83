"""Grasp proposals on plain arrays: a handle detector (or a baseline) and the planner.

The chain (:func:`simgrasp.grasping.trials.chain.run_chain`) and the gymnasium policy
(:class:`simgrasp.envs.policy.DetectorPolicy`) both plan through :func:`plan_grasps`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.planner import (
    GripperGeometry,
    antipodal_grasps,
    centroid_grasps,
    grasps_from_handles,
)
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grasping.trials.chain_config import ChainDetectorConfig
from simgrasp.handles import detect
from simgrasp.handles.detection import Detection
from simgrasp.seeding import rng_for

MIN_CLOUD_POINTS = 10
"""Clouds with fewer points than this get no grasp proposals."""


def plan_grasps(
    points_world: NDArray[np.float64],
    normals_world: NDArray[np.float64],
    cameras_world: NDArray[np.float64],
    geometry: GripperGeometry,
    table_top_z: float,
    detector: ChainDetectorConfig,
    planner: PlannerConfig,
    seed: int,
) -> tuple[list[Grasp], Detection | None]:
    """Ranked grasps (best first) from ``detector`` (a handle detector or a baseline).

    Args:
        points_world: (N, 3) object cloud, world frame, meters.
        normals_world: (N, 3) unit normals turned toward the camera that saw each point (as
            :func:`simgrasp.scenes.observe.viewpoint_normals` makes them); the centroid
            baseline ignores them.
        cameras_world: (K, 3) optical centers of the cameras that saw the cloud (world frame,
            meters), for the planner's view bonus.
        geometry: the gripper's collision boxes; its opening is the detector's too.
        table_top_z: world z of the table top (m).
        detector: which proposer, with its thresholds.
        planner: grasp sampling and ranking.
        seed: seeds the detector's sampling and the planner's approach jitter.

    Returns:
        The grasps and, for the handle detectors, their detection (None for the baselines).
    """
    rng = rng_for(seed, "chain", "plan")
    if detector.kind == "centroid":
        return centroid_grasps(points_world, geometry, table_top_z, planner), None
    if detector.kind == "random":
        grasps = antipodal_grasps(points_world, normals_world, geometry, table_top_z, rng, planner)
        return grasps, None
    detection = detect(
        points_world,
        normals_world,
        detector.for_gripper(geometry.max_opening),
        seed,
        detector=detector.kind,
    )
    grasps = grasps_from_handles(
        detection.handles,
        points_world,
        cameras_world,
        geometry,
        table_top_z,
        rng,
        planner,
        detector.kind,
    )
    return grasps, detection
