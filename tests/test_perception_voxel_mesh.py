"""Voxel down-sampling and counting; area-weighted mesh sampling with exact normals."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from simgrasp.perception import sample_surface, voxel_count, voxel_downsample
from simgrasp.seeding import rng_for


def _box_cloud(count: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    return sample_surface(trimesh.creation.box([0.1, 0.06, 0.04]), count, rng_for(0, "voxel"))


def test_voxel_downsample_matches_the_voxel_count_and_keeps_voxel_means() -> None:
    points, normals = _box_cloud()
    down, down_normals = voxel_downsample(points, 0.005, normals=normals)
    assert down_normals is not None
    assert len(down) == voxel_count(points, 0.005) == len(down_normals)
    np.testing.assert_allclose(np.linalg.norm(down_normals, axis=1), 1.0, atol=1e-9)
    origin = points.min(axis=0) - 0.0025
    cell = np.floor((points - origin) / 0.005).astype(int)
    first = cell[0]
    in_first = np.all(cell == first, axis=1)
    distance = np.linalg.norm(down - points[in_first].mean(axis=0), axis=1)
    assert distance.min() < 1e-12
    coarse, none = voxel_downsample(points, 0.02)
    assert none is None and len(coarse) < len(down) < len(points)


def test_voxel_count_is_about_area_over_voxel_area() -> None:
    points, _ = _box_cloud(50000)
    area = 2 * (0.1 * 0.06 + 0.1 * 0.04 + 0.06 * 0.04)
    assert 0.8 < voxel_count(points, 0.004) / (area / 0.004**2) < 1.6


def test_cancelled_normals_fall_back_to_the_nearest_input_normal() -> None:
    points = np.array([[0.0, 0, 0], [0.0001, 0, 0], [1.0, 0, 0]])
    normals = np.array([[0, 0, 1.0], [0, 0, -1.0], [0, 1.0, 0]])
    down, down_normals = voxel_downsample(points, 0.01, normals)
    assert down_normals is not None
    assert len(down) == 2
    np.testing.assert_allclose(np.abs(down_normals[:, 2]) + np.abs(down_normals[:, 1]), 1.0)


def test_voxel_errors_name_the_parameter() -> None:
    with pytest.raises(ValueError, match="voxel_size"):
        voxel_downsample(np.zeros((3, 3)), 0.0)
    with pytest.raises(ValueError, match="normals"):
        voxel_downsample(np.zeros((3, 3)), 0.1, normals=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="empty"):
        voxel_count(np.zeros((0, 3)), 0.1)


def test_sample_surface_is_seeded_area_weighted_with_face_normals() -> None:
    box = trimesh.creation.box([0.2, 0.1, 0.01])
    points, normals = sample_surface(box, 20000, rng_for(0, "box"))
    again, _ = sample_surface(box, 20000, rng_for(0, "box"))
    other, _ = sample_surface(box, 20000, rng_for(1, "box"))
    np.testing.assert_array_equal(points, again)
    assert not np.array_equal(points, other)
    assert np.all(np.abs(box.nearest.signed_distance(points[:500])) < 1e-9)
    top = np.abs(normals[:, 2] - 1) < 1e-12
    assert np.all(np.abs(points[top, 2] - 0.005) < 1e-12)
    expected_top_share = (0.2 * 0.1) / box.area
    assert abs(top.mean() - expected_top_share) < 0.02


def test_sample_surface_errors() -> None:
    box = trimesh.creation.box([0.1, 0.1, 0.1])
    with pytest.raises(ValueError, match="count"):
        sample_surface(box, 0, rng_for(0))
    with pytest.raises(ValueError, match="Trimesh"):
        sample_surface("box.obj", 10, rng_for(0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="surface area"):
        sample_surface(trimesh.Trimesh(), 10, rng_for(0))
