"""What the body-wall test costs the single-view default: ``detect_single_view`` with
``single_view_preset()`` (the body wall on, as ``simgrasp detect`` runs it) against the
same settings with the body wall off, in CPU time, interleaved in one run on one core
(medians, and the with / without ratio per cloud).

The clouds: rendered single views of generated mugs through the sensor models (no data
needed: a tube mug upright through the stereo model from 0.78 m, its handle in profile and
turned 120 degrees away, and through the kinect model from 0.6 m; a strap mug lying, stereo
from 0.3 m),
and, when ``$SIMGRASP_REAL_DIR`` holds them, the real clouds of the shipped manifest
(``models/handles/real_detect.toml``).

    SIMGRASP_REAL_DIR=../shared/real python benchmarks/bench_single_view.py --runs 5
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
from numpy.typing import NDArray  # noqa: E402

from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.errors import DataNotFoundError  # noqa: E402
from simgrasp.evaluation.real_manifest import load_real_cloud, read_manifest  # noqa: E402
from simgrasp.evaluation.sim_views import SimView, capture  # noqa: E402
from simgrasp.handles.presets import single_view_preset  # noqa: E402
from simgrasp.handles.single_view.detector import detect_single_view  # noqa: E402

SIM_VIEWS = (
    SimView("gen_mug", "upright", 0.78, 32.0, "stereo"),
    SimView("gen_mug", "upright", 0.78, 32.0, "stereo", azimuth_deg=120.0),
    SimView("gen_mug", "upright", 0.6, 40.0, "kinect"),
    SimView("gen_strap_mug", "lying", 0.3, 90.0, "stereo"),
)
"""Rendered views timed on every machine (sensor seed 0)."""

Cloud = tuple[str, NDArray[np.float64], NDArray[np.float64]]
"""A cloud's name, its points (N, 3, m) and the viewpoint (3,) in their frame."""


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    runs: PositiveInt = 5
    """Timed detections of each cloud with and without the body wall; medians are printed."""


def clouds() -> list[Cloud]:
    """The rendered views, then the manifest's real clouds when their files are there."""
    found: list[Cloud] = []
    for view in SIM_VIEWS:
        shot = capture(view, 0)
        found.append((f"sim {view.name}", np.asarray(shot.points_cam, np.float64), np.zeros(3)))
    try:
        for cloud in read_manifest():
            found.append((f"real {cloud.name}", load_real_cloud(cloud), cloud.viewpoint))
    except DataNotFoundError as exc:
        print(f"real clouds skipped: {exc}")
    return found


def run(options: Options) -> None:
    """Print one row per cloud: its points, median ms without and with the body wall, ratio."""
    walled = single_view_preset()
    settings = {"without": walled.with_body_wall(False)}
    settings["with"] = walled
    print(f"median of {options.runs} runs each, interleaved, one core")
    print("| cloud | points | without (ms) | with (ms) | with / without |\n|---|---|---|---|---|")
    ratios = []
    for name, points, eye in clouds():
        seconds: dict[str, list[float]] = {"without": [], "with": []}
        for seed in range(options.runs):
            for key, config in settings.items():
                start = time.process_time()
                detect_single_view(points, config, seed, eye)
                seconds[key].append(time.process_time() - start)
        without, with_wall = (1000 * float(np.median(seconds[k])) for k in ("without", "with"))
        ratios.append(with_wall / without)
        print(f"| {name} | {len(points)} | {without:.0f} | {with_wall:.0f} | {ratios[-1]:.2f} |")
    print(f"ratio with / without: median {np.median(ratios):.2f}, max {max(ratios):.2f}")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
