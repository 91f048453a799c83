"""Paper Table III on the YCB spatula: time per detection step, and the whole detection against
Open3D normal estimation alone on the same cloud, measured in one run (medians).

    SIMGRASP_YCB_DIR=../shared/ycb python benchmarks/bench_detect.py --runs 7
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_variable] = "1"  # one core for Open3D (OpenMP) and numpy alike, before import

import numpy as np  # noqa: E402
import open3d as o3d  # noqa: E402
from needs_ycb import skipped_without_ycb  # noqa: E402  (this folder)

from simgrasp.assets.registry import load_object  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.handles import QuadricDetectorConfig, TenPasConfig, detect  # noqa: E402
from simgrasp.handles.core.detection import TIMING_STEPS  # noqa: E402
from simgrasp.handles.detector_config import DetectorName  # noqa: E402
from simgrasp.perception import sample_surface, voxel_downsample  # noqa: E402
from simgrasp.seeding import rng_for  # noqa: E402

PAPER_TABLE_III_S = {
    "voxelize": 0.10,
    "normals": 39.6,
    "sample": 4.35,
    "fit": 0.13,
    "test": 0.010,
    "cluster": float("nan"),
}


def open3d_normals_seconds(points: np.ndarray, radius: float, max_nn: int) -> float:
    """Open3D normal estimation alone (hybrid KD-tree search), the baseline of the ratio."""
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    start = time.perf_counter()
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=radius, max_nn=max_nn))
    return time.perf_counter() - start


def open3d_oriented_normals_seconds(points: np.ndarray, radius: float, max_nn: int) -> float:
    """Open3D's own way to consistently signed normals for a full cloud: the normals above,
    then ``orient_normals_consistent_tangent_plane`` (k = 10); a reference for the detector's
    normals step, which signs them outward."""
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    start = time.perf_counter()
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=radius, max_nn=max_nn))
    cloud.orient_normals_consistent_tangent_plane(10)
    return time.perf_counter() - start


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    object: str = "033_spatula"
    """Object whose surface is sampled (a YCB id reads ``$SIMGRASP_YCB_DIR``)."""
    points: PositiveInt = 30000
    """Points sampled on its surface, before voxelizing."""
    neighborhoods: PositiveInt = 400
    """Neighborhood centers requested from each detector."""
    runs: PositiveInt = 7
    """Timed runs of each detector and of Open3D's normals; medians are printed."""


def run(options: Options) -> None:
    """Print the per-step table and the ratios to Open3D (see the module doc)."""
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)

    asset = load_object(options.object)
    points, _ = sample_surface(asset.mesh, options.points, rng_for(0, "bench", options.object))
    quadric = QuadricDetectorConfig(neighborhoods=options.neighborhoods)
    tenpas = TenPasConfig(neighborhoods=options.neighborhoods)
    voxelized, _ = voxel_downsample(points, quadric.voxel_size)
    steps, totals, hoods = _measure(points, voxelized, quadric, tenpas, options.runs)
    _report(options, points, voxelized, steps, totals, hoods)


Steps = dict[str, dict[str, list[float]]]


def _measure(
    points: np.ndarray,
    voxelized: np.ndarray,
    quadric: QuadricDetectorConfig,
    tenpas: TenPasConfig,
    runs: int,
) -> tuple[Steps, dict[str, list[float]], dict[str, list[int]]]:
    """Per-step and total seconds of each detector and of Open3D's normals over ``runs`` runs,
    and each detector's fitted neighborhood counts."""
    steps: Steps = {"quadric": {}, "tenpas": {}}
    totals: dict[str, list[float]] = {"quadric": [], "tenpas": [], "open3d_normals": []}
    totals["open3d_normals_input"] = []
    totals["open3d_oriented_normals"] = []
    hoods: dict[str, list[int]] = {"quadric": [], "tenpas": []}
    configs: dict[DetectorName, QuadricDetectorConfig | TenPasConfig] = {
        "quadric": quadric,
        "tenpas": tenpas,
    }
    for run in range(runs):
        totals["open3d_normals"].append(
            open3d_normals_seconds(voxelized, quadric.normal_radius, 30)
        )
        totals["open3d_normals_input"].append(
            open3d_normals_seconds(points, quadric.normal_radius, 30)
        )
        totals["open3d_oriented_normals"].append(
            open3d_oriented_normals_seconds(voxelized, quadric.normal_radius, 30)
        )
        for name, config in configs.items():
            start = time.perf_counter()
            detection = detect(points, config=config, seed=run, detector=name)
            totals[name].append(time.perf_counter() - start)
            hoods[name].append(detection.neighborhoods)
            for step in TIMING_STEPS:
                steps[name].setdefault(step, []).append(detection.timings_s.get(step, 0.0))
    return steps, totals, hoods


def _report(
    options: Options,
    points: np.ndarray,
    voxelized: np.ndarray,
    steps: Steps,
    totals: dict[str, list[float]],
    hoods: dict[str, list[int]],
) -> None:
    """Print the per-step table against the paper's Table III and the ratios to Open3D."""
    print(
        f"{options.object}: {len(points)} points -> {len(voxelized)} after voxelizing, "
        f"{options.neighborhoods} neighborhood centers requested, fitted (min-max over runs): "
        f"quadric {min(hoods['quadric'])}-{max(hoods['quadric'])}, "
        f"tenpas {min(hoods['tenpas'])}-{max(hoods['tenpas'])}; median of {options.runs} runs, "
        "one core"
    )
    print("| step | paper (s) | quadric (ms) | tenpas (ms) |\n|---|---|---|---|")
    for step in TIMING_STEPS:
        paper = PAPER_TABLE_III_S[step]
        q = 1000 * np.median(steps["quadric"][step])
        t = 1000 * np.median(steps["tenpas"][step])
        print(f"| {step} | {paper:g} | {q:.1f} | {t:.1f} |")
    normals = np.median(totals["open3d_normals"])
    print(
        f"| whole detection | 44 | {1000 * np.median(totals['quadric']):.1f} | "
        f"{1000 * np.median(totals['tenpas']):.1f} |"
    )
    print(f"Open3D normal estimation alone on the same voxelized cloud: {1000 * normals:.1f} ms")
    for name in ("quadric", "tenpas"):
        ratio = np.median(totals[name]) / normals
        print(f"ratio whole {name} detection / Open3D normals: {ratio:.2f}x (target <= 2x)")
    floor = np.median(steps["quadric"]["voxelize"]) + normals + np.median(steps["quadric"]["fit"])
    print(
        "floor of the quadric ratio set by Open3D (voxelizing, normals) and the quadric fit "
        f"alone: {floor / normals:.2f}x"
    )
    normals_input = np.median(totals["open3d_normals_input"])
    print(
        f"for reference, Open3D normals on the {len(points)}-point input cloud (before "
        f"voxelizing): {1000 * normals_input:.1f} ms; whole quadric detection / that: "
        f"{np.median(totals['quadric']) / normals_input:.2f}x"
    )
    oriented = np.median(totals["open3d_oriented_normals"])
    print(
        "for reference, Open3D normals consistently oriented (orient_normals_consistent_"
        f"tangent_plane, k = 10) on the voxelized cloud: {1000 * oriented:.1f} ms; whole "
        f"quadric detection / that: {np.median(totals['quadric']) / oriented:.2f}x"
    )


def main() -> int:
    return script_main(
        Options, skipped_without_ycb(run, "bench_detect.py"), __doc__.splitlines()[0]
    )


if __name__ == "__main__":
    sys.exit(main())
