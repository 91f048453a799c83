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
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from simgrasp.config.checks import Checked, NonNegative, Positive, PositiveInt
from simgrasp.transforms import make_transform

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.trial import _Trial


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


def _axis_angle(axis: int, angle: float) -> NDArray[np.float64]:
    """Rotation (3 x 3) by ``angle`` about coordinate axis ``axis``."""
    c, s = math.cos(angle), math.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    rotation = np.eye(3)
    rotation[i, i], rotation[i, j], rotation[j, i], rotation[j, j] = c, -s, s, c
    return rotation


def tcp_offset(shake: ShakeConfig, t: float) -> NDArray[np.float64]:
    """``tcp0_T_tcp`` (4 x 4) of the shaking motion at time ``t`` (s) since it began: first the
    translation along TCP z, then the rotation about TCP y; identity after both."""
    period = shake.cycles / shake.frequency
    phase = math.sin(2 * math.pi * shake.frequency * t)
    if t < period:
        return make_transform(np.eye(3), np.array([0.0, 0.0, shake.linear_amplitude * phase]))
    if t < 2 * period:
        return make_transform(_axis_angle(1, shake.angular_amplitude * phase), np.zeros(3))
    return np.eye(4)


def _motion(trial: _Trial, tcp_T_com0: NDArray[np.float64], radius: float) -> float:
    """The object's motion in the jaws since the close (m, module docstring)."""
    scene = trial.scene
    world_T_tcp = scene.gripper.world_T_tcp(scene.data)
    body = scene.object_body
    world_T_com = make_transform(
        scene.data.ximat[body].reshape(3, 3), np.asarray(scene.data.xipos[body])
    )
    tcp_T_com = np.linalg.inv(world_T_tcp) @ world_T_com
    turn = tcp_T_com0[:3, :3].T @ tcp_T_com[:3, :3]
    angle = math.acos(max(-1.0, min(1.0, (np.trace(turn) - 1.0) / 2.0)))
    return float(np.linalg.norm(tcp_T_com[:3, 3] - tcp_T_com0[:3, 3])) + angle * radius


def shake_phase(trial: _Trial) -> Failure | None:
    """5'. Shake the closed hand (the object still without gravity); unless both fingers still
    touch the object afterwards, ``dropped_in_shaking``. Sets ``score`` and the contacts'
    ``on_handle`` as the hold does."""
    from simgrasp.grasping.trials.runner import Released
    from simgrasp.grasping.trials.trial import score_contacts

    scene, config, runner = trial.scene, trial.config, trial.runner
    shake = config.shake
    assert shake is not None, "the shake phase runs with a ShakeConfig"
    data, body = scene.data, scene.object_body
    world_T_tcp0 = scene.gripper.world_T_tcp(data)
    tcp_T_com0 = np.linalg.inv(world_T_tcp0) @ make_transform(
        data.ximat[body].reshape(3, 3), np.asarray(data.xipos[body])
    )
    runner.watch_release = True
    runner.use_hold_timestep()
    largest, steps = 0.0, runner.chunks(2 * shake.cycles / shake.frequency)
    try:
        for k in range(1, steps + 1):
            scene.gripper.command_tcp(data, world_T_tcp0 @ tcp_offset(shake, k * runner.control_dt))
            runner.step()
            largest = max(largest, _motion(trial, tcp_T_com0, runner.object_radius))
    except Released:
        trial.record["score"] = 0.0
        trial.lap("shake")
        return "dropped_in_shaking"
    trial.lap("shake")
    trial.moment("perturbed")
    trial.record["score"] = 1.0 / (1.0 + largest / shake.score_scale)
    contacts = score_contacts(trial)
    return None if contacts.both else "dropped_in_shaking"
