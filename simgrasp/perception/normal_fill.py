"""Normals a file left out: scanner exports give the vertices that no face uses a zero normal
(ToolKinect's PLY reconstructions: half their vertices), and other tools write NaN. Each such
point gets the normal of its surface estimated from its neighbours (a plane fit over its
``FILL_NEIGHBORS`` nearest points), signed to agree with the file's normals around it; a point
whose neighbourhood is no surface (all its neighbours on one spot or one line: duplicated
vertices) takes its nearest given normal.

Meters, the cloud's frame.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

FILL_NEIGHBORS = 16
"""Points in a missing normal's plane fit (itself among them)."""
_FLAT_RATIO = 1e-6
"""A neighbourhood whose second-largest spread is below this share of its largest holds no
plane (its points lie on one spot or one line)."""


def missing_normals(normals: NDArray[np.float64]) -> NDArray[np.bool_]:
    """(N,) which of the (N, 3) ``normals`` say nothing: NaN, inf or (near) zero length."""
    length = np.linalg.norm(normals, axis=1)
    return ~np.isfinite(length) | (length < 1e-12)


def fill_missing_normals(
    points: NDArray[np.float64], normals: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(N, 3) unit ``normals`` of the (N, 3) ``points``, the missing ones
    (:func:`missing_normals`) estimated (module docstring). At least one normal must be given."""
    missing = missing_normals(normals)
    given = np.flatnonzero(~missing)
    filled = np.where(missing[:, None], 0.0, normals)
    filled[given] /= np.linalg.norm(filled[given], axis=1)[:, None]
    lost = np.flatnonzero(missing)
    if len(lost) == 0:
        return filled
    _, nearest_given = cKDTree(points[given]).query(points[lost])
    reference = filled[given[nearest_given]]
    k = min(FILL_NEIGHBORS, len(points))
    _, neighbors = cKDTree(points).query(points[lost], k=k)
    plane = _plane_normals(points[neighbors.reshape(len(lost), k)])
    flat = ~np.isfinite(plane).all(axis=1)
    plane[flat] = reference[flat]
    sign = np.where(np.einsum("ij,ij->i", plane, reference) < 0, -1.0, 1.0)
    filled[lost] = plane * sign[:, None]
    return filled


def _plane_normals(neighborhoods: NDArray[np.float64]) -> NDArray[np.float64]:
    """(M, 3) unit normals of the best planes through (M, K, 3) neighbourhoods (the direction
    of least spread); NaN rows where a neighbourhood holds no plane."""
    centered = neighborhoods - neighborhoods.mean(axis=1, keepdims=True)
    covariance = np.einsum("mki,mkj->mij", centered, centered)
    spread, axes = np.linalg.eigh(covariance)
    normals = axes[:, :, 0].copy()
    no_plane = spread[:, 1] <= _FLAT_RATIO * np.maximum(spread[:, 2], 1e-300)
    normals[no_plane] = np.nan
    return normals
