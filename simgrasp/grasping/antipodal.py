"""Antipodal grasp sampling on an object's mesh, as ACRONYM does (Eppner et al. 2021).

For each candidate: a point ``p`` on the surface (area-uniform) with outward normal ``n``; a ray
from ``p`` along ``-n`` finds the opposite contact ``q`` where it leaves the object. The pair is
kept when the jaws can span it (``min_width`` <= |q - p| <= the gripper's opening minus twice
``width_margin``) and the closing line ``q - p`` lies in both contacts' friction cones (half
angle ``atan(friction)``). The TCP goes to the contacts' midpoint, shifted along the approach by
a random depth; +y (the closing direction) is ``q - p``; the approach is a random direction
perpendicular to it. The jaws open by the contact width plus twice ``width_margin``. A grasp
whose open gripper (the planner's finger and palm boxes,
:class:`~simgrasp.grasping.planner.GripperGeometry`) holds any of the mesh's surface samples
is dropped. With a table (``world_T_object``, the object's rest pose in a scene), so is a grasp
whose gripper would reach below the table top at the grasp or the pre-grasp (the planner's
:func:`~simgrasp.grasping.planner.table_margin`): the set then suits that scene. Everything is
in the object's mesh frame (meters); every draw comes from the seed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.grasping.planner import (
    GripperGeometry,
    PlannerConfig,
    gripper_distances,
    table_margin,
)
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
    collision_points: int = 3000
    """Surface samples of the mesh the open gripper must not hold."""
    batch: int = 512
    """Candidates drawn per round."""
    max_rounds: int = 200
    """Rounds before giving up on reaching the requested count."""

    def __post_init__(self) -> None:
        if not self.friction > 0 or not self.min_width > 0 or self.width_margin < 0:
            raise ValueError("AntipodalConfig friction and min_width must be > 0, margin >= 0")
        if self.max_depth < 0 or self.batch < 1 or self.max_rounds < 1:
            raise ValueError("AntipodalConfig max_depth >= 0, batch and max_rounds >= 1")


def _contact_pairs(
    mesh: trimesh.Trimesh, count: int, rng: np.random.Generator, config: AntipodalConfig
) -> tuple[NDArray, NDArray]:
    """(K, 3) first contacts and (K, 3) their opposite contacts passing the cone test."""
    points, faces = trimesh.sample.sample_surface(mesh, count, seed=rng)
    normals = mesh.face_normals[faces]
    origins = points - 1e-5 * normals
    hits, ray_index, hit_faces = mesh.ray.intersects_location(
        origins, -normals, multiple_hits=False
    )
    p, n_p, n_q = points[ray_index], normals[ray_index], mesh.face_normals[hit_faces]
    span = hits - p
    width = np.linalg.norm(span, axis=1)
    axis = span / np.maximum(width, 1e-12)[:, None]
    cos_limit = np.cos(np.arctan(config.friction))
    keep = (width >= config.min_width) & (np.sum(axis * -n_p, axis=1) >= cos_limit)
    keep &= np.sum(axis * n_q, axis=1) >= cos_limit
    return p[keep], hits[keep]


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

    def clears(self, object_T_tcp: NDArray[np.float64], geometry: GripperGeometry) -> bool:
        """Whether the gripper at this grasp and its pre-grasp stays above the top."""
        world_T_tcp = self.world_T_object @ object_T_tcp
        return table_margin(world_T_tcp, geometry, self.top_z, PlannerConfig()) >= 0.0


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
    if count < 1:
        raise ValueError(f"--n must be a positive number of grasps, got {count}")
    rng = rng_for(seed, "antipodal")
    obstacles, _ = trimesh.sample.sample_surface(mesh, config.collision_points, seed=rng)
    poses, widths = [], []
    for _ in range(config.max_rounds):
        first, second = _contact_pairs(mesh, config.batch, rng, config)
        opening = np.linalg.norm(second - first, axis=1) + 2 * config.width_margin
        fits = opening <= geometry.max_opening
        candidates = _poses(first[fits], second[fits], rng, config.max_depth)
        if table is not None:  # a quick pre-filter: approaches rising steeply start under it
            world_approach_z = (table.world_T_object[2, :3] @ candidates[:, :3, 2].T).T
            fits[fits] = world_approach_z < 0.5
            candidates = candidates[world_approach_z < 0.5]
        for pose, width in zip(candidates, opening[fits], strict=True):
            open_geometry = replace(geometry, max_opening=float(width))
            if table is not None and not table.clears(pose, open_geometry):
                continue
            if np.all(gripper_distances(pose, obstacles, open_geometry) > 0.0):
                poses.append(pose)
                widths.append(width)
        if len(poses) >= count:
            break
    if not poses:
        raise ValueError("no antipodal grasp fits this object and gripper")
    return np.asarray(poses[:count]), np.asarray(widths[:count])
