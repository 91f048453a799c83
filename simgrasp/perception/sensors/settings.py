"""Which depth sensor sees a scene, with every model's parameters, as one settings branch."""

from __future__ import annotations

from dataclasses import dataclass, field

from simgrasp.config import setting
from simgrasp.config.checks import Checked
from simgrasp.perception.sensors.base import SensorConfig
from simgrasp.perception.sensors.kinect import KinectConfig
from simgrasp.perception.sensors.registry import DEFAULT_SENSOR, sensor_entry, sensor_names
from simgrasp.perception.sensors.stereo import StereoConfig


@dataclass(frozen=True)
class SensorSettings(Checked):
    """The simulated depth sensor the rendered depth images pass through, per view, before
    the object's pixels are taken (only the chosen model's parameters are used)."""

    kind: str = setting(DEFAULT_SENSOR, flag="--sensor", choices=sensor_names, main=True)
    """ideal: the renderer's exact depth; kinect: a structured-light camera calibrated on
    osd-learn; stereo: a D435-like active stereo camera."""
    kinect: KinectConfig = field(default_factory=KinectConfig)
    stereo: StereoConfig = field(default_factory=StereoConfig)

    def model(self) -> SensorConfig:
        """The chosen model's config: this branch's parameters for a model that has some
        (a field named as the model), else the model's defaults."""
        given = getattr(self, self.kind, None)
        return (
            given if isinstance(given, SensorConfig) else sensor_entry(self.kind).config_class()()
        )
