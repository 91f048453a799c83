"""ACRONYM's test of a closed grasp: shake the hand, then is the object still between the jaws?

ACRONYM (Eppner, Mousavian, Fox, ICRA 2021) labels a grasp in free space: the object floats
(no table, no gravity), the hand appears at the grasp, closes, then runs a fixed shaking
motion; the grasp succeeds when the object is still in the gripper afterwards, and FleX records
how much the object moved in the jaws while closing and shaking
(``object_motion_during_shaking_*``). Its FleX code was never released and the paper gives no
amplitudes: :class:`ShakeConfig` is our reading of it (a translation along the approach, then a
rotation about the closing axis, each a few sine cycles about the TCP), and its values are the
ones chosen on the tuning half of ``docs/results/acronym/``.

Each label also gets a continuous ``score`` in [0, 1]: ``1 / (1 + motion / score_scale)`` of
the object's largest motion in the jaws during the shake (its center of mass's displacement in
the TCP frame plus its rotation times its bounding radius, m); 0 when it was let go.

This module holds the motion and its settings, free of MuJoCo; the trial phase that runs it is
:class:`simgrasp.grasping.trials.phases.shake.Shake`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from simgrasp.config.checks import Checked, NonNegative, Positive, PositiveInt
from simgrasp.transforms import rotations_to_quats_wxyz


@dataclass(frozen=True)
class ShakeConfig(Checked):
    """The shaking motion about the TCP after the close (m, rad, Hz, s)."""

    linear_amplitude: NonNegative = 0.03
    """Peak displacement along the approach (TCP z), m."""
    angular_amplitude: NonNegative = 0.15
    """Peak rotation about the closing axis (TCP y), rad."""
    frequency: Positive = 2.0
    """Shaking frequency (Hz) of both motions."""
    cycles: PositiveInt = 2
    """Sine cycles of each motion."""
    score_scale: Positive = 0.01
    """Motion (m) at which the score is 1/2."""


def _motion(shake: ShakeConfig, t: float) -> tuple[float, float]:
    """(displacement along TCP z (m), rotation about TCP y (rad)) of the shaking motion at
    time ``t`` (s) since it began: first the translation, then the rotation; zero after both."""
    period = shake.cycles / shake.frequency
    if t >= 2 * period:
        return 0.0, 0.0
    phase = math.sin(2 * math.pi * shake.frequency * t)
    if t < period:
        return shake.linear_amplitude * phase, 0.0
    return 0.0, shake.angular_amplitude * phase


def tcp_offsets(shake: ShakeConfig, times: list[float]) -> NDArray[np.float64]:
    """``tcp0_T_tcp`` ``(len(times), 4, 4)`` of the shaking motion at each of ``times`` (s)
    since it began (:func:`_motion`): a translation along TCP z or a rotation about TCP y."""
    motions = np.array([_motion(shake, t) for t in times]).reshape(-1, 2)
    offsets = np.tile(np.eye(4), (len(motions), 1, 1))
    angles = motions[:, 1].tolist()
    cosines = np.array([math.cos(a) for a in angles])
    sines = np.array([math.sin(a) for a in angles])
    offsets[:, 2, 3] = motions[:, 0]
    offsets[:, 0, 0] = offsets[:, 2, 2] = cosines
    offsets[:, 0, 2], offsets[:, 2, 0] = sines, 0.0 - sines  # +0.0 where no rotation
    return offsets


def tcp_offset(shake: ShakeConfig, t: float) -> NDArray[np.float64]:
    """``tcp0_T_tcp`` (4 x 4) of the shaking motion at time ``t`` (s): one row of
    :func:`tcp_offsets`."""
    return tcp_offsets(shake, [t])[0]


def shake_targets(
    shake: ShakeConfig,
    world_T_tcp0: NDArray[np.float64],
    tcp_T_root: NDArray[np.float64],
    control_dt: float,
    steps: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The mocap targets of the whole shake, computed before it runs: positions ``(steps, 3)``
    (world frame, m) and ``[w, x, y, z]`` quaternions ``(steps, 4)`` (w >= 0) of the gripper
    root at control steps ``1 .. steps`` of ``control_dt`` seconds; row ``k - 1`` has the same
    bits as ``Mount.command_tcp(world_T_tcp0 @ tcp_offset(shake, k * control_dt))``."""
    times = [k * control_dt for k in range(1, steps + 1)]
    world_T_root = world_T_tcp0 @ tcp_offsets(shake, times) @ tcp_T_root
    quats = rotations_to_quats_wxyz(world_T_root[:, :3, :3])
    quats[quats[:, 0] < 0] *= -1.0
    return world_T_root[:, :3, 3].copy(), quats


def largest_motion(frames: NDArray[np.float64], radius: float) -> float:
    """The object's largest motion in the jaws (m, module docstring) over ``frames``
    ``(N, 24)``: per control step the TCP's position and row-major rotation (world frame),
    then the object's center of mass and rotation; row 0 is the pose at the close."""
    world_p_tcp, world_R_tcp = frames[:, 0:3], frames[:, 3:12].reshape(-1, 3, 3)
    world_p_com, world_R_com = frames[:, 12:15], frames[:, 15:24].reshape(-1, 3, 3)
    tcp_R_world = world_R_tcp.transpose(0, 2, 1)
    tcp_R_com = tcp_R_world @ world_R_com
    tcp_p_com = np.einsum("nij,nj->ni", tcp_R_world, world_p_com - world_p_tcp)
    turn = tcp_R_com[0].T @ tcp_R_com
    cosine = np.clip((np.trace(turn, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    motion = np.linalg.norm(tcp_p_com - tcp_p_com[0], axis=1) + np.arccos(cosine) * radius
    return float(motion.max())
