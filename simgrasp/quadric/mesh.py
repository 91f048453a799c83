"""Triangle meshes of quadric surfaces inside a cube, for plots.

Real ellipsoids, one-sheet hyperboloids and real elliptic cylinders are meshed parametrically
(exact surface points, no sampling ambiguity between one- and two-sheet hyperboloids); every
other kind falls back to marching cubes on f sampled over the cube. Vertices are in the
quadric's frame and units.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from skimage.measure import marching_cubes

from simgrasp.errors import SimgraspError
from simgrasp.quadric.kinds import QuadricKind
from simgrasp.quadric.quadric import Quadric

SQRT3 = float(np.sqrt(3.0))


def surface_mesh(
    quadric: Quadric, center: ArrayLike, half_size: float, resolution: int = 48
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Mesh the surface f = 0 inside the cube ``center ± half_size``.

    Args:
        quadric: the surface.
        center: (3,) cube center, same frame as the quadric.
        half_size: cube half edge (> 0), same units.
        resolution: samples per parameter (parametric kinds) or per cube edge (marching cubes).

    Returns:
        ``(vertices (V, 3), faces (F, 3))``; both empty when the surface misses the cube.
    """
    cube_center = np.asarray(center, dtype=np.float64)
    if cube_center.shape != (3,) or not np.all(np.isfinite(cube_center)):
        raise SimgraspError(f"surface_mesh: center must be one finite 3-D point, got {center!r}")
    if not (np.isfinite(half_size) and half_size > 0):
        raise SimgraspError(f"surface_mesh: half_size must be > 0, got {half_size!r}")
    if resolution < 4:
        raise SimgraspError(f"surface_mesh: resolution must be >= 4, got {resolution}")
    kind = quadric.kind
    if kind == QuadricKind.REAL_ELLIPSOID:
        vertices, faces = _ellipsoid(quadric, resolution)
    elif kind == QuadricKind.REAL_ELLIPTIC_CYLINDER:
        vertices, faces = _cylinder(quadric, cube_center, half_size, resolution)
    elif kind == QuadricKind.HYPERBOLOID_ONE_SHEET:
        vertices, faces = _hyperboloid(quadric, cube_center, half_size, resolution)
    else:
        return _marching_cubes(quadric, cube_center, half_size, resolution)
    return _clip(vertices, faces, cube_center, half_size)


def _grid_faces(rows: int, columns: int, wrap: bool) -> np.ndarray:
    """Two triangles per cell of a rows x columns vertex grid (columns wrap around if asked)."""
    grid_r, grid_c = np.meshgrid(np.arange(rows - 1), np.arange(columns if wrap else columns - 1))
    r, c = grid_r.ravel(), grid_c.ravel()
    c1 = (c + 1) % columns
    a, b = r * columns + c, r * columns + c1
    d, e = (r + 1) * columns + c, (r + 1) * columns + c1
    return np.concatenate([np.stack([a, b, e], 1), np.stack([a, e, d], 1)]).astype(np.int64)


def _frame_points(quadric: Quadric, local: np.ndarray) -> np.ndarray:
    """Points given in the principal frame (coordinates along ``axes`` rows) -> quadric frame."""
    return quadric.center + local @ quadric.axes


def _ellipsoid(quadric: Quadric, n: int) -> tuple[np.ndarray, np.ndarray]:
    polar = np.linspace(0, np.pi, n)
    azimuth = np.linspace(0, 2 * np.pi, n, endpoint=False)
    p, a = np.meshgrid(polar, azimuth, indexing="ij")
    unit = np.stack([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)], -1).reshape(-1, 3)
    return _frame_points(quadric, unit * quadric.semi_axes), _grid_faces(n, n, wrap=True)


def _axial_range(quadric: Quadric, cube_center: np.ndarray, half: float) -> tuple[float, float]:
    """Range of the coordinate along the handle axis (from the center) covering the cube."""
    along = float((cube_center - quadric.center) @ quadric.handle_axis)
    return along - SQRT3 * half, along + SQRT3 * half


def _transverse_frame(quadric: Quadric) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit axes (e1, e2) across the handle with their semi-axes, and the handle axis row."""
    handle_row = int(np.argmin(quadric.eigenvalues))
    if quadric.kind == QuadricKind.REAL_ELLIPTIC_CYLINDER:
        handle_row = 2
    rows = [i for i in range(3) if i != handle_row]
    return quadric.axes[rows], quadric.semi_axes[rows], quadric.axes[handle_row]


def _cylinder(
    quadric: Quadric, cube_center: np.ndarray, half: float, n: int
) -> tuple[np.ndarray, np.ndarray]:
    transverse, semi, axis = _transverse_frame(quadric)
    low, high = _axial_range(quadric, cube_center, half)
    s, theta = np.meshgrid(
        np.linspace(low, high, n), np.linspace(0, 2 * np.pi, n, endpoint=False), indexing="ij"
    )
    ring = semi[0] * np.cos(theta)[..., None] * transverse[0]
    ring = ring + semi[1] * np.sin(theta)[..., None] * transverse[1]
    vertices = quadric.center + ring + s[..., None] * axis
    return vertices.reshape(-1, 3), _grid_faces(n, n, wrap=True)


def _hyperboloid(
    quadric: Quadric, cube_center: np.ndarray, half: float, n: int
) -> tuple[np.ndarray, np.ndarray]:
    transverse, semi, axis = _transverse_frame(quadric)
    conjugate = float(quadric.semi_axes[int(np.argmin(quadric.eigenvalues))])
    low, high = _axial_range(quadric, cube_center, half)
    t, theta = np.meshgrid(
        np.linspace(np.arcsinh(low / conjugate), np.arcsinh(high / conjugate), n),
        np.linspace(0, 2 * np.pi, n, endpoint=False),
        indexing="ij",
    )
    ring = semi[0] * (np.cosh(t) * np.cos(theta))[..., None] * transverse[0]
    ring = ring + semi[1] * (np.cosh(t) * np.sin(theta))[..., None] * transverse[1]
    vertices = quadric.center + ring + (conjugate * np.sinh(t))[..., None] * axis
    return vertices.reshape(-1, 3), _grid_faces(n, n, wrap=True)


def _clip(
    vertices: np.ndarray, faces: np.ndarray, cube_center: np.ndarray, half: float
) -> tuple[np.ndarray, np.ndarray]:
    """Keep the faces whose three vertices lie in the cube; drop unused vertices."""
    inside = np.all(np.abs(vertices - cube_center) <= half * (1 + 1e-9), axis=1)
    kept = faces[np.all(inside[faces], axis=1)]
    used, remapped = np.unique(kept, return_inverse=True)
    return vertices[used], remapped.reshape(-1, 3).astype(np.int64)


def _marching_cubes(
    quadric: Quadric, cube_center: np.ndarray, half: float, n: int
) -> tuple[np.ndarray, np.ndarray]:
    ticks = np.linspace(-half, half, n)
    grid = np.stack(np.meshgrid(ticks, ticks, ticks, indexing="ij"), -1).reshape(-1, 3)
    values = np.asarray(quadric.evaluate(grid + cube_center)).reshape(n, n, n)
    if not (values.min() < 0 < values.max()):
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    step = ticks[1] - ticks[0]
    vertices, faces, _, _ = marching_cubes(values, level=0.0, spacing=(step, step, step))
    return vertices + (cube_center - half), faces.astype(np.int64)
