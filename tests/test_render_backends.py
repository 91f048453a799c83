"""EGL, OSMesa and ray casting render the same depth and segmentation.

The GL platform is fixed per process, so each backend renders the shared test scene in its own
Python process (forced with SIMGRASP_RENDER_BACKEND) and saves its frames; the comparisons and
the surface-accuracy checks then run here on every backend's frames.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_render import N_VIEWS, box_surface_distance, build_scene

from simgrasp.scenes.observe import object_cloud
from simgrasp.scenes.render import BACKENDS, DepthFrame

_RENDER_SCRIPT = """
import sys
sys.path.insert(0, {tests_dir!r})
import numpy as np
from test_render import N_VIEWS, build_scene
from simgrasp.scenes.render import SceneRenderer, select_backend
model, data = build_scene()
with SceneRenderer(model) as renderer:
    frames = [renderer.depth(data, f"view{{k}}") for k in range(N_VIEWS)]
    rgb = renderer.rgb(data, "view0") if select_backend() != "raycast" else np.zeros((0,))
np.savez({out!r}, backend=select_backend(), rgb=rgb,
         depth=np.stack([f.depth for f in frames]),
         geom_ids=np.stack([f.geom_ids for f in frames]),
         body_ids=np.stack([f.body_ids for f in frames]),
         world_T_cam=np.stack([f.world_T_cam for f in frames]))
"""


def _render_in_subprocess(backend: str, out: Path) -> dict[str, np.ndarray]:
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    env["SIMGRASP_RENDER_BACKEND"] = backend
    if backend != "raycast":
        env["MUJOCO_GL"] = backend  # the scene module imports mujoco before render.py
    script = _RENDER_SCRIPT.format(tests_dir=str(Path(__file__).parent), out=str(out))
    result = subprocess.run(
        [sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, f"{backend} render failed:\n{result.stderr[-3000:]}"
    return dict(np.load(out))


@pytest.fixture(scope="module")
def renders(tmp_path_factory) -> dict[str, dict[str, np.ndarray]]:
    tmp = tmp_path_factory.mktemp("renders")
    return {b: _render_in_subprocess(b, tmp / f"{b}.npz") for b in BACKENDS}


def _frames(render: dict[str, np.ndarray]) -> list[DepthFrame]:
    from simgrasp.scenes.camera import model_camera_intrinsics

    model, _ = build_scene()
    return [
        DepthFrame(
            depth=render["depth"][k],
            geom_ids=render["geom_ids"][k],
            body_ids=render["body_ids"][k],
            intrinsics=model_camera_intrinsics(model, f"view{k}"),
            world_T_cam=render["world_T_cam"][k],
            camera_name=f"view{k}",
            backend=str(render["backend"]),
        )
        for k in range(N_VIEWS)
    ]


def test_each_backend_really_ran(renders) -> None:
    for backend, render in renders.items():
        assert str(render["backend"]) == backend
    for backend in ("egl", "osmesa"):
        rgb = renders[backend]["rgb"]
        assert rgb.shape == (480, 640, 3) and rgb.dtype == np.uint8
        assert rgb.std() > 5.0  # a picture, not a blank buffer


@pytest.mark.parametrize("other", ["osmesa", "raycast"])
def test_backends_agree_with_egl(renders, other: str) -> None:
    reference, candidate = renders["egl"], renders[other]
    np.testing.assert_allclose(reference["world_T_cam"], candidate["world_T_cam"], atol=1e-12)
    both = (reference["depth"] > 0) & (candidate["depth"] > 0)
    assert both.mean() > 0.5
    delta = np.abs(reference["depth"] - candidate["depth"])[both]
    assert np.median(delta) < 1e-3
    assert np.mean(delta < 5e-3) > 0.99
    # Same pixel centers: a half-pixel offset in the ray directions leaves only ~1 % of the
    # pixels within 0.1 mm (it passes the two looser checks above).
    assert np.mean(delta < 1e-4) > 0.99
    assert np.mean(reference["geom_ids"] == candidate["geom_ids"]) > 0.99
    assert np.mean(reference["body_ids"] == candidate["body_ids"]) > 0.99


@pytest.mark.parametrize("backend", BACKENDS)
def test_object_cloud_lies_on_the_box_for_every_backend(renders, backend: str) -> None:
    model, _ = build_scene()
    frames = _frames(renders[backend])
    object_body = model.body("object").id
    cloud = object_cloud(frames, [object_body])
    distance = box_surface_distance(cloud.points_world)
    assert len(cloud) > 10000
    assert np.median(distance) < 5e-4 and distance.max() < 2e-3
    # Segmentation removed the table and the distractors although they fill most pixels.
    object_pixels = sum(int(np.count_nonzero(f.body_ids == object_body)) for f in frames)
    other_pixels = sum(int(np.count_nonzero(f.body_ids >= 0)) for f in frames) - object_pixels
    assert other_pixels > 5 * object_pixels and len(cloud) == object_pixels


def test_invalid_forced_backend_is_a_clear_error() -> None:
    env = dict(os.environ, SIMGRASP_RENDER_BACKEND="vulkan")
    result = subprocess.run(
        [sys.executable, "-c", "import simgrasp.scenes.render"],
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode != 0
    assert "SIMGRASP_RENDER_BACKEND='vulkan' is not a render backend" in result.stderr
