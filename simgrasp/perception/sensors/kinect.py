"""Structured-light depth camera (Microsoft Kinect v1 / PrimeSense class)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.config.checks import Fraction, NonNegative, Positive, Range
from simgrasp.perception.sensors.base import (
    SensorConfig,
    checked_depth,
    drop,
    drop_at,
    in_range,
    round_depth,
)
from simgrasp.perception.sensors.edges import flying_pixels, lateral_jitter
from simgrasp.perception.sensors.geometry import (
    band,
    baseline_shadow,
    depth_edges,
    incidence_angle,
    open_rows,
)

Degrees = Annotated[float, Range(ge=0, le=90)]
"""An incidence angle in [0, 90] degrees."""


@dataclass(frozen=True)
class KinectConfig(SensorConfig):
    """A Kinect-v1-class structured-light camera (PrimeSense: IR projector + IR camera).

    Sources:

    - Axial and lateral noise: C. V. Nguyen, S. Izadi, D. Lovell, "Modeling Kinect sensor noise
      for improved 3D reconstruction and tracking", 3DIMPVT 2012: ``sigma_z(z, theta) =
      a + b (z - c)^2 + (d / sqrt(z)) theta^2 / (pi/2 - theta)^2`` (theta the angle between
      viewing ray and surface normal) with a = 1.2 mm, b = 1.9 mm/m^2, c = 0.4 m,
      d = 0.1 mm m^0.5, and lateral ``sigma_L = 0.8 + 0.035 theta / (pi/2 - theta)`` pixels
      at their camera's 585 px focal length, i.e. an angle of 0.8 / 585 rad.
    - Disparity quantization: K. Khoshelham, S. O. Elberink, "Accuracy and resolution of
      Kinect depth data for indoor mapping applications", Sensors 12(2), 2012: the depth
      comes from a disparity measured in 1/8 pixel, ``1/z = c0 + c1 d`` with
      ``c1 = -2.85e-3 /m`` per disparity unit, so depth steps grow as ``2.85e-3 z^2``
      (7 cm at 5 m); range 0.5 - 5 m; projector-camera baseline ~7.5 cm.
    - Depth unit: OpenNI returns integer millimeters (the osd-learn clouds hold millimeter
      multiples, in 2.85e-3 /m steps of inverse depth: checked there).
    - Calibrated on osd-learn (45 real scans, Richtsfeld et al., IROS 2012;
      ``scripts/calibrate_sensor.py``, ``docs/results/sensor-calibration/``) by a grid over
      the fields marked "fitted": the table's 5 cm plane-fit residual is 0.88 - 1.39 mm from
      0.6 to 1.6 m, below Nguyen et al.'s per-pixel axial noise plus quantization (their
      model gives +24 to +48 %), hence the smaller a and b; the invalid pixels around object
      silhouettes are the projector's and the IR camera's shadows (with depth registered to
      the RGB camera), less the narrow ones. Flying pixels, the lateral noise and the grazing
      ramp are not constrained by these two measurements (Nguyen et al.'s values and guesses).
    """

    name: ClassVar[str] = "kinect"

    min_range: NonNegative = 0.4
    """Nearest depth returned (m); nearer surfaces give no return."""
    max_range: Positive = 4.5
    """Farthest depth returned (m)."""
    axial_a: NonNegative = 0.0008
    """Constant term a of the axial standard deviation (m; fitted on osd-learn, Nguyen et
    al.'s 1.2 mm over-predicts the table residual)."""
    axial_b: NonNegative = 0.0013
    """Quadratic coefficient b of the axial standard deviation (m per m^2; fitted on
    osd-learn; Nguyen et al.: 1.9 mm/m^2)."""
    axial_c: NonNegative = 0.4
    """Depth c of the least axial noise (m; Nguyen et al.)."""
    axial_angle: NonNegative = 0.0001
    """Coefficient d of the incidence-angle term of the axial noise (m^1.5; Nguyen et al.)."""
    lateral_rad: NonNegative = 0.8 / 585.0
    """Lateral standard deviation at normal incidence as an angle (rad): times fx gives pixels
    (Nguyen et al.: 0.8 px at 585 px)."""
    lateral_angle_rad: NonNegative = 0.035 / 585.0
    """Coefficient of theta / (pi/2 - theta) in the lateral standard deviation (rad)."""
    inverse_depth_step: NonNegative = 2.85e-3
    """Quantization step of 1/z (1/m): one 1/8-pixel disparity unit (Khoshelham & Elberink)."""
    depth_resolution: NonNegative = 0.001
    """Unit the depth is returned in (m): OpenNI's millimeters; 0 keeps it continuous."""
    projector_baseline: NonNegative = 0.075
    """Offset of the projector from the IR camera along +x (m; Khoshelham & Elberink):
    pixels it cannot light give no return."""
    registration_offset: NonNegative = 0.025
    """Offset of the IR camera from the camera the depth is returned in, along -x (m): 0 for
    depth in the IR camera's own frame; OpenNI registers depth to the RGB camera, 2.5 cm from
    the IR camera toward the projector (osd-learn's K is OpenNI's RGB default, fx = 525 px).
    Pixels the IR camera does not see give no return."""
    min_shadow_px: NonNegative = 5.0
    """Shadowed runs along an image row narrower than this are filled: the matching window
    bridges them (px; fitted on osd-learn, where the narrow shadows behind low steps hold
    depth: without it the simulated invalid share is +38 % at 0.8 - 1.0 m)."""
    edge_jump: NonNegative = 0.02
    """A depth step of more than this fraction of the nearer depth between neighboring pixels
    is a depth edge (unitless)."""
    edge_jitter_px: NonNegative = 2.0
    """Pixels within this many pixels of a depth edge get the lateral noise (px); on smooth
    surfaces the sensor's lateral error is part of the axial one (Nguyen et al.)."""
    flying_probability: Fraction = 0.05
    """Probability that an edge pixel floats between foreground and background depth (a
    guess: Kinect v1 interpolates few; not measured by the calibration)."""
    edge_dropout: Fraction = 0.0
    """Probability of no return for a pixel within ``edge_dropout_px`` of a depth edge
    (fitted on osd-learn: the shadows alone explain the invalid pixels around silhouettes;
    0.01 already gives +21 % at 0.8 - 1.0 m)."""
    edge_dropout_px: NonNegative = 2.0
    """Width of the edge-dropout band (px)."""
    grazing_start_deg: Degrees = 70.0
    """Incidence angle from which pixels start to give no return (degrees) ..."""
    grazing_end_deg: Degrees = 85.0
    """... rising linearly to no return at all from this angle (degrees)."""

    def _check(self) -> None:
        self.require_below("min_range", "max_range")
        self.require_below("grazing_start_deg", "grazing_end_deg")

    def axial_sigma(self, z: NDArray[np.floating], theta: NDArray[np.floating]) -> NDArray:
        """Axial standard deviation (m) at depth ``z`` (m) and incidence angle ``theta``
        (rad, below pi/2)."""
        slope = theta / (math.pi / 2 - theta)
        slope *= slope
        with np.errstate(divide="ignore", invalid="ignore"):
            slope *= self.axial_angle / np.sqrt(z)
        offset = z - self.axial_c
        offset *= offset
        offset *= self.axial_b
        slope += offset
        slope += self.axial_a
        return slope

    def lateral_sigma_px(self, fx: float, theta: NDArray[np.floating]) -> NDArray[np.floating]:
        """Lateral standard deviation (px of an image of focal length ``fx`` px)."""
        return fx * (self.lateral_rad + self.lateral_angle_rad * theta / (math.pi / 2 - theta))

    def missing_probability(self, theta: NDArray[np.floating]) -> NDArray[np.floating]:
        """Probability of no return at incidence angle ``theta`` (rad)."""
        start, end = math.radians(self.grazing_start_deg), math.radians(self.grazing_end_deg)
        return np.clip((theta - start) / (end - start), 0.0, 1.0)


def quantize_inverse_depth(z: NDArray[np.floating], step: float) -> NDArray[np.floating]:
    """Depths whose inverse is rounded to a multiple of ``step`` (1/m); 0 stays 0."""
    if step <= 0.0:
        return z
    with np.errstate(divide="ignore"):
        levels = np.reciprocal(z)
    levels *= 1.0 / step
    np.rint(levels, out=levels)
    np.maximum(levels, 1.0, out=levels)
    levels *= step
    quantized = np.reciprocal(levels, out=levels)
    quantized[z <= 0.0] = 0.0
    return quantized


def unseen(
    z: NDArray[np.floating], K: NDArray[np.floating], baseline: float, config: KinectConfig
) -> NDArray[np.bool_]:
    """Pixels hidden from a center of projection ``baseline`` m along +x (the projector or
    the IR camera), less the runs narrower than ``config.min_shadow_px`` along a row."""
    if baseline == 0.0:
        return np.zeros(z.shape, dtype=bool)
    return open_rows(baseline_shadow(z, K, baseline), round(config.min_shadow_px))


def kinect(
    z: NDArray[np.floating], K: NDArray[np.floating], config: KinectConfig, rng: np.random.Generator
) -> NDArray[np.floating]:
    """The depth a structured-light camera returns for the true depth ``z`` (m, 0 = none).

    Order: lateral jitter and flying pixels at depth edges, axial noise (depth and incidence
    angle), inverse-depth quantization, depth unit, then no return for pixels out of range,
    hidden from the projector or the IR camera, at grazing incidence and (randomly) along
    depth edges.
    Geometry (angles, edges, shadow) is that of the true depth.
    """
    theta = incidence_angle(z, K)
    edges = depth_edges(z, config.edge_jump)
    shadow = unseen(z, K, config.projector_baseline - config.registration_offset, config)
    shadow |= unseen(z, K, -config.registration_offset, config)
    zone = np.nonzero(band(edges, round(config.edge_jitter_px)))
    out = lateral_jitter(z, zone, config.lateral_sigma_px(K[0, 0], theta[zone]), rng)
    out = flying_pixels(out, edges, config.flying_probability, rng)
    noise = rng.standard_normal(z.shape, dtype=np.float32)
    noise *= config.axial_sigma(np.where(out > 0.0, out, 1.0), theta)
    noise += out
    out = np.where(out > 0.0, np.fmax(noise, 1e-3), 0.0).astype(z.dtype)
    out = quantize_inverse_depth(out, config.inverse_depth_step)
    round_depth(out, config.depth_resolution)
    in_range(out, config.min_range, config.max_range)
    out[shadow] = 0.0
    grazing = np.nonzero(theta > math.radians(config.grazing_start_deg))
    drop_at(out, grazing, config.missing_probability(theta[grazing]), rng)
    if config.edge_dropout > 0.0:
        edge_band = band(edges, round(config.edge_dropout_px))
        drop(out, np.where(edge_band, np.float32(config.edge_dropout), np.float32(0.0)), rng)
    return out


def apply_kinect(
    depth: ArrayLike,
    K: ArrayLike,
    config: KinectConfig,
    rng: np.random.Generator,
    intensity: ArrayLike | None = None,
) -> NDArray[np.floating]:
    """:func:`kinect` on a checked depth image, in its dtype (``intensity`` is not used)."""
    z, K = checked_depth(depth, K)
    return kinect(z, K, config, rng).astype(np.asarray(depth).dtype)
