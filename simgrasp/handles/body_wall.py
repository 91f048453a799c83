"""The wall of a body of revolution as one camera sees it: the side of a mug, a jug, a pot or a
bottle, whose handle stands off it.

In a single view the wall is most of the points, and a noisy or sparse capture of it yields
small curved fits that pass for handles (docs/results/real-detect/README.md, "Which path the
degraded held-out runs fail by"). A fitted wall says which candidates are part of a body wider
than a handle. The axis is the direction most perpendicular to the view's normals (on a wall
every normal is perpendicular to it); across the axis, the centre is the point the normals'
lines pass nearest (least squares, reweighted so that points off the wall, a handle's or a
rim's, count less); the radius is the median distance of the points whose normal lines pass
near it. Noisy normals pull that centre toward the seen side (2 mm of range noise took a real
mug's 3.8 cm wall to 3.3 cm), so a circle fitted to the points near that first wall then sets
the centre and radius; a wall must pass the radius and share tests both before and after.
A half wall seen from one side is enough, where
:func:`simgrasp.handles.revolution.fit_revolution` (for meshes) asks for normals from every
side. A flat knife or a spatula, whose normals are parallel, or a hammer or screwdriver, round
about a handle thinner than ``min_radius``, has no wall.

Lengths in meters, in the frame of the points (a sensor's frame for a single view).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares

from simgrasp.config.checks import Checked, Fraction, Positive, Range
from simgrasp.perception.normals import estimate_normals

MIN_VIEW_POINTS = 50
"""A view of fewer points is not searched for a wall."""
MIN_WALL_POINTS = 20
"""A wall needs at least this many points whose normals lie across its axis and whose normal
lines pass near its centre."""
REWEIGHTINGS = 4
"""Least-squares passes for the wall's centre, each reweighting the normal lines by how near
the last centre they pass (the first pass weighs all alike)."""
REFINE_BAND = 0.01
"""Points this near (m) the first wall estimate refine it (:func:`_circle_through`)."""
CIRCLE_LOSS_SCALE = 0.002
"""Residual (m) beyond which a point counts less in the circle fit (soft L1): a handle's or a
rim's points inside the band do not pull the wall."""
NORMAL_REACH = 0.05
"""Search radius (m) of the normals' neighbours: wide, so that ``normal_neighbors`` decides."""


@dataclass(frozen=True)
class BodyWallConfig(Checked):
    """When and how a single view's body wall drops candidates: on in
    :meth:`~simgrasp.handles.single_view.SingleViewConfig.learned`, the single-view default
    since 7 December 2026; off in a bare ``SingleViewConfig()`` and the presets kept for old
    runs (docs/results/real-detect/README.md for its figures and how it was chosen)."""

    enabled: bool = False
    """Drop kept candidates whose seen surface point lies on the view's body wall."""
    min_radius: Positive = 0.025
    """The narrowest wall (m): a hammer's or a screwdriver's round handle (1-2 cm) is no body."""
    max_radius: Positive = 0.12
    """The widest wall (m): a flat face's normal lines meet nowhere near, at a huge radius."""
    min_wall_share: Fraction = 0.4
    """A wall must hold at least this share of the view's points (within ``wall_tolerance``)."""
    wall_tolerance: Positive = 0.004
    """A point this near the wall's radius (m) is on the wall, for ``min_wall_share``."""
    drop_distance: Positive = 0.006
    """A candidate whose seen surface point lies this near the wall's radius (m) is dropped."""
    line_miss: Positive = 0.005
    """A normal line passing this near the centre (m) is a wall point: it counts fully in the
    reweighting and its distance sets the radius."""
    normal_neighbors: Annotated[int, Range(ge=3)] = 12
    """Nearest points of each point's PCA normal."""

    def _check(self) -> None:
        self.require_below("min_radius", "max_radius")


@dataclass(frozen=True)
class BodyWall:
    """A fitted wall: a unit ``axis`` (3,), a ``center`` (3,) on the axis, its ``radius`` (m)
    and the share of the view's points on it (``wall_share``)."""

    axis: NDArray[np.float64]
    center: NDArray[np.float64]
    radius: float
    wall_share: float

    def distance(self, points: NDArray[np.float64]) -> NDArray[np.float64]:
        """(N,) distances (m) of ``points`` (N, 3) from the wall, measured across the axis."""
        offsets = points - self.center
        across = offsets - np.outer(offsets @ self.axis, self.axis)
        return np.abs(np.linalg.norm(across, axis=1) - self.radius)


