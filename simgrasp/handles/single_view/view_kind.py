"""Is a cloud one camera's view? Measured from the points and the camera position, so that
``detect`` picks the single-view detector for a sensor's capture and the quadric detector for
a cloud seen from all around (a mesh's samples, a fused chain cloud), with no preset to choose.

A single view holds one surface per ray from the camera: along any direction from the
viewpoint, every point lies at about the nearest point's range. A cloud seen from all around
also holds the surfaces behind (a mug's far wall, a hammer's underside). The measure is the
share of points lying more than :attr:`ViewKindConfig.depth_gap` behind the nearest point of
their ray bin; the bins are as wide as a few of the cloud's own point spacings, seen from the
viewpoint (measured: the median nearest-neighbor distance of the distinct points over their
median range). The points must also lie in one camera's field of view. Measured figures: real
captures and simulated kinect / stereo views 0.000-0.047, full clouds sampled from the YCB
mug's and the generated hammer's and mug's meshes 0.19-0.45 from viewpoints outside them
(docs/results/real-detect/README.md, :mod:`tests.test_view_kind`); from a viewpoint inside
such a cloud, rays go all around.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.config.checks import Checked, Fraction, Positive, PositiveInt, Range
from simgrasp.perception.normals import point_spacing


@dataclass(frozen=True)
class ViewKindConfig(Checked):
    """Thresholds of the single-view test."""

    depth_gap: Positive = 0.02
    """A point more than this (m) behind the nearest point of its ray bin is hidden from the
    viewpoint: a back surface, not sensor noise or a silhouette's flying pixel."""
    bin_spacings: Positive = 2.0
    """Ray bins' width in point spacings at the cloud's median range."""
    max_hidden_share: Fraction = 0.10
    """A cloud with at most this share of hidden points is one view."""
    min_points: PositiveInt = 50
    """Fewer distinct points than this: no test, not a single view."""
    max_half_angle_deg: Annotated[float, Range(gt=0, le=180)] = 75.0
    """A view lies in one camera's field of view: 99 % of the rays from the viewpoint within
    this angle (degrees) of their mean. A viewpoint inside a cloud seen from all around (a
    mesh's samples around the origin) sees one surface per ray too, but all around it."""


def hidden_share(
    points: ArrayLike, viewpoint: ArrayLike, config: ViewKindConfig | None = None
) -> float:
    """Share of the distinct ``points`` (N, 3, m) hidden behind others as seen from
    ``viewpoint`` (3, m, the points' frame); NaN for fewer than ``min_points`` distinct
    points or none apart."""
    config = config or ViewKindConfig()
    distinct = _distinct(points)
    if len(distinct) < config.min_points:
        return float("nan")
    return _hidden_share(distinct, point_spacing(distinct, sample=len(distinct)), viewpoint, config)


def _distinct(points: ArrayLike) -> NDArray[np.float64]:
    """The points (N, 3, m) without repeats (rounded to 10 um)."""
    return np.unique(np.round(np.asarray(points, dtype=np.float64), 5), axis=0)


def _hidden_share(
    distinct: NDArray[np.float64], spacing: float, viewpoint: ArrayLike, config: ViewKindConfig
) -> float:
    """:func:`hidden_share` of ``distinct`` points (at least ``min_points``) whose point
    spacing (m) is ``spacing``: what depends on the viewpoint."""
    rays = distinct - np.asarray(viewpoint, dtype=np.float64)
    ranges = np.linalg.norm(rays, axis=1)
    if not (ranges > 0).all() or spacing <= 0:
        return float("nan")
    bin_rad = config.bin_spacings * spacing / float(np.median(ranges))
    keys = _ray_bins(rays / ranges[:, None], bin_rad)
    order = np.argsort(keys, kind="stable")
    sorted_keys, sorted_ranges = keys[order], ranges[order]
    starts = np.r_[0, np.flatnonzero(np.diff(sorted_keys)) + 1]
    nearest = np.minimum.reduceat(sorted_ranges, starts)
    counts = np.diff(np.r_[starts, len(sorted_keys)])
    hidden = sorted_ranges > np.repeat(nearest, counts) + config.depth_gap
    return float(hidden.mean())


