"""Neighbourhood centres scale with voxel count; cube and ball neighbourhoods hold exactly the
brute-force point sets (before subsampling), padded and seeded."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from simgrasp.perception import (
    gather_neighborhoods,
    sample_centers,
    sample_surface,
    voxel_count,
)
from simgrasp.perception.neighborhoods import NeighborhoodShape
from simgrasp.seeding import rng_for


def _cloud(count: int = 20000, size: float = 0.1) -> tuple[np.ndarray, np.ndarray]:
    mesh = trimesh.creation.box([size, 0.6 * size, 0.4 * size])
    return sample_surface(mesh, count, rng_for(0, "test_neighborhoods", count, str(size)))


def _brute_force(points: np.ndarray, center: np.ndarray, half: float, shape: str) -> set[int]:
    offset = points - center
    distance = np.abs(offset).max(axis=1) if shape == "cube" else np.linalg.norm(offset, axis=1)
    return set(np.flatnonzero(distance <= half).tolist())


@pytest.mark.parametrize("shape", ["cube", "sphere"])
def test_neighborhoods_hold_exactly_the_brute_force_points(shape: NeighborhoodShape) -> None:
    points, normals = _cloud(4000)
    rng = rng_for(1, "centers")
    centers = points[sample_centers(points, rng, count=50)]
    hoods = gather_neighborhoods(points, normals, centers, 0.012, shape, 10_000, 1, rng)
    assert hoods.points.shape == (len(hoods.centers), 10_000, 3)
    row_of = {tuple(p): i for i, p in enumerate(points)}
    for b in range(len(hoods.centers)):
        found = {row_of[tuple(p)] for p in hoods.points[b, hoods.mask[b]]}
        assert found == _brute_force(points, hoods.centers[b], 0.012, shape)
        assert hoods.counts[b] == len(found)
        index = [row_of[tuple(p)] for p in hoods.points[b, hoods.mask[b]]]
        np.testing.assert_array_equal(hoods.normals[b, hoods.mask[b]], normals[index])
        assert not hoods.points[b, ~hoods.mask[b]].any()


def test_cube_holds_more_than_the_inscribed_ball() -> None:
    points, normals = _cloud(4000)
    centers = points[:100]
    cube = gather_neighborhoods(points, normals, centers, 0.01, "cube", 4000, 1)
    ball = gather_neighborhoods(points, normals, centers, 0.01, "sphere", 4000, 1)
    assert np.all(cube.counts >= ball.counts) and cube.counts.sum() > ball.counts.sum()


def test_large_neighborhoods_are_subsampled_from_the_seed() -> None:
    points, normals = _cloud(20000)
    centers = points[:200]

    def gather(seed: int):  # noqa: ANN202
        return gather_neighborhoods(points, normals, centers, 0.015, "cube", 64, 10, rng_for(seed))

    first, again, other = gather(3), gather(3), gather(4)
    assert first.counts.max() == 64 and first.mask.sum(axis=1).tolist() == first.counts.tolist()
    np.testing.assert_array_equal(first.points, again.points)
    assert not np.array_equal(first.points, other.points)
    full = _brute_force(points, first.centers[0], 0.015, "cube")
    row_of = {tuple(p): i for i, p in enumerate(points)}
    assert {row_of[tuple(p)] for p in first.points[0, first.mask[0]]} <= full


def test_a_given_tree_gives_the_same_neighborhoods() -> None:
    points, normals = _cloud(5000)
    centers = points[:50]
    built = gather_neighborhoods(points, normals, centers, 0.015, "cube", 64, 10, rng_for(1))
    given = gather_neighborhoods(
        points, normals, centers, 0.015, "cube", 64, 10, rng_for(1), tree=cKDTree(points)
    )
    for field in ("points", "normals", "mask", "counts", "centers", "source"):
        np.testing.assert_array_equal(getattr(given, field), getattr(built, field))
    with pytest.raises(ValueError, match="tree holds 10 points"):
        gather_neighborhoods(points, normals, centers, 0.015, tree=cKDTree(points[:10]))


def test_small_neighborhoods_are_dropped_and_traced_to_their_centers() -> None:
    points, normals = _cloud(2000)
    far = np.array([[1.0, 1.0, 1.0]])
    centers = np.vstack([points[:3], far, points[3:5]])
    hoods = gather_neighborhoods(points, normals, centers, 0.01, "cube", 64, 5, rng_for(0))
    assert hoods.source.tolist() == [0, 1, 2, 4, 5]
    np.testing.assert_array_equal(hoods.centers, centers[hoods.source])
    assert np.all(hoods.counts >= 5)
    none = gather_neighborhoods(points, normals, far, 0.01, "cube", 64, 5, rng_for(0))
    assert none.points.shape == (0, 64, 3) and none.counts.shape == (0,)


def test_center_count_scales_with_voxel_count() -> None:
    small, _ = _cloud(20000, size=0.05)
    large, _ = _cloud(20000, size=0.15)
    rng = rng_for(0, "scale")
    n_small = len(sample_centers(small, rng, voxel_size=0.003, per_voxels=10))
    n_large = len(sample_centers(large, rng, voxel_size=0.003, per_voxels=10))
    assert n_small == int(np.ceil(voxel_count(small, 0.003) / 10))
    assert n_large == int(np.ceil(voxel_count(large, 0.003) / 10))
    assert 6 < n_large / n_small < 12  # area grows 9x
    n_denser = len(sample_centers(large, rng, voxel_size=0.003, per_voxels=5))
    assert abs(n_denser - 2 * n_large) <= 1


def test_centers_are_distinct_seeded_and_count_overrides() -> None:
    points, _ = _cloud(3000)
    first = sample_centers(points, rng_for(5), count=100)
    assert len(np.unique(first)) == 100
    np.testing.assert_array_equal(first, sample_centers(points, rng_for(5), count=100))
    assert not np.array_equal(first, sample_centers(points, rng_for(6), count=100))
    assert len(sample_centers(points, rng_for(5), count=10**6)) == len(points)


def test_thousands_of_neighborhoods_on_20k_points() -> None:
    points, normals = _cloud(20000)
    centers = points[sample_centers(points, rng_for(0), count=3000)]
    hoods = gather_neighborhoods(points, normals, centers, 0.016, "cube", 64, 10, rng_for(0))
    assert hoods.points.shape == (3000, 64, 3) and np.all(hoods.counts == 64)
    assert np.all(np.abs(hoods.points - hoods.centers[:, None]).max(axis=2) <= 0.016)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"half_size": 0.0}, "half_size"),
        ({"shape": "ellipsoid"}, "shape"),
        ({"max_points": 0}, "max_points"),
        ({"min_points": 100, "max_points": 64}, "exceeds"),
    ],
)
def test_bad_gather_arguments_are_named(kwargs: dict, message: str) -> None:
    points, normals = _cloud(500)
    args = {"half_size": 0.01} | kwargs
    with pytest.raises(ValueError, match=message):
        gather_neighborhoods(points, normals, points[:3], rng=rng_for(0), **args)


def test_bad_sample_arguments_are_named() -> None:
    points, _ = _cloud(500)
    with pytest.raises(ValueError, match="count or voxel_size"):
        sample_centers(points, rng_for(0))
    with pytest.raises(ValueError, match="count"):
        sample_centers(points, rng_for(0), count=0)
    with pytest.raises(ValueError, match="normals"):
        gather_neighborhoods(points, points[:10], points[:3], 0.01)
