"""An object's points from any file ``simgrasp detect`` takes: a point cloud (``.ply``,
``.pcd``, ``.xyz``, ``.npy``: :func:`~simgrasp.perception.cloud_io.read_cloud`), a mesh
(``.obj``, ``.stl``, ``.off``, ``.glb``, ``.gltf``, or a ``.ply`` with faces: a scanner's
reconstruction) read by its vertices or its sampled surface (:class:`MeshReadConfig`: by
default a scan's vertices, a model's surface), or the valid pixels of a depth image
(:mod:`simgrasp.perception.depth_image`).

Everything comes back in meters, in the file's frame; a size that only other units explain is
refused with the fix spelled for the caller (:func:`~simgrasp.perception.units.cloud_in_meters`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.config.checks import Checked, Positive, PositiveInt
from simgrasp.errors import SimgraspError
from simgrasp.perception.depth_image import DEPTH_IMAGE_FORMATS, DepthImageConfig
from simgrasp.perception.units import UNIT_SCALE, Units, cloud_in_meters

MESH_FORMATS = (".obj", ".stl", ".off", ".glb", ".gltf")
"""Mesh files by extension; a ``.ply`` is a mesh when its header declares faces."""
MeshPoints = Literal["auto", "vertices", "surface"]
Cloud = tuple[NDArray[np.float64], NDArray[np.float64] | None]


@dataclass(frozen=True)
class MeshReadConfig(Checked):
    """How a mesh file (a scanner's reconstruction, a CAD model) becomes the cloud detected
    on."""

    points: MeshPoints = "auto"
    """vertices: its vertices as stored (loose ones too), with the file's normals where it has
    them: a scanner's measured points; surface: points drawn uniformly over its triangles
    every `spacing` (by the seed), whatever the vertex density; auto: its vertices when its
    triangles are a scan's (`scan_edge`), else its surface (a model's large triangles)."""
    scan_edge: Positive = 0.008
    """With `points` auto: a mesh is read by its vertices when half its area lies in triangles
    whose longest edge is at most this (m). A reconstruction joins neighbouring measured
    points (edges of 2-5 mm on ToolKinect's Kinect scans, YCB's 16k meshes); a model's
    triangles span its flat parts (centimetres)."""
    spacing: Positive = 0.0015
    """Mean distance (m) between the points drawn over the surface (area / spacing^2 points):
    half the detector's 3 mm voxel."""
    max_points: PositiveInt = 200_000
    """At most this many points are drawn over the surface."""


def is_mesh_file(path: Path) -> bool:
    """Whether ``path`` is a mesh: a mesh extension, or a PLY whose header declares faces."""
    suffix = path.suffix.lower()
    if suffix in MESH_FORMATS:
        return True
    if suffix != ".ply" or not path.is_file():
        return False
    from simgrasp.perception.cloud_formats import ply_face_count

    with path.open("rb") as handle:
        head = handle.read(1 << 16)
    return b"end_header" in head and ply_face_count(path, head) > 0


def read_object_cloud(
    path: Path,
    units: Units = "m",
    depth: DepthImageConfig | None = None,
    mesh: MeshReadConfig | None = None,
    seed: int = 0,
) -> Cloud:
    """(N, 3) points (m, the file's frame) and unit normals or None of the object file at
    ``path`` in ``units`` (module docstring); ``seed`` draws a mesh's surface points."""
    path = Path(path)
    if path.suffix.lower() in DEPTH_IMAGE_FORMATS:
        return _depth_pixels(path, units, depth), None
    if is_mesh_file(path):
        return read_mesh_cloud(path, units, mesh or MeshReadConfig(), seed)
    from simgrasp.perception.cloud_io import read_cloud

    points, normals = read_cloud(path)
    return cloud_in_meters(points, units, str(path)), normals


def _depth_pixels(path: Path, units: Units, depth: DepthImageConfig | None) -> NDArray[np.float64]:
    """The valid pixels of a depth image (an object cut from its frame: other pixels 0)."""
    from simgrasp.perception.depth_image import read_depth_image, returned_points

    if units != "m":
        raise SimgraspError(f"{path}: a depth image's units are set by --depth.scale, not --units")
    return returned_points(read_depth_image(path, depth))


def read_mesh_cloud(path: Path, units: Units, config: MeshReadConfig, seed: int = 0) -> Cloud:
    """A mesh file's cloud (m): its vertices (a PLY's through
    :func:`~simgrasp.perception.cloud_io.read_cloud`, with its normals; another format's
    without), or its surface sampled every ``config.spacing`` (face normals when it is a
    closed, consistently wound solid, else None: estimated by the detector), as
    ``config.points`` says."""
    loaded = _load_triangles(path)
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    cloud_in_meters(vertices[np.unique(loaded.faces)], units, str(path))  # size check
    scale = UNIT_SCALE[units]
    if config.points == "surface" or (
        config.points == "auto" and _typical_edge(loaded) * scale > config.scan_edge
    ):
        return _surface(path, loaded, scale, config, seed)
    if path.suffix.lower() == ".ply":
        from simgrasp.perception.cloud_io import read_cloud

        points, normals = read_cloud(path)
        return cloud_in_meters(points, units, str(path)), normals
    return cloud_in_meters(vertices, units, str(path)), None


def _typical_edge(mesh) -> float:  # noqa: ANN001 (a trimesh.Trimesh, imported lazily)
    """The longest edge (file units) of the triangle at the area-weighted median: half the
    mesh's area lies in triangles whose longest edge is at most this."""
    corners = np.asarray(mesh.vertices)[np.asarray(mesh.faces)]
    longest = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).max(axis=1)
    order = np.argsort(longest)
    area = np.asarray(mesh.area_faces)[order]
    return float(longest[order][np.searchsorted(np.cumsum(area), 0.5 * area.sum())])


def _load_triangles(path: Path):  # noqa: ANN202 (trimesh is imported lazily)
    """The file's triangles as stored (trimesh, no merging); one line when it has none."""
    import trimesh

    if not path.is_file():
        raise SimgraspError(f"{path}: no such mesh file")
    try:
        loaded = trimesh.load(path, force="mesh", process=False, skip_materials=True)
    except Exception as exc:  # trimesh raises many types for unreadable files
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise SimgraspError(f"{path}: cannot read the mesh ({reason})") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise SimgraspError(f"{path}: no triangles in the mesh file")
    if not np.isfinite(loaded.vertices).all():
        raise SimgraspError(f"{path}: the mesh has NaN or inf vertex coordinates")
    return loaded


def _surface(path: Path, loaded, scale: float, config: MeshReadConfig, seed: int) -> Cloud:  # noqa: ANN001
    """Points drawn over the mesh's triangles (``scale`` meters per file unit)."""
    import trimesh

    from simgrasp.perception.mesh_cloud import sample_surface

    mesh = trimesh.Trimesh(np.asarray(loaded.vertices) * scale, loaded.faces, process=False)
    if not mesh.area > 0:
        raise SimgraspError(f"{path}: the mesh's triangles have no area")
    count = int(np.clip(round(mesh.area / config.spacing**2), 1, config.max_points))
    points, normals = sample_surface(mesh, count, np.random.default_rng(seed))
    solid = mesh.is_watertight and mesh.is_winding_consistent
    if not solid:
        return points, None
    return points, normals if mesh.volume > 0 else -normals
