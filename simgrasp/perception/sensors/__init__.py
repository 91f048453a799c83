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

from simgrasp.errors import SimgraspError
from simgrasp.perception.sensors.base import SensorConfig
from simgrasp.perception.sensors.ideal import IdealConfig
from simgrasp.perception.sensors.kinect import KinectConfig
from simgrasp.perception.sensors.registry import SENSOR_MODELS, sensor_entry, sensor_names
from simgrasp.perception.sensors.stereo import StereoConfig

SENSORS: dict[str, type[SensorConfig]] = {
    name: entry.config_class() for name, entry in SENSOR_MODELS.items()
}
"""The built-in sensor models' config classes by name (the registry's, resolved)."""


def sensor_config(name: str) -> SensorConfig:
    """The default config of the sensor model ``name`` (a registered one)."""
    return sensor_entry(name).config_class()()


def apply_sensor(
    depth: ArrayLike,
    K: ArrayLike,
    config: SensorConfig,
    rng: np.random.Generator,
    intensity: ArrayLike | None = None,
) -> NDArray[np.floating]:
    """The depth image the sensor of ``config`` returns for the true ``depth``: the model
    registered under ``config.name`` (:mod:`simgrasp.perception.sensors.registry`).

    Args:
        depth: (H, W) float meters along the optical axis; 0, NaN, inf or negative = no hit.
        K: 3x3 OpenCV camera matrix of the image (px).
        config: a sensor's config (``IdealConfig`` returns ``depth`` unchanged, as a copy).
        rng: the seeded generator every random draw comes from.
        intensity: optional (H, W) image in [0, 1] for models that need texture (``stereo``).

    Returns:
        (H, W) depth of the input's dtype, meters, 0 where the sensor gives no return.

    Raises:
        ValueError: bad shape, dtype or camera matrix, or a config of no registered model.
    """
    entry = SENSOR_MODELS.get(config.name)
    if entry is None or not isinstance(config, entry.config_class()):
        raise SimgraspError(f"no sensor model for config {type(config).__name__}")
    result: NDArray[np.floating] = entry.model_function()(depth, K, config, rng, intensity)
    return result


__all__ = [
    "SENSORS",
    "IdealConfig",
    "KinectConfig",
    "SensorConfig",
    "StereoConfig",
    "apply_sensor",
    "sensor_config",
    "sensor_names",
]
