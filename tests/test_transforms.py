"""Pose and transform helpers: round trips, the closed-form inverse, canonical quaternions."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from simgrasp.transforms import (
    invert_transform,
    make_transform,
    matrix_to_pos_quat,
    matrix_to_pose7,
    pose7_to_matrix,
    rotation_to_quat_wxyz,
    rotations_to_quats_wxyz,
)


def _random_transforms(n: int) -> list[np.ndarray]:
    rng = np.random.default_rng(0)
    rotations = Rotation.random(n, random_state=1).as_matrix()
    return [make_transform(r, rng.normal(size=3)) for r in rotations]


def test_make_transform_is_a_rigid_matrix() -> None:
    transform = make_transform(np.diag([1.0, -1.0, -1.0]), [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(transform[3], [0.0, 0.0, 0.0, 1.0])
    np.testing.assert_array_equal(transform[:3, 3], [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(transform @ [0.0, 0.0, 1.0, 1.0], [0.1, 0.2, -0.7, 1.0])


@pytest.mark.parametrize("a_T_b", _random_transforms(5))
def test_inverse_and_pose7_round_trips(a_T_b: np.ndarray) -> None:
    np.testing.assert_allclose(invert_transform(a_T_b) @ a_T_b, np.eye(4), atol=1e-12)
    np.testing.assert_allclose(invert_transform(a_T_b), np.linalg.inv(a_T_b), atol=1e-12)
    pose7 = matrix_to_pose7(a_T_b)
    assert pose7[3] >= 0
    np.testing.assert_allclose(pose7_to_matrix(pose7), a_T_b, atol=1e-12)
    pos, quat = matrix_to_pos_quat(a_T_b)
    np.testing.assert_array_equal(np.concatenate([pos, quat]), pose7)


def test_quaternion_sign_is_canonical_and_normalized() -> None:
    half_turn = make_transform(Rotation.from_euler("x", np.pi - 1e-3).as_matrix(), np.zeros(3))
    assert matrix_to_pose7(half_turn)[3] >= 0
    scaled = pose7_to_matrix([0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(scaled, np.eye(4), atol=1e-15)


@pytest.mark.parametrize(
    ("bad", "message"),
    [([0.0] * 6, "7 finite numbers"), ([0, 0, 0, np.nan, 0, 0, 1], "7 finite"), ([0] * 7, "zero")],
)
def test_bad_pose7_names_what_it_is(bad: list[float], message: str) -> None:
    with pytest.raises(ValueError, match=f"object pose .*{message}|object pose has a {message}"):
        pose7_to_matrix(bad, "object pose")


def test_quaternion_is_scipys_to_the_bit() -> None:
    """The shortcut past SciPy's check gives SciPy's quaternion exactly: on rotations, on
    matrices off orthogonal by less and by more than its 1e-12 tolerance (those it
    orthonormalizes), and a reflection still fails as in SciPy."""
    rng = np.random.default_rng(0)
    rotations = Rotation.random(300, random_state=1).as_matrix()
    for index, rotation in enumerate(rotations):
        matrix = rotation + rng.normal(0.0, (0.0, 1e-13, 1e-12, 1e-10)[index % 4], (3, 3))
        expected = Rotation.from_matrix(matrix).as_quat(scalar_first=True)
        assert np.array_equal(rotation_to_quat_wxyz(matrix), expected)
    with pytest.raises(ValueError, match="determinant"):
        rotation_to_quat_wxyz(np.diag([1.0, 1.0, -1.0]))


def test_batched_quaternions_match_one_by_one_to_the_bit() -> None:
    """The shake's batched conversion gives each row's quaternion of the one-matrix call, bit
    for bit, on a batch of rotations and on one holding a matrix SciPy must orthonormalize."""
    rng = np.random.default_rng(2)
    rotations = Rotation.random(200, random_state=3).as_matrix()
    for batch in (rotations, rotations + rng.normal(0.0, 1e-10, rotations.shape)):
        expected = np.stack([rotation_to_quat_wxyz(matrix) for matrix in batch])
        assert np.array_equal(rotations_to_quats_wxyz(batch), expected)
