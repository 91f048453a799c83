"""Cluster accepted candidates into handle hypotheses (single linkage on handle points)."""

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
) -> tuple[Handle, ...]:
    """Group candidates whose handle points chain within ``distance`` (m) into handles.

    Args:
        handle_points: (M, 3) points on each candidate's handle axis (cloud frame, m).
        axes: (M, 3) unit handle directions (sign arbitrary).
        widths: (M,) grasp widths (m).
        distance: single-linkage cut distance (m).
        min_support: clusters with fewer candidates are dropped.

    Returns:
        Handles sorted by decreasing score. A handle's axis is the dominant direction of its
        candidates' axes (sign-free), its ``score`` is its share of all candidates times that
        direction's coherence (mean squared cosine), its center the candidate point nearest
        the cluster's median.
    """
    count = len(handle_points)
    if count == 0:
        return ()
    labels = (
        np.ones(1, dtype=int)
        if count == 1
        else fcluster(linkage(handle_points, method="single"), t=distance, criterion="distance")
    )
    handles = []
    for label in np.unique(labels):
        members = np.flatnonzero(labels == label)
        if len(members) < min_support:
            continue
        handles.append(
            _handle_from_members(handle_points[members], axes[members], widths[members], count)
        )
    return tuple(sorted(handles, key=lambda h: -h.score))


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
        extent=float(max(along.max(), -along.min())),
    )
