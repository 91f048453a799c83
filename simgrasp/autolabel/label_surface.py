"""A handle part's region on the scanned surface, and the boxes that make it a label.

:func:`part_surface` takes the scanned points that belong to one part of
:mod:`simgrasp.autolabel.auto_label` (near its candidates, or reached along their axes,
:mod:`simgrasp.autolabel.axis_reach`); :func:`part_surfaces` keeps a strap's region off a body
of revolution's wall (:mod:`simgrasp.autolabel.revolution`) and a long tool's region off its thin
sections (:mod:`simgrasp.autolabel.cross_section`), and :func:`standoff_joining` adds the surface
that stands off the body; :func:`piece_boxes` turns points into oriented boxes, one per k-means
piece (or slab along their main axis). Mesh frame, meters.
"""

from __future__ import annotations

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.cluster.vq import ClusterError, kmeans2
from scipy.spatial import cKDTree

from simgrasp.autolabel.axis_reach import (
    SectionStop,
    near_within_stops,
    reached_along_axes,
    section_stops,
)
from simgrasp.autolabel.config import AutoLabelConfig, Candidates
from simgrasp.autolabel.cross_section import SectionProfile, off_head, section_run, thick_enough
from simgrasp.autolabel.revolution import Revolution, standoff_pieces, standoff_points
from simgrasp.labels import Box


def part_surfaces(
    candidates: Candidates,
    parts: tuple[NDArray[np.int64], ...],
    surface: NDArray[np.float64],
    config: AutoLabelConfig,
    beyond: NDArray[np.bool_] | None,
    standing: tuple[bool, ...],
    profile: SectionProfile | None,
) -> tuple[NDArray[np.bool_], ...]:
    """(N,) per part, which ``surface`` points are its region (:func:`part_surface`). On a
    body of revolution (``beyond``: which ``surface`` points stand off its wall,
    :func:`simgrasp.autolabel.revolution.standoff_points`), a part that stands off the body
    (``standing``, :func:`stands_off`: a strap) keeps only its points beyond the wall: the
    wall its reach took at the strap's roots is the body's, and a grasp of the rim beside the
    strap is no handle grasp. Other parts (a hammer's round handle, itself the body) keep
    their whole region. On a long tool, a part takes the runs of slabs whose section stays like
    its own (the rest of a flat handle), keeps the slabs about as thick as where it was
    found (:mod:`simgrasp.autolabel.cross_section`: not a knife's blade past its guard) and
    leaves out the slabs both wider and thicker than it (a head); ``profile`` is the
    surface's section profile (None: not a long tool)."""
    section = config.cross_section
    regions = []
    for part, stands in zip(parts, standing, strict=True):
        region = part_surface(candidates, part, surface, config)
        if beyond is not None and stands:
            region &= beyond
        if profile is not None:
            own = candidates.centers[part]
            if section.grow_ratio > 0:
                region |= section_run(surface, own, profile, section)
            if section.min_ratio > 0:
                region &= thick_enough(surface, own, profile, section)
            region &= off_head(surface, own, profile, section)
        regions.append(region)
    return tuple(regions)


def stands_off(
    candidates: Candidates,
    part: NDArray[np.int64],
    revolution: Revolution,
    config: AutoLabelConfig,
) -> bool:
    """Whether most of the part's candidates lie beyond the body's wall."""
    beyond = standoff_points(candidates.centers[part], revolution, config.revolution.margin)
    return bool(beyond.mean() >= 0.5)


def standoff_joining(
    surface: NDArray[np.float64],
    beyond: NDArray[np.bool_],
    standing_regions: list[NDArray[np.bool_]],
    had_parts: bool,
    config: AutoLabelConfig,
) -> tuple[NDArray[np.int64], ...]:
    """Indices into ``surface`` of the pieces standing off the body of revolution (``beyond``,
    :mod:`simgrasp.autolabel.revolution`) that join the label: those within ``region_radius``
    of the region of a part that stands off the body itself (``standing_regions``: a strap,
    not a hammer's round handle under its head), or all of them when there was no part
    (``had_parts`` false)."""
    pieces = standoff_pieces(surface, beyond, config.revolution)
    if not had_parts or not pieces:
        return tuple(pieces)
    own = np.zeros(len(surface), dtype=bool)
    for region in standing_regions:
        own |= region
    if not own.any():
        return ()
    tree = cKDTree(surface[own])
    return tuple(
        piece
        for piece in pieces
        if np.isfinite(
            tree.query(surface[piece], distance_upper_bound=config.region_radius)[0]
        ).any()
    )


