"""Edge pixels of a grid cut joined to a neighbouring segment: a mixed pixel at an occluding
edge, or a pixel on a concave crease, takes the segment of the pixel nearest to it in 3-D
within a few image pixels (:func:`attach_edges`).
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.segmentation.segment_config import SegmentConfig

Grid = NDArray[np.float32]
Scalar = TypeVar("Scalar", bound=np.generic)


def attach_edges(
    segments: NDArray[np.int32],
    flat_planes: Grid,
    candidates: NDArray[np.bool_],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    """Give each cut-edge candidate pixel the segment of the pixel nearest to it in 3-D among
    those up to ``attach_radius_px`` away in the image (rows and columns at odd offsets and
    0; the first in row-major offset order on a tie), when within ``attach_distance`` (m): a
    mixed pixel at an occluding edge joins the side whose depth it is nearer. Repeated
    ``attach_passes`` times, each pass on the pixels still loose, so a run of mixed pixels
    joins one pixel-step at a time. ``flat_planes`` (3, (H + 2r) (W + 2r)) are the positions
    (m) of the ``candidates`` (H, W) as channel planes padded by r = ``attach_radius_px`` (any
    value elsewhere), each flattened; every offset is tried at once, one (pixels, offsets)
    array a block of loose pixels (:func:`_nearest_labels`), the 3-D gap computed only to
    labeled pixels."""
    reach = config.attach_radius_px
    loose_mask = candidates & (segments == 0)
    if not segments.any() or not loose_mask.any():
        return segments
    labels = zero_padded(segments, reach)
    flat_labels = labels.reshape(-1)
    loose = np.flatnonzero(loose_mask)  # flat in the crop, then in the padded crop
    loose += 2 * reach * (loose // segments.shape[1]) + reach * (labels.shape[1] + 1)
    steps = np.array([0, *range(1, reach + 1, 2), *range(-1, -reach - 1, -2)])
    shifts = (steps[:, None] * labels.shape[1] + steps[None, :]).reshape(-1)
    for _ in range(config.attach_passes):
        found = np.concatenate(
            [
                _nearest_labels(
                    flat_labels, flat_planes, loose[start : start + ATTACH_BLOCK], shifts, config
                )
                for start in range(0, len(loose), ATTACH_BLOCK)
            ]
        )
        near = found > 0
        flat_labels[loose[near]] = found[near]
        loose = loose[~near]
        if len(loose) == 0:
            break
    return labels[reach:-reach, reach:-reach]


ATTACH_BLOCK = 512
"""Loose pixels per (pixels, offsets) block in :func:`attach_edges`: arrays of ~200 KB that
stay in cache and that the allocator reuses from block to block, where one array for all the
loose pixels of a crowded crop takes MBs (256 - 1024 measure alike)."""


def _nearest_labels(
    flat_labels: NDArray[np.int32],
    flat_planes: Grid,
    loose: NDArray[np.intp],
    shifts: NDArray[np.intp],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    """The label of the 3-D nearest labeled pixel among the ``shifts`` (flat offsets, in
    tie order) around each ``loose`` pixel (flat indices into the padded ``flat_labels`` and
    ``flat_planes``' channels), when within ``attach_distance`` (m); 0 otherwise."""
    around = loose[:, None] + shifts[None, :]  # (pixels, offsets): each pixel's row contiguous
    label = flat_labels[around]
    pairs = np.flatnonzero(label > 0)
    gap = np.full(around.shape, np.inf, dtype=flat_planes.dtype)
    gap.reshape(-1)[pairs] = _squared_gaps(
        flat_planes, around.reshape(-1)[pairs], loose[pairs // len(shifts)]
    )
    nearest = gap.argmin(axis=1)
    rows = np.arange(len(loose))
    near = gap[rows, nearest] <= config.attach_distance**2
    return np.where(near, label[rows, nearest], 0)


def _squared_gaps(
    flat_planes: Grid, around: NDArray[np.intp], loose: NDArray[np.intp]
) -> NDArray[np.float32]:
    """Squared 3-D distance (m^2) from each ``loose`` pixel to each pixel ``around`` it (flat
    indices into ``flat_planes``' channels, broadcast against each other), channel by channel
    in place: the same float32 operations as the sum of the squared offsets' channels in order,
    without stacking them."""
    gap = np.empty(around.shape, dtype=flat_planes.dtype)
    channel = np.empty_like(gap)
    for index, plane in enumerate(flat_planes):
        np.take(plane, around, out=channel)
        channel -= plane[loose]
        channel *= channel
        if index == 0:
            gap, channel = channel, gap
        else:
            gap += channel
    return gap


def zero_padded(grid: NDArray[Scalar], reach: int) -> NDArray[Scalar]:
    """``grid`` (..., H, W) with ``reach`` zeros around its last two axes (``np.pad``'s
    result, without its per-call overhead)."""
    *lead, height, width = grid.shape
    padded = np.zeros((*lead, height + 2 * reach, width + 2 * reach), dtype=grid.dtype)
    padded[..., reach : reach + height, reach : reach + width] = grid
    return padded
