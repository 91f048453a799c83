"""Grasp trial speed: simulated seconds per wall second, and trial wall time over raw mj_step.

For each gripper, one handle grasp on a generated hammer is run ``--repeats`` times; a raw
``mj_step`` loop of the same model for the same number of steps (from the same initial state,
with the gripper parked) is timed in the same run. Medians are reported.

    python benchmarks/bench_trial.py [--repeats 7] [--json]

Targets: >= 30x real time (built-in gripper), >= 10x (Robotiq 2F-85), ratio <= 1.25.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import mujoco

from simgrasp.assets.model import build_object_model
from simgrasp.assets.registry import load_object
from simgrasp.grasping.trial import TrialConfig, run_trial
from simgrasp.scenes.gripper import make_gripper
from simgrasp.scenes.scene import build_scene

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from test_trial import handle_grasp  # noqa: E402  (the hand-placed handle grasp of the tests)


def raw_step_seconds(model: mujoco.MjModel, data: mujoco.MjData, steps: int, nstep: int) -> float:
    """Wall time of ``steps`` physics steps in chunks of ``nstep`` (no control, no checks)."""
    mujoco.mj_resetData(model, data)
    start = time.perf_counter()
    for _ in range(steps // nstep):
        mujoco.mj_step(model, data, nstep)
    return time.perf_counter() - start


def bench(gripper_name: str, repeats: int) -> dict[str, float | str | int]:
    model = build_object_model(load_object("gen_hammer", seed=1))
    scene = build_scene(model, make_gripper(gripper_name), seed=3)
    grasp = handle_grasp(scene)
    config = TrialConfig()
    trial_wall, raw_wall, sim_time, steps, outcome = [], [], 0.0, 0, None
    for _ in range(repeats):
        result = run_trial(scene, grasp, config)
        trial_wall.append(result.timings_s["total"])
        sim_time, steps, outcome = result.sim_time, result.steps, result.failure
        raw_wall.append(raw_step_seconds(scene.model, scene.data, steps, config.control_steps))
    trial, raw = statistics.median(trial_wall), statistics.median(raw_wall)
    return {
        "gripper": gripper_name,
        "outcome": outcome or "success",
        "steps": steps,
        "sim_time_s": sim_time,
        "trial_wall_s": trial,
        "raw_step_wall_s": raw,
        "real_time_factor": sim_time / trial,
        "trial_over_raw": trial / raw,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    rows = [bench(name, args.repeats) for name in ("builtin", "robotiq_2f85")]
    if args.json:
        print(json.dumps(rows, indent=2))
        return 0
    print(
        f"{'gripper':14} {'outcome':10} {'sim s':>6} {'trial s':>8} {'raw s':>7} {'x RT':>6} ratio"
    )
    for r in rows:
        print(
            f"{r['gripper']:14} {r['outcome']:10} {r['sim_time_s']:6.2f} {r['trial_wall_s']:8.3f} "
            f"{r['raw_step_wall_s']:7.3f} {r['real_time_factor']:6.1f} {r['trial_over_raw']:.2f}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
