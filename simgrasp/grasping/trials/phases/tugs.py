"""The tugs: weight-sized forces pull at the held object, one direction at a time (N, s)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.runner import Released

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState


class Tugs(TrialPhase):
    """A force of ``perturb_force_scale`` x the object's weight pulls at its center of mass
    along each of ``perturb_directions`` in turn (as GraspDataGen does) for ``perturb_time``,
    each followed by a rest; unless the object is still held and lifted afterwards,
    ``dropped_in_perturbation``. Records ``slip_perturb``."""

    name = "tugs"

    def run(self, state: TrialState) -> Failure | None:
        scene, config, runner = state.scene, state.config, state.runner
        data, body = scene.data, scene.object_body
        weight = scene.model.body_subtreemass[body] * np.linalg.norm(scene.model.opt.gravity)
        try:
            for direction in np.asarray(config.perturb_directions, dtype=float).reshape(-1, 3):
                force = config.perturb_force_scale * weight * direction / np.linalg.norm(direction)
                data.xfrc_applied[body, :3] = force
                runner.wait(config.perturb_time, min_time=config.quiet_min_tug)
                data.xfrc_applied[body, :3] = 0.0
                runner.wait(config.rest_time)
        except Released:
            data.xfrc_applied[body, :3] = 0.0
            return "dropped_in_perturbation"
        state.moment("perturbed")
        world_T_object = scene.object_pose()
        state.record["slip_perturb"] = state.slip(world_T_object)
        if not (state.held().both and state.still_lifted(world_T_object)):
            return "dropped_in_perturbation"
        return None
