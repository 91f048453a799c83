"""Depth and segmentation rendering in this process (whichever backend it selects).

The same scene is rendered by every backend, each in its own process, in
``test_render_backends.py``; :func:`build_scene` is shared with it.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from simgrasp.scenes.camera import add_camera, default_viewpoints
from simgrasp.scenes.render import DepthFrame, SceneRenderer, select_backend

BOX_HALF_SIZE = np.array([0.04, 0.03, 0.05])
BOX_POS = np.array([0.02, -0.01, 0.05])
BOX_QUAT = np.array([np.cos(0.3), 0.0, 0.0, np.sin(0.3)])  # 0.6 rad about world z
TARGET = (0.0, 0.0, 0.05)
N_VIEWS = 4

pytestmark = pytest.mark.filterwarnings("ignore:no working headless GL:RuntimeWarning")


def build_scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Table (world geom), free box object, tilted cylinder clutter, a distractor "gripper"
    (a visible box and a group-3 collision sphere the depth camera must not see), 4 cameras."""
    spec = mujoco.MjSpec()
    box, cylinder, sphere = (
        mujoco.mjtGeom.mjGEOM_BOX,
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        mujoco.mjtGeom.mjGEOM_SPHERE,
    )
    spec.worldbody.add_geom(name="table", type=box, size=[0.5, 0.5, 0.02], pos=[0, 0, -0.02])
    obj = spec.worldbody.add_body(name="object", pos=BOX_POS.tolist(), quat=BOX_QUAT.tolist())
    obj.add_freejoint()
    obj.add_geom(name="object_box", type=box, size=BOX_HALF_SIZE.tolist())
    clutter = spec.worldbody.add_body(name="clutter", pos=[0.14, 0.06, 0.06])
    clutter.add_geom(type=cylinder, size=[0.02, 0.06], quat=[0.92388, 0, 0.382683, 0])
    gripper = spec.worldbody.add_body(name="gripper", pos=[-0.03, -0.04, 0.16])
    gripper.add_geom(name="gripper_palm", type=box, size=[0.01, 0.04, 0.02])
    gripper.add_geom(name="gripper_collision", type=sphere, size=[0.03], group=3)
    for view in default_viewpoints(TARGET, distance=0.6, n=N_VIEWS):
        add_camera(spec, view)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def box_surface_distance(points_world: np.ndarray) -> np.ndarray:
    """Unsigned distance (m) from world points to the surface of the object box."""
    world_R_box = np.zeros(9)
    mujoco.mju_quat2Mat(world_R_box, BOX_QUAT)
    points_box = (points_world - BOX_POS) @ world_R_box.reshape(3, 3)
    q = np.abs(points_box) - BOX_HALF_SIZE
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    inside = np.minimum(q.max(axis=1), 0.0)
    return np.abs(outside + inside)


@pytest.fixture(scope="module")
def scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    return build_scene()


@pytest.fixture(scope="module")
def frames(scene) -> list[DepthFrame]:
    model, data = scene
    with SceneRenderer(model) as renderer:
        return [renderer.depth(data, f"view{k}") for k in range(N_VIEWS)]


def test_frame_layout(scene, frames: list[DepthFrame]) -> None:
    model, _ = scene
    frame = frames[0]
    assert frame.backend == select_backend()
    assert frame.depth.shape == frame.geom_ids.shape == frame.body_ids.shape == (480, 640)
    hit = frame.geom_ids >= 0
    assert np.all(frame.depth[hit] > 0) and np.all(frame.depth[~hit] == 0)
    np.testing.assert_array_equal(frame.body_ids[hit], model.geom_bodyid[frame.geom_ids[hit]])
    assert np.all(frame.body_ids[~hit] == -1)
    with pytest.raises(ValueError, match="read-only"):
        frame.depth[0, 0] = 1.0


def test_rendered_box_points_lie_on_its_faces(scene, frames: list[DepthFrame]) -> None:
    from simgrasp.perception.camera import depth_to_points_cam, transform_points

    model, _ = scene
    box_geom = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "object_box")
    for frame in frames:
        points_cam, _ = depth_to_points_cam(
            frame.depth, frame.intrinsics, frame.geom_ids == box_geom
        )
        assert len(points_cam) > 2000
        distance = box_surface_distance(transform_points(frame.world_T_cam, points_cam))
        assert np.median(distance) < 5e-4
        assert distance.max() < 2e-3


def test_depth_camera_sees_only_depth_geom_groups(scene, frames: list[DepthFrame]) -> None:
    model, _ = scene
    seen = set(np.unique(np.concatenate([f.geom_ids.ravel() for f in frames])).tolist())
    geom = {
        name: mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, name)
        for name in ("table", "object_box", "gripper_palm", "gripper_collision")
    }
    assert {geom["table"], geom["object_box"], geom["gripper_palm"]} <= seen
    assert geom["gripper_collision"] not in seen


def test_renderer_errors(scene) -> None:
    model, data = scene
    with SceneRenderer(model, backend="raycast") as renderer:
        with pytest.raises(ValueError, match="no camera named 'nope'"):
            renderer.depth(data, "nope")
        with pytest.raises(RuntimeError, match="need a GL backend"):
            renderer.rgb(data)
    with pytest.raises(RuntimeError, match="closed"):
        renderer.depth(data, "view0")
    with pytest.raises(ValueError, match="unknown render backend"):
        SceneRenderer(model, backend="vulkan")
    with pytest.raises(ValueError, match="geom_groups"):
        SceneRenderer(model, backend="raycast", geom_groups=(6,))
