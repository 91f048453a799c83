"""Seconds to render the full chain's depth views of one scene: a fresh renderer per scene
against the kept renderer (``simgrasp.scenes.kept_renderer``), in one run (medians).

Scenes of one object differ by seed (rest pose, yaw, camera placement), as in a sweep. Each
seed's scene is rendered both ways; the first seed only warms up.

    SIMGRASP_YCB_DIR=../shared/ycb python benchmarks/bench_observe.py --runs 9
"""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from simgrasp.assets.model import model_for
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers import make_gripper
from simgrasp.scenes.kept_renderer import close_kept_renderer, kept_renderer
from simgrasp.scenes.observe import render_views
from simgrasp.scenes.render import SceneRenderer
from simgrasp.scenes.scene import build_scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="048_hammer")
    parser.add_argument("--gripper", default="builtin")
    parser.add_argument("--runs", type=int, default=9)
    args = parser.parse_args()

    model = model_for(args.object)
    gripper = make_gripper(args.gripper)
    config = ChainConfig().scene
    times: dict[str, list[float]] = {"build": [], "fresh": [], "kept": []}
    for seed in range(args.runs + 1):
        start = time.perf_counter()
        scene = build_scene(model, gripper, config, seed)
        built = time.perf_counter()
        with SceneRenderer(scene.model) as renderer:
            render_views(scene, renderer)
        fresh = time.perf_counter()
        render_views(scene, kept_renderer(scene))
        kept = time.perf_counter()
        if seed > 0:
            times["build"].append(built - start)
            times["fresh"].append(fresh - built)
            times["kept"].append(kept - fresh)
    close_kept_renderer()

    median = {name: float(np.median(values)) for name, values in times.items()}
    print(
        f"{args.object}, {args.gripper} gripper, {len(scene.cameras)} views of 640x480 depth + "
        f"segmentation, median of {args.runs} scenes (seeds 1..{args.runs})"
    )
    print(f"build scene:                 {1000 * median['build']:.0f} ms")
    print(f"render views, fresh renderer: {1000 * median['fresh']:.0f} ms")
    print(f"render views, kept renderer:  {1000 * median['kept']:.0f} ms")
    print(f"fresh / kept: {median['fresh'] / median['kept']:.2f}x")


if __name__ == "__main__":
    try:
        main()
    except FileNotFoundError as exc:  # YCB meshes missing: nothing here runs without them
        sys.exit(f"bench_observe.py: skipped, it measures YCB objects: {exc}")
