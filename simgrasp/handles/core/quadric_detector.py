"""The quadric handle detector (the paper's method, with its suggested extras switchable).

Pipeline, timed per step as in the paper's Table III: voxelize the cloud; estimate normals;
sample neighborhood centers and gather cube-shaped neighborhoods; fit one quadric per
neighborhood (Birdal et al. normals-based least squares by default); test each fit for handle
shape; cluster accepted candidates into handle hypotheses. One KD-tree of the voxelized cloud
serves the normal orientation, the neighborhoods and the tests; it is built (and timed) in the
normals step.
The passes' accepted neighborhoods and their clustering into handles are in
:mod:`simgrasp.handles.core.quadric_passes`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

import simgrasp.handles.core.criteria as criteria
from simgrasp.handles.core.cloud_input import validate_cloud
from simgrasp.handles.core.config import QuadricDetectorConfig
from simgrasp.handles.core.detection import Detection
from simgrasp.handles.core.plate import plate_handles
from simgrasp.handles.core.quadric_passes import Accepted, Pass, cluster_passes, joined
from simgrasp.handles.core.step_timer import new_timings, timed
from simgrasp.perception import (
    estimate_normals,
    gather_neighborhoods,
    sample_centers,
    voxel_downsample,
)
from simgrasp.quadric import (
    HANDLE_KINDS,
    QuadricAnalysis,
    QuadricFit,
    analyze_quadrics,
    fit_quadrics,
)
from simgrasp.seeding import rng_for


def detect_quadric_handles(
    points: ArrayLike,
    normals: ArrayLike | None = None,
    config: QuadricDetectorConfig | None = None,
    seed: int = 0,
    viewpoint: ArrayLike | None = None,
    table: ArrayLike | None = None,
    scene: ArrayLike | None = None,
) -> Detection:
    """Detect handles in one object's point cloud.

    Args:
        points: (N, 3) cloud of one segmented object (any frame, meters).
        normals: (N, 3) unit normals pointing out of the object, or None to estimate them.
        config: thresholds; defaults to :class:`QuadricDetectorConfig` ().
        seed: seeds neighborhood sampling.
        viewpoint: camera position (cloud frame) for a single-view cloud: estimated normals
            are turned toward it; without it they are oriented outward for a full cloud.
        table, scene: the supporting plane [a, b, c, d] and (M, 3) everything the sensor saw,
            for the plate test (``config.plate_test``, :func:`plate_handles`).

    Returns:
        A :class:`Detection` in the cloud's frame. A cloud too small or too flat for any
        neighborhood gives an empty detection, not an error.
    """
    config = config or QuadricDetectorConfig()
    pts, nrm = validate_cloud(points, normals)
    timings = new_timings()
    with timed(timings, "voxelize"):
        if config.voxel_size > 0:
            pts, nrm = voxel_downsample(pts, config.voxel_size, normals=nrm)
    if len(pts) < config.min_points:  # no neighborhood can hold enough points for a fit
        return Detection((), (), np.zeros((0, 3)), "quadric", timings, pts)
    with timed(timings, "normals"):
        tree = cKDTree(pts)
        nrm = _normals(pts, nrm, config, viewpoint, tree)
    view = (viewpoint, table, scene)
    rng = rng_for(seed, "quadric_detector", "sample")
    passes = [_run_pass(pts, nrm, tree, rng, view, config, timings)]
    if config.fine_half_size > 0:
        fine_rng = rng_for(seed, "quadric_detector", "fine")
        fine = fine_pass_config(config)
        passes.append(_run_pass(pts, nrm, tree, fine_rng, view, fine, timings))
    sampled_centers = np.concatenate([p.sampled_centers for p in passes])
    if not any(p.fitted for p in passes):
        return Detection((), (), sampled_centers, "quadric", timings, pts)
    with timed(timings, "cluster"):
        handles, candidates = cluster_passes(pts, passes, config)
    return Detection(candidates, handles, sampled_centers, "quadric", timings, pts)


def fine_pass_config(config: QuadricDetectorConfig) -> QuadricDetectorConfig:
    """The settings of the fine pass (``config.fine_*``): its neighborhoods, fit and shell."""
    return replace(
        config,
        neighborhood_half_size=config.fine_half_size,
        neighborhood_scales=(1.0,),
        voxels_per_neighborhood=config.fine_voxels_per_neighborhood,
        fit_method=config.fine_fit_method,
        second_fit_method=None,
        shell_thickness=config.fine_shell_thickness,
        fine_half_size=0.0,
        plate_test=False,
    )


def _run_pass(
    pts: NDArray[np.float64],
    nrm: NDArray[np.float64],
    tree: cKDTree,
    rng: np.random.Generator,
    view: tuple[ArrayLike | None, ArrayLike | None, ArrayLike | None],
    config: QuadricDetectorConfig,
    timings: dict[str, float],
) -> Pass:
    """Sample neighborhoods, fit and test them with ``config``'s settings; with the plate
    test, plates among the centers no quadric passed (``view``: see :func:`_with_plates`)."""
    with timed(timings, "sample"):
        center_index = _sample(pts, rng, config)
        hoods = _gather(pts, nrm, pts[center_index], tree, rng, config)
    sampled_centers = pts[center_index[np.unique(hoods.source)]]
    if len(hoods.centers) == 0:
        return Pass(Accepted.none(), sampled_centers, fitted=False)
    with timed(timings, "fit"):
        fit, hoods = _fit(hoods, config)
    with timed(timings, "test"):
        accepted, on_axis, analysis = _test(fit, hoods.centers, tree, nrm, config)
        accepted = _first_per_center(accepted, hoods.source)
        found = Accepted.of(hoods.centers, analysis, on_axis, fit)
        accepted = _with_plates(found, pts, tree, hoods, accepted, view, config)
    return Pass(found.rows(np.flatnonzero(accepted)), sampled_centers, fitted=True)


def _sample(
    pts: NDArray[np.float64], rng: np.random.Generator, config: QuadricDetectorConfig
) -> NDArray[np.int64]:
    """Indices of the sampled neighborhood centers (``sample_centers``)."""
    return sample_centers(
        pts,
        rng,
        count=config.neighborhoods,
        voxel_size=max(config.voxel_size, 1e-4),
        per_voxels=config.voxels_per_neighborhood,
    )


@dataclass(frozen=True)
class _Neighborhoods:
    """Every scale's neighborhoods joined along the batch axis (see ``gather_neighborhoods``):
    (B, K, 3) points and normals, (B, K) mask, (B, 3) centers, (B,) index of each one's
    sampled center."""

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    mask: NDArray[np.bool_]
    centers: NDArray[np.float64]
    source: NDArray[np.int64]


def _gather(
    pts: NDArray[np.float64],
    nrm: NDArray[np.float64],
    centers: NDArray[np.float64],
    tree: cKDTree,
    rng: np.random.Generator,
    config: QuadricDetectorConfig,
) -> _Neighborhoods:
    """The neighborhoods around ``centers`` at each of ``config.neighborhood_scales``."""
    scales = [
        gather_neighborhoods(
            pts,
            nrm,
            centers,
            config.neighborhood_half_size * scale,
            shape=config.neighborhood_shape,
            max_points=config.max_points,
            min_points=config.min_points,
            rng=rng,
            tree=tree,
        )
        for scale in config.neighborhood_scales
    ]
    return _Neighborhoods(
        points=joined([h.points for h in scales]),
        normals=joined([h.normals for h in scales]),
        mask=joined([h.mask for h in scales]),
        centers=joined([h.centers for h in scales]),
        source=joined([h.source for h in scales]),
    )


def _fit(hoods: _Neighborhoods, config: QuadricDetectorConfig) -> tuple[QuadricFit, _Neighborhoods]:
    """One quadric per neighborhood with ``config.fit_method``; with ``second_fit_method``,
    the neighborhoods repeated after themselves with the second method's fits."""
    fit = fit_quadrics(hoods.points, hoods.normals, method=config.fit_method, mask=hoods.mask)
    if config.second_fit_method is None:
        return fit, hoods
    second = fit_quadrics(
        hoods.points, hoods.normals, method=config.second_fit_method, mask=hoods.mask
    )
    both = QuadricFit(
        coefficients=np.concatenate([fit.coefficients, second.coefficients]),
        valid=np.concatenate([fit.valid, second.valid]),
        failure=fit.failure + second.failure,
        method=f"{fit.method}+{second.method}",
        centroids=np.concatenate([fit.centroids, second.centroids]),
    )
    twice = _Neighborhoods(
        *(
            np.concatenate([array, array])
            for array in (hoods.points, hoods.normals, hoods.mask, hoods.centers, hoods.source)
        )
    )
    return both, twice


