"""Handle labels found automatically on any mesh: our detector on virtual scans, clustered.

The mesh is scanned from many directions (:mod:`simgrasp.autolabel.virtual_scan`); the quadric
detector runs on every view; its accepted neighborhoods (candidates) from all views are pooled
in the mesh frame and kept when they look like a handle's cross-section: narrow enough to be a
handle rather than the object's body (``max_width``) and round rather than flat
(``max_flatness``: a blade's or a wall's fits are flat; looser, ``retry_flatness``, when that
finds nothing on an object that is not a body of revolution). The kept candidates are clustered by
single linkage; clusters seen from enough views, with enough support against the best one,
become handle parts; a part's candidates much wider than its median (``max_section_ratio``:
a knife's blade root or guard fitted as one wide round section) are then left out and,
optionally (``resplit``, off: on ACRONYM tune mugs it dropped strap fragments too), the part
is clustered again, keeping the pieces that pass the part tests on their own.
Optionally (``free_space_fallback``, off by default: on held-out ACRONYM mugs it labeled
rims, see docs/results/handle-labels/README.md), when no round part is found (a flat strap),
the narrow candidates of any flatness that have free space around their axis
(:mod:`simgrasp.autolabel.free_space`: a handle stands off the object, a wall continues
sideways) are clustered instead. Each part's scanned surface points (those near its
candidates, followed ``axis_reach`` along the candidates' axes but not onto the surface of
flat candidates thinner than the part, a blade, and, optionally, not past where the section
grows: :mod:`simgrasp.autolabel.axis_reach`),
split into ``segments`` pieces by k-means (or slabs along their main axis: ``pieces``), give
one oriented box per piece (the way ``models/handles/ycb_handles.json`` was made by hand),
grown by ``margin``. On a body of
revolution (a mug, a jug, a pot: :mod:`simgrasp.autolabel.revolution`), the scanned surface that
stands off the body joins the label where it touches a part that stands off the body itself
(the rest of a strap the detector saw in part), and is the label when no part was found (a flat
strap, a solid fin). The result is a
:class:`~simgrasp.labels.HandleLabel` in the mesh frame, meters; no part found means
an empty label (no handle).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import trimesh
from numpy.typing import NDArray
from scipy.cluster.hierarchy import fcluster, linkage

from simgrasp.autolabel.config import AutoLabelConfig, Candidates
from simgrasp.autolabel.cross_section import (
    SectionProfile,
    alike_share,
    long_runs,
    section_profile,
)
from simgrasp.autolabel.free_space import sideways_occupancy, voxel_thinned
from simgrasp.autolabel.label_surface import (
    part_surfaces,
    piece_boxes,
    standoff_joining,
    stands_off,
)
from simgrasp.autolabel.revolution import fit_revolution, standoff_points
from simgrasp.autolabel.virtual_scan import View, scan_mesh
from simgrasp.errors import SimgraspError
from simgrasp.handles import detect
from simgrasp.handles.core.detection import Detection
from simgrasp.labels import HandleLabel
from simgrasp.quadric import analyze_quadrics


@dataclass(frozen=True)
class AutoLabel:
    """An automatic label with what it was made from (for plots and reports)."""

    label: HandleLabel
    candidates: Candidates
    kept: NDArray[np.bool_]
    """Which candidates passed the width and flatness tests (or, in the fallback, the width
    and free-space tests)."""
    parts: tuple[NDArray[np.int64], ...]
    """Candidate indices of each accepted part."""
    surface: NDArray[np.float64]
    """All scanned points (mesh frame, m)."""
    standoff: tuple[NDArray[np.int64], ...] = ()
    """Indices into ``surface`` of the pieces standing off a body of revolution that joined
    the label (:func:`simgrasp.autolabel.label_surface.standoff_joining`)."""


def auto_handle_label(
    mesh: trimesh.Trimesh, name: str, config: AutoLabelConfig | None = None
) -> AutoLabel:
    """The automatic handle label of ``mesh`` (its own frame, meters) for object ``name``."""
    config = config or AutoLabelConfig()
    views = scan_mesh(mesh, config.scan)
    if not views:
        raise SimgraspError(f"object {name!r}: no scan saw the mesh")
    candidates = pooled_candidates(views, config)
    surface = np.concatenate([v.points for v in views])
    normals = np.concatenate([v.normals for v in views])
    return label_from_candidates(candidates, surface, name, config, normals)


def label_from_candidates(
    candidates: Candidates,
    surface: NDArray[np.float64],
    name: str,
    config: AutoLabelConfig,
    normals: NDArray[np.float64] | None = None,
) -> AutoLabel:
    """The label made from pooled ``candidates`` and the scanned ``surface`` (mesh frame, m)
    with its unit ``normals`` (None: no stand-off test): everything of
    :func:`auto_handle_label` after the scans and the detector."""
    revolution = None
    if normals is not None and config.revolution.margin > 0:
        revolution = fit_revolution(surface, normals, config.revolution)
    narrow = candidates.widths <= config.max_width
    kept = narrow & (candidates.flatness <= config.max_flatness)
    parts = handle_parts(candidates, kept, config)
    profile = section_profile(surface, config.cross_section)
    if not parts and revolution is None and config.retry_flatness > config.max_flatness:
        kept = narrow & (candidates.flatness <= config.retry_flatness)
        parts = flat_handle_parts(candidates, kept, surface, profile, config)
    if config.free_space_fallback and not parts and narrow.any():
        kept = narrow & (free_space_shares(candidates, surface, config) <= config.max_occupancy)
        parts = handle_parts(candidates, kept, config)
    if config.max_section_ratio > 0:
        parts = tuple(uniform_section(candidates, part, config) for part in parts)
    if config.resplit:
        parts = tuple(piece for part in parts for piece in resplit(candidates, part, config))
    long = long_runs([candidates.centers[p] for p in parts], profile, config.cross_section)
    parts = tuple(part for part, keep in zip(parts, long, strict=True) if keep)
    standing = tuple(
        revolution is not None and stands_off(candidates, part, revolution, config)
        for part in parts
    )
    beyond = None
    if revolution is not None:
        beyond = standoff_points(surface, revolution, config.revolution.margin)
    regions = part_surfaces(candidates, parts, surface, config, beyond, standing, profile)
    boxes = tuple(box for region in regions for box in piece_boxes(surface[region], config))
    standoff: tuple[NDArray[np.int64], ...] = ()
    if beyond is not None:
        strap_regions = [r for r, stands in zip(regions, standing, strict=True) if stands]
        standoff = standoff_joining(surface, beyond, strap_regions, bool(parts), config)
    boxes += tuple(box for piece in standoff for box in piece_boxes(surface[piece], config))
    return AutoLabel(HandleLabel(name, boxes), candidates, kept, parts, surface, standoff)


def pooled_candidates(views: list[View], config: AutoLabelConfig) -> Candidates:
    """Run the detector on every view and pool its candidates."""
    rows: list[NDArray[np.float64]] = []
    for k, view in enumerate(views):
        detection = detect(
            view.points, view.normals, config.detector, config.seed + k, viewpoint=view.viewpoint
        )
        rows.append(_candidate_rows(detection, k, config.detector.kind_rtol))
    table = np.concatenate(rows) if rows else np.zeros((0, 13))
    return Candidates(
        table[:, :3],
        table[:, 3],
        table[:, 4],
        table[:, 5].astype(np.int64),
        table[:, 6:9],
        table[:, 9:12],
        table[:, 12],
    )


def free_space_shares(
    candidates: Candidates, surface: NDArray[np.float64], config: AutoLabelConfig
) -> NDArray[np.float64]:
    """(M,) per candidate, the share of directions around its axis where the scanned
    ``surface`` continues sideways (:func:`simgrasp.autolabel.free_space.sideways_occupancy`)."""
    return sideways_occupancy(
        voxel_thinned(surface, config.free_voxel),
        candidates.handle_points,
        candidates.axes,
        np.fmin(candidates.semi_major, config.free_max_semi_axis),
        slab=config.free_slab,
        gap=config.free_gap,
        ring=config.free_ring,
    )


def _candidate_rows(detection: Detection, view: int, rtol: float) -> NDArray[np.float64]:
    """(M, 13) rows ``[center xyz, width, flatness, view, axis xyz, handle point xyz, larger
    transverse semi-axis]`` of one detection's candidates."""
    if not detection.candidates:
        return np.zeros((0, 13))
    centers = detection.candidate_centers
    coefficients = np.stack([c.quadric.coefficients for c in detection.candidates])
    semi = analyze_quadrics(coefficients, rtol, centers).transverse_semi_axes
    with np.errstate(invalid="ignore", divide="ignore"):
        flatness = np.where(semi[:, 0] > 0, semi[:, 1] / semi[:, 0], np.inf)
    flatness = np.nan_to_num(flatness, nan=np.inf)
    widths = np.array([c.width for c in detection.candidates])
    axes = np.stack([c.axis for c in detection.candidates])
    handle_points = np.stack([c.handle_point for c in detection.candidates])
    return np.column_stack(
        [centers, widths, flatness, np.full(len(centers), view), axes, handle_points, semi[:, 1]]
    )


