"""Normal estimation and neighbourhood gathering on a 20k-point cloud: medians of repeats.

Compares plain Open3D ``estimate_normals`` (hybrid KD search, no orientation) with
``simgrasp.perception.estimate_normals`` in its three orientation modes, and times
``gather_neighborhoods`` for 3000 cube neighbourhoods. Run:
``MUJOCO_GL=egl .venv/bin/python benchmarks/bench_normals.py [--object 025_mug]``
(a YCB id reads ``$SIMGRASP_YCB_DIR``; the default is a generated torus).
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_variable] = "1"  # one core for Open3D (OpenMP) and numpy alike, before import

import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import cast  # noqa: E402

import numpy as np  # noqa: E402
import open3d as o3d  # noqa: E402
import trimesh  # noqa: E402

from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.perception import (  # noqa: E402
    estimate_normals,
    gather_neighborhoods,
    point_spacing,
    sample_centers,
    sample_surface,
)
from simgrasp.perception.normals import RADIUS_PER_SPACING  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402


def _median_s(step: Callable[[], object], repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        step()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def _mesh(name: str) -> trimesh.Trimesh:
    if name == "torus":
        return trimesh.creation.torus(major_radius=0.05, minor_radius=0.015)
    path = Path(os.environ["SIMGRASP_YCB_DIR"]) / name / "google_16k" / "textured.obj"
    return cast(trimesh.Trimesh, trimesh.load(path, force="mesh"))  # force="mesh": one mesh


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    object: str = "torus"
    """The cloud's mesh: ``torus`` (generated) or a YCB id such as ``025_mug`` (read from
    ``$SIMGRASP_YCB_DIR``)."""
    points: PositiveInt = 20000
    """Points sampled on the mesh's surface."""
    repeats: PositiveInt = 7
    """Timed runs of each step; the median is printed."""


def run(options: Options) -> None:
    """Print the median time of each step (see the module doc)."""
    points, _ = sample_surface(_mesh(options.object), options.points, rng_for(0, "bench_normals"))
    radius = RADIUS_PER_SPACING * point_spacing(points)

    def open3d_only() -> None:
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=radius, max_nn=30))

    centers = points[sample_centers(points, rng_for(0, "centers"), count=3000)]
    normals = estimate_normals(points, orient="none")
    rows = {
        "open3d estimate_normals": open3d_only,
        "estimate_normals orient=none": lambda: estimate_normals(points, orient="none"),
        "estimate_normals orient=viewpoint": lambda: estimate_normals(
            points, orient="viewpoint", viewpoint=np.array([0, 0, 1.0])
        ),
        "estimate_normals orient=outward": lambda: estimate_normals(points, orient="outward"),
        "gather_neighborhoods 3000 cubes 16 mm": lambda: gather_neighborhoods(
            points, normals, centers, 0.016, "cube", 64, 10, rng_for(0)
        ),
    }
    medians = {name: _median_s(step, options.repeats) for name, step in rows.items()}
    base = medians["open3d estimate_normals"]
    print(f"{options.object}: {len(points)} points, radius {radius * 1000:.2f} mm")
    print(f"median of {options.repeats} runs, one thread")
    for name, seconds in medians.items():
        print(f"  {name:40s} {seconds * 1000:8.1f} ms  ({seconds / base:5.1f}x Open3D)")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
