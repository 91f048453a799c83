"""Grasp trial speed: simulated seconds per wall second, and trial wall time over raw mj_step.

For each gripper, one handle grasp on a generated hammer is run ``--repeats`` times and, in the
same run, two raw ``mj_step`` baselines of the same model for the same number of steps:

- ``replay`` (the ratio's baseline): the trial's own trajectory with no harness. Every
  ``mj_step`` call of one recorded trial is replayed from its recorded integration state
  (qpos, qvel, warm start, ctrl, mocap, applied forces, ...), timing only the ``mj_step``
  calls, so the physics work (contacts while closing, lifting, tugging) is exactly the
  trial's and the ratio measures the harness's overhead alone.
- ``parked``: the same number of steps from the initial state with the gripper parked and no
  control (cheaper physics: no finger contacts), for reference.

Medians are reported.

    python benchmarks/bench_trial.py [--repeats 7] [--json]

Targets: >= 30x real time (built-in gripper), >= 10x (Robotiq 2F-85), ratio <= 1.25.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from simgrasp._mujoco import mujoco
from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.grasping.trials.trial import run_trial
from simgrasp.grasping.trials.trial_config import TrialConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.scene import build_scene

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from step_replay import STATE, Calls, recorded_steps, replay_seconds  # noqa: E402
from test_trial import handle_grasp  # noqa: E402  (the hand-placed handle grasp of the tests)


def raw_step_seconds(model: mujoco.MjModel, data: mujoco.MjData, steps: int, nstep: int) -> float:
    """Wall time of ``steps`` physics steps in chunks of ``nstep`` from the initial state
    (gripper parked, no control, no checks)."""
    mujoco.mj_resetData(model, data)
    start = time.perf_counter()
    for _ in range(steps // nstep):
        mujoco.mj_step(model, data, nstep)
    return time.perf_counter() - start


def record_trial(scene, grasp, config: TrialConfig):
    """Run one trial recording, before each ``mj_step`` call, the integration state and
    ``nstep``; also the state after the last call. Returns (result, calls, final state)."""
    with recorded_steps(scene.model) as calls:
        result = run_trial(scene, grasp, config)
    final = np.empty(mujoco.mj_stateSize(scene.model, STATE))
    mujoco.mj_getState(scene.model, scene.data, final, STATE)
    if sum(n for _, n in calls) != result.steps:
        raise RuntimeError("recorded mj_step calls do not add up to the trial's steps")
    return result, calls, final


def replayed(model: mujoco.MjModel, data: mujoco.MjData, calls: Calls) -> tuple[float, np.ndarray]:
    """Seconds spent in ``mj_step`` replaying the recorded calls, and the state after the
    last one."""
    seconds = replay_seconds(model, data, calls)
    final = np.empty(mujoco.mj_stateSize(model, STATE))
    mujoco.mj_getState(model, data, final, STATE)
    return seconds, final


def bench(gripper_name: str, repeats: int) -> dict[str, float | str | int]:
    model = build_object_model(load_object("gen_hammer", seed=1))
    scene = build_scene(model, make_gripper(gripper_name), seed=3)
    grasp = handle_grasp(scene)
    config = TrialConfig()
    recorded, calls, recorded_final = record_trial(scene, grasp, config)
    steps, sim_time = recorded.steps, recorded.sim_time
    trial_wall, replay_wall, parked_wall = [], [], []
    replay_exact = True
    for _ in range(repeats):
        result = run_trial(scene, grasp, config)
        if (result.steps, result.failure) != (steps, recorded.failure):
            raise RuntimeError("trial is not reproducible: steps or outcome changed")
        trial_wall.append(result.timings_s["total"])
        seconds, final = replayed(scene.model, scene.data, calls)
        replay_exact &= bool(np.array_equal(final, recorded_final))
        replay_wall.append(seconds)
        parked_wall.append(raw_step_seconds(scene.model, scene.data, steps, config.control_steps))
    trial = statistics.median(trial_wall)
    replay, parked = statistics.median(replay_wall), statistics.median(parked_wall)
    return {
        "gripper": gripper_name,
        "outcome": recorded.failure or "success",
        "steps": steps,
        "sim_time_s": sim_time,
        "trial_wall_s": trial,
        "raw_replay_wall_s": replay,
        "raw_parked_wall_s": parked,
        "replay_bit_exact": replay_exact,
        "real_time_factor": sim_time / trial,
        "trial_over_raw": trial / replay,
        "trial_over_parked": trial / parked,
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    repeats: PositiveInt = 7
    """Timed trials, each with its raw baselines, per gripper; medians are printed."""
    json: bool = False
    """Print the rows as JSON (the skipped grippers on stderr) instead of the table."""


def run(options: Options) -> None:
    """Time the trials of every gripper there is and print the table (see the module doc)."""
    rows, skipped = [], []
    for name in ("builtin", "robotiq_2f85"):
        try:
            make_gripper(name)
        except FileNotFoundError as exc:  # the Robotiq without MENAGERIE_ROOT
            skipped.append(f"skipped {name}: {exc}")
            continue
        rows.append(bench(name, options.repeats))
    if options.json:
        print(json.dumps(rows, indent=2))
        print("\n".join(skipped), file=sys.stderr)
        return
    print(f"median of {options.repeats} runs; ratio = trial wall / raw replay (target <= 1.25)")
    print(
        f"{'gripper':14} {'outcome':8} {'steps':>6} {'sim s':>6} {'trial s':>8} {'x RT':>6} "
        f"{'replay s':>9} {'ratio':>6} {'parked s':>9} {'ratio':>6}"
    )
    for r in rows:
        print(
            f"{r['gripper']:14} {r['outcome']:8} {r['steps']:6d} {r['sim_time_s']:6.2f} "
            f"{r['trial_wall_s']:8.3f} {r['real_time_factor']:6.1f} "
            f"{r['raw_replay_wall_s']:9.3f} {r['trial_over_raw']:6.2f} "
            f"{r['raw_parked_wall_s']:9.3f} {r['trial_over_parked']:6.2f}"
            + ("" if r["replay_bit_exact"] else "  (replay not bit-exact)")
        )
    for line in skipped:
        print(line)


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
