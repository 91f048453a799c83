"""Surface normal estimation (Open3D PCA) with viewpoint or outward orientation.

``orient="outward"`` is meant for a full-object cloud (all sides sampled). Outward means away
from the object's material, per point, not away from the centroid: the inside of a mug's
wall, a handle's inner side and the underside of a plate all point away from the surface
they belong to. The sign is decided by visibility: the cloud is seen from
``_VIEW_COUNT`` orthographic directions spread over the sphere; a point in the front layer of
a view is visible, and a visible surface faces its viewer, so each view votes for the sign
that turns the normal toward it. Points no view sees (deep concavities) take the sign that
agrees with their already-oriented neighbours, spread over a k-nearest-neighbour graph.

All views are projected and binned at once (one pixel grid per view, the grids stacked), and
only the unsigned points query their neighbours; a caller that already has a ``cKDTree`` of the
cloud passes it, so the spacing and the propagation do not rebuild one.
"""

from __future__ import annotations

from functools import cache
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import as_points, import_open3d, kd_tree, positive, to_open3d

Orientation = Literal["outward", "viewpoint", "none"]

RADIUS_PER_SPACING = 5.0
"""Default search radius = this x the median nearest-neighbour distance of the cloud. For a
randomly sampled surface that holds about 20 points; ``max_nn`` caps denser neighbourhoods."""

_VIEW_COUNT = 32
_PIXEL_PER_SPACING = 5.0
_DEPTH_TOLERANCE_PER_SPACING = 1.5
_MIN_VIEW_COSINE = 0.2
_PROPAGATION_NEIGHBORS = 8
_MAX_PIXELS_PER_SIDE = 4000
_MAX_FRONT_CELLS = 1 << 22
"""Views are binned in groups whose pixel grids total at most this many cells (bounds memory;
a single larger grid gets a group of its own)."""


def point_spacing(
    points: NDArray[np.float64], sample: int = 1000, tree: cKDTree | None = None
) -> float:
    """Median distance (m) from a point to its nearest other point (on at most ``sample``
    evenly strided points, for speed). Zero only if the points coincide. ``tree`` is an
    optional ``cKDTree`` of ``points`` to reuse."""
    stride = max(1, len(points) // sample)
    tree = kd_tree(points, tree)
    distances, _ = tree.query(points[::stride], k=2)
    return float(np.median(distances[:, 1]))


def estimate_normals(
    points: ArrayLike,
    radius: float | None = None,
    max_nn: int = 30,
    orient: Orientation = "outward",
    viewpoint: ArrayLike | None = None,
    tree: cKDTree | None = None,
) -> NDArray[np.float64]:
    """Unit surface normals of a point cloud (Open3D ``estimate_normals``, hybrid KD search).

    Args:
        points: (N, 3) cloud, meters, any frame (the frame of ``viewpoint`` too).
        radius: neighbourhood radius (m) of the PCA plane fit; default
            ``RADIUS_PER_SPACING`` x the median nearest-neighbour spacing.
        max_nn: at most this many nearest neighbours within ``radius`` are used.
        orient: ``"outward"`` (full-object cloud: away from the material, see the module
            docstring), ``"viewpoint"`` (single-view cloud: toward ``viewpoint``) or
            ``"none"`` (Open3D's arbitrary signs).
        viewpoint: (3,) camera position in the cloud's frame; required for ``"viewpoint"``.
        tree: optional ``cKDTree`` of ``points`` (same order), reused for the spacing and the
            orientation's neighbour queries instead of building one.

    Returns:
        (N, 3) unit normals in the cloud's frame.
    """
    pts = as_points(points)
    if len(pts) < 3:
        raise SimgraspError(f"normal estimation needs at least 3 points, got {len(pts)}")
    eye = _checked_viewpoint(max_nn, orient, viewpoint)

    if radius is None or orient == "outward":
        tree = kd_tree(pts, tree)
        spacing = point_spacing(pts, tree=tree)
    if radius is None:
        if spacing <= 0:
            raise SimgraspError("cannot derive a normal radius: the points coincide; pass radius")
        radius = RADIUS_PER_SPACING * spacing
    radius = positive(radius, "radius")

    o3d = import_open3d()
    cloud = to_open3d(pts)
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=radius, max_nn=max_nn))
    normals = np.asarray(cloud.normals, dtype=np.float64)
    normals /= np.maximum(np.linalg.norm(normals, axis=1), 1e-12)[:, None]
    if eye is not None:  # orient == "viewpoint"
        flip = np.einsum("ij,ij->i", normals, eye - pts) < 0
    elif orient == "outward":
        flip = _outward_flips(pts, normals, max(spacing, 1e-9), tree)
    else:
        flip = np.zeros(len(pts), dtype=bool)
    normals[flip] *= -1
    return normals


