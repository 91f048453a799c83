"""Scoring a grasp trial in clutter: the neighbors it disturbed, lifted or knocked over.

Success stays the target lifted and held through the tugs (``on_handle`` with it: by its
handle). A trial that failed is named after what went wrong among the neighbors:

- ``wrong_object``: a distractor rose at least ``lifted_fraction`` of ``lift_height`` with the
  gripper. A trial that ended ``missed`` with both fingers on one distractor is lifted on
  (``lift_height`` at ``lift_speed``) to see whether the gripper took it instead;
- ``collision``: when the jaws had closed (or when the trial ended, if before), a distractor
  had turned by more than ``KNOCKED_ANGLE`` or been pushed more than ``KNOCKED_DISTANCE``: the
  approach knocked it over.

``neighbors_disturbed`` counts the distractors that moved more than ``DISTURBED_DISTANCE`` or
turned more than ``DISTURBED_ANGLE`` from their initial pose by the end of the trial (world
frame, m, degrees).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.grasping.trials.result import Phase, TrialResult
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.scenes.scene import Scene
from simgrasp.transforms import make_transform

KNOCKED_ANGLE = 30.0
KNOCKED_DISTANCE = 0.05
DISTURBED_ANGLE = 10.0
DISTURBED_DISTANCE = 0.01


@dataclass
class NeighborWatch:
    """An ``on_phase`` hook that keeps the distractors' poses (4 x 4, world) when the jaws
    have closed; it only reads the state."""

    bodies: list[int]
    closed: list[NDArray[np.float64]] | None = field(default=None)

    @classmethod
    def of(cls, scene: Scene) -> NeighborWatch:
        return cls([scene.model.body(d.body).id for d in scene.distractors])

    def __call__(self, phase: Phase, scene: Scene) -> None:
        if phase == "closed":
            self.closed = _poses(scene, self.bodies)


def _poses(scene: Scene, bodies: list[int]) -> list[NDArray[np.float64]]:
    data = scene.data
    return [make_transform(data.xmat[b].reshape(3, 3), data.xpos[b]) for b in bodies]


def _moved(
    start: NDArray[np.float64], now: NDArray[np.float64], distance: float, angle_deg: float
) -> bool:
    """Whether ``now`` lies more than ``distance`` (m) or ``angle_deg`` from ``start``."""
    turn = np.degrees(np.arccos(np.clip((np.trace(start[:3, :3].T @ now[:3, :3]) - 1) / 2, -1, 1)))
    return bool(np.linalg.norm(now[:3, 3] - start[:3, 3]) > distance or turn > angle_deg)


def score_in_clutter(
    scene: Scene, trial: TrialResult | None, watch: NeighborWatch, config: TrialConfig
) -> dict[str, object]:
    """The clutter fields of a trial's record (``neighbors_disturbed``, and ``failure`` when
    a neighbor explains it), read from ``scene``'s state right after the trial."""
    starts = [d.world_T_object for d in scene.distractors]
    if trial is None:
        return {"neighbors_disturbed": 0}
    fields: dict[str, object] = {}
    if trial.success is False:
        if trial.failure == "missed":
            _lift_on(scene, config)
        ends = _poses(scene, watch.bodies)
        rise = config.lifted_fraction * config.lift_height
        if any(end[2, 3] - start[2, 3] >= rise for start, end in zip(starts, ends, strict=True)):
            fields["failure"] = "wrong_object"
        elif any(
            _moved(start, now, KNOCKED_DISTANCE, KNOCKED_ANGLE)
            for start, now in zip(starts, watch.closed or ends, strict=True)
        ):
            fields["failure"] = "collision"
    ends = _poses(scene, watch.bodies)
    fields["neighbors_disturbed"] = sum(
        _moved(start, end, DISTURBED_DISTANCE, DISTURBED_ANGLE)
        for start, end in zip(starts, ends, strict=True)
    )
    return fields


def _lift_on(scene: Scene, config: TrialConfig) -> None:
    """Lift the closed gripper by ``lift_height`` at ``lift_speed`` when both fingers touch
    one distractor (a trial that ``missed`` the target stops before its lift)."""
    if not _fingers_on_a_distractor(scene):
        return
    model, data, mocap = scene.model, scene.data, scene.gripper.mocap_id
    start = data.mocap_pos[mocap].copy()
    periods = max(1, round(config.lift_height / config.lift_speed / config.control_dt))
    for k in range(1, periods + 1):
        data.mocap_pos[mocap] = start + np.array([0.0, 0.0, config.lift_height * k / periods])
        mujoco.mj_step(model, data, config.control_steps)


def _fingers_on_a_distractor(scene: Scene) -> bool:
    """Whether both fingers touch one and the same distractor now."""
    model, data = scene.model, scene.data
    left, right = (set(fingers) for fingers in scene.gripper.finger_geoms)
    bodies = {model.body(d.body).id for d in scene.distractors}
    touched: dict[int, set[str]] = {}
    for first, second in data.contact.geom.tolist():
        for finger, other in ((first, second), (second, first)):
            body = int(model.geom_bodyid[other])
            if body in bodies and (finger in left or finger in right):
                touched.setdefault(body, set()).add("left" if finger in left else "right")
    return any(len(sides) == 2 for sides in touched.values())
