"""Where a fixed pinhole depth camera sits and what it sees (world frame, meters).

Free of MuJoCo imports, so scene settings can hold cameras.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from simgrasp.errors import SimgraspError
from simgrasp.perception.camera import CameraIntrinsics

_WORLD_UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class CameraSpec:
    """A fixed pinhole depth camera.

    ``pos`` and ``lookat`` are world-frame points in meters; ``fovy_deg`` the vertical field of
    view in degrees; ``width`` x ``height`` the image size in pixels (square pixels).
    """

    name: str
    pos: tuple[float, float, float]
    lookat: tuple[float, float, float]
    fovy_deg: float = 58.0
    width: int = 640
    height: int = 480

    def __post_init__(self) -> None:
        if not self.name:
            raise SimgraspError("camera name must not be empty")
        for field in ("pos", "lookat"):
            value = np.asarray(getattr(self, field), dtype=np.float64)
            if value.shape != (3,) or not np.all(np.isfinite(value)):
                raise SimgraspError(f"camera {self.name!r}: {field} must be 3 finite numbers")
            object.__setattr__(self, field, tuple(float(x) for x in value))
        if np.linalg.norm(np.subtract(self.lookat, self.pos)) < 1e-6:
            raise SimgraspError(f"camera {self.name!r}: pos and lookat coincide")
        # Validates fovy and the image size.
        CameraIntrinsics.from_fovy(self.width, self.height, self.fovy_deg)

    @property
    def intrinsics(self) -> CameraIntrinsics:
        return CameraIntrinsics.from_fovy(self.width, self.height, self.fovy_deg)

    @property
    def world_R_mjcam(self) -> np.ndarray:
        """Rotation of the MuJoCo camera frame (looking along -z, +y up) in the world frame."""
        forward = np.subtract(self.lookat, self.pos)
        forward /= np.linalg.norm(forward)
        up = _WORLD_UP if abs(forward @ _WORLD_UP) < 0.999 else np.array([0.0, 1.0, 0.0])
        right = np.cross(forward, up)
        right /= np.linalg.norm(right)
        cam_up = np.cross(right, forward)
        return np.column_stack([right, cam_up, -forward])
