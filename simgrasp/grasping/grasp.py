"""A parallel-jaw grasp: where the TCP goes, how wide the jaws open, and who proposed it.

Convention (README): ``world_T_tcp`` (4x4) puts the TCP midway between the finger pads, +z the
approach direction (palm toward object), +y the direction in which the jaws open and close.
Flattened poses are ``[x, y, z, qw, qx, qy, qz]`` (meters, unit quaternion).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.transforms import make_transform, matrix_to_pose7, pose7_to_matrix


def tcp_pose(position: ArrayLike, closing: ArrayLike, approach: ArrayLike) -> NDArray[np.float64]:
    """``world_T_tcp`` (4x4) at ``position`` with +z along ``approach`` and +y along the part
    of ``closing`` (the jaw direction) orthogonal to it; +x completes a right-handed frame.

    Frame-agnostic: give all three in one frame to get the TCP pose in that frame.
    """
    z = np.asarray(approach, dtype=float)
    y = np.asarray(closing, dtype=float)
    if np.linalg.norm(z) < 1e-9:
        raise SimgraspError(f"approach direction must be non-zero, got {approach!r}")
    z = z / np.linalg.norm(z)
    y = y - (y @ z) * z
    if np.linalg.norm(y) < 1e-9:
        raise SimgraspError("closing direction must not be parallel to the approach direction")
    y = y / np.linalg.norm(y)
    return make_transform(np.column_stack([np.cross(y, z), y, z]), np.asarray(position, float))


_IDENTITY = np.eye(3)
_GRAM_TOLERANCE = 1e-6 + 1e-5 * _IDENTITY
"""How far ``R^T R`` may be from the identity (``np.allclose(R.T @ R, I, atol=1e-6)``)."""
_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])
_LAST_ROW_TOLERANCE = 1e-8 + 1e-5 * _LAST_ROW
"""How far a 4x4 transform's last row may be from ``[0 0 0 1]`` (``np.allclose``'s defaults)."""


def _check_rigid(transform: NDArray[np.float64], what: str) -> NDArray[np.float64]:
    """``transform`` as a float array, or an error naming ``what`` unless it is a finite rigid
    4x4 transform (checked once per grasp and frame: the tolerances of ``np.allclose``
    without its overhead)."""
    arr = np.asarray(transform, dtype=float)
    if arr.shape != (4, 4) or not np.isfinite(arr).all():
        raise SimgraspError(f"{what} must be a finite 4x4 matrix, got shape {arr.shape}")
    rotation = arr[:3, :3]
    gram_error = np.abs(rotation.T @ rotation - _IDENTITY)
    if (gram_error > _GRAM_TOLERANCE).any() or np.linalg.det(rotation) < 0:
        raise SimgraspError(f"{what} has no proper rotation block (not orthonormal, det != +1)")
    if (np.abs(arr[3] - _LAST_ROW) > _LAST_ROW_TOLERANCE).any():
        raise SimgraspError(f"{what} must have last row [0 0 0 1], got {arr[3].tolist()}")
    return arr


@dataclass(frozen=True)
class Grasp:
    """One parallel-jaw grasp in the world frame.

    Attributes:
        world_T_tcp: TCP pose (4x4, world frame, meters).
        width: jaw opening before closing (m).
        score: the proposer's ranking score (higher is better; units are the proposer's).
        source: name of the detector/planner that proposed it (``"manual"`` for hand-placed).
    """

    world_T_tcp: NDArray[np.float64]
    width: float
    score: float = 0.0
    source: str = "manual"

    def __post_init__(self) -> None:
        object.__setattr__(self, "world_T_tcp", _check_rigid(self.world_T_tcp, "world_T_tcp"))
        if not (np.isfinite(self.width) and self.width > 0):
            raise SimgraspError(
                f"grasp width must be a positive number of meters, got {self.width}"
            )

    @property
    def approach_world(self) -> NDArray[np.float64]:
        """Unit approach direction (TCP +z) in the world frame."""
        return self.world_T_tcp[:3, 2].copy()

    def to_pose7(self) -> NDArray[np.float64]:
        """The TCP pose as ``[x, y, z, qw, qx, qy, qz]`` (world frame)."""
        return matrix_to_pose7(self.world_T_tcp)

    @staticmethod
    def from_pose7(
        pose7: ArrayLike, width: float, score: float = 0.0, source: str = "manual"
    ) -> Grasp:
        """A grasp from a world-frame ``[x, y, z, qw, qx, qy, qz]`` TCP pose."""
        return Grasp(pose7_to_matrix(pose7, "grasp pose"), float(width), score, source)

    def object_T_tcp(self, world_T_object: NDArray[np.float64]) -> NDArray[np.float64]:
        """The TCP pose in the object frame, given the object's pose ``world_T_object``."""
        world_T_object = _check_rigid(world_T_object, "world_T_object")
        return np.linalg.inv(world_T_object) @ self.world_T_tcp

    @staticmethod
    def from_object_frame(
        object_T_tcp: NDArray[np.float64],
        world_T_object: NDArray[np.float64],
        width: float,
        score: float = 0.0,
        source: str = "manual",
    ) -> Grasp:
        """A world-frame grasp from a TCP pose given in the object frame."""
        object_T_tcp = _check_rigid(object_T_tcp, "object_T_tcp")
        world_T_object = _check_rigid(world_T_object, "world_T_object")
        return Grasp(world_T_object @ object_T_tcp, width, score, source)
