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

import argparse
import statistics
import time

import simgrasp


def timed_trial(name: str, seed: int, clutter: int, sensor: str) -> tuple[float, dict[str, float]]:
    """Wall time (s) of one full-chain trial and its stage timings."""
    config = simgrasp.ChainConfig.of(
        scene__clutter=clutter, scene__clutter_objects="generated", sensor__kind=sensor
    )
    start = time.perf_counter()
    result = simgrasp.run_trial(name, seed=seed, config=config)
    return time.perf_counter() - start, dict(result.timings_s)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clutter", type=int, default=5)
    parser.add_argument("--objects", default="gen_hammer,gen_mug")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--sensor", default="kinect")
    args = parser.parse_args()
    walls: dict[int, list[float]] = {0: [], args.clutter: []}
    stages: dict[int, dict[str, list[float]]] = {0: {}, args.clutter: {}}
    for name in args.objects.split(","):
        for clutter in walls:  # warm-up
            timed_trial(name, 10_000, clutter, args.sensor)
        for seed in range(args.seeds):
            for clutter in walls:
                wall, timings = timed_trial(name, seed, clutter, args.sensor)
                walls[clutter].append(wall)
                for stage, seconds in timings.items():
                    stages[clutter].setdefault(stage, []).append(seconds)
    for clutter, values in walls.items():
        parts = ", ".join(
            f"{stage} {statistics.median(v):.3f}" for stage, v in stages[clutter].items()
        )
        print(f"clutter {clutter}: median trial {statistics.median(values):.2f} s ({parts})")
    ratio = statistics.median(walls[args.clutter]) / statistics.median(walls[0])
    print(f"ratio clutter {args.clutter} / single: {ratio:.2f} (goal <= 2)")


if __name__ == "__main__":
    main()
