"""Pinhole camera model: intrinsics, depth image <-> camera-frame points, frame conventions.

Conventions used throughout simgrasp:

- The **camera frame** is OpenCV's: origin at the optical center, +x right in the image, +y down
  in the image, +z forward along the optical axis. ``points_cam`` are in meters in this frame.
- Pixel ``(u, v)`` is column ``u``, row ``v`` (row 0 at the top); integer pixel coordinates are
  pixel *centers*. A symmetric frustum rendered by OpenGL/MuJoCo therefore has its principal
  point at ``cx = (width - 1) / 2``, ``cy = (height - 1) / 2``.
- A **depth image** holds, per pixel, the distance in meters along the optical axis (the
  camera-frame z of the surface point), not the ray length. 0, NaN, inf, negative values and
  values beyond ``max_depth`` mean "no return".
- Flattened pixel indices are ``v * width + u`` (row-major, as ``depth.ravel()``).
- A MuJoCo camera looks along its own -z with +y up and +x right; :data:`cv_R_mujoco` maps
  MuJoCo-camera coordinates to OpenCV-camera coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from simgrasp.errors import SimgraspError

#: Rotation taking MuJoCo-camera-frame vectors (x right, y up, looking along -z) to the OpenCV
#: camera frame (x right, y down, z forward). It is its own inverse.
cv_R_mujoco: np.ndarray = np.diag([1.0, -1.0, -1.0])
cv_R_mujoco.flags.writeable = False

#: The same change of frame as a 4x4 homogeneous transform (``cv_T_mujoco``).
cv_T_mujoco: np.ndarray = np.diag([1.0, -1.0, -1.0, 1.0])
cv_T_mujoco.flags.writeable = False


@dataclass(frozen=True)
class CameraIntrinsics:
    """Pinhole intrinsics in pixels (no distortion).

    ``fx, fy`` are focal lengths in pixels; ``cx, cy`` the principal point in pixel coordinates
    whose integer values are pixel centers (see the module docstring).
    """

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float

    def __post_init__(self) -> None:
        if int(self.width) != self.width or int(self.height) != self.height:
            raise SimgraspError(f"image size must be integers, got {self.width}x{self.height}")
        if self.width <= 0 or self.height <= 0:
            raise SimgraspError(f"image size must be positive, got {self.width}x{self.height}")
        for name in ("fx", "fy"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise SimgraspError(f"camera intrinsics: {name} must be positive, got {value}")
        for name in ("cx", "cy"):
            if not math.isfinite(getattr(self, name)):
                raise SimgraspError(f"camera intrinsics: {name} must be finite")

    @classmethod
    def from_fovy(cls, width: int, height: int, fovy_deg: float) -> CameraIntrinsics:
        """Intrinsics of a MuJoCo camera: vertical field of view ``fovy_deg`` (degrees), square
        pixels and a centered principal point, exactly as MuJoCo renders an image of this size.
        """
        if not (0.0 < fovy_deg < 180.0):
            raise SimgraspError(f"fovy_deg must be in (0, 180) degrees, got {fovy_deg}")
        if width <= 0 or height <= 0:
            raise SimgraspError(f"image size must be positive, got {width}x{height}")
        focal = 0.5 * height / math.tan(math.radians(fovy_deg) / 2.0)
        return cls(
            width=int(width),
            height=int(height),
            fx=focal,
            fy=focal,
            cx=(width - 1) / 2.0,
            cy=(height - 1) / 2.0,
        )

    @property
    def matrix(self) -> np.ndarray:
        """The 3x3 camera matrix K mapping camera-frame points to homogeneous pixels."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @property
    def fovy_deg(self) -> float:
        """Vertical field of view in degrees."""
        return math.degrees(2.0 * math.atan(0.5 * self.height / self.fy))

    def pixel_rays_cam(self) -> np.ndarray:
        """Unnormalized ray directions ``(u - cx) / fx, (v - cy) / fy, 1`` for every pixel,
        shape (H*W, 3), in flattened pixel order; scaling a ray by a depth gives the point.
        """
        v, u = np.divmod(np.arange(self.width * self.height), self.width)
        return np.column_stack(
            [(u - self.cx) / self.fx, (v - self.cy) / self.fy, np.ones(u.shape[0])]
        )


