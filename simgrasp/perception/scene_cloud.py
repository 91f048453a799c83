"""Read a whole sensor scene cloud, keeping every point in the file's order.

Unlike :func:`simgrasp.perception.cloud_io.read_cloud` (an object cloud: a PCD's pixels with
no return are left out, any other invalid point refused), a scene cloud keeps its invalid
(NaN) points, so per-point results (segmentation labels) line up with the file, and an
organized cloud keeps its image grid (``width`` x ``height``, row-major: point
``r * width + c`` is pixel row ``r``, column ``c``).

Formats: ``.pcd`` (ascii, binary, binary_compressed; organized or not; a ``label`` field and
the ``VIEWPOINT`` are kept), ``.ply`` (unorganized), ``.npy`` ((N, 3) points, or (H, W, 3) an
organized grid), and a depth image (``.png``, ``.tif``: one sensor frame, back-projected
through its intrinsics by :mod:`simgrasp.perception.depth_image`). Coordinates are meters in
the sensor's frame unless ``VIEWPOINT`` says where the sensor is. A cut or corrupt file is
refused, as by ``read_cloud``: PLY and ascii / binary PCD go through the strict readers of
:mod:`simgrasp.perception.cloud_formats`; a ``binary_compressed`` PCD has its sizes checked
there and is decoded by Open3D.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import DataNotFoundError, SimgraspError
from simgrasp.perception._arrays import import_open3d
from simgrasp.perception.cloud_formats import (
    check_compressed_pcd,
    pcd_header,
    read_pcd,
    read_ply,
)
from simgrasp.perception.depth_image import (
    DEPTH_IMAGE_FORMATS,
    DepthImageConfig,
    read_depth_image,
)

SCENE_FORMATS = (".pcd", ".ply", ".npy", ".png", ".tif", ".tiff")


@dataclass(frozen=True)
class SceneCloud:
    """A scene cloud as read, invalid points included.

    Attributes:
        points: (N, 3) float32 coordinates (m, cloud frame), NaN rows for invalid pixels.
        width: grid columns (N for an unorganized cloud).
        height: grid rows (1 for an unorganized cloud).
        viewpoint: (3,) sensor position in the cloud frame (m), from the PCD ``VIEWPOINT``
            (the origin when the file has none).
        labels: (N,) int64 per-point ``label`` field of the file, or None.
        source: the file it was read from ("" when built in memory).
    """

    points: NDArray[np.float32]
    width: int
    height: int
    viewpoint: NDArray[np.float64]
    labels: NDArray[np.int64] | None = None
    source: str = ""

    @property
    def organized(self) -> bool:
        """True when the points form an image grid (more than one row)."""
        return self.height > 1

    @property
    def valid(self) -> NDArray[np.bool_]:
        """(N,) mask of points with finite coordinates."""
        return np.asarray(np.isfinite(self.points).all(axis=1))

    def grid(self) -> NDArray[np.float32]:
        """The points as a (height, width, 3) image (a view, not a copy)."""
        return self.points.reshape(self.height, self.width, 3)


def scene_from_array(
    points: NDArray[np.floating],
    viewpoint: NDArray[np.floating] | None = None,
    source: str = "",
) -> SceneCloud:
    """A :class:`SceneCloud` from an (N, 3) or organized (H, W, 3) array (m)."""
    array = np.asarray(points)
    if array.dtype.kind != "f" or array.ndim not in (2, 3) or array.shape[-1] != 3:
        raise SimgraspError(
            f"{source or 'scene'}: expected (N, 3) or (H, W, 3) float points, "
            f"got {array.dtype} {array.shape}"
        )
    height, width = array.shape[:2] if array.ndim == 3 else (1, array.shape[0])
    if height * width == 0:
        raise SimgraspError(f"{source or 'scene'}: the point cloud is empty")
    eye = np.zeros(3) if viewpoint is None else np.asarray(viewpoint, dtype=np.float64)
    flat = np.ascontiguousarray(array.reshape(-1, 3), dtype=np.float32)
    return SceneCloud(flat, int(width), int(height), eye, None, source)


def read_scene(path: str | Path, depth: DepthImageConfig | None = None) -> SceneCloud:
    """Read a scene cloud file (see the module docstring), a depth image through ``depth``'s
    intrinsics and scale; ``ValueError`` / ``FileNotFoundError`` with one line naming the file
    when it cannot be read."""
    path = Path(path)
    suffix = path.suffix.lower()
    if path.is_dir():
        raise SimgraspError(f"{path}: is a folder, not a scene-cloud file")
    if suffix not in SCENE_FORMATS:
        raise SimgraspError(
            f"{path}: unknown scene-cloud extension {suffix!r}; use one of "
            f"{', '.join(SCENE_FORMATS)}"
        )
    if not path.is_file():
        raise DataNotFoundError(f"{path}: no such scene-cloud file")
    if suffix == ".npy":
        return scene_from_array(_load_npy(path), source=str(path))
    if suffix in DEPTH_IMAGE_FORMATS:
        return scene_from_array(read_depth_image(path, depth), source=str(path))
    return _read_structured(path, suffix)


def _load_npy(path: Path) -> NDArray[np.floating]:
    try:
        array = np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise SimgraspError(f"{path}: not a readable .npy array ({exc})") from exc
    if array.ndim == 2 and array.shape[1] > 3:
        array = array[:, :3]  # extra columns (normals, colors) are not needed for a scene
    return array


def _read_structured(path: Path, suffix: str) -> SceneCloud:
    data = path.read_bytes()
    header = pcd_header(path, data) if suffix == ".pcd" else {}
    if (header.get("DATA") or [""])[0] == "binary_compressed":
        check_compressed_pcd(path, data)
        return _read_open3d(path, header)
    table = read_pcd(path, data) if suffix == ".pcd" else read_ply(path, data)
    if not {"x", "y", "z"} <= set(table) or len(table["x"]) == 0:
        raise SimgraspError(f"{path}: no points could be read (empty or not a valid {suffix})")
    points = np.column_stack([table["x"], table["y"], table["z"]]).astype(np.float32)
    labels = table["label"].astype(np.int64) if "label" in table else None
    width, height = _grid_shape(path, header, len(points))
    return SceneCloud(points, width, height, _viewpoint(path, header), labels, str(path))


def _read_open3d(path: Path, header: dict[str, list[str]]) -> SceneCloud:
    """A ``binary_compressed`` PCD (sizes already checked), decoded by Open3D with its NaN
    points and ``label`` field kept."""
    o3d = import_open3d()
    with o3d.utility.VerbosityContextManager(o3d.utility.VerbosityLevel.Error):
        cloud = o3d.t.io.read_point_cloud(
            str(path), format="auto", remove_nan_points=False, remove_infinite_points=False
        )
    if "positions" not in cloud.point or len(cloud.point.positions) == 0:
        raise SimgraspError(f"{path}: no points could be read (the compressed body is corrupt)")
    points = np.ascontiguousarray(cloud.point.positions.numpy(), dtype=np.float32)
    width, height = _grid_shape(path, header, len(points))
    labels = (
        cloud.point.label.numpy().reshape(-1).astype(np.int64) if "label" in cloud.point else None
    )
    return SceneCloud(points, width, height, _viewpoint(path, header), labels, str(path))


def _grid_shape(path: Path, header: dict[str, list[str]], count: int) -> tuple[int, int]:
    try:
        width, height = int(header["WIDTH"][0]), int(header["HEIGHT"][0])
    except (KeyError, IndexError, ValueError):
        return count, 1
    if width * height != count:
        raise SimgraspError(
            f"{path}: header says {width} x {height} points but {count} were read "
            "(truncated or corrupt file)"
        )
    return width, height


def _viewpoint(path: Path, header: dict[str, list[str]]) -> NDArray[np.float64]:
    values = header.get("VIEWPOINT")
    if values is None:
        return np.zeros(3)
    try:
        origin = np.array([float(v) for v in values[:3]])
    except ValueError as exc:
        raise SimgraspError(f"{path}: unreadable VIEWPOINT {' '.join(values)!r}") from exc
    if origin.shape != (3,) or not np.isfinite(origin).all():
        raise SimgraspError(f"{path}: unreadable VIEWPOINT {' '.join(values)!r}")
    return origin
