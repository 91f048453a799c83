"""Depth sensor models applied to a rendered depth image: ``ideal``, ``kinect``, ``stereo``.

    from simgrasp.perception.sensors import KinectConfig, apply_sensor
    noisy = apply_sensor(depth, K, KinectConfig(), rng)

``depth`` is an (H, W) float image of meters along the optical axis (0 = no hit), ``K`` the
3x3 OpenCV camera matrix, ``rng`` the seeded generator (``simgrasp.seeding.rng_for``). The
result has the input's shape and dtype, 0 where the sensor returns nothing. ``SENSORS`` maps
each model's name to its config class; ``sensor_config(name)`` gives the defaults.
Importable without MuJoCo.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.perception.sensors.base import SensorConfig, checked_depth
from simgrasp.perception.sensors.ideal import IdealConfig
from simgrasp.perception.sensors.kinect import KinectConfig, kinect
from simgrasp.perception.sensors.stereo import StereoConfig, stereo

SENSORS: dict[str, type[SensorConfig]] = {
    IdealConfig.name: IdealConfig,
    KinectConfig.name: KinectConfig,
    StereoConfig.name: StereoConfig,
}


def sensor_config(name: str) -> SensorConfig:
    """The default config of the sensor model ``name`` (a key of ``SENSORS``)."""
    if name not in SENSORS:
        raise ValueError(f"unknown sensor {name!r}; choose one of {', '.join(SENSORS)}")
    return SENSORS[name]()


def apply_sensor(
    depth: ArrayLike,
    K: ArrayLike,
    config: SensorConfig,
    rng: np.random.Generator,
    intensity: ArrayLike | None = None,
) -> NDArray[np.floating]:
    """The depth image the sensor of ``config`` returns for the true ``depth``.

    Args:
        depth: (H, W) float meters along the optical axis; 0, NaN, inf or negative = no hit.
        K: 3x3 OpenCV camera matrix of the image (px).
        config: a sensor's config (``IdealConfig`` returns ``depth`` unchanged, as a copy).
        rng: the seeded generator every random draw comes from.
        intensity: optional (H, W) image in [0, 1] for models that need texture (``stereo``).

    Returns:
        (H, W) depth of the input's dtype, meters, 0 where the sensor gives no return.

    Raises:
        ValueError: bad shape, dtype or camera matrix, or an unknown config type.
    """
    z, K = checked_depth(depth, K)
    dtype = np.asarray(depth).dtype
    if isinstance(config, IdealConfig):
        return np.array(depth, dtype=dtype, copy=True)
    if isinstance(config, KinectConfig):
        return kinect(z, K, config, rng).astype(dtype)
    if isinstance(config, StereoConfig):
        return stereo(z, K, config, rng, _checked_intensity(intensity, z.shape)).astype(dtype)
    raise ValueError(f"no sensor model for config {type(config).__name__}")


def _checked_intensity(
    intensity: ArrayLike | None, shape: tuple[int, ...]
) -> NDArray[np.float64] | None:
    if intensity is None:
        return None
    image = np.asarray(intensity, dtype=np.float64)
    if image.shape != shape or not np.all(np.isfinite(image)):
        raise ValueError(f"intensity must be a finite image of shape {shape}, got {image.shape}")
    return image


__all__ = [
    "SENSORS",
    "IdealConfig",
    "KinectConfig",
    "SensorConfig",
    "StereoConfig",
    "apply_sensor",
    "sensor_config",
]
