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

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import as_normals, as_points, kd_tree, positive
from simgrasp.perception.voxel import voxel_count

NeighborhoodShape = Literal["cube", "sphere"]

_KEYS_PER_CHUNK = 4_000_000


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
            raise SimgraspError("sample_centers needs count or voxel_size (to scale with size)")
        per = positive(per_voxels, "per_voxels")
        count = math.ceil(voxel_count(pts, voxel_size) / per)
    elif isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 1:
        raise SimgraspError(f"count must be a positive integer, got {count!r}")
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
    tree: cKDTree | None = None,
) -> Neighborhoods:
    """Collect the cloud points around each centre (scipy ``cKDTree``, one dual-tree query).

    Args:
        points, normals: (N, 3) cloud and its unit normals, meters.
        center_points: (B, 3) neighbourhood centres (usually cloud points).
        half_size: half edge of the axis-aligned cube (``shape="cube"``, Chebyshev distance
            ``<= half_size``, the paper's neighbourhood) or radius of the ball
            (``shape="sphere"``), meters.
        max_points: neighbourhoods with more points keep a uniform random subset of this many
            (drawn from ``rng``, required then).
        min_points: neighbourhoods with fewer points are dropped.
        tree: optional ``cKDTree`` of ``points`` (same order) to query instead of building one.
    """
    pts = as_points(points)
    nrm = as_normals(normals, pts)
    centers = as_points(center_points, "center_points")
    radius = positive(half_size, "half_size")
    if shape not in ("cube", "sphere"):
        raise SimgraspError(f"shape must be 'cube' or 'sphere', got {shape!r}")
    for name, value in (("max_points", max_points), ("min_points", min_points)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise SimgraspError(f"{name} must be a positive integer, got {value!r}")
    if min_points > max_points:
        raise SimgraspError(f"min_points ({min_points}) exceeds max_points ({max_points})")

    owner, flat = _pairs_within(kd_tree(pts, tree), centers, radius, shape)
    sizes = np.bincount(owner, minlength=len(centers))
    keep = np.flatnonzero(sizes >= min_points)
    if len(keep) < len(centers):
        kept = np.zeros(len(centers), dtype=bool)
        kept[keep] = True
        flat = flat[kept[owner]]
    sizes = sizes[keep]
    if (sizes > max_points).any() and rng is None:
        raise SimgraspError("gather_neighborhoods needs rng to subsample large neighbourhoods")
    offsets = _chosen_offsets(sizes, max_points, rng)
    mask = offsets < sizes[:, None]
    rows = (np.cumsum(sizes) - sizes)[:, None] + offsets
    index = np.full(mask.shape, len(pts))  # padding reads the appended zero row
    index[mask] = flat[rows[mask]]
    padding = np.zeros((1, 3))
    hood_points = np.concatenate([pts, padding]).take(index, axis=0)
    hood_normals = np.concatenate([nrm, padding]).take(index, axis=0)
    counts = np.minimum(sizes, max_points)
    return Neighborhoods(hood_points, hood_normals, mask, counts, centers[keep], keep)


def _pairs_within(
    tree: cKDTree, centers: NDArray[np.float64], radius: float, shape: NeighborhoodShape
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """All (centre, point) index pairs within ``radius`` (Chebyshev for a cube, Euclidean for
    a ball), grouped by centre in increasing order; within a centre the points keep the
    deterministic order of scipy's dual-tree traversal (one ``sparse_distance_matrix`` call
    between a tree of the centres and ``tree``: no per-centre Python lists)."""
    norm = np.inf if shape == "cube" else 2.0
    pairs = cKDTree(centers).sparse_distance_matrix(tree, radius, p=norm, output_type="ndarray")
    owner = pairs["i"]
    order = np.argsort(owner.astype(np.min_scalar_type(len(centers))), kind="stable")
    return owner[order], pairs["j"][order]


def _chosen_offsets(
    sizes: NDArray[np.int64], max_points: int, rng: np.random.Generator | None
) -> NDArray[np.int64]:
    """(B, max_points) positions within each neighbourhood's point list: all of them (then
    padding positions >= size) when it fits, else a uniform random subset without repetition
    (the smallest ``max_points`` of one random key per point)."""
    offsets = np.broadcast_to(np.arange(max_points), (len(sizes), max_points)).copy()
    big = np.flatnonzero(sizes > max_points)
    if len(big) == 0:
        return offsets
    assert rng is not None
    longest = int(sizes[big].max())
    rows_per_chunk = max(1, _KEYS_PER_CHUNK // longest)
    for first in range(0, len(big), rows_per_chunk):
        chunk = big[first : first + rows_per_chunk]
        keys = rng.random((len(chunk), longest))
        keys[np.arange(longest) >= sizes[chunk, None]] = np.inf
        offsets[chunk] = np.argpartition(keys, max_points - 1, axis=1)[:, :max_points]
    return offsets
