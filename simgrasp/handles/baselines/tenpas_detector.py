"""The ten Pas & Platt style handle detector ("Localizing handle-like grasp affordances in 3-D
point clouds using Taubin quadric fitting", arXiv 1311.3192).

Pipeline, timed per step like the quadric detector: voxelize the cloud (normals are not
needed: Taubin's fit uses points only); sample neighborhood centers and gather spherical
neighborhoods; fit a Taubin quadric per neighborhood; take the direction of minimal curvature
at the neighborhood's surface point as the local axis and fit a circle across it (radius and
axis point); keep cylindrical shells whose radius fits the gripper and that have a clear gap
for the fingers around them; chain aligned shells into handles. One KD-tree of the voxelized
cloud, built (and timed) in the sampling step, serves the neighborhoods and the shell test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

import simgrasp.handles.core.criteria as criteria
from simgrasp.handles.baselines.cylinder_fit import (
    fit_circles,
    minimal_curvature_axes,
    project_to_surface,
)
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.cloud_input import validate_cloud
from simgrasp.handles.core.detection import TIMING_STEPS, Candidate, Detection, Handle
from simgrasp.handles.core.step_timer import new_timings, timed
from simgrasp.perception import gather_neighborhoods, sample_centers, voxel_downsample
from simgrasp.quadric import Quadric, QuadricFit, fit_quadrics
from simgrasp.seeding import rng_for

KIND = "cylinder_shell"


@dataclass(frozen=True)
class Shells:
    """Cylindrical shells of a batch of B neighborhoods (cloud frame, meters).

    Attributes:
        axes: (B, 3) unit axis directions (minimal curvature).
        axis_points: (B, 3) axis points in the plane through each neighborhood center.
        radii: (B,) fitted radii (m).
        accepted: (B,) which shells passed every test.
    """

    axes: NDArray[np.float64]
    axis_points: NDArray[np.float64]
    radii: NDArray[np.float64]
    accepted: NDArray[np.bool_]


def detect_tenpas_handles(
    points: ArrayLike,
    normals: ArrayLike | None = None,
    config: TenPasConfig | None = None,
    seed: int = 0,
    viewpoint: ArrayLike | None = None,
) -> Detection:
    """Detect handles in one object's point cloud with cylindrical shells.

    Args:
        points: (N, 3) cloud of one segmented object (any frame, meters).
        normals: (N, 3) unit normals or None; validated and down-sampled with the cloud but
            not needed by this method (the Taubin fit uses points only).
        config: thresholds; defaults to :class:`TenPasConfig` ().
        seed: seeds neighborhood sampling.
        viewpoint: accepted for interface parity with the quadric detector; unused, since no
            normals are estimated.

    Returns:
        A :class:`Detection` (``detector="tenpas"``) in the cloud's frame: candidates are the
        accepted shells (kind ``"cylinder_shell"``). A cloud too small or too flat for any
        neighborhood or shell gives an empty detection, not an error.
    """
    del viewpoint  # no normals are estimated, so no orientation is needed
    config = config or TenPasConfig()
    pts, nrm = validate_cloud(points, normals)
    timings = new_timings()
    with timed(timings, "voxelize"):
        if config.voxel_size > 0:
            pts, nrm = voxel_downsample(pts, config.voxel_size, normals=nrm)
    timings["normals"] = 0.0
    rng = rng_for(seed, "tenpas", "sample")
    with timed(timings, "sample"):
        tree = cKDTree(pts)
        center_index = sample_centers(
            pts, rng, count=config.neighborhoods, voxel_size=max(config.voxel_size, 1e-4)
        )
        hoods = gather_neighborhoods(
            pts,
            np.zeros_like(pts) if nrm is None else nrm,  # carried along, never used
            pts[center_index],
            config.neighborhood_radius,
            shape="sphere",
            max_points=config.max_points,
            min_points=config.min_points,
            rng=rng,
            tree=tree,
        )
    if len(hoods.centers) == 0:
        return Detection((), (), pts[center_index], "tenpas", _complete(timings), pts)
    with timed(timings, "fit"):
        fit = fit_quadrics(hoods.points, None, method="taubin", mask=hoods.mask)
    with timed(timings, "test"):
        shells = _test_shells(
            fit.coefficients, fit.valid, hoods.points, hoods.mask, hoods.centers, tree, config
        )
    with timed(timings, "cluster"):
        candidates, handles = _candidates_and_handles(shells, fit, hoods.centers, config)
    return Detection(candidates, handles, pts[center_index], "tenpas", _complete(timings), pts)


def _candidates_and_handles(
    shells: Shells,
    fit: QuadricFit,
    hood_centers: NDArray[np.float64],
    config: TenPasConfig,
) -> tuple[tuple[Candidate, ...], tuple[Handle, ...]]:
    """The accepted shells as candidates, and the handles aligned from them."""
    index = np.flatnonzero(shells.accepted)
    candidates = tuple(
        Candidate(
            center=hood_centers[i],
            quadric=quadric,
            kind=KIND,
            axis=shells.axes[i],
            width=float(2 * shells.radii[i]),
            handle_point=shells.axis_points[i],
        )
        for i, quadric in zip(
            index, Quadric.batch(fit.coefficients[index], config.kind_rtol), strict=True
        )
    )
    handles = align_shells(
        shells.axis_points[index], shells.axes[index], shells.radii[index], config
    )
    return candidates, handles


def _complete(timings: dict[str, float]) -> dict[str, float]:
    """Every step of the timing table, zero for steps that did not run."""
    return {step: timings.get(step, 0.0) for step in TIMING_STEPS}


def _test_shells(
    coefficients: NDArray[np.float64],
    fit_valid: NDArray[np.bool_],
    hood_points: NDArray[np.float64],
    hood_mask: NDArray[np.bool_],
    centers: NDArray[np.float64],
    tree: cKDTree,
    config: TenPasConfig,
) -> Shells:
    """Axis, circle, radius filter and shell test for a batch of B neighborhoods (``tree``: a
    ``cKDTree`` of the voxelized cloud)."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        surface = project_to_surface(coefficients, centers)
        curvature = minimal_curvature_axes(coefficients, surface)
        circles = fit_circles(hood_points, hood_mask, curvature.axes, centers)
        radii = circles.radii
        off_axis = np.linalg.norm(centers - circles.axis_points, axis=1)
        accepted = fit_valid & curvature.valid & circles.valid
        accepted &= (radii >= config.min_radius) & (radii <= config.gripper_max_opening / 2)
        accepted &= circles.rms <= config.max_circle_residual * radii
        accepted &= np.abs(off_axis - radii) <= config.surface_tolerance * radii
    index = np.flatnonzero(accepted)
    if len(index):
        clear = criteria.shell_clear(
            tree,
            circles.axis_points[index],
            curvature.axes[index],
            radii[index],
            half_length=config.shell_half_length,
            gap=config.shell_gap,
            thickness=config.finger_clearance,
            max_fraction=config.max_shell_fraction,
        )
        accepted[index[~clear]] = False
    return Shells(curvature.axes, circles.axis_points, radii, accepted)


