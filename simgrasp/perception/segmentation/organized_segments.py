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

from simgrasp.perception.segmentation.segment_attach import attach_edges
from simgrasp.perception.segmentation.segment_config import SegmentConfig

Grid = NDArray[np.float32]


def grid_components(
    points: Grid,
    candidates: NDArray[np.bool_],
    viewpoint: NDArray[np.float64],
    config: SegmentConfig,
) -> NDArray[np.int32]:
    """Segment ids (H, W) of the ``candidates`` pixels (0 elsewhere), in no particular order.

    ``points`` is the (H, W, 3) position image (m, NaN where invalid). The candidates are cut
    group by group (:func:`candidate_groups`, at the reach of every step together), each in
    its bounding box: groups lie too far apart for any step to see two at once, and a group
    with fewer than ``min_object_points`` pixels can only give segments that are dropped, so
    it is skipped. Within a group the cuts are taken sub-group by sub-group
    (:func:`_split_cuts`). With ``normal_bin_px`` > 1 each group is cut whole in its box,
    whose corner lies on the blocks' grid anchored at the image's corner.
    """
    segments = np.zeros(candidates.shape, dtype=np.int32)
    next_id = 0
    size = config.normal_bin_px
    margin = size * (config.normal_window_px + 2 * config.normal_step_px)
    reach = margin + size * config.concave_step_px + config.attach_radius_px
    for rows, cols, group in candidate_groups(candidates, margin, reach, size):
        if np.count_nonzero(group) < config.min_object_points:
            continue
        crop = _crop_components(points[rows, cols], group, viewpoint, config)
        cut = crop > 0
        segments[rows, cols][cut] = crop[cut] + next_id
        next_id += int(crop.max())
    return segments


GROUP_BLOCK = 8
"""Edge (px) of the blocks in which :func:`candidate_groups` gathers candidate pixels: 1, 2, 4
or 8, since :func:`_blocks_any` reads a block row of booleans as one unsigned word."""


