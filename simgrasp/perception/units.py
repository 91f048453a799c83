"""Cloud units: files are read as meters unless told otherwise, and a cloud whose size only
other units explain (millimetres read as meters, or meters read as millimetres) is refused
before any detection work, with the fix spelled for the caller (``--units mm`` on the command
line, ``units="mm"`` in Python).

Meshes are checked the same way when loaded (:mod:`simgrasp.assets.mesh_check`). For a point
cloud the check is its bounding-box diagonal, an O(N) test made before voxelizing or normal
estimation: a 2M-point mug in millimetres otherwise costs about 27 s and 4 GB to give no
handles.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from simgrasp.errors import SimgraspError, fix_for_caller

Units = Literal["m", "mm", "cm"]
UNIT_SCALE: dict[str, float] = {"m": 1.0, "mm": 1e-3, "cm": 1e-2}
"""Meters per unit, in the order a wrong size is explained by (meters, then millimetres)."""
_UNIT_NAMES = {"m": "meters", "mm": "millimetres", "cm": "centimetres"}


@dataclass(frozen=True)
class CloudUnitsConfig:
    """How a cloud's units are taken and checked."""

    max_extent: float = 5.0
    """Largest bounding-box diagonal (m) of a cloud to detect on: a graspable object spans well
    under a meter and a tabletop scene a few meters, while the same object in millimetres spans
    tens to hundreds of units."""
    min_extent: float = 0.01
    """Smallest bounding-box diagonal (m) of a cloud to detect on: nothing a gripper takes by
    a handle spans under a centimetre, while an object in meters read as millimetres spans a
    tenth of a millimetre (the detector would find no neighborhood in it, silently)."""


def cloud_in_meters(
    points: NDArray[np.float64],
    units: Units,
    source: str,
    config: CloudUnitsConfig | None = None,
) -> NDArray[np.float64]:
    """``points`` given in ``units``, in meters; a ValueError naming ``source`` and the units
    that explain its size if the result spans more than ``config.max_extent`` (a cloud in
    millimetres read as meters) or, read in other units than meters, less than
    ``config.min_extent`` (a cloud in meters read as millimetres)."""
    config = config or CloudUnitsConfig()
    if units not in UNIT_SCALE:
        raise SimgraspError(f"unknown units {units!r}; use one of {', '.join(UNIT_SCALE)}")
    scaled = points * UNIT_SCALE[units] if units != "m" else points
    extent = float(np.linalg.norm(scaled.max(axis=0) - scaled.min(axis=0))) if len(scaled) else 0.0
    if extent > config.max_extent or (units != "m" and 0 < extent < config.min_extent):
        raise SimgraspError(_size_error(source, extent, units, config))
    return scaled


def _size_error(source: str, extent: float, units: str, config: CloudUnitsConfig) -> str:
    """One line: the cloud's implausible size ``extent`` (m, read in ``units``) and, as meshes
    do, the first other units that make it an object or a tabletop scene (at least twice
    ``min_extent`` and at most ``max_extent`` across), spelled for the caller."""
    size = f"{extent:.0f} m" if extent > config.max_extent else f"{extent * 1000:.2g} mm"
    limit = (
        f"more than the {config.max_extent:g} m any object or tabletop scene spans"
        if extent > config.max_extent
        else f"less than the {config.min_extent * 100:g} cm any object to grasp spans"
    )
    message = f"{source}: the cloud spans {size} (bounding-box diagonal) read as {units}, {limit}"
    for other, scale in UNIT_SCALE.items():
        rescaled = extent / UNIT_SCALE[units] * scale
        if other != units and 2 * config.min_extent <= rescaled <= config.max_extent:
            cli = "drop --units" if other == "m" else f"pass --units {other}"
            return f"{message}: is it in {_UNIT_NAMES[other]}? " + fix_for_caller(
                cli, f'pass units="{other}"'
            )
    return f"{message}: check its units"
