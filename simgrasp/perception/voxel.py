"""Voxel-grid down-sampling of point clouds (Open3D), and the occupied-voxel count."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.perception._arrays import as_normals, as_points, positive, to_open3d


def voxel_downsample(
    points: ArrayLike, voxel_size: float, normals: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Replace the points of every occupied voxel by their mean (Open3D ``voxel_down_sample``).

    Args:
        points: (N, 3) cloud in any frame, meters.
        voxel_size: voxel edge (m). The grid starts half a voxel below the cloud's minimum
            corner, as in Open3D.
        normals: optional (N, 3) unit normals; each voxel gets the normalised mean of its
            normals. Where opposite normals cancel (both sides of a wall thinner than a voxel)
            the voxel takes the normal of the input point nearest its mean point.

    Returns:
        ``(points, normals)``: (M, 3) voxel means in the input frame and (M, 3) unit normals,
        or ``None`` when no normals were given. ``M == voxel_count(points, voxel_size)``.
    """
    pts = as_points(points)
    size = positive(voxel_size, "voxel_size")
    nrm = None if normals is None else as_normals(normals, pts)
    down = to_open3d(pts, nrm).voxel_down_sample(size)
    down_points = np.asarray(down.points, dtype=np.float64)
    if nrm is None:
        return down_points, None
    down_normals = np.asarray(down.normals, dtype=np.float64)
    length = np.linalg.norm(down_normals, axis=1)
    cancelled = length < 1e-6
    if cancelled.any():
        _, nearest = cKDTree(pts).query(down_points[cancelled])
        down_normals[cancelled] = nrm[nearest]
        length[cancelled] = np.linalg.norm(down_normals[cancelled], axis=1)
    return down_points, down_normals / np.maximum(length, 1e-12)[:, None]


def voxel_count(points: ArrayLike, voxel_size: float) -> int:
    """Number of voxels of edge ``voxel_size`` (m) occupied by ``points`` (N, 3).

    Uses the same grid as :func:`voxel_downsample` (origin half a voxel below the minimum
    corner), so it equals the number of points that function returns. It measures object
    size: roughly surface area / voxel_size² for a surface cloud. Distinct cells are counted
    on the lexicographically sorted cell indices.
    """
    pts = as_points(points)
    size = positive(voxel_size, "voxel_size")
    origin = pts.min(axis=0) - 0.5 * size
    cells = np.floor((pts - origin) / size).astype(np.int64)
    ordered = cells[np.lexsort(cells.T)]
    return 1 + int(np.count_nonzero(np.any(ordered[1:] != ordered[:-1], axis=1)))