def _first_per_center(accepted: NDArray[np.bool_], source: NDArray[np.int64]) -> NDArray[np.bool_]:
    """One candidate per sampled center: its first passing neighborhood (smallest scale,
    first fit method)."""
    rows = np.flatnonzero(accepted)
    _, first = np.unique(source[rows], return_index=True)
    kept = np.zeros_like(accepted)
    kept[rows[first]] = True
    return kept


def _with_plates(
    found: Accepted,
    pts: NDArray[np.float64],
    tree: cKDTree,
    hoods: _Neighborhoods,
    accepted: NDArray[np.bool_],
    view: tuple[ArrayLike | None, ArrayLike | None, ArrayLike | None],
    config: QuadricDetectorConfig,
) -> NDArray[np.bool_]:
    """``accepted`` with the plate handles among the sampled centers no quadric passed (one
    row each, its first); their rows of ``found`` are overwritten with the plate's handle
    point (the center), edge axis, thickness and faces (:func:`_plate_faces`). ``view``: the
    viewpoint, the table plane and the scene points, cloud frame; without ``plate_test``, a
    viewpoint or a table plane, ``accepted`` as it is."""
    viewpoint, table, scene = view
    if not config.plate_test or viewpoint is None or table is None:
        return accepted
    _, first = np.unique(hoods.source, return_index=True)
    rows = first[~np.isin(hoods.source[first], hoods.source[accepted])]
    plane = np.asarray(table, dtype=np.float64) / np.linalg.norm(np.asarray(table)[:3])
    up = plane[:3]
    sight = None if scene is None else cKDTree(_voxelized(scene, config.voxel_size))
    eye = np.asarray(viewpoint, dtype=np.float64)
    plates = plate_handles(pts, tree, hoods.centers[rows], plane, eye, config, sight)
    rows = rows[plates.accepted]
    thickness = plates.widths[plates.accepted]
    found.on_axis[rows] = hoods.centers[rows]
    found.axes[rows] = plates.axes[plates.accepted]
    found.half_widths[rows] = thickness / 2
    found.kinds[rows] = "plate"
    found.coefficients[rows] = _plate_faces(up, hoods.centers[rows] @ up, thickness)
    found.centroids[rows] = hoods.centers[rows]
    with_plates = accepted.copy()
    with_plates[rows] = True
    return with_plates