def handle_parts(
    candidates: Candidates, kept: NDArray[np.bool_], config: AutoLabelConfig
) -> tuple[NDArray[np.int64], ...]:
    """Clusters of the kept candidates that count as handle parts, best supported first."""
    index = np.flatnonzero(kept)
    if len(index) < config.min_candidates:
        return ()
    if len(index) == 1:
        groups = np.ones(1, dtype=np.int64)
    else:
        tree = linkage(candidates.centers[index], method="single")
        groups = fcluster(tree, t=config.cluster_distance, criterion="distance")
    clusters = [index[groups == g] for g in np.unique(groups)]
    clusters = [
        c
        for c in clusters
        if len(c) >= config.min_candidates
        and len(np.unique(candidates.views[c])) >= config.min_views
    ]
    if not clusters:
        return ()
    best = max(len(c) for c in clusters)
    chosen = [c for c in clusters if len(c) >= config.min_relative_support * best]
    return tuple(sorted(chosen, key=len, reverse=True))


def flat_handle_parts(
    candidates: Candidates,
    kept: NDArray[np.bool_],
    surface: NDArray[np.float64],
    profile: SectionProfile | None,
    config: AutoLabelConfig,
) -> tuple[NDArray[np.int64], ...]:
    """The parts :func:`handle_parts` finds among ``kept`` (the flatter candidates of the
    retry) on a long tool whose section changes along it: none without a ``profile`` (not
    elongated), or when the slabs alike the parts' section hold more than ``max_run_share`` of
    the scanned ``surface`` (a ruler, a flat bar: no handle) or that share is not measured
    (:func:`simgrasp.autolabel.cross_section.alike_share`)."""
    parts = handle_parts(candidates, kept, config)
    if profile is None or not parts:
        return ()
    own = candidates.centers[np.concatenate(parts)]
    share = alike_share(surface, own, profile, config.cross_section)
    return parts if share <= config.max_run_share else ()  # NaN: not measured, refused


def uniform_section(
    candidates: Candidates, part: NDArray[np.int64], config: AutoLabelConfig
) -> NDArray[np.int64]:
    """The part's candidates whose larger transverse semi-axis is at most
    ``max_section_ratio`` times the part's median (the others span a guard, a blade's root or
    the wall a strap joins); all of them where the semi-axes are undefined."""
    semi = candidates.semi_major[part]
    median = np.nanmedian(semi) if np.isfinite(semi).any() else np.nan
    if not np.isfinite(median) or len(part) < config.section_min_candidates:
        return part
    return part[~(semi > config.max_section_ratio * median)]


def resplit(
    candidates: Candidates, part: NDArray[np.int64], config: AutoLabelConfig
) -> tuple[NDArray[np.int64], ...]:
    """The pieces of ``part`` that pass :func:`handle_parts` when clustered on their own, or
    ``(part,)`` when none does."""
    mask = np.zeros(len(candidates.centers), dtype=bool)
    mask[part] = True
    alone = replace(config, min_relative_support=0.0)
    return handle_parts(candidates, mask, alone) or (part,)
