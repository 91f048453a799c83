"""Quadric fits per second for 50-point neighborhoods, per method, single core, batched.

Run: ``.venv/bin/python benchmarks/bench_fit.py [--batch 20000] [--repeats 7]``. Threads are
pinned to one before numpy is imported. Neighborhoods are noisy patches of cylinders of
random pose (points and unit normals); the median wall time of several runs is reported,
with a ragged batch (``mask``, half to all of the points) and the analysis (classification)
of the same batch for reference.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_variable] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from simgrasp.quadric import METHODS, analyze_quadrics, fit_quadrics  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

PAPER_FITS_PER_SECOND = 40 / 0.13  # Table III: 40 quadrics in 0.13 s


def neighborhoods(batch: int, points: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(batch, points, 3) noisy cylinder patches (radius 1.5 cm) and their unit normals."""
    rng = rng_for(seed, "bench_fit")
    theta = rng.uniform(-0.8, 0.8, (batch, points))
    z = rng.uniform(-0.02, 0.02, (batch, points))
    local = np.stack([0.015 * np.cos(theta), 0.015 * np.sin(theta), z], -1)
    normals_local = np.stack([np.cos(theta), np.sin(theta), np.zeros_like(z)], -1)
    rotations = Rotation.random(batch, random_state=rng).as_matrix()
    offsets = rng.uniform(-0.5, 0.5, (batch, 1, 3))
    points_world = np.einsum("bij,bkj->bki", rotations, local) + offsets
    points_world += rng.normal(0, 2e-4, points_world.shape)
    return points_world, np.einsum("bij,bkj->bki", rotations, normals_local)


def median_seconds(run, repeats: int) -> tuple[float, float]:  # noqa: ANN001 - a callable
    """Median wall and CPU (process) seconds of ``run()`` after one warm-up call. On a shared
    machine the CPU time is the fairer single-core figure."""
    run()
    wall, cpu = [], []
    for _ in range(repeats):
        start_wall, start_cpu = time.perf_counter(), time.process_time()
        run()
        wall.append(time.perf_counter() - start_wall)
        cpu.append(time.process_time() - start_cpu)
    return float(np.median(wall)), float(np.median(cpu))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=20000)
    parser.add_argument("--points", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    pts, nrm = neighborhoods(args.batch, args.points, args.seed)
    print(
        f"B = {args.batch} neighborhoods x {args.points} points, 1 thread, median of "
        f"{args.repeats} runs"
    )
    print("| step | wall s | CPU s | per wall second | per CPU second | vs paper (~308/s) |")
    print("|---|---|---|---|---|---|")
    for method in METHODS:
        wall, cpu = median_seconds(lambda m=method: fit_quadrics(pts, nrm, method=m), args.repeats)
        rate = args.batch / cpu
        print(
            f"| fit {method} | {wall:.3f} | {cpu:.3f} | {args.batch / wall:,.0f} | {rate:,.0f} | "
            f"{rate / PAPER_FITS_PER_SECOND:,.0f}x |"
        )
    sizes = rng_for(args.seed, "bench_fit", "ragged").integers(
        args.points // 2, args.points + 1, args.batch
    )
    mask = np.arange(args.points) < sizes[:, None]
    wall, cpu = median_seconds(lambda: fit_quadrics(pts, nrm, mask=mask), args.repeats)
    rate = args.batch / cpu
    print(
        f"| fit birdal, ragged (mask) | {wall:.3f} | {cpu:.3f} | {args.batch / wall:,.0f} | "
        f"{rate:,.0f} | {rate / PAPER_FITS_PER_SECOND:,.0f}x |"
    )
    fit = fit_quadrics(pts, nrm)
    wall, cpu = median_seconds(
        lambda: analyze_quadrics(fit.coefficients, rtol=1e-2, reference_points=fit.centroids),
        args.repeats,
    )
    print(
        f"| analyze (birdal fits) | {wall:.3f} | {cpu:.3f} | {args.batch / wall:,.0f} | "
        f"{args.batch / cpu:,.0f} | |"
    )


if __name__ == "__main__":
    main()
