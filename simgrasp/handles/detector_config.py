"""Which handle detector runs, with every threshold of both, as one settings branch."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Literal

from simgrasp.config import setting
from simgrasp.config.checks import Checked
from simgrasp.errors import SimgraspError
from simgrasp.handles.baselines.tenpas_config import TenPasConfig
from simgrasp.handles.core.config import QuadricDetectorConfig

DetectorName = Literal["quadric", "tenpas"]
DETECTORS: tuple[DetectorName, ...] = ("quadric", "tenpas")


@dataclass(frozen=True)
class DetectorConfig(Checked):
    """The handle detector and the settings of each (only the chosen one's are used)."""

    kind: DetectorName = setting("quadric", flag="--detector", main=True)
    """quadric: quadric fits with the paper's criteria (Birdal et al. 2018); tenpas: ten Pas &
    Platt 2013's cylindrical shells."""
    quadric: QuadricDetectorConfig = field(default_factory=QuadricDetectorConfig)
    tenpas: TenPasConfig = field(default_factory=TenPasConfig)

    def chosen(self) -> QuadricDetectorConfig | TenPasConfig:
        """The settings of the chosen detector."""
        return self.quadric if self.kind == "quadric" else self.tenpas

    def handle_detector(self) -> DetectorName:
        """The chosen handle detector's name (an error for a proposer that detects none)."""
        if self.kind not in DETECTORS:
            raise SimgraspError(
                f"{self.kind!r} is no handle detector; choose one of {', '.join(DETECTORS)}"
            )
        return self.kind

    def for_gripper(self, max_opening: float) -> QuadricDetectorConfig | TenPasConfig:
        """The chosen detector's settings for a gripper opening ``max_opening`` (m)."""
        return replace(self.chosen(), gripper_max_opening=max_opening)
