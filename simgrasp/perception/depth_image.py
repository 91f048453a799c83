"""A depth image file (one real sensor frame) as an organized grid of camera-frame points.

Most depth sensors store a frame as a one-channel image: a 16-bit PNG of millimetres
(RealSense, Kinect, Azure Kinect, GraspNet-1Billion, OCID) or a float TIFF. Back-projected
through the pinhole intrinsics, every pixel becomes a point of the camera frame (OpenCV axes:
x right, y down, z forward; meters; the sensor at the origin), in image order, NaN where the
sensor returned nothing (0 or not finite). :func:`simgrasp.perception.scene_cloud.read_scene`
makes it what ``simgrasp segment`` and ``simgrasp detect`` take from a ``.pcd``: an organized
scene cloud.

The intrinsics are ``DepthImageConfig.intrinsics`` (``--depth.intrinsics FX FY CX CY``), or,
when not given, a GraspNet ``meta.mat`` beside the image (its ``intrinsic_matrix`` and
``factor_depth``, which then also sets the scale).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp.config import setting
from simgrasp.config.checks import Checked, Positive
from simgrasp.errors import SimgraspError

DEPTH_IMAGE_FORMATS = (".png", ".tif", ".tiff")
PLAUSIBLE_DEPTH_M = (0.05, 20.0)
"""Range (m) that a frame's median valid depth must fall in: outside it the scale is wrong."""
Intrinsics = tuple[float, float, float, float]
"""(fx, fy, cx, cy) in pixels."""


@dataclass(frozen=True)
class DepthImageConfig(Checked):
    """How a depth image file (16-bit PNG or float TIFF) becomes a scene cloud: each pixel's
    stored value times ``scale`` is its depth (m) along the camera's z, back-projected through
    the pinhole ``intrinsics`` ``(fx, fy, cx, cy)`` (pixels) to camera-frame points, the sensor at
    the origin; 0 is no return. Both come from a GraspNet ``meta.mat`` beside the image when
    ``intrinsics`` is None."""

    intrinsics: Intrinsics | None = setting(None, metavar=("FX", "FY", "CX", "CY"))
    """Pinhole intrinsics of the depth image (pixels): focal lengths and principal point.
    Not needed when a GraspNet meta.mat lies beside the image."""
    scale: Positive = 0.001
    """Meters per stored unit of the depth image (a 16-bit PNG of millimetres: 0.001; a
    float TIFF of meters: 1)."""

    def _check(self) -> None:
        if self.intrinsics is not None and not (self.intrinsics[0] > 0 and self.intrinsics[1] > 0):
            self.refuse("intrinsics", "focal lengths must be positive")


def back_project(depth_m: NDArray[np.float64], intrinsics: Intrinsics) -> NDArray[np.float32]:
    """(H, W, 3) camera-frame points (m) of an (H, W) depth image in meters, NaN where it has
    no return (:func:`simgrasp.perception.camera.depth_to_points_cam` on every pixel)."""
    from simgrasp.perception.camera import CameraIntrinsics, depth_to_points_cam

    height, width = depth_m.shape
    camera = CameraIntrinsics(width, height, *intrinsics)
    points_cam, pixels = depth_to_points_cam(depth_m, camera)
    grid = np.full((height * width, 3), np.nan, dtype=np.float32)
    grid[pixels] = points_cam
    return grid.reshape(height, width, 3)


def graspnet_meta(path: Path) -> tuple[Intrinsics, float]:
    """(intrinsics, stored units per meter: ``factor_depth``) of a GraspNet ``meta.mat``."""
    from scipy.io import loadmat

    try:
        meta = loadmat(path)
    except (ValueError, OSError) as exc:
        raise SimgraspError(f"{path}: not a readable .mat file ({exc})") from exc
    if "intrinsic_matrix" not in meta or "factor_depth" not in meta:
        raise SimgraspError(f"{path}: no intrinsic_matrix or factor_depth")
    k = np.asarray(meta["intrinsic_matrix"], dtype=np.float64)
    if k.shape != (3, 3):
        raise SimgraspError(f"{path}: intrinsic_matrix must be 3 x 3, got {k.shape}")
    factor = float(np.asarray(meta["factor_depth"], dtype=np.float64).squeeze())
    if not factor > 0:
        raise SimgraspError(f"{path}: factor_depth must be positive, got {factor}")
    return (k[0, 0], k[1, 1], k[0, 2], k[1, 2]), factor


def read_depth_image(path: Path, config: DepthImageConfig | None = None) -> NDArray[np.float32]:
    """(H, W, 3) camera-frame points (m) of the depth image at ``path`` (module docstring), NaN
    where the sensor returned nothing; one line naming the file when it cannot be read or its
    intrinsics or scale are missing or wrong."""
    config = config or DepthImageConfig()
    intrinsics, units_per_meter = _camera(path, config)
    depth = _depth_units(path) / units_per_meter
    depth[~(depth > 0)] = np.nan  # no return: 0, negative or not finite
    _check_depths(path, depth)
    return back_project(depth, intrinsics)


def returned_points(grid: NDArray[np.float32]) -> NDArray[np.float64]:
    """(M, 3) the points of a depth image's ``grid`` (:func:`read_depth_image`) with a return,
    in image order (m)."""
    flat = grid.reshape(-1, 3)
    return flat[np.isfinite(flat).all(axis=1)].astype(np.float64)


def _camera(path: Path, config: DepthImageConfig) -> tuple[Intrinsics, float]:
    """(intrinsics, stored units per meter) of the image at ``path``."""
    if config.intrinsics is not None:
        return config.intrinsics, 1.0 / config.scale
    meta = path.parent / "meta.mat"
    if meta.is_file():
        return graspnet_meta(meta)
    raise SimgraspError(
        f"{path}: a depth image needs its camera's intrinsics: --depth.intrinsics FX FY CX CY "
        "(pixels), or a GraspNet meta.mat beside it"
    )


def _depth_units(path: Path) -> NDArray[np.float64]:
    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(path) as image:
            depth = np.asarray(image, dtype=np.float64)
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise SimgraspError(f"{path}: not a readable depth image ({exc})") from exc
    if depth.ndim != 2:
        raise SimgraspError(
            f"{path}: a depth image has one channel, this one has shape {depth.shape} "
            "(a colour image?)"
        )
    return depth


def _check_depths(path: Path, depth_m: NDArray[np.float64]) -> None:
    valid = depth_m[np.isfinite(depth_m)]
    if valid.size == 0:
        raise SimgraspError(f"{path}: the depth image has no valid pixel")
    median = float(np.median(valid))
    low, high = PLAUSIBLE_DEPTH_M
    if not low <= median <= high:
        raise SimgraspError(
            f"{path}: median depth {median:.4g} m; is the scale right (--depth.scale, meters "
            "per stored unit; a 16-bit PNG of millimetres takes 0.001)?"
        )
