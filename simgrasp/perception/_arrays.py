"""Input checks shared by the perception functions: clear errors instead of numpy tracebacks."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from simgrasp.errors import SimgraspError


def float_array(values: object, name: str, expected: str) -> NDArray[np.float64]:
    """``values`` as a float64 array; text (a file name, say), ragged lists and other values
    that are not numbers are a :class:`SimgraspError` naming argument ``name`` and what it
    must be (``expected``: ``"an (N, 3) array of numbers"``)."""
    if not isinstance(values, str | bytes):
        try:
            return np.asarray(values, dtype=np.float64)
        except (TypeError, ValueError):
            pass
    raise SimgraspError(f"{name} must be {expected}, got {type(values).__name__}")


def as_points(points: ArrayLike, name: str = "points") -> NDArray[np.float64]:
    """Return ``points`` as a finite, non-empty (N, 3) float64 array or raise ``ValueError``."""
    array = float_array(points, name, "an (N, 3) array of numbers")
    if array.ndim != 2 or array.shape[1] != 3:
        raise SimgraspError(f"{name} must be an (N, 3) array, got shape {array.shape}")
    if len(array) == 0:
        raise SimgraspError(f"{name} is empty")
    bad = ~np.isfinite(array).all(axis=1)
    if bad.any():
        raise SimgraspError(f"{name} has {int(bad.sum())} of {len(array)} rows with NaN or inf")
    return array


def as_normals(
    normals: ArrayLike, points: NDArray[np.float64], name: str = "normals"
) -> NDArray[np.float64]:
    """Return ``normals`` as a finite (N, 3) float64 array matching ``points``."""
    array = float_array(normals, name, "an (N, 3) array of numbers")
    if array.shape != points.shape:
        raise SimgraspError(
            f"{name} must match the points' shape {points.shape}, got {array.shape}"
        )
    bad = ~np.isfinite(array).all(axis=1)
    if bad.any():
        raise SimgraspError(f"{name} has {int(bad.sum())} of {len(array)} rows with NaN or inf")
    return array


def kd_tree(points: NDArray[np.float64], tree: cKDTree | None = None) -> cKDTree:
    """``tree`` (a caller's ``cKDTree`` of ``points``, checked to hold as many 3-D points) or,
    when None, a new ``cKDTree`` of ``points``."""
    if tree is None:
        return cKDTree(points)
    if tree.n != len(points) or tree.m != 3:
        raise SimgraspError(f"tree holds {tree.n} points of dimension {tree.m}, not the cloud's")
    return tree


def positive(value: float, name: str) -> float:
    """Return ``value`` as a float if it is a finite positive number, else raise ``ValueError``."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise SimgraspError(f"{name} must be a positive number, got {value!r}")
    if not (np.isfinite(value) and value > 0):
        raise SimgraspError(f"{name} must be a finite positive number, got {value!r}")
    return float(value)


def import_open3d():  # noqa: ANN201
    """The ``open3d`` module, imported on first use rather than with simgrasp (about 1 s)."""
    import open3d

    return open3d


def to_open3d(points: NDArray[np.float64], normals: NDArray[np.float64] | None = None):  # noqa: ANN201
    """Wrap arrays in an ``open3d.geometry.PointCloud``."""
    o3d = import_open3d()
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    if normals is not None:
        cloud.normals = o3d.utility.Vector3dVector(normals)
    return cloud
