"""The grippers simgrasp knows, by name: the one list that ``make_gripper``, the CLI choices
and the gymnasium env read. Importable without MuJoCo: a gripper's module (and its model) is
loaded only by :func:`make_gripper`.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING

from simgrasp.registry import Registry

if TYPE_CHECKING:
    from simgrasp.grippers.base import Gripper


@dataclass(frozen=True)
class GripperEntry:
    """A registered gripper: its ``name``, the ``module:function`` returning it, a one-line
    ``summary`` (for help texts)."""

    name: str
    loader: str
    summary: str

    def load(self) -> Gripper:
        module, function = self.loader.split(":")
        gripper: Gripper = getattr(importlib.import_module(module), function)()
        return gripper


GRIPPERS: Registry[GripperEntry] = Registry(
    "gripper",
    (
        GripperEntry(
            "builtin",
            "simgrasp.grippers.builtin:builtin",
            "simgrasp's parallel-jaw gripper, 0-8.5 cm, 60 N",
        ),
        GripperEntry(
            "robotiq_2f85",
            "simgrasp.grippers.robotiq_2f85:robotiq_2f85",
            "the MuJoCo Menagerie Robotiq 2F-85 (needs $MENAGERIE_ROOT)",
        ),
        GripperEntry(
            "franka_panda",
            "simgrasp.grippers.franka_panda:franka_panda",
            "the Franka Emika Panda hand of ACRONYM / GraspGen, 0-8 cm, 70 N",
        ),
    ),
)
"""Registered grippers by name; the first is the default."""

DEFAULT_GRIPPER = "builtin"


def gripper_names() -> tuple[str, ...]:
    """Names of the registered grippers, the default first."""
    return GRIPPERS.names()


def check_gripper_name(name: str) -> str:
    """``name`` if it is a registered gripper, else a ``ValueError`` naming the choices."""
    return GRIPPERS.entry(name).name


def make_gripper(name: str) -> Gripper:
    """The gripper called ``name`` (one of :func:`gripper_names`), its module loaded now."""
    return GRIPPERS.entry(name).load()
