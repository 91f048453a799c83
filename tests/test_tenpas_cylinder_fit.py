"""Cylinder estimation helpers of the ten Pas detector on exact and noisy synthetic data."""

from __future__ import annotations

import numpy as np
import pytest

from simgrasp.handles.baselines.cylinder_fit import (
    fit_circles,
    minimal_curvature_axes,
    perpendicular_basis,
    project_to_surface,
)
from simgrasp.quadric.coefficients import matrix_to_coefficients


def _cylinder_coefficients(axis: np.ndarray, point: np.ndarray, radius: float) -> np.ndarray:
    """Coefficients of |(x - p) - ((x - p)·a) a|² - r² = 0 (a unit axis, p on the axis)."""
    q = np.eye(3) - np.outer(axis, axis)
    matrix = np.zeros((4, 4))
    matrix[:3, :3] = q
    matrix[:3, 3] = matrix[3, :3] = -q @ point
    matrix[3, 3] = point @ q @ point - radius**2
    return matrix_to_coefficients(matrix)


def _unit(v: list[float]) -> np.ndarray:
    return np.asarray(v, dtype=float) / np.linalg.norm(v)


def test_perpendicular_basis_is_orthonormal_and_right_handed() -> None:
    directions = np.stack([_unit([1, 0, 0]), _unit([0, 1, 0]), _unit([0.3, -2, 0.7])])
    first, second = perpendicular_basis(directions)
    frames = np.stack([first, second, directions], axis=-1)
    assert np.allclose(np.einsum("bji,bjk->bik", frames, frames), np.eye(3), atol=1e-12)
    assert np.allclose(np.linalg.det(frames), 1.0)


def test_minimal_curvature_axis_and_curvature_of_exact_cylinders() -> None:
    axes = np.stack([_unit([1, 2, 0.5]), _unit([0, 0, 1]), _unit([-1, 0.2, 0.1])])
    points = np.array([[0.1, 0.2, 0.3], [-0.4, 0.0, 1.0], [2.0, -1.0, 0.5]])
    radii = np.array([0.015, 0.004, 0.05])
    coefficients = np.stack(
        [_cylinder_coefficients(a, p, r) for a, p, r in zip(axes, points, radii, strict=True)]
    )
    # start off the surface: Newton steps must bring the points onto it
    first, _ = perpendicular_basis(axes)
    start = points + 1.3 * radii[:, None] * first
    surface = project_to_surface(coefficients, start)
    off_axis = surface - points
    off_axis -= np.einsum("bi,bi->b", off_axis, axes)[:, None] * axes
    assert np.allclose(np.linalg.norm(off_axis, axis=1), radii, rtol=1e-6)
    result = minimal_curvature_axes(coefficients, surface)
    assert result.valid.all()
    assert np.allclose(np.abs(np.einsum("bi,bi->b", result.axes, axes)), 1.0, atol=1e-9)
    assert np.allclose(result.curvatures[:, 0], 0.0, atol=1e-6)
    assert np.allclose(np.abs(result.curvatures[:, 1]), 1 / radii, rtol=1e-6)


def test_vanishing_gradient_is_marked_invalid() -> None:
    sphere_center = np.array([1.0, 2.0, 3.0])
    coefficients = np.array(
        [[1, 1, 1, 0, 0, 0, *(-sphere_center), sphere_center @ sphere_center - 1]]
    )
    result = minimal_curvature_axes(coefficients, sphere_center[None])
    assert not result.valid[0]


@pytest.mark.parametrize("arc_degrees", [60.0, 170.0, 360.0])
def test_circle_fit_recovers_radius_and_axis_point_on_short_and_full_arcs(
    arc_degrees: float,
) -> None:
    rng = np.random.default_rng(3)
    axis = _unit([0.2, -0.5, 1.0])
    axis_point = np.array([0.3, -0.1, 0.05])
    radius = 0.012
    first, second = (v[0] for v in perpendicular_basis(axis[None]))
    angle = rng.uniform(0, np.radians(arc_degrees), 80)
    along = rng.uniform(-0.01, 0.01, 80)
    points = (
        axis_point
        + radius * (np.cos(angle)[:, None] * first + np.sin(angle)[:, None] * second)
        + along[:, None] * axis
    )
    padded = np.concatenate([points, np.full((20, 3), 5.0)])  # padding must be ignored
    mask = np.arange(100) < 80
    origin = points[0]
    circle = fit_circles(padded[None], mask[None], axis[None], origin[None])
    assert circle.valid[0]
    assert circle.radii[0] == pytest.approx(radius, rel=1e-6)
    assert circle.rms[0] < 1e-9
    expected = axis_point + ((origin - axis_point) @ axis) * axis
    assert np.allclose(circle.axis_points[0], expected, atol=1e-8)


def test_circle_fit_on_noisy_arc_stays_close() -> None:
    rng = np.random.default_rng(7)
    angle = rng.uniform(0, np.pi, 200)
    points = np.column_stack(
        [0.02 * np.cos(angle), 0.02 * np.sin(angle), rng.uniform(-0.01, 0.01, 200)]
    )
    points[:, :2] += rng.normal(scale=4e-4, size=(200, 2))
    circle = fit_circles(
        points[None], np.ones((1, 200), bool), np.array([[0, 0, 1.0]]), np.zeros((1, 3))
    )
    assert circle.radii[0] == pytest.approx(0.02, rel=0.05)
    assert np.linalg.norm(circle.axis_points[0]) < 1e-3
    assert 2e-4 < circle.rms[0] < 8e-4


def test_collinear_points_give_no_finite_small_circle() -> None:
    points = np.outer(np.linspace(-0.01, 0.01, 30), [1.0, 0, 0])
    circle = fit_circles(
        points[None], np.ones((1, 30), bool), np.array([[0, 0, 1.0]]), np.zeros((1, 3))
    )
    assert not (circle.valid[0] and circle.radii[0] < 1.0)