def _ray_bins(directions: NDArray[np.float64], bin_rad: float) -> NDArray[np.int64]:
    """One integer key per unit direction (N, 3): bins of about ``bin_rad`` on a side in
    polar angle and in azimuth times the polar angle's sine."""
    polar = np.arccos(np.clip(directions[:, 2], -1.0, 1.0))
    azimuth = np.arctan2(directions[:, 1], directions[:, 0])
    row = np.floor(polar / bin_rad).astype(np.int64)
    ring = np.maximum(np.sin((row + 0.5) * bin_rad), bin_rad)
    column = np.floor(azimuth * ring / bin_rad).astype(np.int64)
    return row * (2 * int(np.ceil(np.pi / bin_rad)) + 4) + column


def is_single_view(
    points: ArrayLike, viewpoint: ArrayLike | None, config: ViewKindConfig | None = None
) -> bool:
    """Whether ``points`` (N, 3, m) are one camera's view from ``viewpoint`` (None: no
    camera known, so not a single view)."""
    if viewpoint is None:
        return False
    config = config or ViewKindConfig()
    if view_half_angle_deg(points, viewpoint) > config.max_half_angle_deg:
        return False
    share = hidden_share(points, viewpoint, config)
    return bool(share <= config.max_hidden_share)


def one_view_from_somewhere(
    points: ArrayLike,
    config: ViewKindConfig | None = None,
    directions: int = 64,
    max_points: int = 3000,
) -> bool:
    """Whether ``points`` (N, 3, m) hold one surface per ray from some far viewpoint: the
    least :func:`hidden_share` over ``directions`` viewpoints spread evenly around the cloud
    (at three times its extent, at least 0.5 m, from its median point; every k-th point,
    at most ``max_points``) is within ``config.max_hidden_share``. For telling a user that
    a cloud not seen from the origin may be one camera's view in another frame: measured,
    the real mug and knife clouds 0.000, clouds sampled all over the YCB and generated mugs'
    and hammers' meshes 0.14-0.30; a thin flat object's mesh cloud (a knife, a fork, a
    spatula's blade thinner than ``depth_gap``) is 0.000-0.07 too, so this cannot say which
    it is. It does not say from which side: a height field is one too from behind."""
    config = config or ViewKindConfig()
    cloud = np.asarray(points, dtype=np.float64)
    cloud = cloud[:: max(1, len(cloud) // max_points)]
    distinct = _distinct(cloud)
    if len(distinct) < config.min_points:
        return False
    spacing = point_spacing(distinct, sample=len(distinct))
    center = np.median(cloud, axis=0)
    reach = max(0.5, 3.0 * float(np.linalg.norm(np.ptp(cloud, axis=0))))
    eyes = center + reach * _even_directions(directions)
    shares = np.array([_hidden_share(distinct, spacing, eye, config) for eye in eyes])
    measured = shares[np.isfinite(shares)]
    return bool(measured.size and measured.min() <= config.max_hidden_share)


def _even_directions(count: int) -> NDArray[np.float64]:
    """``count`` unit vectors (count, 3) spread evenly over the sphere (a Fibonacci lattice)."""
    index = np.arange(count) + 0.5
    polar = np.arccos(1.0 - 2.0 * index / count)
    azimuth = np.pi * (1.0 + 5.0**0.5) * index
    return np.column_stack(
        [np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar), np.cos(polar)]
    )


def view_half_angle_deg(points: ArrayLike, viewpoint: ArrayLike) -> float:
    """The 99th percentile of the angle (degrees) between the rays from ``viewpoint`` to
    ``points`` (N, 3, m) and their mean direction; 180 when they have none."""
    rays = np.asarray(points, dtype=np.float64) - np.asarray(viewpoint, dtype=np.float64)
    lengths = np.linalg.norm(rays, axis=1)
    directions = rays[lengths > 0] / lengths[lengths > 0, None]
    mean = directions.sum(axis=0)
    if len(directions) == 0 or np.linalg.norm(mean) == 0:
        return 180.0
    cosines = directions @ (mean / np.linalg.norm(mean))
    return float(np.degrees(np.arccos(np.clip(np.percentile(cosines, 1), -1.0, 1.0))))
