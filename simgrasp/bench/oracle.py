"""What was possible in each scene: grasps sampled with the object's true mesh and label,
executed in the scene itself.

Per scene, the antipodal sampler (:mod:`simgrasp.grasping.planning.antipodal`) draws
``OracleBudget.samples`` grasps on the target's mesh at its settled pose, clear of the table;
those whose open gripper would hold a neighbor's surface are dropped. A grasp whose two
contacts (the TCP +- half the contact width along the jaws) both lie on the labeled handle
(grown by ``HANDLE_CONTACT_MARGIN``) is a handle grasp. Up to ``handle_trials`` handle grasps
are executed (the suite's protocol), stopping at the first that lifts and holds the object
by its handle: the scene is ``solvable``. Unless one lifted it already, up to
``lift_trials`` of the other grasps are executed for ``liftable`` (held anyhow). The oracle
sees no camera, so its record is one per world (:attr:`~simgrasp.bench.suites.BenchScene.world`:
the scenes that differ only in their sensor share it). Every draw comes from the scene's
seed, so the oracle is computed once per suite and kept in the cache
(``$SIMGRASP_CACHE_DIR/bench/SUITE-DIGEST/oracle.jsonl``), resumable as any run.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import numpy as np
import trimesh
from numpy.typing import NDArray

from simgrasp.bench.scene_build import build_bench_scene, chain_config
from simgrasp.bench.suites import BenchScene, SuiteDefinition
from simgrasp.errors import SimgraspError
from simgrasp.grasping.grasp import Grasp
from simgrasp.grasping.planning.antipodal import AntipodalConfig, Table, sample_antipodal
from simgrasp.grasping.planning.clearance import gripper_distances
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.labels import Box, Capsule, Region
from simgrasp.scenes.scene import Scene
from simgrasp.seeding import rng_for

HANDLE_CONTACT_MARGIN = 0.01
"""A sampled contact within this distance (m) of a handle region is on it (the sampler
shifts the TCP up to 1 cm along the approach)."""
NEIGHBOR_POINTS = 1500
"""Surface samples of each neighbor the open gripper must not hold."""


def oracle_record(suite: SuiteDefinition, scene: BenchScene) -> dict[str, Any]:
    """The oracle's record of ``scene`` (module docstring)."""
    start, cpu = time.perf_counter(), time.process_time()
    built = build_bench_scene(suite, scene)
    config = chain_config(suite, scene).trial
    budget = suite.oracle
    handle, other, sampled = oracle_candidates(built, budget.samples, budget.rounds)
    solved, handle_tries, lifted = _first_hold(built, handle[: budget.handle_trials], config)
    lift_tries = 0
    if not lifted:
        _, lift_tries, lifted = _first_hold(built, other[: budget.lift_trials], config)
    axes = {k: v for k, v in scene.axes().items() if k != "sensor"}
    return {
        "world": scene.world,
        "suite": suite.name,
        "suite_sha256": suite.digest(),
        **axes,
        "seed": scene.seed,
        "sampled": sampled,
        "handle_candidates": len(handle),
        "handle_trials": handle_tries,
        "lift_trials": lift_tries,
        "solvable": solved is not None,
        "liftable": lifted,
        "solving_grasp": None if solved is None else solved.to_pose7().tolist(),
        "timings_s": {"total": time.perf_counter() - start, "cpu": time.process_time() - cpu},
    }


def oracle_task(scene: BenchScene, suite: SuiteDefinition) -> dict[str, Any]:
    """:func:`oracle_record` as a run's task (the scene first)."""
    return oracle_record(suite, scene)


def _first_hold(
    scene: Scene, grasps: list[Grasp], config: TrialConfig
) -> tuple[Grasp | None, int, bool]:
    """Execute ``grasps`` in turn until one holds the object by its handle: that grasp (or
    None), the trials run and whether any trial lifted and held the object."""
    lifted = False
    for tries, grasp in enumerate(grasps, start=1):
        trial = run_trial(scene, grasp, config)
        lifted = lifted or bool(trial.success)
        if trial.success and trial.on_handle:
            return grasp, tries, True
    return None, len(grasps), lifted


def oracle_candidates(
    scene: Scene, samples: int, rounds: int
) -> tuple[list[Grasp], list[Grasp], int]:
    """The sampled grasps clear of the neighbors, on the handle and elsewhere (in sampled
    order), and how many were sampled."""
    model, world_T_object = scene.object_model, scene.world_T_object
    geometry = scene.gripper.gripper.planning_geometry()
    table = Table(world_T_object, scene.config.table_top_z)
    try:
        object_T_tcp, widths = sample_antipodal(
            model.asset.mesh,
            geometry,
            samples,
            scene.seed,
            AntipodalConfig(max_rounds=rounds),
            table,
        )
    except SimgraspError:  # no antipodal grasp fits this object and gripper
        return [], [], 0
    neighbors = _neighbor_points(scene)
    handle: list[Grasp] = []
    other: list[Grasp] = []
    for pose, width in zip(object_T_tcp, widths, strict=True):
        world_T_tcp = world_T_object @ pose
        open_geometry = replace(geometry, max_opening=float(width))
        if len(neighbors) and np.any(gripper_distances(world_T_tcp, neighbors, open_geometry) <= 0):
            continue
        grasp = Grasp(world_T_tcp, float(width), source="oracle")
        (handle if _on_handle(scene, pose, float(width)) else other).append(grasp)
    return handle, other, len(widths)


def _on_handle(scene: Scene, object_T_tcp: NDArray[np.float64], width: float) -> bool:
    """Whether both contacts of a sampled grasp (object frame) lie on the labeled handle (any
    grasp does on an object graspable as a handle everywhere: a can, a fruit)."""
    label = scene.object_model.asset.handle
    if label.whole_object or not label.has_handle:
        return label.whole_object
    half = max(width / 2 - AntipodalConfig().width_margin, 0.0)
    closing = object_T_tcp[:3, 1]
    contacts = object_T_tcp[:3, 3] + np.outer([half, -half], closing)
    grown = [_grown(region) for region in label.regions]
    return bool(np.all(np.any([region.contains(contacts) for region in grown], axis=0)))


def _grown(region: Region) -> Region:
    """``region`` grown by ``HANDLE_CONTACT_MARGIN`` on every side."""
    if isinstance(region, Capsule):
        return replace(region, radius=region.radius + HANDLE_CONTACT_MARGIN)
    assert isinstance(region, Box)
    return replace(region, half_extents=region.half_extents + HANDLE_CONTACT_MARGIN)


def _neighbor_points(scene: Scene) -> NDArray[np.float64]:
    """Seeded surface samples (world frame) of the scene's neighbors; none alone."""
    points = []
    for index, neighbor in enumerate(scene.distractors):
        seed = int(rng_for(scene.seed, "bench", "oracle", index).integers(2**31))
        samples, _ = trimesh.sample.sample_surface(
            neighbor.model.asset.mesh, NEIGHBOR_POINTS, seed=seed
        )
        pose = neighbor.world_T_object
        points.append(samples @ pose[:3, :3].T + pose[:3, 3])
    return np.concatenate(points, axis=0) if points else np.zeros((0, 3))