def _checked_viewpoint(
    max_nn: int, orient: Orientation, viewpoint: ArrayLike | None
) -> NDArray[np.float64] | None:
    """Validate :func:`estimate_normals`' ``max_nn``, ``orient`` and ``viewpoint``; the
    viewpoint as a (3,) array for ``orient="viewpoint"``, else None."""
    if isinstance(max_nn, bool) or not isinstance(max_nn, int | np.integer) or max_nn < 3:
        raise SimgraspError(f"max_nn must be an integer >= 3, got {max_nn!r}")
    if orient not in ("outward", "viewpoint", "none"):
        raise SimgraspError(f"orient must be 'outward', 'viewpoint' or 'none', got {orient!r}")
    if orient == "viewpoint":
        if viewpoint is None:
            raise SimgraspError("orient='viewpoint' needs viewpoint, the camera position (3,)")
        eye = np.asarray(viewpoint, dtype=np.float64)
        if eye.shape != (3,) or not np.isfinite(eye).all():
            raise SimgraspError(f"viewpoint must be a finite (3,) position, got {viewpoint!r}")
        return eye
    if viewpoint is not None:
        raise SimgraspError(f"viewpoint is only used with orient='viewpoint', not {orient!r}")
    return None


def _view_directions(count: int) -> NDArray[np.float64]:
    """``count`` unit vectors evenly spread over the sphere (Fibonacci lattice)."""
    i = np.arange(count) + 0.5
    z = 1 - 2 * i / count
    phi = np.pi * (1 + 5**0.5) * i
    r = np.sqrt(1 - z**2)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


@cache
def _view_frames(count: int) -> NDArray[np.float64]:
    """(count, 3, 3) orthographic view frames: rows u, v (pixel axes) and the unit direction
    toward the viewer, for the ``count`` directions of :func:`_view_directions`."""
    rows = []
    for toward_viewer in _view_directions(count):
        helper = np.array([1.0, 0, 0]) if abs(toward_viewer[0]) < 0.9 else np.array([0, 1.0, 0])
        u = np.cross(toward_viewer, helper)
        u /= np.linalg.norm(u)
        rows.append([u, np.cross(toward_viewer, u), toward_viewer])
    frames = np.array(rows)
    frames.setflags(write=False)
    return frames


def _project(vectors: NDArray[np.float64], axes: NDArray[np.float64]) -> NDArray[np.float64]:
    """(V, N) components of the (N, 3) ``vectors`` along each of the (V, 3) ``axes`` (one
    matrix product)."""
    return axes @ vectors.T


