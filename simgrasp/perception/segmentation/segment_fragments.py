"""Fragments of an organized cut absorbed by the segment they touch: a bumpy object seen by a
noisy sensor (a toy's folds, a cup's rim seen from above) breaks along short concave creases
and depth steps into pieces smaller than ``min_object_points``, which would otherwise be
dropped as noise and leave holes in the object (:func:`absorb_fragments`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.segmentation.segment_config import SegmentConfig

NEIGHBOURS = ((0, 1), (0, -1), (1, 0), (-1, 0))
"""(row, column) steps to a fragment pixel's 4-neighbours."""


def absorb_fragments(
    raw: NDArray[np.int32],
    points: NDArray[np.float32],
    shape: tuple[int, int],
    config: SegmentConfig,
) -> None:
    """Give each segment of ``raw`` (N,; ids, 0 for none; the (H, W) = ``shape`` image
    flattened) smaller than ``min_object_points`` the id of the segment of at least that size
    it touches with the most 4-neighbour pixel pairs whose points (N, 3, m) lie within
    ``attach_distance`` (the lowest id on a tie); repeated ``fragment_passes`` times, so a
    chain of fragments joins one link a pass. In place; fragments touching no such segment
    keep their ids."""
    index = np.flatnonzero(raw)  # the segmented pixels: a minority of the image
    ids = raw[index]
    small = np.bincount(ids, minlength=1) < config.min_object_points
    small[0] = False
    here = index[small[ids]]
    for _ in range(config.fragment_passes):
        if len(here) == 0:
            return
        target = _targets(raw, points, shape, here, small, config.attach_distance)
        absorbed = target != np.arange(len(target))
        if not absorbed.any():
            return
        raw[here] = target[raw[here]]
        small &= ~absorbed
        here = here[small[raw[here]]]


def _targets(
    raw: NDArray[np.int32],
    points: NDArray[np.float32],
    shape: tuple[int, int],
    here: NDArray[np.intp],
    small: NDArray[np.bool_],
    reach: float,
) -> NDArray[np.int32]:
    """Per id of ``raw``, the id it joins: for a fragment (``small``, its pixels ``here``)
    the large segment with the most 4-neighbour pairs within ``reach`` (m), else itself."""
    height, width = shape
    size = len(small)
    rows, cols = np.divmod(here, width)
    codes = []
    for step_row, step_col in NEIGHBOURS:
        if step_row:
            inside = (rows + step_row >= 0) & (rows + step_row < height)
        else:
            inside = (cols + step_col >= 0) & (cols + step_col < width)
        mine = here[inside]
        there = mine + (step_row * width + step_col)
        other = raw[there]
        large = (other > 0) & ~small[other]
        mine, there, other = mine[large], there[large], other[large]
        gaps = points[there] - points[mine]
        near = np.einsum("ij,ij->i", gaps, gaps) <= np.float32(reach**2)
        codes.append(raw[mine[near]].astype(np.int64) * size + other[near])
    target = np.arange(size, dtype=np.int32)
    pairs, contacts = np.unique(np.concatenate(codes), return_counts=True)
    if len(pairs) == 0:
        return target
    order = np.lexsort((-contacts, pairs // size))
    fragment = pairs[order] // size
    first = np.ones(len(order), dtype=bool)
    first[1:] = fragment[1:] != fragment[:-1]
    target[fragment[first]] = (pairs[order][first] % size).astype(np.int32)
    return target
