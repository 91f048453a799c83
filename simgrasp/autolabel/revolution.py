"""What stands off a body of revolution: a mug's, a jug's or a pot's handle, found by shape.

Many objects with a handle are a body of revolution (a mug, a jug, a pot) with the handle
standing off its wall. On such a body every surface normal of the wall meets one axis, and at
each height the wall lies at one radius all the way round; the handle is the surface that lies
farther out than the wall at its height. :func:`fit_revolution` finds the axis from the
scanned points and normals (the direction the wall's normals are perpendicular to, then the
point their lines pass nearest), says whether the surface is one at all (most wall normals
point at the axis, from every side) and takes, per height slab, the wall's radius as the
median over azimuth sectors of each sector's outermost point; :func:`standoff_points` marks
the points more than ``margin`` beyond it. A flat knife or a spatula is no body of
revolution: its flat faces' normals are parallel, not radial, and the fit refuses it; a drill,
round about its housing, leaves azimuth sectors nearly empty. A tool whose round handle is
most of it (a hammer, a screwdriver) is one about its handle; the handle is then the body, and
:mod:`simgrasp.autolabel.label_surface` keeps its label whole.

All lengths in meters, in the frame of the points (the mesh frame for
:mod:`simgrasp.autolabel.auto_label`, which uses it to label handles;
the settings were chosen on ACRONYM mugs and knives and on generated objects:
docs/results/handle-labels/README.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from simgrasp.config.checks import Checked, Fraction, NonNegative, Positive, PositiveInt


@dataclass(frozen=True)
class RevolutionConfig(Checked):
    """Settings of the body-of-revolution test and of the stand-off region (m, shares)."""

    margin: NonNegative = 0.003
    """Points more than this beyond the wall's radius at their height stand off the body; a
    strap's label keeps to them (0: the test is off and nothing stands off)."""
    wall_cosine: Fraction = 0.5
    """Points whose normal makes a cosine of at most this with the axis are the wall's."""
    radial_cosine: Fraction = 0.9
    """A wall point's normal points at the axis when the cosine between its normal and its
    radial direction (both across the axis) is at least this ..."""
    min_radial_share: Fraction = 0.8
    """... and the surface is a body of revolution when at least this share of its wall
    points do (a mug with a big round handle: 0.84; ACRONYM knives up to 0.70) ..."""
    sectors: PositiveInt = 24
    """... and its wall points fill every one of this many azimuth sectors round the axis
    with at least ``min_sector_share`` of their number divided by the sector count."""
    min_sector_share: Fraction = 0.7
    """See ``sectors`` (mugs and pans fill 0.76 or more; a drill about its housing 0.56-0.64,
    ACRONYM knives up to 0.69: docs/results/handle-labels/README.md)."""
    slab: Positive = 0.004
    """Height slabs (along the axis) in which the wall's radius is taken."""
    link: Positive = 0.003
    """Stand-off points closer than this are one piece."""
    min_piece_share: Fraction = 0.01
    """Pieces holding less than this share of all points are noise, not a handle."""


