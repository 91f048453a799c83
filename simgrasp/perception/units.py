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

Units = Literal["m", "mm"]
UNIT_SCALE: dict[str, float] = {"m": 1.0, "mm": 1e-3}
"""Meters per unit."""


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
    """``points`` given in ``units``, in meters; a ValueError naming ``source`` if the result
    spans more than ``config.max_extent`` (the cloud is then almost surely in millimetres) or,
    read as millimetres, less than ``config.min_extent`` (then almost surely in meters)."""
    config = config or CloudUnitsConfig()
    if units not in UNIT_SCALE:
        raise SimgraspError(f"unknown units {units!r}; use one of {', '.join(UNIT_SCALE)}")
    scaled = points * UNIT_SCALE[units] if units != "m" else points
    extent = float(np.linalg.norm(scaled.max(axis=0) - scaled.min(axis=0))) if len(scaled) else 0.0
    if extent > config.max_extent:
        guess = (
            "is it in millimetres? " + fix_for_caller("pass --units mm", 'pass units="mm"')
            if units == "m"
            else "check its units"
        )
        raise SimgraspError(
            f"{source}: the cloud spans {extent:.0f} m (bounding-box diagonal) read as "
            f"{units}, more than the {config.max_extent:g} m any object or tabletop scene "
            f"spans: {guess}"
        )
    if units != "m" and 0 < extent < config.min_extent:
        raise SimgraspError(
            f"{source}: the cloud spans {extent * 1000:.2g} mm (bounding-box diagonal) read as "
            f"{units}, less than the {config.min_extent * 100:g} cm any object to grasp spans: "
            "is it in meters? " + fix_for_caller("drop --units", 'pass units="m"')
        )
    return scaled
