"""ACRONYM's shake: the targets computed before the shake are the ones the hand was
commanded step by step, and the object's motion in the jaws is measured in the TCP frame."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

from simgrasp.assets.model import model_for
from simgrasp.grasping.labeling.labeling import GraspLabeler, LabelConfig
from simgrasp.grasping.trials.shake import (
    ShakeConfig,
    largest_motion,
    shake_targets,
    tcp_offset,
)
from simgrasp.transforms import make_transform


def test_shake_targets_are_the_commanded_poses_to_the_bit(tmp_path: Path) -> None:
    trimesh.creation.box((0.04, 0.06, 0.10)).export(tmp_path / "box.stl")
    name = f"{tmp_path / 'box.stl'}?mass=0.2"
    labeler = GraspLabeler(
        model_for(name), LabelConfig(object=name, gripper="franka_panda", protocol="acronym")
    )
    mount, data = labeler.scene.gripper, labeler.scene.data
    shake = ShakeConfig()
    world_T_tcp0 = make_transform(Rotation.random(random_state=4).as_matrix(), [0.1, -0.2, 0.9])
    control_dt, steps = 0.01, 200
    positions, quats = shake_targets(shake, world_T_tcp0, mount.tcp_T_root, control_dt, steps)
    assert positions.shape == (steps, 3) and quats.shape == (steps, 4)
    for k in range(1, steps + 1):
        mount.command_tcp(data, world_T_tcp0 @ tcp_offset(shake, k * control_dt))
        assert np.array_equal(data.mocap_pos[mount.mocap_id], positions[k - 1])
        assert np.array_equal(data.mocap_quat[mount.mocap_id], quats[k - 1])


def _frame(world_T_tcp: np.ndarray, world_T_com: np.ndarray) -> np.ndarray:
    return np.concatenate(
        [
            world_T_tcp[:3, 3],
            world_T_tcp[:3, :3].ravel(),
            world_T_com[:3, 3],
            world_T_com[:3, :3].ravel(),
        ]
    )


def test_largest_motion_is_measured_in_the_jaws() -> None:
    """An object carried rigidly by the hand has not moved in the jaws, however far the hand
    goes; one that slid 1 cm along the jaws and turned 0.1 rad moved 1 cm + 0.1 x radius."""
    tcp_T_com = make_transform(np.eye(3), [0.0, 0.0, 0.02])
    hands = [
        make_transform(Rotation.from_rotvec([0.0, angle, 0.0]).as_matrix(), [0.0, 0.0, angle])
        for angle in (0.0, 0.1, 0.3)
    ]
    carried = np.stack([_frame(hand, hand @ tcp_T_com) for hand in hands])
    assert largest_motion(carried, radius=0.05) < 1e-6  # arccos near 1: ~1e-8 rad
    slid = make_transform(Rotation.from_rotvec([0.0, 0.0, 0.1]).as_matrix(), [0.0, 0.01, 0.02])
    moved = np.stack([carried[0], _frame(hands[2], hands[2] @ slid), carried[1]])
    assert np.isclose(largest_motion(moved, radius=0.05), 0.01 + 0.1 * 0.05)
