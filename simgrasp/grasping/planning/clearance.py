"""The open gripper against a cloud: its boxes, the points it must keep clear of and how near
they come. All in the world frame (the TCP frame for the boxes), meters; the grasp convention
is :mod:`simgrasp.grasping.planning.planner`'s."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grippers.geometry import GripperGeometry


def gripper_boxes(
    geometry: GripperGeometry, opening: float, reach: float | None = None
) -> list[tuple[NDArray, NDArray]]:
    """(center, half extents) of the fingers and palm in the TCP frame; the fingertips reach
    ``reach`` (m, default ``geometry.pad_reach``) past the TCP."""
    reach = geometry.pad_reach if reach is None else reach
    half_len = (geometry.finger_length + reach) / 2
    z_finger = reach - half_len
    y_finger = opening / 2 + geometry.finger_thickness / 2
    finger_half = np.array([geometry.finger_width / 2, geometry.finger_thickness / 2, half_len])
    palm_half = np.asarray(geometry.palm_size) / 2
    palm_center = np.array([0.0, 0.0, -geometry.finger_length - palm_half[2]])
    return [
        (np.array([0.0, y_finger, z_finger]), finger_half),
        (np.array([0.0, -y_finger, z_finger]), finger_half),
        (palm_center, palm_half),
    ]


def gripper_distances(
    world_T_tcp: NDArray, points_world: NDArray, geometry: GripperGeometry
) -> NDArray[np.float64]:
    """(N,) distance (m) from each cloud point to the nearest box of the open gripper at
    ``world_T_tcp`` (0 inside one)."""
    tcp_T_world = np.linalg.inv(world_T_tcp)
    points_tcp = points_world @ tcp_T_world[:3, :3].T + tcp_T_world[:3, 3]
    distances = np.full(len(points_tcp), np.inf)
    for center, half in gripper_boxes(geometry, geometry.max_opening):
        outside = np.maximum(np.abs(points_tcp - center) - half, 0.0)
        np.minimum(distances, np.linalg.norm(outside, axis=1), out=distances)
    return distances


def collides(
    world_T_tcp: NDArray, points_world: NDArray, geometry: GripperGeometry, limit: int
) -> bool:
    """Whether more than ``limit`` cloud points fall inside the open gripper's boxes."""
    return inside_count(gripper_distances(world_T_tcp, points_world, geometry)) > limit


def obstacle_points(
    points_world: NDArray[np.float64], config: PlannerConfig
) -> NDArray[np.float64]:
    """The cloud points the gripper must keep clear of: those with at least
    ``config.obstacle_min_neighbors`` other points within ``config.obstacle_radius`` (isolated
    points are flying pixels, not surfaces)."""
    if config.obstacle_radius <= 0 or len(points_world) == 0:
        return points_world
    # The point itself and its obstacle_min_neighbors nearest others: its last is within the
    # radius exactly when the ball holds more than obstacle_min_neighbors points (itself
    # included); the k nearest are cheaper than counting every point in the ball.
    nearest = config.obstacle_min_neighbors + 1
    if nearest > len(points_world):
        return points_world[:0]
    distances, _ = cKDTree(points_world).query(
        points_world, k=[nearest], distance_upper_bound=np.nextafter(config.obstacle_radius, 1.0)
    )
    return points_world[distances[:, 0] <= config.obstacle_radius]


def planning_obstacles(
    points_world: NDArray[np.float64],
    config: PlannerConfig,
    scene_world: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """:func:`obstacle_points` of the object cloud and, in clutter, of the rest of the scene
    (``scene_world``, (M, 3) world frame, m)."""
    if scene_world is None or len(scene_world) == 0:
        return obstacle_points(points_world, config)
    return obstacle_points(np.concatenate([points_world, scene_world]), config)


NEAR_QUERY_POINTS = 8_000
"""An obstacle cloud larger than this (a cluttered scene's) is searched through a KD-tree for
the points near each candidate gripper; a smaller one (an object's) is tested whole."""


def near_gripper(
    world_T_tcp: NDArray,
    obstacles_world: NDArray,
    tree: cKDTree | None,
    geometry: GripperGeometry,
    reach: float,
) -> NDArray[np.float64]:
    """The obstacle points (world frame) that can lie within ``reach`` (m) of the open
    gripper's boxes at ``world_T_tcp``: those within ``reach`` of a box's bounding sphere
    (``tree`` is over ``obstacles_world``), in cloud order; the whole cloud without a tree.
    Every point left out is farther than ``reach`` from every box."""
    if tree is None:
        return obstacles_world
    found = [
        tree.query_ball_point(
            world_T_tcp[:3, :3] @ center + world_T_tcp[:3, 3],
            float(np.linalg.norm(half)) + reach + 1e-6,
        )
        for center, half in gripper_boxes(geometry, geometry.max_opening)
    ]
    return obstacles_world[np.unique(np.concatenate(found).astype(np.intp))]


def inside_count(distances: NDArray[np.float64]) -> int:
    """How many of a cloud's gripper distances are 0 (points inside a box)."""
    return int(np.count_nonzero(distances == 0.0))
