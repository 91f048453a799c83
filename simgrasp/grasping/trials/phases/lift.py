"""The lift and the hold: the closed gripper raises the object (free-floating: the object's
gravity comes on instead) and holds it still (m, s)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.runner import Released

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState


class Lift(TrialPhase):
    """Lift by ``lift_height`` at ``lift_speed`` (free-floating: switch the object's gravity
    on, the gripper still). From here on an object let go (``release_gap``) ends the trial:
    ``slipped_in_lift``."""

    name = "lift"

    def run(self, state: TrialState) -> Failure | None:
        scene, config, runner = state.scene, state.config, state.runner
        runner.watch_release = True
        lift_start = scene.data.mocap_pos[scene.gripper.mocap_id].copy()
        lift_goal = lift_start + np.array([0.0, 0.0, config.lift_height])
        try:
            if config.free_floating:
                scene.model.body_gravcomp[scene.object_body] = 0.0
            else:
                runner.advance(config.lift_height / config.lift_speed, lift_start, lift_goal)
        except Released:
            return _dropped(state)
        return None


class Hold(TrialPhase):
    """Hold still for ``hold_time`` (stepping with ``hold_timestep`` from here on); unless the
    object rose with the gripper and both fingers still touch it, ``slipped_in_lift``. Scores
    the contacts (``on_handle``) at its end and records ``lift_height`` and ``slip_lift``."""

    name = "hold"

    def run(self, state: TrialState) -> Failure | None:
        scene, record = state.scene, state.record
        state.runner.use_hold_timestep()
        try:
            state.runner.wait(state.config.hold_time)
        except Released:
            return _dropped(state)
        state.moment("lifted")
        world_T_object = scene.object_pose()
        record["lift_height"] = float(world_T_object[2, 3] - state.object_z_closed)
        record["slip_lift"] = state.slip(world_T_object)
        contacts = state.score_contacts()
        if not (contacts.both and state.still_lifted(world_T_object)):
            return "slipped_in_lift"
        return None


def _dropped(state: TrialState) -> Failure:
    """``slipped_in_lift`` of an object let go, with the height it reached (m)."""
    height = state.scene.object_pose()[2, 3] - state.object_z_closed
    state.record["lift_height"] = float(height)
    return "slipped_in_lift"
