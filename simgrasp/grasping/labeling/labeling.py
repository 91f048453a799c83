"""The grasp-labeling engine: one object's scene compiled once, every grasp a trial on it.

A :class:`GraspLabeler` builds the scene of one object, gripper and seed once; each grasp is
then a :func:`~simgrasp.grasping.trials.trial.run_trial` on that scene, which resets the compiled
model's state (``mj_resetData`` and forward kinematics, no rebuild, no rendering) before
executing it. It is the same trial code path as ``simgrasp trial``, ``evaluate`` and the env,
so a grasp labeled with the full protocol has the record ``trial --grasp`` gives it.

Grasps come in the object's mesh frame (``object_T_tcp``, our TCP convention) and are placed
at the object's starting pose (the scene's seeded rest pose, raised into free space with
``free_floating``) before execution.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement, check_placement
from simgrasp.config import setting
from simgrasp.errors import SimgraspError
from simgrasp.grasping.trials.protocol import DEFAULT_PROTOCOL, PROTOCOLS, Protocol
from simgrasp.grasping.trials.trial_config import TrialConfig, protocol_config
from simgrasp.grippers.registry import DEFAULT_GRIPPER, check_gripper_name, gripper_names

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel
    from simgrasp.scenes.scene import Scene

INVALID = "invalid"
"""The failure of a row that is not a grasp (it is never executed)."""
GRASP_SOURCE = "grasp_set"


@dataclass(frozen=True)
class LabelConfig:
    """What a grasp set is labeled with (importable without MuJoCo).

    Attributes:
        object: YCB id, generated tool name, catalog name or mesh file spec
            (:mod:`simgrasp.assets.mesh_object`); may be left out for grasp files that name
            their object (ACRONYM, GraspGen).
        gripper: a registered gripper (:func:`simgrasp.grippers.gripper_names`).
        protocol: trial protocol, ``"full"`` (as ``trial``/``evaluate``) or ``"fast"``.
        seed: seed of the scene (the object's rest pose and yaw on the table).
        placement: ``"stable"`` or ``"upright"`` rest poses (:class:`SceneConfig`).
        free_floating: label in free space as ACRONYM does (``TrialConfig.free_floating``):
            the object floats above its rest pose, the gripper closes at the grasp itself and
            the object's weight and the tugs test the hold.
    """

    object: str = setting("", positional=True, metavar="OBJECT")
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names)
    protocol: Protocol = DEFAULT_PROTOCOL
    seed: int = 0
    placement: Placement = setting(DEFAULT_PLACEMENT, flag="--placement")
    free_floating: bool = False

    def __post_init__(self) -> None:
        if self.protocol not in PROTOCOLS:
            raise SimgraspError(f"unknown protocol {self.protocol!r}; use one of {PROTOCOLS}")
        check_gripper_name(self.gripper)
        if not isinstance(self.seed, int) or self.seed < 0:
            raise SimgraspError(f"seed must be a non-negative integer, got {self.seed!r}")
        check_placement(self.placement)

    @property
    def trial(self) -> TrialConfig:
        """The trial settings of every grasp: the protocol's, in free space if asked."""
        trial = protocol_config(self.protocol)
        return replace(trial, free_floating=self.free_floating or trial.free_floating)


class GraspLabeler:
    """Labels grasps of one object with one gripper and protocol on one compiled scene."""

    def __init__(self, object_model: ObjectModel, config: LabelConfig) -> None:
        from simgrasp.grasping.trials.trial import initial_object_pose
        from simgrasp.grippers import make_gripper
        from simgrasp.scenes.config import SceneConfig
        from simgrasp.scenes.scene import build_scene

        self.config = config
        self.trial_config = config.trial
        self.gripper = make_gripper(config.gripper)
        scene_config = SceneConfig(placement=config.placement)
        self.scene: Scene = build_scene(object_model, self.gripper, scene_config, config.seed)
        self.world_T_object = initial_object_pose(self.scene, self.trial_config)
        """Where the object starts (world frame): the grasps are placed relative to it."""

    def label(self, index: int, object_T_tcp: NDArray[np.float64], width: float) -> dict[str, Any]:
        """The trial record of one grasp (object frame; ``width`` NaN: fully open), with its
        ``index`` and the ``protocol``."""
        from simgrasp.grasping.grasp import Grasp
        from simgrasp.grasping.trials.trial import run_trial

        opening = self.gripper.max_opening if not np.isfinite(width) else float(width)
        grasp = Grasp.from_object_frame(
            np.asarray(object_T_tcp, dtype=float),
            self.world_T_object,
            opening,
            source=GRASP_SOURCE,
        )
        record = run_trial(self.scene, grasp, self.trial_config).to_json()
        return {"index": int(index), "protocol": self.config.protocol, **record}


def invalid_record(index: int, problem: str, config: LabelConfig) -> dict[str, Any]:
    """The record of a row that is not a grasp: failure ``invalid``, never executed."""
    return {
        "index": int(index),
        "protocol": config.protocol,
        "object": config.object,
        "gripper": config.gripper,
        "seed": config.seed,
        "success": False,
        "failure": INVALID,
        "problem": problem,
        "on_handle": False,
        "handle_fraction": 0.0,
        "lift_height": 0.0,
    }


@functools.cache
def cached_labeler(config: LabelConfig, ycb_dir: str | None) -> GraspLabeler:
    """This process's labeler for ``config`` (the scene is built on the first call)."""
    from simgrasp.assets.model import model_for

    return GraspLabeler(model_for(config.object, ycb_dir), config)


def label_one(
    config: LabelConfig, ycb_dir: str | None, index: int, object_T_tcp: NDArray, width: float
) -> dict[str, Any]:
    """Label one grasp in this process (worker entry point)."""
    return cached_labeler(config, ycb_dir).label(index, object_T_tcp, width)


def prepare(config: LabelConfig, ycb_dir: str | None) -> None:
    """Build this process's labeler (worker warm-up)."""
    cached_labeler(config, ycb_dir)
