"""Validation of point clouds handed to a detector: clear errors instead of deep tracebacks."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError


def validate_cloud(
    points: ArrayLike, normals: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Return ``points`` (N, 3) and ``normals`` (N, 3) or None as float64 arrays.

    Raises:
        ValueError: values that are not numbers, wrong shape, empty cloud, non-finite values,
            or normals that do not match the points or are not unit length.
    """
    pts = _numbers(points, "points")
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
    nrm = _numbers(normals, "normals")
    if nrm.shape != pts.shape:
        raise SimgraspError(f"normals must match points {pts.shape}, got shape {nrm.shape}")
    lengths = np.linalg.norm(nrm, axis=1)
    if not np.all(np.isfinite(lengths)) or np.any(np.abs(lengths - 1) > 1e-3):
        raise SimgraspError("normals must be finite unit vectors")
    return pts, nrm


def _numbers(values: ArrayLike, name: str) -> NDArray[np.float64]:
    """``values`` as a float array; text (a file name, say) or ragged lists are a
    :class:`SimgraspError` naming argument ``name``."""
    if not isinstance(values, str | bytes):
        try:
            return np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError):
            pass
    raise SimgraspError(f"{name} must be an (N, 3) array of numbers, got {type(values).__name__}")
