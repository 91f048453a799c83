"""Antipodal grasp sampling on an object's mesh, as ACRONYM does (Eppner et al. 2021).

For each candidate: a point ``p`` on the surface (area-uniform) with outward normal ``n``; a ray
from ``p`` along ``-n`` finds the opposite contact ``q`` where it leaves the object. The pair is
kept when the jaws can span it (``min_width`` <= |q - p| <= the gripper's opening minus twice
``width_margin``) and the closing line ``q - p`` lies in both contacts' friction cones (half
angle ``atan(friction)``). The TCP goes to the contacts' midpoint, shifted along the approach by
a random depth; +y (the closing direction) is ``q - p``; the approach is a random direction
perpendicular to it. The jaws open by the contact width plus twice ``width_margin``. A grasp
whose open gripper (the planner's finger and palm boxes,
:class:`~simgrasp.grasping.planning.planner.GripperGeometry`) holds any of the mesh's surface
samples is dropped. With a table (``world_T_object``, the object's rest pose in a scene), so is a
grasp whose gripper would reach below the table top at the grasp or the pre-grasp (the planner's
:func:`~simgrasp.grasping.planning.planner.table_margin`, vectorized): the set then suits that
scene. Everything is in the object's mesh frame (meters); every draw comes from the seed. Contacts
are found with Open3D's ray casting (trimesh's took ~2.5 s per 512 rays on a YCB scan).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grasping.planning.clearance import gripper_distances
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.seeding import rng_for


@dataclass(frozen=True)
class AntipodalConfig:
    """Antipodal sampler settings (meters, radians)."""

    friction: float = 0.5
    """Friction coefficient of the cone test (half angle ``atan(friction)``, 26.6 degrees)."""
    min_width: float = 0.002
    """Contact pairs closer than this (m) are rejected (a ray grazing a thin shell)."""
    width_margin: float = 0.01
    """The jaws open this much (m) wider than the contacts on each side."""
    max_depth: float = 0.01
    """The TCP is shifted along the approach by a uniform draw in +-this (m)."""
    approaches_per_pair: int = 8
    """Random approach directions tried around each contact pair's closing line."""
    collision_points: int = 3000
    """Surface samples of the mesh the open gripper must not hold."""
    batch: int = 512
    """Surface points drawn per round."""
    max_rounds: int = 200
    """Rounds before giving up on reaching the requested count."""

    def __post_init__(self) -> None:
        if not self.friction > 0 or not self.min_width > 0 or self.width_margin < 0:
            raise SimgraspError("AntipodalConfig friction and min_width must be > 0, margin >= 0")
        if self.max_depth < 0 or min(self.batch, self.max_rounds, self.approaches_per_pair) < 1:
            raise SimgraspError("AntipodalConfig max_depth >= 0; batch, rounds, approaches >= 1")


