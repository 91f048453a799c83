"""The wall of a body of revolution as one camera sees it: the side of a mug, a jug, a pot or a
bottle, whose handle stands off it.

In a single view the wall is most of the points, and a noisy or sparse capture of it yields
small curved fits that pass for handles (docs/results/real-detect/README.md, "Which path the
degraded held-out runs fail by"). A fitted wall says which candidates are part of a body wider
than a handle. The axis is the direction most perpendicular to the view's normals (on a wall
every normal is perpendicular to it). Across the axis, a first circle is found by RANSAC:
circles through three seen points, the one with most points on it whose normals point along
its radius. Normals from the whole view tilt the axis where a handle is seen edge-on, so the
axis is taken again from the normals near that first circle alone, and the circle drawn again
about it. A least-squares circle through the points near it then sets the centre and radius;
a wall must pass the radius and share tests both before and after, be no longer along its
axis than ``max_length_radii`` radii (a mug's wall is about 3; a hammer's round handle, which
RANSAC can take for a narrow wall, about 13) and cover ``min_arc_deg`` of arc (a flat blade
seen along its length lies within millimetres of a large circle, on a short arc). A half wall
seen from one side is enough, where :func:`simgrasp.autolabel.revolution.fit_revolution` (for
meshes) asks for normals from every side. A knife or a spatula, flat, or a screwdriver, round
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
"""A wall needs at least this many points whose normals lie across its axis, and its first
circle this many of them on it with their normals along its radius."""
REFINE_BAND = 0.01
"""Points this near (m) the first circle set the axis again and then refine the circle
(:func:`_circle_through`)."""
CIRCLE_LOSS_SCALE = 0.002
"""Residual (m) beyond which a point counts less in the circle fit (soft L1): a handle's or a
rim's points inside the band do not pull the wall."""
NORMAL_REACH = 0.05
"""Search radius (m) of the normals' neighbours: wide, so that ``normal_neighbors`` decides."""


@dataclass(frozen=True)
class BodyWallConfig(Checked):
    """When and how a single view's body wall drops candidates: on in the single-view default
    (the preset ``learned``, :mod:`simgrasp.handles.presets`), off in a bare
    ``SingleViewConfig()`` (docs/results/real-detect/README.md for its figures and how it was
    chosen)."""

    enabled: bool = False
    """Drop kept candidates whose seen surface point lies on the view's body wall."""
    min_radius: Positive = 0.025
    """The narrowest wall (m): a hammer's or a screwdriver's round handle (1-2 cm) is no body."""
    max_radius: Positive = 0.12
    """The widest wall (m): three points of a flat face lie on a huge circle or none."""
    min_wall_share: Fraction = 0.4
    """A wall must hold at least this share of the view's points (within ``wall_tolerance``)."""
    wall_tolerance: Positive = 0.004
    """A point this near the wall's radius (m) is on the wall, for ``min_wall_share``."""
    drop_distance: Positive = 0.006
    """A candidate whose seen surface point lies this near the wall's radius (m) is dropped."""
    ransac_draws: Annotated[int, Range(ge=1)] = 200
    """Circles through three seen points drawn for the first circle (from the detection's
    seed)."""
    radial_cos: Fraction = 0.8
    """A point is on a drawn circle only if its normal's cosine with the circle's radius is at
    least this (either sign): a handle's points crossing the circle do not count."""
    min_arc_deg: Annotated[float, Range(gt=0.0, le=360.0)] = 90.0
    """A wall's points must cover at least this arc about its axis (degrees): a flat blade
    seen along its length lies near a large circle, but on an arc of 20-65 degrees; a mug's
    seen wall covers about 150, with its rim about 350 (docs/results/real-detect/README.md)."""
    max_length_radii: Positive = 6.0
    """A wall whose points span more than this many radii along its axis is a long round
    handle, not a body (fixed before it was measured: docs/results/real-detect/README.md)."""
    retry_threshold: Fraction | None = None
    """Where the single-view detector ends with no handle and the view has a wall of at most
    ``retry_max_radius``: keep the candidates off the wall whose classifier probability is at
    least this, before the fallback (None: no retry)."""
    retry_max_radius: Positive = 0.06
    """The widest wall (m) the retry runs on: a mug's or a cup's body (3-4.5 cm); a pot's
    (8 cm and more), whose flat side tabs only the fallback's plate test finds, keeps the
    fallback."""
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


