"""Split a whole scene cloud into its supporting plane (the table) and the objects on it.

The table is the dominant plane (RANSAC on a seeded subsample, refined by least squares on
its inliers, then on the points within ``table_distance`` of it). Above it, an organized cloud
is cut into objects on its image grid
(:mod:`simgrasp.perception.segmentation.organized_segments`: depth steps and concave creases
separate stacked and touching objects; pieces too small to be objects join the segment they
touch, :mod:`simgrasp.perception.segmentation.segment_fragments`), its pixel settings at the
sensor's pixel scale (:mod:`simgrasp.perception.segmentation.segment_scale`); an unorganized
one, or ``method="dbscan"``, is clustered with Open3D's DBSCAN on a voxel grid (the baseline).

Labels, one int32 per input point in the input's order: 0 invalid or unassigned (NaN,
beyond range, below the table, too small a segment), 1 table, 2.. objects by increasing
distance of their centroid to the sensor.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import import_open3d
from simgrasp.perception.camera import TRANSFORM_BLOCK
from simgrasp.perception.scene_cloud import SceneCloud
from simgrasp.perception.segmentation.organized_segments import grid_components
from simgrasp.perception.segmentation.segment_config import (
    FIRST_OBJECT as FIRST_OBJECT,  # re-exported: the plots and the evaluation read it here
)
from simgrasp.perception.segmentation.segment_config import TABLE, SegmentConfig
from simgrasp.perception.segmentation.segment_floors import inner_floors
from simgrasp.perception.segmentation.segment_fragments import absorb_fragments
from simgrasp.perception.segmentation.segment_objects import (
    LabelPixels,
    SegmentedObject,
    label_pixels,
    objects_of,
    ordered_labels,
)
from simgrasp.perception.segmentation.segment_parts import part_parents, table_edge_claims
from simgrasp.perception.segmentation.segment_rims import rim_parents
from simgrasp.perception.segmentation.segment_scale import pixel_footprint, pixel_scale, scaled
from simgrasp.seeding import rng_for

Method = Literal["auto", "grid", "dbscan"]


@dataclass(frozen=True)
class Segmentation:
    """What :func:`segment_scene` returns.

    Attributes:
        labels: (N,) int32 per input point, in order (an H x W image: ``reshape(H, W)``):
            0 invalid, 1 table, 2.. objects nearest the sensor first.
        plane: (4,) table plane ``[a, b, c, d]``, unit normal toward the sensor:
            ``a x + b y + c z + d`` is the height above the table (m).
        table_points: number of points labeled table.
        objects: the objects, label 2 first (nearest the sensor).
        timings_s: wall seconds per step, and ``total`` for the whole call.
        pixel_scale: the scale the pixel settings ran at (1: as given;
            :mod:`simgrasp.perception.segmentation.segment_scale`).
    """

    labels: NDArray[np.int32]
    plane: NDArray[np.float64]
    table_points: int
    objects: tuple[SegmentedObject, ...]
    timings_s: dict[str, float]
    pixel_scale: int = 1

    def to_json(self) -> dict[str, Any]:
        return {
            "table": {"plane": self.plane.tolist(), "points": self.table_points},
            "objects": [obj.to_json() for obj in self.objects],
            "timings_s": dict(self.timings_s),
            "pixel_scale": self.pixel_scale,
        }

    def whole_objects(self) -> tuple[int, ...]:
        """Labels of the objects that are not a side part of another."""
        return tuple(obj.label for obj in self.objects if obj.part_of == obj.label)

    def object_mask(self, label: int) -> NDArray[np.bool_]:
        """(N,) the points of object ``label`` and of its side parts."""
        members = [obj.label for obj in self.objects if label in (obj.label, obj.part_of)]
        return np.isin(self.labels, members or [label])


def segment_scene(
    scene: SceneCloud, config: SegmentConfig | None = None, method: Method = "auto"
) -> Segmentation:
    """Segment ``scene`` (module docstring); ``ValueError`` naming the scene when it has no
    valid point, no table plane, or coordinates that are not meters."""
    given = config or SegmentConfig()
    if method == "auto":
        method = "grid" if scene.organized else "dbscan"
    if method == "grid" and not scene.organized:
        raise SimgraspError(f"{scene.source or 'scene'}: method 'grid' needs an organized cloud")
    timings: dict[str, float] = {}
    start = time.perf_counter()
    points = scene.points
    valid = _timed(timings, "valid", lambda: _valid_points(scene, given))
    plane = _timed(timings, "plane", lambda: fit_table_plane(points, valid, scene, given))
    height, table, above = _heights(points, valid, plane, given)
    scale = 1
    if method == "grid":
        scale = pixel_scale(pixel_footprint(scene, valid), given.reference_footprint)
    config = scaled(given, scale)
    cluster = _grid_segments if method == "grid" else _dbscan_segments
    raw = _timed(timings, "cluster", lambda: cluster(scene, above, config))
    if method == "grid":
        _timed(timings, "floors", lambda: _floors(scene, raw, table, above, config))
        if config.fragment_passes:
            shape = (scene.height, scene.width)
            _timed(timings, "fragments", lambda: absorb_fragments(raw, points, shape, config))
    labels, objects, pixels = _timed(
        timings,
        "order",
        lambda: ordered_labels(raw, table, points, scene.viewpoint, config.min_object_points),
    )
    if method == "grid":
        objects = _timed(
            timings,
            "parts",
            lambda: _parts(scene, labels, height, plane, (objects, pixels), config),
        )
        table = labels == TABLE
    timings["total"] = time.perf_counter() - start
    return Segmentation(labels, plane, int(table.sum()), objects, timings, scale)


def _heights(
    points: NDArray[np.float32],
    valid: NDArray[np.bool_],
    plane: NDArray[np.float64],
    config: SegmentConfig,
) -> tuple[NDArray[np.float32], NDArray[np.bool_], NDArray[np.bool_]]:
    """(N,) float32 height of each point above ``plane`` (m), and which ``valid`` points are
    the table (within ``table_distance`` of it) and which above it (below
    ``max_object_height``), in place: a valid point's height is finite, so ``|h| <= d`` is
    ``h >= -d`` and not ``h > d``."""
    height = row_dot(points, plane[:3].astype(np.float32))
    height += np.float32(plane[3])
    high = height > config.table_distance
    table = height >= -config.table_distance
    table &= valid
    table &= ~high
    above = height < config.max_object_height
    above &= valid
    above &= high
    return height, table, above


def row_dot(points: NDArray[np.float32], vector: NDArray[np.float32]) -> NDArray[np.float32]:
    """(N,) ``points @ vector`` in blocks of ``TRANSFORM_BLOCK`` rows (one BLAS thread's worth;
    the same result per row)."""
    out = np.empty(len(points), dtype=np.result_type(points, vector))
    for start in range(0, len(points), TRANSFORM_BLOCK):
        block = slice(start, start + TRANSFORM_BLOCK)
        np.matmul(points[block], vector, out=out[block])
    return out


def _timed(timings: dict[str, float], step: str, work: Callable[[], Any]) -> Any:
    start = time.perf_counter()
    result = work()
    timings[step] = time.perf_counter() - start
    return result


def _valid_points(scene: SceneCloud, config: SegmentConfig) -> NDArray[np.bool_]:
    """(N,) whether each point is finite, not at the sensor and within ``max_range`` (m) of
    it; ``ValueError`` naming the scene when none is finite or their median range says the
    units are not meters."""
    name = scene.source or "scene"
    points, eye = scene.points, scene.viewpoint.astype(np.float32)
    squared = _squared_ranges(points, eye)
    finite = np.isfinite(squared)
    if not finite.any():
        raise SimgraspError(f"{name}: no valid point (every point is NaN or inf)")
    median = float(np.sqrt(np.median(np.take(squared, np.flatnonzero(finite)[::97]))))
    if median > config.max_range:
        raise SimgraspError(
            f"{name}: points lie a median {median:.4g} units from the sensor, beyond "
            f"max_range {config.max_range} m: coordinates must be meters (millimetres?)"
        )
    valid = squared <= config.max_range**2  # False where NaN or inf, as finite is
    valid &= squared > 0
    return valid


def _squared_ranges(points: NDArray[np.float32], eye: NDArray[np.float32]) -> NDArray[np.float32]:
    """(N,) float32 squared distance (m^2) of each of ``points`` (N, 3) from ``eye`` (3,):
    ``x x + y y + z z``, then ``+ e.e - 2 p.e`` when ``eye`` is off the origin (``p.e`` as
    :func:`row_dot` takes it), in blocks of ``TRANSFORM_BLOCK`` rows through two reused
    block buffers: no (N, 3) temporary, each block's squares summed while in cache."""
    squared = np.empty(len(points), dtype=np.float32)
    squares = np.empty((min(len(points), TRANSFORM_BLOCK), 3), dtype=np.float32)
    toward = np.empty(len(squares), dtype=np.float32)
    offset = eye @ eye if eye.any() else None
    for start in range(0, len(points), TRANSFORM_BLOCK):
        block = points[start : start + TRANSFORM_BLOCK]
        rows, out = len(block), squared[start : start + TRANSFORM_BLOCK]
        np.multiply(block, block, out=squares[:rows])
        np.add(squares[:rows, 0], squares[:rows, 1], out=out)
        out += squares[:rows, 2]
        if offset is not None:
            np.matmul(block, eye, out=toward[:rows])
            toward[:rows] *= 2.0
            out += np.subtract(offset, toward[:rows], out=toward[:rows])
    return squared


