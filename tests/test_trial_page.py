"""The trial page draws the built-in gripper as its model's boxes: the palm and each finger
(with its pad) of ``parallel_jaw.xml``, in the TCP frame, at the jaw opening of the frame."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from simgrasp.grippers.builtin import BUILTIN
from simgrasp.resources import model_path
from simgrasp.viewer.trial_page import gripper_mesh


def _geom_bounds(model: mujoco.MjModel, data: mujoco.MjData, names: list[str]) -> np.ndarray:
    """(2, 3) low and high corners of the named box geoms (world = the TCP frame here)."""
    corners = []
    for name in names:
        geom = model.geom(name).id
        rotation = data.geom_xmat[geom].reshape(3, 3)
        signs = np.array(np.meshgrid(*[[-1, 1]] * 3)).reshape(3, -1).T
        corners.append(data.geom_xpos[geom] + (signs * model.geom_size[geom]) @ rotation.T)
    stacked = np.concatenate(corners)
    return np.stack([stacked.min(axis=0), stacked.max(axis=0)])


@pytest.mark.parametrize("opening", [0.0, 0.04, 0.085])
def test_builtin_gripper_drawn_as_its_model(opening):
    model = mujoco.MjModel.from_xml_path(str(model_path("grippers", "parallel_jaw.xml")))
    data = mujoco.MjData(model)
    data.qpos[model.joint("left_slide").qposadr[0]] = opening / 2
    data.qpos[model.joint("right_slide").qposadr[0]] = opening / 2
    mujoco.mj_kinematics(model, data)
    mesh, sides = gripper_mesh(BUILTIN.planning_geometry())
    vertices = np.array(mesh.vertices)
    vertices[:, 1] += sides * opening / 2  # what the page's script does per frame
    parts = {0: ["palm"], -1: ["left_finger", "left_pad"], 1: ["right_finger", "right_pad"]}
    for side, names in parts.items():
        drawn = vertices[sides == side]
        expected = _geom_bounds(model, data, names)
        np.testing.assert_allclose(drawn.min(axis=0), expected[0], atol=1e-6)
        np.testing.assert_allclose(drawn.max(axis=0), expected[1], atol=1e-6)
