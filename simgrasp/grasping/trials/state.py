"""What one grasp trial's phases share: :class:`TrialState`, handed to each phase in turn
(:mod:`simgrasp.grasping.trials.phases`) by :func:`simgrasp.grasping.trials.trial.run_trial`."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.result import Phase
from simgrasp.grasping.trials.runner import Runner
from simgrasp.grasping.trials.scoring import (
    FingerContacts,
    handle_fraction,
    points_in_object_frame,
    relative_pose,
    slip_distance,
)
from simgrasp.grasping.trials.start_states import StartStates
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene


def _empty_record() -> dict[str, Any]:
    """The record fields the phases fill, as a trial that ends before its lift leaves them."""
    return {
        "on_handle": False,
        "handle_fraction": 0.0,
        "lift_height": 0.0,
        "slip_lift": None,
        "slip_perturb": None,
        "contact_points_object": [],
    }


@dataclass
class TrialState:
    """The state one trial's phases share: its inputs (``scene``, ``grasp``, ``config``), the
    control loop (``runner``), wall-clock ``timings`` per phase (s) and the ``record`` fields
    the phases fill (:class:`~simgrasp.grasping.trials.result.TrialResult`'s), plus what a
    phase leaves for the later ones (world frame, m)."""

    scene: Scene
    grasp: Grasp
    config: TrialConfig
    runner: Runner
    on_phase: Callable[[Phase, Scene], None] | None = None
    """Called at the key moments (``pregrasp``, ``closed``, ``lifted``, ``perturbed``); it
    must not change the simulation state."""
    timings: dict[str, float] = field(default_factory=dict)
    record: dict[str, Any] = field(default_factory=_empty_record)
    clock: float = 0.0
    """``time.perf_counter()`` at the end of the previous phase (s)."""
    starts: StartStates | None = None
    """Where a free-floating trial's start is kept and restored from (see ``run_trial``)."""
    world_T_object_settled: NDArray[np.float64] | None = None
    """The object's pose after the settle."""
    tcp_T_object_closed: NDArray[np.float64] | None = None
    """The object's pose in the TCP frame when the jaws had closed."""
    object_z_closed: float = 0.0
    """The object's height when the jaws had closed (m)."""

    def lap(self, name: str) -> None:
        """Record the wall time since the previous lap as phase ``name``."""
        now = time.perf_counter()
        self.timings[name] = now - self.clock
        self.clock = now

    def moment(self, phase: Phase) -> None:
        """Hand the scene to ``on_phase`` at the key moment ``phase``."""
        if self.on_phase:
            self.on_phase(phase, self.scene)

    def held(self) -> FingerContacts:
        """Finger-object contacts now."""
        return self.runner.finger_contacts()

    def slip(self, world_T_object: NDArray[np.float64]) -> float:
        """The object's motion relative to the TCP since the end of the close (m)."""
        world_T_tcp = self.scene.gripper.world_T_tcp(self.scene.data)
        assert self.tcp_T_object_closed is not None, "slip is measured after the close"
        return slip_distance(self.tcp_T_object_closed, relative_pose(world_T_tcp, world_T_object))

    def still_lifted(self, world_T_object: NDArray[np.float64]) -> bool:
        """Whether the object rose at least ``lifted_fraction`` of ``lift_height`` since the
        close (free-floating: sagged less than that)."""
        rise = world_T_object[2, 3] - self.object_z_closed
        limit = self.config.lifted_fraction * self.config.lift_height
        return bool(rise >= -limit if self.config.free_floating else rise >= limit)

    def score_contacts(self) -> FingerContacts:
        """The finger-object contacts now, recorded in the object frame with the share on the
        handle label (``contact_points_object``, ``handle_fraction``, ``on_handle``)."""
        scene, config, record = self.scene, self.config, self.record
        contacts = self.held()
        points_object = points_in_object_frame(contacts.points_world, scene.object_pose())
        handle = scene.object_model.asset.handle
        fraction = handle_fraction(points_object, handle, config.handle_margin)
        record["contact_points_object"] = points_object.tolist()
        record["handle_fraction"] = fraction
        record["on_handle"] = bool(len(points_object)) and fraction >= config.on_handle_threshold
        return contacts
