"""The flat-plate handle test: a thin horizontal plate standing off an object's body (a pot's
side tab), grasped across its thickness.

A quadric fitted to a flat plate seen face-on at Kinect-class resolution shows no curvature, so
the quadric tests never accept a pot's flat side tab seen from above. With the supporting
table's plane known (a tabletop scene; ``up`` its upward normal), a neighborhood center ``c``
is a plate handle when, in its surroundings within ``plate_reach`` (cloud frame, meters):

1. thin: the heights (along ``up``) of the points within ``neighborhood_half_size`` of ``c``
   span at most ``plate_max_thickness`` (5th-95th percentile): a horizontal plate;
2. on a body: at least ``plate_min_body`` points lie farther than that above or below the
   plate's height (the body the plate stands off); ``d``, the horizontal direction from the
   object's centroid to ``c``, is the way the plate must stand off, toward its free edge;
3. clear for the fingers: within ``plate_finger_half_width`` of the line through ``c`` along
   ``d`` and within ``plate_finger_clearance`` above and below, at most ``plate_max_blocked``
   of the points from ``c`` outward lie off the plate (the jaws close across the plate from
   above and below); the points are everything the sensor saw (the scene, when given)
   higher than ``plate_edge_margin`` above the table;
4. standing off: the plate's free edge (95th percentile along ``d`` of the plate's points in
   that corridor) lies at least ``plate_min_protrusion`` beyond the body's front (95th
   percentile of the body's points behind ``c``), and at most ``plate_max_depth`` beyond
   ``c`` (the fingers reach the grasp point from the edge);
5. a seen edge: the point just past the free edge (``plate_edge_margin``) at the plate's
   height, and the one below it where the lower finger goes (``plate_finger_clearance``
   below, at most down to ``plate_edge_margin`` above the table), are seen by the sensor: no
   point of the scene lies within ``plate_ray_radius`` of the ray from the viewpoint to
   either. The space past and under the edge is free, not hidden behind a nearer surface:
   the seen edge of a pot's floor, cut by its front rim, is no edge, nor is the far edge of
   a box's top, seen above its front face (the box's back face is under it, unseen).

The handle axis of a plate is its edge direction (``up x d``), its grasp width the plate's
thickness (the height span of test 1).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from simgrasp.handles.core.config import QuadricDetectorConfig

RAY_STEP = 0.003
"""Spacing (m) of the sample points along a ray checked for occluders (one voxel)."""
RAY_START = 0.01
"""Distance (m) from the checked point at which the occluder search along its ray starts:
the plate's own edge, a margin away, does not occlude it."""


@dataclass(frozen=True)
class PlateHandles:
    """The plate test on a batch of B neighborhood centers (cloud frame, m).

    Attributes:
        accepted: (B,) the center is a plate handle.
        axes: (B, 3) unit edge directions (NaN where not accepted).
        widths: (B,) plate thickness (m; NaN where not accepted).
    """

    accepted: NDArray[np.bool_]
    axes: NDArray[np.float64]
    widths: NDArray[np.float64]


def plate_handles(
    points: NDArray[np.float64],
    tree: cKDTree,
    centers: NDArray[np.float64],
    table: NDArray[np.float64],
    viewpoint: NDArray[np.float64],
    config: QuadricDetectorConfig,
    sight: cKDTree | None = None,
) -> PlateHandles:
    """The plate test (module docstring) at each of the (B, 3) ``centers`` of the cloud
    ``points`` (its KD-tree ``tree``), ``table`` the supporting plane ``[a, b, c, d]`` (unit
    normal up, ``a x + b y + c z + d`` the height above it) and
    ``viewpoint`` the sensor position, all in the cloud frame (m). ``sight`` is a KD-tree of
    everything the sensor saw (the whole scene the object was cut from) for test 5; by
    default the object's own points (an occluder cut away with another object is missed)."""
    count = len(centers)
    result = PlateHandles(
        np.zeros(count, bool), np.full((count, 3), np.nan), np.full(count, np.nan)
    )
    if count == 0:
        return result
    up = table[:3] / np.linalg.norm(table[:3])
    near = tree.query_ball_point(centers, config.neighborhood_half_size)
    around = tree.query_ball_point(centers, config.plate_reach)
    sight = sight or tree
    middle = points.mean(axis=0)
    for i, center in enumerate(centers):
        found = _plate_at(points, center, near[i], around[i], up, middle, config)
        if found is None or _blocked(sight, center, found, table, config):
            continue
        if _seen(sight, viewpoint, found.past_edge, table, config):
            result.accepted[i] = True
            result.axes[i], result.widths[i] = found.edge_axis, found.thickness
    return result