def fit_table_plane(
    points: NDArray[np.float32], valid: NDArray[np.bool_], scene: SceneCloud, config: SegmentConfig
) -> NDArray[np.float64]:
    """The dominant plane of the ``valid`` ``points`` (m), unit normal turned toward the sensor:
    RANSAC on ``plane_samples`` seeded points, then least squares on the inliers among
    ``refine_samples`` seeded points, then ``TABLE_REFITS`` times on those within
    ``table_distance`` of the plane."""
    name = scene.source or "scene"
    index = np.flatnonzero(valid)
    if len(index) < 3:
        raise SimgraspError(f"{name}: too few valid points ({len(index)}) to find a table plane")
    rng = rng_for(config.seed, "segment", "plane")
    sample = np.take(points, index[rng.integers(0, len(index), config.plane_samples)], axis=0)
    plane = _ransac_plane(sample.astype(np.float64), rng, config, name)
    refine = np.take(points, index[rng.integers(0, len(index), config.refine_samples)], axis=0)
    plane = _refined_plane(refine, plane, config.plane_distance)
    for _ in range(TABLE_REFITS):
        plane = _refined_plane(refine, plane, config.table_distance)
    _check_table(np.abs(refine @ plane[:3] + plane[3]), config, name)
    if plane[:3] @ scene.viewpoint + plane[3] < 0:
        plane = -plane
    return plane


