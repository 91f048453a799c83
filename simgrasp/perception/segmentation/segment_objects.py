"""The objects of a segmentation: each segment's point count, centroid and bounding box, and
the final labels ordered by distance to the sensor.

Per-label statistics come from the labeled pixels grouped by label (:data:`LabelPixels`, one
sort), never from a pass over the whole image per label: a centroid is the float64 sum of its
points in ascending index order (as ``mean(axis=0)`` of the gathered points sums them) over
their count, a bounding box the per-coordinate max - min.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.segmentation.segment_config import FIRST_OBJECT, INVALID, TABLE

assert (INVALID, TABLE) == (0, 1), "ordered_labels writes the table mask as its labels"


@dataclass(frozen=True)
class SegmentedObject:
    """One object on the table.

    Attributes:
        label: its label in :attr:`Segmentation.labels` (2, 3, ...).
        points: its number of points.
        center: (3,) centroid (m, cloud frame).
        extent: (3,) edge lengths of its axis-aligned bounding box (m, cloud frame).
        part_of: the label of the object this one is a thin side part of (a pot's tab:
            :mod:`simgrasp.perception.segmentation.segment_parts`), its own label otherwise.
    """

    label: int
    points: int
    center: NDArray[np.float64]
    extent: NDArray[np.float64]
    part_of: int = 0

    def to_json(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "points": self.points,
            "center": self.center.tolist(),
            "extent": self.extent.tolist(),
            "part_of": self.part_of,
        }


LabelPixels = tuple[NDArray[np.intp], NDArray[np.intp]]
"""Labeled pixels grouped by label: their flat indices (by label, ascending within a label)
and where each label's run starts (indexed by label 0 .. count; the last entry is the total)."""


def label_pixels(own: NDArray[np.integer], index: NDArray[np.intp], count: int) -> LabelPixels:
    """The pixels ``index`` (ascending flat indices) grouped by their labels ``own`` (each
    below ``count``)."""
    return index[stable_order(own, count)], _starts(own, count)


def stable_order(own: NDArray[np.integer], count: int) -> NDArray[np.intp]:
    """``np.argsort(own, kind="stable")`` for labels ``own`` below ``count``: as uint16 keys
    when they fit, which numpy sorts by radix (the same order, about half the time of an
    int32 key's merge sort)."""
    keys = own.astype(np.uint16) if count <= 1 << 16 else own
    return np.argsort(keys, kind="stable")


def _starts(own: NDArray[np.integer], count: int) -> NDArray[np.intp]:
    """Where each label's run starts once the labels ``own`` are sorted (0 .. ``count``)."""
    starts = np.zeros(count + 1, dtype=np.intp)
    np.cumsum(np.bincount(own, minlength=count), out=starts[1:])
    return starts


def objects_of(
    pixels: LabelPixels, points: NDArray[np.float32], wanted: NDArray[np.intp]
) -> list[SegmentedObject]:
    """The objects of the ``wanted`` labels (ascending, each with a pixel; the pixels from the
    first's run on are theirs), their ``points`` (N, 3) being those of ``pixels``."""
    if len(wanted) == 0:
        return []
    grouped, starts = pixels
    counts = np.diff(starts)
    own = np.repeat(np.arange(len(counts)), counts)
    coords = np.take(points, grouped, axis=0)
    sums = np.stack([np.bincount(own, coords[:, k], len(counts)) for k in range(3)], axis=1)
    centers = sums[wanted] / counts[wanted, None]
    return _objects(wanted, counts[wanted], centers, _extents(coords, starts, wanted))


def _extents(
    coords: NDArray[np.float32], starts: NDArray[np.intp], wanted: NDArray[np.intp]
) -> NDArray[np.float64]:
    """(len(wanted), 3) max - min of the ``coords`` (grouped by label, runs from ``starts``)
    of each of the ``wanted`` labels (as :func:`objects_of` takes them), in float64."""
    first = starts[wanted[0]]
    high = np.maximum.reduceat(coords[first:], starts[wanted] - first)
    low = np.minimum.reduceat(coords[first:], starts[wanted] - first)
    return high.astype(np.float64) - low.astype(np.float64)


def _objects(
    labels: NDArray[np.intp],
    counts: NDArray[np.intp],
    centers: NDArray[np.float64],
    extents: NDArray[np.float64],
) -> list[SegmentedObject]:
    """One object per label, each its own whole."""
    return [
        SegmentedObject(label, int(counts[k]), centers[k], extents[k], label)
        for k, label in enumerate(labels.tolist())
    ]


def ordered_labels(
    raw: NDArray[np.int32],
    table: NDArray[np.bool_],
    points: NDArray[np.float32],
    viewpoint: NDArray[np.float64],
    min_points: int,
) -> tuple[NDArray[np.int32], tuple[SegmentedObject, ...], LabelPixels]:
    """Final labels (N,) from the segment ids ``raw`` (N,; 0 for none): table 1, segments of
    at least ``min_points`` 2.. by the distance of their centroid to the ``viewpoint``, the
    rest 0; their objects and their pixels."""
    labels = table.astype(np.int32)  # TABLE 1 where table, INVALID 0 elsewhere
    index = np.flatnonzero(raw != 0)  # a bool image's nonzero is several times faster
    ids, coords = raw[index], np.take(points, index, axis=0)  # take: rows faster than []
    counts = np.bincount(ids)
    sums = np.stack([np.bincount(ids, coords[:, k], len(counts)) for k in range(3)], axis=1)
    kept = np.flatnonzero(counts >= min_points)
    kept = kept[kept > 0]
    centers = sums[kept] / counts[kept, None]
    order = np.argsort(np.linalg.norm(centers - viewpoint, axis=1), kind="stable")
    count = FIRST_OBJECT + len(kept)
    relabel = np.zeros(len(counts), dtype=np.int32)
    relabel[kept[order]] = np.arange(FIRST_OBJECT, count, dtype=np.int32)
    new = relabel[ids]
    on = new > 0
    labels[index[on]] = new[on]
    own = new[on]
    grouped = np.flatnonzero(on)[stable_order(own, count)]
    pixels = (index[grouped], _starts(own, count))
    if len(kept) == 0:
        return labels, (), pixels
    wanted = np.arange(FIRST_OBJECT, count)
    extents = _extents(np.take(coords, grouped, axis=0), pixels[1], wanted)
    objects = _objects(wanted, counts[kept[order]], centers[order], extents)
    return labels, tuple(objects), pixels
