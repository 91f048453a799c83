"""Point clouds sampled from a mesh surface, with exact face normals."""

from __future__ import annotations

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError


def sample_surface(
    mesh: trimesh.Trimesh, count: int, rng: np.random.Generator
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Sample ``count`` points uniformly by area on ``mesh`` (trimesh ``sample_surface``).

    Args:
        mesh: the surface, in its own frame (meters).
        count: number of points.
        rng: seeded generator; one integer seed for trimesh is drawn from it, so the same
            generator state gives the same cloud.

    Returns:
        ``(points, normals)``: (count, 3) points in the mesh frame and the (count, 3) unit
        normals of the faces they lie on (outward for a consistently wound mesh).
    """
    if not isinstance(mesh, trimesh.Trimesh):
        raise SimgraspError(f"sample_surface needs a trimesh.Trimesh, got {type(mesh).__name__}")
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 1:
        raise SimgraspError(f"count must be a positive integer, got {count!r}")
    if len(mesh.faces) == 0 or not mesh.area > 0:
        raise SimgraspError("cannot sample a mesh with no surface area (no faces or degenerate)")
    seed = int(rng.integers(2**32))
    points, face = trimesh.sample.sample_surface(mesh, int(count), seed=seed)
    return np.asarray(points, dtype=np.float64), np.asarray(mesh.face_normals[face], np.float64)
