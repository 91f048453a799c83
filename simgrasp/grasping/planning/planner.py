"""From handle hypotheses (or baselines) to ranked parallel-jaw grasp poses.

Grasp convention (see README): ``world_T_tcp`` with the TCP midway between the finger pads,
+z the approach direction (palm toward object) and +y the direction in which the jaws open and
close. For a handle, the jaws close across it: +x lies along the handle axis, and approaches
are sampled around that axis.

Candidates whose open fingers or palm would collide with the observed cloud, or reach below
the table top, are rejected. All inputs are in the world frame, meters.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.grasping.grasp import Grasp, tcp_pose
from simgrasp.grasping.planning.approaches import approach_angles, handle_approaches
from simgrasp.grasping.planning.clearance import (
    NEAR_QUERY_POINTS,
    collides,
    gripper_boxes,
    gripper_distances,
    inside_count,
    near_gripper,
    planning_obstacles,
)
from simgrasp.grasping.planning.grasp_points import GraspPoint, axis_points, narrowed, root_point
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.handles.core.detection import Handle
from simgrasp.transforms import orthonormal


def table_margin(
    world_T_tcp: NDArray, geometry: GripperGeometry, table_z: float, config: PlannerConfig
) -> float:
    """Least height (m) of the gripper boxes above the table beyond the required clearance:
    the open gripper at the pre-grasp keeps ``table_clearance``; at the grasp the gripper with
    its fingertips at their closed reach (which contains the open fingers) keeps
    ``grasp_table_clearance``. Negative when one would be too low."""
    signs = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
    closed_reach = max(geometry.pad_reach, geometry.closed_pad_reach)
    checks = (
        (0.0, closed_reach, config.grasp_table_clearance),
        (config.pregrasp_distance, geometry.pad_reach, config.table_clearance),
    )
    margin = np.inf
    for back, reach, clearance in checks:
        for center, half in gripper_boxes(geometry, geometry.max_opening, reach):
            corners_tcp = center + signs * half - np.array([0.0, 0.0, back])
            corners_world = corners_tcp @ world_T_tcp[:3, :3].T + world_T_tcp[:3, 3]
            margin = min(margin, float(corners_world[:, 2].min()) - table_z - clearance)
    return margin


def above_table(
    world_T_tcp: NDArray, geometry: GripperGeometry, table_z: float, config: PlannerConfig
) -> NDArray | None:
    """``world_T_tcp`` if it clears the table, else backed off along its approach by at most
    ``config.max_tcp_shift`` until it does, else None."""
    margin = table_margin(world_T_tcp, geometry, table_z, config)
    if margin >= 0:
        return world_T_tcp
    rise_per_meter = -world_T_tcp[2, 2]
    if rise_per_meter <= 1e-6 or -margin / rise_per_meter > config.max_tcp_shift:
        return None
    shifted = world_T_tcp.copy()
    shifted[:3, 3] -= world_T_tcp[:3, 2] * (-margin / rise_per_meter + 1e-4)
    return shifted


def _rank(approach: NDArray, position: NDArray, cameras: NDArray, config: PlannerConfig) -> float:
    view = position - cameras
    view /= np.linalg.norm(view, axis=1, keepdims=True)
    return config.view_weight * float(np.max(view @ approach)) + config.top_weight * float(
        -approach[2]
    )


def grasps_from_handles(
    handles: Sequence[Handle],
    points_world: NDArray[np.float64],
    cameras_world: NDArray[np.float64],
    geometry: GripperGeometry,
    table_z: float,
    rng: np.random.Generator,
    config: PlannerConfig = PlannerConfig(),
    source: str = "quadric",
    scene_obstacles_world: NDArray[np.float64] | None = None,
) -> list[Grasp]:
    """Grasps closing across each handle, best first.

    Grasp points are the handle's center and the point of the handle nearest the cloud's
    centroid (pads kept a pad width inside the detected stretch), and on a curved handle its
    root (:func:`root_point`), closed across the handle's local direction there with the
    jaws opened to its width plus ``config.root_opening_margin``. Approaches are sampled
    around the axis: the steepest downward approach first (exactly, so a handle lying flat on
    the table keeps its one feasible top-down grasp), then evenly spaced ones turned by a
    seeded jitter, each also tilted down by ``config.approach_pitches`` toward the lower end of
    a sloping axis; only when none of them is clear, the same approaches are tilted down by
    ``config.fallback_pitches`` (steeper, over the neighbors around a standing handle); only
    when none of those is clear either, both passes are tried again with the jaws opened to
    each handle's width plus each of ``config.fallback_opening_margins`` (a finger inside the
    loop of a mug's strap lying flat, where the fully open jaws reach its body). A grasp's
    score is the handle's score relative to the best handle's (1 for the best) plus bonuses
    for approaching from the camera's side, from above and with the open gripper clear of the
    cloud, less penalties for backing off the handle to clear the table and for the lever arm
    to the centroid along the handle.
    """
    handles = list(handles)[: config.max_handles]
    obstacles_world = planning_obstacles(points_world, config, scene_obstacles_world)
    centroid = points_world.mean(axis=0) if len(points_world) else None
    plan = _HandlePlan(
        handles,
        [approach_angles(rng, config) for _ in handles],
        [root_point(handle, centroid, geometry, config) for handle in handles],
        centroid,
        obstacles_world,
        cKDTree(obstacles_world) if len(obstacles_world) > NEAR_QUERY_POINTS else None,
        np.atleast_2d(np.asarray(cameras_world, dtype=float)),
    )
    passes = ((config.approach_pitches, True), (config.fallback_pitches, False))
    for margin in (None, *config.fallback_opening_margins):
        for pitches, level in passes:
            grasps = plan.grasps(pitches, level, margin, geometry, table_z, config, source)
            if grasps:
                return sorted(grasps, key=lambda g: -g.score)
    return []


@dataclass(frozen=True)
class _HandlePlan:
    """What every pass of :func:`grasps_from_handles` shares: the handles (best first), their
    approach angles (rad), their root grasp points (:func:`root_point`, None for a straight
    handle), the cloud's centroid, the obstacle points (and a KD-tree over them when they are
    many, else None) and the cameras (world frame, m)."""

    handles: list[Handle]
    angles: list[NDArray[np.floating]]
    roots: list[GraspPoint | None]
    centroid: NDArray[np.float64] | None
    obstacles_world: NDArray[np.float64]
    obstacles_tree: cKDTree | None
    cameras_world: NDArray[np.float64]

    def grasps(
        self,
        pitches: Sequence[float],
        level: bool,
        margin: float | None,
        geometry: GripperGeometry,
        table_z: float,
        config: PlannerConfig,
        source: str,
    ) -> list[Grasp]:
        """The clear grasps of one pass: approaches tilted by ``pitches`` (``level``: the
        untilted ones around a flat axis too), the jaws fully open (``margin`` None) or opened
        to each handle's width plus ``margin`` (m) on each side."""
        best_score = max((h.score for h in self.handles), default=1.0) or 1.0
        grasps: list[Grasp] = []
        for handle, handle_angles, root in zip(self.handles, self.angles, self.roots, strict=True):
            jaws = geometry if margin is None else narrowed(geometry, handle.width, margin)
            points = axis_points(handle, self.centroid, geometry, jaws)
            points += [] if root is None else [root]
            for point in points:
                for around, approach in handle_approaches(
                    point.axis, handle_angles, pitches, config, level
                ):
                    grasp = _scored_grasp(
                        (point.position, np.cross(around, point.axis), approach),
                        handle.score / best_score,
                        point.lever,
                        (self.obstacles_world, self.obstacles_tree),
                        self.cameras_world,
                        point.jaws,
                        table_z,
                        config,
                        source,
                    )
                    if grasp is not None:
                        grasps.append(grasp)
        return grasps


