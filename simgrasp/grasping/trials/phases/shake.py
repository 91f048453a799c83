"""The shake: ACRONYM's test of a closed grasp (the motion and its settings:
:mod:`simgrasp.grasping.trials.shake`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.runner import Released
from simgrasp.grasping.trials.shake import largest_motion, shake_targets

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState


class Shake(TrialPhase):
    """Shake the closed hand as ``config.shake`` says (the object as the earlier phases left
    it: without gravity in a free-floating trial); unless both fingers still touch the object
    afterwards, ``dropped_in_shaking``. Sets ``score`` (how little the object moved in the
    jaws) and the contacts' ``on_handle`` as the hold does."""

    name = "shake"

    def run(self, state: TrialState) -> Failure | None:
        scene, runner, shake = state.scene, state.runner, state.config.shake
        assert shake is not None, "the shake phase runs with a ShakeConfig"
        data, mount = scene.data, scene.gripper
        runner.watch_release = True
        runner.use_hold_timestep()
        steps = runner.chunks(2 * shake.cycles / shake.frequency)
        positions, quats = shake_targets(
            shake, mount.world_T_tcp(data), mount.tcp_T_root, runner.control_dt, steps
        )
        frames = np.empty((steps + 1, 24))
        _record_frame(frames, 0, state)
        try:
            for k in range(steps):
                data.mocap_pos[mount.mocap_id] = positions[k]
                data.mocap_quat[mount.mocap_id] = quats[k]
                runner.step()
                _record_frame(frames, k + 1, state)
        except Released:
            state.record["score"] = 0.0
            return "dropped_in_shaking"
        state.moment("perturbed")
        largest = largest_motion(frames, runner.object_radius)
        state.record["score"] = 1.0 / (1.0 + largest / shake.score_scale)
        contacts = state.score_contacts()
        return None if contacts.both else "dropped_in_shaking"


def _record_frame(frames: NDArray[np.float64], row: int, state: TrialState) -> None:
    """Copy the TCP's and the object's poses now into ``frames[row]`` (see
    :func:`~simgrasp.grasping.trials.shake.largest_motion`)."""
    data, site, body = state.scene.data, state.scene.gripper.tcp_site, state.scene.object_body
    frames[row, 0:3], frames[row, 3:12] = data.site_xpos[site], data.site_xmat[site]
    frames[row, 12:15], frames[row, 15:24] = data.xipos[body], data.ximat[body]
