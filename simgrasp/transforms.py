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


_ORTHOGONAL_TOLERANCE = 1e-12 + 1e-5 * np.eye(3)
"""SciPy's own test of a rotation matrix (``np.isclose(R @ R.T, I, atol=1e-12)``, default
rtol 1e-5), elementwise."""


def rotation_to_quat_wxyz(rotation: ArrayLike) -> NDArray[np.float64]:
    """``[w, x, y, z]`` quaternion of a 3x3 rotation matrix (either sign).

    SciPy's ``from_matrix`` checks the determinant and orthogonality with several NumPy calls
    (about 3/4 of its time on one matrix); a matrix that passes the same test, done here in
    one step, is converted with ``assume_valid``, the very conversion SciPy runs after its
    check (same bits). Others (batches, matrices to orthonormalize, reflections) go the full
    way."""
    matrix = np.asarray(rotation, dtype=float)
    valid = matrix.shape == (3, 3) and _is_rotation(matrix)
    return Rotation.from_matrix(matrix, assume_valid=valid).as_quat(scalar_first=True)


def rotations_to_quats_wxyz(rotations: NDArray[np.float64]) -> NDArray[np.float64]:
    """``[w, x, y, z]`` quaternions ``(N, 4)`` of ``N`` rotation matrices ``(N, 3, 3)`` (either
    sign), row for row the same bits as :func:`rotation_to_quat_wxyz`, in one SciPy call when
    every matrix passes its test."""
    if _are_rotations(rotations):
        return Rotation.from_matrix(rotations, assume_valid=True).as_quat(scalar_first=True)
    return np.stack([rotation_to_quat_wxyz(matrix) for matrix in rotations])


def _is_rotation(matrix: NDArray[np.float64]) -> bool:
    """Whether a 3x3 ``matrix`` passes SciPy's rotation test: orthogonal to its tolerance and
    a positive determinant (the sign of ``r0 . (r1 x r2)``, exact enough near +-1)."""
    if not np.all(np.abs(matrix @ matrix.T - np.eye(3)) <= _ORTHOGONAL_TOLERANCE):
        return False
    (a, b, c), (d, e, f), (g, h, i) = matrix.tolist()
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) > 0


def _are_rotations(matrices: NDArray[np.float64]) -> bool:
    """Whether every matrix of ``(N, 3, 3)`` passes :func:`_is_rotation`'s test (in one pass of
    array operations)."""
    gram = matrices @ matrices.transpose(0, 2, 1)
    if not np.all(np.abs(gram - np.eye(3)) <= _ORTHOGONAL_TOLERANCE):
        return False
    (a, b, c), (d, e, f), (g, h, i) = np.moveaxis(matrices, 0, -1)
    return bool(np.all(a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) > 0))


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


def orthonormal(axis: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unit vectors ``u, v`` perpendicular to the unit ``axis`` and to each other (``axis``,
    ``u``, ``v`` right-handed)."""
    helper = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(axis, helper)
    u /= np.linalg.norm(u)
    return u, np.cross(axis, u)
