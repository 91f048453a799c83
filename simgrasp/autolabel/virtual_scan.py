"""Dense virtual scans of a mesh: what an ideal depth sensor sees of it from many directions.

Each view casts a square grid of parallel rays (an orthographic scan) at the mesh from one
direction of a Fibonacci sphere around the mesh's bounding-box center, with Open3D's
``RaycastingScene``; the first hits are the view's points, with the hit faces' normals turned
toward the sensor. Everything is in the mesh's own frame, meters.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Any

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.config.checks import Checked, Positive, PositiveInt, Range
from simgrasp.errors import SimgraspError


@dataclass(frozen=True)
class ScanConfig(Checked):
    """How the mesh is scanned."""

    views: PositiveInt = 24
    """Scan directions, spread evenly over the sphere (Fibonacci lattice)."""
    resolution: Positive = 0.001
    """Spacing of the ray grid (m) on the mesh ..."""
    max_rays_per_side: Annotated[int, Range(ge=2)] = 400
    """... coarsened so a side of the grid has at most this many rays (large meshes)."""


@dataclass(frozen=True)
class View:
    """One scan: ``points`` (N, 3) and unit ``normals`` (N, 3) facing ``viewpoint`` (3,), a
    point on the sensor side of the mesh from which the scan looked (mesh frame, m)."""

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    viewpoint: NDArray[np.float64]


def sphere_directions(count: int) -> NDArray[np.float64]:
    """``count`` unit vectors spread evenly over the sphere (Fibonacci lattice)."""
    i = np.arange(count) + 0.5
    polar = np.arccos(1.0 - 2.0 * i / count)
    azimuth = np.pi * (1.0 + 5.0**0.5) * i
    return np.stack(
        [np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)], axis=1
    )


def scan_mesh(mesh: trimesh.Trimesh, config: ScanConfig | None = None) -> list[View]:
    """Scan ``mesh`` (its frame, m) from ``config.views`` directions; views that see nothing
    are left out."""
    from simgrasp.perception import import_open3d

    o3d = import_open3d()
    config = config or ScanConfig()
    if len(mesh.faces) == 0:
        raise SimgraspError("cannot scan a mesh without faces")
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(
        o3d.core.Tensor(np.asarray(mesh.vertices, np.float32)),
        o3d.core.Tensor(np.asarray(mesh.faces, np.uint32)),
    )
    center = mesh.bounds.mean(axis=0)
    radius = float(np.linalg.norm(mesh.extents)) / 2.0
    spacing = max(config.resolution, 2.0 * radius / config.max_rays_per_side)
    offsets = np.arange(-radius, radius + spacing / 2, spacing)
    views = []
    for direction in sphere_directions(config.views):
        view = _scan_one(o3d, scene, center + 3.0 * radius * direction, -direction, offsets)
        if len(view.points):
            views.append(view)
    return views


def _scan_one(
    o3d: Any,
    scene: Any,
    viewpoint: NDArray[np.float64],
    forward: NDArray[np.float64],
    offsets: NDArray[np.float64],
) -> View:
    """Cast a grid of rays along ``forward`` from the plane through ``viewpoint``."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(forward[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(forward, helper)
    right /= np.linalg.norm(right)
    up = np.cross(forward, right)
    u, v = np.meshgrid(offsets, offsets)
    origins = viewpoint + u.reshape(-1, 1) * right + v.reshape(-1, 1) * up
    rays = np.hstack([origins, np.broadcast_to(forward, origins.shape)]).astype(np.float32)
    hits = scene.cast_rays(o3d.core.Tensor(rays))
    distance = hits["t_hit"].numpy().astype(np.float64)
    seen = np.isfinite(distance)
    points = origins[seen] + distance[seen, None] * forward
    normals = hits["primitive_normals"].numpy()[seen].astype(np.float64)
    normals[normals @ forward > 0] *= -1.0
    return View(points, normals, viewpoint)