def candidate_groups(
    candidates: NDArray[np.bool_], margin: int, reach: int, align: int = 1
) -> list[tuple[slice, slice, NDArray[np.bool_]]]:
    """The ``candidates`` (H, W) split into groups whose pixels lie more than ``reach`` (px)
    apart: ``GROUP_BLOCK`` blocks holding a candidate, joined when dilations of the blocks
    make them touch (with no dilation, pixels of two groups are at least one block + 1
    apart; with one, 3 blocks + 1). Each group as the row and column slices of its blocks
    grown by ``margin`` (px), their starts a multiple of ``align`` (the normals' blocks of
    every group then lie on one grid anchored at the image's corner), and its pixels within
    them."""
    dilation = max(0, -(-(reach - GROUP_BLOCK) // (2 * GROUP_BLOCK)))
    (height, width), size = candidates.shape, GROUP_BLOCK
    padded = np.zeros((-(-height // size) * size, -(-width // size) * size), dtype=bool)
    padded[:height, :width] = candidates
    blocks = _blocks_any(padded)
    if dilation:  # (iterations=0 would dilate until nothing changes)
        grown = ndimage.binary_dilation(blocks, np.ones((3, 3), bool), iterations=dilation)
    ids, _ = ndimage.label(grown if dilation else blocks, np.ones((3, 3), bool))
    ids *= blocks
    groups = []
    for group, found in enumerate(ndimage.find_objects(ids), start=1):
        if found is None:
            continue
        top = max(found[0].start * size - margin, 0) // align * align
        left = max(found[1].start * size - margin, 0) // align * align
        rows = slice(top, found[0].stop * size + margin)
        cols = slice(left, found[1].stop * size + margin)
        groups.append(
            (
                rows,
                cols,
                candidates[rows, cols] & _group_pixels(ids, group, rows, cols, (height, width)),
            )
        )
    return groups


def _group_pixels(
    ids: NDArray[np.int32], group: int, rows: slice, cols: slice, shape: tuple[int, int]
) -> NDArray[np.bool_]:
    """Whether each pixel of the ``rows`` and ``cols`` of an image of ``shape`` (cut at its
    edge) lies in a ``GROUP_BLOCK`` block of ``group`` (``ids`` per block)."""
    size = GROUP_BLOCK
    top, left = rows.start // size, cols.start // size
    bottom, right = min(rows.stop, shape[0]), min(cols.stop, shape[1])
    blocks = ids[top : -(-bottom // size), left : -(-right // size)] == group
    pixels = np.repeat(np.repeat(blocks, size, axis=0), size, axis=1)
    return pixels[
        rows.start - top * size : bottom - top * size,
        cols.start - left * size : right - left * size,
    ]


def _blocks_any(padded: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Whether each ``GROUP_BLOCK`` x ``GROUP_BLOCK`` block of ``padded`` (H, W; multiples of
    the block) holds a True pixel: each block row of ``GROUP_BLOCK`` bytes read as one word."""
    rows = padded.view(np.dtype(f"u{GROUP_BLOCK}"))
    words = rows.reshape(padded.shape[0] // GROUP_BLOCK, GROUP_BLOCK, -1)
    return np.bitwise_or.reduce(words, axis=1) != 0


def bounding_slices(mask: NDArray[np.bool_], margin: int) -> tuple[slice, slice]:
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
    """Segment ids of the ``candidates`` pixels of the (H, W, 3) crop ``points``: the
    connected pixels left between the cuts (:func:`_split_cuts`, or :func:`_cuts` of the
    whole crop with ``normal_bin_px`` > 1; closed by ``cut_close_px``), numbered in raster
    order, then the cut pixels attached (:func:`attach_edges`)."""
    if candidates.size == 0:
        return np.zeros(candidates.shape, dtype=np.int32)
    if config.normal_bin_px == 1:
        cut, kept = _split_cuts(points, candidates, viewpoint, config)
    else:
        cut, kept = _cuts(points, candidates, viewpoint, config), candidates
    if config.cut_close_px:
        cut = _closed_cuts(cut, kept, config.cut_close_px)
    segments, _ = ndimage.label(kept & ~cut)
    segments = segments.astype(np.int32, copy=False)
    flat_planes = _masked_planes(points, kept, config.attach_radius_px).reshape(3, -1)
    return attach_edges(segments, flat_planes, kept, config)


def _closed_cuts(cut: NDArray[np.bool_], kept: NDArray[np.bool_], steps: int) -> NDArray[np.bool_]:
    """The ``cut`` pixels (H, W) of the ``kept`` candidates with their gaps of up to
    ``2 steps`` pixels closed: a closing (4-neighbour steps) of the cuts together with all
    that is not a candidate, the crop's border counted as outside, cut to the candidates."""
    pad = steps + 1
    barrier = np.pad(cut | ~kept, pad, constant_values=True)
    closed = ndimage.binary_closing(barrier, iterations=steps)[pad:-pad, pad:-pad]
    return closed & kept


def _split_cuts(
    points: Grid,
    candidates: NDArray[np.bool_],
    viewpoint: NDArray[np.float64],
    config: SegmentConfig,
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """The cut pixels (H, W) of the ``candidates`` of the (H, W, 3) crop ``points``, taken
    sub-group by sub-group (:func:`candidate_groups` at the reach of the cuts' own steps and
    of the attach radius, 7 px by default: a group's bounding box is mostly empty when sensor
    speckles chain its objects), and the candidates kept: those of sub-groups of at least
    ``min_object_points`` pixels (the others can only give segments that are dropped, and no
    other pixel attaches to them). A pixel's cut reads the candidates within the normals'
    half window + baseline + the concave baseline of it (7 px by default), all of its own
    sub-group, and, while the normals' margin covers that reach (9 px by default), inside its
    sub-group's box, so it is the same as in the group's box (labels and objects bit-identical
    to the cut of whole groups on 45 osd-learn and 24 clutter frames, several settings). Each
    sub-group is cut in the bounding box of its pixels grown by the normals' half window:
    beyond it the box means are NaN (no pixel in the window) and the filters' running sums see
    only zeros, so the cuts are the same bit for bit in a smaller box."""
    margin = config.normal_window_px + 2 * config.normal_step_px
    reach = config.normal_window_px // 2 + config.normal_step_px + config.concave_step_px
    cut = np.zeros(candidates.shape, dtype=bool)
    kept = candidates.copy()
    for rows, cols, group in candidate_groups(
        candidates, margin, max(reach, config.attach_radius_px)
    ):
        if np.count_nonzero(group) < config.min_object_points:
            kept[rows, cols] &= ~group
            continue
        tight_rows, tight_cols = bounding_slices(group, config.normal_window_px // 2)
        tight = group[tight_rows, tight_cols]
        crop_cut = _cuts(points[rows, cols][tight_rows, tight_cols], tight, viewpoint, config)
        cut[rows, cols][tight_rows, tight_cols] |= crop_cut & tight
    return cut, kept


def _cuts(
    points: Grid,
    candidates: NDArray[np.bool_],
    viewpoint: NDArray[np.float64],
    config: SegmentConfig,
) -> NDArray[np.bool_]:
    """Cut pixels (H, W) of the ``candidates`` of the (H, W, 3) crop ``points``: depth steps
    and concave creases. The steps work on channel planes (3, H, W): each coordinate a
    contiguous image, zero outside the candidates, sums of products written out component
    by component (the same float32 operations as ``einsum``)."""
    eye = viewpoint.astype(np.float32)[:, None, None]
    planes = _masked_planes(points, candidates, 0)
    binned, binned_mask = _binned(points, candidates, config.normal_bin_px)
    binned_planes = planes if binned is points else _masked_planes(binned, binned_mask, 0)
    smooth = _box_mean(binned_planes, binned_mask, config.normal_window_px)
    normals = _grid_normals(smooth, eye, config.normal_step_px)
    concave = _concave_cuts(smooth, normals, config.concave_step_px, config.concave_threshold)
    cut = _depth_cuts(planes, candidates, eye, config.depth_jump)
    cut |= _unbinned(concave, config.normal_bin_px, candidates.shape)
    return cut


def _masked_planes(points: Grid, mask: NDArray[np.bool_], reach: int) -> Grid:
    """(3, H + 2 reach, W + 2 reach) the (H, W, 3) positions as three contiguous channel
    planes, zero outside ``mask`` (H, W) and in a border of ``reach`` pixels."""
    height, width = mask.shape
    planes = np.zeros((3, height + 2 * reach, width + 2 * reach), dtype=points.dtype)
    inner = planes[:, reach : reach + height, reach : reach + width]
    for channel in range(3):
        np.copyto(inner[channel], points[..., channel], where=mask)
    return planes


def _binned(points: Grid, mask: NDArray[np.bool_], size: int) -> tuple[Grid, NDArray[np.bool_]]:
    """Mean position of the masked pixels in each ``size`` x ``size`` block (NaN if none), and
    the mask of blocks holding any."""
    if size == 1:
        return points, mask
    height, width = -(-mask.shape[0] // size) * size, -(-mask.shape[1] // size) * size
    padded = np.zeros((height, width, 3), dtype=np.float32)
    padded[: mask.shape[0], : mask.shape[1]] = np.where(mask[..., None], points, 0.0)
    counts = np.zeros((height, width), dtype=np.float32)
    counts[: mask.shape[0], : mask.shape[1]] = mask
    shape = (height // size, size, width // size, size)
    sums = padded.reshape(*shape, 3).sum(axis=(1, 3))
    count = counts.reshape(shape).sum(axis=(1, 3))
    with np.errstate(invalid="ignore", divide="ignore"):
        return sums / count[..., None], count > 0


def _unbinned(blocks: NDArray[np.bool_], size: int, shape: tuple[int, ...]) -> NDArray[np.bool_]:
    """A block mask blown up to pixels and cut to ``shape``."""
    if size == 1:
        return blocks
    return np.repeat(np.repeat(blocks, size, axis=0), size, axis=1)[: shape[0], : shape[1]]


def _box_mean(planes: Grid, mask: NDArray[np.bool_], size: int) -> Grid:
    """Mean position (3, H, W) over each ``size`` x ``size`` window of the masked pixels of
    ``planes`` (3, H, W; zero outside ``mask``; NaN where a window holds none)."""
    count = ndimage.uniform_filter(mask.view(np.uint8), size, np.float32, mode="constant")
    mean = ndimage.uniform_filter1d(planes, size, axis=1, mode="constant")
    mean = ndimage.uniform_filter1d(mean, size, axis=2, mode="constant")
    with np.errstate(invalid="ignore", divide="ignore"):
        mean /= count
    np.copyto(mean, np.float32(np.nan), where=count < 0.5 / (size * size))
    return mean


def _grid_normals(smooth: Grid, eye: NDArray[np.float32], step: int) -> Grid:
    """Unit normals (3, H, W) from central differences over ``step`` pixels of ``smooth``
    (3, H, W), turned toward ``eye`` (3, 1, 1); NaN where a neighbour is missing. Written
    into reused buffers (the float32 operations of the cross product and :func:`_dot_into`)."""
    du, dv = np.empty_like(smooth), np.empty_like(smooth)
    for border in (slice(None, step), slice(-step, None)):  # NaN where a neighbour is missing
        du[:, :, border] = np.nan
        dv[:, border] = np.nan
    np.subtract(smooth[:, :, 2 * step :], smooth[:, :, : -2 * step], out=du[:, :, step:-step])
    np.subtract(smooth[:, 2 * step :], smooth[:, : -2 * step], out=dv[:, step:-step])
    normals = np.empty_like(smooth)
    scratch = np.empty_like(smooth[0])
    for axis, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):
        np.multiply(du[a], dv[b], out=normals[axis])
        np.multiply(du[b], dv[a], out=scratch)
        normals[axis] -= scratch
    length = _dot_into(normals, normals, scratch, du[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        normals /= np.sqrt(length, out=length)
    np.subtract(eye, smooth, out=dv)
    toward = _dot_into(normals, dv, du[1], du[2])
    np.negative(normals, out=normals, where=toward < 0)
    return normals


def _dot_into(a: Grid, b: Grid, out: Grid, scratch: Grid) -> Grid:
    """Per-pixel dot product ``a[0] b[0] + a[1] b[1] + a[2] b[2]`` of two (3, ...) channel
    stacks (float32, in that order) written into ``out``,
    with ``scratch`` a buffer of its shape."""
    np.multiply(a[0], b[0], out=out)
    for channel in (1, 2):
        np.multiply(a[channel], b[channel], out=scratch)
        out += scratch
    return out


def _depth_cuts(
    planes: Grid, mask: NDArray[np.bool_], eye: NDArray[np.float32], jump: float
) -> NDArray[np.bool_]:
    """Pixels with a 4-neighbour whose range differs by more than ``jump`` x range^2 (m);
    ``planes`` (3, H, W), ``eye`` (3, 1, 1)."""
    offset = planes - eye
    ranges = np.sqrt(_dot_into(offset, offset, offset[0], offset[1]), out=offset[0])
    np.copyto(ranges, np.float32(np.nan), where=~mask)
    limit = np.multiply(ranges, jump, out=offset[1])
    limit *= ranges
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
    ``(n_j - n_i) . u_ij < -threshold``, ``u_ij`` the unit direction from i to j (``smooth``
    and ``normals`` (3, H, W))."""
    cut = np.zeros(smooth.shape[1:], dtype=bool)
    for axis in (1, 2):
        lo = [slice(None)] * 3
        hi = [slice(None)] * 3
        lo[axis], hi[axis] = slice(None, -step), slice(step, None)
        offset = smooth[tuple(hi)] - smooth[tuple(lo)]
        turn = normals[tuple(hi)] - normals[tuple(lo)]
        fold = _dot_into(turn, offset, turn[0], turn[1])  # turn[0] read before written
        limit = _dot_into(offset, offset, turn[2], turn[1])
        with np.errstate(invalid="ignore"):
            limit = np.sqrt(limit, out=limit)
            limit *= -threshold
            concave = fold < limit
        for shift in range(step + 1):
            span = [slice(None), slice(None)]
            span[axis - 1] = slice(shift, shift + concave.shape[axis - 1])
            cut[tuple(span)] |= concave
    return cut
