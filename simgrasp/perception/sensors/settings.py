"""Which depth sensor sees a scene, with every model's parameters, as one settings branch."""

from __future__ import annotations

from dataclasses import dataclass, field

from simgrasp.config import setting
from simgrasp.perception.sensors.base import SensorConfig
from simgrasp.perception.sensors.ideal import IdealConfig
from simgrasp.perception.sensors.kinect import KinectConfig
from simgrasp.perception.sensors.stereo import StereoConfig


def sensor_names() -> tuple[str, ...]:
    """The sensor models (:data:`simgrasp.perception.sensors.SENSORS`)."""
    from simgrasp.perception.sensors import SENSORS

    return tuple(SENSORS)


@dataclass(frozen=True)
class SensorSettings:
    """The simulated depth sensor the rendered depth images pass through, per view, before
    the object's pixels are taken (only the chosen model's parameters are used)."""

    kind: str = setting("ideal", flag="--sensor", choices=sensor_names)
    """ideal: the renderer's exact depth; kinect: a structured-light camera calibrated on
    osd-learn; stereo: a D435-like active stereo camera."""
    kinect: KinectConfig = field(default_factory=KinectConfig)
    stereo: StereoConfig = field(default_factory=StereoConfig)

    def model(self) -> SensorConfig:
        """The chosen model's config."""
        return {"kinect": self.kinect, "stereo": self.stereo}.get(self.kind, IdealConfig())
