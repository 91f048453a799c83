"""Which depth sensor the rendered depth images pass through before segmentation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from simgrasp.config import setting


@dataclass(frozen=True)
class SensorConfig:
    """The simulated depth sensor."""

    kind: Literal["ideal"] = setting("ideal", flag="--sensor")
    """ideal: the renderer's exact depth."""
