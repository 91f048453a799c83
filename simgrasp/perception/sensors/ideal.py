"""The ideal sensor: the rendered depth itself."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from simgrasp.perception.sensors.base import SensorConfig


@dataclass(frozen=True)
class IdealConfig(SensorConfig):
    """A perfect depth camera: every rendered depth is returned exactly (no parameters)."""

    name: ClassVar[str] = "ideal"
