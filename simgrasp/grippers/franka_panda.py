"""The Franka Emika Panda hand (models/grippers/franka_panda.xml): the hand that ACRONYM,
GraspGen and GraspDataGen label grasps with, shipped with its Apache-2.0 meshes and notice.

Its root body is the hand base in ACRONYM's grasp frame (+z approach, +x closing) and its
``tcp`` site is :data:`simgrasp.grasping.grasp_sets.FRANKA_T_TCP` in it, so a grasp file's
hand pose maps to our TCP and back with no offset of our own: the hand is placed exactly
where the file's ``grasps/transforms`` put it.
"""

from __future__ import annotations

from dataclasses import dataclass

from simgrasp._mujoco import mujoco
from simgrasp.grippers.base import Gripper
from simgrasp.grippers.geometry import GripperGeometry
from simgrasp.resources import model_path

FINGER_BASE = 0.0584
"""Finger frames' height above the hand base (m, franka_ros URDF)."""
FINGER_LENGTH = 0.0538
"""Finger mesh length (m): the fingertips are 0.1122 from the hand base."""
TCP_DEPTH = 0.1034
"""The TCP's height above the hand base (m), as ACRONYM takes it."""


@dataclass(frozen=True)
class FrankaPanda(Gripper):
    """The Panda hand: its actuator takes the pad gap itself (m)."""

    def load_spec(self) -> mujoco.MjSpec:
        return mujoco.MjSpec.from_file(str(model_path("grippers", "franka_panda.xml")))

    def ctrl_for_opening(self, opening: float) -> float:
        return opening

    def planning_geometry(self) -> GripperGeometry:
        """Boxes of the hand in its TCP frame: fingers 2.1 cm wide (TCP x), up to 2.64 cm
        thick (TCP y, at their base), from the finger frames to the tips
        (``finger_reach`` past the TCP); the palm the hand mesh's bounds (TCP x = hand -y:
        0.063, TCP y = hand x: 0.204, z 0.092 m)."""
        return GripperGeometry(
            max_opening=self.max_opening,
            finger_length=TCP_DEPTH - FINGER_BASE,
            finger_thickness=0.0264,
            finger_width=0.021,
            pad_reach=self.finger_reach,
            palm_size=(0.063, 0.204, 0.092),
        )


FRANKA_PANDA = FrankaPanda(
    name="franka_panda",
    max_opening=0.08,
    root_body="hand",
    tcp_site="tcp",
    fingers=(("left_finger",), ("right_finger",)),
    pads=(("left_pad",), ("right_pad",)),
    actuator="fingers",
    ctrl_closed=0.0,
    grip_force=70.0,
    finger_reach=FINGER_BASE + FINGER_LENGTH - TCP_DEPTH,
)
"""The Panda hand: 0.08 m stroke, 70 N per jaw (the datasheet's continuous force)."""


def franka_panda() -> Gripper:
    """The Franka Panda hand (the registry's loader)."""
    return FRANKA_PANDA
