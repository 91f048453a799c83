"""The phases that bring the open gripper to the grasp: settle, pre-grasp and approach
(world frame, m, s)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from simgrasp._mujoco import mujoco
from simgrasp.grasping.trials.phases.base import TrialPhase
from simgrasp.grasping.trials.scoring import geoms_touching

if TYPE_CHECKING:
    from simgrasp.grasping.trials.result import Failure
    from simgrasp.grasping.trials.state import TrialState

OPEN_TOLERANCE = 0.001
"""A free-floating trial starts once the jaws are this close (m) to the grasp width..."""
OPEN_LIMIT = 1.0
"""... or after this many seconds of opening."""


class Settle(TrialPhase):
    """The object settles (``settle_time``) while the parked gripper opens to the grasp
    width; restored from ``state.starts`` where it holds this start. Free-floating, the jaws
    then finish opening (no approach follows, during which they would)."""

    name = "settle"

    def run(self, state: TrialState) -> None:
        scene, config, starts = state.scene, state.config, state.starts
        width = min(state.grasp.width, scene.gripper.gripper.max_opening)
        restored = None if starts is None else starts.restore(scene, config, width)
        if restored is not None:
            state.runner.steps += restored
        else:
            scene.gripper.set_opening(scene.data, width)
            state.runner.wait(config.settle_time)
            if config.free_floating:
                _open_jaws(state, width)
            if starts is not None:
                starts.record(scene, config, width, state.runner.steps)
        state.world_T_object_settled = scene.object_pose()


def _open_jaws(state: TrialState, width: float) -> None:
    """Step until the jaws are within ``OPEN_TOLERANCE`` of ``width`` (at most ``OPEN_LIMIT``
    seconds: a linkage may stop short of its full stroke)."""
    data, gripper, runner = state.scene.data, state.scene.gripper, state.runner
    elapsed = 0.0
    while abs(gripper.opening(data) - width) > OPEN_TOLERANCE and elapsed < OPEN_LIMIT:
        runner.advance(runner.control_dt)
        elapsed += runner.control_dt


class Pregrasp(TrialPhase):
    """The open gripper appears ``pregrasp_distance`` back along the approach (free-floating:
    at the grasp itself); touching anything there (deeper than ``start_tolerance`` where it
    is set) is ``invalid_start``."""

    name = "pregrasp"

    def run(self, state: TrialState) -> Failure | None:
        scene, grasp, config = state.scene, state.grasp, state.config
        world_T_pregrasp = grasp.world_T_tcp.copy()
        if not config.free_floating:
            world_T_pregrasp[:3, 3] -= config.pregrasp_distance * grasp.approach_world
        scene.gripper.teleport(scene.data, world_T_pregrasp)
        mujoco.mj_forward(scene.model, scene.data)
        state.moment("pregrasp")
        touching = geoms_touching(scene.data, state.runner.gripper_geoms, config.start_tolerance)
        return "invalid_start" if touching else None


class Approach(TrialPhase):
    """The target moves to the grasp pose at ``approach_speed``; a TCP held back more than
    ``approach_lag_limit`` or an object shoved more than ``approach_push_limit`` is
    ``approach_collision``. Free-floating: nothing (the gripper already is at the grasp)."""

    name = "approach"

    def run(self, state: TrialState) -> Failure | None:
        scene, grasp, config, runner = state.scene, state.grasp, state.config, state.runner
        if config.free_floating:
            return None
        data, gripper = scene.data, scene.gripper
        mocap_start = data.mocap_pos[gripper.mocap_id].copy()
        gripper.command_tcp(data, grasp.world_T_tcp)
        mocap_goal = data.mocap_pos[gripper.mocap_id].copy()
        runner.advance(config.pregrasp_distance / config.approach_speed, mocap_start, mocap_goal)
        runner.advance(2 * runner.control_dt)  # let the weld catch up
        lag = np.linalg.norm(gripper.world_T_tcp(data)[:3, 3] - grasp.world_T_tcp[:3, 3])
        settled = state.world_T_object_settled
        assert settled is not None, "the approach follows the settle"
        pushed = np.linalg.norm(scene.object_pose()[:3, 3] - settled[:3, 3])
        if lag > config.approach_lag_limit or pushed > config.approach_push_limit:
            return "approach_collision"
        return None
