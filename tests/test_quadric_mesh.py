"""Surface meshes of quadrics inside a cube: vertices on the surface, inside the cube."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from test_quadric_classification import Motion, canonical_form

from simgrasp.quadric import Quadric, QuadricKind, surface_mesh

HALF = 0.03


def _moved(kind: QuadricKind) -> Quadric:
    """A handle-sized quadric (semi-axes 1, 1.5, 4 cm) in a random pose."""
    rng = np.random.default_rng(list(QuadricKind).index(kind))
    motion = Motion(
        Rotation.random(random_state=rng).as_matrix(), rng.uniform(-0.5, 0.5, 3), 0.01, 1.0
    )
    return Quadric(motion.apply(canonical_form(kind, 1.0, 1.5, 4.0).coefficients))


def _surface_distance(quadric: Quadric, vertices: np.ndarray) -> np.ndarray:
    """First-order distance |f| / |∇f| of points to the surface."""
    return np.abs(quadric.evaluate(vertices)) / np.linalg.norm(quadric.gradient(vertices), axis=1)


@pytest.mark.parametrize(
    "kind",
    [
        QuadricKind.REAL_ELLIPSOID,
        QuadricKind.HYPERBOLOID_ONE_SHEET,
        QuadricKind.REAL_ELLIPTIC_CYLINDER,
        QuadricKind.HYPERBOLOID_TWO_SHEETS,
        QuadricKind.REAL_CONE,
        QuadricKind.HYPERBOLIC_PARABOLOID,
    ],
)
def test_mesh_lies_on_the_surface_inside_the_cube(kind: QuadricKind) -> None:
    quadric = _moved(kind)
    center = quadric.center + 0.004
    vertices, faces = surface_mesh(quadric, center, HALF)
    assert len(faces) > 50 and faces.max() < len(vertices)
    assert np.all(np.abs(vertices - center) <= HALF * (1 + 1e-6))
    parametric = kind in (
        QuadricKind.REAL_ELLIPSOID,
        QuadricKind.HYPERBOLOID_ONE_SHEET,
        QuadricKind.REAL_ELLIPTIC_CYLINDER,
    )
    # Parametric meshes are exact; marching cubes is within a fraction of a grid cell.
    limit = 1e-9 if parametric else 2 * HALF / 48
    assert np.max(_surface_distance(quadric, vertices)) < limit


def test_parametric_hyperboloid_covers_both_halves_without_a_second_sheet() -> None:
    quadric = _moved(QuadricKind.HYPERBOLOID_ONE_SHEET)
    vertices, _ = surface_mesh(quadric, quadric.center, HALF)
    along = (vertices - quadric.center) @ quadric.handle_axis
    assert along.min() < -0.5 * HALF and along.max() > 0.5 * HALF
    radial = vertices - quadric.center - along[:, None] * quadric.handle_axis
    # Every vertex is at least the smaller transverse semi-axis away from the axis.
    assert np.min(np.linalg.norm(radial, axis=1)) >= quadric.transverse_semi_axes[0] * (1 - 1e-9)


def test_surface_outside_the_cube_gives_an_empty_mesh() -> None:
    for kind in (QuadricKind.REAL_ELLIPSOID, QuadricKind.REAL_CONE):
        quadric = _moved(kind)
        vertices, faces = surface_mesh(quadric, quadric.center + 1.0, HALF)
        assert vertices.shape == (0, 3) and faces.shape == (0, 3)


def test_bad_mesh_arguments_are_rejected() -> None:
    quadric = _moved(QuadricKind.REAL_ELLIPSOID)
    with pytest.raises(ValueError, match="half_size"):
        surface_mesh(quadric, quadric.center, 0.0)
    with pytest.raises(ValueError, match="center"):
        surface_mesh(quadric, [0.0, 0.0], HALF)
