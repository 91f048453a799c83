"""Thin side parts of an object (a pot's flat side tabs, a pan's handle): small, thin segments
that touch a larger segment, found after the grid cuts.

The grid cuts separate a pot's side tab from its wall at the concave crease between them, so
the tab comes out as a segment of its own. Such a segment keeps its own label (OSD labels the
tabs as parts of their own), and records the larger segment it belongs to, so a detector can be
handed the whole object: the segment's points are at most ``part_max_points``, its height
above the table spans at most ``part_max_thickness`` (a horizontal plate, not a box standing
on another), and at least ``part_min_contact`` of its pixels lie within ``part_contact_px``
pixels and ``part_contact_distance`` (3-D) of a pixel of a larger segment. A tab seen past
the occluding rim of an upturned pot, whose joint with the wall is hidden, stays an object.

A side part near the table (a tab 1 cm above it) also claims the table-band pixels of its
edge, where the sensor's depth ramps from the tab down to the table: table pixels within
``part_edge_px`` of a part pixel, within ``part_contact_distance`` of it in 3-D and more than
``part_edge_height`` above the table.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from simgrasp.perception.segmentation.segment_attach import zero_padded
from simgrasp.perception.segmentation.segment_config import FIRST_OBJECT, TABLE, SegmentConfig
from simgrasp.perception.segmentation.segment_objects import LabelPixels


def part_parents(
    labels: NDArray[np.int32],
    points: NDArray[np.float32],
    height: NDArray[np.float32],
    config: SegmentConfig,
    grouped: LabelPixels,
) -> NDArray[np.int32]:
    """The object each label belongs to, indexed by label (labels below 2 map to themselves).

    ``labels`` is the (H, W) label image (objects >= 2), ``points`` the (H, W, 3) position
    image (m) and ``height`` the (H, W) height above the table (m); ``grouped`` the pixels of
    its objects grouped by label (no pass over the image). A thin side part maps
    to the root of the larger segment it touches most (module docstring), every other label to
    itself.
    """
    count = len(grouped[1]) - 1
    parents = np.arange(count, dtype=np.int32)
    if count <= FIRST_OBJECT + 1 or config.part_min_contact <= 0:
        return parents
    flat = labels.reshape(-1)
    sizes = np.diff(grouped[1])  # labels 0 and 1 (never parts nor wholes): 0, never read
    small = sizes <= config.part_max_points
    small[:FIRST_OBJECT] = False
    pixels = _pixels_of(small, grouped)
    spread = _spread(flat[pixels], height.reshape(-1)[pixels], count)
    thin = small & (spread <= config.part_max_thickness)
    pixels = pixels[thin[flat[pixels]]]
    if len(pixels) == 0:
        return parents
    pairs, contacts = _contacts(labels, points, sizes, pixels, config)
    for part, whole in _best_pairs(pairs, contacts, count, config.part_min_contact):
        parents[part] = whole
    for _ in range(count):
        roots = parents[parents]
        if (roots == parents).all():
            break
        parents = roots
    return parents


def _pixels_of(chosen: NDArray[np.bool_], grouped: LabelPixels) -> NDArray[np.intp]:
    """Ascending flat indices of the pixels of the ``chosen`` labels (a mask over labels),
    from ``grouped`` (the object pixels by label)."""
    pixels, starts = grouped
    runs = np.repeat(chosen[: len(starts) - 1], np.diff(starts))
    return np.sort(pixels[runs])


def _spread(own: NDArray[np.int32], height: NDArray[np.float32], count: int) -> NDArray[np.float64]:
    """Per label, the 5th-95th percentile span of the ``height`` (m) of its pixels, given the
    label ``own`` of each; infinite for labels without pixels. One sort of int64 keys: the
    label in the high word, the height's float32 bits made order-preserving in the low."""
    bits = height.view(np.int32).astype(np.int64)
    keys = np.where(bits < 0, ~bits & 0x7FFFFFFF, bits | 0x80000000)
    keys |= own.astype(np.int64) << 32
    keys.sort()
    low = keys & 0xFFFFFFFF
    bits = np.where(low & 0x80000000, low & 0x7FFFFFFF, (~low & 0x7FFFFFFF) | 0x80000000)
    sorted_height = bits.astype(np.uint32).view(np.float32)
    sizes = np.bincount(own, minlength=count)
    starts = np.concatenate(([0], np.cumsum(sizes)[:-1]))
    span = np.full(count, np.inf)
    has = sizes > 0
    low = sorted_height[starts[has] + ((sizes[has] - 1) * 0.05).astype(np.int64)]
    high = sorted_height[starts[has] + ((sizes[has] - 1) * 0.95).astype(np.int64)]
    span[has] = high - low
    return span