def _voxelized(points: ArrayLike, voxel_size: float) -> NDArray[np.float64]:
    """``points`` (M, 3) down-sampled on the detector's voxel grid (0: as they are)."""
    points = np.asarray(points, dtype=np.float64)
    return voxel_downsample(points, voxel_size)[0] if voxel_size > 0 else points


def _plate_faces(
    up: NDArray[np.float64], levels: NDArray[np.float64], thickness: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(B, 10) coefficients of each plate's two faces, the planes ``up . x = level +- t / 2``
    (a quadric of two parallel planes: ``(up . x - level)^2 - (t / 2)^2``)."""
    quadratic = [up[0] ** 2, up[1] ** 2, up[2] ** 2, up[0] * up[1], up[0] * up[2], up[1] * up[2]]
    rows = np.empty((len(levels), 10))
    rows[:, :6] = quadratic
    rows[:, 6:9] = -levels[:, None] * up
    rows[:, 9] = levels**2 - (thickness / 2) ** 2
    return rows


def _estimate_normals(
    pts: NDArray[np.float64],
    config: QuadricDetectorConfig,
    viewpoint: ArrayLike | None,
    tree: cKDTree,
) -> NDArray[np.float64]:
    if viewpoint is None:
        return estimate_normals(pts, radius=config.normal_radius, orient="outward", tree=tree)
    return estimate_normals(
        pts, radius=config.normal_radius, orient="viewpoint", viewpoint=np.asarray(viewpoint)
    )


def _test(
    fit: QuadricFit,
    centers: NDArray[np.float64],
    tree: cKDTree,
    normals: NDArray[np.float64],
    config: QuadricDetectorConfig,
) -> tuple[NDArray[np.bool_], NDArray[np.float64], QuadricAnalysis]:
    """Apply every enabled criterion; returns (accepted mask, handle points, analysis)."""
    analysis = analyze_quadrics(
        fit.coefficients, rtol=config.kind_rtol, reference_points=fit.centroids
    )
    kinds = analysis.kinds
    handle_kind = fit.valid & np.isin(kinds, list(HANDLE_KINDS))
    axes = np.where(handle_kind[:, None], analysis.handle_axes, 0.0)
    on_axis = criteria.handle_points(kinds, analysis.centers, axes, centers)
    with np.errstate(invalid="ignore"):
        accepted = handle_kind & np.all(np.isfinite(on_axis), axis=1)
        accepted &= criteria.center_near(
            on_axis, centers, config.center_tolerance * config.gripper_max_opening / 2
        )
        accepted &= criteria.fits_gripper(
            analysis.transverse_semi_axes, config.gripper_max_opening, 0
        )
        if config.width_test:
            accepted &= criteria.fits_gripper(
                analysis.transverse_semi_axes, config.gripper_max_opening * config.width_slack, 1
            )
        if config.eccentricity_test:
            accepted &= criteria.elongated(kinds, analysis.semi_axes, config.min_elongation)
    idx = np.flatnonzero(accepted)
    if config.inside_test and len(idx):
        inside = criteria.inside_object(tree, normals, on_axis[idx], config.inside_neighbors)
        accepted[idx[~inside]] = False
        idx = idx[inside]
    if config.shell_test and len(idx):
        clear = criteria.shell_clear(
            tree,
            on_axis[idx],
            axes[idx],
            analysis.transverse_semi_axes[idx, 1],
            half_length=config.shell_half_length,
            gap=config.shell_gap,
            thickness=config.shell_thickness,
            max_fraction=config.max_shell_fraction,
        )
        accepted[idx[~clear]] = False
    return accepted, on_axis, analysis


def _normals(
    pts: NDArray[np.float64],
    given: NDArray[np.float64] | None,
    config: QuadricDetectorConfig,
    viewpoint: ArrayLike | None,
    tree: cKDTree,
) -> NDArray[np.float64]:
    """The caller's normals, or estimated ones (``own_normals``: with the caller's signs)."""
    if given is None:
        return _estimate_normals(pts, config, viewpoint, tree)
    if not config.own_normals:
        return given
    nrm = estimate_normals(pts, radius=config.normal_radius, orient="none", tree=tree)
    nrm[np.einsum("ij,ij->i", nrm, given) < 0] *= -1
    return nrm
