"""Milliseconds per 640x480 frame of each depth sensor model, against rendering that frame.

The frame is the depth of bench_render.py's scene (a table, a box, a 20k-triangle mesh and a
distractor seen by one camera), rendered with the process's backend (EGL, else OSMesa, else
ray casting). Each sensor model is applied to it with a fresh seeded generator per run;
the baseline is rendering the same frame, in the same run. Medians.

    python benchmarks/bench_sensor.py --runs 15
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass

import numpy as np  # noqa: E402
from bench_render import tabletop_model  # noqa: E402  (this folder)

from simgrasp._mujoco import mujoco  # noqa: E402
from simgrasp.config.arguments import script_main  # noqa: E402
from simgrasp.config.checks import Checked, PositiveInt  # noqa: E402
from simgrasp.perception.sensors import SENSORS, apply_sensor, sensor_config  # noqa: E402
from simgrasp.scenes.render import SceneRenderer  # first: chooses the GL platform
from simgrasp.seeding import rng_for  # noqa: E402


def _median_ms(function, runs: int) -> float:
    times = []
    for run in range(runs):
        start = time.perf_counter()
        function(run)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.median(times))


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    runs: PositiveInt = 15
    """Timed frames of the rendering and of each sensor model, after a warm-up; medians are
    printed."""


def run(options: Options) -> None:
    """Print the rendering's and each sensor model's milliseconds per frame."""
    model = tabletop_model(mesh_subdivisions=5)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with SceneRenderer(model) as renderer:
        frame = renderer.depth(data, "view0")  # warm-up
        render_ms = _median_ms(lambda _: renderer.depth(data, "view0"), options.runs)
        backend = frame.backend
    depth = frame.depth.astype(np.float32)
    K = frame.intrinsics.matrix
    print(f"render ({backend}) {render_ms:8.1f} ms/frame (640x480 depth+segmentation)")
    for name in SENSORS:
        config = sensor_config(name)
        apply_sensor(depth, K, config, rng_for(0, "bench"))  # warm-up

        def apply(seed: int, config=config) -> None:
            apply_sensor(depth, K, config, rng_for(seed, "bench"))

        ms = _median_ms(apply, options.runs)
        print(f"{name:8s} {ms:8.1f} ms/frame  {ms / render_ms:5.2f} x render")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
