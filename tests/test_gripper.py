"""Both grippers in a bare MuJoCo scene: TCP convention, opening control, mocap following."""

from __future__ import annotations

import subprocess
import sys

import mujoco
import numpy as np
import pytest
from data_needs import ROBOTIQ

from simgrasp.grasping.grasp import tcp_pose
from simgrasp.grippers import gripper_names, make_gripper
from simgrasp.grippers.mount import BoundGripper, attach_gripper
from simgrasp.grippers.robotiq_2f85 import menagerie_mjcf

GRIPPERS = ("builtin", ROBOTIQ)


def bare_scene(name: str) -> tuple[mujoco.MjModel, mujoco.MjData, BoundGripper, np.ndarray]:
    spec = mujoco.MjSpec()
    world_T_tcp = tcp_pose([0.1, -0.2, 0.5], [1.0, 1.0, 0.0], [0.0, 0.0, -1.0])
    handles = attach_gripper(spec, make_gripper(name), world_T_tcp)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data, handles.bind(model), world_T_tcp


@pytest.mark.parametrize("name", GRIPPERS)
def test_tcp_starts_at_the_commanded_pose_between_the_pads(name: str) -> None:
    model, data, gripper, world_T_tcp = bare_scene(name)
    np.testing.assert_allclose(gripper.world_T_tcp(data), world_T_tcp, atol=1e-6)
    gripper.set_opening(data, 0.06)
    mujoco.mj_step(model, data, 500)
    left, right = (data.geom_xpos[pads[0]] for pads in gripper.pad_geoms)
    tcp_world = gripper.world_T_tcp(data)
    # The pads sit symmetrically about the TCP along +y (left on -y), centered in x.
    offsets_tcp = (np.stack([left, right]) - tcp_world[:3, 3]) @ tcp_world[:3, :3]
    assert offsets_tcp[0, 1] < 0 < offsets_tcp[1, 1]
    assert offsets_tcp[0, 1] == pytest.approx(-offsets_tcp[1, 1], abs=1e-3)
    np.testing.assert_allclose(offsets_tcp[:, 0], 0.0, atol=1e-3)
    assert abs(offsets_tcp[0, 2]) < 0.01  # the pad center is within 1 cm of the TCP along z


@pytest.mark.parametrize("name", GRIPPERS)
def test_pad_contacts_resist_twisting(name: str) -> None:
    """Pad contacts carry torsional friction (condim >= 4): with point contacts alone a long
    tool held off its center of mass swings about the line between the pads and drops."""
    model, _, gripper, _ = bare_scene(name)
    for pads in gripper.pad_geoms:
        for pad in pads:
            assert model.geom_condim[pad] >= 4
            assert model.geom_friction[pad, 1] > 0


@pytest.mark.parametrize("name", GRIPPERS)
@pytest.mark.parametrize("width", [0.02, 0.05, 0.08])
def test_set_opening_reaches_the_commanded_gap(name: str, width: float) -> None:
    model, data, gripper, _ = bare_scene(name)
    gripper.set_opening(data, width)
    mujoco.mj_step(model, data, 1000)
    assert gripper.opening(data) == pytest.approx(width, abs=0.003)


@pytest.mark.parametrize("name", GRIPPERS)
def test_close_on_nothing_shuts_the_jaws(name: str) -> None:
    model, data, gripper, _ = bare_scene(name)
    gripper.set_opening(data, gripper.gripper.max_opening)
    mujoco.mj_step(model, data, 1000)
    assert gripper.opening(data) == pytest.approx(gripper.gripper.max_opening, abs=0.003)
    gripper.close(data)
    mujoco.mj_step(model, data, 1000)
    assert gripper.opening(data) < 0.003


@pytest.mark.parametrize("name", GRIPPERS)
def test_gripper_follows_the_mocap_target(name: str) -> None:
    model, data, gripper, world_T_tcp = bare_scene(name)
    target = tcp_pose(world_T_tcp[:3, 3] + [0.05, 0.0, -0.1], [0.0, 1.0, 0.0], [1.0, 0.0, -1.0])
    gripper.command_tcp(data, target)
    mujoco.mj_step(model, data, 500)
    reached = gripper.world_T_tcp(data)
    np.testing.assert_allclose(reached[:3, 3], target[:3, 3], atol=2e-3)
    np.testing.assert_allclose(reached[:3, :3], target[:3, :3], atol=1e-2)


def test_unknown_gripper_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match="unknown gripper 'parallel'"):
        make_gripper("parallel")


def test_robotiq_needs_menagerie_root(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    monkeypatch.delenv("MENAGERIE_ROOT", raising=False)
    with pytest.raises(FileNotFoundError, match="MENAGERIE_ROOT"):
        menagerie_mjcf()
    monkeypatch.setenv("MENAGERIE_ROOT", str(tmp_path))
    with pytest.raises(FileNotFoundError, match="2f85.xml"):
        menagerie_mjcf()


def test_registry_names_every_gripper_without_importing_mujoco() -> None:
    code = (
        "import sys; from simgrasp.grippers import gripper_names; "
        "print(','.join(gripper_names()), 'mujoco' in sys.modules)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.split() == [",".join(gripper_names()), "False"]


@pytest.mark.parametrize("name", GRIPPERS)
def test_gripper_carries_its_planning_geometry(name: str) -> None:
    """The planner's boxes match the model: the same stroke, and the fingertips past the TCP
    at most ``finger_reach`` open and at most that when closed (the Robotiq's swing forward)."""
    gripper = make_gripper(name)
    geometry = gripper.planning_geometry()
    assert gripper.name == name
    assert geometry.max_opening == gripper.max_opening
    assert max(geometry.pad_reach, geometry.closed_pad_reach) == gripper.finger_reach
