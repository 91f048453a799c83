"""Seconds to detect handles in the full chain's fused camera clouds: the chain's default
``quadric_preset("two_scales")`` against the paper's single pass, in one run (medians).

The clouds are the chain's own (stable placement, 4 views, the given sensor) for the paper's
objects, one scene per seed; each is detected with both settings in turn, ``--runs`` times.

    SIMGRASP_YCB_DIR=../shared/ycb python benchmarks/bench_chain_detect.py --runs 5
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from typing import Literal

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_variable] = "1"  # one core for Open3D (OpenMP) and numpy alike, before import

import numpy as np  # noqa: E402
from needs_ycb import skipped_without_ycb  # noqa: E402  (this folder)

from simgrasp.assets.model import model_for  # noqa: E402
from simgrasp.assets.object_sets import PAPER_OBJECTS  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.grasping.trials.chain_config import ChainConfig  # noqa: E402
from simgrasp.grippers import make_gripper  # noqa: E402
from simgrasp.handles import QuadricDetectorConfig, detect  # noqa: E402
from simgrasp.handles.presets import quadric_preset  # noqa: E402
from simgrasp.perception.sensors.settings import SensorSettings  # noqa: E402
from simgrasp.scenes.kept_renderer import RendererKeeper  # noqa: E402
from simgrasp.scenes.observe import observe, viewpoint_normals  # noqa: E402
from simgrasp.scenes.scene import build_scene  # noqa: E402

SETTINGS = {
    "single pass": QuadricDetectorConfig(),
    "two_scales()": quadric_preset("two_scales"),
}


def chain_clouds(sensor: str, seeds: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """(points, viewpoint normals) of the chain's cloud of each paper object and seed."""
    config = ChainConfig(sensor=SensorSettings(kind=sensor))
    gripper = make_gripper(config.gripper)
    clouds = []
    with RendererKeeper() as renderers:
        for name in PAPER_OBJECTS:
            model = model_for(name)
            for seed in range(seeds):
                scene = build_scene(model, gripper, config.scene, seed)
                renderer = renderers.renderer_for(scene)
                cloud = observe(scene, renderer, 0.0, seed, config.sensor).cloud
                clouds.append((cloud.points_world, viewpoint_normals(cloud)))
    return clouds


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    sensor: Literal["ideal", "kinect"] = "kinect"
    """Depth sensor model of the chain's camera clouds."""
    seeds: PositiveInt = 2
    """Scenes per paper object (seeds 0 .. seeds - 1), one cloud each."""
    runs: PositiveInt = 5
    """Timed passes of both settings over all clouds; medians are printed."""


def run(options: Options) -> None:
    """Print the milliseconds per cloud of both settings and their ratio."""
    clouds = chain_clouds(options.sensor, options.seeds)
    per_cloud: dict[str, list[float]] = {name: [] for name in SETTINGS}
    for _ in range(options.runs):
        for name, settings in SETTINGS.items():
            start = time.perf_counter()
            for seed, (points, normals) in enumerate(clouds):
                detect(points, normals, settings, seed)
            per_cloud[name].append((time.perf_counter() - start) / len(clouds))
    median = {name: float(np.median(values)) for name, values in per_cloud.items()}
    print(
        f"{len(clouds)} chain clouds ({len(PAPER_OBJECTS)} paper objects x {options.seeds} seeds, "
        f"{options.sensor} depth), median of {options.runs} runs, one core"
    )
    for name, seconds in median.items():
        print(f"{name:14s} {1000 * seconds:6.0f} ms a cloud")
    print(f"two_scales() / single pass: {median['two_scales()'] / median['single pass']:.2f}x")


def main() -> int:
    return script_main(
        Options, skipped_without_ycb(run, "bench_chain_detect.py"), __doc__.splitlines()[0]
    )


if __name__ == "__main__":
    sys.exit(main())
