"""Batched cylinder estimation from fitted quadrics and neighborhoods (ten Pas & Platt style).

For a batch of B neighborhoods (cloud frame, meters): the local cylinder axis is the direction
of minimal principal curvature of the neighborhood's fitted quadric at its surface point, and
the cylinder's radius and axis point come from a circle fitted to the neighborhood points
projected on the plane perpendicular to that axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simgrasp.quadric.coefficients import coefficients_to_matrix

_EPS = 1e-12
_MIN_CONDITION = 1e-9
"""Smallest/largest singular value of the scaled circle-fit system below which the projected
points are degenerate (collinear or coincident)."""


def quadric_parts(
    coefficients: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Split (B, 10) coefficients ``[A..J]`` into the (B, 3, 3) quadratic part ``q``, the
    (B, 3) linear part ``[G, H, I]`` and the (B,) constant ``J``, so that
    ``f(x) = xᵀ q x + 2 [G, H, I]·x + J``."""
    matrix = coefficients_to_matrix(coefficients)
    return matrix[:, :3, :3], matrix[:, :3, 3], matrix[:, 3, 3]


def project_to_surface(
    coefficients: NDArray[np.float64], points: NDArray[np.float64], steps: int = 3
) -> NDArray[np.float64]:
    """Move each of the (B, 3) points onto its quadric's zero set by Newton steps along the
    gradient (``x <- x - f ∇f / |∇f|²``); points where the gradient vanishes stay put."""
    q, linear, const = quadric_parts(coefficients)
    x = np.array(points, dtype=float)
    for _ in range(steps):
        qx = np.einsum("bij,bj->bi", q, x)
        value = np.einsum("bi,bi->b", x, qx) + 2 * np.einsum("bi,bi->b", linear, x) + const
        gradient = 2 * (qx + linear)
        norm2 = np.einsum("bi,bi->b", gradient, gradient)
        step = np.where(norm2 > _EPS, value / np.maximum(norm2, _EPS), 0.0)
        x = x - step[:, None] * gradient
    return x


