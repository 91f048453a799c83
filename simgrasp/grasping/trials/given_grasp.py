"""A trial of one given grasp pose (world frame or the object's mesh frame)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from simgrasp.assets.model import ObjectModel
from simgrasp.errors import SimgraspError
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.trials.result import Phase, TrialResult
from simgrasp.grasping.trials.trial import initial_object_pose, run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers.base import Gripper
from simgrasp.scenes.config import SceneConfig
from simgrasp.scenes.scene import Scene, build_scene
from simgrasp.transforms import pose7_to_matrix

GraspFrame = Literal["world", "object"]


def trial_of_grasp(
    object_model: ObjectModel,
    gripper: Gripper,
    pose7: ArrayLike,
    *,
    frame: GraspFrame = "world",
    width: float | None = None,
    scene_config: SceneConfig | None = None,
    trial_config: TrialConfig | None = None,
    phases: Sequence[str] | None = None,
    seed: int = 0,
    on_phase: Callable[[Phase, Scene], None] | None = None,
) -> TrialResult:
    """Execute the TCP pose ``pose7`` (``[x, y, z, qw, qx, qy, qz]``, meters, in ``frame``:
    the world, or the object's mesh frame placed where the trial starts it: its seeded scene
    pose, raised when free-floating, as label-grasps places its grasps) with the jaws opened
    to ``width`` (m; default the gripper's maximum) on the scene of ``seed``; ``phases`` as
    :func:`~simgrasp.grasping.trials.trial.run_trial` takes them (default: those of
    ``trial_config``)."""
    trial_config = trial_config or TrialConfig()
    scene = build_scene(object_model, gripper, scene_config or SceneConfig(), seed)
    width = gripper.max_opening if width is None else width
    if not 0 < width <= gripper.max_opening:
        raise SimgraspError(
            f"--width must be in (0, {gripper.max_opening}] m for gripper {gripper.name!r}, "
            f"got {width}"
        )
    pose = pose7_to_matrix(np.asarray(pose7, dtype=float), "--grasp")
    if frame == "object":
        world_T_object = initial_object_pose(scene, trial_config)
        grasp = Grasp.from_object_frame(pose, world_T_object, width, source="cli")
    else:
        grasp = Grasp(pose, width, source="cli")
    return run_trial(scene, grasp, trial_config, on_phase, phases=phases)
