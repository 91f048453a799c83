"""Milliseconds of CPU per 640x480 frame of the scene segmenter (``segment_scene``), on one core.

Two sets of frames: the 45 real osd-learn scenes (``$SIMGRASP_REAL_DIR/osd-learn``; skipped
with a line when absent; default settings) and the kinect views of simulated clutter scenes (a
generated tool among five generated distractors, ``--distractors``, four views each, rendered
once through the chain's own scene, render and sensor code, segmented with the chain's settings,
``SegmentConfig.simulated``: the ``segment`` perception of ``simgrasp evaluate --clutter``).
Per frame the least CPU time of ``--repeats`` runs is taken; medians over the frames are
printed with their stage medians (``Segmentation.timings_s``). The same-run baseline is back-
projecting the frame's depth image to camera-frame points (``depth_to_points_cam``), the
cheapest whole-frame step every cut needs; its ratio tells a slow machine from a slow segmenter.
CPU time (not wall) because the machine is shared; BLAS and OpenMP are held to one thread.

    python benchmarks/bench_segment.py [--repeats 3] [--clutter-scenes 3] [--distractors 5]

Goal: <= 50 ms per frame on one core.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # run, not imported (a test reading the options)
    for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[_var] = "1"  # one core, before numpy and Open3D load

import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from functools import partial  # noqa: E402
from typing import Annotated  # noqa: E402

import numpy as np  # noqa: E402

from simgrasp.assets.real import default_real_dir  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, NonNegativeInt, PositiveInt, Range  # noqa: E402
from simgrasp.perception.camera import CameraIntrinsics, depth_to_points_cam  # noqa: E402
from simgrasp.perception.scene_cloud import SceneCloud, read_scene  # noqa: E402
from simgrasp.perception.segmentation.segment import Segmentation, segment_scene  # noqa: E402
from simgrasp.perception.segmentation.segment_config import SegmentConfig  # noqa: E402
from simgrasp.scenes.clutter_sets import MAX_CLUTTER  # noqa: E402

KINECT = CameraIntrinsics(width=640, height=480, fx=525.0, fy=525.0, cx=319.5, cy=239.5)
"""The osd-learn scenes' camera (camera-frame points; only the baseline uses it)."""

Frame = tuple[SceneCloud, np.ndarray, CameraIntrinsics]
"""A scene cloud, its depth image (m, 0 where none) and the camera that took it."""
SIMULATED = SegmentConfig.simulated()
"""The chain's segmenter settings (``ChainConfig.segment``), used on the rendered frames."""


def osd_frames() -> list[Frame]:
    """The osd-learn scenes with their depth (the camera-frame z of each point)."""
    from simgrasp.evaluation.segment_eval import osd_scenes

    frames = []
    for path in osd_scenes(default_real_dir() / "osd-learn"):
        scene = read_scene(path)
        depth = np.nan_to_num(scene.grid()[..., 2].astype(np.float64), nan=0.0)
        frames.append((scene, depth, KINECT))
    return frames


def clutter_frames(scenes: int, distractors: int) -> list[Frame]:
    """Kinect views of ``scenes`` generated-tool clutter scenes (seeds 0..) with
    ``distractors`` distractors each, as perceive cuts them."""
    from simgrasp.assets.model import model_for
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grippers import make_gripper
    from simgrasp.scenes.kept_renderer import RendererKeeper
    from simgrasp.scenes.observe import observe
    from simgrasp.scenes.perceive import organized_cloud
    from simgrasp.scenes.scene import build_scene

    config = ChainConfig.of(
        scene__clutter=distractors, scene__clutter_objects="generated", sensor__kind="kinect"
    )
    gripper, frames = make_gripper("builtin"), []
    with RendererKeeper() as renderers:
        for index in range(scenes):
            target = ("gen_hammer", "gen_mug", "gen_spatula", "gen_pan")[index % 4]
            scene = build_scene(model_for(target), gripper, config.scene, index)
            renderer = renderers.renderer_for(scene)
            observation = observe(scene, renderer, 0.0, index, config.sensor)
            frames += [(organized_cloud(f), f.depth, f.intrinsics) for f in observation.frames]
    return frames


def least_cpu_ms(work: Callable[[], object], repeats: int) -> float:
    """The least CPU time of ``repeats`` calls of ``work`` (ms), after one untimed call."""
    work()
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        work()
        best = min(best, time.process_time() - start)
    return 1000.0 * best


def report(name: str, frames: list[Frame], repeats: int, config: SegmentConfig) -> None:
    """Print the median segmentation (``config``) and baseline ms per frame of ``frames``."""
    segment_ms, baseline_ms = [], []
    stages: dict[str, list[float]] = {}
    for scene, depth, intrinsics in frames:
        segment_ms.append(least_cpu_ms(partial(segment_scene, scene, config), repeats))
        baseline_ms.append(least_cpu_ms(partial(depth_to_points_cam, depth, intrinsics), repeats))
        result: Segmentation = segment_scene(scene, config)
        for stage, seconds in result.timings_s.items():
            stages.setdefault(stage, []).append(1000.0 * seconds)
    segment, baseline = statistics.median(segment_ms), statistics.median(baseline_ms)
    parts = ", ".join(f"{k} {statistics.median(v):.1f}" for k, v in stages.items() if k != "total")
    print(
        f"{name}: {len(frames)} frames, segment_scene median {segment:.1f} ms CPU per frame "
        f"(goal <= 50), baseline depth_to_points {baseline:.1f} ms, ratio {segment / baseline:.1f}"
    )
    print(f"  stage medians (wall ms): {parts}")


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    repeats: PositiveInt = 3
    """Timed runs per frame (after an untimed one); the least CPU time is taken."""
    clutter_scenes: NonNegativeInt = 3
    """Simulated clutter scenes, four kinect views each (0: the osd-learn frames only)."""
    distractors: Annotated[int, Range(ge=0, le=MAX_CLUTTER)] = 5
    """Distractors per clutter scene."""


def run(options: Options) -> None:
    """Print the segmenter's and the baseline's CPU ms per frame of both frame sets."""
    osd = osd_frames()
    if osd:
        report("osd-learn", osd, options.repeats, SegmentConfig())
    else:
        print(
            f"skipped osd-learn: no learn*.pcd in {default_real_dir() / 'osd-learn'} "
            "(set SIMGRASP_REAL_DIR)"
        )
    if options.clutter_scenes > 0:
        frames = clutter_frames(options.clutter_scenes, options.distractors)
        report(
            f"kinect clutter views ({options.distractors} distractors)",
            frames,
            options.repeats,
            SIMULATED,
        )


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
