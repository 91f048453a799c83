"""Quadric fits per second for 50-point neighborhoods, per method, single core, batched.

Run: ``.venv/bin/python benchmarks/bench_fit.py [--batch 20000] [--repeats 7]``. Threads are
pinned to one before numpy is imported. Neighborhoods are noisy patches of cylinders of
random pose (points and unit normals); the median wall time of several runs is reported,
with a ragged batch (``mask``, half to all of the points) and the analysis (classification)
of the same batch for reference.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_variable] = "1"

import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402

import numpy as np  # noqa: E402
from scipy.spatial.transform import Rotation  # noqa: E402

from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
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


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    batch: PositiveInt = 20000
    """Neighborhoods fitted in one batch."""
    points: PositiveInt = 50
    """Points per neighborhood."""
    repeats: PositiveInt = 7
    """Timed runs of each step (after one warm-up run); the median is printed."""
    seed: int = 0
    """Seed of the neighborhoods and of the ragged batch's sizes."""


def run(options: Options) -> None:
    """Print the table of fits per second (see the module doc)."""
    pts, nrm = neighborhoods(options.batch, options.points, options.seed)
    print(
        f"B = {options.batch} neighborhoods x {options.points} points, 1 thread, median of "
        f"{options.repeats} runs"
    )
    print("| step | wall s | CPU s | per wall second | per CPU second | vs paper (~308/s) |")
    print("|---|---|---|---|---|---|")
    for method in METHODS:
        wall, cpu = median_seconds(
            lambda m=method: fit_quadrics(pts, nrm, method=m), options.repeats
        )
        rate = options.batch / cpu
        print(
            f"| fit {method} | {wall:.3f} | {cpu:.3f} | {options.batch / wall:,.0f} | "
            f"{rate:,.0f} | {rate / PAPER_FITS_PER_SECOND:,.0f}x |"
        )
    sizes = rng_for(options.seed, "bench_fit", "ragged").integers(
        options.points // 2, options.points + 1, options.batch
    )
    mask = np.arange(options.points) < sizes[:, None]
    wall, cpu = median_seconds(lambda: fit_quadrics(pts, nrm, mask=mask), options.repeats)
    rate = options.batch / cpu
    print(
        f"| fit birdal, ragged (mask) | {wall:.3f} | {cpu:.3f} | {options.batch / wall:,.0f} | "
        f"{rate:,.0f} | {rate / PAPER_FITS_PER_SECOND:,.0f}x |"
    )
    fit = fit_quadrics(pts, nrm)
    wall, cpu = median_seconds(
        lambda: analyze_quadrics(fit.coefficients, rtol=1e-2, reference_points=fit.centroids),
        options.repeats,
    )
    print(
        f"| analyze (birdal fits) | {wall:.3f} | {cpu:.3f} | {options.batch / wall:,.0f} | "
        f"{options.batch / cpu:,.0f} | |"
    )


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