def _scored_grasp(
    position_closing_approach: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    handle_score: float,
    lever: float,
    obstacles: tuple[NDArray[np.float64], cKDTree | None],
    cameras: NDArray[np.float64],
    geometry: GripperGeometry,
    table_z: float,
    config: PlannerConfig,
    source: str,
) -> Grasp | None:
    """The grasp at a TCP ``position`` with jaws ``closing`` and ``approach`` directions
    (world frame; backed off to clear the table) with its rank score
    (:func:`grasps_from_handles`), or None when it cannot clear the table or the open
    gripper holds cloud points of ``obstacles`` (world frame, and a KD-tree over them or
    None); ``handle_score`` is relative to the best handle's."""
    position, closing, approach = position_closing_approach
    pose = above_table(tcp_pose(position, closing, approach), geometry, table_z, config)
    if pose is None:
        return None
    # points beyond clearance_cap of every box change neither the count nor the clearance
    near = near_gripper(pose, *obstacles, geometry, config.clearance_cap)
    distances = gripper_distances(pose, near, geometry)
    if inside_count(distances) > config.max_colliding_points:
        return None
    clearance = min(float(distances.min(initial=np.inf)), config.clearance_cap)
    shift = float(np.linalg.norm(pose[:3, 3] - position))
    score = (
        handle_score
        + _rank(approach, position, cameras, config)
        + config.clearance_weight * clearance / config.clearance_cap
        - config.shift_weight * shift / config.max_tcp_shift
        - config.lever_weight * lever / 0.1
    )
    return Grasp(world_T_tcp=pose, width=geometry.max_opening, score=score, source=source)


