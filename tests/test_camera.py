"""Pinhole camera model and MuJoCo camera placement."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from simgrasp.perception.camera import (
    CameraIntrinsics,
    cv_R_mujoco,
    cv_T_mujoco,
    depth_to_points_cam,
    project,
    transform_points,
)
from simgrasp.scenes.camera import (
    CameraSpec,
    add_camera,
    default_viewpoints,
    model_camera_intrinsics,
    world_T_cam,
)
from simgrasp.seeding import rng_for


def test_from_fovy_matches_mujoco_pinhole() -> None:
    intrinsics = CameraIntrinsics.from_fovy(640, 480, 58.0)
    assert intrinsics.fx == intrinsics.fy
    assert intrinsics.fy == pytest.approx(240.0 / math.tan(math.radians(29.0)))
    assert (intrinsics.cx, intrinsics.cy) == (319.5, 239.5)
    assert intrinsics.fovy_deg == pytest.approx(58.0)
    np.testing.assert_allclose(
        intrinsics.matrix,
        [[intrinsics.fx, 0.0, 319.5], [0.0, intrinsics.fy, 239.5], [0.0, 0.0, 1.0]],
    )


@settings(max_examples=50, deadline=None)
@given(
    width=st.integers(2, 64),
    height=st.integers(2, 64),
    fovy=st.floats(20.0, 120.0),
    seed=st.integers(0, 2**31),
)
def test_depth_to_points_inverts_projection(width: int, height: int, fovy: float, seed: int):
    intrinsics = CameraIntrinsics.from_fovy(width, height, fovy)
    rng = np.random.default_rng(seed)
    depth = rng.uniform(0.1, 3.0, size=(height, width))
    depth[rng.random((height, width)) < 0.2] = 0.0
    points_cam, pixel_indices = depth_to_points_cam(depth, intrinsics)
    assert len(points_cam) == np.count_nonzero(depth)
    pixels, z = project(points_cam, intrinsics)
    v, u = np.divmod(pixel_indices, width)
    np.testing.assert_allclose(pixels, np.column_stack([u, v]), atol=1e-9)
    np.testing.assert_allclose(z, depth.ravel()[pixel_indices], rtol=0, atol=0)


def test_depth_to_points_drops_invalid_and_masked_pixels() -> None:
    intrinsics = CameraIntrinsics.from_fovy(4, 2, 60.0)
    depth = np.array([[0.0, np.nan, np.inf, -1.0], [1.0, 2.0, 5.0, 0.5]])
    mask = np.array([[True] * 4, [True, True, True, False]])
    points_cam, pixel_indices = depth_to_points_cam(depth, intrinsics, mask, max_depth=4.0)
    assert pixel_indices.tolist() == [4, 5]
    np.testing.assert_allclose(points_cam[:, 2], [1.0, 2.0])
    # The image center row/column sign: left pixels have x < 0, the lower row has y > 0.
    assert points_cam[0, 0] < 0 and points_cam[0, 1] > 0


def test_project_marks_points_behind_camera() -> None:
    intrinsics = CameraIntrinsics.from_fovy(10, 10, 60.0)
    pixels, z = project(np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]), intrinsics)
    np.testing.assert_allclose(pixels[0], [4.5, 4.5])
    assert np.all(np.isnan(pixels[1])) and z[1] == -1.0


def test_bad_camera_inputs_name_the_problem() -> None:
    intrinsics = CameraIntrinsics.from_fovy(4, 3, 60.0)
    with pytest.raises(ValueError, match="shape"):
        depth_to_points_cam(np.ones((4, 3)), intrinsics)
    with pytest.raises(ValueError, match="mask"):
        depth_to_points_cam(np.ones((3, 4)), intrinsics, np.ones((3, 4)))
    with pytest.raises(ValueError, match="fovy"):
        CameraIntrinsics.from_fovy(4, 3, 0.0)
    with pytest.raises(ValueError, match="fx"):
        CameraIntrinsics(4, 3, -1.0, 1.0, 1.5, 1.0)
    with pytest.raises(ValueError, match="4x4"):
        transform_points(np.eye(3), np.zeros((1, 3)))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        transform_points(np.eye(4), np.zeros((3,)))
    with pytest.raises(ValueError, match="coincide"):
        CameraSpec("c", pos=(0, 0, 1), lookat=(0, 0, 1))


def test_frame_conventions() -> None:
    # MuJoCo camera looks along its -z with +y up; OpenCV looks along +z with +y down.
    np.testing.assert_array_equal(cv_R_mujoco @ [0, 0, -1], [0, 0, 1])
    np.testing.assert_array_equal(cv_R_mujoco @ [0, 1, 0], [0, -1, 0])
    np.testing.assert_array_equal(cv_T_mujoco[:3, :3], cv_R_mujoco)
    a_T_b = np.eye(4)
    a_T_b[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    a_T_b[:3, 3] = [1, 2, 3]
    np.testing.assert_allclose(transform_points(a_T_b, np.array([[1.0, 0, 0]])), [[1, 3, 3]])


def _scene_with(cameras: list[CameraSpec]) -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.3, 0.3, 0.01])
    for camera in cameras:
        add_camera(spec, camera)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def test_add_camera_points_the_optical_axis_at_lookat() -> None:
    target = np.array([0.1, -0.05, 0.08])
    views = default_viewpoints(target, distance=0.6, n=4, rng=rng_for(3, "cameras"))
    large = CameraSpec("large", pos=(0.0, 0.5, 0.5), lookat=(0, 0, 0), width=800, height=600)
    model, data = _scene_with([*views, large])
    assert model.vis.global_.offwidth >= 800 and model.vis.global_.offheight >= 600
    for view in views:
        world_T_cv = world_T_cam(model, data, view.name)
        np.testing.assert_allclose(world_T_cv[:3, 3], view.pos, atol=1e-9)
        # The target projects to the principal point, and "down" in the image is world -z-ish.
        points_cam = transform_points(np.linalg.inv(world_T_cv), target[None])
        pixels, depth = project(points_cam, model_camera_intrinsics(model, view.name))
        np.testing.assert_allclose(pixels[0], [319.5, 239.5], atol=1e-6)
        assert 0.54 < depth[0] < 0.66
        assert (world_T_cv[:3, :3] @ [0, 1, 0])[2] < 0
        assert abs(world_T_cv[:3, 0][2]) < 1e-9  # no roll: image x stays horizontal
        world_T_mj = world_T_cam(model, data, view.name, convention="mujoco")
        np.testing.assert_allclose(world_T_mj @ cv_T_mujoco, world_T_cv, atol=1e-12)


def test_default_viewpoints_spread_and_seeded_jitter() -> None:
    views = default_viewpoints((0, 0, 0), distance=0.6, elevation_deg=40, n=4)
    assert [v.name for v in views] == ["view0", "view1", "view2", "view3"]
    positions = np.array([v.pos for v in views])
    np.testing.assert_allclose(np.linalg.norm(positions, axis=1), 0.6)
    np.testing.assert_allclose(positions[:, 2], 0.6 * math.sin(math.radians(40)))
    azimuths = np.sort(np.degrees(np.arctan2(positions[:, 1], positions[:, 0])))
    np.testing.assert_allclose(np.diff(azimuths), 90.0)
    first = default_viewpoints((0, 0, 0), n=2, rng=rng_for(7, "views"))
    again = default_viewpoints((0, 0, 0), n=2, rng=rng_for(7, "views"))
    other = default_viewpoints((0, 0, 0), n=2, rng=rng_for(8, "views"))
    assert first == again and first != other
    with pytest.raises(ValueError, match="1..4"):
        default_viewpoints((0, 0, 0), n=5)


def test_camera_errors_name_the_camera() -> None:
    spec = mujoco.MjSpec()
    add_camera(spec, CameraSpec("front", pos=(1, 0, 1), lookat=(0, 0, 0)))
    with pytest.raises(ValueError, match="already has a camera named 'front'"):
        add_camera(spec, CameraSpec("front", pos=(1, 0, 1), lookat=(0, 0, 0)))
    spec.worldbody.add_camera(name="bare")
    model = spec.compile()
    data = mujoco.MjData(model)
    with pytest.raises(ValueError, match=r"no camera named 'side'.*front"):
        world_T_cam(model, data, "side")
    with pytest.raises(ValueError, match="'bare' has no image resolution"):
        model_camera_intrinsics(model, "bare")
