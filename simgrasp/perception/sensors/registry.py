"""The depth sensor models simgrasp knows, by name: the one list that ``apply_sensor``, the
settings' choices (``sensor.kind``) and the command lines read.

Each entry names its config class and its model, ``module:attribute`` strings resolved only
when used, so reading the registry imports nothing else (no MuJoCo, no SciPy). A model is
``model(depth, K, config, rng, intensity) -> depth`` (the arguments as
:func:`simgrasp.perception.sensors.apply_sensor` documents them). A new model is a module
with its config (a :class:`~simgrasp.perception.sensors.base.SensorConfig` subclass whose
``name`` is the entry's) and model function, plus an entry here or :func:`register_sensor`
at run time.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from simgrasp.registry import Registry

if TYPE_CHECKING:
    from simgrasp.perception.sensors.base import SensorConfig


def resolve(target: str) -> Any:
    """The attribute a ``module:attribute`` string names, its module imported now."""
    module, _, attribute = target.partition(":")
    return getattr(importlib.import_module(module), attribute)


@dataclass(frozen=True)
class SensorEntry:
    """A registered sensor model: its ``name``, its ``config`` class and its ``model``
    function (``module:attribute`` each) and a one-line ``summary`` (for help texts)."""

    name: str
    config: str
    model: str
    summary: str

    def config_class(self) -> type[SensorConfig]:
        cls: type[SensorConfig] = resolve(self.config)
        return cls

    def model_function(self) -> Any:
        return resolve(self.model)


SENSOR_MODELS: Registry[SensorEntry] = Registry(
    "sensor",
    (
        SensorEntry(
            "ideal",
            "simgrasp.perception.sensors.ideal:IdealConfig",
            "simgrasp.perception.sensors.ideal:apply_ideal",
            "the renderer's exact depth",
        ),
        SensorEntry(
            "kinect",
            "simgrasp.perception.sensors.kinect:KinectConfig",
            "simgrasp.perception.sensors.kinect:apply_kinect",
            "a structured-light camera calibrated on osd-learn",
        ),
        SensorEntry(
            "stereo",
            "simgrasp.perception.sensors.stereo:StereoConfig",
            "simgrasp.perception.sensors.stereo:apply_stereo",
            "a D435-like active stereo camera",
        ),
    ),
)
"""Registered sensor models by name; the first is the default."""

DEFAULT_SENSOR = "ideal"


def sensor_names() -> tuple[str, ...]:
    """Names of the registered sensor models, the default first."""
    return SENSOR_MODELS.names()


def sensor_entry(name: str) -> SensorEntry:
    """The entry of the sensor model ``name``, else an error naming the choices."""
    return SENSOR_MODELS.entry(name)


def register_sensor(entry: SensorEntry) -> None:
    """Add a sensor model at run time (its name must be new)."""
    SENSOR_MODELS.register(entry)