def _contacts(
    labels: NDArray[np.int32],
    points: NDArray[np.float32],
    sizes: NDArray[np.int64],
    pixels: NDArray[np.int64],
    config: SegmentConfig,
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Codes ``part * count + whole`` of (thin segment, larger segment) pairs and, for each,
    how many of the thin segment's ``pixels`` (flat indices) have a pixel of the larger one
    within ``part_contact_px`` (rows and columns at offsets -r, -1, 0, 1, r) and
    ``part_contact_distance`` (m). Every offset at once, on grids padded with label 0; the
    3-D distance only to pixels of larger segments."""
    count, reach = len(sizes), config.part_contact_px
    steps = sorted({-reach, -1, 0, 1, reach})
    offsets = np.array([(dr, dc) for dr in steps for dc in steps if dr or dc])
    flat = labels.reshape(-1)
    there, inside = _neighbours(labels.shape, pixels, offsets)
    other = np.where(inside, flat[there], 0).reshape(-1)  # label 0 beyond the image
    larger = (other >= FIRST_OBJECT) & (sizes[other] > np.tile(sizes[flat[pixels]], len(offsets)))
    slots = np.flatnonzero(larger)  # (offset, pixel) pairs, row-major
    here = pixels[slots % len(pixels)]
    gaps = _pair_gaps(points.reshape(-1, 3), here, there.reshape(-1)[slots])
    near = gaps <= config.part_contact_distance**2
    pixel_pairs = np.unique(here[near].astype(np.int64) * count + other[slots[near]])
    parts = flat[pixel_pairs // count].astype(np.int64)
    return np.unique(parts * count + pixel_pairs % count, return_counts=True)


def _neighbours(
    shape: tuple[int, ...], pixels: NDArray[np.intp], offsets: NDArray[np.intp]
) -> tuple[NDArray[np.intp], NDArray[np.bool_]]:
    """(S, L) flat indices of the pixels at the S (row, column) ``offsets`` from each of the L
    flat ``pixels`` of an image of ``shape``, and whether each lies in the image (those that do
    not get their own pixel's index)."""
    rows, cols = np.divmod(pixels, shape[1])
    there_rows = rows[None, :] + offsets[:, :1]
    there_cols = cols[None, :] + offsets[:, 1:]
    inside = (there_rows >= 0) & (there_rows < shape[0]) & (there_cols >= 0)
    inside &= there_cols < shape[1]
    there = np.where(inside, there_rows * shape[1] + there_cols, pixels[None, :])
    return there, inside


def _pair_gaps(
    points: NDArray[np.float32], here: NDArray[np.intp], there: NDArray[np.intp]
) -> NDArray[np.float32]:
    """(P,) squared 3-D distance (m^2) from each of the rows ``here`` (P,) of ``points``
    (N, 3) to the row ``there`` (P,) paired with it, channel by channel in float32."""
    near = np.take(points, here, axis=0)
    far = np.take(points, there, axis=0)
    offset = [far[:, k] - near[:, k] for k in range(3)]
    return offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]


def _window(
    shape: tuple[int, ...], pixels: NDArray[np.int64], reach: int
) -> tuple[slice, slice, NDArray[np.int64]]:
    """Row and column slices of the bounding box of the flat ``pixels`` of an image of
    ``shape``, grown by ``reach`` (cut at the image), and the pixels' flat indices in it."""
    rows, cols = np.divmod(pixels, shape[1])
    if len(pixels) == 0:
        return slice(0, 0), slice(0, 0), pixels
    top, left = max(int(rows.min()) - reach, 0), max(int(cols.min()) - reach, 0)
    right = min(int(cols.max()) + reach + 1, shape[1])
    window = (slice(top, min(int(rows.max()) + reach + 1, shape[0])), slice(left, right))
    return window[0], window[1], (rows - top) * (right - left) + cols - left


def _padded(
    labels: NDArray[np.int32], points: NDArray[np.float32], pixels: NDArray[np.int64], reach: int
) -> tuple[NDArray[np.int32], NDArray[np.float32], NDArray[np.int64]]:
    """``labels`` (H, W) padded by ``reach`` pixels of label 0, the (H, W, 3) ``points``
    padded alike as rows ((H + 2 reach) (W + 2 reach), 3), and the flat ``pixels`` as
    indices into the padded grid."""
    padded = zero_padded(labels, reach)
    planes = zero_padded(np.moveaxis(points, 2, 0), reach)
    rows, cols = np.divmod(pixels, labels.shape[1])
    return padded, planes.reshape(3, -1).T, (rows + reach) * padded.shape[1] + cols + reach


def _best_pairs(
    pairs: NDArray[np.int64], contacts: NDArray[np.int64], count: int, min_contact: int
) -> list[tuple[int, int]]:
    """For each thin segment, the larger segment it touches with the most contact pixels,
    when at least ``min_contact``; ``pairs`` are codes ``small * count + large``."""
    strong = contacts >= min_contact
    pairs, contacts = pairs[strong], contacts[strong]
    order = np.lexsort((-contacts, pairs // count))
    small = pairs[order] // count
    first = np.ones(len(order), dtype=bool)
    first[1:] = small[1:] != small[:-1]
    chosen = pairs[order][first]
    return [(int(c // count), int(c % count)) for c in chosen]


def table_edge_claims(
    labels: NDArray[np.int32],
    points: NDArray[np.float32],
    height: NDArray[np.float32],
    parents: NDArray[np.int32],
    config: SegmentConfig,
    grouped: LabelPixels,
) -> tuple[slice, slice, NDArray[np.int32]] | None:
    """The table pixels at a side part's edge (module docstring) given that part's label: the
    row and column slices of a window of ``labels`` holding every pixel of every side part,
    and the window's labels after the claims; None when there is no side part. ``parents`` as
    :func:`part_parents` returns them, ``grouped`` as it takes it."""
    is_part = parents != np.arange(len(parents))
    reach = config.part_edge_px
    if not is_part.any() or reach <= 0:
        return None
    flat = labels.reshape(-1)
    is_part[:FIRST_OBJECT] = False
    pixels = _pixels_of(is_part, grouped)
    rows, cols, inner = _window(labels.shape, pixels, reach)
    padded, padded_points, padded_pixels = _padded(
        labels[rows, cols], points[rows, cols], inner, reach
    )
    width = padded.shape[1]
    steps = np.arange(-reach, reach + 1)
    shifts = (steps[:, None] * width + steps[None, :]).reshape(-1)
    there = (padded_pixels[None, :] + shifts[:, None]).reshape(-1)  # (offset, pixel) pairs
    padded_height = zero_padded(height[rows, cols], reach).reshape(-1)
    window = padded.reshape(-1).copy()
    table = (window[there] == TABLE) & (padded_height[there] > config.part_edge_height)
    slots = np.flatnonzero(table)
    part = slots % len(pixels)
    gaps = _pair_gaps(padded_points, padded_pixels[part], there[slots])
    edge = gaps <= config.part_contact_distance**2
    window[there[slots[edge]]] = flat[pixels][part[edge]]
    return rows, cols, window.reshape(padded.shape)[reach:-reach, reach:-reach]
