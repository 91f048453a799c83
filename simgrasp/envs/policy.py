"""A scripted policy for ``simgrasp/HandleGrasp-v0``: the chain's detectors as observation ->
action.

:class:`DetectorPolicy` plans with the very function the chain plans with
(:func:`simgrasp.grasping.planning.proposal.plan_grasps`), on the observation's cloud, normals and
the centers of the cameras that saw the cloud, and returns the best-ranked grasp as an action.
Given the episode seed, it proposes exactly the grasp ``run_chain`` executes for that object
and seed when the env and the chain share gripper, noise and scene (and the cloud was not
subsampled, see :mod:`simgrasp.envs.observation`).

Fallback: when the cloud has fewer than ``MIN_CLOUD_POINTS`` points or no grasp survives
planning (the chain would then run no trial), the action is a top-down grasp (approach world
-z, jaws opening along world y) at full opening, centered on the cloud's centroid (on the table
top at the world origin for an empty cloud) and raised until the gripper clears the table.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import gymnasium
import numpy as np
from numpy.typing import NDArray

from simgrasp.config import build as build_settings
from simgrasp.envs.action import action_from_grasp
from simgrasp.envs.handle_grasp import HandleGraspEnv
from simgrasp.envs.observation import Observation
from simgrasp.grasping.cloud_view import CloudView
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.planner import top_down_above_table
from simgrasp.grasping.planning.planner_config import PlannerConfig
from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS, plan_grasps
from simgrasp.grasping.trials.chain_config import ChainDetectorConfig
from simgrasp.grippers import DEFAULT_GRIPPER, make_gripper
from simgrasp.grippers.geometry import GripperGeometry

FALLBACK_SOURCE = "fallback"
"""``Grasp.source`` of the fallback grasp."""


@dataclass(frozen=True)
class DetectorPolicy:
    """Grasp actions from a handle detector (``"quadric"``, ``"tenpas"``) or a baseline
    (``"centroid"``, ``"random"``), for ``gripper`` over a table top at ``table_top_z`` (world
    z, meters); :meth:`for_env` takes both from an env."""

    detector: str | ChainDetectorConfig = "quadric"
    """A proposer's name (with default thresholds) or its full settings."""
    gripper: str = DEFAULT_GRIPPER
    table_top_z: float = 0.0
    planner: PlannerConfig = field(default_factory=PlannerConfig)
    geometry: GripperGeometry = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.detector, ChainDetectorConfig):
            object.__setattr__(
                self, "detector", build_settings(ChainDetectorConfig, {"kind": self.detector})
            )
        object.__setattr__(self, "geometry", make_gripper(self.gripper).planning_geometry())

    @classmethod
    def for_env(
        cls,
        env: gymnasium.Env,
        detector: str | ChainDetectorConfig = "quadric",
        planner: PlannerConfig | None = None,
    ) -> DetectorPolicy:
        """The policy for ``env`` (a possibly wrapped :class:`HandleGraspEnv`): its gripper
        and table height."""
        unwrapped = env.unwrapped
        if not isinstance(unwrapped, HandleGraspEnv):
            raise TypeError(f"DetectorPolicy.for_env needs a HandleGraspEnv, got {unwrapped!r}")
        config = unwrapped.config
        return cls(detector, config.gripper, config.scene.table_top_z, planner or PlannerConfig())

    @property
    def detector_config(self) -> ChainDetectorConfig:
        assert isinstance(self.detector, ChainDetectorConfig)  # normalized by __post_init__
        return self.detector

    def plan(self, observation: Observation, seed: int) -> Grasp:
        """The best grasp (world frame) on the observed cloud, or the fallback grasp; ``seed``
        (the episode seed, to match the chain) seeds the detector and the planner."""
        valid = observation["valid"].astype(bool)
        points_world = observation["points_world"][valid]
        if len(points_world) < MIN_CLOUD_POINTS:
            return self.fallback(points_world)
        view = CloudView.from_views(
            points_world,
            observation["normals_world"][valid],
            observation["world_T_cam"][observation["view_index"][valid], :3, 3],
            self.table_top_z,
        )
        grasps, _ = plan_grasps(view, self.geometry, self.detector_config, self.planner, seed)
        return grasps[0] if grasps else self.fallback(points_world)

    def act(self, observation: Observation, seed: int) -> NDArray[np.float64]:
        """The action ``[x, y, z, qw, qx, qy, qz, width]`` of :meth:`plan`."""
        return action_from_grasp(self.plan(observation, seed))

    def fallback(self, points_world: NDArray[np.float64]) -> Grasp:
        """The documented fallback grasp (module docstring) for the cloud ``points_world``."""
        center = (
            points_world.mean(axis=0) if len(points_world) else np.array([0, 0, self.table_top_z])
        )
        world_T_tcp = top_down_above_table(
            center, (0.0, 1.0, 0.0), self.geometry, self.table_top_z, self.planner
        )
        return Grasp(world_T_tcp, self.geometry.max_opening, score=0.0, source=FALLBACK_SOURCE)
