"""Point-cloud noise models: the paper's multiplicative noise and a Kinect-like depth camera.

Depth-camera model (Nguyen, Izadi & Lovell, "Modeling Kinect sensor noise for improved 3D
reconstruction and tracking", 3DIMPVT 2012), in the camera frame (OpenCV: +z forward, meters):

- axial (depth) noise, standard deviation ``sigma_z(z) = a + b (z - c)^2`` with the paper's
  fit a = 0.0012 m, b = 0.0019 m^-1, c = 0.4 m (surfaces seen at 10-60 degrees). It is applied
  along each point's viewing ray, so the point stays on its pixel: ``p' = p z'/z``.
- lateral noise, standard deviation ``sigma_L(z) = k z`` on x and y; the paper's ~0.8 pixel
  at a focal length of ~585 pixels gives k = 0.8 / 585 = 1.37e-3.
- dropout: exactly ``round(dropout N)`` points, chosen uniformly, are removed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.config.checks import Checked, NonNegative, Range
from simgrasp.errors import SimgraspError
from simgrasp.perception._arrays import as_points


def multiplicative_noise(
    points: ArrayLike, sigma: float, rng: np.random.Generator
) -> NDArray[np.float64]:
    """The paper's noise: every point is multiplied by its own factor ~ N(1, sigma).

    The scaling is about the origin of the points' frame, so a point moves along the line
    through the origin by ``(factor - 1) x`` its distance to it: centre the cloud first (e.g.
    subtract the centroid) for noise proportional to object size.

    Args:
        points: (N, 3) meters. sigma: standard deviation of the factor (>= 0).
        rng: the seeded generator of the factors.
    """
    pts = as_points(points)
    if not (isinstance(sigma, int | float | np.number) and np.isfinite(sigma) and sigma >= 0):
        raise SimgraspError(f"sigma must be a finite number >= 0, got {sigma!r}")
    factor = rng.normal(1.0, float(sigma), size=(len(pts), 1))
    return pts * factor


@dataclass(frozen=True)
class DepthNoiseConfig(Checked):
    """Parameters of :func:`depth_camera_noise` (meters; defaults: module docstring)."""

    axial_a: NonNegative = 0.0012
    """Constant term of the axial standard deviation (m)."""
    axial_b: NonNegative = 0.0019
    """Quadratic coefficient of the axial standard deviation (1/m)."""
    axial_c: NonNegative = 0.4
    """Depth of the minimum axial noise (m)."""
    lateral_per_meter: NonNegative = 0.8 / 585.0
    """Lateral standard deviation per meter of depth (unitless)."""
    dropout: Annotated[float, Range(ge=0, lt=1)] = 0.0
    """Fraction of points removed, in [0, 1)."""

    def axial_sigma(self, z: ArrayLike) -> NDArray[np.float64]:
        """Axial standard deviation (m) at depth ``z`` (m)."""
        depth = np.asarray(z, dtype=np.float64)
        return self.axial_a + self.axial_b * (depth - self.axial_c) ** 2

    def lateral_sigma(self, z: ArrayLike) -> NDArray[np.float64]:
        """Lateral standard deviation (m) at depth ``z`` (m)."""
        return self.lateral_per_meter * np.asarray(z, dtype=np.float64)


def depth_camera_noise(
    points_cam: ArrayLike, rng: np.random.Generator, config: DepthNoiseConfig | None = None
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Apply depth-camera noise to a camera-frame cloud (OpenCV frame, +z forward, meters).

    Returns:
        ``(noisy_points_cam, kept)``: the (M, 3) noisy points that survive dropout and their
        (M,) indices into the input, increasing, so per-point labels can follow them.
    """
    config = config or DepthNoiseConfig()
    pts = as_points(points_cam, "points_cam")
    z = pts[:, 2]
    if (z <= 0).any():
        raise SimgraspError(
            f"points_cam has {int((z <= 0).sum())} points at z <= 0 (behind the camera); "
            "depth noise needs points in front of it (OpenCV frame, +z forward)"
        )
    noisy_z = z + rng.normal(size=len(pts)) * config.axial_sigma(z)
    noisy = pts * (noisy_z / z)[:, None]
    noisy[:, :2] += rng.normal(size=(len(pts), 2)) * config.lateral_sigma(z)[:, None]
    dropped = rng.choice(len(pts), size=round(config.dropout * len(pts)), replace=False)
    kept = np.setdiff1d(np.arange(len(pts)), dropped).astype(np.int64)
    return noisy[kept], kept