def _front_layer(
    points: NDArray[np.float64], frames: NDArray[np.float64], spacing: float
) -> NDArray[np.bool_]:
    """(V, N) visibility of each point for orthographic viewers placed far along each of the
    (V, 3, 3) ``frames``' view directions (see :func:`_view_frames`).

    Per view, the points are binned into square pixels of ``_PIXEL_PER_SPACING`` point spacings
    (large enough that a sampled surface leaves no holes for hidden points to show through); a
    point is visible if its depth is within ``_DEPTH_TOLERANCE_PER_SPACING`` spacings of the
    nearest point of its pixel.
    """
    u, v = _project(points, frames[:, 0]), _project(points, frames[:, 1])
    depth = -_project(points, frames[:, 2])
    u_min, v_min = u.min(axis=1), v.min(axis=1)
    extent = np.maximum(u.max(axis=1) - u_min, v.max(axis=1) - v_min)
    pixel = np.maximum(_PIXEL_PER_SPACING * spacing, extent / _MAX_PIXELS_PER_SIDE)[:, None]
    row = np.floor((u - u_min[:, None]) / pixel)  # whole numbers, exact in float64
    column = np.floor((v - v_min[:, None]) / pixel)
    columns = column.max(axis=1) + 1
    cells = ((row.max(axis=1) + 1) * columns).astype(np.int64)
    tolerance = _DEPTH_TOLERANCE_PER_SPACING * spacing
    visible = np.empty(depth.shape, dtype=bool)
    for group in _view_groups(cells):
        first_cell = np.cumsum(cells[group]) - cells[group]
        cell = (row[group] * columns[group, None] + column[group]).astype(np.int64)
        cell = (cell + first_cell[:, None]).ravel()
        front = np.full(int(cells[group].sum()), np.inf)
        np.minimum.at(front, cell, depth[group].ravel())
        visible[group] = (depth[group].ravel() <= front[cell] + tolerance).reshape(-1, len(points))
    return visible


def _view_groups(cells: NDArray[np.int64]) -> list[slice]:
    """Consecutive runs of views whose pixel grids total at most ``_MAX_FRONT_CELLS`` cells."""
    groups, start, total = [], 0, 0
    for view, count in enumerate(cells.tolist()):
        if view > start and total + count > _MAX_FRONT_CELLS:
            groups.append(slice(start, view))
            start, total = view, 0
        total += count
    return [*groups, slice(start, len(cells))]


def _outward_flips(
    points: NDArray[np.float64], normals: NDArray[np.float64], spacing: float, tree: cKDTree
) -> NDArray[np.bool_]:
    """Which normals to negate so that they point away from the material (see module doc).
    ``tree`` is a ``cKDTree`` of ``points``."""
    frames = _view_frames(_VIEW_COUNT)
    cosine = _project(normals, frames[:, 2])
    counted = _front_layer(points, frames, spacing) & (np.abs(cosine) >= _MIN_VIEW_COSINE)
    sign = np.sign(np.where(counted, cosine, 0.0).sum(axis=0))
    sign = _propagate_signs(points, normals, sign, tree)
    return sign < 0


def _propagate_signs(
    points: NDArray[np.float64],
    normals: NDArray[np.float64],
    sign: NDArray[np.float64],
    tree: cKDTree,
) -> NDArray[np.float64]:
    """Give every unsigned point (sign 0) the sign that best agrees with its signed
    neighbours' oriented normals, growing outward from the signed points; points in parts no
    view reached fall back to facing away from the centroid. ``tree`` is a ``cKDTree`` of
    ``points``; only the unsigned points query it."""
    sign = sign.copy()
    unsigned = np.flatnonzero(sign == 0)
    if len(unsigned) == 0:
        return sign
    k = min(_PROPAGATION_NEIGHBORS + 1, len(points))
    _, neighbors = tree.query(points[unsigned], k=k)
    while len(unsigned):
        agreement = np.einsum("ij,ikj->ik", normals[unsigned], normals[neighbors]) * sign[neighbors]
        score = agreement.sum(axis=1)
        decided = score != 0
        if not decided.any():
            break
        sign[unsigned[decided]] = np.sign(score[decided])
        unsigned, neighbors = unsigned[~decided], neighbors[~decided]
    rest = sign == 0
    outward = points[rest] - points.mean(axis=0)
    sign[rest] = np.where(np.einsum("ij,ij->i", normals[rest], outward) >= 0, 1.0, -1.0)
    return sign
