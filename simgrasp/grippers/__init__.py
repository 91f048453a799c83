"""grippers: the parallel-jaw grippers behind one interface.

Modules: ``registry`` (names, :func:`make_gripper`; no MuJoCo), ``base`` (the
:class:`~simgrasp.grippers.base.Gripper` interface), ``geometry`` (the planner's boxes), one
module per gripper (``builtin``, ``robotiq_2f85``), and ``mount`` (a gripper in a MuJoCo
scene: free joint on a mocap weld, :class:`~simgrasp.grippers.mount.BoundGripper`). Importing
this package does not import MuJoCo.
"""

from simgrasp.grippers.registry import (
    DEFAULT_GRIPPER,
    GRIPPERS,
    check_gripper_name,
    gripper_names,
    make_gripper,
)

__all__ = ["DEFAULT_GRIPPER", "GRIPPERS", "check_gripper_name", "gripper_names", "make_gripper"]
