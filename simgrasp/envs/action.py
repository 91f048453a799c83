"""The action of :class:`~simgrasp.envs.handle_grasp.HandleGraspEnv`: one grasp as 8 numbers.

``[x, y, z, qw, qx, qy, qz, width]`` (float64): the TCP pose ``world_T_tcp`` as position
(meters, world frame) and unit quaternion (scalar first), following the README's grasp
convention (TCP midway between the finger pads, +z the approach direction, +y the direction in
which the jaws open and close), and ``width`` the jaw opening before closing (meters).
"""

from __future__ import annotations

import reprlib

import numpy as np
from gymnasium import spaces
from numpy.typing import ArrayLike, NDArray

from simgrasp.errors import SimgraspError
from simgrasp.grasping.grasp import Grasp
from simgrasp.scenes.config import SceneConfig

ACTION_SIZE = 8
MIN_OPENING = 1e-3
"""Smallest jaw opening (m) an action's width is clipped to (a grasp needs a positive width)."""
MIN_QUATERNION_NORM = 1e-6
"""Quaternions shorter than this have no usable direction: the action is rejected."""
ACTION_SOURCE = "action"
"""``grasp_source`` of the trial record for a grasp given as an action."""


def action_space(max_opening: float, scene: SceneConfig) -> spaces.Box:
    """The Box of grasp actions: the position spans the table top (x, y) and the heights from
    the table top up to the gripper's parking height (z); quaternion components in [-1, 1];
    width in [0, ``max_opening``] (m). Positions outside the box are executed as given."""
    half_x, half_y, _ = scene.table_half_size
    top = scene.table_top_z
    low = np.array([-half_x, -half_y, top, -1.0, -1.0, -1.0, -1.0, 0.0])
    high = np.array([half_x, half_y, top + scene.park_height, 1.0, 1.0, 1.0, 1.0, max_opening])
    return spaces.Box(low=low, high=high, dtype=np.float64)


def grasp_from_action(action: ArrayLike, max_opening: float) -> Grasp:
    """The world-frame grasp an action encodes: the quaternion is normalized and the width
    clipped into [``MIN_OPENING``, ``max_opening``] (m).

    Raises:
        ValueError: naming the action, if it is not 8 finite numbers or its quaternion is
            (nearly) zero.
    """
    expected = f"expected {ACTION_SIZE} finite numbers [x, y, z, qw, qx, qy, qz, width]"
    try:
        values = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        shown = " ".join(reprlib.repr(action).split())
        raise SimgraspError(f"invalid action {shown}: {expected}") from None
    if values.shape != (ACTION_SIZE,) or not np.all(np.isfinite(values)):
        raise SimgraspError(f"invalid action {np.asarray(action).tolist()!r}: {expected}")
    norm = float(np.linalg.norm(values[3:7]))
    if norm < MIN_QUATERNION_NORM:
        raise SimgraspError(
            f"invalid action {values.tolist()!r}: the quaternion [qw, qx, qy, qz] has norm "
            f"{norm:.3g}, below {MIN_QUATERNION_NORM:g}; it encodes no rotation"
        )
    width = float(np.clip(values[7], MIN_OPENING, max_opening))
    return Grasp.from_pose7(values[:7], width, source=ACTION_SOURCE)


def action_from_grasp(grasp: Grasp) -> NDArray[np.float64]:
    """The action ``[x, y, z, qw, qx, qy, qz, width]`` that executes ``grasp`` (qw >= 0)."""
    return np.append(grasp.to_pose7(), grasp.width)
