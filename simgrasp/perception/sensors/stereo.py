"""Active stereo depth camera (Intel RealSense D435 class)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from simgrasp.config.checks import Fraction, NonNegative, Positive
from simgrasp.errors import SimgraspError
from simgrasp.perception.sensors.base import (
    SensorConfig,
    checked_depth,
    drop,
    in_range,
    round_depth,
)
from simgrasp.perception.sensors.geometry import band, baseline_shadow, depth_edges, incidence_angle
from simgrasp.perception.sensors.kinect import Degrees


@dataclass(frozen=True)
class StereoConfig(SensorConfig):
    """An active infrared stereo camera like the Intel RealSense D435 (depth from the left
    imager, the right one ``baseline`` along +x, an IR pattern projector for texture).

    Sources:

    - Intel, "Intel RealSense D400 Series Product Family Datasheet" (rev. 2019+): D435
      baseline 50 mm, depth field of view 87 x 58 degrees, min-Z ~0.1 m (at 640 x 480),
      depth unit 1 mm by default.
    - Intel (A. Grunnet-Jepsen et al.), "Tuning depth cameras for best performance" and
      "Depth camera quality metrics / RMS error" white papers: ``RMS error = z^2 x subpixel /
      (focal length in px x baseline)`` with a subpixel RMS of ~0.08 px for a well-textured
      scene, focal length ``0.5 x width / tan(HFOV / 2)`` (~380 px for the D435's depth
      camera at 640 px wide); holes where the left-right check fails (pixels the right imager
      does not see), on low-texture areas (the projector's pattern fades with distance and on
      dark or shiny surfaces) and on steeply oblique surfaces; and "edge fattening": near a
      depth edge the correlation window is dominated by the foreground, so foreground depth
      spreads by about half the window onto the background.
    - The window size: the D400 ASIC matches 7 x 7 census windows (Intel D400 datasheet,
      "Stereo depth algorithm"), hence 3 px of fattening.
    """

    name: ClassVar[str] = "stereo"

    min_range: NonNegative = 0.11
    """Nearest depth returned (m; D435 min-Z at 640 x 480)."""
    max_range: Positive = 6.0
    """Farthest depth returned (m)."""
    baseline: Positive = 0.05
    """Offset of the right imager along +x (m): its occlusions give no return."""
    focal_px: Positive = 382.0
    """The sensor's own focal length (px) that its disparity noise is measured in."""
    subpixel_rms: NonNegative = 0.08
    """Standard deviation of the matched disparity (px of ``focal_px``)."""
    depth_resolution: NonNegative = 0.001
    """Unit the depth is returned in (m); 0 keeps it continuous."""
    edge_jump: NonNegative = 0.02
    """A depth step of more than this fraction of the nearer depth is a depth edge."""
    fattening_px: NonNegative = 3.0
    """Foreground depth spreads this many pixels onto the background at a depth edge (px)."""
    edge_dropout: Fraction = 0.2
    """Probability of no return for a pixel within one pixel of a depth edge."""
    oblique_start_deg: Degrees = 65.0
    """Incidence angle from which pixels start to give no return (degrees) ..."""
    oblique_end_deg: Degrees = 82.0
    """... rising linearly to no return at all from this angle (degrees)."""
    texture_window_px: NonNegative = 7.0
    """Side of the window the intensity texture is measured in (px; the matching window)."""
    texture_min: NonNegative = 0.01
    """Intensity standard deviation (intensity in [0, 1]) below which matching fails ..."""
    texture_full: Positive = 0.03
    """... rising linearly to always matching at this standard deviation."""

    def _check(self) -> None:
        self.require_below("min_range", "max_range")
        self.require_below("oblique_start_deg", "oblique_end_deg")
        self.require_below("texture_min", "texture_full")

    def axial_sigma(self, z: NDArray[np.floating]) -> NDArray[np.floating]:
        """Axial standard deviation (m) at depth ``z`` (m): Intel's RMS error formula."""
        return z**2 * self.subpixel_rms / (self.focal_px * self.baseline)

    def missing_probability(self, theta: NDArray[np.floating]) -> NDArray[np.floating]:
        """Probability of no return at incidence angle ``theta`` (rad)."""
        start, end = math.radians(self.oblique_start_deg), math.radians(self.oblique_end_deg)
        return np.clip((theta - start) / (end - start), 0.0, 1.0)

    def texture_failure(self, intensity: NDArray[np.floating]) -> NDArray[np.floating]:
        """Probability that matching fails, from the local standard deviation of
        ``intensity`` (H, W, in [0, 1]) over the matching window."""
        size = max(round(self.texture_window_px), 1)
        mean = ndimage.uniform_filter(intensity, size)
        spread = np.sqrt(np.maximum(ndimage.uniform_filter(intensity**2, size) - mean**2, 0.0))
        ramp = (self.texture_full - spread) / (self.texture_full - self.texture_min)
        return np.clip(ramp, 0.0, 1.0)