def piece_boxes(points: NDArray[np.float64], config: AutoLabelConfig) -> list[Box]:
    """One oriented box, grown by ``margin``, per piece of ``points``: ``segments`` slabs of
    equal point count along their main axis, or ``segments`` k-means clusters started from
    those slabs (``pieces``)."""
    if len(points) < 4:
        return []
    piece = _slab_pieces(points, config.segments)
    if config.pieces == "kmeans" and len(points) >= 4 * config.segments:
        clusters = _kmeans_from(points, piece, config.segments)
        piece = piece if clusters is None else clusters
    boxes = [_box(points[piece == s], config.margin) for s in range(config.segments)]
    return [b for b in boxes if b is not None]


def _slab_pieces(points: NDArray[np.float64], pieces: int) -> NDArray[np.int64]:
    """(N,) the slab of each point: ``pieces`` slabs of equal point count along the main axis."""
    centered = points - points.mean(axis=0)
    main_axis = np.linalg.svd(centered, full_matrices=False)[2][0]
    along = centered @ main_axis
    edges = np.quantile(along, np.linspace(0.0, 1.0, pieces + 1))
    return np.clip(np.searchsorted(edges, along, side="right") - 1, 0, pieces - 1)


def _kmeans_from(
    points: NDArray[np.float64], slab: NDArray[np.int64], pieces: int
) -> NDArray[np.int64] | None:
    """(N,) k-means pieces started from the centroids of ``slab``'s pieces (no random draw:
    the same points always give the same boxes), or None when a piece comes out empty (points
    repeated or too few apart): the caller then keeps the slabs."""
    if (np.bincount(slab, minlength=pieces) == 0).any():
        return None
    start = np.array([points[slab == s].mean(axis=0) for s in range(pieces)])
    try:
        with np.errstate(divide="ignore", invalid="ignore"):
            return kmeans2(points, start, minit="matrix", missing="raise")[1]
    except ClusterError:
        return None


def _box(points: NDArray[np.float64], margin: float) -> Box | None:
    """The oriented bounding box (trimesh) of ``points``, grown by ``margin``."""
    if len(points) < 4:
        return None
    try:
        box_T_points, extents = trimesh.bounds.oriented_bounds(points)
    except (ValueError, TypeError, np.linalg.LinAlgError):
        return None
    points_T_box = np.linalg.inv(box_T_points)
    rotation = points_T_box[:3, :3]
    if np.linalg.det(rotation) < 0:
        rotation = rotation * np.array([1.0, 1.0, -1.0])
    half = np.maximum(np.asarray(extents, float) / 2.0, 1e-4) + margin
    return Box(points_T_box[:3, 3].copy(), rotation, half)


def part_surface(
    candidates: Candidates,
    part: NDArray[np.int64],
    surface: NDArray[np.float64],
    config: AutoLabelConfig,
) -> NDArray[np.bool_]:
    """(N,) which ``surface`` points belong to one part: within ``region_radius`` of its
    candidates, or reached along their axes (:mod:`simgrasp.autolabel.axis_reach`) away from
    the narrow candidates that failed the flatness test and are thinner than the part
    (``block_width_ratio``)."""
    tree = cKDTree(surface)
    flat = (candidates.widths <= config.max_width) & (candidates.flatness > config.max_flatness)
    if config.block_width_ratio > 0:
        flat &= candidates.widths <= config.block_width_ratio * np.median(candidates.widths[part])
    blocked = np.zeros(len(surface), dtype=bool)
    if config.flat_block > 0 and flat.any():
        blocked = cKDTree(candidates.centers[flat]).query(surface)[0] <= config.flat_block
    handle_points, axes = candidates.handle_points[part], candidates.axes[part]
    semi = np.fmin(candidates.semi_major[part], config.reach_max_semi_axis)
    stops = np.tile([-np.inf, np.inf], (len(part), 1))
    if config.stop_growth > 0:
        stop = SectionStop(config.stop_growth, config.stop_ring, config.stop_slab)
        reach = max(config.axis_reach, config.region_radius)
        own, typical = candidates.centers[part], np.fmin(semi, np.nanmedian(semi))
        stops = section_stops(
            tree, surface, own, handle_points, axes, typical, reach=reach, stop=stop
        )
    near = near_within_stops(
        tree, surface, candidates.centers[part], handle_points, axes, stops, config.region_radius
    )
    reached = reached_along_axes(
        surface,
        handle_points,
        axes,
        semi + config.reach_pad,
        reach=config.axis_reach,
        blocked=blocked,
        stops=stops,
    )
    return near | reached
