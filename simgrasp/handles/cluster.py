"""Cluster accepted candidates into handle hypotheses (single linkage on handle points), score
them and keep the plausible ones."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.cluster.hierarchy import fcluster, linkage

from simgrasp.handles.detection import Handle


def cluster_handles(
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    widths: NDArray[np.float64],
    *,
    distance: float,
    min_support: int,
    object_center: NDArray[np.float64] | None = None,
    centrality_length: float | None = None,
    centrality_to_stretch: bool = False,
    max_opening: float | None = None,
    min_relative_score: float = 0.0,
    anchors: NDArray[np.float64] | None = None,
) -> tuple[tuple[Handle, ...], tuple[NDArray[np.int64], ...]]:
    """Group candidates whose handle points chain within ``distance`` (m) into handles.

    Args:
        handle_points: (M, 3) points on each candidate's handle axis (cloud frame, m).
        axes: (M, 3) unit handle directions (sign arbitrary).
        widths: (M,) grasp widths (m).
        distance: single-linkage cut distance (m).
        min_support: clusters with fewer candidates are dropped.
        object_center, centrality_length: the cloud's centroid and a length (m). When given,
            a handle's score is weighted by its centrality exp(-(d / length)^2), d the distance
            from the centroid to the handle's center (with ``centrality_to_stretch``: to the
            nearest point of its covered stretch, :func:`_span_distance`).
        max_opening: the gripper's maximum opening (m). When given, a handle's score is
            weighted by its jaw clearance min(1, (max_opening - width) / (max_opening / 2)):
            a part barely narrower than the open jaws (a mug's body) leaves no room for pose
            error, a handle half the opening or narrower is not penalized.
        min_relative_score: handles scoring below this fraction of the best are dropped.
        anchors: (M, 3) points to take the handle centers from instead of ``handle_points``
            (the candidates' seen surface points); the clustering still joins handle points.

    Returns:
        Handles sorted by decreasing score, and for each the indices of its candidates. A
        handle's axis is the dominant direction of its candidates' axes (sign-free), its
        center the candidate point nearest the cluster's median, its score its share of all
        candidates times that direction's coherence (mean squared cosine) times centrality.
    """
    count = len(handle_points)
    if count == 0:
        return (), ()
    labels = (
        np.ones(1, dtype=int)
        if count == 1
        else fcluster(linkage(handle_points, method="single"), t=distance, criterion="distance")
    )
    found = []
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        if len(members) < min_support:
            continue
        centers = handle_points if anchors is None else anchors
        handle = _handle_from_members(centers[members], axes[members], widths[members], count)
        weighted = _weighted(
            handle, object_center, centrality_length, centrality_to_stretch, max_opening
        )
        found.append((weighted, members))
    return best_first(found, min_relative_score)


def best_first(
    found: list[tuple[Handle, NDArray[np.int64]]], min_relative_score: float
) -> tuple[tuple[Handle, ...], tuple[NDArray[np.int64], ...]]:
    """The handles scoring at least ``min_relative_score`` of the best, best first, with
    their member indices."""
    if not found:
        return (), ()
    best = max(h.score for h, _ in found)
    kept = sorted(
        ((h, m) for h, m in found if h.score >= min_relative_score * best),
        key=lambda x: -x[0].score,
    )
    return tuple(h for h, _ in kept), tuple(m for _, m in kept)


def _weighted(
    handle: Handle,
    object_center: NDArray[np.float64] | None,
    centrality_length: float | None,
    to_stretch: bool,
    max_opening: float | None,
) -> Handle:
    """``handle`` with its score weighted by centrality and jaw clearance, each when its
    parameters are given (see :func:`cluster_handles`)."""
    if object_center is not None and centrality_length:
        offset = (
            _span_distance(handle, object_center)
            if to_stretch
            else float(np.linalg.norm(handle.center - object_center))
        ) / centrality_length
        handle = _rescored(handle, handle.score * float(np.exp(-(offset**2))))
    if max_opening:
        clearance = np.clip((max_opening - handle.width) / (max_opening / 2), 0.0, 1.0)
        handle = _rescored(handle, handle.score * float(clearance))
    return handle


def _span_distance(handle: Handle, point: NDArray[np.float64]) -> float:
    """Distance (m) from ``point`` to the nearest point of the stretch of the handle's axis its
    candidates cover (``handle.span`` around ``handle.center``): the planner grasps a handle
    there too (the point nearest the cloud's centroid), so that is the grasp's lever arm. A
    pan's long handle, its center 15 cm from the centroid, ranked below arcs of its thin rim
    with a twentieth of its support when scored by its center's distance."""
    along = float(np.clip((point - handle.center) @ handle.axis, *handle.span))
    return float(np.linalg.norm(handle.center + along * handle.axis - point))


def _rescored(handle: Handle, score: float) -> Handle:
    return Handle(handle.center, handle.axis, handle.width, score, handle.support, handle.span)


def _handle_from_members(
    points: NDArray[np.float64], axes: NDArray[np.float64], widths: NDArray[np.float64], total: int
) -> Handle:
    scatter = axes.T @ axes / len(axes)
    eigenvalues, eigenvectors = np.linalg.eigh(scatter)
    axis = eigenvectors[:, -1]
    axis = axis if axis[np.argmax(np.abs(axis))] > 0 else -axis
    coherence = float(eigenvalues[-1])
    median = np.median(points, axis=0)
    center = points[np.argmin(np.linalg.norm(points - median, axis=1))]
    along = (points - center) @ axis
    return Handle(
        center=center.copy(),
        axis=axis,
        width=float(np.median(widths)),
        score=float(len(points) / total * coherence),
        support=len(points),
        span=(float(along.min()), float(along.max())),
    )
