"""The segmenter at the sensor's pixel scale (``SegmentConfig.reference_footprint``), measured.

Each set's pixel footprint (``segment_scale.pixel_footprint``: the width one pixel covers at
the scene's median range, mm) and its segmentation with the defaults against the same
defaults with scaling off (``reference_footprint`` 0), scored as in ``segment_cv.py`` (mean
part IoU, least scene IoU, scenes under 0.5, median CPU ms on one thread):

- osd-learn's 45 scenes and ``segment_cv.py``'s kinect clutter frames (``sim-tune``'s first
  scene and ``sim-10-20``), where the settings were chosen: 640 x 480, scale 1, the same
  labels;
- the same clutter scenes seen by the **stereo** (RealSense D435 class) model at 1280 x 720,
  58 degrees vertical field of view, four cameras 0.5 m from the target, as the GraspNet
  frame was taken: the tune scene (seed 100) and the ten held-out scenes of 11 - 20 objects
  (``segment_cv.HELD_OUT``), rendered with the chain's scene, render and sensor code, exact
  labels. Parts under ``HIRES_MIN_PART_PX`` pixels are not scored (``segment_cv``'s 200 px at
  four times the pixels per area).

    SIMGRASP_REAL_DIR=../shared/real SIMGRASP_YCB_DIR=../shared/ycb MUJOCO_GL=egl \\
        python scripts/segment_scale.py --out docs/results/segment-cv \\
        --cache /tmp/segcv/frames --hires-cache /tmp/segcv/hires

Writes ``scale.md`` and ``scale.json`` (numbers only); the caches hold derived clouds.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # one core, before numpy and Open3D load

import json  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import segment_cv as cv  # noqa: E402

from simgrasp.assets.real import default_real_dir  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.perception.scene_cloud import SceneCloud  # noqa: E402
from simgrasp.perception.segmentation.segment_config import SegmentConfig  # noqa: E402
from simgrasp.perception.segmentation.segment_scale import pixel_footprint  # noqa: E402

HIRES = ("stereo", 1280, 720, 0.5)
"""Sensor model, image width and height (px) and camera distance (m) of the fine frames."""
HIRES_MIN_PART_PX = 800
SCENES = ((cv.TARGETS[0], cv.TUNE_SEED, cv.TUNE_CLUTTER), *cv.HELD_OUT)
CONFIGS = {"scaled (default)": SegmentConfig(), "unscaled": SegmentConfig(reference_footprint=0.0)}


def hires_frames(cache: Path | None) -> list[cv.Frame]:
    """The fine stereo views of ``SCENES``, group ``stereo-tune`` (seed 100) or
    ``stereo-10-20``."""
    frames = []
    _, width, height, _ = HIRES
    for target, seed, clutter in SCENES:
        group = "stereo-tune" if seed == cv.TUNE_SEED else "stereo-10-20"
        views = cv.cached_views(cache, (target, seed, clutter), _render)
        for index, (points, labels, viewpoint) in enumerate(views):
            kept = cv.drop_small_parts(labels, HIRES_MIN_PART_PX)
            cloud = SceneCloud(points, width, height, viewpoint, kept)
            frames.append(cv.Frame(f"{target}_s{seed}_c{clutter}_v{index}", group, cloud))
    return frames


def _render(target: str, seed: int, clutter: int) -> list[cv.View]:
    """The fine views of one scene (``segment_cv.View``): the scene is built once to find
    where its target settles, then with four cameras ``HIRES``'s distance from there."""
    from simgrasp.assets.model import model_for
    from simgrasp.grasping.trials.chain_config import ChainConfig
    from simgrasp.grippers import make_gripper
    from simgrasp.scenes.camera import default_viewpoints
    from simgrasp.scenes.scene import build_scene

    sensor, width, height, distance = HIRES
    first = ChainConfig.of(scene__clutter=clutter, sensor__kind=sensor)
    aim = build_scene(model_for(target), make_gripper("builtin"), first.scene, seed).object_pose()
    cameras = tuple(default_viewpoints(aim[:3, 3], distance, n=4, width=width, height=height))
    config = ChainConfig.of(scene__clutter=clutter, sensor__kind=sensor, scene__cameras=cameras)
    return cv.labeled_views(target, seed, config)


def footprint_mm(frame: cv.Frame) -> float:
    """The frame's pixel footprint (mm), over its finite points."""
    cloud = frame.cloud
    finite = np.asarray(np.isfinite(cloud.points).all(axis=1), dtype=bool)
    return 1000.0 * pixel_footprint(cloud, finite)


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    data: Path = default_real_dir() / "osd-learn"
    """Folder of the osd-learn scenes (default: under $SIMGRASP_REAL_DIR, else ../shared/real)."""
    out: Path = Path("docs/results/segment-cv")
    """Folder of scale.md and scale.json."""
    cache: Path | None = None
    """Folder keeping the rendered kinect frames (segment_cv.py's --cache; derived data)."""
    hires_cache: Path | None = None
    """Folder keeping the rendered fine stereo frames (derived data)."""
    repeats: PositiveInt = 3
    """Runs of each scene per setting; its CPU time is the least of them."""


def run(options: Options) -> str:
    """Each set's pixel footprint and segmentation, scaled and unscaled; the table."""
    frames = [cv.Frame(f.name, "osd-learn", f.cloud) for f in cv.osd_frames(options.data)]
    frames += cv.simulated_frames(SCENES[:1], "kinect-tune", options.cache)
    frames += cv.simulated_frames(cv.HELD_OUT, "kinect-10-20", options.cache)
    frames += hires_frames(options.hires_cache)
    groups = list(dict.fromkeys(f.group for f in frames))
    report: dict[str, dict] = {}
    for group in groups:
        chosen = [f for f in frames if f.group == group]
        sizes = [footprint_mm(f) for f in chosen]
        report[group] = {"footprint_mm": [min(sizes), float(np.median(sizes)), max(sizes)]}
        for name, config in CONFIGS.items():
            report[group][name] = cv.stats([cv.score(f, config, options.repeats) for f in chosen])
    options.out.mkdir(parents=True, exist_ok=True)
    (options.out / "scale.json").write_text(json.dumps(report, indent=2) + "\n")
    lines = [
        "| set | pixel footprint mm (min / median / max) | setting | mean part IoU | least scene "
        "IoU | scenes < 0.5 | median CPU ms |",
        "|---|---|---|---|---|---|---|",
    ]
    for group, row in report.items():
        low, mid, high = row["footprint_mm"]
        for name in CONFIGS:
            s = row[name]
            lines.append(
                f"| {group} | {low:.2f} / {mid:.2f} / {high:.2f} | {name} | {s['mean_iou']:.3f} | "
                f"{s['min_scene_iou']:.3f} | {s['under_0.5']} | {s['median_ms']:.1f} |"
            )
    (options.out / "scale.md").write_text("\n".join(lines) + "\n")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    return script_main(Options, run, __doc__.splitlines()[0], argv)


if __name__ == "__main__":
    raise SystemExit(main())
