"""What every depth sensor model shares: its config base class, input checks, random dropout.

A sensor model maps a rendered depth image (H x W meters along the optical axis, 0 = no hit,
OpenCV pinhole intrinsics ``K``) to the image that sensor would return, with 0 for every pixel
it returns no depth for. Every random draw comes from the caller's ``np.random.Generator``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError


@dataclass(frozen=True)
class SensorConfig(Checked):
    """Base of every sensor model's frozen parameter set; ``name`` keys it in the sensor
    registry (:mod:`simgrasp.perception.sensors.registry`).

    Subclasses declare their fields' ranges in their types (:mod:`simgrasp.config.checks`)
    and checks between fields in ``_check``.
    """

    name: ClassVar[str] = ""


def checked_depth(depth: ArrayLike, K: ArrayLike) -> tuple[NDArray[np.float32], NDArray]:
    """Validate a depth image and its camera matrix.

    Returns:
        ``(z, K)``: the depth as an (H, W) float32 copy (the models compute in float32) with
        every no-return pixel (0, NaN, inf, negative) set to 0, and ``K`` as a 3x3 float64
        array.

    Raises:
        ValueError: depth not a 2-D real image, or K not a finite 3x3 pinhole matrix with
            positive focal lengths.
    """
    depth = np.asarray(depth)
    if depth.ndim != 2 or min(depth.shape, default=0) == 0:
        raise SimgraspError(f"depth must be an (H, W) image, got shape {depth.shape}")
    if not np.issubdtype(depth.dtype, np.floating):
        raise SimgraspError(f"depth must be a float image in meters, got dtype {depth.dtype}")
    K = np.asarray(K, dtype=np.float64)
    if K.shape != (3, 3) or not np.all(np.isfinite(K)):
        raise SimgraspError(f"K must be a finite 3x3 camera matrix, got {K.tolist()}")
    if K[0, 0] <= 0 or K[1, 1] <= 0 or K[2, 2] != 1.0:
        raise SimgraspError(f"K must have positive fx, fy and K[2, 2] = 1, got {K.tolist()}")
    z = depth.astype(np.float32)
    with np.errstate(invalid="ignore"):
        z[~(np.isfinite(z) & (z > 0.0))] = 0.0
    return z, K


def drop(
    z: NDArray[np.floating], probability: NDArray[np.floating], rng: np.random.Generator
) -> None:
    """Set each pixel of ``z`` to 0 (no return) with its own ``probability`` (an (H, W)
    image), in place. One uniform number is drawn per pixel of positive probability."""
    rows, cols = np.nonzero(probability > 0.0)
    drop_at(z, (rows, cols), probability[rows, cols], rng)


def drop_at(
    z: NDArray[np.floating],
    pixels: tuple[NDArray[np.intp], ...],
    probability: NDArray[np.floating],
    rng: np.random.Generator,
) -> None:
    """Set each of the ``pixels`` (rows, columns) of ``z`` to 0 with its own ``probability``,
    in place; draws one uniform number per pixel."""
    rows, cols = pixels
    dropped = rng.random(rows.size, dtype=np.float32) < probability
    z[rows[dropped], cols[dropped]] = 0.0


def in_range(z: NDArray[np.floating], min_range: float, max_range: float) -> None:
    """Set depths outside ``[min_range, max_range]`` (m) to 0, in place."""
    z[(z < min_range) | (z > max_range)] = 0.0


def round_depth(z: NDArray[np.floating], resolution: float) -> None:
    """Round depths to multiples of ``resolution`` (m; a sensor's depth unit), in place (0
    stays 0, nothing returns less than one unit); ``resolution`` 0 keeps them."""
    if resolution > 0.0:
        zero = z <= 0.0
        z *= 1.0 / resolution
        np.rint(z, out=z)
        np.maximum(z, 1.0, out=z)
        z *= resolution
        z[zero] = 0.0
