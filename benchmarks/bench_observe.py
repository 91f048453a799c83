"""Seconds to render the full chain's depth views of one scene: a fresh renderer per scene
against the kept renderer (``simgrasp.scenes.kept_renderer``), in one run (medians).

Scenes of one object differ by seed (rest pose, yaw, camera placement), as in a sweep. Each
seed's scene is rendered both ways; the first seed only warms up.

    SIMGRASP_YCB_DIR=../shared/ycb python benchmarks/bench_observe.py --runs 9
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass

import numpy as np
from needs_ycb import skipped_without_ycb  # (this folder)

from simgrasp.assets.model import model_for
from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, PositiveInt
from simgrasp.config.fields import setting
from simgrasp.grasping.trials.chain_config import ChainConfig
from simgrasp.grippers import gripper_names, make_gripper
from simgrasp.scenes.kept_renderer import RendererKeeper
from simgrasp.scenes.observe import render_views
from simgrasp.scenes.render import SceneRenderer
from simgrasp.scenes.scene import build_scene


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    object: str = "048_hammer"
    """Object of the scenes (a YCB id reads ``$SIMGRASP_YCB_DIR``)."""
    gripper: str = setting("builtin", choices=gripper_names)
    """Gripper of the scenes."""
    runs: PositiveInt = 9
    """Timed scenes, seeds 1 .. runs (seed 0 warms up); medians are printed."""


def run(options: Options) -> None:
    """Print the milliseconds to build a scene and render its views both ways."""
    model = model_for(options.object)
    gripper = make_gripper(options.gripper)
    config = ChainConfig().scene
    times: dict[str, list[float]] = {"build": [], "fresh": [], "kept": []}
    renderers = RendererKeeper()
    for seed in range(options.runs + 1):
        start = time.perf_counter()
        scene = build_scene(model, gripper, config, seed)
        built = time.perf_counter()
        with SceneRenderer(scene.model) as renderer:
            render_views(scene, renderer)
        fresh = time.perf_counter()
        render_views(scene, renderers.renderer_for(scene))
        kept = time.perf_counter()
        if seed > 0:
            times["build"].append(built - start)
            times["fresh"].append(fresh - built)
            times["kept"].append(kept - fresh)
    renderers.close()

    median = {name: float(np.median(values)) for name, values in times.items()}
    print(
        f"{options.object}, {options.gripper} gripper, {len(scene.cameras)} views of 640x480 "
        f"depth + segmentation, median of {options.runs} scenes (seeds 1..{options.runs})"
    )
    print(f"build scene:                 {1000 * median['build']:.0f} ms")
    print(f"render views, fresh renderer: {1000 * median['fresh']:.0f} ms")
    print(f"render views, kept renderer:  {1000 * median['kept']:.0f} ms")
    print(f"fresh / kept: {median['fresh'] / median['kept']:.2f}x")


def main() -> int:
    return script_main(
        Options, skipped_without_ycb(run, "bench_observe.py"), __doc__.splitlines()[0]
    )


if __name__ == "__main__":
    sys.exit(main())
