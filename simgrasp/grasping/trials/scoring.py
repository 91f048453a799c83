"""What a grasp trial measures: finger-object contacts, the handle share of them, and slip.

The trial collects the finger-object contacts (:class:`FingerContacts`, from its geom codes);
these functions score them. Contact points are world-frame positions (``points_world``,
meters) unless named ``points_object`` (the object's mesh frame, the frame its
:class:`~simgrasp.labels.HandleLabel` lives in).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.trials.trial_config import HANDLE_MARGIN
from simgrasp.labels import Box, Capsule, HandleLabel, Region


@dataclass(frozen=True)
class FingerContacts:
    """Finger-object contacts at one instant.

    Attributes:
        points_world: (N, 3) contact points between any finger geom and the object (m).
        left: the left finger touches the object.
        right: the right finger touches the object.
    """

    points_world: NDArray[np.float64]
    left: bool
    right: bool

    @property
    def both(self) -> bool:
        return self.left and self.right


def geoms_touching(
    data: mujoco.MjData, geoms: NDArray[np.int64], tolerance: float | None = None
) -> bool:
    """Whether any of ``geoms`` is in contact (penetration or within margin) with anything;
    with ``tolerance`` (m), only contacts that penetrate deeper than it count."""
    contacts = data.contact
    rows = np.isin(contacts.geom1, geoms) | np.isin(contacts.geom2, geoms)
    if tolerance is not None:
        rows &= contacts.dist < -tolerance
    return bool(np.any(rows))


def points_in_object_frame(
    points_world: NDArray[np.float64], world_T_object: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Map (N, 3) world points into the object frame given ``world_T_object`` (4x4)."""
    rotation, translation = world_T_object[:3, :3], world_T_object[:3, 3]
    return (points_world - translation) @ rotation


def _grown(region: Region, margin: float) -> Region:
    if isinstance(region, Capsule):
        return replace(region, radius=region.radius + margin)
    assert isinstance(region, Box)
    return replace(region, half_extents=region.half_extents + margin)


def handle_fraction(
    points_object: NDArray[np.float64], handle: HandleLabel, margin: float = HANDLE_MARGIN
) -> float:
    """Share of contact points (object frame) inside the handle label grown by ``margin`` (m);
    0 without points or without a handle."""
    if len(points_object) == 0 or not handle.has_handle:
        return 0.0
    grown = replace(handle, regions=tuple(_grown(r, margin) for r in handle.regions))
    return float(np.mean(grown.contains(points_object)))


def relative_pose(
    world_T_a: NDArray[np.float64], world_T_b: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``a_T_b`` from two world poses."""
    return np.linalg.inv(world_T_a) @ world_T_b


def slip_distance(
    tcp_T_object_before: NDArray[np.float64], tcp_T_object_after: NDArray[np.float64]
) -> float:
    """How far the object's origin moved in the TCP frame between two instants (m)."""
    return float(np.linalg.norm(tcp_T_object_after[:3, 3] - tcp_T_object_before[:3, 3]))