def fatten_edges(z: NDArray[np.floating], width_px: int, edge_jump: float) -> NDArray[np.floating]:
    """Background pixels within ``width_px`` columns of a nearer surface take its depth (the
    matching window straddles the edge along the epipolar line, the image row)."""
    if width_px <= 0:
        return z
    near = ndimage.minimum_filter1d(np.where(z > 0.0, z, np.inf), 2 * width_px + 1, axis=1)
    fattened = np.isfinite(near) & ((z <= 0.0) | (z - near > edge_jump * near))
    return np.where(fattened, near, z).astype(z.dtype)


def disparity_noise(
    z: NDArray[np.floating], config: StereoConfig, rng: np.random.Generator
) -> NDArray[np.floating]:
    """Gaussian noise on the disparity ``focal_px x baseline / z`` (``subpixel_rms`` px)."""
    scale = config.focal_px * config.baseline
    with np.errstate(divide="ignore"):
        disparity = scale / z
    noise = rng.standard_normal(z.shape, dtype=np.float32)
    noise *= config.subpixel_rms
    disparity += noise
    valid = (z > 0.0) & (disparity > 0.0)
    return np.where(valid, scale / np.maximum(disparity, 1e-9), 0.0).astype(z.dtype)


def stereo(
    z: NDArray[np.floating],
    K: NDArray[np.floating],
    config: StereoConfig,
    rng: np.random.Generator,
    intensity: NDArray[np.floating] | None = None,
) -> NDArray[np.floating]:
    """The depth an active stereo camera returns for the true depth ``z`` (m, 0 = none).

    Order: edge fattening, disparity noise, depth unit, then no return out of range, where
    the right imager is occluded, at oblique incidence, along depth edges (randomly) and,
    given an ``intensity`` image (H, W, in [0, 1]), on low texture. Without one, every surface
    counts as textured (the projector's pattern).
    """
    theta = incidence_angle(z, K)
    edges = depth_edges(z, config.edge_jump)
    occluded = baseline_shadow(z, K, config.baseline)
    out = fatten_edges(z, round(config.fattening_px), config.edge_jump)
    out = disparity_noise(out, config, rng)
    round_depth(out, config.depth_resolution)
    in_range(out, config.min_range, config.max_range)
    out[occluded] = 0.0
    drop(out, config.missing_probability(theta), rng)
    drop(out, np.where(band(edges, 1), np.float32(config.edge_dropout), np.float32(0.0)), rng)
    if intensity is not None:
        drop(out, config.texture_failure(intensity), rng)
    return out


def apply_stereo(
    depth: ArrayLike,
    K: ArrayLike,
    config: StereoConfig,
    rng: np.random.Generator,
    intensity: ArrayLike | None = None,
) -> NDArray[np.floating]:
    """:func:`stereo` on a checked depth image (and ``intensity``), in its dtype."""
    z, K = checked_depth(depth, K)
    texture = _checked_intensity(intensity, z.shape)
    return stereo(z, K, config, rng, texture).astype(np.asarray(depth).dtype)


def _checked_intensity(
    intensity: ArrayLike | None, shape: tuple[int, ...]
) -> NDArray[np.float64] | None:
    if intensity is None:
        return None
    image = np.asarray(intensity, dtype=np.float64)
    if image.shape != shape or not np.all(np.isfinite(image)):
        raise SimgraspError(f"intensity must be a finite image of shape {shape}, got {image.shape}")
    return image
