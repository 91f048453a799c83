"""Validation of point clouds handed to a detector: clear errors instead of deep tracebacks."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import as_normals, as_points


def validate_cloud(
    points: ArrayLike, normals: ArrayLike | None = None
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Return ``points`` (N, 3) and ``normals`` (N, 3) or None as float64 arrays: the
    perception checks (:func:`~simgrasp.perception._arrays.as_points`, ``as_normals``) plus
    unit-length normals (the detectors use them as directions, unscaled).

    Raises:
        SimgraspError: values that are not numbers, wrong shape, empty cloud, non-finite
            values, or normals that do not match the points or are not unit length.
    """
    pts = as_points(points)
    if normals is None:
        return pts, None
    nrm = as_normals(normals, pts)
    if np.any(np.abs(np.linalg.norm(nrm, axis=1) - 1) > 1e-3):
        raise SimgraspError("normals must be unit vectors")
    return pts, nrm
