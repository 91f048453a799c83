"""Milliseconds per 640x480 frame of each depth sensor model, against rendering that frame.

The frame is the depth of bench_render.py's scene (a table, a box, a 20k-triangle mesh and a
distractor seen by one camera), rendered with the process's backend (EGL, else OSMesa, else
ray casting). Each sensor model is applied to it with a fresh seeded generator per run;
the baseline is rendering the same frame, in the same run. Medians.

    python benchmarks/bench_sensor.py --runs 15
"""

from __future__ import annotations

import argparse
import time

import mujoco  # noqa: E402  (after the renderer module chose MUJOCO_GL)
import numpy as np  # noqa: E402
import trimesh  # noqa: E402

from simgrasp.perception.sensors import SENSORS, apply_sensor, sensor_config  # noqa: E402
from simgrasp.scenes.camera import add_camera, default_viewpoints  # noqa: E402
from simgrasp.scenes.render import SceneRenderer  # first: chooses the GL platform
from simgrasp.seeding import rng_for  # noqa: E402


def _scene() -> mujoco.MjModel:
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.05)
    spec = mujoco.MjSpec()
    spec.add_mesh(name="blob", uservert=sphere.vertices.ravel(), userface=sphere.faces.ravel())
    box = mujoco.mjtGeom.mjGEOM_BOX
    spec.worldbody.add_geom(type=box, size=[0.5, 0.5, 0.02], pos=[0, 0, -0.02])
    spec.worldbody.add_body(pos=[0, 0, 0.05]).add_geom(type=box, size=[0.04, 0.03, 0.05])
    blob = spec.worldbody.add_body(pos=[0.1, 0.08, 0.05])
    blob.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname="blob")
    spec.worldbody.add_body(pos=[-0.03, -0.04, 0.16]).add_geom(type=box, size=[0.01, 0.04, 0.02])
    add_camera(spec, default_viewpoints((0.0, 0.0, 0.05), n=1)[0])
    return spec.compile()


def _median_ms(function, runs: int) -> float:
    times = []
    for run in range(runs):
        start = time.perf_counter()
        function(run)
        times.append(time.perf_counter() - start)
    return 1000.0 * float(np.median(times))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args()
    model = _scene()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with SceneRenderer(model) as renderer:
        frame = renderer.depth(data, "view0")  # warm-up
        render_ms = _median_ms(lambda _: renderer.depth(data, "view0"), args.runs)
        backend = frame.backend
    depth = frame.depth.astype(np.float32)
    K = frame.intrinsics.matrix
    print(f"render ({backend}) {render_ms:8.1f} ms/frame (640x480 depth+segmentation)")
    for name in SENSORS:
        config = sensor_config(name)
        apply_sensor(depth, K, config, rng_for(0, "bench"))  # warm-up

        def run(seed: int, config=config) -> None:
            apply_sensor(depth, K, config, rng_for(seed, "bench"))

        ms = _median_ms(run, args.runs)
        print(f"{name:8s} {ms:8.1f} ms/frame  {ms / render_ms:5.2f} x render")


if __name__ == "__main__":
    main()