def top_down_above_table(
    position_world: ArrayLike,
    closing_world: ArrayLike,
    geometry: GripperGeometry,
    table_z: float,
    config: PlannerConfig,
) -> NDArray[np.float64]:
    """``world_T_tcp`` approaching straight down (world -z) at ``position_world``, jaws along
    ``closing_world``, raised (never lowered) until the open gripper clears the table."""
    pose = tcp_pose(position_world, closing_world, (0.0, 0.0, -1.0))
    pose[2, 3] -= min(table_margin(pose, geometry, table_z, config), 0.0)
    return pose


def centroid_grasps(
    points_world: NDArray[np.float64],
    geometry: GripperGeometry,
    table_z: float,
    config: PlannerConfig = PlannerConfig(),
    scene_obstacles_world: NDArray[np.float64] | None = None,
) -> list[Grasp]:
    """Baseline: top-down grasps at the cloud centroid, jaws across the narrower horizontal
    extent first, then rotated in 30 degree steps."""
    centroid = points_world.mean(axis=0)
    spread = np.cov((points_world[:, :2] - centroid[:2]).T)
    _, vectors = np.linalg.eigh(spread)
    narrow = np.append(vectors[:, 0], 0.0)
    down = np.array([0.0, 0.0, -1.0])
    obstacles = planning_obstacles(points_world, config, scene_obstacles_world)
    grasps = []
    for step in range(6):
        angle = np.radians(30 * step)
        closing = np.cos(angle) * narrow + np.sin(angle) * np.cross(down, narrow)
        pose = top_down_above_table(centroid, closing, geometry, table_z, config)
        if collides(pose, obstacles, geometry, config.max_colliding_points):
            continue
        grasps.append(
            Grasp(
                world_T_tcp=pose,
                width=geometry.max_opening,
                score=1.0 - step / 6,
                source="centroid",
            )
        )
    return grasps


def antipodal_grasps(
    points_world: NDArray[np.float64],
    normals_world: NDArray[np.float64],
    geometry: GripperGeometry,
    table_z: float,
    rng: np.random.Generator,
    config: PlannerConfig = PlannerConfig(),
    scene_obstacles_world: NDArray[np.float64] | None = None,
) -> list[Grasp]:
    """Baseline: random antipodal point pairs (normals opposed along the line joining them,
    closer than the opening), approached from a random direction perpendicular to the jaws."""
    count = len(points_world)
    obstacles = planning_obstacles(points_world, config, scene_obstacles_world)
    first = rng.integers(0, count, config.antipodal_samples)
    second = rng.integers(0, count, config.antipodal_samples)
    grasps = []
    for i, j in zip(first, second, strict=True):
        line = points_world[j] - points_world[i]
        distance = float(np.linalg.norm(line))
        if not 0.005 < distance < geometry.max_opening * 0.9:
            continue
        line /= distance
        if (
            normals_world[i] @ -line < config.antipodal_cos
            or normals_world[j] @ line < config.antipodal_cos
        ):
            continue
        u, v = orthonormal(line)
        angle = rng.uniform(0, 2 * np.pi)
        approach = np.cos(angle) * u + np.sin(angle) * v
        pose = above_table(
            tcp_pose((points_world[i] + points_world[j]) / 2, line, approach),
            geometry,
            table_z,
            config,
        )
        if pose is None:
            continue
        if collides(pose, obstacles, geometry, config.max_colliding_points):
            continue
        grasps.append(
            Grasp(
                world_T_tcp=pose,
                width=geometry.max_opening,
                score=float(-approach[2]),
                source="random",
            )
        )
    return sorted(grasps, key=lambda g: -g.score)