def _check_table(distance: NDArray[np.float64], config: SegmentConfig, name: str) -> None:
    """``ValueError`` unless the plane, at ``distance`` (m) from sampled points, is a table:
    enough inliers (``min_plane_share``) and flat (``min_plane_flatness``)."""
    inliers = distance <= config.plane_distance
    share = float(np.mean(inliers))
    if share < config.min_plane_share:
        raise SimgraspError(
            f"{name}: no table plane (the best plane holds {share:.1%} of the valid points, "
            f"min_plane_share is {config.min_plane_share:.0%})"
        )
    flatness = float(np.mean(distance[inliers] <= config.table_distance))
    if flatness < config.min_plane_flatness:
        raise SimgraspError(
            f"{name}: no table plane (the best plane is curved: {flatness:.0%} of its inliers "
            f"lie within table_distance, min_plane_flatness is {config.min_plane_flatness:.0%})"
        )


VOTE_BLOCK = 256
"""Sample rows per matrix product of the RANSAC vote: OpenBLAS spreads one (2000, 3) x
(3, 100) product over threads, which on the shared 2-core machine now and then cost ~8 ms
instead of ~0.1; each entry is the same either way, and the votes are counts."""


def _ransac_plane(
    sample: NDArray[np.float64], rng: np.random.Generator, config: SegmentConfig, name: str
) -> NDArray[np.float64]:
    """The plane through three ``sample`` points with the most inliers (m)."""
    triples = sample[rng.integers(0, len(sample), (config.plane_iterations, 3))]
    normals = np.cross(triples[:, 1] - triples[:, 0], triples[:, 2] - triples[:, 0])
    length = np.linalg.norm(normals, axis=1)
    good = length > 1e-12
    if not good.any():
        raise SimgraspError(f"{name}: no table plane (the valid points are collinear)")
    normals = normals[good] / length[good, None]
    offsets = -np.einsum("kj,kj->k", normals, triples[good, 0])
    votes = np.zeros(len(normals), dtype=np.int64)
    for start in range(0, len(sample), VOTE_BLOCK):  # one BLAS thread's worth each
        block = sample[start : start + VOTE_BLOCK] @ normals.T + offsets
        votes += (np.abs(block) <= config.plane_distance).sum(axis=0)
    best = int(np.argmax(votes))
    return np.append(normals[best], offsets[best])


TABLE_REFITS = 2
"""Least-squares refits of the table plane on the points within ``table_distance`` of the
previous plane, after the fit of all the RANSAC plane's inliers: flat objects on a crowded
table (pans, boards, a spatula's blade) lie within ``plane_distance`` of it and tilt that
first fit toward them; the refits keep the table's own points."""


def _refined_plane(
    points: NDArray[np.float32], plane: NDArray[np.float64], band: float
) -> NDArray[np.float64]:
    """Least-squares plane through the ``points`` within ``band`` (m) of ``plane`` (m)."""
    inliers = points[np.abs(points @ plane[:3] + plane[3]) <= band]
    if len(inliers) < 3:
        return plane
    center = inliers.mean(axis=0, dtype=np.float64)
    centered = inliers - center
    _, vectors = np.linalg.eigh(centered.T @ centered)
    normal = vectors[:, 0]
    return np.append(normal, -normal @ center)


