"""The Kinect model on a table top rendered by MuJoCo (the chain's renderer): the rendered
plane is the analytic one, and the model's noise and quantization hold on it."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

from simgrasp.perception.sensors import KinectConfig, apply_sensor
from simgrasp.perception.sensors.calibration import plane_depth
from simgrasp.perception.sensors.geometry import incidence_angle
from simgrasp.scenes.camera import CameraSpec, add_camera
from simgrasp.scenes.render import SceneRenderer
from simgrasp.seeding import rng_for

pytestmark = pytest.mark.filterwarnings("ignore:no working headless GL:RuntimeWarning")
CAMERA = CameraSpec(name="kinect", pos=(0.0, -0.9, 0.8), lookat=(0.0, 0.0, 0.0), fovy_deg=49.0)


@pytest.fixture(scope="module")
def table_frame():
    spec = mujoco.MjSpec()
    box = mujoco.mjtGeom.mjGEOM_BOX
    spec.worldbody.add_geom(type=box, size=[2.0, 2.0, 0.02], pos=[0, 0, -0.02])
    add_camera(spec, CAMERA)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    with SceneRenderer(model) as renderer:
        return renderer.depth(data, "kinect")


def test_rendered_table_is_the_analytic_plane(table_frame) -> None:
    cam_T_world = np.linalg.inv(table_frame.world_T_cam)
    normal = cam_T_world[:3, :3] @ [0.0, 0.0, 1.0]
    d = -normal @ cam_T_world[:3, 3]
    analytic = plane_depth(
        table_frame.intrinsics.matrix, table_frame.depth.shape, (normal, float(d))
    )
    hit = table_frame.depth > 0
    assert hit.mean() > 0.99
    assert np.abs(table_frame.depth - analytic)[hit].max() < 5e-4


def test_kinect_on_the_rendered_table(table_frame) -> None:
    """Axial noise: (measured - rendered) / sigma_z has unit spread without quantization;
    with it neighbouring depths lie one disparity step (2.85e-3 z^2) apart, in millimeters."""
    depth = table_frame.depth.astype(np.float32)
    K = table_frame.intrinsics.matrix
    quiet = dataclasses.replace(
        KinectConfig(),
        inverse_depth_step=0.0,
        depth_resolution=0.0,
        grazing_start_deg=89.0,
        grazing_end_deg=90.0,
    )
    out = apply_sensor(depth, K, quiet, rng_for(0, "rendered"))
    theta = incidence_angle(depth, K)
    inner = np.zeros(depth.shape, dtype=bool)
    inner[2:-2, 2:-2] = True
    normalized = ((out - depth) / quiet.axial_sigma(depth, theta))[inner]
    assert normalized.std() == pytest.approx(1.0, abs=0.02)
    levels = np.unique(apply_sensor(depth, K, KinectConfig(), rng_for(0, "levels")))
    levels = levels[levels > 0]
    assert np.allclose(levels * 1000, np.round(levels * 1000), atol=1e-3)
    gaps = np.diff(levels)  # one disparity step, give or take the millimeter rounding
    middle = levels[:-1] + gaps / 2
    assert np.all(np.abs(gaps - 2.85e-3 * middle**2) <= 0.00101)
    assert levels.size > 100
