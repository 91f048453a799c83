"""The Robotiq 2F-85 (MuJoCo Menagerie model) behind the :class:`~simgrasp.grippers.base.Gripper`
interface.

The model is read from ``$MENAGERIE_ROOT/robotiq_2f85/2f85.xml`` and never shipped with
simgrasp. A ``tcp`` site is added to its ``base`` body at the center of the finger pads (base
frame: +z toward the fingertips, +y the jaw direction, so the TCP convention holds as is).
Its actuator takes 0 (open, 0.085 m) .. 255 (closed) and drives a four-bar linkage, so the
control for a given opening comes from a calibration of the bare gripper (cached per process).

The Menagerie pad boxes have contact priority, so their parameters decide every pad contact,
and they come with ``condim=3``: point contacts without torsional friction, so a held object
turns freely about the line between the two pads (a long tool held off its center of mass
swings down, which a real silicone pad's contact area resists). The pads get ``condim=4``
with ``PAD_TORSIONAL_FRICTION``, like the built-in gripper's.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from simgrasp._mujoco import mujoco
from simgrasp.errors import DataNotFoundError
from simgrasp.grippers.base import Gripper
from simgrasp.grippers.geometry import GripperGeometry

TCP_HEIGHT = 0.14
"""TCP above the ``base`` body origin (m): the middle of the two pad boxes at mid stroke (the
pads ride on an arc, so their center moves from 0.131 m fully open to 0.144 m closed)."""

FINGER_REACH = 0.023
"""Pad tips past the TCP (m): 0.0095 fully open, 0.023 closed (the pads swing forward)."""

OPEN_FINGER_REACH = 0.0095
"""Pad tips past the TCP (m) with the jaws fully open, as during the pre-grasp and approach."""

CTRL_CLOSED = 255.0
CALIBRATION_CTRLS = np.linspace(0.0, 255.0, 18)
CALIBRATION_STEPS = 600
"""Steps (2 ms) the bare gripper settles at each calibration control value."""


def menagerie_mjcf() -> Path:
    """Path of the 2F-85 MJCF under ``$MENAGERIE_ROOT``, failing clearly if it is unavailable."""
    root = os.environ.get("MENAGERIE_ROOT")
    if not root:
        raise DataNotFoundError(
            "the Robotiq 2F-85 gripper needs MENAGERIE_ROOT, the directory of a MuJoCo "
            "Menagerie checkout (holding robotiq_2f85/2f85.xml); it is not set"
        )
    path = Path(root) / "robotiq_2f85" / "2f85.xml"
    if not path.is_file():
        raise DataNotFoundError(
            f"the Robotiq 2F-85 model {path} does not exist; MENAGERIE_ROOT={root!r} must be a "
            "MuJoCo Menagerie checkout"
        )
    return path


PADS = (("left_pad1", "left_pad2"), ("right_pad1", "right_pad2"))
"""The pad box geoms of the left and right finger."""

PAD_TORSIONAL_FRICTION = 0.01
"""Torsional friction (m) given to the pad boxes (the objects' own torsional friction)."""


def _load_spec() -> mujoco.MjSpec:
    spec = mujoco.MjSpec.from_file(str(menagerie_mjcf()))
    spec.body("base").add_site(name="tcp", pos=[0.0, 0.0, TCP_HEIGHT], size=[0.004])
    for name in PADS[0] + PADS[1]:
        pad = spec.geom(name)
        pad.condim = 4
        pad.friction[1] = PAD_TORSIONAL_FRICTION
    return spec


@cache
def _calibration() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(pad gaps ascending, matching controls) of the bare, fixed gripper at rest."""
    model = _load_spec().compile()
    model.opt.timestep = 0.002
    data = mujoco.MjData(model)
    left = model.geom("left_pad1").id
    right = model.geom("right_pad1").id
    site = model.site("tcp").id
    pad_depth = model.geom_size[left, 1] + model.geom_size[right, 1]
    gaps = []
    for ctrl in CALIBRATION_CTRLS:
        data.ctrl[0] = ctrl
        mujoco.mj_step(model, data, CALIBRATION_STEPS)
        y_world = data.site_xmat[site].reshape(3, 3)[:, 1]
        gaps.append((data.geom_xpos[right] - data.geom_xpos[left]) @ y_world - pad_depth)
    gaps_arr = np.asarray(gaps)
    order = np.argsort(gaps_arr)
    return gaps_arr[order], CALIBRATION_CTRLS[order]


@dataclass(frozen=True)
class Robotiq2F85(Gripper):
    """The Menagerie 2F-85 with a ``tcp`` site and torsional pad friction (module docstring)."""

    def load_spec(self) -> mujoco.MjSpec:
        return _load_spec()

    def ctrl_for_opening(self, opening: float) -> float:
        gaps, ctrls = _calibration()
        return float(np.interp(opening, gaps, ctrls))

    def planning_geometry(self) -> GripperGeometry:
        """The boxes of the open gripper (pre-grasp and approach), the fingertips
        ``OPEN_FINGER_REACH`` past the TCP. The pads swing forward as they close (21-23 mm
        once closed on a handle narrower than 4 cm), so grasps keep the closed fingertips
        (``finger_reach``) above the table: closing tips that hit the table top stall the jaws
        before they squeeze the handle."""
        return GripperGeometry(
            max_opening=self.max_opening,
            pad_reach=OPEN_FINGER_REACH,
            closed_pad_reach=self.finger_reach,
            finger_length=0.06,
            finger_width=0.025,
            palm_size=(0.07, 0.14, 0.06),
        )


@cache
def robotiq_2f85() -> Gripper:
    """The Menagerie Robotiq 2F-85: 0.085 m stroke; its actuator force limit (5 on the driver
    tendon) squeezes a 3 cm handle with about 45 N per jaw (the real one: 20-235 N)."""
    menagerie_mjcf()
    return Robotiq2F85(
        name="robotiq_2f85",
        max_opening=0.085,
        root_body="base_mount",
        tcp_site="tcp",
        fingers=(("left_driver", "left_spring_link"), ("right_driver", "right_spring_link")),
        pads=PADS,
        actuator="fingers_actuator",
        ctrl_closed=CTRL_CLOSED,
        grip_force=45.0,
        finger_reach=FINGER_REACH,
    )
