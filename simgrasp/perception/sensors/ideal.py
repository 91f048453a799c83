"""The ideal sensor: the rendered depth itself."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.perception.sensors.base import SensorConfig, checked_depth


@dataclass(frozen=True)
class IdealConfig(SensorConfig):
    """A perfect depth camera: every rendered depth is returned exactly (no parameters)."""

    name: ClassVar[str] = "ideal"


def apply_ideal(
    depth: ArrayLike,
    K: ArrayLike,
    config: IdealConfig,
    rng: np.random.Generator,
    intensity: ArrayLike | None = None,
) -> NDArray[np.floating]:
    """``depth`` itself, as a copy of its dtype (checked as every model checks it)."""
    checked_depth(depth, K)
    return np.array(depth, dtype=np.asarray(depth).dtype, copy=True)