def _parts(
    scene: SceneCloud,
    labels: NDArray[np.int32],
    height: NDArray[np.float32],
    plane: NDArray[np.float64],
    found: tuple[tuple[SegmentedObject, ...], LabelPixels],
    config: SegmentConfig,
) -> tuple[SegmentedObject, ...]:
    """The ``found`` objects (with their pixels) with ``part_of`` set, and ``labels`` (N,)
    with the side parts' table edges claimed, in place
    (:mod:`simgrasp.perception.segmentation.segment_parts`, on the image grid; with
    ``rim_band``, a round container's inside joined to its outside, :mod:`.segment_rims`)."""
    objects, pixels = found
    shape = (scene.height, scene.width)
    grid, height_grid, image = scene.grid(), height.reshape(shape), labels.reshape(shape)
    parents = part_parents(image, grid, height_grid, config, pixels)
    claims = table_edge_claims(image, grid, height_grid, parents, config, pixels)
    redone: dict[int, SegmentedObject] = {}
    if claims is not None:
        rows, cols, window = claims
        changed = np.unique(window[window != image[rows, cols]])
        image[rows, cols] = window
        redone = _objects_in(window, (rows.start, cols.start), scene, changed)
    parents = rim_parents(labels, scene.points, height, plane, parents, config)
    return tuple(
        replace(redone.get(obj.label, obj), part_of=int(parents[obj.label])) for obj in objects
    )


def _objects_in(
    window: NDArray[np.int32],
    corner: tuple[int, int],
    scene: SceneCloud,
    wanted: NDArray[np.int32],
) -> dict[int, SegmentedObject]:
    """The objects of the ``wanted`` labels, all of whose pixels lie in ``window``, the labels
    of the rows and columns of the scene's image from ``corner`` on."""
    if len(wanted) == 0:
        return {}
    local = np.flatnonzero(np.isin(window, wanted))
    rows, cols = np.divmod(local, window.shape[1])
    index = (rows + corner[0]) * scene.width + cols + corner[1]
    count = int(wanted.max()) + 1
    pixels = label_pixels(window.reshape(-1)[local], index, count)
    return {obj.label: obj for obj in objects_of(pixels, scene.points, wanted.astype(np.intp))}


def _floors(
    scene: SceneCloud,
    raw: NDArray[np.int32],
    table: NDArray[np.bool_],
    above: NDArray[np.bool_],
    config: SegmentConfig,
) -> None:
    """The objects' inner floors (:func:`inner_floors`) moved from ``table`` (N,) to segments
    of their own in ``raw`` (N,; ids after its largest), in place."""
    shape = (scene.height, scene.width)
    rows, cols, floors = inner_floors(table.reshape(shape), above.reshape(shape), config)
    if floors.size == 0:
        return
    floor = floors > 0
    np.copyto(raw.reshape(shape)[rows, cols], floors + raw.max(), where=floor)
    table.reshape(shape)[rows, cols] &= ~floor


def _grid_segments(
    scene: SceneCloud, above: NDArray[np.bool_], config: SegmentConfig
) -> NDArray[np.int32]:
    mask = above.reshape(scene.height, scene.width)
    return grid_components(scene.grid(), mask, scene.viewpoint, config).reshape(-1)


def _dbscan_segments(
    scene: SceneCloud, above: NDArray[np.bool_], config: SegmentConfig
) -> NDArray[np.int32]:
    """Open3D DBSCAN on the ``cluster_voxel`` grid of the above-table points; each point gets
    its voxel's cluster (1-based, 0 for noise)."""
    segments = np.zeros(len(above), dtype=np.int32)
    index = np.flatnonzero(above)
    if len(index) == 0:
        return segments
    cells = np.floor(scene.points[index] / config.cluster_voxel).astype(np.int64)
    cells -= cells.min(axis=0)
    span = cells.max(axis=0) + 1
    keys = (cells[:, 0] * span[1] + cells[:, 1]) * span[2] + cells[:, 2]
    _, voxel_of, counts = np.unique(keys, return_inverse=True, return_counts=True)
    centers = np.zeros((len(counts), 3))
    np.add.at(centers, voxel_of.reshape(-1), scene.points[index])
    o3d = import_open3d()
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(centers / counts[:, None]))
    clusters = np.asarray(cloud.cluster_dbscan(config.cluster_eps, config.cluster_min_points))
    segments[index] = clusters[voxel_of.reshape(-1)] + 1
    return segments