def align_shells(
    axis_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    radii: NDArray[np.float64],
    config: TenPasConfig,
) -> tuple[Handle, ...]:
    """Chain aligned shells into handles (ten Pas & Platt's handle search).

    Two shells are linked when their axes differ by less than ``config.align_angle``, each
    axis point lies within ``config.align_distance`` (m) of the other's axis line, their radii
    differ by at most ``config.align_radius_ratio`` of the larger, and their axis points are at
    most ``config.align_gap`` (m) apart along the axis. Connected groups of at least
    ``config.min_shells`` shells become handles, sorted by decreasing score.

    Args:
        axis_points: (M, 3) axis points of the accepted shells (cloud frame, m).
        axes: (M, 3) unit axis directions (sign arbitrary).
        radii: (M,) shell radii (m).
    """
    count = len(axis_points)
    if count < config.min_shells:
        return ()
    reach = float(np.hypot(config.align_gap, config.align_distance))
    pairs = cKDTree(axis_points).query_pairs(reach, output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    offset = axis_points[j] - axis_points[i]
    parallel = np.abs(np.einsum("ni,ni->n", axes[i], axes[j])) >= np.cos(config.align_angle)
    along_i = np.einsum("ni,ni->n", offset, axes[i])
    along_j = np.einsum("ni,ni->n", offset, axes[j])
    distance = np.linalg.norm(offset, axis=1)
    off_line_i = np.sqrt(np.maximum(distance**2 - along_i**2, 0.0))
    off_line_j = np.sqrt(np.maximum(distance**2 - along_j**2, 0.0))
    similar = np.abs(radii[i] - radii[j]) <= config.align_radius_ratio * np.maximum(
        radii[i], radii[j]
    )
    linked = (
        parallel
        & (np.maximum(off_line_i, off_line_j) <= config.align_distance)
        & (np.abs(along_i) <= config.align_gap)
        & similar
    )
    graph = coo_matrix((np.ones(int(linked.sum())), (i[linked], j[linked])), shape=(count, count))
    _, labels = connected_components(graph, directed=False)
    handles = [
        _handle_from_shells(axis_points[members], axes[members], radii[members], count)
        for members in (np.flatnonzero(labels == label) for label in np.unique(labels))
        if len(members) >= config.min_shells
    ]
    return tuple(sorted(handles, key=lambda h: -h.score))


def _handle_from_shells(
    axis_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    radii: NDArray[np.float64],
    total: int,
) -> Handle:
    """One handle from its shells: the dominant (sign-free) axis direction, the median axis
    point along it, the median width; score = share of all accepted shells x the axes'
    coherence (mean squared cosine to the dominant direction), in [0, 1]."""
    eigenvalues, eigenvectors = np.linalg.eigh(axes.T @ axes / len(axes))
    axis = eigenvectors[:, -1]
    axis = axis if axis[np.argmax(np.abs(axis))] > 0 else -axis
    mean = axis_points.mean(axis=0)
    along = (axis_points - mean) @ axis
    middle = float(np.median(along))
    return Handle(
        center=mean + middle * axis,
        axis=axis,
        width=float(np.median(2 * radii)),
        score=float(np.clip(len(axes) / total * eigenvalues[-1], 0.0, 1.0)),
        support=len(axes),
        span=(float(np.min(along - middle)), float(np.max(along - middle))),
        trace=axis_points.copy(),
        trace_axes=axes.copy(),
    )