@dataclass(frozen=True)
class _Plate:
    """A center that passed tests 1, 2 and 4: the plate's unit edge direction and outward
    direction, its thickness and the height of its middle above the center (m), and the
    point just past its free edge (cloud frame)."""

    edge_axis: NDArray[np.float64]
    outward: NDArray[np.float64]
    thickness: float
    level: float
    past_edge: NDArray[np.float64]


def _plate_at(
    points: NDArray[np.float64],
    center: NDArray[np.float64],
    near: list[int],
    around: list[int],
    up: NDArray[np.float64],
    middle: NDArray[np.float64],
    config: QuadricDetectorConfig,
) -> _Plate | None:
    """The plate at ``center`` when it passes tests 1, 2 and 4 of the plate test, else
    None."""
    if len(near) < config.min_points:
        return None
    heights = (points[near] - center) @ up
    low, level, high = np.percentile(heights, [5, 50, 95])
    if high - low > config.plate_max_thickness:
        return None
    offsets = points[around] - center
    height = offsets @ up - level
    body = np.abs(height) > config.plate_max_thickness
    if body.sum() < config.plate_min_body:
        return None
    outward = center - middle
    outward -= (outward @ up) * up
    if np.linalg.norm(outward) < 1e-9:
        return None
    outward /= np.linalg.norm(outward)
    edge_axis = np.cross(up, outward)
    edge = _free_edge(offsets @ outward, np.abs(offsets @ edge_axis), body, config)
    if edge is None:
        return None
    past_edge = center + (edge + config.plate_edge_margin) * outward
    return _Plate(edge_axis, outward, float(high - low), float(level), past_edge)


def _blocked(
    sight: cKDTree,
    center: NDArray[np.float64],
    plate: _Plate,
    table: NDArray[np.float64],
    config: QuadricDetectorConfig,
) -> bool:
    """Test 3 against everything seen (``sight``): the share of the points in the fingers'
    corridor, from ``center`` outward, that lie off the plate, higher than
    ``plate_edge_margin`` above the table (the table under a low tab is not in the way)."""
    scale = np.linalg.norm(table[:3])
    seen = sight.data[sight.query_ball_point(center, config.plate_reach)]
    seen = seen[(seen @ table[:3] + table[3]) / scale > config.plate_edge_margin]
    offsets = seen - center
    height = offsets @ (table[:3] / scale) - plate.level
    fingers = np.abs(offsets @ plate.edge_axis) <= config.plate_finger_half_width
    fingers &= (offsets @ plate.outward > -config.plate_edge_margin) & (
        np.abs(height) <= config.plate_finger_clearance
    )
    off_plate = fingers & (np.abs(height) > config.plate_max_thickness)
    return bool(off_plate.sum() > config.plate_max_blocked * max(int(fingers.sum()), 1))


def _free_edge(
    along: NDArray[np.float64],
    across: NDArray[np.float64],
    body: NDArray[np.bool_],
    config: QuadricDetectorConfig,
) -> float | None:
    """Test 4 on the points around a center: offsets ``along`` the outward direction and
    ``across`` it (m), ``body`` the points off the plate. The free edge's offset along the
    outward direction (m), or None."""
    corridor = across <= config.plate_finger_half_width
    behind = corridor & body & (along <= -config.plate_edge_margin)
    plate = corridor & ~body
    if not behind.any() or not plate.any():
        return None
    front = float(np.percentile(along[behind], 95))
    edge = float(np.percentile(along[plate], 95))
    if edge > config.plate_max_depth or edge - front < config.plate_min_protrusion:
        return None
    return edge


def _seen(
    tree: cKDTree,
    viewpoint: NDArray[np.float64],
    past_edge: NDArray[np.float64],
    table: NDArray[np.float64],
    config: QuadricDetectorConfig,
) -> bool:
    """Test 5: the point ``past_edge`` and the lower finger's place under it are seen."""
    up = table[:3] / np.linalg.norm(table[:3])
    height = (past_edge @ table[:3] + table[3]) / np.linalg.norm(table[:3])
    drop = min(config.plate_finger_clearance, height - config.plate_edge_margin)
    targets = [past_edge] + ([past_edge - drop * up] if drop > 0 else [])
    return not any(_occluded(tree, viewpoint, target, config) for target in targets)


def _occluded(
    tree: cKDTree,
    viewpoint: NDArray[np.float64],
    target: NDArray[np.float64],
    config: QuadricDetectorConfig,
) -> bool:
    """Whether a point of ``tree`` lies within ``plate_ray_radius`` (m) of the ray from
    ``viewpoint`` to ``target``, from ``RAY_START`` before the target on."""
    ray = target - viewpoint
    length = float(np.linalg.norm(ray))
    steps = np.arange(RAY_START, length, RAY_STEP)
    samples = target - np.outer(steps, ray / length)
    hits = tree.query_ball_point(samples, config.plate_ray_radius)
    return any(len(hit) for hit in hits)
