"""Milliseconds per 640x480 depth + segmentation frame for each render backend (medians).

The GL platform is fixed per process, so each backend runs in its own process. The scene is a
table, a box, a 20k-triangle mesh object (ray casting cost grows with triangles) and a
distractor, seen by one camera.

    python benchmarks/bench_render.py --runs 15
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from dataclasses import dataclass

from simgrasp.config.arguments import script_main
from simgrasp.config.checks import Checked, NonNegativeInt, PositiveInt
from simgrasp.config.fields import setting

BACKENDS = ("egl", "osmesa", "raycast")


def tabletop_model(mesh_subdivisions: int):  # -> mujoco.MjModel (mujoco imported late)
    """A table with a box, a mesh sphere and a floating bar, and one default camera."""
    import trimesh

    from simgrasp._mujoco import mujoco
    from simgrasp.scenes.camera import add_camera, default_viewpoints

    sphere = trimesh.creation.icosphere(subdivisions=mesh_subdivisions, radius=0.05)
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


def _measure(backend: str, runs: int, mesh_subdivisions: int) -> dict[str, float]:
    # Imports here: the GL platform must be set (by the parent) before mujoco is imported.
    import numpy as np

    from simgrasp._mujoco import mujoco
    from simgrasp.scenes.render import SceneRenderer

    model = tabletop_model(mesh_subdivisions)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with SceneRenderer(model, backend=backend) as renderer:
        renderer.depth(data, "view0")  # warm-up: contexts, buffers, ray directions
        times = []
        for _ in range(runs):
            start = time.perf_counter()
            frame = renderer.depth(data, "view0")
            times.append(time.perf_counter() - start)
    return {
        "ms_per_frame": 1000.0 * float(np.median(times)),
        "hit_fraction": float(np.mean(frame.depth > 0)),
        "triangles": int(model.mesh_facenum[0]),
    }


@dataclass(frozen=True, kw_only=True)
class Options(Checked):
    runs: PositiveInt = 15
    """Timed frames per backend, after a warm-up frame; the median is printed."""
    mesh_subdivisions: NonNegativeInt = 5
    """Subdivisions of the scene's mesh sphere (5: 20,480 triangles)."""
    child: str | None = setting(None, choices=BACKENDS)
    """Internal: measure this backend in this process and print its figures as JSON (the run
    starts one such process per backend)."""


def run(options: Options) -> None:
    """Print each backend's milliseconds per frame and its ratio to EGL's."""
    if options.child:
        print(json.dumps(_measure(options.child, options.runs, options.mesh_subdivisions)))
        return
    results = {}
    for backend in BACKENDS:
        env = dict(os.environ, SIMGRASP_RENDER_BACKEND=backend)
        env.pop("PYOPENGL_PLATFORM", None)
        if backend == "raycast":
            env.pop("MUJOCO_GL", None)
        else:
            env["MUJOCO_GL"] = backend
        command = [sys.executable, __file__, "--child", backend, "--runs", str(options.runs)]
        command += ["--mesh-subdivisions", str(options.mesh_subdivisions)]
        out = subprocess.run(command, env=env, capture_output=True, text=True, check=False)
        if out.returncode != 0:
            print(f"{backend:8s} failed: {out.stderr.strip().splitlines()[-1]}")
            continue
        results[backend] = json.loads(out.stdout.strip().splitlines()[-1])
        r = results[backend]
        print(
            f"{backend:8s} {r['ms_per_frame']:8.1f} ms/frame (640x480 depth+segmentation, "
            f"median of {options.runs}; {r['hit_fraction']:.0%} pixels hit, "
            f"mesh {r['triangles']} triangles)"
        )
    if "egl" in results:
        for backend, r in results.items():
            ratio = r["ms_per_frame"] / results["egl"]["ms_per_frame"]
            print(f"{backend:8s} {ratio:6.2f} x egl")


def main() -> int:
    return script_main(Options, run, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
