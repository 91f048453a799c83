"""The names of the grippers (no MuJoCo import)."""

from __future__ import annotations


def gripper_names() -> tuple[str, ...]:
    """Every gripper a run can use."""
    return ("builtin", "robotiq_2f85")
