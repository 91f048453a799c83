"""Grasp labeling speed: labeled grasps per second per core, and the harness over raw mj_step.

For each object (default the YCB hammer and mug) and gripper, ``--n`` antipodal grasps are
sampled (``simgrasp sample-grasps``, seed 0, clear of the table of scene seed 0) and labeled
in this one process, once per protocol (``fast``, ``full``, ACRONYM's free-floating close
and shake ``acronym`` and its one-cycle shake ``acronym-fast``), on one compiled scene
(:class:`GraspLabeler`), after one untimed warm-up grasp. In the same run, the baseline of
the ratio, ``raw``: each of the first ``--raw`` grasps is labeled again right after its timed
labeling (the simulation is deterministic: the same steps from the same states) timing only
the time spent inside ``mj_step``, so ``over raw`` is the harness's overhead alone (reset,
checks, contact scoring, records), measured at the same moment of this virtual machine, whose
speed swings. A replay
of recorded states cannot serve here: the fast protocol lets the resting object sleep, and
which bodies sleep is not part of MuJoCo's state vector.

Grippers: the built-in one, the Robotiq 2F-85 (needs ``MENAGERIE_ROOT``; without it its rows
are skipped with a message) and the Franka hand (``franka_panda``, ACRONYM's).
Last, one settle phase is stepped with ``mujoco.rollout`` against the engine's ``mj_step``
chunks (the engine keeps ``mj_step``: see the printed ratio).

    python benchmarks/bench_label.py [--n 500] [--raw 50] [--json]

Goals: >= 25 grasps/s per core with ``fast`` and the built-in gripper, and with the ACRONYM
protocol and the Franka hand (``acronym``, or its fast variant ``acronym-fast``, whose agreement
with ``acronym`` on ACRONYM's grasps is in ``docs/results/acronym-fast/``); over raw <= 1.2.
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time
from dataclasses import dataclass

import numpy as np
from mujoco import rollout
from step_replay import timed_steps  # noqa: E402  (this folder)

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import model_for
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.config.fields import setting
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig
from simgrasp.grasping.planning.antipodal import Table, sample_antipodal
from simgrasp.grasping.trials.protocol import protocol_names
from simgrasp.grippers import gripper_names, make_gripper


def bench_protocol(model, obj: str, gripper: str, protocol: str, grasps, raw: int) -> dict:
    labeler = GraspLabeler(model, LabelConfig(obj, gripper, protocol))
    labeler.label(-1, *grasps[0])  # warm-up, not timed: first calls import and allocate
    walls, steps, held, physics = [], 0, 0, 0.0
    for index, (pose, width) in enumerate(grasps):
        start = time.perf_counter()
        record = labeler.label(index, pose, width)
        walls.append(time.perf_counter() - start)
        steps += record["steps"]
        held += record["success"] is True
        if index < raw:  # the same grasp again right away: the machine's speed is the same
            with timed_steps(labeler.scene.model) as seconds:
                labeler.label(index, pose, width)
            physics += seconds[0]
    subset = grasps[:raw]
    return {
        "object": obj,
        "gripper": gripper,
        "protocol": protocol,
        "grasps": len(grasps),
        "success_share": held / len(grasps),
        "grasps_per_s": len(grasps) / sum(walls),
        "median_ms": 1e3 * statistics.median(walls),
        "steps_per_grasp": steps / len(grasps),
        "us_per_step": 1e6 * sum(walls) / steps,
        "over_raw": sum(walls[: len(subset)]) / physics,
        "raw_grasps": len(subset),
    }


def reference_us_per_step(model, obj: str) -> float:
    """This machine's speed now: raw ``mj_step`` of the object resting on the table, gripper
    parked (full protocol: nothing asleep), microseconds per step, median of 7 x 1000 steps.
    Runs at different times of this virtual machine differ by up to 1.4 x; this line shows how
    fast the machine ran."""
    labeler = GraspLabeler(model, LabelConfig(obj, "builtin", "full"))
    m, d = labeler.scene.model, labeler.scene.data
    times = []
    for _ in range(7):
        mujoco.mj_resetData(m, d)
        start = time.perf_counter()
        mujoco.mj_step(m, d, 1000)
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def rollout_check(model, obj: str) -> dict:
    """One settle phase (the full protocol's 250 steps): ``mujoco.rollout`` against the
    engine's ``mj_step`` chunks of 10, medians of 7."""
    labeler = GraspLabeler(model, LabelConfig(obj, "builtin", "full"))
    m, d = labeler.scene.model, labeler.scene.data
    steps = int(round(labeler.trial_config.settle_time / labeler.trial_config.timestep))
    mujoco.mj_resetData(m, d)
    initial = np.empty(mujoco.mj_stateSize(m, mujoco.mjtState.mjSTATE_FULLPHYSICS))
    mujoco.mj_getState(m, d, initial, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    stepped, rolled = [], []
    for _ in range(7):
        mujoco.mj_resetData(m, d)
        start = time.perf_counter()
        for _ in range(steps // 10):
            mujoco.mj_step(m, d, 10)
        stepped.append(time.perf_counter() - start)
        start = time.perf_counter()
        rollout.rollout(m, d, initial[None], nstep=steps)
        rolled.append(time.perf_counter() - start)
    return {
        "settle_steps": steps,
        "mj_step_ms": 1e3 * statistics.median(stepped),
        "rollout_ms": 1e3 * statistics.median(rolled),
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    n: PositiveInt = 500
    """Antipodal grasps sampled per object and gripper, each labeled once per protocol."""
    raw: PositiveInt = 50
    """Grasps labeled again timing only ``mj_step``: the baseline of ``over raw``."""
    objects: tuple[str, ...] = ("048_hammer", "025_mug")
    """Objects (a YCB id reads ``$SIMGRASP_YCB_DIR``); the first also gives the machine
    reference and the rollout check."""
    protocols: tuple[str, ...] = setting(
        ("fast", "full", "acronym", "acronym-fast"), choices=protocol_names
    )
    """Trial protocols, each timed on the same grasps."""
    grippers: tuple[str, ...] = setting(
        ("builtin", "robotiq_2f85", "franka_panda"), choices=gripper_names
    )
    """Grippers (``robotiq_2f85`` is skipped without ``$MENAGERIE_ROOT``)."""
    json: bool = False
    """Print the rows, the rollout check and the notes as JSON instead of the table."""


def run(options: Options) -> None:
    """Label the grasps of every object, gripper and protocol and print the rates."""
    first = options.objects[0]
    protocols = options.protocols
    reference = reference_us_per_step(model_for(first), first)
    rows, notes = [], []
    for obj in options.objects:
        model = model_for(obj)
        for gripper_name in options.grippers:
            if gripper_name == "robotiq_2f85" and not os.environ.get("MENAGERIE_ROOT"):
                notes.append(f"robotiq_2f85 skipped on {obj}: MENAGERIE_ROOT is not set")
                continue
            gripper = make_gripper(gripper_name)
            scene = GraspLabeler(model, LabelConfig(obj, gripper_name)).scene
            start = time.perf_counter()
            poses, widths = sample_antipodal(
                model.asset.mesh, gripper.planning_geometry(), options.n, 0,
                table=Table(scene.world_T_object, scene.config.table_top_z),
            )  # fmt: skip
            notes.append(f"sampled {len(poses)} grasps on {obj} for {gripper_name} in "
                         f"{time.perf_counter() - start:.1f} s")  # fmt: skip
            grasps = list(zip(poses, widths, strict=True))
            for protocol in protocols:
                rows.append(bench_protocol(model, obj, gripper_name, protocol, grasps, options.raw))
    check = rollout_check(model_for(first), first)
    after = reference_us_per_step(model_for(first), first)
    notes.append(f"machine reference (raw mj_step, {first} resting, gripper parked): "
                 f"{reference:.1f} us/step before, {after:.1f} after")  # fmt: skip
    if options.json:
        print(json.dumps({"rows": rows, "rollout": check, "notes": notes}, indent=2))
        return
    _print(rows, check, notes, options.raw)


def _print(rows: list[dict], check: dict, notes: list[str], raw: int) -> None:
    print("\n".join(notes))
    print(f"one process (one core); over raw = labeling wall / time inside mj_step when the "
          f"first {raw} grasps are labeled again")  # fmt: skip
    print("goal: fast + builtin and acronym(-fast) + franka_panda >= 25 grasps/s, over raw <= 1.2")
    print(f"{'object':11} {'gripper':13} {'protocol':12} {'held':>5} {'grasps/s':>9} "
          f"{'ms med':>7} {'steps':>6} {'us/step':>8} {'over raw':>9}")  # fmt: skip
    for r in rows:
        print(f"{r['object']:11} {r['gripper']:13} {r['protocol']:12} {r['success_share']:5.2f} "
              f"{r['grasps_per_s']:9.1f} {r['median_ms']:7.1f} {r['steps_per_grasp']:6.0f} "
              f"{r['us_per_step']:8.1f} {r['over_raw']:9.2f}")  # fmt: skip
    print(f"settle phase ({check['settle_steps']} steps): mj_step chunks {check['mj_step_ms']:.2f} "
          f"ms, mujoco.rollout {check['rollout_ms']:.2f} ms")  # fmt: skip


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
