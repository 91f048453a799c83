"""The start of a free-floating trial, simulated once per scene and width and then restored.

A free-floating trial (``TrialConfig.free_floating``, ACRONYM's protocol) begins with the
object floating at rest while the parked gripper, far from it, opens its jaws to the grasp
width (the settle and the opening of :mod:`simgrasp.grasping.trials.trial`: for the Franka
hand about 270 physics steps of its ~1300 per held grasp). Nothing in those steps depends on
the grasp but its width: every trial resets the scene to the same state, so every trial of
that width reaches the same state after them. :class:`StartStates` keeps that state
(``mjSTATE_INTEGRATION``: time, positions, velocities, actuation, controls, mocap targets and
the solver's warm start) and the number of physics steps it took after the first trial, and
restores both in the next ones, which then run bit for bit as if they had stepped the start
themselves: their records (``steps`` included) are those of a lone ``trial --grasp``.

The states belong to one compiled scene as it was when they were recorded: a change of its
model (a friction, a force limit) after the first trial needs a fresh :class:`StartStates`.
Trials that let bodies sleep are not cached (which bodies sleep is not part of MuJoCo's state).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
"""Everything ``mj_step`` reads from ``mjData`` (bit-identical continuation)."""


@dataclass
class StartStates:
    """The states of one scene after a free-floating trial's settle and jaw opening, per trial
    config and grasp width (m)."""

    states: dict[tuple[TrialConfig, float], tuple[NDArray[np.float64], int]] = field(
        default_factory=dict
    )
    """Per (trial config, width): the state and the physics steps taken to reach it."""

    @staticmethod
    def applies(config: TrialConfig) -> bool:
        """Whether trials of ``config`` may reuse their start (free-floating, nothing asleep)."""
        return config.free_floating and not config.sleep

    def restore(self, scene: Scene, config: TrialConfig, width: float) -> int | None:
        """Put ``scene`` in the recorded start of ``config`` and ``width`` (kinematics
        updated) and return the physics steps it stands for; None, with the scene untouched,
        when none is recorded."""
        recorded = self.states.get((config, width))
        if recorded is None:
            return None
        state, steps = recorded
        mujoco.mj_setState(scene.model, scene.data, state, _STATE)
        mujoco.mj_forward(scene.model, scene.data)
        return steps

    def record(self, scene: Scene, config: TrialConfig, width: float, steps: int) -> None:
        """Keep ``scene``'s state now, reached in ``steps`` physics steps, as the start of
        ``config`` and ``width``."""
        state = np.empty(mujoco.mj_stateSize(scene.model, _STATE))
        mujoco.mj_getState(scene.model, scene.data, state, _STATE)
        self.states[(config, width)] = (state, steps)
