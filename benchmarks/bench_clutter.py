"""Clutter's cost: a full-chain trial among N distractors against the single-object trial.

For each object and seed, the same chain (render, cut, detect, plan, execute, score) runs on
the single-object scene (``--clutter 0``, the renderer's mask) and on the scene with N
distractors (``--clutter N``, cut by our scene segmenter), interleaved so both see the same
machine speed. Each pair's first run per object is an untimed warm-up (object models,
decompositions and the kept renderer). Medians of the whole trial's wall time and of its
stages (``timings_s``) are printed, and the ratio of the medians, clutter over single.

    python benchmarks/bench_clutter.py [--clutter 5] [--objects gen_hammer,gen_mug] [--seeds 3]

Goal: the clutter trial within 2x the single-object trial.
"""

from __future__ import annotations

import statistics
import sys
import time
from dataclasses import dataclass
from typing import Annotated

import simgrasp
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt, Range
from simgrasp.config.fields import setting
from simgrasp.perception.sensors.registry import sensor_names
from simgrasp.scenes.clutter_sets import MAX_CLUTTER


def timed_trial(name: str, seed: int, clutter: int, sensor: str) -> tuple[float, dict[str, float]]:
    """Wall time (s) of one full-chain trial and its stage timings."""
    config = simgrasp.ChainConfig.of(
        scene__clutter=clutter, scene__clutter_objects="generated", sensor__kind=sensor
    )
    start = time.perf_counter()
    result = simgrasp.run_trial(name, seed=seed, config=config)
    return time.perf_counter() - start, dict(result.timings_s)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    clutter: Annotated[int, Range(ge=0, le=MAX_CLUTTER)] = 5
    """Distractors of the cluttered scene (the single-object scene has none)."""
    objects: tuple[str, ...] = ("gen_hammer", "gen_mug")
    """Target objects, each timed alone and among the distractors."""
    seeds: PositiveInt = 3
    """Timed scene pairs per object (seeds 0 .. seeds - 1), after an untimed warm-up pair."""
    sensor: str = setting("kinect", choices=sensor_names)
    """Depth sensor model of the chain."""


def run(options: Options) -> None:
    """Print the median trial and stage times of both scenes and their ratio."""
    walls: dict[int, list[float]] = {0: [], options.clutter: []}
    stages: dict[int, dict[str, list[float]]] = {0: {}, options.clutter: {}}
    for name in options.objects:
        for clutter in walls:  # warm-up
            timed_trial(name, 10_000, clutter, options.sensor)
        for seed in range(options.seeds):
            for clutter in walls:
                wall, timings = timed_trial(name, seed, clutter, options.sensor)
                walls[clutter].append(wall)
                for stage, seconds in timings.items():
                    stages[clutter].setdefault(stage, []).append(seconds)
    for clutter, values in walls.items():
        parts = ", ".join(
            f"{stage} {statistics.median(v):.3f}" for stage, v in stages[clutter].items()
        )
        print(f"clutter {clutter}: median trial {statistics.median(values):.2f} s ({parts})")
    ratio = statistics.median(walls[options.clutter]) / statistics.median(walls[0])
    print(f"ratio clutter {options.clutter} / single: {ratio:.2f} (goal <= 2)")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