def perpendicular_basis(
    directions: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two (B, 3) unit vectors completing each unit direction to a right-handed frame."""
    helper = np.where(
        (np.abs(directions[:, 0]) < 0.9)[:, None], np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    )
    first = np.cross(directions, helper)
    first /= np.linalg.norm(first, axis=1, keepdims=True)
    return first, np.cross(directions, first)


@dataclass(frozen=True)
class CurvatureAxes:
    """Principal curvature directions of B quadrics at points on their surfaces.

    Attributes:
        axes: (B, 3) unit directions of minimal absolute curvature (the local cylinder axis).
        curvatures: (B, 2) principal curvatures (1/m), minimal absolute value first; the sign
            follows the quadric's gradient direction.
        valid: (B,) False where the gradient vanishes or the values are not finite.
    """

    axes: NDArray[np.float64]
    curvatures: NDArray[np.float64]
    valid: NDArray[np.bool_]


def minimal_curvature_axes(
    coefficients: NDArray[np.float64], surface_points: NDArray[np.float64]
) -> CurvatureAxes:
    """Principal curvatures of each quadric at its (B, 3) surface point.

    The shape operator is the Hessian ``2q`` projected on the tangent plane (perpendicular to
    the gradient) and divided by the gradient's length; its 2 x 2 eigen-decomposition gives
    the principal curvatures and directions.
    """
    q, linear, _ = quadric_parts(coefficients)
    gradient = 2 * (np.einsum("bij,bj->bi", q, surface_points) + linear)
    length = np.linalg.norm(gradient, axis=1)
    valid = np.isfinite(length) & (length > _EPS)
    normal = np.where(valid[:, None], gradient / np.where(valid, length, 1.0)[:, None], [0, 0, 1.0])
    t1, t2 = perpendicular_basis(normal)
    tangent = np.stack([t1, t2], axis=-1)  # (B, 3, 2)
    shape = 2 * np.einsum("bia,bij,bjc->bac", tangent, q, tangent)
    shape /= np.where(valid, length, 1.0)[:, None, None]
    shape = np.where(np.isfinite(shape), shape, 0.0)
    values, vectors = np.linalg.eigh(shape)
    order = np.argsort(np.abs(values), axis=1)
    values = np.take_along_axis(values, order, axis=1)
    minimal = np.take_along_axis(vectors, order[:, None, :1], axis=2)[..., 0]  # (B, 2)
    axes = np.einsum("bia,ba->bi", tangent, minimal)
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    valid &= np.all(np.isfinite(values), axis=1)
    return CurvatureAxes(axes, values, valid)


@dataclass(frozen=True)
class CircleFit:
    """Circles fitted across B neighborhoods, in 3-D (cloud frame, meters).

    Attributes:
        axis_points: (B, 3) the circle centers: points on the cylinder axes, in the plane
            through the neighborhood centers perpendicular to the axes.
        radii: (B,) circle radii (m).
        rms: (B,) root mean square distance of the projected points from the circle (m).
        valid: (B,) False for degenerate fits (collinear points, non-finite values).
    """

    axis_points: NDArray[np.float64]
    radii: NDArray[np.float64]
    rms: NDArray[np.float64]
    valid: NDArray[np.bool_]


def fit_circles(
    points: NDArray[np.float64],
    mask: NDArray[np.bool_],
    axes: NDArray[np.float64],
    origins: NDArray[np.float64],
    refine_steps: int = 5,
) -> CircleFit:
    """Fit one circle per neighborhood to its points projected along its axis.

    Args:
        points: (B, K, 3) neighborhood points (padded), cloud frame, meters.
        mask: (B, K) which points are real.
        axes: (B, 3) unit axis directions; points are projected on the plane perpendicular.
        origins: (B, 3) the plane's origin (the neighborhood centers).
        refine_steps: Gauss-Newton steps on the geometric distance after the algebraic (Kåsa)
            fit, which is biased toward small circles on short arcs.
    """
    e1, e2 = perpendicular_basis(axes)
    offsets = points - origins[:, None, :]
    u = np.einsum("bki,bi->bk", offsets, e1)
    v = np.einsum("bki,bi->bk", offsets, e2)
    weight = mask.astype(float)
    count = np.maximum(weight.sum(axis=1), 1.0)
    # algebraic fit in coordinates scaled to unit RMS spread, so conditioning is scale-free
    scale = np.sqrt(((u**2 + v**2) * weight).sum(axis=1) / count)
    scale = np.where(scale > 0, scale, 1.0)[:, None]
    us, vs = u / scale, v / scale
    design = np.stack([us, vs, np.ones_like(us)], axis=-1) * weight[..., None]
    rhs = -(us**2 + vs**2) * weight
    normal = np.einsum("bki,bkj->bij", design, design)
    singular = np.linalg.svd(normal, compute_uv=False)
    well_posed = singular[:, -1] > _MIN_CONDITION * singular[:, 0]
    solution = np.einsum("bij,bj->bi", np.linalg.pinv(normal), np.einsum("bki,bk->bi", design, rhs))
    cu, cv = -solution[:, 0] / 2, -solution[:, 1] / 2
    radius = np.sqrt(np.maximum(cu**2 + cv**2 - solution[:, 2], 0.0))
    cu, cv, radius = cu * scale[:, 0], cv * scale[:, 0], radius * scale[:, 0]
    params = np.stack([cu, cv, radius], axis=-1)
    for _ in range(refine_steps):
        params = _gauss_newton_step(u, v, weight, params)
    du, dv = u - params[:, :1], v - params[:, 1:2]
    residual = (np.hypot(du, dv) - params[:, 2:]) * weight
    rms = np.sqrt((residual**2).sum(axis=1) / count)
    axis_points = origins + params[:, :1] * e1 + params[:, 1:2] * e2
    valid = well_posed & np.all(np.isfinite(axis_points), axis=1) & np.isfinite(rms)
    valid &= params[:, 2] > 0
    return CircleFit(axis_points, params[:, 2], rms, valid)


def _gauss_newton_step(
    u: NDArray[np.float64],
    v: NDArray[np.float64],
    weight: NDArray[np.float64],
    params: NDArray[np.float64],
) -> NDArray[np.float64]:
    """One batched Gauss-Newton step on sum w (|p - c| - r)² over (cu, cv, r)."""
    du, dv = u - params[:, :1], v - params[:, 1:2]
    distance = np.maximum(np.hypot(du, dv), _EPS)
    residual = (distance - params[:, 2:]) * weight
    jacobian = np.stack([-du / distance, -dv / distance, -np.ones_like(du)], axis=-1)
    jacobian *= weight[..., None]
    normal = np.einsum("bki,bkj->bij", jacobian, jacobian)
    gradient = np.einsum("bki,bk->bi", jacobian, residual)
    step = np.einsum("bij,bj->bi", np.linalg.pinv(normal), gradient)
    updated = params - step
    return np.where(np.all(np.isfinite(updated), axis=1)[:, None], updated, params)