def fit_body_wall(
    points: NDArray[np.float64], config: BodyWallConfig, seed: int
) -> BodyWall | None:
    """The body wall of a single view's ``points`` (N, 3), or None when the view holds none
    within ``config``'s radii, share, length and arc. ``seed`` draws the RANSAC samples (the
    detection's seed). Normal signs play no part: only the radial cosine's size counts."""
    if len(points) < MIN_VIEW_POINTS:
        return None
    normals = estimate_normals(
        points, radius=NORMAL_REACH, max_nn=config.normal_neighbors, orient="none"
    )
    rng = np.random.default_rng(seed)
    axis = _least_direction(normals)
    first = _first_circle(points, normals, axis, config, rng)
    if first is None:
        return None
    near_first = _across(points, axis, first) < REFINE_BAND
    axis = _least_direction(normals[near_first])
    first = _first_circle(points, normals, axis, config, rng)
    if first is None:
        return None
    across = _basis_across(axis)
    points_2d = points @ across.T
    center_2d, radius = first
    radii = np.linalg.norm(points_2d - center_2d, axis=1)
    if _wall_share(radii, radius, config) is None:
        return None
    near_wall = np.abs(radii - radius) < REFINE_BAND
    center_2d, radius = _circle_through(points_2d[near_wall], center_2d, radius)
    radii = np.linalg.norm(points_2d - center_2d, axis=1)
    share = _wall_share(radii, radius, config)
    if share is None:
        return None
    on_wall = np.abs(radii - radius) < config.wall_tolerance
    if np.ptp(points[on_wall] @ axis) > config.max_length_radii * radius:
        return None
    if _arc_deg(points_2d[on_wall] - center_2d) < config.min_arc_deg:
        return None
    return BodyWall(axis, center_2d @ across, radius, share)


def _arc_deg(offsets: NDArray[np.float64]) -> float:
    """The arc (degrees) that points at ``offsets`` (M, 2) from a circle's centre cover: 360
    less the widest angle between angularly neighbouring points."""
    angles = np.sort(np.arctan2(offsets[:, 1], offsets[:, 0]))
    gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
    return float(np.degrees(2 * np.pi - gaps.max()))


def _least_direction(normals: NDArray[np.float64]) -> NDArray[np.float64]:
    """The unit direction (3,) most perpendicular to ``normals`` (N, 3): on a wall every
    normal is perpendicular to its axis."""
    return np.linalg.eigh(normals.T @ normals)[1][:, 0]


def _across(
    points: NDArray[np.float64],
    axis: NDArray[np.float64],
    circle: tuple[NDArray[np.float64], float],
) -> NDArray[np.float64]:
    """(N,) distances (m) of ``points`` (N, 3) from the wall of ``circle`` (centre (2,) in
    :func:`_basis_across` of ``axis``, radius m), measured across ``axis``."""
    center_2d, radius = circle
    radii = np.linalg.norm(points @ _basis_across(axis).T - center_2d, axis=1)
    return np.abs(radii - radius)


def _first_circle(
    points: NDArray[np.float64],
    normals: NDArray[np.float64],
    axis: NDArray[np.float64],
    config: BodyWallConfig,
    rng: np.random.Generator,
) -> tuple[NDArray[np.float64], float] | None:
    """The circle across ``axis`` (centre (2,) in :func:`_basis_across` of it, radius m)
    through three of the points whose normals lie mostly across it, drawn
    ``config.ransac_draws`` times, that has most such points on it (within
    ``wall_tolerance``, normal along its radius by ``radial_cos``), its radius in range; None
    when fewer than :data:`MIN_WALL_POINTS` points are on the best one."""
    across = _basis_across(axis)
    points_2d, normals_2d = points @ across.T, normals @ across.T
    length = np.linalg.norm(normals_2d, axis=1)
    crossing = length > 0.5  # normals mostly across the axis: the wall's, not a rim's or base's
    if crossing.sum() < MIN_WALL_POINTS:
        return None
    seen, directions = points_2d[crossing], normals_2d[crossing] / length[crossing, None]
    draws = seen[rng.integers(len(seen), size=(config.ransac_draws, 3))]
    centers, radii = _circles_through_three(draws)
    fine = np.isfinite(radii) & (radii >= config.min_radius) & (radii <= config.max_radius)
    if not fine.any():
        return None
    centers, radii = centers[fine], radii[fine]
    dx = seen[None, :, 0] - centers[:, 0, None]  # (draws, points)
    dy = seen[None, :, 1] - centers[:, 1, None]
    distances = np.sqrt(dx * dx + dy * dy)
    draw, point = np.nonzero(np.abs(distances - radii[:, None]) < config.wall_tolerance)
    along = np.abs(dx[draw, point] * directions[point, 0] + dy[draw, point] * directions[point, 1])
    radial = along / np.maximum(distances[draw, point], 1e-12) >= config.radial_cos
    counts = np.bincount(draw[radial], minlength=len(radii))
    best = int(np.argmax(counts))
    if counts[best] < MIN_WALL_POINTS:
        return None
    return centers[best], float(radii[best])


def _circles_through_three(
    triples: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centres (D, 2) and radii (D,) of the circles through each of ``triples`` (D, 3, 2);
    radius inf where the three points are (nearly) on a line."""
    a, b, c = triples[:, 0], triples[:, 1], triples[:, 2]
    ab, ac = b - a, c - a
    cross = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
    ab2, ac2 = (ab**2).sum(axis=1), (ac**2).sum(axis=1)
    degenerate = np.abs(cross) < 1e-12
    denominator = np.where(degenerate, 1.0, 2 * cross)
    offset = (
        np.stack([ac[:, 1] * ab2 - ab[:, 1] * ac2, ab[:, 0] * ac2 - ac[:, 0] * ab2], axis=1)
        / denominator[:, None]
    )
    radii = np.where(degenerate, np.inf, np.linalg.norm(offset, axis=1))
    return a + offset, radii


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
    sense, started from ``center`` and ``radius``: three drawn points set the first circle,
    all the wall's points this one."""
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