def fit_body_wall(points: NDArray[np.float64], config: BodyWallConfig) -> BodyWall | None:
    """The body wall of a single view's ``points`` (N, 3), or None when the view holds none
    within ``config``'s radii and share. Normal signs play no part: lines have none."""
    if len(points) < MIN_VIEW_POINTS:
        return None
    normals = estimate_normals(
        points, radius=NORMAL_REACH, max_nn=config.normal_neighbors, orient="none"
    )
    axis = np.linalg.eigh(normals.T @ normals)[1][:, 0]
    across = _basis_across(axis)
    points_2d, normals_2d = points @ across.T, normals @ across.T
    length = np.linalg.norm(normals_2d, axis=1)
    crossing = length > 0.5  # normals mostly across the axis: the wall's, not a rim's or base's
    if crossing.sum() < MIN_WALL_POINTS:
        return None
    center_2d, misses = _nearest_to_lines(
        points_2d[crossing], normals_2d[crossing] / length[crossing, None], config.line_miss
    )
    on_lines = misses < config.line_miss
    if on_lines.sum() < MIN_WALL_POINTS:
        return None
    radii = np.linalg.norm(points_2d - center_2d, axis=1)
    radius = float(np.median(radii[crossing][on_lines]))
    if _wall_share(radii, radius, config) is None:
        return None
    near_wall = np.abs(radii - radius) < REFINE_BAND
    center_2d, radius = _circle_through(points_2d[near_wall], center_2d, radius)
    radii = np.linalg.norm(points_2d - center_2d, axis=1)
    share = _wall_share(radii, radius, config)
    if share is None:
        return None
    return BodyWall(axis, center_2d @ across, radius, share)


def off_body_wall(
    surface: NDArray[np.float64], points: NDArray[np.float64], config: BodyWallConfig
) -> NDArray[np.bool_]:
    """(M,) True for the candidates whose seen surface points ``surface`` (M, 3) lie off the
    body wall of the view ``points`` (N, 3) by at least ``config.drop_distance``; all True
    where the view has no wall."""
    wall = fit_body_wall(points, config)
    if wall is None:
        return np.ones(len(surface), dtype=bool)
    return wall.distance(surface) >= config.drop_distance


def _wall_share(radii: NDArray[np.float64], radius: float, config: BodyWallConfig) -> float | None:
    """The share of the points, at ``radii`` (N,) from a circle's centre, on that circle of
    ``radius`` (m) when it is a wall (its radius in ``config``'s range, enough points on it);
    else None."""
    share = float(np.mean(np.abs(radii - radius) < config.wall_tolerance))
    in_range = config.min_radius <= radius <= config.max_radius
    return share if in_range and share >= config.min_wall_share else None


def _circle_through(
    points: NDArray[np.float64], center: NDArray[np.float64], radius: float
) -> tuple[NDArray[np.float64], float]:
    """The circle (centre (2,), radius m) nearest ``points`` (M, 2) in the least-squares
    sense, started from ``center`` and ``radius``: the wall's points lie on it whatever the
    noise in their normals, which pulls the normal lines' meeting point toward them."""
    start = np.append(center, radius)
    fit = least_squares(
        lambda p: np.linalg.norm(points - p[:2], axis=1) - p[2],
        start,
        loss="soft_l1",
        f_scale=CIRCLE_LOSS_SCALE,
    )
    return fit.x[:2], float(fit.x[2])


def _basis_across(axis: NDArray[np.float64]) -> NDArray[np.float64]:
    """(2, 3) orthonormal rows spanning the plane across unit ``axis``."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    first = np.cross(axis, helper)
    first /= np.linalg.norm(first)
    return np.stack([first, np.cross(axis, first)])


def _nearest_to_lines(
    points: NDArray[np.float64], directions: NDArray[np.float64], line_miss: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The 2-D point nearest the lines through ``points`` (M, 2) along unit ``directions``
    (M, 2), lines missing the last estimate by more than ``line_miss`` weighted down by
    ``line_miss`` over their miss; and each line's miss (m) of it."""
    projectors = np.eye(2)[None] - directions[:, :, None] * directions[:, None, :]
    weights = np.ones(len(points))
    for _ in range(REWEIGHTINGS):
        system = np.einsum("n,nij->ij", weights, projectors)
        target = np.einsum("n,nij,nj->i", weights, projectors, points)
        center = np.linalg.lstsq(system, target, rcond=None)[0]
        offsets = center - points
        misses = np.abs(offsets[:, 0] * directions[:, 1] - offsets[:, 1] * directions[:, 0])
        weights = np.minimum(1.0, line_miss / np.maximum(misses, 1e-12))
    return center, misses
