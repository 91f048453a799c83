"""The close: the jaws close on the object and squeeze it (m, s)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.scoring import relative_pose

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState


class Close(TrialPhase):
    """The jaws close and squeeze (force limited) for ``close_time``, or, with
    ``squeeze_time``, that long after both fingers first touch the object; unless both fingers
    touch it then, ``missed``. Keeps the object's pose in the TCP frame and its height for the
    slip and lift measures of the later phases."""

    name = "close"

    def run(self, state: TrialState) -> Failure | None:
        scene, config, runner = state.scene, state.config, state.runner
        scene.gripper.close(scene.data)
        if config.squeeze_time is None:
            runner.wait(config.close_time)
        else:
            closing = runner.wait_for_touch(config.close_time)
            if closing < config.close_time:
                runner.wait(min(config.squeeze_time, config.close_time - closing))
        state.moment("closed")
        if not state.held().both:
            return "missed"
        state.tcp_T_object_closed = relative_pose(
            scene.gripper.world_T_tcp(scene.data), scene.object_pose()
        )
        state.object_z_closed = scene.object_pose()[2, 3]
        return None
