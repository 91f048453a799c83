"""A gripper's planning geometry: the boxes the grasp planner checks against the cloud and
the table (pure data, no MuJoCo)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class GripperGeometry:
    """Boxes swept by an open parallel-jaw gripper, in its TCP frame (meters).

    Each finger is a box ``finger_thickness`` (y) x ``finger_width`` (x) x ``finger_length``
    (z, from the TCP back toward the palm, plus ``pad_reach`` past the TCP); the palm is a box
    ``palm_size`` (x, y, z) just behind the fingers. ``closed_pad_reach`` is how far the
    fingertips reach past the TCP once the jaws have closed, for fingers that swing forward as
    they close (the Robotiq's four-bar linkage); the table check at the grasp pose uses the
    larger of it and ``pad_reach``, so closing fingertips do not jam against the table.
    """

    max_opening: float
    finger_length: float = 0.05
    finger_thickness: float = 0.012
    finger_width: float = 0.022
    pad_reach: float = 0.012
    palm_size: tuple[float, float, float] = (0.05, 0.12, 0.04)
    closed_pad_reach: float = 0.0
