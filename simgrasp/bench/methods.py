"""The methods ``simgrasp bench run`` scores in process: a registered proposer or the user's
``MODULE:FUNCTION``.

A method is a function of one :class:`~simgrasp.bench.observation.BenchObservation` returning
its answer: the grasp file's table (``{"grasps": [{"world_T_tcp": ..., "width": ...}]}``), its
list, or :class:`~simgrasp.grasping.grasp.Grasp` objects, best first
(:mod:`simgrasp.bench.grasp_files`). A proposer of :mod:`simgrasp.grasping.proposers`
(``quadric``, ``tenpas``, ``centroid``, ``random``) runs with its chain defaults on the cut
cloud, its normals turned toward the cameras, clear of the neighbors' points.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from simgrasp.bench.observation import BenchObservation
from simgrasp.errors import SimgraspError
from simgrasp.grasping.proposers import PROPOSERS, proposer_entry

Method = Callable[[BenchObservation], Any]


@dataclass(frozen=True)
class ProposerMethod:
    """The registered proposer ``name`` as a bench method."""

    name: str

    def __call__(self, observation: BenchObservation) -> Any:
        from simgrasp.grasping.cloud_view import CloudView
        from simgrasp.grasping.planning.planner_config import PlannerConfig
        from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS, plan_grasps
        from simgrasp.grasping.trials.chain_config import ChainDetectorConfig
        from simgrasp.scenes.observe import ObjectCloud, viewpoint_normals

        if len(observation.cloud) < MIN_CLOUD_POINTS:
            return []
        cloud = ObjectCloud(observation.cloud, observation.cloud_viewpoints, (), ())
        obstacles = observation.obstacle_cloud if len(observation.obstacle_cloud) else None
        view = CloudView.from_views(
            cloud.points_world,
            viewpoint_normals(cloud),
            cloud.viewpoints_world,
            observation.table_top_z,
            obstacles,
        )
        detector = ChainDetectorConfig(kind=self.name)
        geometry = gripper_geometry(observation)
        grasps, _ = plan_grasps(view, geometry, detector, PlannerConfig(), observation.seed)
        return grasps


def gripper_geometry(observation: BenchObservation) -> Any:
    """The observation's gripper as the planner's
    :class:`~simgrasp.grippers.geometry.GripperGeometry`."""
    from simgrasp.grippers.geometry import GripperGeometry

    given = observation.gripper
    values = {f.name: given[f.name] for f in fields(GripperGeometry) if f.name in given}
    values["palm_size"] = tuple(np.asarray(values["palm_size"], dtype=float).tolist())
    return GripperGeometry(**values)


def check_method(name: str) -> str:
    """``name`` if it names a registered proposer or has the form ``MODULE:FUNCTION``; an
    error listing the choices otherwise."""
    if ":" in name:
        module, _, function = name.partition(":")
        if not module or not function:
            raise SimgraspError(f"--method {name!r}: give MODULE:FUNCTION")
        return name
    if name not in PROPOSERS:
        raise SimgraspError(
            f"--method {name!r}: choose one of {', '.join(PROPOSERS)} or MODULE:FUNCTION"
        )
    return name


def load_method(name: str) -> Method:
    """The method ``name`` (:func:`check_method`): its module imported now; an error naming
    the module or function that cannot be found."""
    check_method(name)
    if ":" not in name:
        proposer_entry(name)
        return ProposerMethod(name)
    module_name, _, function_name = name.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as error:
        raise SimgraspError(f"--method {name}: cannot import {module_name} ({error})") from None
    function = getattr(module, function_name, None)
    if not callable(function):
        raise SimgraspError(f"--method {name}: {module_name} has no function {function_name}")
    return function
