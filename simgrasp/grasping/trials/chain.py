"""The full chain of one grasp trial: observe -> detect -> plan -> execute -> score.

One seed fixes everything random: the object's rest pose and yaw (scene), cloud noise, the
detector's neighborhood sampling, the planner's approach jitter. The settings are one
:class:`~simgrasp.grasping.trials.chain_config.ChainConfig`.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from simgrasp.assets.model import ObjectModel
from simgrasp.grasping.cloud_view import CloudView
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.proposal import MIN_CLOUD_POINTS, plan_grasps
from simgrasp.grasping.session import Session
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grasping.trials.clutter_scoring import NeighborWatch, score_in_clutter
from simgrasp.grasping.trials.result import Phase, TrialResult
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grippers import make_gripper
from simgrasp.grippers.base import Gripper
from simgrasp.handles.accuracy import score_detection
from simgrasp.handles.core.detection import Detection
from simgrasp.scenes.observe import ObjectCloud, observe, viewpoint_normals
from simgrasp.scenes.perceive import perceive_target
from simgrasp.scenes.scene import Scene, build_scene


@dataclass(frozen=True)
class ChainResult:
    """A full-chain trial: what was seen, detected, chosen and what happened.

    ``cloud_points``, ``candidates``, ``handles`` and ``grasp_candidates`` are counts (the
    fused object cloud's points, the detector's accepted neighborhoods, its handles, the
    planner's grasps); ``detection_accuracy`` is the share of candidates on the labeled handle
    (None without candidates) and ``handle_recall`` whether a handle's center lies on it (both
    None when the detector did not run);
    ``trial`` is the executed grasp's :class:`~simgrasp.grasping.trials.result.TrialResult`,
    None when no grasp was found (``failure`` ``no_grasp`` in the record). ``to_json()`` is the
    flat record ``trials.jsonl`` holds.
    """

    object: str
    detector: str
    gripper: str
    noise: float
    seed: int
    cloud_points: int
    candidates: int
    handles: int
    detection_accuracy: float | None
    handle_recall: bool | None
    grasp_candidates: int
    trial: TrialResult | None
    timings_s: dict[str, float]
    scene_fields: dict[str, Any] = field(default_factory=dict)
    """Fields of a cluttered scene or of a segmented cut (``clutter``, ``perception``,
    ``target_iou``, ...; a ``failure`` a neighbor explains), merged into the record; empty for
    one object cut by the mask."""

    @property
    def success(self) -> bool | None:
        return False if self.trial is None else self.trial.success

    @property
    def failure(self) -> str | None:
        """Why the chain did not succeed, as its record says: a neighbor's doing in clutter
        (``wrong_object``, ``collision``), ``no_grasp`` when the detector and planner gave no
        grasp to execute (no handle found included), else the trial's failure
        (:data:`~simgrasp.grasping.trials.result.Failure`); None on success."""
        if "failure" in self.scene_fields:
            return str(self.scene_fields["failure"])
        return "no_grasp" if self.trial is None else self.trial.failure

    @property
    def on_handle(self) -> bool:
        return self.trial is not None and self.trial.on_handle and bool(self.trial.success)

    def to_json(self) -> dict[str, Any]:
        """One flat record: the trial's fields, the chain's fields and merged timings."""
        trial = self.trial.to_json() if self.trial else _NO_GRASP_RECORD
        chain = {k: v for k, v in self.__dict__.items() if k not in ("trial", "scene_fields")}
        record = {**trial, **chain, **self.scene_fields}
        record["timings_s"] = {**trial.get("timings_s", {}), **self.timings_s}
        record["success"] = self.success
        record["failure"] = self.failure
        record["on_handle"] = self.on_handle
        return record


_NO_GRASP_RECORD: dict[str, Any] = {
    "object_pose": None,
    "grasp": None,
    "success": False,
    "failure": "no_grasp",
    "on_handle": False,
    "lift_height": 0.0,
    "timings_s": {},
}


def propose_grasps(
    scene: Scene,
    cloud: ObjectCloud,
    config: ChainConfig,
    seed: int,
    scene_obstacles_world: np.ndarray | None = None,
) -> tuple[list[Grasp], Detection | None]:
    """Ranked grasps from the configured detector (or baseline) on the observed cloud, clear
    of ``scene_obstacles_world`` (the rest of a cluttered scene)."""
    if len(cloud) < MIN_CLOUD_POINTS:
        return [], None
    view = CloudView.from_views(
        cloud.points_world,
        viewpoint_normals(cloud),
        cloud.viewpoints_world,
        scene.config.table_top_z,
        scene_obstacles_world,
    )
    geometry = scene.gripper.gripper.planning_geometry()
    return plan_grasps(view, geometry, config.detector, config.planner, seed)


def run_chain(
    object_model: ObjectModel,
    config: ChainConfig,
    seed: int,
    gripper: Gripper | None = None,
    on_phase: Callable[[Phase, Scene], None] | None = None,
    session: Session | None = None,
) -> ChainResult:
    """Observe, detect, plan and execute the best-ranked grasp on ``object_model``;
    ``on_phase`` is passed to :func:`run_trial` (e.g. to render key frames). The depth views
    are rendered with ``session``'s renderer (without one, a renderer made for this trial and
    closed before it returns)."""
    with contextlib.ExitStack() as owned:
        if session is None:
            session = owned.enter_context(Session())
        return _chain(
            object_model, config, seed, gripper or make_gripper(config.gripper), on_phase, session
        )


def _chain(
    object_model: ObjectModel,
    config: ChainConfig,
    seed: int,
    gripper: Gripper,
    on_phase: Callable[[Phase, Scene], None] | None,
    session: Session,
) -> ChainResult:
    """:func:`run_chain` with its gripper and session given."""
    timings: dict[str, float] = {}
    clock = time.perf_counter()

    def lap(name: str) -> None:
        nonlocal clock
        now = time.perf_counter()
        timings[name], clock = now - clock, now

    scene = build_scene(object_model, gripper, config.scene, seed)
    lap("scene")
    renderer = session.renderers.renderer_for(scene)
    observation = observe(scene, renderer, config.noise, seed, config.sensor)
    if config.perception_mode == "mask":  # the mask's cut, fused in the render stage
        cloud = observation.cloud  # (our segmenter's cut never needs it)
    lap("render")
    perceived, fields = None, {}
    if config.scene.clutter or config.perception_mode != "mask":
        perceived = perceive_target(
            scene, observation, config.perception_mode, config.noise, seed, config.segment
        )
        fields = {"perception": config.perception_mode, "target_iou": perceived.target_iou}
        lap("segment")
    cloud = perceived.cloud if perceived else observation.cloud
    obstacles = perceived.obstacles_world if perceived else None
    grasps, detection = propose_grasps(scene, cloud, config, seed, obstacles)
    lap("detect_and_plan")
    object_T_world = np.linalg.inv(scene.world_T_object).astype(np.float64)
    accuracy, recall = score_detection(detection, object_T_world, object_model.asset.handle)
    trial, fields = _executed(scene, grasps, config, on_phase, fields)
    return ChainResult(
        object=object_model.asset.name,
        detector=config.detector.kind,
        gripper=gripper.name,
        noise=config.noise,
        seed=seed,
        cloud_points=len(cloud),
        candidates=len(detection.candidates) if detection else 0,
        handles=len(detection.handles) if detection else 0,
        detection_accuracy=accuracy,
        handle_recall=recall,
        grasp_candidates=len(grasps),
        trial=trial,
        timings_s=timings,
        scene_fields=fields,
    )


def _executed(
    scene: Scene,
    grasps: list[Grasp],
    config: ChainConfig,
    on_phase: Callable[[Phase, Scene], None] | None,
    fields: dict[str, Any],
) -> tuple[TrialResult | None, dict[str, Any]]:
    """The trial of the best grasp (None without one) and the record's scene fields, with
    the clutter scoring's (:mod:`simgrasp.grasping.trials.clutter_scoring`) in clutter."""
    if not config.scene.clutter:
        return (run_trial(scene, grasps[0], config.trial, on_phase) if grasps else None), fields
    watch = NeighborWatch.of(scene)

    def phase_hook(phase: Phase, at: Scene) -> None:
        watch(phase, at)
        if on_phase is not None:
            on_phase(phase, at)

    trial = run_trial(scene, grasps[0], config.trial, phase_hook) if grasps else None
    clutter = {
        "clutter": config.scene.clutter,
        "distractors": [d.object_name for d in scene.distractors],
    }
    return trial, {**clutter, **fields, **score_in_clutter(scene, trial, watch, config.trial)}
