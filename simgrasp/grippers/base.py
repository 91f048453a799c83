"""The gripper interface: a parallel-jaw gripper model as data (names in its MJCF, stroke,
control range) plus what differs per gripper (its MJCF, its opening control, its planning
geometry). Importable without MuJoCo; :mod:`simgrasp.grippers.mount` puts a gripper in a scene.

TCP convention (README): origin midway between the finger pads, +z the approach direction
(palm toward object), +y the direction in which the jaws open and close. Units: m, kg, N.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING

from simgrasp.grippers.geometry import GripperGeometry

if TYPE_CHECKING:
    import mujoco


@dataclass(frozen=True)
class Gripper(ABC):
    """A parallel-jaw gripper model; one subclass per gripper (:mod:`simgrasp.grippers`).

    Attributes:
        name: the gripper's registry name (:data:`simgrasp.grippers.GRIPPERS`).
        max_opening: largest gap between the pads (m).
        root_body: the body that gets the free joint.
        tcp_site: site at the TCP.
        fingers: (left, right) tuples of the bodies whose subtrees make up each finger; the
            left finger is on the -y side.
        pads: (left, right) names of the pad geoms, one tuple per finger.
        actuator: the actuator that opens and closes the jaws.
        ctrl_closed: control value that squeezes with the full grip force.
        grip_force: nominal squeezing force per jaw (N), for documentation and reports.
        finger_reach: how far the fingertips reach past the TCP along +z (m), the most over
            the stroke; a grasp whose TCP is closer than this to the table hits it.
        max_timestep: the coarsest physics time step (s) at which a grip of this gripper is
            simulated as at the scene's 2 ms (``TrialConfig.hold_timestep`` is capped at it);
            2 ms unless measured otherwise.
    """

    name: str
    max_opening: float
    root_body: str
    tcp_site: str
    fingers: tuple[tuple[str, ...], tuple[str, ...]]
    pads: tuple[tuple[str, ...], tuple[str, ...]]
    actuator: str
    ctrl_closed: float
    grip_force: float
    finger_reach: float
    max_timestep: float = 0.002

    @abstractmethod
    def load_spec(self) -> mujoco.MjSpec:
        """A fresh ``MjSpec`` of the gripper (no free joint; it has the site ``tcp_site``
        following the TCP convention)."""

    @abstractmethod
    def ctrl_for_opening(self, opening: float) -> float:
        """Control value that holds the pads ``opening`` meters apart."""

    @abstractmethod
    def planning_geometry(self) -> GripperGeometry:
        """The grasp planner's collision boxes for this gripper (documented approximations)."""
