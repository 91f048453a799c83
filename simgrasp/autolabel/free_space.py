"""Free space around a handle candidate: does the object's surface continue sideways from it?

A handle stands off the object: across its axis, just outside its own cross-section, there is
air (the hole a hand reaches through, or open space). A wall, a rim's lip or a body's edge
continues sideways instead. For each candidate (its axis point ``handle_point``, unit
``axis`` and larger transverse semi-axis ``semi_major``) this module looks at the scanned
surface in a thin slab across the axis (``|along| <= slab``) and in a ring around the axis
from ``semi_major + gap`` to ``semi_major + gap + ring`` out, and returns the share of
``sectors`` equal angular sectors around the axis in which surface lies in that ring
(0: free all around, 1: surrounded). Mesh frame, meters.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.transforms import orthonormal


def voxel_thinned(points: NDArray[np.float64], voxel: float) -> NDArray[np.float64]:
    """One point (the first) of ``points`` (N, 3) per cube of side ``voxel`` (m)."""
    keys = np.floor(points / voxel).astype(np.int64)
    _, first = np.unique(keys, axis=0, return_index=True)
    return points[np.sort(first)]


def sideways_occupancy(
    surface: NDArray[np.float64],
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    semi_major: NDArray[np.float64],
    *,
    slab: float,
    gap: float,
    ring: float,
    sectors: int = 12,
) -> NDArray[np.float64]:
    """(M,) share of angular sectors around each candidate's axis with surface in its ring
    (see the module docstring); candidates without a finite axis or semi-axis get 1."""
    tree = cKDTree(surface)
    shares = np.ones(len(handle_points))
    for i, (center, axis, semi) in enumerate(zip(handle_points, axes, semi_major, strict=True)):
        if not (np.all(np.isfinite(center)) and np.all(np.isfinite(axis)) and np.isfinite(semi)):
            continue
        inner = semi + gap
        near = tree.query_ball_point(center, float(np.hypot(inner + ring, slab)))
        offsets = surface[near] - center
        along = offsets @ axis
        across = offsets - along[:, None] * axis
        radius = np.linalg.norm(across, axis=1)
        in_ring = (np.abs(along) <= slab) & (radius >= inner) & (radius <= inner + ring)
        u, v = orthonormal(axis)
        angle = np.arctan2(across[in_ring] @ v, across[in_ring] @ u)
        sector = np.floor((angle + np.pi) / (2.0 * np.pi) * sectors).astype(np.int64)
        shares[i] = len(np.unique(np.clip(sector, 0, sectors - 1))) / sectors
    return shares
