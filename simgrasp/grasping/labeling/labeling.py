"""Label grasps: one object's scene compiled once, every grasp a trial on it; in memory with
:func:`label_grasps` (arrays in, a :class:`LabelResult` out).

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
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from simgrasp.assets.placement import DEFAULT_PLACEMENT, Placement
from simgrasp.config import setting
from simgrasp.config.checks import Checked, NonNegativeInt
from simgrasp.errors import SimgraspError
from simgrasp.grasping.labeling.grasp_sets import GraspSet
from simgrasp.grasping.trials.protocol import DEFAULT_PROTOCOL, get_protocol, protocol_names
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers.registry import DEFAULT_GRIPPER, gripper_names
from simgrasp.runs.engine import RunConfig, Work, run_tasks

if TYPE_CHECKING:
    from simgrasp.assets.model import ObjectModel
    from simgrasp.grasping.trials.result import Phase
    from simgrasp.scenes.scene import Scene

INVALID = "invalid"
"""The failure of a row that is not a grasp (it is never executed)."""
GRASP_SOURCE = "grasp_set"
Job = tuple[int, NDArray[np.float64], float]
"""(index, object_T_tcp, width) of one grasp to label."""


@dataclass(frozen=True)
class LabelConfig(Checked):
    """What a grasp set is labeled with (importable without MuJoCo).

    Attributes:
        object: YCB id, generated tool name, catalog name or mesh file spec
            (:mod:`simgrasp.assets.mesh_object`); may be left out for grasp files that name
            their object (ACRONYM, GraspGen).
        gripper: a registered gripper (:func:`simgrasp.grippers.gripper_names`).
        protocol: a registered trial protocol (``simgrasp.grasping.trials.protocol``):
            ``full`` (as ``trial``/``evaluate``), ``fast`` (for large grasp sets), ``acronym``
            (ACRONYM's free-floating close and shake), ``acronym-fast`` (its one-cycle shake).
        seed: seed of the scene (the object's rest pose and yaw on the table).
        placement: ``"stable"`` or ``"upright"`` rest poses (:class:`SceneConfig`).
        free_floating: label in free space as ACRONYM does (``TrialConfig.free_floating``):
            the object floats above its rest pose, the gripper closes at the grasp itself and
            the object's weight and the tugs test the hold.
    """

    object: str = setting("", positional=True, metavar="OBJECT")
    gripper: str = setting(DEFAULT_GRIPPER, choices=gripper_names, main=True)
    protocol: str = setting(DEFAULT_PROTOCOL, choices=protocol_names, main=True)
    seed: NonNegativeInt = 0
    placement: Placement = setting(DEFAULT_PLACEMENT, flag="--placement", main=True)
    free_floating: bool = False

    @property
    def trial(self) -> TrialConfig:
        """The trial settings of every grasp: the protocol's, in free space if asked."""
        trial = get_protocol(self.protocol).config
        return replace(trial, free_floating=self.free_floating or trial.free_floating)

    @property
    def phases(self) -> tuple[str, ...]:
        """The phases every grasp's trial runs: the protocol's."""
        return get_protocol(self.protocol).phases


class GraspLabeler:
    """Labels grasps of one object with one gripper and protocol on one compiled scene."""

    def __init__(self, object_model: ObjectModel, config: LabelConfig) -> None:
        from simgrasp.grasping.trials.start_states import StartStates
        from simgrasp.grasping.trials.trial import initial_object_pose
        from simgrasp.grippers import make_gripper
        from simgrasp.scenes.config import SceneConfig
        from simgrasp.scenes.scene import build_scene

        self.config = config
        self.trial_config = config.trial
        self.phases = config.phases
        """The trial phases run (names): change them with ``trial_config``."""
        self.gripper = make_gripper(config.gripper)
        scene_config = SceneConfig(placement=config.placement)
        self.scene: Scene = build_scene(object_model, self.gripper, scene_config, config.seed)
        self.world_T_object = initial_object_pose(self.scene, self.trial_config)
        """Where the object starts (world frame): the grasps are placed relative to it."""
        self.starts = StartStates()
        """Free-floating trials' starts, simulated once per width (their records are those of
        trials that step them): change ``scene.model`` only before the first label."""

    def label(
        self,
        index: int,
        object_T_tcp: NDArray[np.float64],
        width: float,
        on_phase: Callable[[Phase, Scene], None] | None = None,
    ) -> dict[str, Any]:
        """The trial record of one grasp (object frame; ``width`` NaN: fully open), with its
        ``index`` and the ``protocol``; ``on_phase`` as :func:`run_trial` takes it (e.g. a
        :class:`~simgrasp.scenes.key_frames.FrameRecorder`)."""
        from simgrasp.grasping.grasp import Grasp
        from simgrasp.grasping.trials.trial import run_trial

        opening = self.gripper.max_opening if not np.isfinite(width) else float(width)
        grasp = Grasp.from_object_frame(
            np.asarray(object_T_tcp, dtype=float),
            self.world_T_object,
            opening,
            source=GRASP_SOURCE,
        )
        result = run_trial(
            self.scene, grasp, self.trial_config, on_phase, starts=self.starts, phases=self.phases
        )
        record = result.to_json()
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


@functools.lru_cache(maxsize=1)
def cached_labeler(config: LabelConfig, ycb_dir: str | None) -> GraspLabeler:
    """This process's labeler for ``config`` (the scene is built on the first call); only the
    latest is kept, so a worker that labels a data set's files one after another holds one
    object's scene, not all of them."""
    from simgrasp.assets.model import model_for

    return GraspLabeler(model_for(config.object, ycb_dir), config)


def label_one(job: Job, config: LabelConfig, ycb_dir: str | None) -> dict[str, Any]:
    """Label one grasp in this process (the run engine's task)."""
    return cached_labeler(config, ycb_dir).label(*job)


def prepare(config: LabelConfig, ycb_dir: str | None) -> None:
    """Build this process's labeler (worker warm-up)."""
    cached_labeler(config, ycb_dir)


def label_records(
    grasps: GraspSet,
    indices: Sequence[int],
    config: LabelConfig,
    ycb_dir: str | None,
    run: RunConfig,
) -> Iterator[dict[str, Any]]:
    """The records of the rows ``indices`` of ``grasps``: those of invalid rows first (never
    executed), then each executed grasp's as it finishes (:func:`~simgrasp.runs.engine.run_tasks`:
    every worker builds its labeler before the first grasp)."""
    jobs: list[Job] = []
    for index in indices:
        if index in grasps.problems:
            yield invalid_record(index, grasps.problems[index], config)
        else:
            jobs.append((index, grasps.object_T_tcp[index], float(grasps.width[index])))
    if jobs and run.workers > 1:
        from simgrasp.assets.model import model_for

        # built here once, so that its disk caches (CoACD's hulls, an automatic handle label)
        # are filled before the workers build it at the same time
        model_for(config.object, ycb_dir)
    warm_calls = ((),) * run.workers
    work = Work(label_one, (config, ycb_dir), warm_up=prepare, warm_calls=warm_calls)
    yield from run_tasks(work, jobs, run)


@dataclass(frozen=True)
class LabelResult:
    """The labels of a grasp set, in input order.

    Attributes:
        success: (N,) bool, the object was held (``sim_unstable`` and invalid rows: False).
        on_handle: (N,) bool, the fingers touched the handle (share above the trial's bound).
        failure: (N,) str, why a grasp failed (``""`` for a success, ``"invalid"`` for a row
            that is not a grasp).
        handle_fraction: (N,) share of the finger contacts on the handle.
        lift_height: (N,) how high the object was lifted (m).
        records: the full trial record of every row (``index``, ``protocol`` and the trial's
            fields; an invalid row's says its ``problem``).
    """

    success: NDArray[np.bool_]
    on_handle: NDArray[np.bool_]
    failure: NDArray[np.str_]
    handle_fraction: NDArray[np.float64]
    lift_height: NDArray[np.float64]
    records: list[dict[str, Any]]

    @classmethod
    def from_records(cls, records: list[dict[str, Any]]) -> LabelResult:
        """The arrays of ``records`` (in input order)."""
        return cls(
            success=np.array([r["success"] is True for r in records], dtype=bool),
            on_handle=np.array([bool(r["on_handle"]) for r in records], dtype=bool),
            failure=np.array([r["failure"] or "" for r in records], dtype=str),
            handle_fraction=np.array([r["handle_fraction"] for r in records], dtype=float),
            lift_height=np.array([r["lift_height"] for r in records], dtype=float),
            records=records,
        )


def label_grasps(
    obj: str,
    grasps: GraspSet | ArrayLike,
    *,
    config: LabelConfig | None = None,
    workers: int = 1,
    ycb_dir: str | None = None,
) -> LabelResult:
    """Label grasps of object ``obj`` (YCB id or generated tool name) in memory: no file, no
    output directory. ``grasps`` is a :class:`GraspSet` or an (N, 4, 4) ``object_T_grasp``
    array (TCP poses in the object's mesh frame, m; checked by :meth:`GraspSet.from_arrays`,
    invalid rows labeled ``invalid``); ``config`` defaults to ``LabelConfig(obj)`` and must
    name ``obj``; ``workers > 1`` labels in spawned worker processes. The on-disk, resumable
    ``label-grasps`` run gives the same records."""
    if not isinstance(obj, str):
        raise SimgraspError(f"obj must be an object name (str), got {type(obj).__name__}")
    config = config if config is not None else LabelConfig(obj)
    if not isinstance(config, LabelConfig):
        raise SimgraspError(f"config must be a LabelConfig, got {type(config).__name__}")
    if config.object != obj:
        raise SimgraspError(f"label_grasps: config labels {config.object!r}, not {obj!r}")
    grasp_set = grasps if isinstance(grasps, GraspSet) else GraspSet.from_arrays(grasps)
    run = RunConfig(workers=workers, progress=False)
    rows = range(len(grasp_set))
    by_index = {r["index"]: r for r in label_records(grasp_set, rows, config, ycb_dir, run)}
    return LabelResult.from_records([by_index[i] for i in rows])