def depth_to_points_cam(
    depth: np.ndarray,
    intrinsics: CameraIntrinsics,
    mask: np.ndarray | None = None,
    *,
    max_depth: float = math.inf,
) -> tuple[np.ndarray, np.ndarray]:
    """Back-project a depth image into camera-frame points.

    Args:
        depth: (H, W) distances along the optical axis in meters; 0, NaN, inf, negative values
            and values above ``max_depth`` are "no return" and produce no point.
        intrinsics: the camera that took the image; its size must match ``depth``.
        mask: optional (H, W) boolean image; only pixels where it is true produce points.
        max_depth: far limit in meters (the far clipping distance of a rendered image).

    Returns:
        ``points_cam`` (N, 3) in meters in the OpenCV camera frame and ``pixel_indices`` (N,)
        the flattened pixel index ``v * width + u`` of each point, ascending.
    """
    depth = np.asarray(depth)
    expected = (intrinsics.height, intrinsics.width)
    if depth.shape != expected:
        raise SimgraspError(f"depth image has shape {depth.shape}, intrinsics expect {expected}")
    flat = depth.astype(np.float64, copy=False).ravel()
    with np.errstate(invalid="ignore"):
        valid = np.isfinite(flat) & (flat > 0.0) & (flat <= max_depth)
    if mask is not None:
        mask = np.asarray(mask)
        if mask.shape != expected or mask.dtype != np.bool_:
            raise SimgraspError(
                f"mask must be a boolean image of shape {expected}, got {mask.dtype} {mask.shape}"
            )
        valid &= mask.ravel()
    pixel_indices = np.flatnonzero(valid)
    v, u = np.divmod(pixel_indices, intrinsics.width)
    z = flat[pixel_indices]
    points_cam = np.column_stack(
        [(u - intrinsics.cx) / intrinsics.fx * z, (v - intrinsics.cy) / intrinsics.fy * z, z]
    )
    return points_cam, pixel_indices


def project(points_cam: np.ndarray, intrinsics: CameraIntrinsics) -> tuple[np.ndarray, np.ndarray]:
    """Project camera-frame points to pixel coordinates.

    Args:
        points_cam: (N, 3) points in meters in the OpenCV camera frame.
        intrinsics: the camera.

    Returns:
        ``pixels`` (N, 2) continuous ``(u, v)`` coordinates (integer values are pixel centers)
        and ``depth`` (N,) the camera-frame z in meters. Points with z <= 0 (behind the camera)
        get NaN pixel coordinates.
    """
    points_cam = _as_points(points_cam, "points_cam")
    z = points_cam[:, 2]
    in_front = z > 0.0
    safe_z = np.where(in_front, z, 1.0)
    u = intrinsics.fx * points_cam[:, 0] / safe_z + intrinsics.cx
    v = intrinsics.fy * points_cam[:, 1] / safe_z + intrinsics.cy
    pixels = np.column_stack([u, v])
    pixels[~in_front] = np.nan
    return pixels, z.copy()


def transform_points(a_T_b: np.ndarray, points_b: np.ndarray) -> np.ndarray:
    """Map (N, 3) points from frame b to frame a with the 4x4 rigid transform ``a_T_b``."""
    a_T_b = np.asarray(a_T_b, dtype=np.float64)
    if a_T_b.shape != (4, 4) or not np.all(np.isfinite(a_T_b)):
        raise SimgraspError(f"transform must be a finite 4x4 matrix, got shape {a_T_b.shape}")
    points_b = _as_points(points_b, "points")
    rotation, points_a = a_T_b[:3, :3].T, np.empty_like(points_b)
    for start in range(0, len(points_b), TRANSFORM_BLOCK):
        block = slice(start, start + TRANSFORM_BLOCK)
        np.matmul(points_b[block], rotation, out=points_a[block])
    return points_a + a_T_b[:3, 3]


TRANSFORM_BLOCK = 16384
"""Rows per matrix product in :func:`transform_points`: OpenBLAS spreads one tall (N, 3) x
(3, 3) product over threads, which made a 640 x 480 frame cost ~30 ms instead of ~5 on the
2-core machine; each row's result is the same either way."""


def _as_points(points: np.ndarray, name: str) -> np.ndarray:
    points = np.asarray(points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] != 3:
        raise SimgraspError(f"{name} must have shape (N, 3), got {points.shape}")
    return points
