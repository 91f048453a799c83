"""Neighbourhood sampling: random centres, and the cube (or ball) of points around each.

The number of neighbourhoods scales with object size measured as the occupied-voxel count
(as in the paper): ``count = ceil(voxel_count(points, voxel_size) / per_voxels)``, at least
one and at most the number of points. With the default ``per_voxels=10`` a mug-sized object
voxelised at 3 mm (about 5000 voxels) gets about 500 neighbourhoods.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.perception._arrays import as_normals, as_points, positive
from simgrasp.perception.voxel import voxel_count

NeighborhoodShape = Literal["cube", "sphere"]


@dataclass(frozen=True)
class Neighborhoods:
    """A padded batch of B neighbourhoods of at most K points (cloud frame, meters).

    Rows ``points[b, :counts[b]]`` are real (``mask`` True); the rest is zero padding.
    ``source[b]`` is the index in the ``center_points`` passed to
    :func:`gather_neighborhoods` of the centre of neighbourhood ``b`` (neighbourhoods with
    fewer than ``min_points`` points are dropped, so B can be smaller than the centre count).
    """

    points: NDArray[np.float64]
    """(B, K, 3) neighbourhood points."""
    normals: NDArray[np.float64]
    """(B, K, 3) their normals."""
    mask: NDArray[np.bool_]
    """(B, K) True for real points."""
    counts: NDArray[np.int64]
    """(B,) number of real points per neighbourhood."""
    centers: NDArray[np.float64]
    """(B, 3) neighbourhood centres."""
    source: NDArray[np.int64]
    """(B,) index of each centre among the requested centres."""


def sample_centers(
    points: ArrayLike,
    rng: np.random.Generator,
    count: int | None = None,
    voxel_size: float | None = None,
    per_voxels: float = 10.0,
) -> NDArray[np.int64]:
    """Indices of randomly chosen neighbourhood centres, without repetition, sorted.

    Args:
        points: (N, 3) cloud, meters.
        rng: the seeded generator every draw comes from.
        count: number of centres; overrides the size rule (clipped to N).
        voxel_size: voxel edge (m) measuring object size when ``count`` is None.
        per_voxels: one centre per this many occupied voxels (module docstring).
    """
    pts = as_points(points)
    if count is None:
        if voxel_size is None:
            raise ValueError("sample_centers needs count or voxel_size (to scale with size)")
        per = positive(per_voxels, "per_voxels")
        count = math.ceil(voxel_count(pts, voxel_size) / per)
    elif isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 1:
        raise ValueError(f"count must be a positive integer, got {count!r}")
    count = min(int(count), len(pts))
    return np.sort(rng.choice(len(pts), size=count, replace=False)).astype(np.int64)


def gather_neighborhoods(
    points: ArrayLike,
    normals: ArrayLike,
    center_points: ArrayLike,
    half_size: float,
    shape: NeighborhoodShape = "cube",
    max_points: int = 64,
    min_points: int = 10,
    rng: np.random.Generator | None = None,
) -> Neighborhoods:
    """Collect the cloud points around each centre (scipy ``cKDTree.query_ball_point``).

    Args:
        points, normals: (N, 3) cloud and its unit normals, meters.
        center_points: (B, 3) neighbourhood centres (usually cloud points).
        half_size: half edge of the axis-aligned cube (``shape="cube"``, Chebyshev distance
            ``<= half_size``, the paper's neighbourhood) or radius of the ball
            (``shape="sphere"``), meters.
        max_points: neighbourhoods with more points keep a uniform random subset of this many
            (drawn from ``rng``, required then).
        min_points: neighbourhoods with fewer points are dropped.
    """
    pts = as_points(points)
    nrm = as_normals(normals, pts)
    centers = as_points(center_points, "center_points")
    radius = positive(half_size, "half_size")
    if shape not in ("cube", "sphere"):
        raise ValueError(f"shape must be 'cube' or 'sphere', got {shape!r}")
    for name, value in (("max_points", max_points), ("min_points", min_points)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if min_points > max_points:
        raise ValueError(f"min_points ({min_points}) exceeds max_points ({max_points})")

    norm = np.inf if shape == "cube" else 2.0
    found = cKDTree(pts).query_ball_point(centers, radius, p=norm, return_sorted=False)
    sizes = np.fromiter((len(f) for f in found), dtype=np.int64, count=len(found))
    keep = np.flatnonzero(sizes >= min_points)
    flat = np.concatenate([np.asarray(found[i], dtype=np.int64) for i in keep] or [[]])
    flat = flat.astype(np.int64)
    group = np.repeat(np.arange(len(keep)), sizes[keep])
    if (sizes[keep] > max_points).any():
        if rng is None:
            raise ValueError("gather_neighborhoods needs rng to subsample large neighbourhoods")
        order = np.lexsort((rng.random(len(flat)), group))
        flat, group = flat[order], group[order]
    starts = np.cumsum(sizes[keep]) - sizes[keep]
    rank = np.arange(len(flat)) - np.repeat(starts, sizes[keep])
    chosen = rank < max_points
    counts = np.minimum(sizes[keep], max_points)
    hood_points = np.zeros((len(keep), max_points, 3))
    hood_normals = np.zeros((len(keep), max_points, 3))
    mask = np.zeros((len(keep), max_points), dtype=bool)
    slot = (group[chosen], rank[chosen])
    hood_points[slot] = pts[flat[chosen]]
    hood_normals[slot] = nrm[flat[chosen]]
    mask[slot] = True
    return Neighborhoods(hood_points, hood_normals, mask, counts, centers[keep], keep)