@dataclass(frozen=True)
class Revolution:
    """A body of revolution: ``center`` (3,) a point on its axis, ``axis`` (3,) the axis's unit
    direction, and the wall's radius ``wall`` (S,) in height slabs ``slab`` thick along the
    axis from ``bottom`` (heights measured from ``center``), in the frame of the points it was
    fitted to."""

    center: NDArray[np.float64]
    axis: NDArray[np.float64]
    bottom: float
    slab: float
    wall: NDArray[np.float64]

    def radii_heights(
        self, points: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """(radial vectors (N, 3), radii (N,), heights (N,)) of ``points`` about the axis."""
        return _about_axis(points, self.center, self.axis)

    def wall_at(self, heights: NDArray[np.float64]) -> NDArray[np.float64]:
        """The wall's radius (m) at ``heights`` (the nearest slab's, beyond the ends the end's)."""
        slabs = np.floor((heights - self.bottom) / self.slab).astype(np.int64)
        return self.wall[np.clip(slabs, 0, len(self.wall) - 1)]


def fit_revolution(
    points: NDArray[np.float64], normals: NDArray[np.float64], config: RevolutionConfig
) -> Revolution | None:
    """The axis of the body of revolution that ``points`` (N, 3) with unit ``normals`` (N, 3)
    scan, or None when they are no body of revolution (see :class:`RevolutionConfig`).

    Each eigenvector of the normals' scatter is tried as the axis (a short, wide mug's
    bottom and rim outweigh its wall, so the axis need not be the least one); the one whose
    wall normals point at it most often wins."""
    fits = [
        _fit_about(points, normals, start, config)
        for start in np.linalg.eigh(normals.T @ normals)[1].T
    ]
    best = max(fits, key=lambda fit: fit[1])
    axis_fit, radial_share, sector_share = best
    round_enough = radial_share >= config.min_radial_share
    if axis_fit is None or not round_enough or sector_share < config.min_sector_share:
        return None
    return _with_wall(points, *axis_fit, config)


def _with_wall(
    points: NDArray[np.float64],
    center: NDArray[np.float64],
    axis: NDArray[np.float64],
    config: RevolutionConfig,
) -> Revolution | None:
    """The body about ``center`` and ``axis`` with its wall's radius per height slab: the
    median over azimuth sectors of each sector's outermost point (a handle fills few sectors);
    slabs seen in under half the sectors take the nearest such slab's radius. None when no
    slab is."""
    radial, radii, heights = _about_axis(points, center, axis)
    bottom = float(heights.min())
    slabs = np.floor((heights - bottom) / config.slab).astype(np.int64)
    outer = np.full((slabs.max() + 1, config.sectors), np.nan)
    np.fmax.at(outer, (slabs, _sector(radial, axis, config.sectors)), radii)
    seen = np.isfinite(outer).sum(axis=1) >= config.sectors / 2
    if not seen.any():
        return None
    known = np.flatnonzero(seen)
    nearest = known[np.abs(np.arange(len(outer))[:, None] - known[None, :]).argmin(axis=1)]
    wall = np.nanmedian(outer[known], axis=1)[np.searchsorted(known, nearest)]
    return Revolution(center, axis, bottom, config.slab, wall)


def _fit_about(
    points: NDArray[np.float64],
    normals: NDArray[np.float64],
    start: NDArray[np.float64],
    config: RevolutionConfig,
) -> tuple[tuple[NDArray[np.float64], NDArray[np.float64]] | None, float, float]:
    """The axis refined from direction ``start``, the share of its wall points whose normals
    point at it, and its least-filled azimuth sector's share of an even fill."""
    wall = np.abs(normals @ start) <= config.wall_cosine
    if wall.sum() < 3 * config.sectors:
        return None, 0.0, 0.0
    axis = np.linalg.eigh(normals[wall].T @ normals[wall])[1][:, 0]
    wall = np.abs(normals @ axis) <= config.wall_cosine
    across = np.eye(3) - np.outer(axis, axis)
    points_across, normals_across = points[wall] @ across, normals[wall] @ across
    normals_across /= np.maximum(np.linalg.norm(normals_across, axis=1, keepdims=True), 1e-12)
    radial_ok = np.ones(len(points_across), dtype=bool)
    for _ in range(3):
        center = _nearest_point_to_lines(points_across[radial_ok], normals_across[radial_ok], axis)
        radial = points_across - center
        radii = np.maximum(np.linalg.norm(radial, axis=1), 1e-12)
        cosines = np.abs(np.einsum("ij,ij->i", radial, normals_across)) / radii
        radial_ok = cosines >= config.radial_cosine
        if radial_ok.sum() < 3:
            return None, 0.0, 0.0
    counts = np.bincount(_sector(radial, axis, config.sectors), minlength=config.sectors)
    fill = float(counts.min() / (len(radial) / config.sectors))
    return (center, axis), float(radial_ok.mean()), fill


def standoff_points(
    points: NDArray[np.float64], revolution: Revolution, margin: float
) -> NDArray[np.bool_]:
    """(N,) which ``points`` lie more than ``margin`` (m) beyond the wall's radius at their
    height."""
    _, radii, heights = revolution.radii_heights(points)
    return radii > revolution.wall_at(heights) + margin


def standoff_pieces(
    points: NDArray[np.float64], standoff: NDArray[np.bool_], config: RevolutionConfig
) -> list[NDArray[np.int64]]:
    """Indices into ``points`` of the connected pieces (``link`` apart) of the stand-off
    points that hold at least ``min_piece_share`` of all points, largest first."""
    index = np.flatnonzero(standoff)
    if len(index) == 0:
        return []
    pairs = cKDTree(points[index]).query_pairs(config.link, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), (len(index),) * 2)
    _, piece = connected_components(graph, directed=False)
    sizes = np.bincount(piece)
    order = np.argsort(-sizes)
    return [index[piece == p] for p in order if sizes[p] >= config.min_piece_share * len(points)]


def _about_axis(
    points: NDArray[np.float64], center: NDArray[np.float64], axis: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """(radial vectors (N, 3), radii (N,), heights (N,)) of ``points`` about the unit ``axis``
    through ``center``."""
    offsets = points - center
    heights = offsets @ axis
    radial = offsets - heights[:, None] * axis
    return radial, np.linalg.norm(radial, axis=1), heights


def _nearest_point_to_lines(
    origins: NDArray[np.float64], directions: NDArray[np.float64], axis: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The point across ``axis`` nearest (least squares) to the lines ``origins + t
    directions`` (unit directions, all across ``axis``)."""
    projectors = np.eye(3)[None] - directions[:, :, None] * directions[:, None, :]
    lhs = projectors.sum(axis=0) + np.outer(axis, axis)
    rhs = np.einsum("nij,nj->i", projectors, origins)
    return np.linalg.lstsq(lhs, rhs, rcond=None)[0]


def _sector(
    radial: NDArray[np.float64], axis: NDArray[np.float64], count: int
) -> NDArray[np.int64]:
    """(N,) the azimuth sector (of ``count``) of each radial vector round ``axis``."""
    first = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    first /= np.linalg.norm(first)
    second = np.cross(axis, first)
    angles = np.arctan2(radial @ second, radial @ first)
    return np.minimum(((angles + np.pi) / (2 * np.pi) * count).astype(np.int64), count - 1)
