"""Rigid transforms and poses: 4x4 matrices ``a_T_b`` (map b-frame coordinates to a-frame),
flattened poses ``[x, y, z, qw, qx, qy, qz]`` (meters, unit quaternion, scalar first).

MuJoCo-free; :func:`make_transform` also builds a pose from MuJoCo's ``xpos`` / ``xmat``
(``make_transform(xmat.reshape(3, 3), xpos)``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from simgrasp.errors import SimgraspError


def make_transform(rotation: ArrayLike, translation: ArrayLike) -> NDArray[np.float64]:
    """``a_T_b`` (4x4) with ``rotation`` (3x3) and ``translation`` (3,), both in frame a."""
    transform = np.eye(4)
    transform[:3, :3] = rotation
    transform[:3, 3] = translation
    return transform


def invert_transform(a_T_b: NDArray[np.float64]) -> NDArray[np.float64]:
    """``b_T_a`` of a rigid ``a_T_b`` (closed form: the rotation's transpose)."""
    rotation = a_T_b[:3, :3]
    return make_transform(rotation.T, -rotation.T @ a_T_b[:3, 3])


def rotation_to_quat_wxyz(rotation: ArrayLike) -> NDArray[np.float64]:
    """``[w, x, y, z]`` quaternion of a 3x3 rotation matrix (either sign)."""
    return Rotation.from_matrix(rotation).as_quat(scalar_first=True)


def matrix_to_pos_quat(
    transform: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Position and ``[w, x, y, z]`` quaternion (w >= 0) of a 4x4 rigid transform."""
    quat = rotation_to_quat_wxyz(transform[:3, :3])
    return transform[:3, 3].copy(), quat if quat[0] >= 0 else -quat


def matrix_to_pose7(transform: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[x, y, z, qw, qx, qy, qz]`` of a 4x4 rigid transform (qw >= 0)."""
    return np.concatenate(matrix_to_pos_quat(transform))


def pose7_to_matrix(pose7: ArrayLike, what: str = "pose") -> NDArray[np.float64]:
    """4x4 rigid transform of ``[x, y, z, qw, qx, qy, qz]``; the quaternion is normalized.

    Raises ``ValueError`` naming ``what`` for anything but 7 finite numbers or a zero
    quaternion.
    """
    pose = np.asarray(pose7, dtype=float)
    if pose.shape != (7,) or not np.all(np.isfinite(pose)):
        raise SimgraspError(f"{what} must be 7 finite numbers [x y z qw qx qy qz], got {pose7!r}")
    norm = np.linalg.norm(pose[3:])
    if norm < 1e-9:
        raise SimgraspError(f"{what} has a zero quaternion: {pose.tolist()}")
    rotation = Rotation.from_quat(pose[3:] / norm, scalar_first=True).as_matrix()
    return make_transform(rotation, pose[:3])
