"""Cluster accepted candidates into handle hypotheses (single linkage on handle points), score
them and keep the plausible ones."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray
from scipy.cluster.hierarchy import fcluster, linkage

from simgrasp.handles.core.config import CentralityMeasure
from simgrasp.handles.core.detection import Handle


@dataclass(frozen=True)
class Ranked:
    """A handle hypothesis, the indices of its candidates and its guard score.

    ``handle.score`` ranks it. ``guard`` is its score with the centrality measured to the
    handle's center: a handle other than the best must keep within the relative score cut by
    both (:func:`best_first`); with the ``"center"`` measure ``guard`` equals the score.
    """

    handle: Handle
    members: NDArray[np.int64]
    guard: float

    def scaled(self, factor: float, offset: int = 0) -> Ranked:
        """Both scores times ``factor``, the member indices shifted by ``offset``."""
        handle = _rescored(self.handle, self.handle.score * factor)
        return Ranked(handle, self.members + offset, self.guard * factor)


def cluster_handles(
    handle_points: NDArray[np.float64],
    axes: NDArray[np.float64],
    widths: NDArray[np.float64],
    *,
    distance: float,
    min_support: int,
    object_center: NDArray[np.float64] | None = None,
    centrality_length: float | None = None,
    centrality_measure: CentralityMeasure = "center",
    max_opening: float | None = None,
    min_relative_score: float = 0.0,
    anchors: NDArray[np.float64] | None = None,
) -> list[Ranked]:
    """Group candidates whose handle points chain within ``distance`` (m) into handles.

    Args:
        handle_points: (M, 3) points on each candidate's handle axis (cloud frame, m).
        axes: (M, 3) unit handle directions (sign arbitrary).
        widths: (M,) grasp widths (m).
        distance: single-linkage cut distance (m).
        min_support: clusters with fewer candidates are dropped.
        object_center, centrality_length: the cloud's centroid and a length (m). When given,
            a handle's score is weighted by its centrality exp(-(d / length)^2), d the lever
            arm from the centroid to the handle by ``centrality_measure``
            (:func:`_lever_arm_sq`).
        max_opening: the gripper's maximum opening (m). When given, a handle's score is
            weighted by its jaw clearance min(1, (max_opening - width) / (max_opening / 2)):
            a part barely narrower than the open jaws (a mug's body) ranks low.
        min_relative_score: the relative score cut of :func:`best_first` (0: keep all).
        anchors: (M, 3) points to take the handle centers from instead of ``handle_points``
            (the candidates' seen surface points); the clustering still joins handle points.

    Returns:
        The kept handles (:class:`Ranked`: each with its candidates' indices), best first. A
        handle's axis is the dominant direction of its candidates' axes (sign-free), its
        center the candidate point nearest the cluster's median, its score its share of all
        candidates times that direction's coherence (mean squared cosine) times centrality.
    """
    count = len(handle_points)
    if count == 0:
        return []
    labels = (
        np.ones(1, dtype=int)
        if count == 1
        else fcluster(linkage(handle_points, method="single"), t=distance, criterion="distance")
    )
    centers = handle_points if anchors is None else anchors
    found = []
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        if len(members) < min_support:
            continue
        handle = _handle_from_members(centers[members], axes[members], widths[members], count)
        weighted = _weighted(
            handle, object_center, centrality_length, centrality_measure, max_opening
        )
        guard = _weighted(handle, object_center, centrality_length, "center", max_opening).score
        found.append(Ranked(weighted, members, guard))
    return best_first(found, min_relative_score)


def best_first(found: list[Ranked], min_relative_score: float) -> list[Ranked]:
    """The best handle and those scoring at least ``min_relative_score`` of the best both by
    score and by guard score (:class:`Ranked`), best first. With the stretch centrality a
    power drill's barrel, whose stretch passes near the centroid, came within the cut of its
    grip (0.76 of its score) but its center lies far off (0.26 of the grip's guard score)."""
    if not found:
        return []
    ordered = sorted(found, key=lambda r: -r.handle.score)
    best = ordered[0].handle.score
    best_guard = max(r.guard for r in found)
    return ordered[:1] + [
        r
        for r in ordered[1:]
        if r.handle.score >= min_relative_score * best
        and r.guard >= min_relative_score * best_guard
    ]


def _weighted(
    handle: Handle,
    object_center: NDArray[np.float64] | None,
    centrality_length: float | None,
    measure: CentralityMeasure,
    max_opening: float | None,
) -> Handle:
    """``handle`` with its score weighted by centrality and jaw clearance, each when its
    parameters are given (see :func:`cluster_handles`)."""
    if object_center is not None and centrality_length:
        offset_sq = _lever_arm_sq(handle, object_center, measure) / centrality_length**2
        handle = _rescored(handle, handle.score * float(np.exp(-offset_sq)))
    if max_opening:
        clearance = np.clip((max_opening - handle.width) / (max_opening / 2), 0.0, 1.0)
        handle = _rescored(handle, handle.score * float(clearance))
    return handle


def _lever_arm_sq(handle: Handle, point: NDArray[np.float64], measure: CentralityMeasure) -> float:
    """The squared lever arm (m^2) from ``point`` (the centroid) to the handle by
    ``measure``: to its center, to the nearest point of its covered stretch, or the mean of
    the two squares (``"grasps"``: the planner's two grasp points on it)."""
    to_center = float(np.sum((handle.center - point) ** 2))
    if measure == "center":
        return to_center
    to_stretch = _span_distance(handle, point) ** 2
    return to_stretch if measure == "stretch" else (to_center + to_stretch) / 2


def _span_distance(handle: Handle, point: NDArray[np.float64]) -> float:
    """Distance (m) from ``point`` to the nearest point of the stretch of the handle's axis its
    candidates cover (``handle.span`` around ``handle.center``): the planner grasps a handle
    there too (the point nearest the cloud's centroid), so that is the grasp's lever arm. A
    pan's long handle, its center 15 cm from the centroid, ranked below arcs of its thin rim
    with a twentieth of its support when scored by its center's distance."""
    along = float(np.clip((point - handle.center) @ handle.axis, *handle.span))
    return float(np.linalg.norm(handle.center + along * handle.axis - point))


def _rescored(handle: Handle, score: float) -> Handle:
    return replace(handle, score=score)


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
        trace=points.copy(),
        trace_axes=axes.copy(),
    )
