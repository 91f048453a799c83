"""Normal estimation: axis accuracy and sign (viewpoint and outward) on shapes with known
normals, including concave parts (a mug's inside, a handle's inner side) and a thin plate."""

from __future__ import annotations

from typing import cast

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from simgrasp.perception import estimate_normals, sample_surface
from simgrasp.perception import normals as normals_module
from simgrasp.seeding import rng_for


def _mug_like() -> trimesh.Trimesh:
    """A closed cup (outer radius 4 cm, 6 mm wall, 9 cm tall, revolved profile) with a
    half-torus handle on +x; outward face normals everywhere, the inside included."""
    profile = np.array(
        [[0, 0], [0.040, 0], [0.040, 0.090], [0.034, 0.090], [0.034, 0.006], [0, 0.006]]
    )
    cup = trimesh.creation.revolve(profile, sections=64)
    if cup.volume < 0:
        cup.invert()
    torus = trimesh.creation.torus(major_radius=0.028, minor_radius=0.007)
    torus.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    torus.apply_translation([0.040, 0, 0.045])
    handle = torus.submesh([np.flatnonzero(torus.triangles_center[:, 0] > 0.046)], append=True)
    return cast(trimesh.Trimesh, trimesh.util.concatenate([cup, handle]))


SHAPES = {
    "sphere": lambda: trimesh.creation.icosphere(subdivisions=4, radius=0.05),
    "torus": lambda: trimesh.creation.torus(major_radius=0.05, minor_radius=0.015),
    "box": lambda: trimesh.creation.box([0.10, 0.06, 0.04]),
    "thin plate": lambda: trimesh.creation.box([0.12, 0.08, 0.004]),
    "mug-like": _mug_like,
}


def _cloud(name: str, count: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    return sample_surface(SHAPES[name](), count, rng_for(0, "test_normals", name))


def test_mug_like_reference_normals_point_out_of_the_material() -> None:
    mesh = _mug_like()
    inner_wall = (np.hypot(*mesh.triangles_center[:, :2].T) < 0.0345) & (
        mesh.triangles_center[:, 2] > 0.01
    )
    radial = mesh.triangles_center[inner_wall, :2]
    assert np.all(np.einsum("ij,ij->i", mesh.face_normals[inner_wall, :2], radial) < 0)


@pytest.mark.parametrize("name", list(SHAPES))
def test_outward_normals_are_accurate_and_signed(name: str) -> None:
    points, true_normals = _cloud(name)
    normals = estimate_normals(points, orient="outward")
    assert normals.shape == points.shape
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-9)
    cosine = np.einsum("ij,ij->i", normals, true_normals)
    assert np.median(np.degrees(np.arccos(np.clip(np.abs(cosine), 0, 1)))) < 5.0
    assert np.mean(cosine > 0) > 0.95


def test_outward_is_not_away_from_the_centroid_inside_the_mug() -> None:
    points, true_normals = _cloud("mug-like")
    normals = estimate_normals(points, orient="outward")
    radius = np.hypot(points[:, 0], points[:, 1])
    inner_wall = (radius < 0.0345) & (points[:, 2] > 0.02) & (np.abs(true_normals[:, 2]) < 0.1)
    assert inner_wall.sum() > 1000
    toward_axis = -points[inner_wall, :2] / radius[inner_wall, None]
    assert np.mean(np.einsum("ij,ij->i", normals[inner_wall, :2], toward_axis) > 0) > 0.9


def test_thin_plate_faces_get_opposite_normals() -> None:
    points, _ = _cloud("thin plate")
    normals = estimate_normals(points, orient="outward")
    top, bottom = points[:, 2] > 0.0019, points[:, 2] < -0.0019
    assert np.mean(normals[top, 2] > 0) > 0.98
    assert np.mean(normals[bottom, 2] < 0) > 0.98


def test_viewpoint_orientation_faces_the_camera() -> None:
    points, true_normals = _cloud("sphere")
    camera = np.array([0.0, 0.0, 0.5])
    normals = estimate_normals(points, orient="viewpoint", viewpoint=camera)
    assert np.all(np.einsum("ij,ij->i", normals, camera - points) >= 0)
    seen = np.einsum("ij,ij->i", true_normals, camera - points) > 0
    assert np.mean(np.einsum("ij,ij->i", normals[seen], true_normals[seen]) > 0.95) > 0.99


def test_explicit_radius_and_unoriented_mode() -> None:
    points, true_normals = _cloud("box", 5000)
    normals = estimate_normals(points, radius=0.008, max_nn=20, orient="none")
    assert np.median(np.abs(np.einsum("ij,ij->i", normals, true_normals))) > 0.999


def test_a_given_tree_and_view_grouping_leave_the_normals_unchanged(monkeypatch) -> None:
    points, _ = _cloud("mug-like", 5000)
    reference = estimate_normals(points, orient="outward")
    np.testing.assert_array_equal(
        estimate_normals(points, orient="outward", tree=cKDTree(points)), reference
    )
    monkeypatch.setattr(normals_module, "_MAX_FRONT_CELLS", 1)  # one pixel grid per group
    np.testing.assert_array_equal(estimate_normals(points, orient="outward"), reference)
    with pytest.raises(ValueError, match="tree holds 10 points"):
        estimate_normals(points, orient="outward", tree=cKDTree(points[:10]))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"orient": "viewpoint"}, "needs viewpoint"),
        ({"orient": "inward"}, "orient must be"),
        ({"orient": "outward", "viewpoint": [0, 0, 1]}, "only used with"),
        ({"orient": "viewpoint", "viewpoint": [0, 1]}, "viewpoint must be"),
        ({"radius": -1.0}, "radius"),
        ({"max_nn": 2}, "max_nn"),
    ],
)
def test_bad_arguments_are_named(kwargs: dict, message: str) -> None:
    points, _ = _cloud("sphere", 500)
    with pytest.raises(ValueError, match=message):
        estimate_normals(points, **kwargs)


def test_bad_clouds_are_refused() -> None:
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        estimate_normals(np.zeros((10, 2)))
    with pytest.raises(ValueError, match="NaN"):
        estimate_normals(np.full((10, 3), np.nan))
    with pytest.raises(ValueError, match="coincide"):
        estimate_normals(np.zeros((10, 3)))
