"""The inner floors of open objects on an organized cloud: the bottom of a bowl or pot seen
from above lies level with the table, so the table plane's inliers take it; a small patch of
them ringed by object pixels is the object's floor instead.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from simgrasp.perception.segmentation.organized_segments import bounding_slices
from simgrasp.perception.segmentation.segment_config import SegmentConfig

Box = tuple[slice, slice, NDArray[np.int32]]
"""Row and column slices of an image and the (rows, cols) values within them."""


def inner_floors(table: NDArray[np.bool_], above: NDArray[np.bool_], config: SegmentConfig) -> Box:
    """Patch ids (0 elsewhere) of the plane inliers ``table`` (H, W) that are an object's
    floor instead (the inner bottom of a bowl or pot, level with the table): connected patches
    smaller than ``floor_share`` of the largest patch whose one-pixel ring lies at least
    ``floor_enclosed`` above the table (``above``). As the box of the candidate patches grown
    by one pixel (all ids 0 outside it; an empty box when none)."""
    none: Box = (slice(0, 0), slice(0, 0), np.zeros((0, 0), dtype=np.int32))
    patches, count = ndimage.label(table, output=np.intp)  # intp: no casts below
    if count < 2:
        return none
    sizes = np.bincount(patches.reshape(-1), minlength=count + 1)
    sizes[0] = 0
    small = (sizes < config.floor_share * sizes.max()) & (sizes >= config.min_object_points)
    small[0] = False
    if not small.any():
        return none
    rows, cols = bounding_slices(small[patches], 1)
    box = patches[rows, cols]
    box = np.where(small[box], box, 0).astype(np.int32)
    grown = _max3x3(box)
    ring = (grown > 0) & (box == 0)
    ring_size = np.bincount(grown[ring], minlength=count + 1)
    ring_above = np.bincount(grown[ring & above[rows, cols]], minlength=count + 1)
    enclosed = small & (ring_above >= config.floor_enclosed * np.maximum(ring_size, 1))
    return rows, cols, np.where(enclosed[box], box, 0).astype(np.int32)


def _max3x3(grid: NDArray[np.int32]) -> NDArray[np.int32]:
    """The largest value of each pixel's 3 x 3 neighbourhood, pixels outside ``grid`` (H, W)
    counting as 0 (``ndimage.maximum_filter(grid, 3, mode="constant")`` for ``grid`` >= 0),
    as two separable passes of shifted maxima."""
    rows = grid.copy()
    np.maximum(rows[1:], grid[:-1], out=rows[1:])
    np.maximum(rows[:-1], grid[1:], out=rows[:-1])
    grown = rows.copy()
    np.maximum(grown[:, 1:], rows[:, :-1], out=grown[:, 1:])
    np.maximum(grown[:, :-1], rows[:, 1:], out=grown[:, :-1])
    return np.maximum(grown, 0, out=grown)
