"""The methods ``simgrasp bench run`` scores in process: a registered proposer or the user's
``MODULE:FUNCTION``.

A method is a function of one :class:`~simgrasp.bench.observation.BenchObservation` returning
its answer: the grasp file's table (``{"grasps": [{"world_T_tcp": ..., "width": ...}]}``), its
list, or :class:`~simgrasp.grasping.grasp.Grasp` objects, best first
(:mod:`simgrasp.bench.grasp_files`). A proposer of :mod:`simgrasp.grasping.proposers`
(``quadric``, ``tenpas``, ``centroid``, ``random``) runs with its chain defaults on the cut
cloud, its normals turned toward the cameras, clear of the neighbors' points; ``antipodal``
(:class:`AntipodalMethod`) draws the random baseline's pairs until it has N grasps, for a
best-of-N with ``--attempts N``.
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
        from simgrasp.grasping.planning.planner_config import PlannerConfig
        from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS, plan_grasps
        from simgrasp.grasping.trials.chain_config import ChainDetectorConfig

        if len(observation.cloud) < MIN_CLOUD_POINTS:
            return []
        detector = ChainDetectorConfig(kind=self.name)
        geometry = gripper_geometry(observation)
        view = cloud_view(observation)
        grasps, _ = plan_grasps(view, geometry, detector, PlannerConfig(), observation.seed)
        return grasps


@dataclass(frozen=True)
class AntipodalMethod:
    """``antipodal``: the random antipodal baseline's point pairs of the cloud
    (:func:`~simgrasp.grasping.planning.planner.antipodal_grasps`), drawn round after round
    until ``count`` grasps are found (at most ``rounds`` rounds), in the order drawn: with
    ``--attempts N`` the best of N tries, the oracle's trial budget without its mesh."""

    count: int = 8
    rounds: int = 20

    def __call__(self, observation: BenchObservation) -> Any:
        from simgrasp.grasping.planning.planner import antipodal_grasps
        from simgrasp.grasping.planning.planner_config import PlannerConfig
        from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS
        from simgrasp.seeding import rng_for

        if len(observation.cloud) < MIN_CLOUD_POINTS:
            return []
        view, geometry = cloud_view(observation), gripper_geometry(observation)
        rng = rng_for(observation.seed, "bench", "antipodal")
        grasps: list[Any] = []
        for _ in range(self.rounds):
            grasps += antipodal_grasps(
                view.points_world,
                view.normals_world,
                geometry,
                view.table_top_z,
                rng,
                PlannerConfig(),
                view.scene_obstacles_world,
            )
            if len(grasps) >= self.count:
                break
        return grasps[: self.count]


BENCH_METHODS = {"antipodal": AntipodalMethod()}
"""Methods of the bench beyond the registered proposers."""


def cloud_view(observation: BenchObservation) -> Any:
    """The observation as a proposer's :class:`~simgrasp.grasping.cloud_view.CloudView`: the
    cut cloud, its normals turned toward the cameras, the neighbors' points as obstacles."""
    from simgrasp.grasping.cloud_view import CloudView
    from simgrasp.scenes.observe import ObjectCloud, viewpoint_normals

    cloud = ObjectCloud(observation.cloud, observation.cloud_viewpoints, (), ())
    obstacles = observation.obstacle_cloud if len(observation.obstacle_cloud) else None
    return CloudView.from_views(
        cloud.points_world,
        viewpoint_normals(cloud),
        cloud.viewpoints_world,
        observation.table_top_z,
        obstacles,
    )


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
    if name not in PROPOSERS and name not in BENCH_METHODS:
        choices = ", ".join([*PROPOSERS, *BENCH_METHODS])
        raise SimgraspError(f"--method {name!r}: choose one of {choices} or MODULE:FUNCTION")
    return name


def load_method(name: str) -> Method:
    """The method ``name`` (:func:`check_method`): its module imported now; an error naming
    the module or function that cannot be found."""
    check_method(name)
    if name in BENCH_METHODS:
        return BENCH_METHODS[name]
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
