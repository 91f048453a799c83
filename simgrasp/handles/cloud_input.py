"""Validation of point clouds handed to a detector: clear errors instead of deep tracebacks."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import float_array


def validate_cloud(
    points: ArrayLike, normals: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Return ``points`` (N, 3) and ``normals`` (N, 3) or None as float64 arrays.

    Raises:
        ValueError: values that are not numbers, wrong shape, empty cloud, non-finite values,
            or normals that do not match the points or are not unit length.
    """
    pts = float_array(points, "points", "an (N, 3) array of numbers")
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise SimgraspError(f"points must be an (N, 3) array, got shape {pts.shape}")
    if len(pts) == 0:
        raise SimgraspError("the point cloud is empty")
    bad = ~np.all(np.isfinite(pts), axis=1)
    if bad.any():
        raise SimgraspError(
            f"the point cloud has {int(bad.sum())} of {len(pts)} points with NaN or inf "
            "coordinates; drop them before detection"
        )
    if normals is None:
        return pts, None
    nrm = float_array(normals, "normals", "an (N, 3) array of numbers")
    if nrm.shape != pts.shape:
        raise SimgraspError(f"normals must match points {pts.shape}, got shape {nrm.shape}")
    lengths = np.linalg.norm(nrm, axis=1)
    if not np.all(np.isfinite(lengths)) or np.any(np.abs(lengths - 1) > 1e-3):
        raise SimgraspError("normals must be finite unit vectors")
    return pts, nrm