class _RayCaster:
    """First hits of rays on a mesh (Open3D's ray casting; its normals are the faces')."""

    def __init__(self, mesh: trimesh.Trimesh) -> None:
        from simgrasp.perception import import_open3d

        o3d = import_open3d()
        self.o3d = o3d
        self.scene = o3d.t.geometry.RaycastingScene()
        self.scene.add_triangles(
            o3d.core.Tensor(np.asarray(mesh.vertices, dtype=np.float32)),
            o3d.core.Tensor(np.asarray(mesh.faces, dtype=np.uint32)),
        )
        self.face_normals = np.asarray(mesh.face_normals)

    def cast(self, origins: NDArray, directions: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """(hit mask, (N, 3) hit points, (N, 3) hit faces' outward normals)."""
        rays = np.hstack([origins, directions]).astype(np.float32)
        answer = self.scene.cast_rays(self.o3d.core.Tensor(rays))
        distance = answer["t_hit"].numpy().astype(float)
        hit = np.isfinite(distance)
        faces = np.where(hit, answer["primitive_ids"].numpy(), 0).astype(np.int64)
        points = origins + np.where(hit, distance, 0.0)[:, None] * directions
        return hit, points, self.face_normals[faces]


def _contact_pairs(
    mesh: trimesh.Trimesh,
    caster: _RayCaster,
    count: int,
    rng: np.random.Generator,
    config: AntipodalConfig,
) -> tuple[NDArray, NDArray]:
    """(K, 3) first contacts and (K, 3) their opposite contacts passing the cone test."""
    points, faces = trimesh.sample.sample_surface(mesh, count, seed=rng)
    normals = mesh.face_normals[faces]
    hit, hits, n_q = caster.cast(points - 1e-5 * normals, -normals)
    span = hits - points
    width = np.linalg.norm(span, axis=1)
    axis = span / np.maximum(width, 1e-12)[:, None]
    cos_limit = np.cos(np.arctan(config.friction))
    keep = hit & (width >= config.min_width) & (np.sum(axis * -normals, axis=1) >= cos_limit)
    keep &= np.sum(axis * n_q, axis=1) >= cos_limit
    return points[keep], hits[keep]


def _poses(
    first: NDArray, second: NDArray, rng: np.random.Generator, max_depth: float
) -> NDArray[np.float64]:
    """(K, 4, 4) TCP poses across each contact pair with random approach and depth."""
    closing = second - first
    closing /= np.linalg.norm(closing, axis=1, keepdims=True)
    helper = np.where(np.abs(closing[:, [2]]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    u = np.cross(closing, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(closing, u)
    angle = rng.uniform(0.0, 2 * np.pi, len(first))[:, None]
    approach = np.cos(angle) * u + np.sin(angle) * v
    depth = rng.uniform(-max_depth, max_depth, len(first))[:, None]
    poses = np.tile(np.eye(4), (len(first), 1, 1))
    poses[:, :3, 0] = np.cross(closing, approach)
    poses[:, :3, 1] = closing
    poses[:, :3, 2] = approach
    poses[:, :3, 3] = (first + second) / 2 + depth * approach
    return poses


@dataclass(frozen=True)
class Table:
    """A table top under the object: ``world_T_object`` its rest pose, ``top_z`` the top's
    height (world frame, m)."""

    world_T_object: NDArray[np.float64]
    top_z: float = 0.0

    def margins(
        self, object_T_tcp: NDArray[np.float64], openings: NDArray, geometry: GripperGeometry
    ) -> NDArray[np.float64]:
        """(K,) the planner's :func:`~simgrasp.grasping.planning.planner.table_margin` of K grasps
        opened ``openings`` (m), vectorized: the least height of the gripper's boxes above the
        top beyond the clearance, at the grasp (closed fingertip reach) and at the pre-grasp;
        negative when one would be too low."""
        planner = PlannerConfig()
        world_T_tcp = self.world_T_object @ object_T_tcp
        rows, tcp_z = world_T_tcp[:, 2, :3], world_T_tcp[:, 2, 3]
        closed_reach = max(geometry.pad_reach, geometry.closed_pad_reach)
        checks = (
            (0.0, closed_reach, planner.grasp_table_clearance),
            (planner.pregrasp_distance, geometry.pad_reach, planner.table_clearance),
        )
        margin = np.full(len(world_T_tcp), np.inf)
        palm_half = np.asarray(geometry.palm_size) / 2
        for back, reach, clearance in checks:
            half_length = (geometry.finger_length + reach) / 2
            finger_half = np.array(
                [geometry.finger_width / 2, geometry.finger_thickness / 2, half_length]
            )
            finger_y = openings / 2 + geometry.finger_thickness / 2
            boxes = [
                (np.column_stack([0 * finger_y, sign * finger_y, 0 * finger_y]), finger_half)
                for sign in (1.0, -1.0)
            ]
            boxes = [(c + [0.0, 0.0, reach - half_length - back], h) for c, h in boxes]
            palm_z = -geometry.finger_length - palm_half[2] - back
            boxes.append((np.array([[0.0, 0.0, palm_z]]), palm_half))
            for center, half in boxes:
                lowest = tcp_z + np.sum(rows * center, axis=1) - np.abs(rows) @ half
                np.minimum(margin, lowest - self.top_z - clearance, out=margin)
        return margin


def _candidates(
    mesh: trimesh.Trimesh,
    caster: _RayCaster,
    geometry: GripperGeometry,
    rng: np.random.Generator,
    config: AntipodalConfig,
) -> tuple[NDArray, NDArray]:
    """One round's (K, 4, 4) poses and (K,) openings that fit the gripper's stroke."""
    first, second = _contact_pairs(mesh, caster, config.batch, rng, config)
    opening = np.linalg.norm(second - first, axis=1) + 2 * config.width_margin
    fits = opening <= geometry.max_opening
    first = np.repeat(first[fits], config.approaches_per_pair, axis=0)
    second = np.repeat(second[fits], config.approaches_per_pair, axis=0)
    opening = np.repeat(opening[fits], config.approaches_per_pair)
    return _poses(first, second, rng, config.max_depth), opening


def grasp_count(count: object) -> int:
    """``count``, a number of grasps to sample, checked to be a positive integer."""
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 1:
        raise SimgraspError(f"count must be a positive integer, got {count!r}")
    return int(count)


def sample_antipodal(
    mesh: trimesh.Trimesh,
    geometry: GripperGeometry,
    count: int,
    seed: int,
    config: AntipodalConfig | None = None,
    table: Table | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``count`` collision-free antipodal grasps on ``mesh``: (N, 4, 4) ``object_T_tcp`` and
    (N,) jaw openings (m), clear of ``table`` if given. Fewer (with a ValueError when none) if
    ``max_rounds`` run out."""
    config = config or AntipodalConfig()
    count = grasp_count(count)
    rng = rng_for(seed, "antipodal")
    obstacles, _ = trimesh.sample.sample_surface(mesh, config.collision_points, seed=rng)
    caster = _RayCaster(mesh)
    poses, widths = [], []
    for _ in range(config.max_rounds):
        candidates, openings = _candidates(mesh, caster, geometry, rng, config)
        if table is not None:
            clear = table.margins(candidates, openings, geometry) >= 0.0
            candidates, openings = candidates[clear], openings[clear]
        for pose, width in zip(candidates, openings, strict=True):
            open_geometry = replace(geometry, max_opening=float(width))
            if np.all(gripper_distances(pose, obstacles, open_geometry) > 0.0):
                poses.append(pose)
                widths.append(width)
        if len(poses) >= count:
            break
    if not poses:
        raise SimgraspError("no antipodal grasp fits this object and gripper")
    return np.asarray(poses[:count]), np.asarray(widths[:count])
