"""Objects on an organized (image-grid) cloud: connected components of the above-table pixels,
cut at depth discontinuities and at sharp concave creases.

In the spirit of PCL's organized connected-component segmentation and of LCCP's convexity
criterion (Stein et al., CVPR 2014): two touching objects meet either at a depth step (one
occludes the other) or at a concave crease (a box standing on a box, a can against a box),
while the faces of one object meet at convex edges. Normals come from central differences of
a box-filtered position image, so every step is a few whole-image numpy / scipy.ndimage passes.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simgrasp.perception.segment_config import SegmentConfig

Grid = NDArray[np.float32]


def grid_components(
    points: Grid,
    candidates: NDArray[np.bool_],
    viewpoint: NDArray[np.float64],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    """Segment ids (H, W) of the ``candidates`` pixels (0 elsewhere), in no particular order.

    ``points`` is the (H, W, 3) position image (m, NaN where invalid).
    """
    rows, cols = _bounding_slices(candidates, config.normal_window_px + 2 * config.normal_step_px)
    segments = np.zeros(candidates.shape, dtype=np.int32)
    segments[rows, cols] = _crop_components(
        points[rows, cols], candidates[rows, cols], viewpoint, config
    )
    return segments


def inner_floors(
    table: NDArray[np.bool_], above: NDArray[np.bool_], config: SegmentConfig
) -> NDArray[np.int32]:
    """Patch ids (H, W; 0 elsewhere) of the plane inliers ``table`` that are an object's
    floor instead (the inner bottom of a bowl or pot, level with the table): connected patches
    smaller than ``floor_share`` of the largest patch whose one-pixel ring lies at least
    ``floor_enclosed`` above the table (``above``)."""
    patches, count = ndimage.label(table)
    if count < 2:
        return np.zeros(table.shape, dtype=np.int32)
    sizes = np.bincount(patches.reshape(-1), minlength=count + 1)
    sizes[0] = 0
    small = (sizes < config.floor_share * sizes.max()) & (sizes >= config.min_object_points)
    small[0] = False
    if not small.any():
        return np.zeros(table.shape, dtype=np.int32)
    floors = np.where(small[patches], patches, 0).astype(np.int32)
    grown = ndimage.maximum_filter(floors, size=3)
    ring = (grown > 0) & (floors == 0)
    ring_size = np.bincount(grown[ring], minlength=count + 1)
    ring_above = np.bincount(grown[ring & above], minlength=count + 1)
    enclosed = small & (ring_above >= config.floor_enclosed * np.maximum(ring_size, 1))
    return np.where(enclosed[floors], floors, 0).astype(np.int32)


def _bounding_slices(mask: NDArray[np.bool_], margin: int) -> tuple[slice, slice]:
    """Row and column slices of the bounding box of ``mask`` grown by ``margin`` pixels."""
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    if len(rows) == 0:
        return slice(0, 0), slice(0, 0)
    return (
        slice(max(rows[0] - margin, 0), rows[-1] + margin + 1),
        slice(max(cols[0] - margin, 0), cols[-1] + margin + 1),
    )


def _crop_components(
    points: Grid,
    candidates: NDArray[np.bool_],
    viewpoint: NDArray[np.float64],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    if candidates.size == 0:
        return np.zeros(candidates.shape, dtype=np.int32)
    eye = viewpoint.astype(np.float32)
    smooth = _box_mean(points, candidates, config.normal_window_px)
    normals = _grid_normals(smooth, eye, config.normal_step_px)
    cut = _depth_cuts(points, candidates, eye, config.depth_jump)
    cut |= _concave_cuts(smooth, normals, config.concave_step_px, config.concave_threshold)
    if config.cut_grow_px > 0:
        cut = ndimage.binary_dilation(cut, iterations=config.cut_grow_px)
    interior = candidates & ~cut
    segments, _ = ndimage.label(interior)
    return _attach_edges(segments.astype(np.int32), points, candidates, config.attach_distance)


def _box_mean(points: Grid, mask: NDArray[np.bool_], size: int) -> Grid:
    """Mean position over each ``size`` x ``size`` window of the masked pixels (NaN if none)."""
    weight = mask.astype(np.float32)
    summed = np.where(mask[..., None], points, 0.0).astype(np.float32)
    count = ndimage.uniform_filter(weight, size, mode="constant")
    mean = ndimage.uniform_filter1d(summed, size, axis=0, mode="constant")
    mean = ndimage.uniform_filter1d(mean, size, axis=1, mode="constant")
    with np.errstate(invalid="ignore", divide="ignore"):
        mean /= count[..., None]
    mean[count < 0.5 / (size * size)] = np.nan
    return mean


def _grid_normals(smooth: Grid, eye: NDArray[np.float32], step: int) -> Grid:
    """Unit normals (H, W, 3) from central differences over ``step`` pixels, turned toward
    ``eye``; NaN where a neighbour is missing."""
    du = np.full_like(smooth, np.nan)
    dv = np.full_like(smooth, np.nan)
    du[:, step:-step] = smooth[:, 2 * step :] - smooth[:, : -2 * step]
    dv[step:-step] = smooth[2 * step :] - smooth[: -2 * step]
    normals = np.cross(du, dv)
    with np.errstate(invalid="ignore", divide="ignore"):
        normals /= np.linalg.norm(normals, axis=2, keepdims=True)
    toward = np.einsum("hwk,hwk->hw", normals, eye - smooth)
    normals[toward < 0] *= -1.0
    return normals


def _depth_cuts(
    points: Grid, mask: NDArray[np.bool_], eye: NDArray[np.float32], jump: float
) -> NDArray[np.bool_]:
    """Pixels with a 4-neighbour whose range differs by more than ``jump`` x range^2 (m)."""
    ranges = np.linalg.norm(points - eye, axis=2)
    ranges[~mask] = np.nan
    limit = jump * ranges * ranges
    cut = np.zeros(mask.shape, dtype=bool)
    for axis in (0, 1):
        lo = [slice(None), slice(None)]
        hi = [slice(None), slice(None)]
        lo[axis], hi[axis] = slice(None, -1), slice(1, None)
        step = np.abs(ranges[tuple(hi)] - ranges[tuple(lo)])
        broken = mask[tuple(lo)] & mask[tuple(hi)] & ~(step <= limit[tuple(lo)])
        cut[tuple(lo)] |= broken
        cut[tuple(hi)] |= broken
    return cut


def _concave_cuts(smooth: Grid, normals: Grid, step: int, threshold: float) -> NDArray[np.bool_]:
    """Pixels spanned by a ``step``-pixel pair whose normals fold concavely:
    ``(n_j - n_i) . u_ij < -threshold``, ``u_ij`` the unit direction from i to j."""
    cut = np.zeros(smooth.shape[:2], dtype=bool)
    for axis in (0, 1):
        lo = [slice(None), slice(None)]
        hi = [slice(None), slice(None)]
        lo[axis], hi[axis] = slice(None, -step), slice(step, None)
        offset = smooth[tuple(hi)] - smooth[tuple(lo)]
        fold = np.einsum("hwk,hwk->hw", normals[tuple(hi)] - normals[tuple(lo)], offset)
        with np.errstate(invalid="ignore"):
            concave = fold < -threshold * np.linalg.norm(offset, axis=2)
        for shift in range(step + 1):
            span = [slice(None), slice(None)]
            span[axis] = slice(shift, shift + concave.shape[axis])
            cut[tuple(span)] |= concave
    return cut


def _attach_edges(
    segments: NDArray[np.int32], points: Grid, candidates: NDArray[np.bool_], distance: float
) -> NDArray[np.int32]:
    """Give each cut-edge candidate pixel the segment of its nearest segment pixel in the
    image, when that pixel is within ``distance`` (m) in 3-D."""
    loose = candidates & (segments == 0)
    if not loose.any() or not segments.any():
        return segments
    _, (rows, cols) = ndimage.distance_transform_edt(segments == 0, return_indices=True)
    r, c = np.nonzero(loose)
    nr, nc = rows[r, c], cols[r, c]
    gap = np.linalg.norm(points[r, c] - points[nr, nc], axis=1)
    near = gap <= distance
    segments[r[near], c[near]] = segments[nr[near], nc[near]]
    return segments
